//! The solver of one spherical instrument module: forward and inverse
//! kinematics, the Jacobian and its inverse, joint rates (see the
//! [module docs](crate::instrument)).

use nalgebra::{Matrix3, Vector3};

use super::geometry::InstrumentGeometry;
use super::types::{
    AssemblyMode, InstrumentMargins, InstrumentSolution, JointMotion, Joints, JointsTrig, TipMotion,
};
use crate::check::{check_results, check_vector};
use crate::error::{Error, InstrumentSingularity};
use crate::frame::{PlatformFrame, PlatformState, Pose};
use crate::real::Real;
use crate::side::Side;

/// A spherical instrument module, ready to solve: its geometry and the
/// trigonometry the geometry fixes.
///
/// All positions are in mm, angles in rad. "Local" means the module's RCM
/// frame (parallel to the platform frame, origin at the RCM).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instrument<T: Real> {
    geometry: InstrumentGeometry<T>,
    sin_alpha: T,
    cos_alpha: T,
    sin_beta: T,
    cos_beta: T,
    /// `-1` for the left module, `+1` for the right: the sign of `det J / (qs3^2 cos qs2 cos beta)`.
    mirror: T,
}

/// The sines and cosines of `qs1` and `qs2`.
#[derive(Clone, Copy)]
struct Trig<T> {
    s1: T,
    c1: T,
    s2: T,
    c2: T,
}

/// The left-convention vectors of a configuration (see the
/// [module docs](crate::instrument), *Jacobian*).
struct Basis<T: Real> {
    /// `w = R_Y(-alpha) u`, the tool direction (unit).
    w: Vector3<T>,
    /// `dw/dqs1`.
    a: Vector3<T>,
    /// `dw/dqs2`.
    b: Vector3<T>,
    /// `d2w/dqs2^2`.
    b2: Vector3<T>,
    /// `cos(beta) cos(qs2)`: `a x b = d w`.
    d: T,
}

impl<T: Real> Instrument<T> {
    /// A module from its geometry, after [`InstrumentGeometry::validate`].
    pub fn new(geometry: InstrumentGeometry<T>) -> Result<Self, Error> {
        geometry.validate()?;
        Ok(Self::from_valid(geometry))
    }

    /// The paper's module ([`InstrumentGeometry::paper`]).
    pub fn paper(side: Side) -> Self {
        Self::from_valid(InstrumentGeometry::paper(side))
    }

    fn from_valid(geometry: InstrumentGeometry<T>) -> Self {
        let (sin_alpha, cos_alpha) = geometry.alpha.sincos();
        let (sin_beta, cos_beta) = geometry.beta.sincos();
        let mirror = match geometry.side {
            Side::Left => -T::one(),
            Side::Right => T::one(),
        };
        Self {
            geometry,
            sin_alpha,
            cos_alpha,
            sin_beta,
            cos_beta,
            mirror,
        }
    }

    /// The geometry.
    pub fn geometry(&self) -> &InstrumentGeometry<T> {
        &self.geometry
    }

    /// Left or right.
    pub fn side(&self) -> Side {
        self.geometry.side
    }

    /// `S v` for the right module, `v` for the left: between the module's own
    /// frame and the left convention the solvers work in.
    #[inline]
    fn in_left_convention(&self, v: &Vector3<T>) -> Vector3<T> {
        match self.geometry.side {
            Side::Left => *v,
            Side::Right => Vector3::new(-v.x, v.y, v.z),
        }
    }

    /// `R_Y(alpha) v`.
    #[inline]
    fn rot_alpha(&self, v: &Vector3<T>) -> Vector3<T> {
        let (s, c) = (self.sin_alpha, self.cos_alpha);
        Vector3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
    }

    /// `R_Y(-alpha) v`.
    #[inline]
    fn unrot_alpha(&self, v: &Vector3<T>) -> Vector3<T> {
        let (s, c) = (self.sin_alpha, self.cos_alpha);
        Vector3::new(c * v.x - s * v.z, v.y, s * v.x + c * v.z)
    }

    fn basis(&self, q: &Joints<T>) -> Basis<T> {
        let (s1, c1) = q.qs1.sincos();
        let (s2, c2) = q.qs2.sincos();
        self.basis_of(&Trig { s1, c1, s2, c2 })
    }

