//! Module 1's solver: closed-form inverse kinematics, actuator rates,
//! singularity margins and the scaled Jacobian (see the
//! [module docs](crate::parallel)).

use nalgebra::{Matrix3, Matrix6, RowVector6, Vector3};

use super::geometry::{ParallelGeometry, length_scale};
use super::margin::MarginTracker;
use super::types::{Actuators, ParallelMargins, ParallelSolution, actuator_number};
use crate::check::{check_frame, check_results};
use crate::error::Error;
use crate::frame::{PlatformFrame, PlatformState, Pose};
use crate::linalg::{Mat6, Svd6};
use crate::real::Real;

/// The legs at one pose: what the IK computes and the rates and margins reuse.
pub(super) struct Legs<T: Real> {
    /// `R a_i`, mm, fixed frame.
    pub(super) rho: [Vector3<T>; 3],
    /// `q_j`, the readings (slider position plus encoder offset), mm.
    pub(super) q: [T; 6],
    /// `e_j = A_i - B_j`, mm, fixed frame.
    pub(super) e: [Vector3<T>; 6],
    /// `e_j . u_j`, mm.
    pub(super) eu: [T; 6],
}

/// Module 1, ready to solve: its geometry (guide directions normalised) and
/// the length scale of its parallel margin.
///
/// All positions in mm, angles in rad, fixed frame unless said otherwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParallelRobot<T: Real> {
    geometry: ParallelGeometry<T>,
    length_scale: T,
}

impl<T: Real> ParallelRobot<T> {
    /// Module 1 from its geometry, after [`ParallelGeometry::validate`]; the
    /// guide directions are normalised.
    pub fn new(geometry: ParallelGeometry<T>) -> Result<Self, Error> {
        geometry.validate()?;
        let mut geometry = geometry;
        for g in geometry.guides.iter_mut() {
            g.direction /= g.direction.norm();
        }
        let length_scale = length_scale(&geometry.nodes);
        Ok(Self {
            geometry,
            length_scale,
        })
    }

    /// Module 1 with the **assumed** geometry ([`ParallelGeometry::assumed`]),
    /// not the real robot's.
    pub fn assumed() -> Self {
        let geometry = ParallelGeometry::assumed();
        Self {
            length_scale: length_scale(&geometry.nodes),
            geometry,
        }
    }

    /// The geometry (guide directions normalised).
    pub fn geometry(&self) -> &ParallelGeometry<T> {
        &self.geometry
    }

    /// `L`, the root-mean-square distance of the nodes from `P` (mm): the
    /// length that makes rotations comparable with translations in the
    /// parallel margin.
    pub fn length_scale(&self) -> T {
        self.length_scale
    }

    /// `R a_i` for the three nodes.
    pub(super) fn node_arms(&self, r: &Matrix3<T>) -> [Vector3<T>; 3] {
        self.geometry.nodes.map(|a| r * a)
    }

    /// The closed-form IK of every actuator; checks only the reach.
    pub(super) fn legs(&self, r: &Matrix3<T>, p: &Vector3<T>) -> Result<Legs<T>, Error> {
        let rho = self.node_arms(r);
        let mut q = [T::zero(); 6];
        let mut e = [Vector3::zeros(); 6];
        let mut eu = [T::zero(); 6];
        for (j, g) in self.geometry.guides.iter().enumerate() {
            let r_j = p + rho[j / 2] - g.point;
            let ru = r_j.dot(&g.direction);
            let disc = discriminant(g.link_length, &(r_j - g.direction * ru));
            if !(disc >= T::zero()) {
                return Err(Error::LegOutOfReach {
                    actuator: actuator_number(j),
                    discriminant: disc.to_f64(),
                });
            }
            eu[j] = g.branch.sign::<T>() * disc.sqrt();
            // The slider's position along its guide; the reading adds the
            // encoder offset.
            let slider = ru - eu[j];
            q[j] = slider + g.encoder_offset;
            e[j] = r_j - g.direction * slider;
        }
        // Finite poses and dimensions so large that a leg's numbers
        // overflow the float type.
        check_results(&q, "module 1: actuators (overflow)")?;
        Ok(Legs { rho, q, e, eu })
    }

