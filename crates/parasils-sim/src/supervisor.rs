//! The margin supervisor's thresholds in the robot file: an optional
//! `[supervisor]` table, each key a warning or stop threshold of one kind of
//! margin (both instrument modules alike), named with its unit.
//!
//! ```toml
//! [supervisor]
//! cos_qs2_warn = 0.1          # |cos qs2| of either instrument module
//! cos_qs2_stop = 0.05
//! qs3_warn_mm = 5             # qs3, the tip's distance from its RCM
//! qs3_stop_mm = 2
//! joint_limit_warn_deg = 5    # qs1, qs2 to their limits
//! joint_limit_stop_deg = 1
//! qs3_limit_warn_mm = 10      # qs3 to its limits
//! qs3_limit_stop_mm = 2
//! serial_margin_warn = 0.1    # module 1's smallest serial margin
//! serial_margin_stop = 0.05
//! parallel_margin_warn = 0.1  # module 1's parallel margin
//! parallel_margin_stop = 0.03
//! stroke_warn_mm = 10         # module 1's actuators to their stroke ends
//! stroke_stop_mm = 2
//! ```
//!
//! Those are the defaults (`parasils::supervisor`'s table), raised where a
//! robot file's hard thresholds are higher (see
//! [`Simulation::new`](crate::Simulation::new)); a key not given keeps its
//! default. A warning marks the samples whose margin is below it (the
//! summary and `--check` list them, with their motion and times); a stop
//! threshold is where the online controller stops the platform. Each stop
//! threshold must be above the solvers' hard one and each warning at least
//! its stop threshold.

use std::path::Path;

use parasils::Supervisor;
use parasils::supervisor::Margin;
use serde::Deserialize;

use crate::robot_file::RobotFileError;

/// The `[supervisor]` table: the thresholds a robot file sets, each `None`
/// when not given.
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupervisorTable {
    /// `|cos qs2|`, warning.
    pub cos_qs2_warn: Option<f64>,
    /// `|cos qs2|`, stop.
    pub cos_qs2_stop: Option<f64>,
    /// `qs3`, warning, mm.
    pub qs3_warn_mm: Option<f64>,
    /// `qs3`, stop, mm.
    pub qs3_stop_mm: Option<f64>,
    /// `qs1`, `qs2` to their limits, warning, deg.
    pub joint_limit_warn_deg: Option<f64>,
    /// `qs1`, `qs2` to their limits, stop, deg.
    pub joint_limit_stop_deg: Option<f64>,
    /// `qs3` to its limits, warning, mm.
    pub qs3_limit_warn_mm: Option<f64>,
    /// `qs3` to its limits, stop, mm.
    pub qs3_limit_stop_mm: Option<f64>,
    /// Module 1's serial margin, warning.
    pub serial_margin_warn: Option<f64>,
    /// Module 1's serial margin, stop.
    pub serial_margin_stop: Option<f64>,
    /// Module 1's parallel margin, warning.
    pub parallel_margin_warn: Option<f64>,
    /// Module 1's parallel margin, stop.
    pub parallel_margin_stop: Option<f64>,
    /// Module 1's strokes, warning, mm.
    pub stroke_warn_mm: Option<f64>,
    /// Module 1's strokes, stop, mm.
    pub stroke_stop_mm: Option<f64>,
}

#[derive(Deserialize)]
struct Only {
    #[serde(default)]
    supervisor: Option<SupervisorTable>,
}

