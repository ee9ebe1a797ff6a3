//! Robot files read: the text parsed and validated, module by module, into
//! a [`Robot`]; errors placed at their line and key.

use std::path::Path;

use parasils::kin::RobotGeometry;

use super::error::RobotFileError;
use super::locate::locate;
use super::schema::RobotFile;
use super::write::to_toml_string;
use crate::robot::Robot;

/// The geometry in a robot file's text, validated: [`parse_robot`]'s
/// geometry. Errors name `"robot file"` as their origin; see [`load`] for a
/// path.
pub fn parse(text: &str) -> Result<RobotGeometry<f64>, RobotFileError> {
    parse_robot(text).map(|robot| robot.geometry)
}

/// The whole robot in a robot file's text, validated: its geometry and its
/// `[supervisor]` thresholds, its `[bodies]`, `[dynamics]` and `[stiffness]`, read in one pass. Errors name `"robot file"`
/// as their origin; see [`load_robot`] for a path.
pub fn parse_robot(text: &str) -> Result<Robot, RobotFileError> {
    parse_from(text, "robot file")
}

fn parse_from(text: &str, origin: &str) -> Result<Robot, RobotFileError> {
    let file: RobotFile = toml::from_str(text).map_err(|e| parse_error(text, origin, e))?;
    let geometry = file.to_geometry();
    // Module by module, so that an instrument's error says which side.
    let checks: [(&str, Result<(), parasils::kin::Error>); 4] = [
        ("module1", geometry.module1.validate()),
        ("left", geometry.left.validate()),
        ("right", geometry.right.validate()),
        ("endoscope", geometry.endoscope.validate()),
    ];
    for (table, result) in checks {
        if let Err(error) = result {
            let place = locate(text, table, &error);
            return Err(RobotFileError::Invalid {
                origin: origin.into(),
                line: place.as_ref().and_then(|p| p.line),
                key: place.as_ref().map(|p| p.key.as_str().into()),
                text: place.and_then(|p| p.text.map(String::into_boxed_str)),
                error,
            });
        }
    }
    let supervisor = file.supervisor.unwrap_or_default();
    if let Some([warn, stop]) = supervisor.clearance()
        && !(warn >= stop && stop.is_finite() && warn.is_finite())
    {
        let (key, value) = if stop.is_finite() {
            ("clearance_warn_mm", warn)
        } else {
            ("clearance_stop_mm", stop)
        };
        return Err(RobotFileError::Invalid {
            origin: origin.into(),
            line: None,
            key: Some(key.into()),
            text: None,
            error: parasils::kin::Error::InvalidParameter {
                what: "supervisor.clearance (warning below the stop threshold, or not finite)",
                value,
            },
        });
    }
    if let Some(limit) = supervisor.port_motion_stop_mm
        && !(limit > 0.0 && limit.is_finite())
    {
        return Err(RobotFileError::Invalid {
            origin: origin.into(),
            line: None,
            key: Some("port_motion_stop_mm".into()),
            text: None,
            error: parasils::kin::Error::InvalidParameter {
                what: "supervisor.port_motion_stop_mm (not a positive finite number of mm)",
                value: limit,
            },
        });
    }
    let bodies = file.bodies.unwrap_or_default().to_bodies();
    if let Err(error) = bodies.validate() {
        return Err(RobotFileError::Invalid {
            origin: origin.into(),
            line: None,
            key: None,
            text: None,
            error,
        });
    }
    if let Some((what, value)) = file.dynamics.as_ref().and_then(|d| d.inertia_problem()) {
        return Err(RobotFileError::Invalid {
            origin: origin.into(),
            line: line_of(text, "platform_inertia_kg_mm2"),
            key: Some("[dynamics] platform_inertia_kg_mm2".into()),
            text: None,
            error: parasils::kin::Error::InvalidParameter { what, value },
        });
    }
    Ok(Robot {
        geometry,
        supervisor,
        bodies,
        dynamics: file.dynamics.map(|d| d.to_payload()),
        stiffness: file.stiffness.unwrap_or_default().to_stiffness(),
    })
}

/// The line (1-based) of the first line that sets `key`.
fn line_of(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|l| l.split_once('=').is_some_and(|(k, _)| k.trim() == key))
        .map(|k| k + 1)
}

/// A [`RobotFileError::Parse`] with the line, column, key and text of the
/// error's position.
fn parse_error(text: &str, origin: &str, source: toml::de::Error) -> RobotFileError {
    let position = source.span().map(|span| {
        let start = span.start.min(text.len());
        let before = &text[..start];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = text[line_start..start].chars().count() + 1;
        let line_text = text[line_start..].lines().next().unwrap_or("").to_owned();
        (line, column, line_text)
    });
    let key = position.as_ref().and_then(|(_, _, t)| {
        let (k, _) = t.split_once('=')?;
        let k = k.trim();
        (!k.is_empty() && !k.starts_with('#')).then(|| k.into())
    });
    RobotFileError::Parse {
        origin: origin.into(),
        line: position.as_ref().map(|p| p.0),
        column: position.as_ref().map(|p| p.1),
        key,
        text: position.map(|p| p.2.into_boxed_str()),
        error: Box::new(source),
    }
}

/// The geometry in the robot file at `path`, validated: [`load_robot`]'s
/// geometry.
pub fn load(path: impl AsRef<Path>) -> Result<RobotGeometry<f64>, RobotFileError> {
    load_robot(path).map(|robot| robot.geometry)
}

/// The whole robot in the robot file at `path`, validated: its geometry and
/// its `[supervisor]` thresholds, from one reading of the file. This is what
/// every front end loads a `--robot`/`robot=` file with.
pub fn load_robot(path: impl AsRef<Path>) -> Result<Robot, RobotFileError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|error| RobotFileError::Io {
        path: path.to_owned(),
        error,
    })?;
    parse_from(&text, &path.display().to_string())
}

/// Writes `geometry` to `path` as [`to_toml_string`] gives it.
pub fn save(path: impl AsRef<Path>, geometry: &RobotGeometry<f64>) -> Result<(), RobotFileError> {
    let path = path.as_ref();
    let text = to_toml_string(geometry)?;
    std::fs::write(path, text).map_err(|error| RobotFileError::Io {
        path: path.to_owned(),
        error,
    })
}