    /// `Err(SerialSingular)` for the first actuator below the serial threshold.
    fn check_serial(&self, eu: &[T; 6]) -> Result<(), Error> {
        let threshold = self.geometry.thresholds.serial;
        for (j, (g, eu)) in self.geometry.guides.iter().zip(eu).enumerate() {
            let margin = eu.abs() / g.link_length;
            if !(margin >= threshold) {
                return Err(Error::SerialSingular {
                    actuator: actuator_number(j),
                    margin: margin.to_f64(),
                    threshold: threshold.to_f64(),
                });
            }
        }
        Ok(())
    }

    /// `Err(ActuatorLimit)` for the first actuator beyond its stroke.
    pub fn check_strokes(&self, q: &Actuators<T>) -> Result<(), Error> {
        for (j, (g, &qj)) in self.geometry.guides.iter().zip(&q.0).enumerate() {
            if !(qj >= g.stroke.min && qj <= g.stroke.max) {
                return Err(Error::ActuatorLimit {
                    actuator: actuator_number(j),
                    value: qj.to_f64(),
                    min: g.stroke.min.to_f64(),
                    max: g.stroke.max.to_f64(),
                });
            }
        }
        Ok(())
    }

    /// Inverse kinematics: the actuators `q1..q6` (mm) that put the platform
    /// at `pose`, in closed form.
    ///
    /// Errors, checked actuator by actuator in this order: non-finite pose
    /// ([`Error::NonFinite`]), a leg that cannot reach its node
    /// ([`Error::LegOutOfReach`], naming the actuator), a serial margin below
    /// its threshold ([`Error::SerialSingular`]), then an actuator beyond its
    /// stroke ([`Error::ActuatorLimit`]).
    pub fn ik(&self, pose: &Pose<T>) -> Result<Actuators<T>, Error> {
        pose.check_finite()?;
        let legs = self.legs(&pose.rotation(), &pose.position())?;
        self.check_serial(&legs.eu)?;
        let q = Actuators(legs.q);
        self.check_strokes(&q)?;
        Ok(q)
    }

    /// Inverse kinematics without the serial and stroke checks: only a leg
    /// out of reach (or a non-finite pose) is an error.
    pub fn ik_unchecked(&self, pose: &Pose<T>) -> Result<Actuators<T>, Error> {
        pose.check_finite()?;
        Ok(Actuators(self.legs(&pose.rotation(), &pose.position())?.q))
    }

    /// Actuator velocities (mm/s) and accelerations (mm/s^2) from the
    /// platform's motion, in closed form, at the actuators `q` of the
    /// frame's pose (for instance from [`ParallelRobot::ik`]):
    ///
    /// ```text
    /// qdot_j  = (e_j . Adot_i) / (e_j . u_j)
    /// qddot_j = (e_j . Addot_i + |Adot_i - qdot_j u_j|^2) / (e_j . u_j)
    /// ```
    ///
    /// The whole platform motion counts: `Pdot`, `Pddot` (motion type 1) and
    /// the rotation's rates. Returns `(qdot, qddot)`. Fails on non-finite `q`
    /// or a serial margin below its threshold ([`Error::SerialSingular`]).
    pub fn rates(
        &self,
        frame: &PlatformFrame<T>,
        q: &Actuators<T>,
    ) -> Result<(Actuators<T>, Actuators<T>), Error> {
        check_frame(frame)?;
        q.check_finite()?;
        let rho = self.node_arms(&frame.rotation);
        let mut e = [Vector3::zeros(); 6];
        let mut eu = [T::zero(); 6];
        for (j, g) in self.geometry.guides.iter().enumerate() {
            e[j] = frame.position + rho[j / 2] - g.point - g.direction * (q[j] - g.encoder_offset);
            eu[j] = e[j].dot(&g.direction);
        }
        self.check_serial(&eu)?;
        let (q_dot, q_ddot) = self.rates_unchecked(frame, &e, &eu);
        check_rates(&q_dot, &q_ddot)?;
        Ok((q_dot, q_ddot))
    }

