//! Statics: the forces every actuator must exert to hold the loads on the
//! tips, the endoscope and the platform's own weight.
//!
//! # Conventions
//! | quantity | convention |
//! |---|---|
//! | units | forces N, moments and rotary torques N mm, lengths mm (so powers are N mm/s = mW) |
//! | a tip force `F` | the force the tip **exerts on its surroundings** (the tissue), N, fixed frame; the tissue pushes back with `-F` |
//! | the platform's wrench `W = (f, m)` | what module 1's actuators deliver to the platform, passed on to its surroundings: the force `f` (N) and its moment `m` (N mm) **about `P`**, the platform's origin, both in the fixed frame |
//! | the platform's twist `t = (Pdot, omega_F)` | `Pdot` mm/s; `omega_F = R omega` rad/s, the angular velocity in the fixed frame ([`PlatformFrame::omega`] is in the platform frame, and neither is the Euler angles' rates) |
//! | a slider force `tau_j` | N, **positive pushing the slider along its guide's direction `u_j`** |
//! | a link force `sigma_j` | N along the link, **positive in compression** (the link pushes its node away from its slider) |
//! | joint efforts of an instrument module | `qs1`, `qs2` N mm about the joint axes (positive in the joint's positive direction), `qs3` N (positive pushing the tool inwards, `qs3` growing) |
//!
//! With these signs every actuator's power `tau . q_dot` is what it gives to
//! the mechanism, and the balance of power is exact: the actuators' power is
//! the power the platform and the tips deliver, `tau . q_dot = W . t`.
//!
//! # Module 1
//! The velocity relation of the [parallel module](crate::parallel) is
//! `J_x t = diag(e_j . u_j) q_dot`, with row `j` of `J_x` the link
//! `e_j = A_i - B_j` and its moment about `P`, `(e_j, (R a_i) x e_j)`.
//! Without friction or inertia the virtual work of the actuators equals that
//! of the platform for every motion the linkage allows,
//! `tau . q_dot = W . t`, so
//!
//! ```text
//! W = J_x^T lambda,   lambda_j = tau_j / (e_j . u_j)
//! ```
//!
//! the sum over the links of the force `lambda_j e_j` each applies to its
//! node: a link is a two-force member, loaded only along itself. Its
//! magnitude `sigma_j = lambda_j l_j` is the link force; along the guide
//! the slider balances the link's push `-lambda_j e_j` with
//! `tau_j = lambda_j (e_j . u_j) = sigma_j (e_j . u_j) / l_j`: never more than
//! the link force, and the less the more the link leans across its guide.
//! The solve is the dimensionless Jacobian of the parallel margin
//! ([`ParallelRobot::jacobian`]) transposed, `J_s^T sigma = (f, m / L)`, by
//! Gaussian elimination with partial pivoting. Its smallest singular value
//! is the parallel margin `m_p`, so `|sigma| <= |(f, m / L)| / m_p`: near the
//! parallel singularity the link forces grow without bound, and a margin
//! below the controller's threshold (`parallel_command`) is
//! [`Error::ParallelSingular`], not huge numbers.
//!
//! The **force transmission** of one wrench,
//! `|(f, m / L)| / |sigma|` (dimensionless), is the force margin: at least
//! the parallel margin (reached by the worst wrench), 1 where the links carry
//! the wrench without amplification.
//!
//! # Instrument modules
//! The tip moves at `Pdot + omega_F x (p - P) + R J qs_dot` (`J` the module's
//! [`Instrument::jacobian`] in its RCM frame), so with the platform held the
//! joints' power `tau_s . qs_dot` equals the tip's `F . R J qs_dot`:
//!
//! ```text
//! tau_s = J^T R^T F
//! ```
//!
//! defined everywhere, singular configurations included (the converse, the
//! tip force from the joint efforts, is not).
//!
//! # The chain
//! With every joint of a module held, the module is part of the platform:
//! each tip force `F` at `p` loads the platform with `(F, (p - P) x F)`, and
//! the endoscope (not actuated: its insertion is held) with its tip's force at
//! `P + R (0, 0, -depth)`. The platform and its payload (mass `M`, centre
//! of mass `c` in the platform frame, inertia `I` about it) weigh `M g`;
//! holding them at rest takes `(-M g, -(R c) x M g)`, and moving them, by
//! Newton-Euler, `f = M (a_c - g)` and `m = (R c) x f + R (I alpha + omega x I omega)`
//! ([`Payload::moving_wrench`]). Their sum is module 1's wrench
//! ([`Controller::forces`]). The legs and the sliders are taken as massless
//! (the platform with its modules is the one body that moves), and the
//! instrument modules' own joint motions do not move their masses: an
//! approximation whose error is the legs' and the modules' kinetic energy.
//!
//! # Stiffness
//! With each actuator a spring (`ActuatorStiffness`, **assumed**: N/mm for
//! the sliders and `qs3`, N mm/rad for `qs1`, `qs2`) and every link rigid,
//! a load `W` on the platform compresses the sliders by `tau_j / k_j`
//! (`tau = J^-T W`) and the platform follows, `J (dP, dtheta_F) = dq`: the
//! displacement solves `K_x (dP, dtheta_F) = W` with `K_x = J^T diag(k) J`
//! ([`ParallelRobot::displacement`], [`ParallelRobot::platform_stiffness`];
//! `J = diag(e_j . u_j)^-1 J_x`). A force at a tip adds the module's own
//! give, `R J dqs` with `dqs_k = tau_k / k_k`
//! ([`Controller::tip_deflection`]).
//!
//! ```
//! use parasils_kin::nalgebra::Vector3;
//! use parasils_kin::{ParallelRobot, Pose, Wrench};
//!
//! let robot = ParallelRobot::<f64>::assumed();
//! // The symmetric pose: the guides point straight down (u = -z), and the
//! // three legs are alike, so an upward 60 N on P is shared equally, each
//! // slider pushed up (against u) with 10 N.
//! let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, -60.0);
//! let up = Wrench::new(Vector3::new(0.0, 0.0, 60.0), Vector3::zeros());
//! let forces = robot.statics(&pose, &up)?;
//! assert!(forces.force.0.iter().all(|tau| (tau + 10.0).abs() < 1e-12));
//! # Ok::<(), parasils_kin::Error>(())
//! ```
//!
//! See `docs/model.md`, *Forces*.

