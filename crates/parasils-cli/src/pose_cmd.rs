//! `parasils ik` and `parasils fk`: the kinematics at one pose, for people
//! (aligned text) or programs (`--json`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use nalgebra::Vector3;
use parasils_kin::controller::{RobotGeometry, mirror_across_platform};
use parasils_kin::parallel::Actuators;
use parasils_kin::{AssemblyMode, Controller, Instrument, Joints, Pose, TipTargets};
use serde_json::{Value, json};

use crate::cli::parse_floats;
use crate::robot_file;

/// Arguments of `parasils ik`.
#[derive(Debug, Args)]
pub struct IkArgs {
    /// Platform pose X,Y,Z,PSI,THETA,PHI (mm, deg). Default: the paper's P0.
    #[arg(long, value_name = "X,Y,Z,PSI,THETA,PHI", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub pose: Option<[f64; 6]>,
    /// Left tip X,Y,Z (mm, fixed frame). Default: (50, -50, -620).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_left: Option<[f64; 3]>,
    /// Right tip X,Y,Z (mm, fixed frame). Default: the mirror image of the
    /// left tip across the platform's Y'Z' plane at the pose.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_right: Option<[f64; 3]>,
    /// Robot geometry as TOML (see `parasils robot`).
    #[arg(long, value_name = "FILE.toml")]
    pub robot: Option<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `parasils fk`.
#[derive(Debug, Args)]
pub struct FkArgs {
    /// Module 1's actuators Q1,...,Q6, mm.
    #[arg(long, value_name = "Q1,Q2,Q3,Q4,Q5,Q6", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub q: [f64; 6],
    /// Starting guess X,Y,Z,PSI,THETA,PHI (mm, deg); it picks the assembly
    /// mode. Default: the paper's P0.
    #[arg(long, value_name = "X,Y,Z,PSI,THETA,PHI", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub guess: Option<[f64; 6]>,
    /// Left module joints QS1,QS2,QS3 (deg, deg, mm): print its tip.
    #[arg(long, value_name = "QS1,QS2,QS3", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub qs_left: Option<[f64; 3]>,
    /// Right module joints QS1,QS2,QS3 (deg, deg, mm): print its tip.
    #[arg(long, value_name = "QS1,QS2,QS3", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub qs_right: Option<[f64; 3]>,
    /// Robot geometry as TOML (see `parasils robot`).
    #[arg(long, value_name = "FILE.toml")]
    pub robot: Option<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

fn controller(robot: &Option<PathBuf>) -> Result<(Controller<f64>, bool)> {
    let geometry = match robot {
        Some(path) => robot_file::load(path)?,
        None => RobotGeometry::paper(),
    };
    let c = Controller::from_geometry(&geometry).context("robot geometry")?;
    Ok((c, geometry.module1.assumed))
}

fn pose_from(p: Option<[f64; 6]>) -> Pose<f64> {
    p.map_or_else(Pose::paper_start, |p| {
        Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5])
    })
}

fn pose_json(p: &Pose<f64>) -> Value {
    json!({
        "x_mm": p.x, "y_mm": p.y, "z_mm": p.z,
        "psi_deg": p.psi.to_degrees(), "theta_deg": p.theta.to_degrees(), "phi_deg": p.phi.to_degrees(),
    })
}

fn pose_text(p: &Pose<f64>) -> String {
    format!(
        "({:.4}, {:.4}, {:.4} mm, {:.4}, {:.4}, {:.4} deg)",
        p.x,
        p.y,
        p.z,
        p.psi.to_degrees(),
        p.theta.to_degrees(),
        p.phi.to_degrees()
    )
}

fn joints_json(q: &Joints<f64>) -> Value {
    json!({"qs1_deg": q.qs1.to_degrees(), "qs2_deg": q.qs2.to_degrees(), "qs3_mm": q.qs3})
}

fn assumed_note(assumed: bool) -> &'static str {
    if assumed {
        " (ASSUMED geometry: the real robot's dimensions are not published)"
    } else {
        ""
    }
}