    /// The basis from the sines and cosines of `qs1` and `qs2`.
    #[inline]
    fn basis_of(&self, trig: &Trig<T>) -> Basis<T> {
        let Trig { s1, c1, s2, c2 } = *trig;
        let (sb, cb) = (self.sin_beta, self.cos_beta);
        let w = Vector3::new(s2 * cb, -c1 * sb - s1 * c2 * cb, -s1 * sb + c1 * c2 * cb);
        Basis {
            a: Vector3::new(T::zero(), -w.z, w.y),
            b: Vector3::new(c2 * cb, s1 * s2 * cb, -c1 * s2 * cb),
            b2: Vector3::new(-s2 * cb, s1 * c2 * cb, -c1 * c2 * cb),
            d: cb * c2,
            w,
        }
    }

    /// Forward kinematics in the module's RCM frame: the tip `p_local`, mm,
    /// the last column of `M_L` (the paper's equation 3; see `docs/model.md`,
    /// *Instrument modules*).
    pub fn fk_local(&self, q: &Joints<T>) -> Vector3<T> {
        let w = self.basis(q).w;
        self.in_left_convention(&(self.rot_alpha(&w) * -q.qs3))
    }

    /// Forward kinematics in the platform frame: the tip `RCM + p_local`, mm.
    pub fn fk_platform(&self, q: &Joints<T>) -> Vector3<T> {
        self.geometry.rcm + self.fk_local(q)
    }

    /// [`Instrument::fk_platform`] from the joints' sines and cosines
    /// computed beforehand: the same expressions, so the same bits.
    pub fn fk_platform_trig(&self, q: &JointsTrig<T>) -> Vector3<T> {
        let trig = Trig {
            s1: q.s1,
            c1: q.c1,
            s2: q.s2,
            c2: q.c2,
        };
        let w = self.basis_of(&trig).w;
        self.geometry.rcm + self.in_left_convention(&(self.rot_alpha(&w) * -q.qs3))
    }

    /// Forward kinematics: the tip in the fixed frame,
    /// `p_F = R (RCM + p_local(q)) + P`, mm, at the platform pose `pose`
    /// (the paper's equations 2 and 4; see `docs/model.md`, *Instrument
    /// modules*).
    ///
    /// Fails on non-finite input, and on finite input so large that the
    /// tip overflows the float type.
    pub fn fk(&self, pose: &Pose<T>, q: &Joints<T>) -> Result<Vector3<T>, Error> {
        pose.check_finite()?;
        q.check_finite()?;
        let tip = pose.rotation() * self.fk_platform(q) + pose.position();
        check_results(tip.as_slice(), "tip (overflow)")?;
        Ok(tip)
    }

    /// The orientation of the module's last frame (the tool frame) in its
    /// RCM frame: the rotation part of `M_L` (the paper's equation 3),
    /// `R_Y(alpha) R_X(qs1) R_Y(qs2) R_X(beta)` for the left module and its
    /// mirror image `S (..) S` for the right, `S = diag(-1, 1, 1)`. The tool
    /// points along the frame's `-z`, the tip at `z = -qs3`:
    /// `tool_rotation(q) (0, 0, -qs3) = fk_local(q)`.
    ///
    /// For display and logging (the 3D scene); the solvers work from the
    /// tool direction alone and do not need it.
    ///
    /// ```
    /// use parasils_kin::{Instrument, Joints, Side};
    /// use parasils_kin::nalgebra::Vector3;
    /// let right = Instrument::<f64>::paper(Side::Right);
    /// let q = Joints::new(0.3, -0.5, 120.0);
    /// let tip = right.tool_rotation(&q) * Vector3::new(0.0, 0.0, -q.qs3);
    /// assert!((tip - right.fk_local(&q)).norm() < 1e-12);
    /// ```
    pub fn tool_rotation(&self, q: &Joints<T>) -> Matrix3<T> {
        use nalgebra::Rotation3;
        let s = match self.geometry.side {
            Side::Left => T::one(),
            Side::Right => -T::one(),
        };
        let ry = |a: T| Rotation3::from_axis_angle(&Vector3::y_axis(), a);
        let rx = |a: T| Rotation3::from_axis_angle(&Vector3::x_axis(), a);
        (ry(s * self.geometry.alpha) * rx(q.qs1) * ry(s * q.qs2) * rx(self.geometry.beta))
            .into_inner()
    }