use nalgebra::{Matrix3, Vector3};

use crate::check::{check_results, check_vector};
use crate::controller::{ControlStep, Controller};
use crate::error::Error;
use crate::frame::{PlatformFrame, PlatformState, Pose};
use crate::instrument::{Instrument, Joints};
use crate::parallel::{Actuators, ParallelRobot, ParallelSolution};
use crate::real::Real;

/// A wrench: a force and its moment about a stated point, fixed frame.
///
/// Module 1's wrench is the one its actuators deliver to the platform, its
/// moment about the platform's origin `P` (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Wrench<T: Real> {
    /// The force, N, fixed frame.
    pub force: Vector3<T>,
    /// The moment, N mm, fixed frame.
    pub moment: Vector3<T>,
}

impl<T: Real> Wrench<T> {
    /// A wrench from its force (N) and moment (N mm), fixed frame.
    pub fn new(force: Vector3<T>, moment: Vector3<T>) -> Self {
        Self { force, moment }
    }

    /// No force, no moment.
    pub fn zero() -> Self {
        Self::new(Vector3::zeros(), Vector3::zeros())
    }

    /// The force `force` (N) applied at `point` (mm), as a wrench about
    /// `about` (mm): the moment `(point - about) x force`, N mm.
    pub fn at(force: &Vector3<T>, point: &Vector3<T>, about: &Vector3<T>) -> Self {
        Self::new(*force, (point - about).cross(force))
    }

    /// The power of the wrench on the twist `(velocity, omega_fixed)`,
    /// `f . velocity + m . omega_fixed`: velocity mm/s (of the point the
    /// moment is taken about), angular velocity rad/s, fixed frame; N mm/s.
    pub fn power(&self, velocity: &Vector3<T>, omega_fixed: &Vector3<T>) -> T {
        self.force.dot(velocity) + self.moment.dot(omega_fixed)
    }

    /// The power on the platform's twist at `frame`, `f . Pdot + m . (R omega)`
    /// (N mm/s), the moment being about `P`.
    pub fn power_on(&self, frame: &PlatformFrame<T>) -> T {
        self.power(&frame.velocity, &(frame.rotation * frame.omega))
    }

