//! The values module 1's solvers take and return: actuators, margins and
//! solutions.

use core::ops::Index;

use crate::error::{Error, check_finite};
use crate::frame::Pose;
use crate::real::Real;

/// The six actuators `q1..q6` (index 0 to 5), or their rates.
///
/// As positions: the readings, mm: the slider's position along its guide
/// from its point `G_j` plus the guide's encoder offset. As rates: mm/s;
/// as accelerations: mm/s^2.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Actuators<T>(pub [T; 6]);

impl<T: Real> Actuators<T> {
    /// The actuators from `[q1, ..., q6]` (mm, mm/s or mm/s^2).
    pub const fn new(q: [T; 6]) -> Self {
        Self(q)
    }

    /// `[q1, ..., q6]`.
    pub fn to_array(&self) -> [T; 6] {
        self.0
    }

    /// The largest absolute value, in the actuators' unit.
    pub fn amax(&self) -> T {
        self.0.iter().fold(T::zero(), |m, v| m.max(v.abs()))
    }

    /// `Err(Error::NonFinite)` naming the first NaN or infinite actuator
    /// (`"q1"` to `"q6"`).
    pub fn check_finite(&self) -> Result<(), Error> {
        const NAMES: [&str; 6] = ["q1", "q2", "q3", "q4", "q5", "q6"];
        for (v, name) in self.0.iter().zip(NAMES) {
            check_finite(*v, name)?;
        }
        Ok(())
    }
}

impl<T> Index<usize> for Actuators<T> {
    type Output = T;
    /// Actuator `q_(j+1)`: index 0 is `q1`.
    fn index(&self, j: usize) -> &T {
        &self.0[j]
    }
}

/// What a controller watches on module 1 every cycle (see the
/// [module docs](crate::parallel) for the physical meaning).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParallelMargins<T> {
    /// Per actuator, the serial margin `|e_j . u_j| / l_j` (dimensionless): 1
    /// with the link along its guide, 0 with the link perpendicular to it
    /// (serial singularity, edge of the leg's reach).
    pub serial: [T; 6],
    /// The smallest of [`ParallelMargins::serial`].
    pub serial_min: T,
    /// The parallel margin (dimensionless): the smallest singular value of the
    /// Jacobian `(e_j, (R a_i) x e_j / L) / l_j`; 0 at a parallel singularity.
    pub parallel: T,
    /// Per actuator, the distance to the nearer end of its stroke, mm
    /// (negative beyond it).
    pub stroke: [T; 6],
}

/// Module 1 at one instant: the actuators, their rates and accelerations, and
/// the margins.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParallelSolution<T> {
    /// Actuator positions, mm.
    pub q: Actuators<T>,
    /// Actuator velocities, mm/s.
    pub q_dot: Actuators<T>,
    /// Actuator accelerations, mm/s^2.
    pub q_ddot: Actuators<T>,
    /// Margins at this pose.
    pub margins: ParallelMargins<T>,
}

/// The result of the forward kinematics.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FkSolution<T> {
    /// The platform pose (mm, rad). The angles are those Newton's method
    /// reached from the guess: not wrapped, so continuous with the guess.
    pub pose: Pose<T>,
    /// The Newton steps taken (0 when the guess already satisfied the test).
    pub iterations: u32,
    /// The final residual `max_j |f_j| / l_j` (dimensionless), at most the
    /// tolerance.
    pub residual: T,
}

/// `j + 1` as a `u8` (the actuators are numbered 1 to 6).
pub(super) fn actuator_number(j: usize) -> u8 {
    match j {
        0 => 1,
        1 => 2,
        2 => 3,
        3 => 4,
        4 => 5,
        _ => 6,
    }
}
