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
//! clearance_warn_mm = 2.0     # the gaps between the shafts and the endoscope
//! clearance_stop_mm = 0.5
//! ```
//!
//! The two clearance keys check the surface gaps between the bodies (the
//! robot file's `[bodies]`) **only when the file gives one of them** (the
//! other then takes its assumed default, 2.0 mm to warn, 0.5 mm to stop).
//! They are off by default because, with the assumed bodies, the paper's
//! own run has its shafts overlapping (see `docs/model.md`, *Clearance*).
//! In a planned run or a procedure, every sample is checked and a gap below
//! the stop threshold fails the run before any output, naming the motion,
//! the time, the pair and the depth below the ports; in an online run
//! (retargets, a stop), the online controller watches the gaps
//! (`parasils::OnlineController::with_clearance`) and stops the platform
//! ahead of the stop threshold, as it does for the margins.
//!
//! Those are the defaults (`parasils::supervisor`'s table), raised where a
//! robot file's hard thresholds are higher (see
//! [`Simulation::new`](crate::Simulation::new)); a key not given keeps its
//! default. A warning marks the samples whose margin is below it (the
//! summary and `--check` list them, with their motion and times); a stop
//! threshold is where the online controller stops the platform. Each stop
//! threshold must be above the solvers' hard one and each warning at least
//! its stop threshold.

use parasils::Supervisor;
use parasils::supervisor::Margin;
use serde::{Deserialize, Serialize};

/// The `[supervisor]` table: the thresholds a robot file sets, each `None`
/// when not given.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupervisorTable {
    /// `|cos qs2|`, warning.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cos_qs2_warn: Option<f64>,
    /// `|cos qs2|`, stop.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cos_qs2_stop: Option<f64>,
    /// `qs3`, warning, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qs3_warn_mm: Option<f64>,
    /// `qs3`, stop, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qs3_stop_mm: Option<f64>,
    /// `qs1`, `qs2` to their limits, warning, deg.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint_limit_warn_deg: Option<f64>,
    /// `qs1`, `qs2` to their limits, stop, deg.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint_limit_stop_deg: Option<f64>,
    /// `qs3` to its limits, warning, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qs3_limit_warn_mm: Option<f64>,
    /// `qs3` to its limits, stop, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qs3_limit_stop_mm: Option<f64>,
    /// Module 1's serial margin, warning.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub serial_margin_warn: Option<f64>,
    /// Module 1's serial margin, stop.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub serial_margin_stop: Option<f64>,
    /// Module 1's parallel margin, warning.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parallel_margin_warn: Option<f64>,
    /// Module 1's parallel margin, stop.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parallel_margin_stop: Option<f64>,
    /// Module 1's strokes, warning, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stroke_warn_mm: Option<f64>,
    /// Module 1's strokes, stop, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stroke_stop_mm: Option<f64>,
    /// The surface gaps between the bodies, warning, mm (see
    /// [`SupervisorTable::clearance`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance_warn_mm: Option<f64>,
    /// The surface gaps between the bodies, stop, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance_stop_mm: Option<f64>,
    /// How far a port (a module's RCM, or the endoscope's insertion point)
    /// may move from where it was at the start of each motion, mm, fixed
    /// frame: a planned run or a procedure that moves one farther fails
    /// before any output. Not supervised unless given (no assumed default).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub port_motion_stop_mm: Option<f64>,
}

/// The clearance thresholds' assumed defaults, mm: warning, stop.
const CLEARANCE_DEFAULTS_MM: [f64; 2] = [2.0, 0.5];

