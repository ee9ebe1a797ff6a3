//! The output columns, in one table: each with its name (which ends with its
//! unit), its unit, its MCAP channel, whether the CSV has it, and how its
//! value is read from a [`Record`].
//!
//! Everything that writes a record out is derived from [`ALL`]: the CSV
//! header and rows ([`csv`](crate::csv)), the MCAP channels, their fields and
//! JSON schemas ([`mcap`](crate::mcap)), the [`summary`](crate::summary), and
//! the Python bindings' `COLUMNS` and arrays. Adding a column is one entry
//! here: a named constant, listed in [`ALL`].
//!
//! One column is not in [`ALL`]: [`COMMAND`], the index of the active
//! command, which only runs with commands (retargets, a stop) have. Their
//! CSV is [`CSV_WITH_COMMAND`], the 57 columns of [`CSV`] and `command` last,
//! and their MCAP file has it on `/motion`; a run without commands writes
//! exactly what it wrote before commands existed ([`csv_columns`] picks).
//!
//! Angles are written in degrees, lengths in mm, times in s; margins are
//! dimensionless. Rates are `_rate_` and accelerations `_acc_` in the names.
//! The Euler angles are written as [`Record::angles_deg`], which gives back
//! the user's start angles exactly.

use crate::record::Record;

/// A data channel of the MCAP file: one message per sample on each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// `/platform`: the pose, the Euler rates and accelerations.
    Platform,
    /// `/module1`: the actuators, their rates and accelerations.
    Module1,
    /// `/left`: the left instrument module's joints, rates, accelerations.
    Left,
    /// `/right`: the right instrument module's.
    Right,
    /// `/tips`: the tips recomputed by forward kinematics and their distances
    /// to the targets.
    Tips,
    /// `/margins`: module 1's serial and parallel margins, `cos qs2` of each
    /// instrument module.
    Margins,
}

impl Channel {
    /// Every data channel, in the order of the file's channel ids.
    pub const ALL: [Channel; 6] = [
        Channel::Platform,
        Channel::Module1,
        Channel::Left,
        Channel::Right,
        Channel::Tips,
        Channel::Margins,
    ];

    /// The MCAP topic.
    pub const fn topic(self) -> &'static str {
        match self {
            Channel::Platform => "/platform",
            Channel::Module1 => "/module1",
            Channel::Left => "/left",
            Channel::Right => "/right",
            Channel::Tips => "/tips",
            Channel::Margins => "/margins",
        }
    }

    /// The name of the channel's JSON schema.
    pub const fn schema_name(self) -> &'static str {
        match self {
            Channel::Platform => "parasils.Platform",
            Channel::Module1 => "parasils.Module1",
            Channel::Left => "parasils.LeftModule",
            Channel::Right => "parasils.RightModule",
            Channel::Tips => "parasils.Tips",
            Channel::Margins => "parasils.Margins",
        }
    }

    /// The description of the channel's JSON schema.
    pub const fn description(self) -> &'static str {
        match self {
            Channel::Platform => "Platform pose (paper's figure 5: psi, theta), fixed frame",
            Channel::Module1 => "Module 1 actuators q1..q6 (paper's figure 6)",
            Channel::Left => "Left instrument module joints (paper's figure 7)",
            Channel::Right => "Right instrument module joints",
            Channel::Tips => {
                "Instrument tips recomputed by forward kinematics (fixed frame) and their distance to the targets"
            }
            Channel::Margins => {
                "Singularity margins: module 1 serial and parallel, cos qs2 of each instrument module; clearance: the surface gaps between the shafts and the endoscope (mm)"
            }
        }
    }
}

