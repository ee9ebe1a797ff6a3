//! Module 1's forward kinematics by the chord method (simplified Newton):
//! every step solved with one Jacobian inverted beforehand, at a pose near
//! the solution, possibly of a slightly different robot (see the
//! [module docs](crate::parallel), *Forward kinematics by the chord method*).

use nalgebra::{Matrix3, Vector3};

use super::geometry::FkOptions;
use super::ik::ParallelRobot;
use super::types::{Actuators, FkSolution};
use crate::error::{Error, ParallelSingularity};
use crate::frame::{Pose, rotation_from_sin_cos};
use crate::linalg::{Mat6, Svd6, mul, transpose};
use crate::real::Real;

/// Module 1's scaled Jacobian at one pose, inverted: the fixed matrix of the
/// chord method ([`ParallelRobot::fk_chord`]).
///
/// The Jacobian is the one of Newton's method in
/// [`ParallelRobot::fk`]: rows `(e_j / l_j, (R a_i) x e_j / (l_j L))` on the
/// unknowns `(dP, L omega_F)` (mm, `omega_F` the rotation's increment in the
/// fixed frame, rad), so its smallest singular value is the parallel margin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FkChord<T: Real> {
    /// The rows of `J^-1`.
    inverse: Mat6<T>,
    /// `L` of the robot the Jacobian belongs to, mm.
    length_scale: T,
    /// The smallest singular value of `J` (dimensionless).
    margin: T,
}

impl<T: Real> FkChord<T> {
    /// The parallel margin at the pose the chord was taken at: the smallest
    /// singular value of the scaled Jacobian (dimensionless).
    pub fn margin(&self) -> T {
        self.margin
    }
}

/// The largest ratio of two successive residuals of the chord method: a
/// slower iteration is refused (the Jacobian is too far from the robot's).
const CHORD_MAX_RATIO: f64 = 0.5;

/// The chord is used only where its margin is at least this many times the
/// robot's parallel threshold, so that a robot near it (a contraction ratio
/// of at most [`CHORD_MAX_RATIO`]) stays clear of the threshold too.
const CHORD_MARGIN_FACTOR: f64 = 2.0;

impl<T: Real> ParallelRobot<T> {
    /// This robot's scaled Jacobian at `pose`, inverted once by the singular
    /// value decomposition of [`ParallelRobot::fk`]'s Newton steps: the
    /// chord for the forward kinematics of this robot, or of a slightly
    /// different one (a perturbed or recalibrated copy), near `pose`.
    ///
    /// Errors: a non-finite pose ([`Error::NonFinite`]), a leg out of reach
    /// ([`Error::LegOutOfReach`]), a Jacobian whose smallest singular value
    /// is below the parallel threshold ([`Error::SingularJacobian`], parallel
    /// kind, iteration 0).
    pub fn fk_chord_at(&self, pose: &Pose<T>) -> Result<FkChord<T>, Error> {
        pose.check_finite()?;
        let legs = self.legs(&pose.rotation(), &pose.position())?;
        let rows = self.scaled_jacobian_rows(&legs.rho, &legs.e);
        let svd = Svd6::of_columns::<true>(transpose(&rows));
        let margin = svd.smallest();
        let threshold = self.geometry().thresholds.parallel;
        if !(margin >= threshold) {
            return Err(Error::SingularJacobian {
                kind: ParallelSingularity::Parallel,
                iteration: 0,
                margin: margin.to_f64(),
                threshold: threshold.to_f64(),
            });
        }
        // The columns of J^-1, then its rows.
        let columns: Mat6<T> = core::array::from_fn(|k| {
            svd.solve(&core::array::from_fn(|i| {
                if i == k { T::one() } else { T::zero() }
            }))
        });
        Ok(FkChord {
            inverse: transpose(&columns),
            length_scale: self.length_scale(),
            margin,
        })
    }