    /// The generalised forces of the wrench (moment about `P`) on the pose's
    /// coordinates `(X_P, Y_P, Z_P, psi, theta, phi)`: the force, then
    /// `m . omega_F` per unit rate of each Euler angle (N, N, N, N mm/rad x3).
    /// Their product with the Euler rates is the power: the virtual work in
    /// the coordinates the poses are written in.
    pub fn on_pose_coordinates(&self, pose: &Pose<T>) -> [T; 6] {
        let (s2, c2) = pose.theta.sincos();
        let (s3, c3) = pose.phi.sincos();
        let r = pose.rotation();
        // omega (platform frame) per unit psi', theta', phi' (see frame).
        let per_psi = r * Vector3::new(c2 * c3, -c2 * s3, s2);
        let per_theta = r * Vector3::new(s3, c3, T::zero());
        let per_phi = r * Vector3::z();
        [
            self.force.x,
            self.force.y,
            self.force.z,
            self.moment.dot(&per_psi),
            self.moment.dot(&per_theta),
            self.moment.dot(&per_phi),
        ]
    }
}

impl<T: Real> core::ops::Add for Wrench<T> {
    type Output = Self;
    /// The sum of two wrenches about the same point.
    fn add(self, rhs: Self) -> Self {
        Self::new(self.force + rhs.force, self.moment + rhs.moment)
    }
}

/// Module 1's forces holding one wrench (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SliderForces<T> {
    /// `tau_1..tau_6`, N, positive pushing each slider along its guide's
    /// direction `u_j`.
    pub force: Actuators<T>,
    /// `sigma_1..sigma_6`, the force along each link, N, positive in
    /// compression.
    pub link: [T; 6],
    /// The force transmission `|(f, m / L)| / |sigma|` (dimensionless): at
    /// least the parallel margin, 1 where the links carry the wrench without
    /// amplification; 1 for the zero wrench.
    pub transmission: T,
}

/// An instrument module's joint efforts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JointForces<T> {
    /// The torque about `qs1`'s axis, N mm, positive in `qs1`'s direction.
    pub qs1: T,
    /// The torque about `qs2`'s axis, N mm, positive in `qs2`'s direction.
    pub qs2: T,
    /// The insertion force, N, positive pushing the tool in (`qs3` growing).
    pub qs3: T,
}

impl<T: Real> JointForces<T> {
    /// `[qs1, qs2, qs3]` (N mm, N mm, N).
    pub fn to_array(&self) -> [T; 3] {
        [self.qs1, self.qs2, self.qs3]
    }

    /// The joints' power `tau . qs_dot` (N mm/s) at the joint rates `q_dot`
    /// (rad/s, rad/s, mm/s).
    pub fn power(&self, q_dot: &Joints<T>) -> T {
        self.qs1 * q_dot.qs1 + self.qs2 * q_dot.qs2 + self.qs3 * q_dot.qs3
    }
}

/// The platform's payload, its weight and its inertia: the platform with
/// the modules it carries as one rigid body (the legs' and the sliders'
/// masses are left out, see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Payload<T: Real> {
    /// The mass, kg (0: no weight).
    pub mass: T,
    /// The centre of mass, mm, platform frame.
    pub com: Vector3<T>,
    /// The acceleration of gravity, mm/s^2, fixed frame (`(0, 0, -9810)` on
    /// a robot whose `-Z` points down).
    pub gravity: Vector3<T>,
    /// The inertia tensor about the centre of mass, kg mm^2, platform axes
    /// (zero: a point mass).
    pub inertia: Matrix3<T>,
}

impl<T: Real> Payload<T> {
    /// Standard gravity along `-Z`, mm/s^2.
    pub const STANDARD_GRAVITY_MM_S2: f64 = 9810.0;

    /// No mass: no weight to hold.
    pub fn none() -> Self {
        Self::new(T::zero(), Vector3::zeros())
    }

    /// A mass (kg) at `com` (mm, platform frame) under standard gravity
    /// along `-Z`.
    pub fn new(mass: T, com: Vector3<T>) -> Self {
        let g = T::lit(-Self::STANDARD_GRAVITY_MM_S2);
        Self {
            mass,
            com,
            gravity: Vector3::new(T::zero(), T::zero(), g),
            inertia: Matrix3::zeros(),
        }
    }