/// One output column.
#[derive(Debug, Clone, Copy)]
pub struct Column {
    /// The name, ending with the unit: `t_s`, `q1_rate_mm_s`.
    pub name: &'static str,
    /// The unit, for people: `"deg/s^2"`, `"1 (dimensionless)"`.
    pub unit: &'static str,
    /// The MCAP channel; `None` for the time, the first field of every
    /// channel, and for [`COMMAND`], which is on `/motion` (see
    /// [`mcap`](crate::mcap)).
    pub channel: Option<Channel>,
    /// Whether the CSV (and the Python table) has the column; `false` for
    /// the MCAP's recomputed tip positions.
    pub csv: bool,
    /// Whether the values are whole numbers, written without a fraction
    /// (`2`, not `2.0`): [`COMMAND`].
    pub integer: bool,
    /// The value in the column's unit.
    pub get: fn(&Record) -> f64,
}

impl Column {
    /// The column's value for `record`, in its unit.
    #[inline]
    pub fn value(&self, record: &Record) -> f64 {
        (self.get)(record)
    }
}

const S: &str = "s";
const MM: &str = "mm";
const MM_S: &str = "mm/s";
const MM_S2: &str = "mm/s^2";
const DEG: &str = "deg";
const DEG_S: &str = "deg/s";
const DEG_S2: &str = "deg/s^2";
const ONE: &str = "1 (dimensionless)";
const INDEX: &str = "index";

const fn col(
    name: &'static str,
    unit: &'static str,
    channel: Channel,
    get: fn(&Record) -> f64,
) -> Column {
    Column {
        name,
        unit,
        channel: Some(channel),
        csv: true,
        integer: false,
        get,
    }
}

const fn mcap_only(
    name: &'static str,
    unit: &'static str,
    channel: Channel,
    get: fn(&Record) -> f64,
) -> Column {
    Column {
        csv: false,
        ..col(name, unit, channel, get)
    }
}

/// Time since the start, s.
pub const T_S: Column = Column {
    name: "t_s",
    unit: S,
    channel: None,
    csv: true,
    integer: false,
    get: |r| r.t,
};
/// `X_P`, mm.
pub const X_MM: Column = col("x_mm", MM, Channel::Platform, |r| r.pose[0]);
/// `Y_P`, mm.
pub const Y_MM: Column = col("y_mm", MM, Channel::Platform, |r| r.pose[1]);
/// `Z_P`, mm.
pub const Z_MM: Column = col("z_mm", MM, Channel::Platform, |r| r.pose[2]);
/// `psi`, deg ([`Record::angles_deg`]).
pub const PSI_DEG: Column = col("psi_deg", DEG, Channel::Platform, |r| r.angles_deg[0]);
/// `theta`, deg ([`Record::angles_deg`]).
pub const THETA_DEG: Column = col("theta_deg", DEG, Channel::Platform, |r| r.angles_deg[1]);
/// `phi`, deg ([`Record::angles_deg`]).
pub const PHI_DEG: Column = col("phi_deg", DEG, Channel::Platform, |r| r.angles_deg[2]);
/// The rate of `psi`, deg/s.
pub const PSI_RATE_DEG_S: Column = col("psi_rate_deg_s", DEG_S, Channel::Platform, |r| {
    r.euler_dot[0].to_degrees()
});
/// The rate of `theta`, deg/s.
pub const THETA_RATE_DEG_S: Column = col("theta_rate_deg_s", DEG_S, Channel::Platform, |r| {
    r.euler_dot[1].to_degrees()
});
/// The acceleration of `psi`, deg/s^2.
pub const PSI_ACC_DEG_S2: Column = col("psi_acc_deg_s2", DEG_S2, Channel::Platform, |r| {
    r.euler_ddot[0].to_degrees()
});
/// The acceleration of `theta`, deg/s^2.
pub const THETA_ACC_DEG_S2: Column = col("theta_acc_deg_s2", DEG_S2, Channel::Platform, |r| {
    r.euler_ddot[1].to_degrees()
});