    /// The Jacobian `d p_local / d(qs1, qs2, qs3)` in the module's RCM frame
    /// (columns in mm/rad, mm/rad, dimensionless).
    pub fn jacobian(&self, q: &Joints<T>) -> Matrix3<T> {
        let k = self.basis(q);
        let c1 = self.in_left_convention(&self.rot_alpha(&(k.a * -q.qs3)));
        let c2 = self.in_left_convention(&self.rot_alpha(&(k.b * -q.qs3)));
        let c3 = self.in_left_convention(&self.rot_alpha(&-k.w));
        Matrix3::from_columns(&[c1, c2, c3])
    }

    /// `det J = -+ qs3^2 cos(qs2) cos(beta)` (`-` left, `+` right), mm^2/rad^2.
    pub fn jacobian_determinant(&self, q: &Joints<T>) -> T {
        self.mirror * q.qs3 * q.qs3 * q.qs2.sincos().1 * self.cos_beta
    }

    /// The closed-form inverse of [`Instrument::jacobian`], or
    /// [`Error::Singular`] when `|cos qs2|` or `qs3` is below its threshold.
    pub fn jacobian_inverse(&self, q: &Joints<T>) -> Result<Matrix3<T>, Error> {
        q.check_finite()?;
        let k = self.basis(q);
        self.check_singular(k.d / self.cos_beta, q.qs3)?;
        // J_L = -R_Y(alpha) K, K = [qs3 a, qs3 b, w]; K^-1 has rows
        // (b x w)/(qs3 d), (w x a)/(qs3 d), w. J_R = S J_L.
        let scale = T::one() / (q.qs3 * k.d);
        let r1 = k.b.cross(&k.w) * scale;
        let r2 = k.w.cross(&k.a) * scale;
        let k_inv = Matrix3::from_rows(&[r1.transpose(), r2.transpose(), k.w.transpose()]);
        let unrot = Matrix3::new(
            self.cos_alpha,
            T::zero(),
            -self.sin_alpha,
            T::zero(),
            T::one(),
            T::zero(),
            self.sin_alpha,
            T::zero(),
            self.cos_alpha,
        );
        let mut inv = -(k_inv * unrot);
        if self.geometry.side == Side::Right {
            inv.column_mut(0).neg_mut();
        }
        Ok(inv)
    }

    fn check_singular(&self, cos_qs2: T, qs3: T) -> Result<(), Error> {
        let th = &self.geometry.thresholds;
        if !(qs3 >= th.qs3) {
            return Err(Error::Singular {
                side: self.geometry.side,
                margin: InstrumentSingularity::Qs3,
                value: qs3.to_f64(),
                threshold: th.qs3.to_f64(),
            });
        }
        if !(cos_qs2.abs() >= th.cos_qs2) {
            return Err(Error::Singular {
                side: self.geometry.side,
                margin: InstrumentSingularity::CosQs2,
                value: cos_qs2.abs().to_f64(),
                threshold: th.cos_qs2.to_f64(),
            });
        }
        Ok(())
    }

    /// Inverse kinematics from a tip in the module's RCM frame (mm), in the
    /// given assembly mode. Joint limits are **not** checked (see
    /// [`JointLimits::check`](super::JointLimits::check)); reach and
    /// singularity are.
    ///
    /// `qs1` and `qs2` come out in `(-180, 180] deg`.
    pub fn ik_local(&self, p_local: &Vector3<T>, mode: AssemblyMode) -> Result<Joints<T>, Error> {
        self.ik_trig(p_local, mode).map(|(q, _)| q)
    }