impl SupervisorTable {
    /// The margins each key sets (both modules' for the instrument keys), the
    /// value in library units, and whether it is a warning (else a stop).
    fn entries(&self) -> [(&'static [Margin], Option<f64>, bool); 14] {
        use Margin::{
            LeftAngleLimits, LeftCosQs2, LeftQs3, LeftQs3Limits, Parallel, RightAngleLimits,
            RightCosQs2, RightQs3, RightQs3Limits, Serial, Stroke,
        };
        let rad = |v: Option<f64>| v.map(f64::to_radians);
        [
            (&[LeftCosQs2, RightCosQs2], self.cos_qs2_warn, true),
            (&[LeftCosQs2, RightCosQs2], self.cos_qs2_stop, false),
            (&[LeftQs3, RightQs3], self.qs3_warn_mm, true),
            (&[LeftQs3, RightQs3], self.qs3_stop_mm, false),
            (
                &[LeftAngleLimits, RightAngleLimits],
                rad(self.joint_limit_warn_deg),
                true,
            ),
            (
                &[LeftAngleLimits, RightAngleLimits],
                rad(self.joint_limit_stop_deg),
                false,
            ),
            (
                &[LeftQs3Limits, RightQs3Limits],
                self.qs3_limit_warn_mm,
                true,
            ),
            (
                &[LeftQs3Limits, RightQs3Limits],
                self.qs3_limit_stop_mm,
                false,
            ),
            (&[Serial], self.serial_margin_warn, true),
            (&[Serial], self.serial_margin_stop, false),
            (&[Parallel], self.parallel_margin_warn, true),
            (&[Parallel], self.parallel_margin_stop, false),
            (&[Stroke], self.stroke_warn_mm, true),
            (&[Stroke], self.stroke_stop_mm, false),
        ]
    }

    /// `base` with the thresholds this table gives.
    pub fn apply(&self, mut base: Supervisor<f64>) -> Supervisor<f64> {
        for (margins, value, warn) in self.entries() {
            if let Some(v) = value {
                for &m in margins {
                    if warn {
                        base.warn[m] = v;
                    } else {
                        base.stop[m] = v;
                    }
                }
            }
        }
        base
    }

    /// Whether no threshold is given.
    pub fn is_empty(&self) -> bool {
        self.entries().iter().all(|(_, v, _)| v.is_none())
    }
}

/// The `[supervisor]` table of a robot file's text (empty when it has none);
/// errors name `origin`, the line and the key.
///
/// # Errors
/// [`RobotFileError::Parse`] for malformed TOML, an unknown key or a value
/// that is not a number.
pub fn parse(text: &str, origin: &str) -> Result<SupervisorTable, RobotFileError> {
    let only: Only =
        toml::from_str(text).map_err(|e| crate::robot_file::parse_error(text, origin, e))?;
    Ok(only.supervisor.unwrap_or_default())
}

/// The `[supervisor]` table of the robot file at `path`.
///
/// # Errors
/// [`RobotFileError::Io`] when the file cannot be read, and as [`parse`].
pub fn load(path: impl AsRef<Path>) -> Result<SupervisorTable, RobotFileError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|error| RobotFileError::Io {
        path: path.to_owned(),
        error,
    })?;
    parse(&text, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_keys_replace_their_thresholds_only() -> Result<(), RobotFileError> {
        let t = parse(
            "[module1]\nassumed = true\n[supervisor]\ncos_qs2_warn = 0.2\njoint_limit_stop_deg = 2\n",
            "r.toml",
        )?;
        let base = Supervisor::<f64>::default();
        let s = t.apply(base);
        assert_eq!(s.warn[Margin::LeftCosQs2], 0.2);
        assert_eq!(s.warn[Margin::RightCosQs2], 0.2);
        assert_eq!(s.stop[Margin::RightAngleLimits], 2f64.to_radians());
        assert_eq!(s.stop[Margin::LeftCosQs2], base.stop[Margin::LeftCosQs2]);
        assert_eq!(s.warn[Margin::Parallel], base.warn[Margin::Parallel]);
        assert!(parse("[module1]\n", "r.toml")?.is_empty());
        Ok(())
    }

    #[test]
    fn unknown_keys_are_errors_with_their_line() {
        let e = parse("[supervisor]\ncos_qs2_warn = 0.2\nspeed = 3\n", "r.toml")
            .map(|_| ())
            .map_err(|e| e.to_string());
        let Err(text) = e else {
            panic!("an unknown key is an error");
        };
        assert!(text.starts_with("r.toml, line 3"), "{text}");
        assert!(text.contains("unknown field `speed`"), "{text}");
    }
}