/// Six columns of module 1, one per actuator, `q1` to `q6`.
macro_rules! per_actuator {
    ($suffix:literal, $unit:expr, $field:ident) => {
        [
            col(concat!("q1", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[0]
            }),
            col(concat!("q2", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[1]
            }),
            col(concat!("q3", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[2]
            }),
            col(concat!("q4", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[3]
            }),
            col(concat!("q5", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[4]
            }),
            col(concat!("q6", $suffix), $unit, Channel::Module1, |r| {
                r.module1.$field[5]
            }),
        ]
    };
}

/// Module 1's actuators `q1..q6`, mm.
pub const Q_MM: [Column; 6] = per_actuator!("_mm", MM, q);
/// Their rates, mm/s.
pub const Q_RATE_MM_S: [Column; 6] = per_actuator!("_rate_mm_s", MM_S, q_dot);
/// Their accelerations, mm/s^2.
pub const Q_ACC_MM_S2: [Column; 6] = per_actuator!("_acc_mm_s2", MM_S2, q_ddot);
/// Module 1's smallest serial margin.
pub const MODULE1_SERIAL_MARGIN: Column =
    col("module1_serial_margin", ONE, Channel::Margins, |r| {
        r.module1.serial_margin
    });
/// Module 1's parallel margin.
pub const MODULE1_PARALLEL_MARGIN: Column =
    col("module1_parallel_margin", ONE, Channel::Margins, |r| {
        r.module1.parallel_margin
    });

/// The columns of one instrument module.
#[derive(Debug, Clone, Copy)]
pub struct InstrumentColumns {
    /// `qs1`, `qs2` (deg), `qs3` (mm).
    pub q: [Column; 3],
    /// Their rates (deg/s, deg/s, mm/s).
    pub q_rate: [Column; 3],
    /// Their accelerations (deg/s^2, deg/s^2, mm/s^2).
    pub q_acc: [Column; 3],
    /// `cos qs2`, signed (positive in assembly mode A).
    pub cos_qs2: Column,
    /// The recomputed tip's distance to its target, mm.
    pub tip_err: Column,
    /// The recomputed tip, mm, fixed frame (MCAP only).
    pub tip: [Column; 3],
}

/// The columns of the instrument module in field `$side` of a record, named
/// `$prefix_...`, on `$channel`.
macro_rules! instrument_columns {
    ($side:ident, $prefix:literal, $channel:expr) => {
        InstrumentColumns {
            q: [
                col(concat!($prefix, "_qs1_deg"), DEG, $channel, |r| {
                    r.$side.q[0].to_degrees()
                }),
                col(concat!($prefix, "_qs2_deg"), DEG, $channel, |r| {
                    r.$side.q[1].to_degrees()
                }),
                col(concat!($prefix, "_qs3_mm"), MM, $channel, |r| r.$side.q[2]),
            ],
            q_rate: [
                col(concat!($prefix, "_qs1_rate_deg_s"), DEG_S, $channel, |r| {
                    r.$side.q_dot[0].to_degrees()
                }),
                col(concat!($prefix, "_qs2_rate_deg_s"), DEG_S, $channel, |r| {
                    r.$side.q_dot[1].to_degrees()
                }),
                col(concat!($prefix, "_qs3_rate_mm_s"), MM_S, $channel, |r| {
                    r.$side.q_dot[2]
                }),
            ],
            q_acc: [
                col(concat!($prefix, "_qs1_acc_deg_s2"), DEG_S2, $channel, |r| {
                    r.$side.q_ddot[0].to_degrees()
                }),
                col(concat!($prefix, "_qs2_acc_deg_s2"), DEG_S2, $channel, |r| {
                    r.$side.q_ddot[1].to_degrees()
                }),
                col(concat!($prefix, "_qs3_acc_mm_s2"), MM_S2, $channel, |r| {
                    r.$side.q_ddot[2]
                }),
            ],
            cos_qs2: col(concat!($prefix, "_cos_qs2"), ONE, Channel::Margins, |r| {
                r.$side.cos_qs2
            }),
            tip_err: col(concat!($prefix, "_tip_err_mm"), MM, Channel::Tips, |r| {
                r.$side.tip_err
            }),
            tip: [
                mcap_only(concat!($prefix, "_tip_x_mm"), MM, Channel::Tips, |r| {
                    r.$side.tip.x
                }),
                mcap_only(concat!($prefix, "_tip_y_mm"), MM, Channel::Tips, |r| {
                    r.$side.tip.y
                }),
                mcap_only(concat!($prefix, "_tip_z_mm"), MM, Channel::Tips, |r| {
                    r.$side.tip.z
                }),
            ],
        }
    };
}

