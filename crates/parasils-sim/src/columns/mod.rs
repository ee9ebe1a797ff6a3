//! The output columns, in one table: each with its name (which ends with its
//! unit), its unit, its MCAP channel, whether the CSV has it, and how its
//! value is read from a [`Record`](crate::Record).
//!
//! Everything that writes a record out is derived from [`ALL`]: the CSV
//! header and rows ([`csv`](crate::csv)), the MCAP channels, their fields and
//! JSON schemas ([`mcap`](crate::mcap)), the [`summary`](crate::summary), and
//! the Python bindings' `COLUMNS` and arrays. Adding a column is one entry
//! here: a named constant, listed in [`ALL`].
//!
//! One column is not in [`ALL`]: [`COMMAND`], the index of the active
//! command, which only runs with commands (retargets, a stop) have. Their
//! CSV is [`CSV_WITH_COMMAND`], the 74 columns of [`CSV`] and `command` last,
//! and their MCAP file has it on `/motion`; a run without commands writes
//! exactly what it wrote before commands existed ([`csv_columns`] picks).
//!
//! Angles are written in degrees, lengths in mm, times in s; margins are
//! dimensionless. Rates are `_rate_` and accelerations `_acc_` in the names.
//! The Euler angles are written as [`Record::angles_deg`](crate::Record::angles_deg), which gives back
//! the user's start angles exactly.

mod column;
mod runs;
mod table;

pub use column::{Channel, Column};
pub(crate) use runs::join;
pub use runs::{
    CSV, CSV_COUNT, CSV_NAMES, CSV_WITH_COMMAND, CSV_WITH_COMMAND_AND_FORCES,
    CSV_WITH_COMMAND_NAMES, CSV_WITH_FORCES, CSV_WITH_PROCEDURE, CSV_WITH_PROCEDURE_AND_FORCES,
    FORCES, PROCEDURE, csv_columns, csv_columns_of, csv_index, csv_row,
};
pub use table::{
    ALL, CAMERA_AIM_ERROR_DEG, CAMERA_ROLL_DEG, CLEARANCE_LEFT_ENDOSCOPE_MM,
    CLEARANCE_LEFT_RIGHT_MM, CLEARANCE_MIN_MM, CLEARANCE_RIGHT_ENDOSCOPE_MM, COMMAND,
    InstrumentColumns, LEFT, LEFT_TIP_IN_VIEW, LEFT_TIP_U, LEFT_TIP_V, MODULE1_PARALLEL_MARGIN,
    MODULE1_SERIAL_MARGIN, PHI_DEG, PORTS, PSI_ACC_DEG_S2, PSI_DEG, PSI_RATE_DEG_S, Q_ACC_MM_S2,
    Q_MM, Q_RATE_MM_S, RIGHT, RIGHT_TIP_IN_VIEW, RIGHT_TIP_U, RIGHT_TIP_V, T_S, THETA_ACC_DEG_S2,
    THETA_DEG, THETA_RATE_DEG_S, X_MM, Y_MM, Z_MM,
};

#[cfg(test)]
mod tests;