    /// The **assumed** platform with its two instrument modules and the
    /// endoscope (the paper gives no masses): 6 kg, its centre of mass
    /// 120 mm above the ports on the platform's axis, the inertia of a
    /// solid cylinder of radius 150 mm and height 200 mm about its axis
    /// `Z'` (`I_zz = M r^2 / 2`, `I_xx = I_yy = M (3 r^2 + h^2) / 12`,
    /// kg mm^2), under standard gravity along `-Z`.
    pub fn assumed() -> Self {
        let (m, r, h) = (6.0, 150.0, 200.0);
        let side = m * (3.0 * r * r + h * h) / 12.0;
        let axis = m * r * r / 2.0;
        let inertia =
            Matrix3::from_diagonal(&Vector3::new(T::lit(side), T::lit(side), T::lit(axis)));
        Self::new(T::lit(m), Vector3::new(T::zero(), T::zero(), T::lit(120.0)))
            .with_inertia(inertia)
    }

    /// The same body with the inertia tensor `inertia` (kg mm^2, about the
    /// centre of mass, platform axes).
    pub fn with_inertia(self, inertia: Matrix3<T>) -> Self {
        Self { inertia, ..self }
    }

    /// The wrench (about `P`, N and N mm) that moves the body as `frame`
    /// says and holds its weight, by Newton-Euler: with `a_c` the centre of
    /// mass's acceleration (`PlatformFrame::point_acceleration`), `omega`
    /// and `alpha` in the platform frame,
    /// `f = M (a_c - g)`, `m = (R c) x f + R (I alpha + omega x I omega)`
    /// (kg mm/s^2 and kg mm^2/s^2 divided by 1000). At rest it is
    /// [`Payload::holding_wrench`].
    pub fn moving_wrench(&self, frame: &PlatformFrame<T>) -> Wrench<T> {
        let milli = T::lit(1e-3);
        let a_c = frame.point_acceleration(&self.com);
        let force = (a_c - self.gravity) * (self.mass * milli);
        let (w, i) = (&frame.omega, &self.inertia);
        let spin = frame.rotation * (i * frame.alpha + w.cross(&(i * w))) * milli;
        let arm = frame.rotation * self.com;
        Wrench::new(force, arm.cross(&force) + spin)
    }

    /// The wrench that holds the weight, about `P`: `(-M g, -(R c) x M g)`,
    /// N and N mm (`M g` in kg mm/s^2 is `M g / 1000` N).
    pub fn holding_wrench(&self, frame: &PlatformFrame<T>) -> Wrench<T> {
        let weight = self.gravity * (self.mass / T::lit(1000.0));
        let arm = frame.rotation * self.com;
        Wrench::new(-weight, -arm.cross(&weight))
    }

    fn check_finite(&self) -> Result<(), Error> {
        crate::error::check_finite(self.mass, "payload.mass")?;
        check_vector(
            &self.com,
            ["payload.com.x", "payload.com.y", "payload.com.z"],
        )?;
        check_vector(
            &self.gravity,
            [
                "payload.gravity.x",
                "payload.gravity.y",
                "payload.gravity.z",
            ],
        )?;
        for &v in self.inertia.as_slice() {
            crate::error::check_finite(v, "payload.inertia")?;
        }
        Ok(())
    }
}

/// What the robot holds in one cycle: the forces the tips exert on their
/// surroundings and the payload's weight.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Loads<T: Real> {
    /// The force the left tip exerts, N, fixed frame.
    pub left: Vector3<T>,
    /// The force the right tip exerts, N, fixed frame.
    pub right: Vector3<T>,
    /// The force the endoscope's tip exerts, N, fixed frame.
    pub endoscope: Vector3<T>,
    /// The endoscope's insertion depth, mm: where its tip is
    /// (`P + R (0, 0, -depth)`).
    pub endoscope_depth: T,
    /// The platform and its payload.
    pub payload: Payload<T>,
}

impl<T: Real> Loads<T> {
    /// Nothing to hold: no tip force, no mass, the endoscope at depth 0.
    pub fn none() -> Self {
        Self {
            left: Vector3::zeros(),
            right: Vector3::zeros(),
            endoscope: Vector3::zeros(),
            endoscope_depth: T::zero(),
            payload: Payload::none(),
        }
    }

    /// The two instruments' tip forces (N, fixed frame) and nothing else.
    pub fn tips(left: Vector3<T>, right: Vector3<T>) -> Self {
        Self {
            left,
            right,
            ..Self::none()
        }
    }
}