/// The surface gap between the two instrument shafts, mm (the distance
/// between their axes minus both radii; negative when they overlap).
pub const CLEARANCE_LEFT_RIGHT_MM: Column =
    col("clearance_left_right_mm", MM, Channel::Margins, |r| {
        r.clearance.left_right
    });
/// The surface gap between the left shaft and the endoscope, mm.
pub const CLEARANCE_LEFT_ENDOSCOPE_MM: Column =
    col("clearance_left_endoscope_mm", MM, Channel::Margins, |r| {
        r.clearance.left_endoscope
    });
/// The surface gap between the right shaft and the endoscope, mm.
pub const CLEARANCE_RIGHT_ENDOSCOPE_MM: Column =
    col("clearance_right_endoscope_mm", MM, Channel::Margins, |r| {
        r.clearance.right_endoscope
    });
/// The smallest of the three gaps, mm.
pub const CLEARANCE_MIN_MM: Column = col("clearance_min_mm", MM, Channel::Margins, |r| {
    r.clearance.min()
});

/// The left instrument module's columns.
pub const LEFT: InstrumentColumns = instrument_columns!(left, "left", Channel::Left);
/// The right instrument module's columns.
pub const RIGHT: InstrumentColumns = instrument_columns!(right, "right", Channel::Right);

/// Every column, in order: the CSV's columns are those with `csv` set, in
/// this order; each MCAP channel's fields are `t_s` then its columns, in this
/// order.
pub const ALL: [Column; 63] = [
    T_S,
    X_MM,
    Y_MM,
    Z_MM,
    PSI_DEG,
    THETA_DEG,
    PHI_DEG,
    PSI_RATE_DEG_S,
    THETA_RATE_DEG_S,
    PSI_ACC_DEG_S2,
    THETA_ACC_DEG_S2,
    Q_MM[0],
    Q_MM[1],
    Q_MM[2],
    Q_MM[3],
    Q_MM[4],
    Q_MM[5],
    Q_RATE_MM_S[0],
    Q_RATE_MM_S[1],
    Q_RATE_MM_S[2],
    Q_RATE_MM_S[3],
    Q_RATE_MM_S[4],
    Q_RATE_MM_S[5],
    Q_ACC_MM_S2[0],
    Q_ACC_MM_S2[1],
    Q_ACC_MM_S2[2],
    Q_ACC_MM_S2[3],
    Q_ACC_MM_S2[4],
    Q_ACC_MM_S2[5],
    MODULE1_SERIAL_MARGIN,
    MODULE1_PARALLEL_MARGIN,
    LEFT.q[0],
    LEFT.q[1],
    LEFT.q[2],
    LEFT.q_rate[0],
    LEFT.q_rate[1],
    LEFT.q_rate[2],
    LEFT.q_acc[0],
    LEFT.q_acc[1],
    LEFT.q_acc[2],
    LEFT.cos_qs2,
    LEFT.tip_err,
    RIGHT.q[0],
    RIGHT.q[1],
    RIGHT.q[2],
    RIGHT.q_rate[0],
    RIGHT.q_rate[1],
    RIGHT.q_rate[2],
    RIGHT.q_acc[0],
    RIGHT.q_acc[1],
    RIGHT.q_acc[2],
    RIGHT.cos_qs2,
    RIGHT.tip_err,
    CLEARANCE_LEFT_RIGHT_MM,
    CLEARANCE_LEFT_ENDOSCOPE_MM,
    CLEARANCE_RIGHT_ENDOSCOPE_MM,
    CLEARANCE_MIN_MM,
    LEFT.tip[0],
    LEFT.tip[1],
    LEFT.tip[2],
    RIGHT.tip[0],
    RIGHT.tip[1],
    RIGHT.tip[2],
];