/// `parasils ik`.
pub fn ik(args: &IkArgs) -> Result<()> {
    let (c, assumed) = controller(&args.robot)?;
    let pose = pose_from(args.pose);
    let left_tip = args
        .tip_left
        .map_or_else(|| TipTargets::<f64>::paper().left, Vector3::from);
    let tips = TipTargets {
        left: left_tip,
        right: args
            .tip_right
            .map_or_else(|| mirror_across_platform(&pose, &left_tip), Vector3::from),
    };
    let q = c.module1.ik(&pose).context("module 1")?;
    let margins = c.module1.margins(&pose).context("module 1")?;
    let mut sides = Vec::new();
    for (name, m, tip) in [
        ("left", &c.left, tips.left),
        ("right", &c.right, tips.right),
    ] {
        let [a, b] = m
            .ik_solutions(&pose, &tip)
            .with_context(|| format!("{name} instrument"))?;
        sides.push((name, m, tip, a, b));
    }
    let limit_status = |m: &Instrument<f64>, q: &Joints<f64>| {
        m.geometry()
            .limits
            .check(m.side(), q)
            .err()
            .map(|e| e.to_string())
    };
    if args.json {
        let mut v = json!({
            "pose": pose_json(&pose),
            "module1": {
                "assumed_geometry": assumed,
                "q_mm": q.to_array(),
                "serial_margins": margins.serial,
                "serial_margin": margins.serial_min,
                "parallel_margin": margins.parallel,
            },
        });
        for (name, m, tip, a, b) in &sides {
            let mode = |q: &Joints<f64>| {
                let mut j = joints_json(q);
                j["cos_qs2"] = json!(q.qs2.cos());
                j["limit_error"] = json!(limit_status(m, q));
                j
            };
            v[*name] = json!({
                "tip_mm": [tip.x, tip.y, tip.z],
                "mode_a": mode(a),
                "mode_b": mode(b),
            });
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("pose {}", pose_text(&pose));
    println!("module 1{}", assumed_note(assumed));
    let qs: Vec<String> = q.to_array().iter().map(|v| format!("{v:.4}")).collect();
    println!("  q1..q6 = {} mm", qs.join(", "));
    println!(
        "  margins: serial {:.4} (smallest), parallel {:.4}",
        margins.serial_min, margins.parallel
    );
    for (name, m, tip, a, b) in &sides {
        println!(
            "{name} instrument, tip ({:.4}, {:.4}, {:.4}) mm",
            tip.x, tip.y, tip.z
        );
        for (mode, q) in [(AssemblyMode::A, a), (AssemblyMode::B, b)] {
            let status = limit_status(m, q).map_or_else(
                || "within limits".to_owned(),
                |e| format!("beyond limits: {e}"),
            );
            println!(
                "  mode {mode:?}: qs1 = {:9.4} deg, qs2 = {:9.4} deg, qs3 = {:8.4} mm, |cos qs2| = {:.4}  [{status}]",
                q.qs1.to_degrees(),
                q.qs2.to_degrees(),
                q.qs3,
                q.qs2.cos().abs()
            );
        }
    }
    Ok(())
}

/// `parasils fk`.
pub fn fk(args: &FkArgs) -> Result<()> {
    let (c, assumed) = controller(&args.robot)?;
    let guess = pose_from(args.guess);
    let sol = c
        .module1
        .fk(&Actuators(args.q), &guess)
        .context("module 1 forward kinematics")?;
    let mut tips = Vec::new();
    for (name, m, qs) in [
        ("left", &c.left, args.qs_left),
        ("right", &c.right, args.qs_right),
    ] {
        if let Some(qs) = qs {
            let q = Joints::from_deg_mm(qs[0], qs[1], qs[2]);
            let tip = m
                .tip(&sol.pose, &q)
                .with_context(|| format!("{name} instrument"))?;
            tips.push((name, q, tip));
        }
    }
    if args.json {
        let mut v = json!({
            "pose": pose_json(&sol.pose),
            "module1": {
                "assumed_geometry": assumed,
                "iterations": sol.iterations,
                "residual": sol.residual,
            },
        });
        for (name, q, tip) in &tips {
            v[*name] = json!({"joints": joints_json(q), "tip_mm": [tip.x, tip.y, tip.z]});
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("pose {}", pose_text(&sol.pose));
    println!(
        "module 1{}: {} Newton iterations, relative residual {:.3e}",
        assumed_note(assumed),
        sol.iterations,
        sol.residual
    );
    for (name, _, tip) in &tips {
        println!("{name} tip ({:.4}, {:.4}, {:.4}) mm", tip.x, tip.y, tip.z);
    }
    Ok(())
}