    /// Forward kinematics by the chord method: from `start`, steps
    /// `dx = -J^-1 f(x)` with the fixed Jacobian of `chord` (taken by
    /// [`ParallelRobot::fk_chord_at`] near the solution, on this robot or a
    /// nearby one), the rotation's part mapped to the Euler angles at each
    /// iterate, until the residual `max_j |f_j| / l_j` is at most
    /// `options.tolerance`: the stopping rule of [`ParallelRobot::fk_with`],
    /// so both meet the same tolerance.
    ///
    /// Each step costs one evaluation of the constraints and a 6x6 product,
    /// against a singular value decomposition for a Newton step; the
    /// iteration converges linearly, by the ratio of the chord's Jacobian to
    /// the true one, which is small for a start and a chord near the
    /// solution.
    ///
    /// `None` when the method is not safe to use or does not converge
    /// quickly, and the caller should solve by [`ParallelRobot::fk_with`]:
    /// non-finite input, a chord whose margin is below twice this robot's
    /// parallel threshold, a residual that does not at least halve at each
    /// step, `options.max_iterations` steps, an iterate at the Euler angles'
    /// singularity, a solution with a link on the other branch or a
    /// non-finite one. A solution returned satisfies the tolerance;
    /// `FkSolution::iterations` counts the chord steps. It comes with its
    /// rotation matrix `R` (platform to fixed frame), which the iteration
    /// computed last.
    pub fn fk_chord(
        &self,
        q: &Actuators<T>,
        start: &Pose<T>,
        chord: &FkChord<T>,
        options: &FkOptions<T>,
    ) -> Option<(FkSolution<T>, Matrix3<T>)> {
        let thresholds = &self.geometry().thresholds;
        let usable = q.check_finite().is_ok()
            && start.check_finite().is_ok()
            && options.tolerance > T::zero()
            && options.tolerance.finite()
            && chord.margin >= T::lit(CHORD_MARGIN_FACTOR) * thresholds.parallel;
        if !usable {
            return None;
        }
        let sliders: [Vector3<T>; 6] = core::array::from_fn(|j| {
            let g = &self.geometry().guides[j];
            g.point + g.direction * (q[j] - g.encoder_offset)
        });
        let inv_scale = T::one() / chord.length_scale;
        // The constraints at `x`, with the sines and cosines of its angles
        // (the rotation's, reused by the Euler-rate map).
        let at = |x: &Pose<T>| {
            let (s1, c1) = x.psi.sincos();
            let (s2, c2) = x.theta.sincos();
            let (s3, c3) = x.phi.sincos();
            let r = rotation_from_sin_cos(s1, c1, s2, c2, s3, c3);
            (
                self.constraints_at(&x.position(), &r, &sliders),
                r,
                [s1, c1, s2, c2],
            )
        };
        let mut x = *start;
        let (mut c, mut r, mut trig) = at(&x);
        let mut iterations = 0;
        loop {
            if !c.residual.finite() {
                return None;
            }
            if c.residual <= options.tolerance {
                return self.fk_solution(x, &c, iterations).ok().map(|s| (s, r));
            }
            if iterations >= options.max_iterations {
                return None;
            }
            let [s1, c1, s2, c2] = trig;
            if !(c2.abs() >= thresholds.euler) {
                return None;
            }
            let step = mul(&chord.inverse, &c.f.map(|f| -f));
            let w = Vector3::new(step[3], step[4], step[5]) * inv_scale;
            let d_phi = (c1 * w.z - s1 * w.y) / c2;
            let d_theta = c1 * w.y + s1 * w.z;
            let d_psi = w.x - s2 * d_phi;
            let dx = [step[0], step[1], step[2], d_psi, d_theta, d_phi];
            let x0 = x.to_array();
            x = Pose::from_array(core::array::from_fn(|k| x0[k] + dx[k]));
            iterations += 1;
            let previous = c.residual;
            (c, r, trig) = at(&x);
            if !(c.residual <= T::lit(CHORD_MAX_RATIO) * previous) && c.residual > options.tolerance
            {
                return None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On the robot the chord was taken at, from a start 0.5 mm and 0.2 deg
    /// away, the chord method reaches Newton's solution within 1e-10 mm
    /// and 1e-12 rad.
    #[test]
    fn the_chord_method_reaches_newtons_solution() {
        let robot = ParallelRobot::<f64>::assumed();
        let pose = Pose::from_mm_deg(3.0, -2.0, -495.0, 4.0, -3.0, -57.0);
        let q = robot.ik(&pose).expect("reachable");
        let chord = robot.fk_chord_at(&pose).expect("regular");
        let start = Pose::from_mm_deg(3.5, -2.2, -495.3, 4.2, -3.1, -56.9);
        let options = robot.geometry().fk;
        let (by_chord, r) = robot
            .fk_chord(&q, &start, &chord, &options)
            .expect("converges");
        assert_eq!(r, by_chord.pose.rotation());
        let by_newton = robot.fk(&q, &start).expect("converges");
        let (a, b) = (by_chord.pose.to_array(), by_newton.pose.to_array());
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-10, "{a:?} {b:?}");
            assert!((a[k + 3] - b[k + 3]).abs() < 1e-12, "{a:?} {b:?}");
        }
        assert!(by_chord.residual <= options.tolerance);
        assert!(by_chord.iterations >= 2, "{}", by_chord.iterations);
    }

    /// A chord taken 30 deg away does not contract: `None`, not a wrong pose.
    #[test]
    fn a_chord_far_from_the_solution_is_refused() {
        let robot = ParallelRobot::<f64>::assumed();
        let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, -60.0);
        let far = Pose::from_mm_deg(40.0, 30.0, -460.0, 30.0, 25.0, -30.0);
        let chord = robot.fk_chord_at(&far).expect("regular");
        let q = robot.ik(&pose).expect("reachable");
        let options = robot.geometry().fk;
        if let Some((s, _)) = robot.fk_chord(&q, &far, &chord, &options) {
            // If it did converge, it is the true solution.
            let back = robot.ik(&s.pose).expect("reachable");
            for j in 0..6 {
                assert!((back[j] - q[j]).abs() < 1e-9, "{back:?} {q:?}");
            }
        }
        let nan = Pose::from_array([f64::NAN, 0.0, -500.0, 0.0, 0.0, 0.0]);
        assert!(robot.fk_chord(&q, &nan, &chord, &options).is_none());
    }
}