/// The index of the active command (see
/// [`Command`](crate::scenario::Command)): 0 for the reorientation, one more
/// at each retarget and at each stop. Only runs with commands have it: the
/// last column of [`CSV_WITH_COMMAND`], and `/motion` in MCAP.
pub const COMMAND: Column = Column {
    name: "command",
    unit: INDEX,
    channel: None,
    csv: true,
    integer: true,
    get: |r| f64::from(r.command),
};

/// The number of CSV columns.
pub const CSV_COUNT: usize = {
    let mut n = 0;
    let mut i = 0;
    while i < ALL.len() {
        if ALL[i].csv {
            n += 1;
        }
        i += 1;
    }
    n
};

/// The CSV's columns, in order.
pub const CSV: [Column; CSV_COUNT] = {
    let mut out = [T_S; CSV_COUNT];
    let (mut i, mut k) = (0, 0);
    while i < ALL.len() {
        if ALL[i].csv {
            out[k] = ALL[i];
            k += 1;
        }
        i += 1;
    }
    out
};

/// The CSV's header: the names of [`CSV`], in order (the Python bindings'
/// `COLUMNS`).
pub const CSV_NAMES: [&str; CSV_COUNT] = {
    let mut out = [""; CSV_COUNT];
    let mut k = 0;
    while k < CSV_COUNT {
        out[k] = CSV[k].name;
        k += 1;
    }
    out
};

/// The CSV's columns in a run with commands: [`CSV`], then [`COMMAND`].
pub const CSV_WITH_COMMAND: [Column; CSV_COUNT + 1] = {
    let mut out = [COMMAND; CSV_COUNT + 1];
    let mut k = 0;
    while k < CSV_COUNT {
        out[k] = CSV[k];
        k += 1;
    }
    out
};

/// The header of a run with commands: [`CSV_NAMES`], then `command`.
pub const CSV_WITH_COMMAND_NAMES: [&str; CSV_COUNT + 1] = {
    let mut out = [COMMAND.name; CSV_COUNT + 1];
    let mut k = 0;
    while k < CSV_COUNT {
        out[k] = CSV_NAMES[k];
        k += 1;
    }
    out
};

/// The CSV's columns of a run: [`CSV_WITH_COMMAND`] when it has commands
/// (retargets or a stop), [`CSV`] otherwise. `command` is left out of runs
/// without commands, where it would be 0 on every row, so that their files
/// stay as they were, byte for byte.
pub fn csv_columns(commands: bool) -> &'static [Column] {
    if commands { &CSV_WITH_COMMAND } else { &CSV }
}

/// The columns a procedure's CSV adds after [`CSV`]: the motion under way
/// (its index from 0 and its type, 1 to 4), the endoscope's depth, and the
/// three tips (the instruments' by forward kinematics from their joints,
/// the endoscope's from its depth), mm, fixed frame.
pub const PROCEDURE: [Column; 12] = {
    const fn in_csv(c: Column) -> Column {
        Column { csv: true, ..c }
    }
    const fn endoscope(name: &'static str, get: fn(&Record) -> f64) -> Column {
        Column {
            name,
            unit: MM,
            channel: None,
            csv: true,
            integer: false,
            get,
        }
    }
    [
        Column {
            name: "motion",
            unit: INDEX,
            channel: None,
            csv: true,
            integer: true,
            get: |r| f64::from(r.motion),
        },
        Column {
            name: "motion_type",
            unit: INDEX,
            channel: None,
            csv: true,
            integer: true,
            get: |r| f64::from(r.motion_type),
        },
        endoscope("endoscope_depth_mm", |r| r.endoscope_depth),
        in_csv(LEFT.tip[0]),
        in_csv(LEFT.tip[1]),
        in_csv(LEFT.tip[2]),
        in_csv(RIGHT.tip[0]),
        in_csv(RIGHT.tip[1]),
        in_csv(RIGHT.tip[2]),
        endoscope("endoscope_tip_x_mm", |r| r.endoscope_tip.x),
        endoscope("endoscope_tip_y_mm", |r| r.endoscope_tip.y),
        endoscope("endoscope_tip_z_mm", |r| r.endoscope_tip.z),
    ]
};