/// Every actuator's force in one cycle ([`Controller::forces`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotForces<T: Real> {
    /// The wrench module 1 delivers to the platform, about `P`.
    pub platform: Wrench<T>,
    /// Module 1's slider and link forces.
    pub module1: SliderForces<T>,
    /// The left module's joint efforts.
    pub left: JointForces<T>,
    /// The right module's joint efforts.
    pub right: JointForces<T>,
}

impl<T: Real> RobotForces<T> {
    /// The twelve actuators' forces in the order of
    /// [`Actuator::ALL`](crate::Actuator::ALL): `q1..q6` (N), then each
    /// module's `qs1`, `qs2` (N mm) and `qs3` (N), as
    /// [`ActuatorLimits::check_forces`](crate::ActuatorLimits::check_forces)
    /// takes them.
    pub fn to_array(&self) -> [T; 12] {
        let (m, l, r) = (self.module1.force.0, self.left, self.right);
        [
            m[0], m[1], m[2], m[3], m[4], m[5], l.qs1, l.qs2, l.qs3, r.qs1, r.qs2, r.qs3,
        ]
    }
}

impl<T: Real> ParallelRobot<T> {
    /// The slider forces holding `wrench` (about `P`, fixed frame) at the
    /// pose of `frame`, with the actuators and the parallel margin of that
    /// pose from `solution` (the cycle's [`ParallelRobot::solve`]).
    ///
    /// Errors: a non-finite frame, actuator or wrench
    /// ([`Error::NonFinite`]); a parallel margin below the geometry's
    /// `thresholds.parallel_command` ([`Error::ParallelSingular`]), where the
    /// forces grow without bound.
    pub fn slider_forces(
        &self,
        frame: &PlatformFrame<T>,
        solution: &ParallelSolution<T>,
        wrench: &Wrench<T>,
    ) -> Result<SliderForces<T>, Error> {
        crate::check::check_frame(frame)?;
        solution.q.check_finite()?;
        check_vector(
            &wrench.force,
            ["wrench.force.x", "wrench.force.y", "wrench.force.z"],
        )?;
        check_vector(
            &wrench.moment,
            ["wrench.moment.x", "wrench.moment.y", "wrench.moment.z"],
        )?;
        let margin = solution.margins.parallel;
        let threshold = self.geometry().thresholds.parallel_command;
        if !(margin >= threshold) {
            return Err(Error::ParallelSingular {
                margin: margin.to_f64(),
                threshold: threshold.to_f64(),
            });
        }
        let inv_scale = T::one() / self.length_scale();
        let (rows, n_dot_u) = self.scaled_rows(frame, &solution.q);
        // The columns of J_s^T are the rows of J_s: (n_j, rho_i x n_j / L).
        let mut m = [[T::zero(); 7]; 6];
        for (j, r) in rows.iter().enumerate() {
            for (row, c) in m.iter_mut().zip(r) {
                row[j] = *c;
            }
        }
        let moment = wrench.moment * inv_scale;
        let rhs = [
            wrench.force.x,
            wrench.force.y,
            wrench.force.z,
            moment.x,
            moment.y,
            moment.z,
        ];
        for (row, b) in m.iter_mut().zip(rhs) {
            row[6] = b;
        }
        let link = solve6(m);
        check_results(&link, "module 1: link forces (overflow)")?;
        let force = Actuators(core::array::from_fn(|j| link[j] * n_dot_u[j]));
        let load = rhs.iter().fold(T::zero(), |s, v| s + *v * *v).sqrt();
        let carried = link.iter().fold(T::zero(), |s, v| s + *v * *v).sqrt();
        let transmission = if carried > T::zero() {
            load / carried
        } else {
            T::one()
        };
        Ok(SliderForces {
            force,
            link,
            transmission,
        })
    }

    /// The rows `(n_j, (R a_i) x n_j / L)` of the dimensionless Jacobian
    /// `J_s` at the actuators `q` of the frame's pose (`n_j = e_j / l_j`),
    /// and `n_j . u_j`.
    fn scaled_rows(&self, frame: &PlatformFrame<T>, q: &Actuators<T>) -> ([[T; 6]; 6], [T; 6]) {
        let g = self.geometry();
        let inv_scale = T::one() / self.length_scale();
        let rho = g.nodes.map(|a| frame.rotation * a);
        let mut rows = [[T::zero(); 6]; 6];
        let mut n_dot_u = [T::zero(); 6];
        for (j, (guide, row)) in g.guides.iter().zip(rows.iter_mut()).enumerate() {
            let e = frame.position + rho[j / 2]
                - guide.point
                - guide.direction * (q[j] - guide.encoder_offset);
            let n = e / guide.link_length;
            n_dot_u[j] = n.dot(&guide.direction);
            let k = rho[j / 2].cross(&n) * inv_scale;
            *row = [n.x, n.y, n.z, k.x, k.y, k.z];
        }
        (rows, n_dot_u)
    }