    /// [`Instrument::ik_local`], with the sines and cosines of `qs1` and
    /// `qs2` that the IK has on the way: `sin qs2 = v_x / cos(beta)`,
    /// `cos qs2` its root, and `qs1`'s `atan2` arguments divided by their
    /// norm. The rates reuse them instead of evaluating `sincos` of the
    /// angles again (equal to rounding).
    #[inline]
    fn ik_trig(
        &self,
        p_local: &Vector3<T>,
        mode: AssemblyMode,
    ) -> Result<(Joints<T>, Trig<T>), Error> {
        check_vector(p_local, ["tip_local.x", "tip_local.y", "tip_local.z"])?;
        let p = self.in_left_convention(p_local);
        let th = &self.geometry.thresholds;
        let qs3 = p.norm();
        // Finite coordinates whose distance overflows the float type (past
        // about 1e154 mm in f64, 1e19 in f32): no finite qs3 reaches them.
        if !qs3.finite() {
            return Err(Error::NonFinite {
                what: "|tip_local| (beyond the float type)",
                value: qs3.to_f64(),
            });
        }
        if !(qs3 >= th.qs3) {
            return Err(Error::Singular {
                side: self.geometry.side,
                margin: InstrumentSingularity::Qs3,
                value: qs3.to_f64(),
                threshold: th.qs3.to_f64(),
            });
        }
        let v = self.unrot_alpha(&(p / -qs3));
        let sin_qs2 = v.x / self.cos_beta;
        if sin_qs2.abs() > T::one() + th.reach {
            return Err(Error::OutOfReach {
                side: self.geometry.side,
                sin_qs2: sin_qs2.abs().to_f64(),
            });
        }
        let s2 = sin_qs2.max(-T::one()).min(T::one());
        let mut c2 = ((T::one() - s2) * (T::one() + s2)).sqrt();
        if mode == AssemblyMode::B {
            c2 = -c2;
        }
        self.check_singular(c2, qs3)?;
        // atan2(s2, c2) with c2 = +-sqrt(1 - s2^2): asin is the same angle in
        // mode A and its supplement in mode B, at about a third of atan2's
        // cost (libm), within an ulp; +pi (not -pi) for s2 = -0 in mode B.
        let qs2 = match mode {
            AssemblyMode::A => s2.asin(),
            AssemblyMode::B if s2 >= T::zero() => T::pi() - s2.asin(),
            AssemblyMode::B => -T::pi() - s2.asin(),
        };
        let (sb, cb) = (self.sin_beta, self.cos_beta);
        let (y, x) = (-sb * v.z - cb * c2 * v.y, cb * c2 * v.z - sb * v.y);
        let qs1 = y.atan2(x);
        // |(x, y)| = 1 - v_x^2 >= cos(qs2)^2 > 0 past the singularity check;
        // should it underflow (thresholds far below the defaults), the angle's
        // own sine and cosine. libm's here, not `Real::sincos`: this branch
        // does not run with the default thresholds, and `sincos` in it makes
        // the common path measurably slower (the `f32` `ik_local` bench).
        let norm = (x * x + y * y).sqrt();
        let (s1, c1) = if norm > T::zero() {
            let inv = T::one() / norm;
            (y * inv, x * inv)
        } else {
            qs1.sin_cos()
        };
        Ok((Joints::new(qs1, qs2, qs3), Trig { s1, c1, s2, c2 }))
    }

    /// The tip (mm, fixed frame) in the module's RCM frame at `pose`:
    /// `R^T (p_F - P) - RCM`.
    pub fn tip_to_local(&self, pose: &Pose<T>, tip: &Vector3<T>) -> Result<Vector3<T>, Error> {
        pose.check_finite()?;
        check_vector(tip, ["tip.x", "tip.y", "tip.z"])?;
        Ok(pose.rotation().tr_mul(&(tip - pose.position())) - self.geometry.rcm)
    }

    /// Both solutions `[mode A, mode B]` of the inverse kinematics for a tip
    /// (mm, fixed frame) at a platform pose. Joint limits are **not** checked:
    /// with the default limits, mode B is always outside them.
    pub fn ik_solutions(&self, pose: &Pose<T>, tip: &Vector3<T>) -> Result<[Joints<T>; 2], Error> {
        let p = self.tip_to_local(pose, tip)?;
        Ok([
            self.ik_local(&p, AssemblyMode::A)?,
            self.ik_local(&p, AssemblyMode::B)?,
        ])
    }