    fn rates_unchecked(
        &self,
        frame: &PlatformFrame<T>,
        e: &[Vector3<T>; 6],
        eu: &[T; 6],
    ) -> (Actuators<T>, Actuators<T>) {
        let a = &self.geometry.nodes;
        let a_dot = [
            frame.point_velocity(&a[0]),
            frame.point_velocity(&a[1]),
            frame.point_velocity(&a[2]),
        ];
        let a_ddot = [
            frame.point_acceleration(&a[0]),
            frame.point_acceleration(&a[1]),
            frame.point_acceleration(&a[2]),
        ];
        let mut q_dot = [T::zero(); 6];
        let mut q_ddot = [T::zero(); 6];
        for (j, g) in self.geometry.guides.iter().enumerate() {
            let i = j / 2;
            q_dot[j] = e[j].dot(&a_dot[i]) / eu[j];
            let slip = a_dot[i] - g.direction * q_dot[j];
            q_ddot[j] = (e[j].dot(&a_ddot[i]) + slip.norm_squared()) / eu[j];
        }
        (Actuators(q_dot), Actuators(q_ddot))
    }

    /// The rows of the dimensionless Jacobian of the parallel margin, row `j`:
    /// `(e_j / l_j, (R a_i) x e_j / (l_j L))`.
    pub(super) fn scaled_jacobian_rows(
        &self,
        rho: &[Vector3<T>; 3],
        e: &[Vector3<T>; 6],
    ) -> Mat6<T> {
        let inv_scale = T::one() / self.length_scale;
        let mut rows = [[T::zero(); 6]; 6];
        for (j, (row, g)) in rows.iter_mut().zip(&self.geometry.guides).enumerate() {
            let n = e[j] / g.link_length;
            let m = rho[j / 2].cross(&n) * inv_scale;
            *row = [n.x, n.y, n.z, m.x, m.y, m.z];
        }
        rows
    }

    /// The margins at the legs' pose; the parallel one by `tracker` if given,
    /// else by the full decomposition.
    fn margins_of(
        &self,
        legs: &Legs<T>,
        tracker: Option<&mut MarginTracker<T>>,
    ) -> ParallelMargins<T> {
        let mut serial = [T::zero(); 6];
        let mut stroke = [T::zero(); 6];
        for (j, g) in self.geometry.guides.iter().enumerate() {
            serial[j] = legs.eu[j].abs() / g.link_length;
            stroke[j] = g.stroke.margin(legs.q[j]);
        }
        let serial_min = serial.iter().fold(T::one(), |m, &s| m.min(s));
        let rows = self.scaled_jacobian_rows(&legs.rho, &legs.e);
        let parallel = match tracker {
            Some(tracker) => tracker.margin(&rows),
            // The singular values of J are those of J^T: the rows serve as
            // the columns of the one-sided Jacobi, without a transposed copy.
            None => Svd6::of_columns::<false>(rows).smallest(),
        };
        ParallelMargins {
            serial,
            serial_min,
            parallel,
            stroke,
        }
    }

    /// The margins at `pose` (see [`ParallelMargins`]); neither the serial
    /// threshold nor the strokes are checked, so that a controller can watch
    /// a margin run out. Fails on a non-finite pose or a leg out of reach.
    ///
    /// Cost: the IK and one 6x6 singular value decomposition.
    pub fn margins(&self, pose: &Pose<T>) -> Result<ParallelMargins<T>, Error> {
        pose.check_finite()?;
        Ok(self.margins_of(&self.legs(&pose.rotation(), &pose.position())?, None))
    }