    /// The platform's small displacement under the external load `load`
    /// (a wrench applied to the platform, about `P`, fixed frame) with each
    /// slider a spring of stiffness `stiffness[j]` (N/mm, along its guide)
    /// and the links rigid: `(dP, dtheta_F)`, mm and rad (a rotation vector,
    /// fixed frame), the solution of `K_x (dP, dtheta_F) = load` with
    /// `K_x = J^T diag(k) J` ([`ParallelRobot::platform_stiffness`]). The
    /// sliders carry `tau = J^-T load` ([`ParallelRobot::slider_forces`]),
    /// give way by `tau_j / k_j`, and the platform follows:
    /// `J (dP, dtheta_F) = dq`. Fails as [`ParallelRobot::slider_forces`],
    /// and on a stiffness that is not a positive number
    /// ([`Error::InvalidParameter`] `"stiffness"`).
    pub fn displacement(
        &self,
        frame: &PlatformFrame<T>,
        solution: &ParallelSolution<T>,
        load: &Wrench<T>,
        stiffness: &[T; 6],
    ) -> Result<(Vector3<T>, Vector3<T>), Error> {
        check_stiffness(stiffness)?;
        let tau = self.slider_forces(frame, solution, load)?.force;
        let (rows, n_dot_u) = self.scaled_rows(frame, &solution.q);
        // J_s (dP, L dtheta) = (n_j . u_j) dq_j.
        let mut m = [[T::zero(); 7]; 6];
        for (j, (row, r)) in m.iter_mut().zip(rows).enumerate() {
            row[..6].copy_from_slice(&r);
            row[6] = n_dot_u[j] * tau[j] / stiffness[j];
        }
        let x = solve6(m);
        check_results(&x, "module 1: displacement (overflow)")?;
        let inv_scale = T::one() / self.length_scale();
        Ok((
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]) * inv_scale,
        ))
    }

    /// The platform's stiffness `K_x = J^T diag(k) J` (`J` the actuators'
    /// rates per twist, `q_dot = J (Pdot, omega_F)`) at the pose of `frame`,
    /// for slider stiffnesses `stiffness` (N/mm): a symmetric 6x6 matrix on
    /// `(dP mm, dtheta_F rad)` giving the wrench about `P` (N, N mm), so
    /// its blocks are in N/mm, N/rad, N mm/mm and N mm/rad. Fails as
    /// [`ParallelRobot::displacement`].
    pub fn platform_stiffness(
        &self,
        frame: &PlatformFrame<T>,
        solution: &ParallelSolution<T>,
        stiffness: &[T; 6],
    ) -> Result<nalgebra::Matrix6<T>, Error> {
        check_stiffness(stiffness)?;
        // The threshold check of slider_forces, on no load.
        self.slider_forces(frame, solution, &Wrench::zero())?;
        let (rows, n_dot_u) = self.scaled_rows(frame, &solution.q);
        let l = self.length_scale();
        let mut k = nalgebra::Matrix6::zeros();
        for (j, r) in rows.iter().enumerate() {
            // Row j of J: (n_j, rho_i x n_j) / (n_j . u_j), the angular part
            // unscaled.
            let jr =
                nalgebra::Vector6::new(r[0], r[1], r[2], r[3] * l, r[4] * l, r[5] * l) / n_dot_u[j];
            k += jr * jr.transpose() * stiffness[j];
        }
        check_results(k.as_slice(), "module 1: stiffness (overflow)")?;
        Ok(k)
    }

    /// The slider forces holding `wrench` (about `P`, fixed frame) at
    /// `pose`, on their own: the IK and the parallel margin from the full
    /// decomposition ([`ParallelRobot::solve`] at rest), then
    /// [`ParallelRobot::slider_forces`]. Fails as both do.
    pub fn statics(&self, pose: &Pose<T>, wrench: &Wrench<T>) -> Result<SliderForces<T>, Error> {
        let frame = PlatformState::at_rest(*pose).frame()?;
        let solution = self.solve(&frame)?;
        self.slider_forces(&frame, &solution, wrench)
    }
}

