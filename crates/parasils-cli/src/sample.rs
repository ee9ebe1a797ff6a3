//! One sample of a simulation, and the columns it is written as.
//!
//! A [`Sample`] holds everything computed at one instant, in the libraries'
//! units (mm, rad, s). [`COLUMNS`] names the CSV columns, each with its unit,
//! and [`Sample::row`] gives the values in those units (degrees for angles):
//! the CSV writer, the MCAP writer and the Python bindings all read them from
//! here, so they agree to the last bit.

use nalgebra::Vector3;

/// One instrument module at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ModuleSample {
    /// `qs1, qs2` (rad), `qs3` (mm).
    pub q: [f64; 3],
    /// Joint rates (rad/s, rad/s, mm/s).
    pub q_dot: [f64; 3],
    /// Joint accelerations (rad/s^2, rad/s^2, mm/s^2).
    pub q_ddot: [f64; 3],
    /// `cos qs2` (signed: positive in assembly mode A).
    pub cos_qs2: f64,
    /// The tip recomputed from the joints by forward kinematics, mm, fixed frame.
    pub tip: Vector3<f64>,
    /// The distance from that tip to its target, mm.
    pub tip_err: f64,
}

/// Everything computed at one instant of a simulation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Time since the start of the motion, s.
    pub t: f64,
    /// Platform pose `[x, y, z]` mm and `[psi, theta, phi]` rad.
    pub pose: [f64; 6],
    /// Euler rates `[psi, theta, phi]`, rad/s.
    pub euler_rate: [f64; 3],
    /// Euler accelerations `[psi, theta, phi]`, rad/s^2.
    pub euler_acc: [f64; 3],
    /// Module 1 actuators `q1..q6`, mm.
    pub q: [f64; 6],
    /// Their rates, mm/s.
    pub q_dot: [f64; 6],
    /// Their accelerations, mm/s^2.
    pub q_ddot: [f64; 6],
    /// Module 1's smallest serial margin `min_j |e_j.u_j| / l_j`.
    pub serial_margin: f64,
    /// Module 1's parallel margin (see `parasils_kin::parallel`).
    pub parallel_margin: f64,
    /// The left instrument module.
    pub left: ModuleSample,
    /// The right instrument module.
    pub right: ModuleSample,
}

macro_rules! side_columns {
    ($s:literal) => {
        [
            concat!($s, "_qs1_deg"),
            concat!($s, "_qs2_deg"),
            concat!($s, "_qs3_mm"),
            concat!($s, "_qs1_rate_deg_s"),
            concat!($s, "_qs2_rate_deg_s"),
            concat!($s, "_qs3_rate_mm_s"),
            concat!($s, "_qs1_acc_deg_s2"),
            concat!($s, "_qs2_acc_deg_s2"),
            concat!($s, "_qs3_acc_mm_s2"),
            concat!($s, "_cos_qs2"),
            concat!($s, "_tip_err_mm"),
        ]
    };
}

const fn concat_columns() -> [&'static str; NUM_COLUMNS] {
    const HEAD: [&str; 11] = [
        "t_s",
        "x_mm",
        "y_mm",
        "z_mm",
        "psi_deg",
        "theta_deg",
        "phi_deg",
        "psi_rate_deg_s",
        "theta_rate_deg_s",
        "psi_acc_deg_s2",
        "theta_acc_deg_s2",
    ];
    const MODULE1: [&str; 20] = [
        "q1_mm",
        "q2_mm",
        "q3_mm",
        "q4_mm",
        "q5_mm",
        "q6_mm",
        "q1_rate_mm_s",
        "q2_rate_mm_s",
        "q3_rate_mm_s",
        "q4_rate_mm_s",
        "q5_rate_mm_s",
        "q6_rate_mm_s",
        "q1_acc_mm_s2",
        "q2_acc_mm_s2",
        "q3_acc_mm_s2",
        "q4_acc_mm_s2",
        "q5_acc_mm_s2",
        "q6_acc_mm_s2",
        "module1_serial_margin",
        "module1_parallel_margin",
    ];
    const LEFT: [&str; 11] = side_columns!("left");
    const RIGHT: [&str; 11] = side_columns!("right");
    let mut out = [""; NUM_COLUMNS];
    let mut i = 0;
    while i < 11 {
        out[i] = HEAD[i];
        i += 1;
    }
    let mut j = 0;
    while j < 20 {
        out[11 + j] = MODULE1[j];
        j += 1;
    }
    let mut k = 0;
    while k < 11 {
        out[31 + k] = LEFT[k];
        out[42 + k] = RIGHT[k];
        k += 1;
    }
    out
}

/// The number of CSV columns.
pub const NUM_COLUMNS: usize = 53;

/// The CSV columns, in order, each named with its unit.
pub const COLUMNS: [&str; NUM_COLUMNS] = concat_columns();

impl ModuleSample {
    /// The module's 11 columns, in display units.
    fn columns(&self) -> [f64; 11] {
        let d = f64::to_degrees;
        [
            d(self.q[0]),
            d(self.q[1]),
            self.q[2],
            d(self.q_dot[0]),
            d(self.q_dot[1]),
            self.q_dot[2],
            d(self.q_ddot[0]),
            d(self.q_ddot[1]),
            self.q_ddot[2],
            self.cos_qs2,
            self.tip_err,
        ]
    }
}

impl Sample {
    /// The values of [`COLUMNS`], in the columns' units.
    pub fn row(&self) -> [f64; NUM_COLUMNS] {
        let d = f64::to_degrees;
        let mut out = [0.0; NUM_COLUMNS];
        out[..11].copy_from_slice(&[
            self.t,
            self.pose[0],
            self.pose[1],
            self.pose[2],
            d(self.pose[3]),
            d(self.pose[4]),
            d(self.pose[5]),
            d(self.euler_rate[0]),
            d(self.euler_rate[1]),
            d(self.euler_acc[0]),
            d(self.euler_acc[1]),
        ]);
        out[11..17].copy_from_slice(&self.q);
        out[17..23].copy_from_slice(&self.q_dot);
        out[23..29].copy_from_slice(&self.q_ddot);
        out[29] = self.serial_margin;
        out[30] = self.parallel_margin;
        out[31..42].copy_from_slice(&self.left.columns());
        out[42..53].copy_from_slice(&self.right.columns());
        out
    }
}

/// Where a simulation's samples go, one at a time, in order.
///
/// Writers implement it so that a run of any length streams through without
/// holding the table in memory.
pub trait Sink {
    /// The error a sink can fail with.
    type Error;
    /// Takes the next sample.
    fn push(&mut self, sample: &Sample) -> Result<(), Self::Error>;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_unique_and_complete() {
        let mut sorted = COLUMNS.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), NUM_COLUMNS);
        assert!(COLUMNS.iter().all(|c| !c.is_empty()));
        assert_eq!(COLUMNS[0], "t_s");
        assert_eq!(COLUMNS[31], "left_qs1_deg");
        assert_eq!(COLUMNS[52], "right_tip_err_mm");
    }

    #[test]
    fn row_converts_angles_to_degrees() {
        let s = Sample {
            pose: [1.0, 2.0, 3.0, core::f64::consts::FRAC_PI_2, 0.0, 0.0],
            left: ModuleSample {
                q: [core::f64::consts::PI, 0.0, 120.0],
                ..ModuleSample::default()
            },
            ..Sample::default()
        };
        let r = s.row();
        assert_eq!(r[4], 90.0);
        assert_eq!(r[31], 180.0);
        assert_eq!(r[33], 120.0);
    }
}