    /// Inverse kinematics in one assembly mode, joint limits checked.
    pub fn ik(
        &self,
        pose: &Pose<T>,
        tip: &Vector3<T>,
        mode: AssemblyMode,
    ) -> Result<Joints<T>, Error> {
        let q = self.ik_local(&self.tip_to_local(pose, tip)?, mode)?;
        self.geometry.limits.check(self.geometry.side, &q)?;
        Ok(q)
    }

    /// Inverse kinematics continuous with the configuration `current`: the
    /// same assembly mode, and `qs1` unwrapped by whole turns to the value
    /// nearest `current.qs1`. Joint limits checked.
    pub fn ik_continuing(
        &self,
        pose: &Pose<T>,
        tip: &Vector3<T>,
        current: &Joints<T>,
    ) -> Result<Joints<T>, Error> {
        current.check_finite()?;
        let mut q = self.ik_local(&self.tip_to_local(pose, tip)?, AssemblyMode::of(current))?;
        q.qs1 = unwrap_near(q.qs1, current.qs1);
        self.geometry.limits.check(self.geometry.side, &q)?;
        Ok(q)
    }

    /// Margins at `q`: `|cos qs2|`, `qs3` and each joint's distance to its limits.
    pub fn margins(&self, q: &Joints<T>) -> InstrumentMargins<T> {
        InstrumentMargins {
            cos_qs2: q.qs2.sincos().1.abs(),
            qs3: q.qs3,
            limits: self.geometry.limits.margins(q),
        }
    }

    /// Joint velocities and accelerations of the module at `q` from the
    /// platform's motion and the tip's, in the general case (see `docs/model.md`,
    /// *Instrument modules*, rates):
    ///
    /// ```text
    /// qsdot  = J^-1 R^T (p_Fdot - Pdot - Rdot c)
    /// qsddot = J^-1 (R^T (p_Fddot - Pddot - Rddot c - 2 Rdot J qsdot) - Jdot qsdot)
    /// ```
    ///
    /// with `c = RCM + p_local(q)`. `q` must be the joints of the tip at this
    /// instant (for instance from [`Instrument::ik`]). Returns
    /// `(qsdot, qsddot)`; fails with [`Error::Singular`] at a singular `q`.
    pub fn rates(
        &self,
        frame: &PlatformFrame<T>,
        q: &Joints<T>,
        tip_velocity: &Vector3<T>,
        tip_acceleration: &Vector3<T>,
    ) -> Result<(Joints<T>, Joints<T>), Error> {
        q.check_finite()?;
        check_vector(
            tip_velocity,
            ["tip_velocity.x", "tip_velocity.y", "tip_velocity.z"],
        )?;
        check_vector(
            tip_acceleration,
            [
                "tip_acceleration.x",
                "tip_acceleration.y",
                "tip_acceleration.z",
            ],
        )?;
        let k = self.basis(q);
        self.check_singular(k.d / self.cos_beta, q.qs3)?;
        // The tip in the platform frame.
        let c = self.geometry.rcm + self.in_left_convention(&(self.rot_alpha(&k.w) * -q.qs3));
        let (q_dot, q_ddot) =
            self.rates_unchecked(frame, q, &k, &c, tip_velocity, tip_acceleration);
        check_rates(self.geometry.side, &q_dot, &q_ddot)?;
        Ok((q_dot, q_ddot))
    }

