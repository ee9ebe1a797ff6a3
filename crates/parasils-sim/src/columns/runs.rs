//! The columns each kind of run writes: the CSV's, with commands, in a
//! procedure, with tip loads.

use super::column::{Column, INDEX, MM};
use super::table::{ALL, COMMAND, LEFT, RIGHT, T_S};
use crate::record::Record;

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
    let loads = scenario.has_forces();
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

/// The columns a run with forces (a tip load, or the robot's `[dynamics]`)
/// adds after its others: every actuator's force holding the loads and
/// moving the platform's body ([`Record::forces`], see `docs/model.md`,
/// *Forces*): module 1's slider forces `q1_force_n` .. `q6_force_n` (N,
/// positive pushing the slider along its guide's direction `u`), then each
/// instrument module's `qs1`, `qs2` torques (N mm) and `qs3` force (N),
/// then how far each tip gives way under the tissue's push with the
/// robot's actuator stiffnesses (mm). In the CSV and Python; in MCAP on
/// their own channel, `/forces` (no column channel of the table).
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