/// [`Error::InvalidParameter`] `"stiffness"` for the first stiffness that
/// is not a positive number.
fn check_stiffness<T: Real>(stiffness: &[T]) -> Result<(), Error> {
    match stiffness.iter().find(|k| !(**k > T::zero() && k.finite())) {
        Some(k) => Err(Error::InvalidParameter {
            what: "stiffness",
            value: k.to_f64(),
        }),
        None => Ok(()),
    }
}

/// `x` with `A x = b` for the augmented `[A | b]` (rows), by Gaussian
/// elimination with partial pivoting. Indices only from loop counters over
/// constant ranges (no panicking branch); a zero pivot gives an infinity or
/// a NaN, which the caller's check reports.
fn solve6<T: Real>(mut m: [[T; 7]; 6]) -> [T; 6] {
    for k in 0..6 {
        // The largest pivot of column k moved up to row k, by swaps.
        for i in k + 1..6 {
            if m[i][k].abs() > m[k][k].abs() {
                m.swap(i, k);
            }
        }
        let pivot_row = m[k];
        for row in m.iter_mut().skip(k + 1) {
            let f = row[k] / pivot_row[k];
            for (x, v) in row.iter_mut().zip(pivot_row).skip(k) {
                *x -= f * v;
            }
        }
    }
    let mut x = [T::zero(); 6];
    for k in (0..6).rev() {
        let mut s = m[k][6];
        for c in k + 1..6 {
            s -= m[k][c] * x[c];
        }
        x[k] = s / m[k][k];
    }
    x
}

impl<T: Real> Instrument<T> {
    /// The joint efforts `tau_s = J^T R^T F` that hold the tip force `force`
    /// (N, fixed frame, the force the tip exerts) at the joints `q`, with
    /// the platform's rotation `rotation` (platform to fixed): `qs1`, `qs2`
    /// in N mm, `qs3` in N (see the [module docs](self)). Defined at every
    /// configuration; fails only on non-finite input or results.
    pub fn joint_forces(
        &self,
        rotation: &Matrix3<T>,
        q: &Joints<T>,
        force: &Vector3<T>,
    ) -> Result<JointForces<T>, Error> {
        q.check_finite()?;
        check_vector(force, ["tip_force.x", "tip_force.y", "tip_force.z"])?;
        let local = rotation.tr_mul(force);
        let tau = self.jacobian(q).tr_mul(&local);
        check_results(tau.as_slice(), "joint forces (overflow)")?;
        Ok(JointForces {
            qs1: tau.x,
            qs2: tau.y,
            qs3: tau.z,
        })
    }
}

/// Each actuator's stiffness, in the order of
/// [`Actuator::ALL`](crate::Actuator::ALL): the sliders and `qs3` in N/mm,
/// `qs1` and `qs2` in N mm/rad. The paper gives none: the defaults are
/// **assumed**.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ActuatorStiffness<T> {
    /// The twelve stiffnesses.
    pub stiffness: [T; 12],
}

impl<T: Real> ActuatorStiffness<T> {
    /// Module 1's sliders' stiffness along their guides, N/mm (**assumed**).
    pub const SLIDER_N_MM: f64 = 200.0;
    /// `qs1`'s and `qs2`'s torsional stiffness, N mm/rad (**assumed**).
    pub const QS12_NMM_RAD: f64 = 2.0e5;
    /// `qs3`'s stiffness, N/mm (**assumed**).
    pub const QS3_N_MM: f64 = 50.0;

    /// The **assumed** stiffnesses: sliders 200 N/mm, `qs1` and `qs2`
    /// 2e5 N mm/rad, `qs3` 50 N/mm.
    pub fn assumed() -> Self {
        let mut stiffness = [T::lit(Self::SLIDER_N_MM); 12];
        for side in [6, 9] {
            stiffness[side] = T::lit(Self::QS12_NMM_RAD);
            stiffness[side + 1] = T::lit(Self::QS12_NMM_RAD);
            stiffness[side + 2] = T::lit(Self::QS3_N_MM);
        }
        Self { stiffness }
    }
}