    /// The rates at `q` (basis `k`), the tip at `c` (mm, platform frame).
    fn rates_unchecked(
        &self,
        frame: &PlatformFrame<T>,
        q: &Joints<T>,
        k: &Basis<T>,
        c: &Vector3<T>,
        tip_velocity: &Vector3<T>,
        tip_acceleration: &Vector3<T>,
    ) -> (Joints<T>, Joints<T>) {
        let w_b = &frame.omega;
        let a_b = &frame.alpha;
        // The tip's platform-frame rates.
        let c_dot = frame.rotation.tr_mul(&(tip_velocity - frame.velocity)) - w_b.cross(c);
        let c_ddot = frame
            .rotation
            .tr_mul(&(tip_acceleration - frame.acceleration))
            - a_b.cross(c)
            - w_b.cross(&w_b.cross(c))
            - w_b.cross(&c_dot) * T::lit(2.0);
        // In the left convention, y = -R_Y(-alpha) p_local = qs3 w, and
        // y_dot = K qsdot with K = [qs3 a, qs3 b, w].
        let y_dot = -self.unrot_alpha(&self.in_left_convention(&c_dot));
        let y_ddot = -self.unrot_alpha(&self.in_left_convention(&c_ddot));
        let inv_qd = T::one() / (q.qs3 * k.d);
        let ba = k.b.cross(&k.w) * inv_qd;
        let wa = k.w.cross(&k.a) * inv_qd;
        let solve = |y: &Vector3<T>| Joints::new(ba.dot(y), wa.dot(y), k.w.dot(y));
        let qd = solve(&y_dot);
        // y_ddot = K qsddot + 2 qs3dot w_dot + qs3 (a_dot qs1dot + b_dot qs2dot)
        let w_dot = k.a * qd.qs1 + k.b * qd.qs2;
        let a_dot = Vector3::new(T::zero(), -w_dot.z, w_dot.y);
        let b_dot = Vector3::new(T::zero(), -k.b.z, k.b.y) * qd.qs1 + k.b2 * qd.qs2;
        let rhs =
            y_ddot - w_dot * (T::lit(2.0) * qd.qs3) - (a_dot * qd.qs1 + b_dot * qd.qs2) * q.qs3;
        (qd, solve(&rhs))
    }

    /// Everything a controller needs of this module at one instant: joints in
    /// `mode` (limits checked), their rates and accelerations, and margins.
    pub fn solve(
        &self,
        frame: &PlatformFrame<T>,
        tip: &TipMotion<T>,
        mode: AssemblyMode,
    ) -> Result<InstrumentSolution<T>, Error> {
        tip.check_finite()?;
        // The tip in the platform frame, then in the module's RCM frame.
        let c = frame.to_platform(&tip.position);
        let (q, trig) = self.ik_trig(&(c - self.geometry.rcm), mode)?;
        self.geometry.limits.check(self.geometry.side, &q)?;
        // The trigonometry of the IK serves the rates and the margins (the
        // same values as `margins(&q)` and `rates(..)`, to rounding).
        let k = self.basis_of(&trig);
        let (q_dot, q_ddot) =
            self.rates_unchecked(frame, &q, &k, &c, &tip.velocity, &tip.acceleration);
        check_rates(self.geometry.side, &q_dot, &q_ddot)?;
        Ok(InstrumentSolution {
            q,
            q_dot,
            q_ddot,
            margins: InstrumentMargins {
                cos_qs2: trig.c2.abs(),
                qs3: q.qs3,
                limits: self.geometry.limits.margins(&q),
            },
        })
    }

    /// [`Instrument::solve`] for a tip held still at `tip` (mm, fixed frame)
    /// and a platform at rest (`frame`'s rates are ignored): the same checks,
    /// joints and margins, the joints' rates and accelerations zero without
    /// being evaluated. For static studies (the reach map).
    pub fn solve_at_rest(
        &self,
        frame: &PlatformFrame<T>,
        tip: &Vector3<T>,
        mode: AssemblyMode,
    ) -> Result<InstrumentSolution<T>, Error> {
        check_vector(tip, ["tip.x", "tip.y", "tip.z"])?;
        let c = frame.to_platform(tip);
        let (q, trig) = self.ik_trig(&(c - self.geometry.rcm), mode)?;
        self.geometry.limits.check(self.geometry.side, &q)?;
        let zero = Joints::new(T::zero(), T::zero(), T::zero());
        Ok(InstrumentSolution {
            q,
            q_dot: zero,
            q_ddot: zero,
            margins: InstrumentMargins {
                cos_qs2: trig.c2.abs(),
                qs3: q.qs3,
                limits: self.geometry.limits.margins(&q),
            },
        })
    }

