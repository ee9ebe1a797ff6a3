//! Measurements: per row the six actuator readings and the measured pose,
//! with optional standard deviations; read from and written as CSV with the
//! column names of `parasils simulate`'s CSV.

use std::io::Read;

use crate::error::CalibError;
use crate::model::PoseMmDeg;

/// The required columns: the readings, then the pose.
pub const COLUMNS: [&str; 12] = [
    "q1_mm",
    "q2_mm",
    "q3_mm",
    "q4_mm",
    "q5_mm",
    "q6_mm",
    "x_mm",
    "y_mm",
    "z_mm",
    "psi_deg",
    "theta_deg",
    "phi_deg",
];

/// The optional columns of per-row standard deviations.
pub const SIGMA_COLUMNS: [&str; 3] = ["sigma_q_mm", "sigma_position_mm", "sigma_angle_deg"];

/// The standard deviations of one row's measurements.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Sigma {
    /// Of each actuator reading, mm.
    pub q_mm: f64,
    /// Of each coordinate of the measured position, mm.
    pub position_mm: f64,
    /// Of each measured Euler angle, deg.
    pub angle_deg: f64,
}

impl Sigma {
    /// Whether all three are 0 (no weighting information).
    pub fn is_zero(&self) -> bool {
        self.q_mm == 0.0 && self.position_mm == 0.0 && self.angle_deg == 0.0
    }
}

/// One measured row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// The actuator readings `q1..q6`, mm.
    pub q_mm: [f64; 6],
    /// The measured pose.
    pub pose: PoseMmDeg,
    /// Its standard deviations (all 0: none given).
    pub sigma: Sigma,
}

/// Checks every value: finite, standard deviations not negative.
pub fn check(data: &[Measurement]) -> Result<(), CalibError> {
    for (k, m) in data.iter().enumerate() {
        let values = m.q_mm.iter().chain(&m.pose);
        for (v, name) in values.zip(COLUMNS) {
            if !v.is_finite() {
                return Err(CalibError::BadValue {
                    row: k + 1,
                    column: name.to_owned(),
                    value: *v,
                    reason: "not a finite number",
                });
            }
        }
        let s = [m.sigma.q_mm, m.sigma.position_mm, m.sigma.angle_deg];
        for (v, name) in s.iter().zip(SIGMA_COLUMNS) {
            if !(v.is_finite() && *v >= 0.0) {
                return Err(CalibError::BadValue {
                    row: k + 1,
                    column: name.to_owned(),
                    value: *v,
                    reason: "a standard deviation must be finite and >= 0",
                });
            }
        }
    }
    Ok(())
}

/// The measurements in CSV text from `reader` (a header row naming the
/// columns, in any order, others ignored), each row checked ([`check`]).
/// `origin` names the source in errors. Rows without the optional
/// standard-deviation columns get `default_sigma`.
pub fn read_csv<R: Read>(
    reader: R,
    origin: &str,
    default_sigma: Sigma,
) -> Result<Vec<Measurement>, CalibError> {
    let read_error = |e: csv::Error| CalibError::Read {
        origin: origin.to_owned(),
        message: e.to_string(),
    };
    let mut csv = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(reader);
    let header: Vec<String> = csv
        .headers()
        .map_err(read_error)?
        .iter()
        .map(str::to_owned)
        .collect();
    let find = |name: &str| header.iter().position(|h| h == name);
    let mut index = [0usize; 12];
    for (slot, name) in index.iter_mut().zip(COLUMNS) {
        *slot = find(name).ok_or_else(|| CalibError::MissingColumn {
            origin: origin.to_owned(),
            column: name.to_owned(),
            found: header.join(", "),
        })?;
    }
    let sigma_index = SIGMA_COLUMNS.map(find);
    let mut out = Vec::new();
    for (k, record) in csv.records().enumerate() {
        let record = record.map_err(read_error)?;
        let row = k + 1;
        let cell = |i: usize, name: &str| -> Result<f64, CalibError> {
            let text = record.get(i).unwrap_or("");
            text.parse::<f64>().map_err(|_| CalibError::NotANumber {
                origin: origin.to_owned(),
                row,
                column: name.to_owned(),
                text: text.to_owned(),
            })
        };
        let mut v = [0.0; 12];
        for ((slot, &i), name) in v.iter_mut().zip(&index).zip(COLUMNS) {
            *slot = cell(i, name)?;
        }
        let mut s = [
            default_sigma.q_mm,
            default_sigma.position_mm,
            default_sigma.angle_deg,
        ];
        for ((slot, i), name) in s.iter_mut().zip(sigma_index).zip(SIGMA_COLUMNS) {
            if let Some(i) = i {
                *slot = cell(i, name)?;
            }
        }
        let m = Measurement {
            q_mm: [v[0], v[1], v[2], v[3], v[4], v[5]],
            pose: [v[6], v[7], v[8], v[9], v[10], v[11]],
            sigma: Sigma {
                q_mm: s[0],
                position_mm: s[1],
                angle_deg: s[2],
            },
        };
        check(core::slice::from_ref(&m)).map_err(|e| match e {
            CalibError::BadValue {
                column,
                value,
                reason,
                ..
            } => CalibError::BadValue {
                row,
                column,
                value,
                reason,
            },
            other => other,
        })?;
        out.push(m);
    }
    Ok(out)
}

/// The measurements as CSV text: the twelve [`COLUMNS`], and the
/// [`SIGMA_COLUMNS`] when some row has standard deviations. Numbers in
/// their shortest round-trip form.
pub fn to_csv_string(data: &[Measurement]) -> String {
    let with_sigma = data.iter().any(|m| !m.sigma.is_zero());
    let mut out = COLUMNS.join(",");
    if with_sigma {
        out.push(',');
        out.push_str(&SIGMA_COLUMNS.join(","));
    }
    out.push('\n');
    for m in data {
        let mut cells: Vec<String> = m.q_mm.iter().chain(&m.pose).map(f64::to_string).collect();
        if with_sigma {
            cells.extend(
                [m.sigma.q_mm, m.sigma.position_mm, m.sigma.angle_deg].map(|v| v.to_string()),
            );
        }
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    out
}
