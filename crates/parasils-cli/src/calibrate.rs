//! `parasils calibrate`: module 1's geometry fitted to measured poses, or
//! the poses to measure (`--plan N`).

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use parasils_calib::data::{self, Measurement};
use parasils_calib::plan::{PlanOptions, plan};
use parasils_calib::{FitOptions, Sigma, calibrate};
use parasils_io::file::{persist, temp_beside};
use parasils_sim::robot_file;

use crate::args::CalibrateArgs;
use crate::stdout;

/// `parasils calibrate`.
pub fn calibrate_command(args: &CalibrateArgs) -> Result<()> {
    let robot = args.robot.geometry()?;
    if let Some(n) = args.plan {
        return plan_command(args, &robot.module1, n);
    }
    let Some(path) = &args.measurements else {
        bail!("give --measurements FILE.csv, or --plan N");
    };
    let sigma = Sigma {
        q_mm: args.sigma_q_mm,
        position_mm: args.sigma_position_mm,
        angle_deg: args.sigma_angle_deg,
    };
    let file = std::fs::File::open(path).with_context(|| path.display().to_string())?;
    let measurements: Vec<Measurement> = data::read_csv(
        std::io::BufReader::new(file),
        &path.display().to_string(),
        sigma,
    )?;
    let options = FitOptions {
        max_iterations: args.max_iterations,
        ..FitOptions::default()
    };
    let fit = calibrate(&robot.module1, &measurements, &options)?;
    let mut fitted = robot;
    fitted.module1 = fit.geometry;
    let text = robot_file::to_toml_string(&fitted)?;
    // What is written must load back as it is.
    robot_file::parse(&text).context("the fitted robot file does not load back")?;
    let report = args.report.as_ref().map(|p| (p, fit.report.to_json()));
    write_all(&args.output, &text, report)?;
    let r = &fit.report;
    let mut out = stdout::stdout();
    writeln!(
        out,
        "module 1 {}: {} identified, {} fixed; {} iterations",
        fit.geometry.provenance(),
        r.identified.len(),
        r.fixed.len(),
        r.outcome.iterations
    )?;
    writeln!(
        out,
        "RMS residual {:.6} mm before, {:.6} mm after (worst {:.6} mm, row {}, q{})",
        r.rms_before_mm,
        r.rms_after_mm,
        r.worst_after.residual_mm,
        r.worst_after.row,
        r.worst_after.actuator
    )?;
    writeln!(
        out,
        "observability: condition number {:.4}, smallest singular value {:.4}, noise amplification index {:.3e}",
        r.observability.condition_number,
        r.observability.singular_value_min,
        r.observability.noise_amplification_index
    )?;
    for f in &r.fixed {
        writeln!(
            out,
            "fixed {} = {} {}: {}",
            f.name, f.value, f.unit, f.reason
        )?;
    }
    writeln!(out, "wrote {}", args.output.display())?;
    out.flush()?;
    Ok(())
}

fn plan_command(
    args: &CalibrateArgs,
    nominal: &parasils::kin::ParallelGeometry<f64>,
    poses: usize,
) -> Result<()> {
    let options = PlanOptions {
        poses,
        candidates: args.candidates.max(poses),
        seed: args.seed,
        ..PlanOptions::default()
    };
    let planned = plan(nominal, &options)?;
    let rows: Vec<Measurement> = planned
        .poses
        .iter()
        .zip(&planned.q_mm)
        .map(|(p, q)| Measurement {
            q_mm: *q,
            pose: *p,
            sigma: Sigma::default(),
        })
        .collect();
    let report = args.report.as_ref().map(|p| (p, planned.report.to_json()));
    write_all(&args.output, &data::to_csv_string(&rows), report)?;
    let r = &planned.report;
    let mut out = stdout::stdout();
    writeln!(
        out,
        "{} poses from {} candidates: smallest singular value {:.4} (random poses: median {:.4} over {} sets, ratio {:.2}), noise amplification index {:.3e}",
        r.poses,
        r.candidates,
        r.planned.singular_value_min,
        r.random_singular_value_min_median,
        r.random_singular_value_min.len(),
        r.ratio_singular_value_min,
        r.planned.noise_amplification_index
    )?;
    writeln!(out, "wrote {}", args.output.display())?;
    out.flush()?;
    Ok(())
}

/// Writes the main output and the report, each to a temporary file beside
/// it, then renames both: a failure leaves neither behind.
fn write_all(path: &Path, text: &str, report: Option<(&PathBuf, String)>) -> Result<()> {
    let write = |target: &Path, text: &str| -> Result<tempfile::NamedTempFile> {
        let mut tmp = temp_beside(target)?;
        tmp.write_all(text.as_bytes())
            .and_then(|()| tmp.flush())
            .with_context(|| format!("writing {}", target.display()))?;
        Ok(tmp)
    };
    let main = write(path, text)?;
    let report = match report {
        Some((p, json)) => Some((p, write(p, &json)?)),
        None => None,
    };
    persist(main, path)?;
    if let Some((p, tmp)) = report {
        persist(tmp, p)?;
    }
    Ok(())
}