    /// The module with its joints commanded directly (see [`JointMotion`]):
    /// the joints checked (finite, within their limits, away from the
    /// singular thresholds, as [`Instrument::solve`] checks the IK's), their
    /// rates passed through, and the margins at `q`. The tip follows by
    /// forward kinematics ([`Instrument::fk_platform`]).
    pub fn solve_joints(&self, motion: &JointMotion<T>) -> Result<InstrumentSolution<T>, Error> {
        motion.q.check_finite()?;
        motion.q_dot.check_finite()?;
        motion.q_ddot.check_finite()?;
        self.geometry.limits.check(self.geometry.side, &motion.q)?;
        let margins = self.margins(&motion.q);
        self.check_singular(margins.cos_qs2, motion.q.qs3)?;
        Ok(InstrumentSolution {
            q: motion.q,
            q_dot: motion.q_dot,
            q_ddot: motion.q_ddot,
            margins,
        })
    }

    /// [`Instrument::solve`] from a platform state (checks it for finiteness first).
    pub fn solve_state(
        &self,
        platform: &PlatformState<T>,
        tip: &TipMotion<T>,
        mode: AssemblyMode,
    ) -> Result<InstrumentSolution<T>, Error> {
        self.solve(&platform.frame()?, tip, mode)
    }
}

/// `angle + 2 pi k` for the whole `k` that brings it nearest `reference`.
fn unwrap_near<T: Real>(angle: T, reference: T) -> T {
    let two_pi = T::two_pi();
    let turns = ((reference - angle) / two_pi).round();
    angle + turns * two_pi
}

/// `Err(Error::NonFinite)` when the joint rates or accelerations overflowed
/// (finite inputs too large for the float type).
fn check_rates<T: Real>(side: Side, q_dot: &Joints<T>, q_ddot: &Joints<T>) -> Result<(), Error> {
    let (rates, accelerations) = match side {
        Side::Left => (
            "left instrument: joint rates (overflow)",
            "left instrument: joint accelerations (overflow)",
        ),
        Side::Right => (
            "right instrument: joint rates (overflow)",
            "right instrument: joint accelerations (overflow)",
        ),
    };
    check_results(&q_dot.to_array(), rates)?;
    check_results(&q_ddot.to_array(), accelerations)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The forward kinematics from the joints' sines and cosines computed
    /// beforehand is the plain one, bit for bit, for both sides and a
    /// perturbed `alpha` and `beta`.
    #[test]
    fn fk_from_precomputed_trig_is_bit_identical() {
        for side in [Side::Left, Side::Right] {
            let mut g = InstrumentGeometry::<f64>::paper(side);
            g.alpha += 1e-3;
            g.beta -= 2e-3;
            let m = Instrument::new(g).expect("valid");
            for k in 0..50 {
                let t = f64::from(k);
                let q = Joints::new(
                    2.9 * (0.37 * t).sin(),
                    1.4 * (0.71 * t).cos(),
                    10.0 + 5.3 * t,
                );
                let a = m.fk_platform(&q);
                let b = m.fk_platform_trig(&JointsTrig::of(&q));
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{q:?}");
            }
        }
    }

    #[test]
    fn determinant_matches_the_matrix() {
        for side in [Side::Left, Side::Right] {
            let m = Instrument::<f64>::paper(side);
            for q in [
                Joints::new(0.3, -0.5, 120.0),
                Joints::new(-2.0, 1.2, 15.0),
                Joints::new(3.0, 2.5, 300.0),
            ] {
                let det = m.jacobian(&q).determinant();
                let closed = m.jacobian_determinant(&q);
                assert!(
                    (det - closed).abs() < 1e-9 * closed.abs(),
                    "{side}: {det} vs {closed}"
                );
            }
        }
    }

    #[test]
    fn inverse_jacobian_is_the_inverse() {
        for side in [Side::Left, Side::Right] {
            let m = Instrument::<f64>::paper(side);
            let q = Joints::new(0.7, -0.9, 80.0);
            let prod = m.jacobian(&q) * m.jacobian_inverse(&q).expect("regular");
            assert!((prod - Matrix3::identity()).norm() < 1e-12);
        }
    }

    #[test]
    fn unwrap_picks_the_nearest_turn() {
        let pi = core::f64::consts::PI;
        assert!((unwrap_near(-pi + 0.1, pi - 0.1) - (pi + 0.1)).abs() < 1e-15);
        assert!((unwrap_near(0.5_f64, 0.4) - 0.5).abs() < 1e-15);
    }
}
