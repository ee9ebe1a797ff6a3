//! Where a validation error's parameter sits in a robot file: its table,
//! occurrence, key and line, for the error message.

/// Where a parameter sits in the file.
pub(super) struct Place {
    pub(super) key: String,
    pub(super) line: Option<usize>,
    pub(super) text: Option<String>,
}

/// The file's table, occurrence and key of the parameter a validation error
/// names (`module1.guides[2].link_length` is `link_length_mm` in the third
/// `[[module1.guides]]`), and its line.
pub(super) fn locate(text: &str, table: &str, error: &parasils::kin::Error) -> Option<Place> {
    let what = match error {
        parasils::kin::Error::InvalidParameter { what, .. }
        | parasils::kin::Error::NonFinite { what, .. } => *what,
        _ => return None,
    };
    let indexed = |prefix: &str| -> Option<(usize, &str)> {
        let rest = what.strip_prefix(prefix)?;
        let (index, field) = rest.split_once(']')?;
        Some((index.parse().ok()?, field.trim_start_matches('.')))
    };
    let (header, occurrence, key, label): (&str, usize, &str, String) =
        if let Some((j, field)) = indexed("module1.guides[") {
            let key = match field.split('.').next().unwrap_or("") {
                "point" => "point_mm",
                "direction" => "direction",
                "link_length" => "link_length_mm",
                "stroke" => "stroke_mm",
                "encoder_offset" => "encoder_offset_mm",
                _ => "",
            };
            (
                "[[module1.guides]]",
                j,
                key,
                format!(" #{} (q{})", j + 1, j + 1),
            )
        } else if let Some((i, _)) = indexed("module1.nodes[") {
            ("[[module1.legs]]", i, "node_mm", format!(" #{}", i + 1))
        } else if what == "module1.nodes" {
            ("[[module1.legs]]", 0, "node_mm", String::from(" #1"))
        } else if table == "module1" {
            let key = match what {
                "module1.thresholds.serial" => "serial_margin_min",
                "module1.thresholds.parallel" => "parallel_margin_min",
                "module1.thresholds.parallel_command" => "parallel_margin_command_min",
                "module1.thresholds.euler" => "euler_cos_theta_min",
                "module1.fk.tolerance" => "fk_tolerance_rel",
                "module1.fk.max_iterations" => "fk_max_iterations",
                _ => "",
            };
            ("[module1]", 0, key, String::new())
        } else {
            let field = what.strip_prefix("instrument.")?;
            let key = match field.split('.').next().unwrap_or("") {
                "alpha" => "alpha_deg",
                "beta" => "beta_deg",
                "radius" => "radius_mm",
                "rcm" => "rcm_mm",
                "limits" => match field {
                    "limits.qs1" => "qs1_deg",
                    "limits.qs2" => "qs2_deg",
                    _ => "qs3_mm",
                },
                "thresholds" => match field {
                    "thresholds.reach" => "reach_tolerance_rel",
                    "thresholds.cos_qs2" => "cos_qs2_min",
                    _ => "qs3_min_mm",
                },
                _ => "",
            };
            let header = if table == "left" { "[left]" } else { "[right]" };
            (header, 0, key, String::new())
        };
    let mut seen = None;
    let mut header_line = None;
    let mut found = None;
    for (n, line) in text.lines().enumerate() {
        let content = line.split('#').next().unwrap_or("").trim();
        if content.starts_with('[') {
            if seen.is_some_and(|k| k == occurrence) && header_line.is_some() {
                break;
            }
            if content == header {
                seen = Some(seen.map_or(0, |k| k + 1));
                if seen == Some(occurrence) {
                    header_line = Some((n + 1, line));
                }
            }
            continue;
        }
        if header_line.is_some() && !key.is_empty() {
            let k = content.split('=').next().unwrap_or("").trim();
            if k == key {
                found = Some((n + 1, line));
                break;
            }
        }
    }
    let at = found.or(header_line);
    Some(Place {
        key: format!("{header}{label} {key}").trim_end().to_owned(),
        line: at.map(|(n, _)| n),
        text: at.map(|(_, t)| t.to_owned()),
    })
}