/// The CSV's columns in a procedure: [`CSV`], then [`PROCEDURE`].
pub const CSV_WITH_PROCEDURE: [Column; CSV_COUNT + 12] = {
    let mut out = [COMMAND; CSV_COUNT + 12];
    let mut k = 0;
    while k < CSV_COUNT + 12 {
        out[k] = if k < CSV_COUNT {
            CSV[k]
        } else {
            PROCEDURE[k - CSV_COUNT]
        };
        k += 1;
    }
    out
};

/// The CSV's columns of `scenario`'s run: [`CSV_WITH_PROCEDURE`] for a
/// procedure, [`CSV_WITH_COMMAND`] with commands, [`CSV`] otherwise; with
/// a tip load given, the same followed by [`FORCES`].
pub fn csv_columns_of(scenario: &crate::scenario::Scenario) -> &'static [Column] {
    let loads = scenario.tip_load_left_n.is_some() || scenario.tip_load_right_n.is_some();
    match (scenario.is_procedure(), loads) {
        (true, false) => &CSV_WITH_PROCEDURE,
        (true, true) => &CSV_WITH_PROCEDURE_AND_FORCES,
        (false, false) => csv_columns(scenario.has_commands()),
        (false, true) if scenario.has_commands() => &CSV_WITH_COMMAND_AND_FORCES,
        (false, true) => &CSV_WITH_FORCES,
    }
}

const N: &str = "N";
const N_MM: &str = "N mm";

const fn force(name: &'static str, unit: &'static str, get: fn(&Record) -> f64) -> Column {
    Column {
        name,
        unit,
        channel: None,
        csv: true,
        integer: false,
        get,
    }
}

/// The columns a run with tip loads adds after its others: every
/// actuator's force holding the loads ([`Record::forces`], see
/// `docs/model.md`, *Forces*): module 1's slider forces `q1_force_n` ..
/// `q6_force_n` (N, positive pushing the slider along its guide's direction
/// `u`), then each instrument module's `qs1`, `qs2` torques (N mm) and
/// `qs3` force (N), then how far each tip gives way under the tissue's push
/// with the assumed actuator stiffnesses (mm). CSV and Python only.
pub const FORCES: [Column; 14] = [
    force("q1_force_n", N, |r| r.forces.module1[0]),
    force("q2_force_n", N, |r| r.forces.module1[1]),
    force("q3_force_n", N, |r| r.forces.module1[2]),
    force("q4_force_n", N, |r| r.forces.module1[3]),
    force("q5_force_n", N, |r| r.forces.module1[4]),
    force("q6_force_n", N, |r| r.forces.module1[5]),
    force("left_qs1_torque_nmm", N_MM, |r| r.forces.left[0]),
    force("left_qs2_torque_nmm", N_MM, |r| r.forces.left[1]),
    force("left_qs3_force_n", N, |r| r.forces.left[2]),
    force("right_qs1_torque_nmm", N_MM, |r| r.forces.right[0]),
    force("right_qs2_torque_nmm", N_MM, |r| r.forces.right[1]),
    force("right_qs3_force_n", N, |r| r.forces.right[2]),
    force("left_tip_deflection_mm", MM, |r| r.forces.deflection[0]),
    force("right_tip_deflection_mm", MM, |r| r.forces.deflection[1]),
];

