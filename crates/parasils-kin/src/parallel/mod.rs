//! Module 1, the 6-DOF parallel robot: geometry, inverse and forward
//! kinematics, actuator rates and singularity margins.
//!
//! Three legs carry the platform. Leg `i = 1..3` has one node `a_i` (the
//! centre of its spherical joint) fixed in the platform frame, so that in the
//! fixed frame `A_i = P + R a_i`. Actuator `j = 1..6` belongs to leg
//! `i = ceil(j/2)`: its slider runs on a straight guide,
//! `B_j = G_j + (q_j - o_j) u_j` (`G_j` a point, `u_j` a unit vector, both
//! fixed in the fixed frame, `q_j` the reading and `o_j` the encoder offset,
//! 0 unless calibrated), and a rigid link of length `l_j` joins slider and node,
//! `|A_i - B_j| = l_j` (see `docs/model.md`, *Module 1, the parallel robot*).
//!
//! **The default geometry is assumed.** The robot's real dimensions are not
//! published with the paper; [`ParallelGeometry::assumed`] is a plausible
//! geometry of the same family, for development and demonstration only.
//! Every dimension is a field of [`ParallelGeometry`], which a user with the
//! real dimensions loads from a file, and its field `assumed` says which kind
//! of geometry is in use.
//!
//! ```
//! use parasils_kin::parallel::ParallelRobot;
//! use parasils_kin::frame::Pose;
//!
//! let robot = ParallelRobot::<f64>::assumed();
//! // The symmetric pose: six equal actuators.
//! let q = robot.ik(&Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, -60.0))?;
//! assert!(q.0.iter().all(|qj| (qj - 92.754).abs() < 5e-4));
//! // And back, by Newton's method from a guess 10 mm and 5 deg away.
//! let guess = Pose::from_mm_deg(10.0, 0.0, -500.0, 5.0, 0.0, -60.0);
//! let fk = robot.fk(&q, &guess)?;
//! assert!((fk.pose.z + 500.0).abs() < 1e-9 && fk.iterations <= 8);
//! # Ok::<(), parasils_kin::Error>(())
//! ```
//!
//! # Inverse kinematics
//! One actuator at a time, in closed form (see `docs/model.md`, *Module 1,
//! the parallel robot*): with `r = A_i - G_j`,
//!
//! ```text
//! q_j = r.u_j - s_j sqrt(l_j^2 - |r - (r.u_j) u_j|^2) + o_j
//! ```
//!
//! (the square-root argument is `l_j^2` minus the squared distance of the node
//! to the guide's line). `s_j` is the [`Branch`]. A negative argument means the
//! node is farther than `l_j` from the guide: [`Error::LegOutOfReach`].
//!
//! # Rates
//! Differentiating `|A_i - B_j|^2 = l_j^2` twice, with `e_j = A_i - B_j`:
//!
//! ```text
//! qdot_j  = (e_j . Adot_i) / (e_j . u_j)
//! qddot_j = (e_j . Addot_i + |Adot_i - qdot_j u_j|^2) / (e_j . u_j)
//! ```
//!
//! with `Adot_i = Pdot + Rdot a_i`, `Addot_i = Pddot + Rddot a_i` from
//! [`PlatformFrame::point_velocity`] and [`PlatformFrame::point_acceleration`].
//!
//! # Singularities and margins
//! With the platform twist `t = (Pdot, omega_F)` (`omega_F` the angular
//! velocity in the fixed frame), the velocity relation is
//! `J_x t = diag(e_j . u_j) qdot`, the row `j` of `J_x` being
//! `(e_j, (R a_i) x e_j)`.
//! - **Serial (type 1)**: `e_j . u_j = 0`, the link perpendicular to its
//!   guide: the actuator's rate is unbounded, and the leg is at the edge of
//!   its reach. The margin is `|e_j . u_j| / l_j = |cos|` of the angle between
//!   link and guide: 1 with the link along its guide, 0 at the singularity.
//! - **Parallel (type 2)**: `J_x` singular: with all actuators locked the
//!   platform can still move (to first order), and the link forces needed to
//!   hold a load grow without bound. The margin is the smallest singular value
//!   of `J_x` made dimensionless: rows divided by `l_j` (unit link directions)
//!   and the angular columns divided by the length scale `L`, the
//!   root-mean-square distance of the nodes from `P`
//!   ([`ParallelRobot::length_scale`]; 180 mm for the assumed geometry), so
//!   that a rotation counts as the motion `L |omega|` it gives a node. A
//!   margin `m` means that some twist of unit size (mm/s, rotation as
//!   `L omega`) stretches the links only by `m` (mm/s): `1/m` bounds how much
//!   actuator errors are amplified into platform pose errors.
//!
//! From scratch the parallel margin costs one singular value decomposition
//! of a 6x6 matrix (one-sided Jacobi, values only, at most 30 sweeps, no
//! panicking branch), most of the time of [`ParallelRobot::solve`]: about 25
//! rounds of two square roots and a division, one after the other. It was
//! chosen over cheaper numbers (a determinant, the pivots of an LU) because
//! those do not measure the distance to the singularity and change with the
//! scaling of the rows. In a control loop the platform moves little from one
//! cycle to the next, and [`ParallelRobot::solve_tracking`] gets the same
//! margin from the previous cycle's weakest direction with one factorisation
//! and a certificate ([`MarginTracker`]), at a fraction of the cost (see
//! `BENCHMARKS.md`); [`Controller::step`](crate::controller::Controller::step)
//! does. See `docs/model.md`, *Module 1, the parallel robot* (margins) and
//! *Singularities and thresholds*.
//!
//! # Forward kinematics
//! Newton's method on the six constraints `f_j = (|A_i - B_j|^2 - l_j^2) / (2 l_j)`
//! (mm) with the unknowns `(X_P, Y_P, Z_P, psi, theta, phi)`. Each step solves
//! the analytic Jacobian for `(dP, omega_F)` and maps `omega_F` to the Euler
//! angles' increments with the inverse of the Euler-rate map, whose
//! determinant is `cos(theta)`: so the Jacobian on the Euler angles is singular
//! at a parallel singularity and also at `theta = +-90 deg`, the Euler angles'
//! own singularity, and each is reported as [`Error::SingularJacobian`] with
//! its kind. It stops when `max_j |f_j| / l_j` is at most
//! [`FkOptions::tolerance`] and gives up after [`FkOptions::max_iterations`]
//! Newton steps in all.
//!
//! Several assembly modes share the same actuators, and a plain Newton's
//! method from a guess near a parallel singularity can leap into another one
//! (the tests found such guesses 10 deg from poses 35 deg from `P0`). So the
//! iteration is globalised by **continuation** from the guess: the guess
//! solves the constraints for its own actuators `q_g` (from the IK), and the
//! target is moved from `q_g` to `q` in stages, each solved by Newton's method
//! from the previous stage's pose and accepted only if every Newton step is
//! at most half the one before (otherwise the stage is halved, down to
//! 1/1024 of the way). The solution found is thus the one connected to the
//! guess. Seeded with the previous pose of a motion, the first stage is the
//! whole way and this is Newton's method, 1 to 3 steps per control cycle. A
//! guess at which a leg is out of reach (no `q_g`) falls back to Newton's
//! method with a backtracking line search. Near a parallel singularity two
//! assembly modes can lie within a few degrees of each other, and a guess
//! between them may lead to either, which no local method can tell apart:
//! the tests see it in about 1 case in 1000 for poses up to 35 deg from `P0`
//! and guesses 17 deg away, never within 20 deg and 10 deg. A solution with
//! a link on the other [`Branch`] than the geometry's is
//! [`Error::BranchMismatch`].
//!
//! # Forward kinematics by the chord method
//! A tolerance study solves the forward kinematics of thousands of robots
//! that differ from the nominal one by manufacturing errors, at poses where
//! the nominal robot's Jacobian is known. [`ParallelRobot::fk_chord`] solves
//! them by the chord method (simplified Newton): every step
//! `dx = -J_0^-1 f(x)` uses one Jacobian `J_0`, the nominal robot's at the
//! commanded pose, inverted once ([`ParallelRobot::fk_chord_at`], an
//! [`FkChord`]), and only the constraints `f` of the robot solved are
//! evaluated at each iterate. The iteration converges linearly, each step
//! multiplying the error by about `|I - J_0^-1 J|`, the relative difference
//! of the two Jacobians (of the order of the perturbation, 1e-3 for
//! tolerances of a tenth of a millimetre), and stops by the same rule as
//! Newton's method, a residual at most [`FkOptions::tolerance`]. It refuses
//! (returns `None`, the caller then solves by Newton) a residual that does
//! not at least halve at each step, an `FkChord` whose margin is less than
//! twice the parallel threshold, and a solution on the other [`Branch`].
//!
//! # Layout
//! The parameters ([`ParallelGeometry`], [`Guide`], [`SymmetricLayout`], the
//! thresholds and [`FkOptions`]) and their validation are defined in
//! `geometry`; the values the solvers take and return ([`Actuators`],
//! [`ParallelMargins`], [`ParallelSolution`], [`FkSolution`]) in `types`;
//! the solver [`ParallelRobot`] with its inverse kinematics, rates, margins
//! and Jacobian in `ik`, its forward kinematics in `fk` and by the chord
//! method in `chord`; the parallel
//! margin from one control cycle to the next in [`margin`]. All are
//! re-exported here and at the crate root.
//!
//! [`Error::BranchMismatch`]: crate::Error::BranchMismatch
//! [`Error::LegOutOfReach`]: crate::Error::LegOutOfReach
//! [`Error::SingularJacobian`]: crate::Error::SingularJacobian
//! [`PlatformFrame::point_acceleration`]: crate::PlatformFrame::point_acceleration
//! [`PlatformFrame::point_velocity`]: crate::PlatformFrame::point_velocity

mod chord;
mod fk;
mod geometry;
mod ik;
pub mod margin;
mod types;

pub use chord::FkChord;
pub use geometry::{
    Branch, Calibration, FkOptions, Guide, MAX_OFFSET_LINKS, ParallelGeometry, ParallelThresholds,
    Provenance, SymmetricLayout,
};
pub use ik::ParallelRobot;
pub use margin::MarginTracker;
pub use types::{Actuators, FkSolution, ParallelMargins, ParallelSolution};