    /// The dimensionless Jacobian whose smallest singular value is the
    /// parallel margin, at `pose`: row `j` is `(e_j / l_j, (R a_i) x e_j / (l_j L))`,
    /// mapping the scaled twist `(Pdot, L omega_F)` (mm/s) to
    /// `(e_j . u_j / l_j) qdot_j` (mm/s). Fails as [`ParallelRobot::margins`].
    pub fn jacobian(&self, pose: &Pose<T>) -> Result<Matrix6<T>, Error> {
        pose.check_finite()?;
        let legs = self.legs(&pose.rotation(), &pose.position())?;
        let rows = self.scaled_jacobian_rows(&legs.rho, &legs.e);
        Ok(Matrix6::from_rows(&rows.map(RowVector6::from)))
    }

    /// Everything a controller needs of module 1 at one instant: the
    /// actuators, their rates and accelerations, and the margins.
    ///
    /// Checks as [`ParallelRobot::ik`] does, **strokes included**: the
    /// controller must refuse a command beyond an actuator's stroke. Then
    /// the parallel margin: below `thresholds.parallel_command` the platform
    /// is no longer held (the IK and the rates are still defined there, but
    /// commanding them is unsafe), [`Error::ParallelSingular`]. A frame with a
    /// NaN or an infinity is [`Error::NonFinite`] (`"frame"`; build frames
    /// with [`PlatformState::frame`], which names the input).
    pub fn solve(&self, frame: &PlatformFrame<T>) -> Result<ParallelSolution<T>, Error> {
        self.solve_with(frame, None)
    }

    /// [`ParallelRobot::solve`] in a control loop: the parallel margin from
    /// the previous cycle's weakest direction, kept in `tracker`, at a
    /// fraction of the cost of the full decomposition when it certifies (see
    /// [`MarginTracker`], and `BENCHMARKS.md` for the costs). The margin
    /// agrees with [`ParallelRobot::solve`]'s within
    /// [`MarginTracker::TOLERANCE_F64`] / 2 relative (`f32`:
    /// [`MarginTracker::TOLERANCE_F32`] / 2), guaranteed, and to rounding in
    /// practice; everything else is the same. Use one tracker per robot and
    /// per motion: a tracker fed poses from elsewhere only falls back to the
    /// full decomposition more often.
    pub fn solve_tracking(
        &self,
        frame: &PlatformFrame<T>,
        tracker: &mut MarginTracker<T>,
    ) -> Result<ParallelSolution<T>, Error> {
        self.solve_with(frame, Some(tracker))
    }

    /// [`ParallelRobot::solve_tracking`] for a platform at rest (a frame
    /// whose rates and accelerations are zero, as
    /// [`PlatformFrame::at_rest`] builds): the same checks, actuators and
    /// margins, the actuators' rates and accelerations zero without being
    /// evaluated. For static studies (the reach map); a control loop uses
    /// [`ParallelRobot::solve_tracking`]. A frame with a non-zero rate is
    /// not refused: its rates are ignored.
    pub fn solve_at_rest(
        &self,
        frame: &PlatformFrame<T>,
        tracker: &mut MarginTracker<T>,
    ) -> Result<ParallelSolution<T>, Error> {
        let (legs, margins) = self.positions(frame, Some(tracker))?;
        Ok(ParallelSolution {
            q: Actuators(legs.q),
            q_dot: Actuators([T::zero(); 6]),
            q_ddot: Actuators([T::zero(); 6]),
            margins,
        })
    }

    /// The position half of [`ParallelRobot::solve`], shared with
    /// [`ParallelRobot::solve_at_rest`]: the frame checked, the legs, the
    /// serial and stroke checks, the margins and the parallel threshold.
    /// Inlined at both: the control step pays no call for it.
    #[inline(always)]
    fn positions(
        &self,
        frame: &PlatformFrame<T>,
        tracker: Option<&mut MarginTracker<T>>,
    ) -> Result<(Legs<T>, ParallelMargins<T>), Error> {
        check_frame(frame)?;
        let legs = self.legs(&frame.rotation, &frame.position)?;
        self.check_serial(&legs.eu)?;
        self.check_strokes(&Actuators(legs.q))?;
        let margins = self.margins_of(&legs, tracker);
        let threshold = self.geometry.thresholds.parallel_command;
        if !(margins.parallel >= threshold) {
            return Err(Error::ParallelSingular {
                margin: margins.parallel.to_f64(),
                threshold: threshold.to_f64(),
            });
        }
        Ok((legs, margins))
    }

