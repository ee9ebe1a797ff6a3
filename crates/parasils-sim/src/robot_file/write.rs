//! A geometry written as a robot file: the header, the file's keys with a
//! comment each, numbers that read back exactly.

use parasils::kin::{ActuatorStiffness, BodyGeometry, RobotGeometry};

use super::dynamics::{DynamicsFile, StiffnessFile};
use super::error::RobotFileError;
use super::schema::{BodiesFile, RobotFile};
use crate::robot::Robot;

/// The header of every file this module writes.
const HEADER: &str = "\
# PARA-SILSROB robot geometry: module 1 (the 6-DOF parallel robot) and the
# two spherical instrument modules, with their limits and thresholds.
# Every key names its unit: _mm millimetres, _deg degrees, _rel relative,
# _n newtons, _nmm newton millimetres;
# module 1's positions are in the fixed frame OXYZ (-Z towards the patient),
# its nodes and the ports (rcm_mm) in the platform frame.
#
# Module 1's default dimensions are ASSUMED, not the real robot's, which are
# not published (see docs/model.md, section \"Module 1, the parallel robot\").
# Replace them with the real ones and set `assumed = false`; as long as it is
# true, every module-1 number the CLI prints is labelled as coming from an
# assumed geometry.
";

/// Comments appended to the lines whose key they explain.
const KEY_COMMENTS: &[(&str, &str)] = &[
    ("assumed", "true: the dimensions below are assumed"),
    ("serial_margin_min", "smallest accepted |e.u|/l, in (0, 1)"),
    (
        "parallel_margin_min",
        "FK: smallest accepted parallel margin",
    ),
    (
        "parallel_margin_command_min",
        "each cycle: smallest accepted parallel margin",
    ),
    ("euler_cos_theta_min", "FK: smallest accepted |cos theta|"),
    ("fk_tolerance_rel", "FK: max |f_j| / l_j at convergence"),
    ("fk_max_iterations", "FK: Newton steps at most"),
    ("direction", "u_j, normalised on loading"),
    ("branch", "s_j: 1 or -1"),
    ("stroke_mm", "[min, max]"),
    ("node_mm", "a_i, platform frame"),
    ("rcm_mm", "the port, platform frame"),
    (
        "reach_tolerance_rel",
        "out of reach beyond |v_x| > cos(beta) (1 + this)",
    ),
    ("cos_qs2_min", "singular below"),
    ("qs3_min_mm", "singular below"),
    ("velocity_max_mm_s", "the slider's velocity limit (assumed)"),
    ("acceleration_max_mm_s2", "its acceleration limit (assumed)"),
    ("force_max_n", "its force limit (assumed)"),
    ("qs1_velocity_max_deg_s", "the joints' limits (assumed)"),
    ("qs1_torque_max_nmm", "the joints' force limits (assumed)"),
    (
        "depth_mm",
        "[min, max], 0 at the port, positive inwards (assumed)",
    ),
];

/// The TOML text of a geometry, with a header and comments: what
/// `parasils robot` prints and `robots/default.toml` holds.
pub fn to_toml_string(geometry: &RobotGeometry<f64>) -> Result<String, RobotFileError> {
    let body = toml::to_string(&RobotFile::from_geometry(geometry))?;
    let mut out = String::from(HEADER);
    let (mut guide, mut leg) = (0, 0);
    for line in body.lines() {
        let line = &exponent_form(line);
        let trimmed = line.trim();
        if trimmed.starts_with('[') && !out.ends_with("\n\n") {
            out.push('\n');
        }
        out.push_str(line);
        match trimmed {
            "[[module1.guides]]" => {
                guide += 1;
                out.push_str(&format!(" # q{guide}"));
            }
            "[[module1.legs]]" => {
                leg += 1;
                out.push_str(&format!(
                    " # leg {leg}: the node of q{} and q{}",
                    2 * leg - 1,
                    2 * leg
                ));
            }
            _ => {
                let key = trimmed.split('=').next().unwrap_or("").trim();
                if let Some((_, comment)) = KEY_COMMENTS.iter().find(|(k, _)| *k == key) {
                    out.push_str(" # ");
                    out.push_str(comment);
                }
            }
        }
        out.push('\n');
    }
    Ok(out)
}

/// The TOML text of a whole robot: [`to_toml_string`] of its geometry, then
/// its `[supervisor]` table with the thresholds it gives (none: no table)
/// and its `[bodies]` when they are not the assumed ones, its `[dynamics]`
/// when it has them and its `[stiffness]` with them or when not the
/// assumed ones, so
/// that [`parse_robot`](crate::robot_file::parse_robot) reads back the same [`Robot`].
pub fn robot_to_toml_string(robot: &Robot) -> Result<String, RobotFileError> {
    let mut out = to_toml_string(&robot.geometry)?;
    if !robot.supervisor.is_empty() {
        out.push_str("\n[supervisor]\n");
        out.push_str(&toml::to_string(&robot.supervisor)?);
    }
    if robot.bodies != BodyGeometry::assumed() {
        out.push_str("\n[bodies]\n");
        out.push_str(&toml::to_string(&BodiesFile::from_bodies(&robot.bodies))?);
    }
    if let Some(payload) = &robot.dynamics {
        out.push_str(
            "\n# The platform with its modules as one rigid body: mass, centre of mass\n\
             # (platform frame), inertia about the centre of mass (platform axes),\n\
             # gravity (fixed frame). ASSUMED: the paper gives no masses.\n[dynamics]\n",
        );
        out.push_str(&toml::to_string(&DynamicsFile::from_payload(payload))?);
    }
    if robot.dynamics.is_some() || robot.stiffness != ActuatorStiffness::assumed() {
        out.push_str(
            "\n# Each actuator as a spring, the links rigid: sliders along their guides\n\
             # N/mm, qs1 and qs2 N mm/rad, qs3 N/mm. ASSUMED.\n[stiffness]\n",
        );
        out.push_str(&toml::to_string(&StiffnessFile::from_stiffness(
            &robot.stiffness,
        ))?);
    }
    Ok(out)
}

/// `key = 0.0000000000001` as `key = 1e-13`: a small number in exponent
/// form, which reads the same (TOML floats may have an exponent).
fn exponent_form(line: &str) -> String {
    if let Some((key, value)) = line.split_once(" = ")
        && let Ok(v) = value.trim().parse::<f64>()
        && v != 0.0
        && v.abs() < 1e-3
        && value.contains('.')
    {
        return format!("{key} = {v:e}");
    }
    line.to_owned()
}