impl SupervisorTable {
    /// Each key: its name in the file, the margins it sets (both modules'
    /// for the instrument keys), the value in library units, and whether it
    /// is a warning (else a stop).
    fn entries(&self) -> [Entry; 14] {
        use Margin::{
            LeftAngleLimits, LeftCosQs2, LeftQs3, LeftQs3Limits, Parallel, RightAngleLimits,
            RightCosQs2, RightQs3, RightQs3Limits, Serial, Stroke,
        };
        const COS_QS2: &[Margin] = &[LeftCosQs2, RightCosQs2];
        const QS3: &[Margin] = &[LeftQs3, RightQs3];
        const ANGLES: &[Margin] = &[LeftAngleLimits, RightAngleLimits];
        const QS3_LIMITS: &[Margin] = &[LeftQs3Limits, RightQs3Limits];
        let t = self;
        [
            Entry::new("cos_qs2_warn", COS_QS2, t.cos_qs2_warn, 1.0, true),
            Entry::new("cos_qs2_stop", COS_QS2, t.cos_qs2_stop, 1.0, false),
            Entry::new("qs3_warn_mm", QS3, t.qs3_warn_mm, 1.0, true),
            Entry::new("qs3_stop_mm", QS3, t.qs3_stop_mm, 1.0, false),
            Entry::new(
                "joint_limit_warn_deg",
                ANGLES,
                t.joint_limit_warn_deg,
                RAD,
                true,
            ),
            Entry::new(
                "joint_limit_stop_deg",
                ANGLES,
                t.joint_limit_stop_deg,
                RAD,
                false,
            ),
            Entry::new(
                "qs3_limit_warn_mm",
                QS3_LIMITS,
                t.qs3_limit_warn_mm,
                1.0,
                true,
            ),
            Entry::new(
                "qs3_limit_stop_mm",
                QS3_LIMITS,
                t.qs3_limit_stop_mm,
                1.0,
                false,
            ),
            Entry::new(
                "serial_margin_warn",
                &[Serial],
                t.serial_margin_warn,
                1.0,
                true,
            ),
            Entry::new(
                "serial_margin_stop",
                &[Serial],
                t.serial_margin_stop,
                1.0,
                false,
            ),
            Entry::new(
                "parallel_margin_warn",
                &[Parallel],
                t.parallel_margin_warn,
                1.0,
                true,
            ),
            Entry::new(
                "parallel_margin_stop",
                &[Parallel],
                t.parallel_margin_stop,
                1.0,
                false,
            ),
            Entry::new("stroke_warn_mm", &[Stroke], t.stroke_warn_mm, 1.0, true),
            Entry::new("stroke_stop_mm", &[Stroke], t.stroke_stop_mm, 1.0, false),
        ]
    }

    /// The thresholds given, each with its key as the file names it, in the
    /// file's units (mm, deg, or none), in the order of the table above.
    pub fn given(&self) -> impl Iterator<Item = (&'static str, f64)> {
        let clearance = [
            ("clearance_warn_mm", self.clearance_warn_mm),
            ("clearance_stop_mm", self.clearance_stop_mm),
            ("port_motion_stop_mm", self.port_motion_stop_mm),
        ];
        self.entries()
            .into_iter()
            .filter_map(|e| e.file_value.map(|v| (e.key, v)))
            .chain(clearance.into_iter().filter_map(|(k, v)| v.map(|v| (k, v))))
    }

    /// The clearance thresholds `[warn, stop]`, mm, when the table gives
    /// either (the other at its assumed default: 2.0 mm to warn, 0.5 mm to stop);
    /// `None` (clearance not supervised) when it gives neither.
    pub fn clearance(&self) -> Option<[f64; 2]> {
        if self.clearance_warn_mm.is_none() && self.clearance_stop_mm.is_none() {
            return None;
        }
        let [warn, stop] = CLEARANCE_DEFAULTS_MM;
        Some([
            self.clearance_warn_mm.unwrap_or(warn),
            self.clearance_stop_mm.unwrap_or(stop),
        ])
    }

    /// The stop threshold of the gaps to forbidden regions, mm: the table's
    /// `clearance_stop_mm`, or its assumed default 0.5 mm. Unlike the gaps
    /// between the bodies, supervised whenever an anatomy is given: giving
    /// the regions is asking for them to be kept out of.
    pub fn no_go_stop_mm(&self) -> f64 {
        self.clearance_stop_mm.unwrap_or(CLEARANCE_DEFAULTS_MM[1])
    }

