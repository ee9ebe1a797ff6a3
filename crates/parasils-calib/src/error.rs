//! What can go wrong in a calibration, each error saying where.

/// A calibration's or a pose plan's failure.
///
/// Rows are counted from 1 among the data rows (in a CSV file, row `k` is
/// on line `k + 1`, after the header).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CalibError {
    /// The measurements could not be read (I/O or malformed CSV).
    #[error("{origin}: {message}")]
    Read {
        /// The file, or `"measurements"`.
        origin: String,
        /// What the reader said.
        message: String,
    },

    /// A required column is absent.
    #[error("{origin}: missing column `{column}` (the columns are {found})")]
    MissingColumn {
        /// The file, or `"measurements"`.
        origin: String,
        /// The column's name.
        column: String,
        /// The columns present, comma-separated.
        found: String,
    },

    /// A cell is not a number.
    #[error("{origin}: row {row}, column `{column}`: `{text}` is not a number")]
    NotANumber {
        /// The file, or `"measurements"`.
        origin: String,
        /// The data row, from 1.
        row: usize,
        /// The column.
        column: String,
        /// The cell.
        text: String,
    },

    /// A value is NaN or infinite, or a standard deviation is negative.
    #[error("row {row}, `{column}` = {value}: {reason}")]
    BadValue {
        /// The data row, from 1.
        row: usize,
        /// The column (or array and index).
        column: String,
        /// The value.
        value: f64,
        /// Why it is refused.
        reason: &'static str,
    },

    /// Some rows give standard deviations and this one's leave its readings
    /// without uncertainty (all 0, or only some of the pose's).
    #[error(
        "row {row}: the standard deviations leave the readings without uncertainty; give sigma_q_mm > 0 here, or no standard deviation in any row"
    )]
    ZeroSigma {
        /// The data row, from 1.
        row: usize,
    },

    /// The robot's parameters are invalid.
    #[error("invalid nominal robot: {0}")]
    Robot(#[from] parasils_kin::Error),

    /// A measured pose is out of the nominal robot's reach.
    #[error(
        "row {row}: the pose is out of reach of the nominal robot (actuator q{actuator}: the node is farther from its guide than the link is long, l^2 - d^2 = {discriminant_mm2} mm^2)"
    )]
    OutOfReach {
        /// The data row, from 1.
        row: usize,
        /// The actuator, 1 to 6.
        actuator: u8,
        /// `l^2 - d^2`, mm^2 (negative).
        discriminant_mm2: f64,
    },

    /// Too few measured poses for the parameters.
    #[error(
        "{poses} measured poses give {equations} equations, not more than the {parameters} identifiable parameters: at least {needed} poses are needed"
    )]
    TooFewPoses {
        /// The poses given.
        poses: usize,
        /// `6 poses`.
        equations: usize,
        /// The parameters that can be identified.
        parameters: usize,
        /// The fewest poses that give more equations than parameters.
        needed: usize,
    },

    /// The fit left the plausible region: a parameter moved beyond its bound
    /// from the nominal, or no step reduced the residual.
    #[error("the fit diverged at iteration {iteration} (RMS residual {rms_mm} mm): {reason}")]
    Diverged {
        /// The iteration, from 1.
        iteration: u32,
        /// The RMS actuator residual there, mm.
        rms_mm: f64,
        /// What happened, with the parameter and the numbers.
        reason: String,
    },

    /// The fit had not converged after the allowed iterations.
    #[error(
        "the fit did not converge in {iterations} iterations (RMS residual {rms_mm} mm, last step {step} scaled mm)"
    )]
    MaxIterations {
        /// The iterations made.
        iterations: u32,
        /// The RMS actuator residual at the end, mm.
        rms_mm: f64,
        /// The last step's size, scaled parameters (mm).
        step: f64,
    },

    /// The pose planner found too few admissible candidates.
    #[error(
        "only {found} admissible poses in {attempts} random draws, fewer than the {needed} needed: widen the ranges or lower the margins"
    )]
    TooFewCandidates {
        /// Admissible candidates found.
        found: usize,
        /// Draws made.
        attempts: usize,
        /// Candidates needed.
        needed: usize,
    },

    /// An option is out of its range.
    #[error("invalid option {what} = {value}: {reason}")]
    Option {
        /// The option.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The range.
        reason: &'static str,
    },
}
