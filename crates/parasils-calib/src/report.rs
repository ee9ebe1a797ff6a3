//! What a calibration reports, as JSON for `--report` and as a dict in
//! Python.

use serde::Serialize;

/// One identified parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identified {
    /// Its name ([`crate::params::Parameter::name`]).
    pub name: String,
    /// `"mm"` or `"1"`.
    pub unit: &'static str,
    /// The nominal value.
    pub nominal: f64,
    /// The fitted value.
    pub fitted: f64,
    /// `fitted - nominal`.
    pub change: f64,
    /// The standard deviation of the fitted value.
    pub std_dev: f64,
}

/// One parameter fixed to its nominal value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FixedParameter {
    /// Its name.
    pub name: String,
    /// `"mm"` or `"1"`.
    pub unit: &'static str,
    /// Its (nominal) value.
    pub value: f64,
    /// Why it is fixed.
    pub reason: String,
    /// What a unit change of it is equivalent to: `[name, change]` of
    /// identified parameters, largest first.
    pub equivalent_to: Vec<(String, f64)>,
}

/// The observability of the identified parameters from a set of poses:
/// indices of the singular values `sigma_1 >= ... >= sigma_n` of the scaled
/// identification Jacobian (unweighted, the parameters in their scales:
/// 1 mm, or the tilt that moves a link's far end by 1 mm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Observability {
    /// `sigma_1`.
    pub singular_value_max: f64,
    /// `sigma_n`: the smallest change of the readings (RMS over all
    /// equations times their square root, mm) that a unit change of the
    /// parameters can make.
    pub singular_value_min: f64,
    /// `sigma_1 / sigma_n`.
    pub condition_number: f64,
    /// `sigma_n^2 / sigma_1`, the noise amplification index.
    pub noise_amplification_index: f64,
}

/// How the fit ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    /// Levenberg-Marquardt iterations (Jacobian evaluations).
    pub iterations: u32,
    /// `"step"` (the last step was below the tolerance), `"gradient"`, or
    /// `"no decrease"` (no step decreased the residual, at a point where
    /// none could).
    pub converged_by: &'static str,
}

/// The worst residual after the fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Worst {
    /// The data row, from 1.
    pub row: usize,
    /// The actuator, 1 to 6.
    pub actuator: u8,
    /// `q_measured - q_predicted`, mm.
    pub residual_mm: f64,
}

/// The calibration report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// Measured poses used.
    pub poses: usize,
    /// Equations (6 per pose).
    pub equations: usize,
    /// How the residuals were weighted.
    pub weighting: String,
    /// How the fit ended.
    pub outcome: Outcome,
    /// RMS of `q_measured - q_predicted` with the nominal geometry, mm.
    pub rms_before_mm: f64,
    /// The same with the fitted geometry, mm.
    pub rms_after_mm: f64,
    /// The largest residual after the fit.
    pub worst_after: Worst,
    /// The weighted sum of squared residuals over the degrees of freedom
    /// (about 1 when the standard deviations are right; the squared RMS
    /// residual over its degrees of freedom without them). The standard
    /// deviations are scaled by its square root.
    pub variance_factor: f64,
    /// The identified parameters, in vector order.
    pub identified: Vec<Identified>,
    /// The parameters fixed to their nominal values, and why.
    pub fixed: Vec<FixedParameter>,
    /// At the fitted geometry.
    pub observability: Observability,
}

impl Report {
    /// The report as indented JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}