    fn solve_with(
        &self,
        frame: &PlatformFrame<T>,
        tracker: Option<&mut MarginTracker<T>>,
    ) -> Result<ParallelSolution<T>, Error> {
        let (legs, margins) = self.positions(frame, tracker)?;
        let (q_dot, q_ddot) = self.rates_unchecked(frame, &legs.e, &legs.eu);
        check_rates(&q_dot, &q_ddot)?;
        Ok(ParallelSolution {
            q: Actuators(legs.q),
            q_dot,
            q_ddot,
            margins,
        })
    }

    /// [`ParallelRobot::solve`] from a platform state (checked for
    /// finiteness first).
    pub fn solve_state(&self, platform: &PlatformState<T>) -> Result<ParallelSolution<T>, Error> {
        self.solve(&platform.frame()?)
    }

    /// The constraint residual `max_j | |A_i - B_j| - l_j | / l_j` of the
    /// actuators `q` at `pose` (dimensionless): 0 when `q` holds the platform
    /// at `pose`.
    pub fn residual(&self, pose: &Pose<T>, q: &Actuators<T>) -> Result<T, Error> {
        pose.check_finite()?;
        q.check_finite()?;
        let rho = self.node_arms(&pose.rotation());
        let p = pose.position();
        let mut worst = T::zero();
        for (j, g) in self.geometry.guides.iter().enumerate() {
            let e = p + rho[j / 2] - g.point - g.direction * (q[j] - g.encoder_offset);
            worst = worst.max((e.norm() - g.link_length).abs() / g.link_length);
        }
        Ok(worst)
    }
}

/// A leg's `l^2 - |r_perp|^2` (mm^2), `r_perp` the part of the node's offset
/// from the guide's point across the guide: the square of the leg's extent
/// along its guide, negative when the leg cannot reach.
///
/// From the squared distance, with one square root a leg (that of the
/// result) instead of two: `(l - d) (l + d)` with `d = |r_perp|` is no more
/// accurate near 0, where it also carries the rounding of `d`. Within
/// `2 eps l^2` of the exact value for the rounded inputs, to first order:
/// each of the six operations rounds by at most `eps / 2` of its result,
/// `l^2`, three squares and two partial sums of `|r_perp|^2 <= l^2`, and
/// the difference, which sum to `(1 + s) eps l^2`, `s = |r_perp|^2 / l^2`
/// (measured near 0 by the test `the_discriminant_is_within_its_bound`:
/// at most 1.55, and 1.86 for the product form).
#[inline(always)]
fn discriminant<T: Real>(link_length: T, r_perp: &Vector3<T>) -> T {
    link_length * link_length - r_perp.norm_squared()
}