/// `a` then `b` (`N = A + B`, checked when the constant is evaluated).
pub(crate) const fn join<const A: usize, const B: usize, const N: usize>(
    a: &[Column; A],
    b: &[Column; B],
) -> [Column; N] {
    assert!(A + B == N, "N must be A + B");
    let mut out = [T_S; N];
    let mut k = 0;
    while k < N {
        out[k] = if k < A { a[k] } else { b[k - A] };
        k += 1;
    }
    out
}

/// [`CSV`], then [`FORCES`].
pub const CSV_WITH_FORCES: [Column; CSV_COUNT + 14] = join(&CSV, &FORCES);
/// [`CSV_WITH_COMMAND`], then [`FORCES`].
pub const CSV_WITH_COMMAND_AND_FORCES: [Column; CSV_COUNT + 15] = join(&CSV_WITH_COMMAND, &FORCES);
/// [`CSV_WITH_PROCEDURE`], then [`FORCES`].
pub const CSV_WITH_PROCEDURE_AND_FORCES: [Column; CSV_COUNT + 26] =
    join(&CSV_WITH_PROCEDURE, &FORCES);

/// The position of `column` among the [`CSV`] columns (by name, which is
/// unique); `None` for an MCAP-only column and for [`COMMAND`].
pub fn csv_index(column: &Column) -> Option<usize> {
    CSV_NAMES.iter().position(|n| *n == column.name)
}