    /// `base` with the thresholds this table gives.
    pub fn apply(&self, mut base: Supervisor<f64>) -> Supervisor<f64> {
        for Entry {
            margins,
            file_value,
            scale,
            warn,
            ..
        } in self.entries()
        {
            if let Some(v) = file_value.map(|v| v * scale) {
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
        self.given().next().is_none()
    }
}

/// Degrees to radians.
const RAD: f64 = core::f64::consts::PI / 180.0;

/// One key of the table.
struct Entry {
    key: &'static str,
    margins: &'static [Margin],
    file_value: Option<f64>,
    /// The factor from the file's unit to the library's.
    scale: f64,
    warn: bool,
}

impl Entry {
    const fn new(
        key: &'static str,
        margins: &'static [Margin],
        file_value: Option<f64>,
        scale: f64,
        warn: bool,
    ) -> Self {
        Self {
            key,
            margins,
            file_value,
            scale,
            warn,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> SupervisorTable {
        toml::from_str(text).unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn given_keys_replace_their_thresholds_only() {
        let t = table("cos_qs2_warn = 0.2\njoint_limit_stop_deg = 2\n");
        let base = Supervisor::<f64>::default();
        let s = t.apply(base);
        assert_eq!(s.warn[Margin::LeftCosQs2], 0.2);
        assert_eq!(s.warn[Margin::RightCosQs2], 0.2);
        assert_eq!(s.stop[Margin::RightAngleLimits], 2f64.to_radians());
        assert_eq!(s.stop[Margin::LeftCosQs2], base.stop[Margin::LeftCosQs2]);
        assert_eq!(s.warn[Margin::Parallel], base.warn[Margin::Parallel]);
        assert!(table("").is_empty());
        assert!(!t.is_empty());
        let given: Vec<_> = t.given().collect();
        assert_eq!(
            given,
            [("cos_qs2_warn", 0.2), ("joint_limit_stop_deg", 2.0)]
        );
    }

    #[test]
    fn every_key_is_named_as_the_file_names_it() {
        // Each field set to a distinct value, written by serde, read back
        // through `given`: the names and the order agree with the struct's.
        let mut text = String::new();
        let names = [
            "cos_qs2_warn",
            "cos_qs2_stop",
            "qs3_warn_mm",
            "qs3_stop_mm",
            "joint_limit_warn_deg",
            "joint_limit_stop_deg",
            "qs3_limit_warn_mm",
            "qs3_limit_stop_mm",
            "serial_margin_warn",
            "serial_margin_stop",
            "parallel_margin_warn",
            "parallel_margin_stop",
            "stroke_warn_mm",
            "stroke_stop_mm",
            "clearance_warn_mm",
            "clearance_stop_mm",
            "port_motion_stop_mm",
        ];
        for (k, name) in names.iter().enumerate() {
            text.push_str(&format!("{name} = {}.5\n", k + 1));
        }
        let t = table(&text);
        let given: Vec<_> = t.given().collect();
        let expected: Vec<_> = names
            .iter()
            .enumerate()
            .map(|(k, n)| (*n, k as f64 + 1.5))
            .collect();
        assert_eq!(given, expected);
    }

    #[test]
    fn clearance_is_supervised_only_when_a_key_is_given() {
        assert_eq!(table("").clearance(), None);
        assert_eq!(table("cos_qs2_warn = 0.2").clearance(), None);
        assert_eq!(table("clearance_stop_mm = 1").clearance(), Some([2.0, 1.0]));
        assert_eq!(table("clearance_warn_mm = 3").clearance(), Some([3.0, 0.5]));
        assert!(!table("clearance_warn_mm = 3").is_empty());
    }

    #[test]
    fn a_table_writes_only_its_given_keys_and_reads_back() {
        let t = table("qs3_warn_mm = 7.5\nparallel_margin_stop = 0.04\n");
        let text = toml::to_string(&t).unwrap_or_default();
        assert_eq!(text, "qs3_warn_mm = 7.5\nparallel_margin_stop = 0.04\n");
        assert_eq!(table(&text), t);
    }
}