impl<T: Real> Controller<T> {
    /// How far the `side` module's tip gives way (mm, fixed frame) under
    /// the external force `force` applied to it (N, fixed frame: the
    /// tissue's push on the tip) in the cycle `step`, with the actuators
    /// springs of `stiffness` and every link rigid: the platform's
    /// displacement under the force's wrench about `P`
    /// ([`ParallelRobot::displacement`]) carried to the tip,
    /// `dP + dtheta_F x (p - P)`, plus the module's own, `R J dqs` with
    /// `dqs_k = tau_k / k_k` and `tau = J^T R^T force`. Linear in `force`;
    /// `force . deflection > 0`.
    pub fn tip_deflection(
        &self,
        step: &ControlStep<T>,
        side: crate::side::Side,
        force: &Vector3<T>,
        stiffness: &ActuatorStiffness<T>,
    ) -> Result<Vector3<T>, Error> {
        check_vector(force, ["force.x", "force.y", "force.z"])?;
        let (module, q, base) = match side {
            crate::side::Side::Left => (&self.left, &step.left.q, 6),
            crate::side::Side::Right => (&self.right, &step.right.q, 9),
        };
        let k = &stiffness.stiffness;
        check_stiffness(k)?;
        let frame = &step.frame;
        let tip = frame.to_fixed(&module.fk_platform(q));
        let load = Wrench::at(force, &tip, &frame.position);
        let slider_k = [k[0], k[1], k[2], k[3], k[4], k[5]];
        let (dp, dtheta) = self
            .module1
            .displacement(frame, &step.module1, &load, &slider_k)?;
        let tau = module.joint_forces(&frame.rotation, q, force)?;
        let dqs = Vector3::new(
            tau.qs1 / k[base],
            tau.qs2 / k[base + 1],
            tau.qs3 / k[base + 2],
        );
        let own = frame.rotation * (module.jacobian(q) * dqs);
        let out = dp + dtheta.cross(&(tip - frame.position)) + own;
        check_results(out.as_slice(), "tip deflection (overflow)")?;
        Ok(out)
    }

    /// Every actuator's force in the cycle `step` (from [`Controller::step`]
    /// or [`Controller::step_commanded`]) holding `loads`: each module's
    /// joint efforts for its tip force, then module 1's slider forces for
    /// the sum of the tips' forces, the endoscope's and the payload's
    /// Newton-Euler wrench (its weight, and its inertia in the step's
    /// motion: [`Payload::moving_wrench`]) as one wrench about `P` (see the
    /// [module docs](self)).
    ///
    /// Errors: non-finite loads ([`Error::NonFinite`] naming the load), an
    /// endoscope depth out of its range under an endoscope force
    /// ([`Error::EndoscopeDepth`]; without one the depth is not used), and as
    /// [`ParallelRobot::slider_forces`].
    pub fn forces(&self, step: &ControlStep<T>, loads: &Loads<T>) -> Result<RobotForces<T>, Error> {
        check_vector(
            &loads.left,
            ["loads.left.x", "loads.left.y", "loads.left.z"],
        )?;
        check_vector(
            &loads.right,
            ["loads.right.x", "loads.right.y", "loads.right.z"],
        )?;
        check_vector(
            &loads.endoscope,
            [
                "loads.endoscope.x",
                "loads.endoscope.y",
                "loads.endoscope.z",
            ],
        )?;
        loads.payload.check_finite()?;
        let frame = &step.frame;
        let p = frame.position;
        let left_tip = frame.to_fixed(&self.left.fk_platform(&step.left.q));
        let right_tip = frame.to_fixed(&self.right.fk_platform(&step.right.q));
        let mut platform = Wrench::at(&loads.left, &left_tip, &p)
            + Wrench::at(&loads.right, &right_tip, &p)
            + loads.payload.moving_wrench(frame);
        // A zero force has no moment wherever it acts: the depth matters
        // (and is checked) only under a force.
        if loads.endoscope != Vector3::zeros() {
            let scope_tip = self.endoscope.tip(frame, loads.endoscope_depth)?;
            platform = platform + Wrench::at(&loads.endoscope, &scope_tip, &p);
        }
        Ok(RobotForces {
            platform,
            module1: self
                .module1
                .slider_forces(frame, &step.module1, &platform)?,
            left: self
                .left
                .joint_forces(&frame.rotation, &step.left.q, &loads.left)?,
            right: self
                .right
                .joint_forces(&frame.rotation, &step.right.q, &loads.right)?,
        })
    }
}