/// The values of the [`CSV`] columns for `record`, in order.
pub fn csv_row(record: &Record) -> [f64; CSV_COUNT] {
    CSV.map(|c| c.value(record))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_end_with_their_unit() {
        let mut names: Vec<&str> = ALL.iter().map(|c| c.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), ALL.len());
        let suffix = |unit: &str| match unit {
            "s" => "_s",
            "mm" => "_mm",
            "mm/s" => "_mm_s",
            "mm/s^2" => "_mm_s2",
            "deg" => "_deg",
            "deg/s" => "_deg_s",
            "deg/s^2" => "_deg_s2",
            _ => "",
        };
        for c in ALL {
            if c.unit == ONE {
                assert!(
                    c.name.contains("margin") || c.name.ends_with("cos_qs2"),
                    "{}",
                    c.name
                );
            } else {
                assert!(c.name.ends_with(suffix(c.unit)), "{} in {}", c.name, c.unit);
            }
            let rate = c.unit.ends_with("/s");
            let acc = c.unit.ends_with("/s^2");
            assert_eq!(c.name.contains("_rate_"), rate, "{}", c.name);
            assert_eq!(c.name.contains("_acc_"), acc, "{}", c.name);
        }
    }

    #[test]
    fn the_csv_is_the_first_57_columns() {
        assert_eq!(CSV_COUNT, 57);
        assert!(ALL[..57].iter().all(|c| c.csv));
        assert!(ALL[57..].iter().all(|c| !c.csv));
        assert_eq!(CSV_NAMES[0], "t_s");
        assert_eq!(CSV_NAMES[31], "left_qs1_deg");
        assert_eq!(CSV_NAMES[52], "right_tip_err_mm");
        assert_eq!(
            CSV_NAMES[53..],
            [
                "clearance_left_right_mm",
                "clearance_left_endoscope_mm",
                "clearance_right_endoscope_mm",
                "clearance_min_mm"
            ]
        );
        assert_eq!(csv_index(&LEFT.q[0]), Some(31));
        assert_eq!(csv_index(&LEFT.tip[0]), None);
    }

    #[test]
    fn the_command_column_comes_last_and_only_with_commands() {
        assert_eq!(csv_columns(false).len(), 57);
        assert_eq!(csv_columns(true).len(), 58);
        assert_eq!(CSV_WITH_COMMAND_NAMES[..57], CSV_NAMES);
        assert_eq!(CSV_WITH_COMMAND_NAMES[57], "command");
        assert!(csv_columns(true)[57].integer);
        assert!(csv_columns(true)[..57].iter().all(|c| !c.integer));
        assert!(ALL.iter().all(|c| c.name != COMMAND.name));
        assert_eq!(csv_index(&COMMAND), None);
        let r = Record {
            command: 3,
            ..Record::default()
        };
        assert_eq!(COMMAND.value(&r), 3.0);
    }

    #[test]
    fn channels_hold_the_documented_fields() {
        let count = |ch: Channel| ALL.iter().filter(|c| c.channel == Some(ch)).count();
        assert_eq!(Channel::ALL.map(count), [10, 18, 9, 9, 8, 8]);
        assert_eq!(T_S.channel, None);
        assert_eq!(LEFT.q_acc[2].channel, Some(Channel::Left));
        assert_eq!(LEFT.tip_err.channel, Some(Channel::Tips));
        assert_eq!(RIGHT.cos_qs2.channel, Some(Channel::Margins));
        assert_eq!(MODULE1_PARALLEL_MARGIN.channel, Some(Channel::Margins));
        assert_eq!(Q_ACC_MM_S2[5].channel, Some(Channel::Module1));
        assert_eq!(PSI_DEG.channel, Some(Channel::Platform));
    }

    #[test]
    fn the_force_columns_come_last_and_only_with_loads() {
        use crate::scenario::{Online, Run, Scenario, Turn};
        let loaded = Scenario {
            tip_load_right_n: Some([0.0, 0.0, 1.0]),
            ..Scenario::paper()
        };
        let n = CSV_COUNT;
        assert_eq!(csv_columns_of(&Scenario::paper()).len(), n);
        let cols = csv_columns_of(&loaded);
        assert_eq!(cols.len(), n + 14);
        assert_eq!(cols[n].name, "q1_force_n");
        assert_eq!(cols[n + 11].name, "right_qs3_force_n");
        assert_eq!(cols[n + 13].name, "right_tip_deflection_mm");
        let with_command = Scenario {
            run: Run::Online(Online {
                turn: Turn::paper(),
                retargets: Vec::new(),
                stop_at_s: Some(1.0),
            }),
            ..loaded.clone()
        };
        let cols = csv_columns_of(&with_command);
        assert_eq!((cols[n].name, cols[n + 1].name), ("command", "q1_force_n"));
        let mut r = Record::default();
        r.forces.module1[4] = -3.5;
        r.forces.left[2] = 2.0;
        r.forces.right[0] = 40.0;
        assert_eq!(FORCES[4].value(&r), -3.5);
        assert_eq!(FORCES[8].value(&r), 2.0);
        assert_eq!(FORCES[9].value(&r), 40.0);
        let mut names: Vec<&str> = CSV_WITH_PROCEDURE_AND_FORCES
            .iter()
            .map(|c| c.name)
            .collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), CSV_COUNT + 26);
    }

    #[test]
    fn values_are_in_the_columns_units() {
        let mut r = Record {
            angles_deg: [90.0, 0.0, 0.0],
            ..Record::default()
        };
        r.left.q = [core::f64::consts::PI, 0.0, 120.0];
        r.right.tip.z = -600.0;
        r.module1.q_ddot[5] = 7.0;
        assert_eq!(PSI_DEG.value(&r), 90.0);
        assert_eq!(LEFT.q[0].value(&r), 180.0);
        assert_eq!(LEFT.q[2].value(&r), 120.0);
        assert_eq!(RIGHT.tip[2].value(&r), -600.0);
        assert_eq!(Q_ACC_MM_S2[5].value(&r), 7.0);
        r.clearance.left_right = 3.0;
        r.clearance.left_endoscope = -1.5;
        r.clearance.right_endoscope = 2.0;
        assert_eq!(CLEARANCE_LEFT_ENDOSCOPE_MM.value(&r), -1.5);
        assert_eq!(CLEARANCE_MIN_MM.value(&r), -1.5);
        let row = csv_row(&r);
        assert_eq!(
            (row[4], row[31], row[33], row[28]),
            (90.0, 180.0, 120.0, 7.0)
        );
    }
}
