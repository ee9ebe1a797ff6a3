//! The unit tests of [`procedure`](crate::procedure) (a module of their own:
//! `procedure.rs` is near the size limit).

use std::path::Path;

use crate::motion::{MotionGoal, Port};
use crate::procedure::*;
use crate::scenario::Scenario;

fn parse_text(text: &str) -> Result<Scenario, ProcedureError> {
    parse(text, "p.toml", Path::new("."))
}

#[test]
fn every_type_reads_with_its_defaults() -> Result<(), ProcedureError> {
    let s = parse_text(
        "pose = [15, 20, -460, -15, 10, -60]\nendoscope_depth_mm = 5\n\
         [[motion]]\ntype = \"position\"\npose = [15, 20, -500, -15, 10, -60]\n\
         [[motion]]\ntype = \"insert\"\ninstrument = \"endoscope\"\ndepth_mm = 60\nvelocity_mm_s = 5\n\
         [[motion]]\ntype = \"manipulate\"\ninstrument = \"both\"\ntip_left_mm = [1, 2, 3]\ntip_right_mm = [4, 5, 6]\n\
         [[motion]]\ntype = \"reorient\"\nname = \"camera\"\npsi_deg = 15\ntheta_deg = 25\n",
    )?;
    assert_eq!(s.start_mm_deg, [15.0, 20.0, -460.0, -15.0, 10.0, -60.0]);
    assert_eq!(s.endoscope_depth_mm, 5.0);
    assert_eq!(s.motions().len(), 4);
    assert_eq!(
        s.motions()[1].goal,
        MotionGoal::Insert {
            port: Port::Endoscope,
            depth_mm: 60.0
        }
    );
    assert_eq!(s.motions()[1].limits.velocity_mm_s, 5.0);
    assert_eq!(s.motions()[1].limits.acceleration_mm_s2, 20.0);
    assert_eq!(s.motions()[3].limits.velocity_deg_s, 10.0);
    assert_eq!(s.motions()[3].name.as_deref(), Some("camera"));
    Ok(())
}

fn error_of(text: &str) -> String {
    match parse_text(text) {
        Ok(_) => String::from("no error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn errors_name_the_line_the_motion_and_the_key() {
    let two = "[[motion]]\ntype = \"reorient\"\npsi_deg = 1\ntheta_deg = 1\n[[motion]]\n";
    assert_eq!(
        error_of(&format!(
            "{two}type = \"insert\"\ninstrument = \"left\"\ndepth_mm = nan\n"
        )),
        "p.toml, line 8, motion 1, key `depth_mm`: NaN is not a finite number"
    );
    assert_eq!(
        error_of(&format!("{two}type = \"insert\"\ninstrument = \"left\"\n")),
        "p.toml, line 5, motion 1, key `depth_mm`: missing for a \"insert\" motion"
    );
    assert_eq!(
        error_of(&format!(
            "{two}type = \"insert\"\ninstrument = \"left\"\ndepth_mm = 1\npsi_deg = 2\n"
        )),
        "p.toml, line 9, motion 1, key `psi_deg`: does not apply to a \"insert\" motion"
    );
    assert_eq!(
        error_of(&format!(
            "{two}type = \"insert\"\ninstrument = \"middle\"\ndepth_mm = 1\n"
        )),
        "p.toml, line 7, motion 1, key `instrument`: \"middle\" is not one of left, right, endoscope"
    );
    assert_eq!(
        error_of(&format!(
            "{two}type = \"insert\"\ninstrument = \"left\"\ndepth_mm = 1\nvelocity_mm_s = -2\n"
        )),
        "p.toml, line 9, motion 1, key `velocity_mm_s`: -2 is not a positive number"
    );
    let unknown = error_of(&format!("{two}type = \"insert\"\nspeed = 3\n"));
    assert!(
        unknown.starts_with("p.toml, line 7, motion 1: unknown field `speed`"),
        "{unknown}"
    );
    assert_eq!(
        error_of("pose = [1, 2, 3]\n[[motion]]\ntype = \"reorient\"\npsi_deg = 1\ntheta_deg = 1\n")
            .split(':')
            .next(),
        Some("p.toml, line 1")
    );
    assert_eq!(
        error_of("pose = [0, 0, -500, 0, 0, 0]\n"),
        "p.toml, line 1: missing field `motion`"
    );
    assert_eq!(
        error_of("motion = []\n"),
        "p.toml, key `motion`: a procedure needs at least one [[motion]]"
    );
    assert_eq!(
        error_of("[[motion]]\ntype = \"jump\"\n"),
        "p.toml, line 2, motion 0, key `type`: unknown motion type \"jump\": expected \"position\", \"insert\", \"manipulate\", \"reorient\" or \"stop\""
    );
    assert_eq!(
        error_of("[[motion]]\ntype = \"reorient\"\npsi_deg = 1\ntheta_deg = 1\nuntil_s = -1\n"),
        "p.toml, line 5, motion 0, key `until_s`: -1 is not a positive number of seconds"
    );
    assert_eq!(
        error_of("[[motion]]\ntype = \"stop\"\npsi_deg = 1\n"),
        "p.toml, line 3, motion 0, key `psi_deg`: does not apply to a \"stop\" motion"
    );
}

#[test]
fn json_reads_like_toml() -> Result<(), ProcedureError> {
    let s = parse_json(
        r#"{"motion": [{"type": "manipulate", "instrument": "right", "tip_mm": [1, 2, 3]}]}"#,
        Path::new("."),
    )?;
    assert_eq!(
        s.motions()[0].goal,
        MotionGoal::Manipulate {
            tip_left_mm: None,
            tip_right_mm: Some([1.0, 2.0, 3.0])
        }
    );
    Ok(())
}
