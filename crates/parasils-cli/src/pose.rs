//! `parasils ik` and `parasils fk`: the kinematics at one pose, for people
//! (aligned text) or programs (`--json`).
//!
//! Every error of the kinematics names its subject (`module 1: ...`,
//! `left instrument: ...`, `module 1 forward kinematics: ...`): it is passed
//! on as it is, without a second prefix.

use core::fmt::Write as _;
use std::io::Write;

use anyhow::{Context, Result};
use nalgebra::Vector3;
use parasils::kin::{
    Actuators, AssemblyMode, Controller, Instrument, Joints, Pose, TipTargets, default_right_tip,
    mirror_across_platform,
};
use serde_json::{Value, json};

use crate::args::{FkArgs, IkArgs, RightTip, RobotArg};
use crate::stdout;

fn controller(robot: &RobotArg) -> Result<(Controller<f64>, bool)> {
    let geometry = robot.geometry()?;
    let c = Controller::from_geometry(&geometry).context("robot geometry")?;
    Ok((c, geometry.module1.assumed))
}

fn pose_from(p: Option<[f64; 6]>) -> Pose<f64> {
    p.map_or_else(Pose::paper_start, |p| {
        Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5])
    })
}

/// Writes `text` to standard output.
fn print(text: &str) -> Result<()> {
    let mut out = stdout::stdout();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .context("writing to standard output")
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
    let pose = pose_from(args.place.pose);
    let left_tip = args
        .place
        .tip_left
        .map_or_else(|| TipTargets::<f64>::paper().left, Vector3::from);
    let tips = TipTargets {
        left: left_tip,
        right: match args.place.tip_right {
            Some(RightTip::Mm(tip)) => Vector3::from(tip),
            Some(RightTip::Mirror) => mirror_across_platform(&pose, &left_tip),
            None => default_right_tip(&pose, &left_tip),
        },
    };
    let q = c.module1.ik(&pose)?;
    let margins = c.module1.margins(&pose)?;
    let mut sides = Vec::new();
    for (name, m, tip) in [
        ("left", &c.left, tips.left),
        ("right", &c.right, tips.right),
    ] {
        let [a, b] = m.ik_solutions(&pose, &tip)?;
        sides.push((name, m, tip, a, b));
    }
    let limit_status = |m: &Instrument<f64>, q: &Joints<f64>| {
        m.geometry()
            .limits
            .check(m.side(), q)
            .err()
            .map(|e| e.to_string())
    };
    let mut text = String::new();
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
        writeln!(text, "{}", serde_json::to_string_pretty(&v)?)?;
        return print(&text);
    }
    writeln!(text, "pose {}", pose_text(&pose))?;
    writeln!(text, "module 1{}", assumed_note(assumed))?;
    let qs: Vec<String> = q.to_array().iter().map(|v| format!("{v:.4}")).collect();
    writeln!(text, "  q1..q6 = {} mm", qs.join(", "))?;
    writeln!(
        text,
        "  margins: serial {:.4} (smallest), parallel {:.4}",
        margins.serial_min, margins.parallel
    )?;
    for (name, m, tip, a, b) in &sides {
        writeln!(
            text,
            "{name} instrument, tip ({:.4}, {:.4}, {:.4}) mm",
            tip.x, tip.y, tip.z
        )?;
        for (mode, q) in [(AssemblyMode::A, a), (AssemblyMode::B, b)] {
            let status = limit_status(m, q).map_or_else(
                || "within limits".to_owned(),
                |e| format!("beyond limits: {e}"),
            );
            writeln!(
                text,
                "  mode {mode:?}: qs1 = {:9.4} deg, qs2 = {:9.4} deg, qs3 = {:8.4} mm, |cos qs2| = {:.4}  [{status}]",
                q.qs1.to_degrees(),
                q.qs2.to_degrees(),
                q.qs3,
                q.qs2.cos().abs()
            )?;
        }
    }
    print(&text)
}

/// `parasils fk`.
pub fn fk(args: &FkArgs) -> Result<()> {
    let (c, assumed) = controller(&args.robot)?;
    let guess = pose_from(args.guess);
    let sol = c.module1.fk(&Actuators(args.q), &guess)?;
    let mut tips = Vec::new();
    for (name, m, qs) in [
        ("left", &c.left, args.qs_left),
        ("right", &c.right, args.qs_right),
    ] {
        if let Some(qs) = qs {
            let q = Joints::from_deg_mm(qs[0], qs[1], qs[2]);
            let tip = m
                .fk(&sol.pose, &q)
                .with_context(|| format!("{name} instrument"))?;
            tips.push((name, q, tip));
        }
    }
    let mut text = String::new();
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
        writeln!(text, "{}", serde_json::to_string_pretty(&v)?)?;
        return print(&text);
    }
    writeln!(text, "pose {}", pose_text(&sol.pose))?;
    writeln!(
        text,
        "module 1{}: {} Newton iterations, relative residual {:.3e}",
        assumed_note(assumed),
        sol.iterations,
        sol.residual
    )?;
    for (name, _, tip) in &tips {
        writeln!(
            text,
            "{name} tip ({:.4}, {:.4}, {:.4}) mm",
            tip.x, tip.y, tip.z
        )?;
    }
    print(&text)
}