/// `Err(Error::NonFinite)` when the actuator rates or accelerations
/// overflowed (finite inputs too large for the float type).
fn check_rates<T: Real>(q_dot: &Actuators<T>, q_ddot: &Actuators<T>) -> Result<(), Error> {
    check_results(&q_dot.0, "module 1: actuator rates (overflow)")?;
    check_results(&q_ddot.0, "module 1: actuator accelerations (overflow)")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An encoder offset adds to every reading and changes nothing else:
    /// the IK's readings, the FK's pose from them, the rates, the solution
    /// and the residual all agree with the robot without offsets.
    #[test]
    fn an_encoder_offset_shifts_the_readings_only() {
        use crate::frame::PoseRate;
        let plain = ParallelRobot::<f64>::assumed();
        let mut g = *plain.geometry();
        let offsets = [1.5, -2.0, 0.0, 0.25, 3.0, -0.75];
        for (guide, o) in g.guides.iter_mut().zip(offsets) {
            guide.encoder_offset = o;
        }
        let shifted = ParallelRobot::new(g).expect("valid");
        let pose = Pose::from_mm_deg(15.0, 20.0, -500.0, -15.0, 10.0, -60.0);
        let q0 = plain.ik(&pose).expect("in reach");
        let q1 = shifted.ik(&pose).expect("in reach");
        for j in 0..6 {
            assert!((q1[j] - q0[j] - offsets[j]).abs() < 1e-12, "q{}", j + 1);
        }
        let guess = Pose::from_mm_deg(20.0, 15.0, -510.0, -10.0, 5.0, -55.0);
        let fk = shifted.fk(&q1, &guess).expect("converges");
        assert!((fk.pose.position() - pose.position()).norm() < 1e-9);
        assert!(shifted.residual(&pose, &q1).expect("finite") < 1e-14);
        assert!(shifted.residual(&pose, &q0).expect("finite") > 1e-4);
        let state = PlatformState {
            pose,
            velocity: PoseRate::euler(0.3, -0.2),
            acceleration: PoseRate::euler(1.0, 0.5),
        };
        let frame = state.frame().expect("finite");
        let (v0, a0) = plain.rates(&frame, &q0).expect("regular");
        let (v1, a1) = shifted.rates(&frame, &q1).expect("regular");
        let s1 = shifted.solve(&frame).expect("regular");
        for j in 0..6 {
            assert!((v1[j] - v0[j]).abs() < 1e-9 && (a1[j] - a0[j]).abs() < 1e-9);
            assert!((s1.q_dot[j] - v0[j]).abs() < 1e-9);
            assert!((s1.q[j] - q1[j]).abs() < 1e-12);
        }
    }

    /// `a + b` as an unevaluated pair `(sum, error)`, exactly (Knuth).
    fn two_sum(a: f64, b: f64) -> (f64, f64) {
        let s = a + b;
        let bb = s - a;
        (s, (a - (s - bb)) + (b - bb))
    }

    /// `l^2 - |r|^2` to about `2^-100` relative to `l^2`: each square exact
    /// as a pair by a fused multiply-add, summed in double-double.
    fn discriminant_reference(l: f64, r: &Vector3<f64>) -> f64 {
        let mut terms = [0.0; 8];
        for (k, (x, sign)) in [(l, 1.0), (r.x, -1.0), (r.y, -1.0), (r.z, -1.0)]
            .into_iter()
            .enumerate()
        {
            let hi = x * x;
            terms[2 * k] = sign * hi;
            terms[2 * k + 1] = sign * x.mul_add(x, -hi);
        }
        let (mut hi, mut lo) = (0.0, 0.0);
        for t in terms {
            let (s, e) = two_sum(hi, t);
            hi = s;
            lo += e;
        }
        hi + lo
    }

    /// Near the serial singularity (`|r_perp| -> l`, the result near 0), the
    /// discriminant stays within its documented `2 eps l^2` of the exact
    /// value; the largest error seen is printed (1.55 eps l^2; the product
    /// form `(l - d) (l + d)` gives 1.86 on the same inputs).
    #[test]
    fn the_discriminant_is_within_its_bound() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut worst: f64 = 0.0;
        for _ in 0..20_000 {
            let l = 200.0 + 200.0 * next();
            // |r_perp| = l (1 - t), t from 1e-15 to 0.5, log-uniform.
            let t = 10f64.powf(-15.0 + 14.7 * next());
            let dir = Vector3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let r = dir * (l * (1.0 - t));
            let err = (discriminant(l, &r) - discriminant_reference(l, &r)).abs();
            worst = worst.max(err / (f64::EPSILON * l * l));
        }
        std::println!("largest error of the discriminant: {worst:.3} eps l^2");
        assert!(worst <= 2.0, "{worst} eps l^2");
        // The bound is not loose: the roundings reach a good part of it.
        assert!(worst > 0.5, "{worst} eps l^2");
    }

    #[test]
    fn length_scale_of_the_assumed_geometry_is_180_mm() {
        let r = ParallelRobot::<f64>::assumed();
        assert!((r.length_scale() - 180.277_563_773_199_47).abs() < 1e-9);
    }
}
