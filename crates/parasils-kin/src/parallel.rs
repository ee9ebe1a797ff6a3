//! Module 1, the 6-DOF parallel robot: geometry, inverse and forward
//! kinematics, actuator rates and singularity margins.
//!
//! Three legs carry the platform. Leg `i = 1..3` has one node `a_i` (the
//! centre of its spherical joint) fixed in the platform frame, so that in the
//! fixed frame `A_i = P + R a_i`. Actuator `j = 1..6` belongs to leg
//! `i = ceil(j/2)`: its slider runs on a straight guide,
//! `B_j = G_j + q_j u_j` (`G_j` a point, `u_j` a unit vector, both fixed in
//! the fixed frame), and a rigid link of length `l_j` joins slider and node,
//! `|A_i - B_j| = l_j` (see `PARALLEL_ROBOT.md`).
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
//! One actuator at a time, in closed form: with `r = A_i - G_j`,
//!
//! ```text
//! q_j = r.u_j - s_j sqrt(l_j^2 - |r - (r.u_j) u_j|^2)
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
//! panicking branch): [`ParallelRobot::solve`] takes about 1.3 us in `f64`
//! on one x86-64 server core (`BENCHMARKS.md`), mostly the margin, whose time
//! is the latency of about 25 rounds of two square roots and a division. It
//! was chosen over cheaper numbers (a determinant, the pivots of an LU)
//! because those do not measure the distance to the singularity and change
//! with the scaling of the rows. In a control loop the platform moves little
//! from one cycle to the next, and [`ParallelRobot::solve_tracking`] gets the
//! same margin from the previous cycle's weakest direction with one
//! factorisation and a certificate ([`MarginTracker`]), at about a quarter of
//! the cost; [`Controller::step`](crate::controller::Controller::step) does.
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

use core::ops::Index;

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use crate::error::{Error, ParallelSingularity, check_finite};
use crate::frame::{PlatformFrame, PlatformState, Pose};
use crate::instrument::{Interval, check_vector};
use crate::real::{Real, deg};

pub mod margin;

pub use margin::MarginTracker;

/// Names `[p0, ..., p5]` of a per-actuator parameter for error reports.
macro_rules! per_guide {
    ($field:literal) => {
        [
            concat!("module1.guides[0].", $field),
            concat!("module1.guides[1].", $field),
            concat!("module1.guides[2].", $field),
            concat!("module1.guides[3].", $field),
            concat!("module1.guides[4].", $field),
            concat!("module1.guides[5].", $field),
        ]
    };
}

/// `[..x, ..y, ..z]` names of a per-actuator vector for error reports.
macro_rules! per_guide_xyz {
    ($field:literal, $j:literal) => {
        [
            concat!("module1.guides[", $j, "].", $field, ".x"),
            concat!("module1.guides[", $j, "].", $field, ".y"),
            concat!("module1.guides[", $j, "].", $field, ".z"),
        ]
    };
}

/// Which root of the inverse kinematics an actuator takes: the sign `s_j`.
///
/// With `r = A_i - G_j`, `q_j = r.u_j - s_j sqrt(...)`, and the two roots put
/// the slider on either side of the foot of the node on the guide's line.
/// The sign of `e_j . u_j` (with `e_j = A_i - B_j`) is `s_j`: a motion never
/// changes branch without crossing the serial singularity `e_j . u_j = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Branch {
    /// `s_j = +1`: the slider before the node's foot along `u_j`
    /// (`e_j . u_j > 0`). For the assumed geometry (guides pointing down from
    /// `Z = 0`) the slider is on the base side of the node. The default.
    #[default]
    Plus,
    /// `s_j = -1`: the slider past the node's foot along `u_j` (`e_j . u_j < 0`).
    Minus,
}

impl Branch {
    /// `s_j` as `+1` or `-1`.
    pub fn sign<T: Real>(self) -> T {
        match self {
            Branch::Plus => T::one(),
            Branch::Minus => -T::one(),
        }
    }

    /// The branch of sign `s` (`+1` or `-1`), `None` for any other value.
    pub fn from_sign(s: i64) -> Option<Self> {
        match s {
            1 => Some(Branch::Plus),
            -1 => Some(Branch::Minus),
            _ => None,
        }
    }

    /// `+1` or `-1`.
    pub fn as_i64(self) -> i64 {
        match self {
            Branch::Plus => 1,
            Branch::Minus => -1,
        }
    }
}

/// One actuator of module 1: its straight guide, its slider's stroke, and the
/// link from the slider to its leg's node.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Guide<T: Real> {
    /// `G_j`, where the slider is at `q_j = 0`, mm, fixed frame.
    pub point: Vector3<T>,
    /// `u_j`, the direction in which `q_j` grows, fixed frame. Unit length:
    /// any non-zero vector is accepted and [`ParallelRobot::new`] normalises it.
    pub direction: Vector3<T>,
    /// `l_j`, the length of the link from slider to node (centre to centre), mm.
    pub link_length: T,
    /// `s_j`, which root of the inverse kinematics this actuator takes.
    pub branch: Branch,
    /// The slider's stroke, mm: `q_j` must stay in it (default **assumed**
    /// `[0, 320]` mm, SPEC section 3). May be infinite.
    pub stroke: Interval<T>,
}

/// The dimensions of a three-legged module 1 with a 120-degree symmetry, from
/// which [`ParallelGeometry::from_layout`] builds the six guides and three
/// nodes: the table of `PARALLEL_ROBOT.md`.
///
/// Leg `i` at azimuth `gamma_i` has the radial unit vector
/// `c_i = (cos gamma_i, sin gamma_i, 0)` and the tangential one
/// `t_i = (-sin gamma_i, cos gamma_i, 0)`; its guides start at
/// `G_(2i-1) = R_b c_i - w t_i` and `G_(2i) = R_b c_i + w t_i` and both run
/// along `direction`; its node is at `r_p (cos, sin)(gamma_i + offset)` and the
/// height `h` along `+z'`, in the platform frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SymmetricLayout<T: Real> {
    /// `gamma_i`, the azimuth of each leg about `Z`, rad.
    pub leg_azimuths: [T; 3],
    /// `R_b`, the radius of each leg's guide-pair centre, mm.
    pub base_radius: T,
    /// `w`, the half-spacing of a leg's two guides (tangential), mm.
    pub half_spacing: T,
    /// The direction of every guide, fixed frame (any non-zero vector).
    pub direction: Vector3<T>,
    /// `l_j`, every link's length, mm.
    pub link_length: T,
    /// The stroke of every slider, mm.
    pub stroke: Interval<T>,
    /// `r_p`, the radius of the platform nodes about `z'`, mm.
    pub node_radius: T,
    /// `h`, the height of the nodes above `P` along `+z'`, mm.
    pub node_height: T,
    /// The azimuth of node `i` in the platform frame minus `gamma_i`, rad.
    pub node_azimuth_offset: T,
}

impl<T: Real> SymmetricLayout<T> {
    /// The **assumed** dimensions of `PARALLEL_ROBOT.md` (not the real
    /// robot's, which are not published): legs at 90, 210, 330 deg,
    /// `R_b = 200 mm`, `w = 160 mm`, guides along `(0, 0, -1)` from `Z = 0`,
    /// links of 350 mm, strokes `[0, 320] mm`, nodes at `r_p = 150 mm`,
    /// `h = 100 mm`, azimuths `gamma_i + 60 deg`.
    pub fn assumed() -> Self {
        Self {
            leg_azimuths: [deg(90.0), deg(210.0), deg(330.0)],
            base_radius: T::lit(200.0),
            half_spacing: T::lit(160.0),
            direction: Vector3::new(T::zero(), T::zero(), -T::one()),
            link_length: T::lit(350.0),
            stroke: Interval::new(T::zero(), T::lit(320.0)),
            node_radius: T::lit(150.0),
            node_height: T::lit(100.0),
            node_azimuth_offset: deg(60.0),
        }
    }
}

/// The thresholds at which module 1's solvers report a singularity.
///
/// All are dimensionless. Defaults: `1e-6` for `serial`, `parallel` and
/// `euler`; `1e-2` for `parallel_command`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParallelThresholds<T> {
    /// Smallest serial margin `|e_j . u_j| / l_j` that [`ParallelRobot::ik`],
    /// [`ParallelRobot::rates`] and [`ParallelRobot::solve`] accept; in
    /// `(0, 1)`.
    pub serial: T,
    /// Smallest parallel margin (see the [module docs](self)) that the
    /// forward kinematics accepts at an iterate.
    pub parallel: T,
    /// Smallest parallel margin that [`ParallelRobot::solve`], the per-cycle
    /// call, accepts: a command closer to a parallel singularity is refused
    /// ([`Error::ParallelSingular`]). At the default `1e-2`, actuator errors
    /// are amplified at most about 100 times into platform errors. It is
    /// checked at each call, so a trajectory sampled at 1 kHz cannot step over
    /// a singularity unnoticed unless its margin changes by more than `1e-2`
    /// per sample.
    pub parallel_command: T,
    /// Smallest `|cos theta|` that the forward kinematics accepts at an
    /// iterate (the Euler angles' own singularity).
    pub euler: T,
}

impl<T: Real> Default for ParallelThresholds<T> {
    fn default() -> Self {
        Self {
            serial: T::lit(1e-6),
            parallel: T::lit(1e-6),
            parallel_command: T::lit(1e-2),
            euler: T::lit(1e-6),
        }
    }
}

/// The stopping rules of the forward kinematics.
///
/// Default: `tolerance = max(1e-13, 128 eps)` (relative: `1e-13` in `f64`,
/// `1.5e-5` in `f32`, that is 35 fm and 5 um on a 350 mm link) and 100
/// Newton steps in all (seeded with the previous pose of a motion it takes
/// 1 to 3; from a guess 10 deg away, 3 to 5; near a parallel singularity the
/// continuation's retried stages have taken up to 60). An absolute tolerance
/// on mm or mm^2 residuals would not scale: the rounding of `|A_i - B_j|` is
/// relative to the robot's size.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FkOptions<T> {
    /// Converged when `max_j |f_j| / l_j` is at most this (dimensionless).
    pub tolerance: T,
    /// At most this many Newton steps (at least 1).
    pub max_iterations: u32,
}

impl<T: Real> Default for FkOptions<T> {
    fn default() -> Self {
        Self {
            tolerance: T::lit(1e-13).max(T::EPSILON * T::lit(128.0)),
            max_iterations: 100,
        }
    }
}

/// The parameters of module 1: six guides with their links, three platform
/// nodes, thresholds and the forward kinematics' stopping rules.
///
/// Actuator `j` (0-based index `j - 1`) belongs to leg `ceil(j/2)`: guides
/// `[0, 1]` to node `0`, `[2, 3]` to node `1`, `[4, 5]` to node `2`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParallelGeometry<T: Real> {
    /// Whether the dimensions are **assumed** (true for
    /// [`ParallelGeometry::assumed`]) rather than the real robot's: anything
    /// that prints module-1 numbers must say so when it is true.
    pub assumed: bool,
    /// The six actuators `q1..q6`, in order.
    pub guides: [Guide<T>; 6],
    /// `a_1..a_3`, the legs' nodes (spherical-joint centres), mm, platform frame.
    pub nodes: [Vector3<T>; 3],
    /// Singularity thresholds.
    pub thresholds: ParallelThresholds<T>,
    /// The forward kinematics' stopping rules.
    pub fk: FkOptions<T>,
}

impl<T: Real> ParallelGeometry<T> {
    /// The **assumed** geometry of `PARALLEL_ROBOT.md`: a plausible robot of
    /// the right family, **not** the real PARA-SILSROB, whose dimensions are
    /// not published ([`SymmetricLayout::assumed`]; `assumed` is `true`).
    /// Load the real dimensions from a file to replace it.
    ///
    /// The coordinates are written in closed form (with `sqrt 3`), so that
    /// the values a file shows are `160`, `200`, `75`, not `74.99999999999999`
    /// from `sin(150 deg)`; they equal those of
    /// [`ParallelGeometry::from_layout`] of [`SymmetricLayout::assumed`] to
    /// the rounding of the trigonometry.
    pub fn assumed() -> Self {
        let lit = T::lit;
        let r3 = lit(3.0).sqrt();
        // G_(2i-1), G_(2i) = R_b c_i -+ w t_i with R_b = 200, w = 160 mm.
        let points = [
            (lit(160.0), lit(200.0)),
            (lit(-160.0), lit(200.0)),
            (lit(-100.0) * r3 - lit(80.0), lit(-100.0) + lit(80.0) * r3),
            (lit(-100.0) * r3 + lit(80.0), lit(-100.0) - lit(80.0) * r3),
            (lit(100.0) * r3 - lit(80.0), lit(-100.0) - lit(80.0) * r3),
            (lit(100.0) * r3 + lit(80.0), lit(-100.0) + lit(80.0) * r3),
        ];
        let guides = points.map(|(x, y)| Guide {
            point: Vector3::new(x, y, T::zero()),
            direction: Vector3::new(T::zero(), T::zero(), -T::one()),
            link_length: lit(350.0),
            branch: Branch::Plus,
            stroke: Interval::new(T::zero(), lit(320.0)),
        });
        // r_p = 150 mm at azimuths 150, 270, 30 deg; h = 100 mm.
        let h = lit(100.0);
        let nodes = [
            Vector3::new(lit(-75.0) * r3, lit(75.0), h),
            Vector3::new(T::zero(), lit(-150.0), h),
            Vector3::new(lit(75.0) * r3, lit(75.0), h),
        ];
        Self {
            assumed: true,
            guides,
            nodes,
            thresholds: ParallelThresholds::default(),
            fk: FkOptions::default(),
        }
    }

    /// The geometry of a symmetric layout, branch `+1` on every actuator,
    /// default thresholds, and `assumed = false`.
    pub fn from_layout(layout: &SymmetricLayout<T>) -> Self {
        let zero = T::zero();
        let guide = |point: Vector3<T>| Guide {
            point,
            direction: layout.direction,
            link_length: layout.link_length,
            branch: Branch::Plus,
            stroke: layout.stroke,
        };
        let mut guides = [guide(Vector3::zeros()); 6];
        let mut nodes = [Vector3::zeros(); 3];
        for (i, &gamma) in layout.leg_azimuths.iter().enumerate() {
            let (s, c) = gamma.sin_cos();
            let radial = Vector3::new(c, s, zero) * layout.base_radius;
            let tangential = Vector3::new(-s, c, zero) * layout.half_spacing;
            guides[2 * i] = guide(radial - tangential);
            guides[2 * i + 1] = guide(radial + tangential);
            let (sn, cn) = (gamma + layout.node_azimuth_offset).sin_cos();
            nodes[i] = Vector3::new(
                cn * layout.node_radius,
                sn * layout.node_radius,
                layout.node_height,
            );
        }
        Self {
            assumed: false,
            guides,
            nodes,
            thresholds: ParallelThresholds::default(),
            fk: FkOptions::default(),
        }
    }

    /// Checks the parameters: everything finite (strokes may be infinite),
    /// guide directions non-zero, links longer than zero, each stroke
    /// `min <= max`, nodes not all at `P`, thresholds positive (the serial one
    /// below 1), a positive FK tolerance and at least one iteration.
    ///
    /// Errors name the parameter, e.g. `module1.guides[2].link_length`.
    pub fn validate(&self) -> Result<(), Error> {
        const POINT: [[&str; 3]; 6] = [
            per_guide_xyz!("point", 0),
            per_guide_xyz!("point", 1),
            per_guide_xyz!("point", 2),
            per_guide_xyz!("point", 3),
            per_guide_xyz!("point", 4),
            per_guide_xyz!("point", 5),
        ];
        const DIRECTION: [[&str; 3]; 6] = [
            per_guide_xyz!("direction", 0),
            per_guide_xyz!("direction", 1),
            per_guide_xyz!("direction", 2),
            per_guide_xyz!("direction", 3),
            per_guide_xyz!("direction", 4),
            per_guide_xyz!("direction", 5),
        ];
        const DIRECTION_NORM: [&str; 6] = per_guide!("direction");
        const LINK: [&str; 6] = per_guide!("link_length");
        const STROKE: [&str; 6] = per_guide!("stroke");
        const NODE: [[&str; 3]; 3] = [
            [
                "module1.nodes[0].x",
                "module1.nodes[0].y",
                "module1.nodes[0].z",
            ],
            [
                "module1.nodes[1].x",
                "module1.nodes[1].y",
                "module1.nodes[1].z",
            ],
            [
                "module1.nodes[2].x",
                "module1.nodes[2].y",
                "module1.nodes[2].z",
            ],
        ];
        let invalid = |what, value: T| Error::InvalidParameter {
            what,
            value: value.to_f64(),
        };
        for (j, g) in self.guides.iter().enumerate() {
            check_vector(&g.point, POINT[j])?;
            check_vector(&g.direction, DIRECTION[j])?;
            let n = g.direction.norm();
            if !(n > T::zero() && n.finite()) {
                return Err(invalid(DIRECTION_NORM[j], n));
            }
            check_finite(g.link_length, LINK[j])?;
            if !(g.link_length > T::zero()) {
                return Err(invalid(LINK[j], g.link_length));
            }
            if !(g.stroke.min <= g.stroke.max) {
                return Err(invalid(STROKE[j], g.stroke.min));
            }
        }
        for (i, a) in self.nodes.iter().enumerate() {
            check_vector(a, NODE[i])?;
        }
        let scale = length_scale(&self.nodes);
        if !(scale > T::zero() && scale.finite()) {
            return Err(invalid("module1.nodes", scale));
        }
        let th = &self.thresholds;
        if !(th.serial > T::zero() && th.serial < T::one()) {
            return Err(invalid("module1.thresholds.serial", th.serial));
        }
        for (what, t) in [
            ("module1.thresholds.parallel", th.parallel),
            ("module1.thresholds.parallel_command", th.parallel_command),
            ("module1.thresholds.euler", th.euler),
            ("module1.fk.tolerance", self.fk.tolerance),
        ] {
            if !(t > T::zero() && t.finite()) {
                return Err(invalid(what, t));
            }
        }
        if self.fk.max_iterations == 0 {
            return Err(Error::InvalidParameter {
                what: "module1.fk.max_iterations",
                value: 0.0,
            });
        }
        Ok(())
    }
}

/// The root-mean-square distance of the nodes from `P`, mm.
fn length_scale<T: Real>(nodes: &[Vector3<T>; 3]) -> T {
    let sum = nodes
        .iter()
        .fold(T::zero(), |acc, a| acc + a.norm_squared());
    (sum / T::lit(3.0)).sqrt()
}

/// The six actuators `q1..q6` (index 0 to 5), or their rates.
///
/// As positions: mm along each guide from its point `G_j`. As rates: mm/s;
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
/// [module docs](self) for the physical meaning).
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

/// The legs at one pose: what the IK computes and the rates and margins reuse.
struct Legs<T: Real> {
    /// `R a_i`, mm, fixed frame.
    rho: [Vector3<T>; 3],
    /// `q_j`, mm.
    q: [T; 6],
    /// `e_j = A_i - B_j`, mm, fixed frame.
    e: [Vector3<T>; 6],
    /// `e_j . u_j`, mm.
    eu: [T; 6],
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
    fn node_arms(&self, r: &Matrix3<T>) -> [Vector3<T>; 3] {
        self.geometry.nodes.map(|a| r * a)
    }

    /// The closed-form IK of every actuator; checks only the reach.
    fn legs(&self, r: &Matrix3<T>, p: &Vector3<T>) -> Result<Legs<T>, Error> {
        let rho = self.node_arms(r);
        let mut q = [T::zero(); 6];
        let mut e = [Vector3::zeros(); 6];
        let mut eu = [T::zero(); 6];
        for (j, g) in self.geometry.guides.iter().enumerate() {
            let r_j = p + rho[j / 2] - g.point;
            let ru = r_j.dot(&g.direction);
            // l^2 - |r_perp|^2 as a product, which keeps its precision near 0.
            let d = (r_j - g.direction * ru).norm();
            let disc = (g.link_length - d) * (g.link_length + d);
            if !(disc >= T::zero()) {
                return Err(Error::LegOutOfReach {
                    actuator: actuator_number(j),
                    discriminant: disc.to_f64(),
                });
            }
            eu[j] = g.branch.sign::<T>() * disc.sqrt();
            q[j] = ru - eu[j];
            e[j] = r_j - g.direction * q[j];
        }
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
            e[j] = frame.position + rho[j / 2] - g.point - g.direction * q[j];
            eu[j] = e[j].dot(&g.direction);
        }
        self.check_serial(&eu)?;
        Ok(self.rates_unchecked(frame, &e, &eu))
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
    fn scaled_jacobian_rows(&self, rho: &[Vector3<T>; 3], e: &[Vector3<T>; 6]) -> [Vector6<T>; 6] {
        let inv_scale = T::one() / self.length_scale;
        let mut rows = [Vector6::zeros(); 6];
        for (j, (row, g)) in rows.iter_mut().zip(&self.geometry.guides).enumerate() {
            let n = e[j] / g.link_length;
            let m = rho[j / 2].cross(&n) * inv_scale;
            *row = Vector6::new(n.x, n.y, n.z, m.x, m.y, m.z);
        }
        rows
    }

    /// The dimensionless Jacobian of the parallel margin (rows as
    /// [`ParallelRobot::scaled_jacobian_rows`]).
    fn scaled_jacobian(&self, rho: &[Vector3<T>; 3], e: &[Vector3<T>; 6]) -> Matrix6<T> {
        Matrix6::from_rows(&self.scaled_jacobian_rows(rho, e).map(|r| r.transpose()))
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
        Ok(self.scaled_jacobian(&legs.rho, &legs.e))
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
    /// the previous cycle's weakest direction, kept in `tracker`, at a tenth
    /// of the cost of the full decomposition when it certifies (see
    /// [`MarginTracker`]). The margin agrees with [`ParallelRobot::solve`]'s
    /// within [`MarginTracker::TOLERANCE_F64`] / 2 relative (`f32`:
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

    fn solve_with(
        &self,
        frame: &PlatformFrame<T>,
        tracker: Option<&mut MarginTracker<T>>,
    ) -> Result<ParallelSolution<T>, Error> {
        check_frame(frame)?;
        let legs = self.legs(&frame.rotation, &frame.position)?;
        self.check_serial(&legs.eu)?;
        let q = Actuators(legs.q);
        self.check_strokes(&q)?;
        let margins = self.margins_of(&legs, tracker);
        let threshold = self.geometry.thresholds.parallel_command;
        if !(margins.parallel >= threshold) {
            return Err(Error::ParallelSingular {
                margin: margins.parallel.to_f64(),
                threshold: threshold.to_f64(),
            });
        }
        let (q_dot, q_ddot) = self.rates_unchecked(frame, &legs.e, &legs.eu);
        Ok(ParallelSolution {
            q,
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
            let e = p + rho[j / 2] - g.point - g.direction * q[j];
            worst = worst.max((e.norm() - g.link_length).abs() / g.link_length);
        }
        Ok(worst)
    }

    /// Forward kinematics with the geometry's stopping rules
    /// ([`ParallelGeometry::fk`]): see [`ParallelRobot::fk_with`].
    pub fn fk(&self, q: &Actuators<T>, guess: &Pose<T>) -> Result<FkSolution<T>, Error> {
        self.fk_with(q, guess, &self.geometry.fk)
    }

    /// Forward kinematics: the pose at which the actuators `q` (mm) hold the
    /// platform, by Newton's method from `guess`, globalised by continuation
    /// (see the [module docs](self)). The guess picks the assembly mode: the
    /// solution is the one connected to it; seed it with the previous pose
    /// along a motion. `FkSolution::iterations` counts the Newton steps of
    /// all stages.
    ///
    /// Strokes are not checked (the actuators are measured, not commanded).
    /// Errors: non-finite `q` or guess ([`Error::NonFinite`]); a singular
    /// Jacobian at an iterate ([`Error::SingularJacobian`], parallel or
    /// Euler-angle kind, with the iteration); no convergence within
    /// `options.max_iterations` steps or a diverging iterate
    /// ([`Error::NoConvergence`]); a solution with a link on the other branch
    /// ([`Error::BranchMismatch`]); invalid options
    /// ([`Error::InvalidParameter`]).
    pub fn fk_with(
        &self,
        q: &Actuators<T>,
        guess: &Pose<T>,
        options: &FkOptions<T>,
    ) -> Result<FkSolution<T>, Error> {
        q.check_finite()?;
        guess.check_finite()?;
        if !(options.tolerance > T::zero() && options.tolerance.finite()) {
            return Err(Error::InvalidParameter {
                what: "fk.tolerance",
                value: options.tolerance.to_f64(),
            });
        }
        let guides = &self.geometry.guides;
        let sliders_at = |target: &[T; 6]| -> [Vector3<T>; 6] {
            core::array::from_fn(|j| guides[j].point + guides[j].direction * target[j])
        };
        let mut budget = Budget {
            used: 0,
            max: options.max_iterations,
        };
        // The homotopy's start: the guess's own actuators, which the guess
        // satisfies exactly. A guess out of reach has none: then a single
        // stage of Newton's method with a line search.
        let Ok(start) = self.legs(&guess.rotation(), &guess.position()) else {
            let (pose, c) = self
                .newton(
                    guess,
                    &sliders_at(&q.0),
                    options.tolerance,
                    false,
                    &mut budget,
                )
                .map_err(|stage| stage.into_error(&budget))?;
            return self.fk_solution(pose, &c, budget.used);
        };
        let stage_tolerance = options.tolerance.max(T::lit(FK_STAGE_TOLERANCE));
        let min_step = T::lit(FK_MIN_CONTINUATION_STEP);
        let (mut x, mut s, mut ds) = (*guess, T::zero(), T::one());
        loop {
            let last = s + ds >= T::one();
            let s_next = if last { T::one() } else { s + ds };
            let target: [T; 6] = if last {
                q.0
            } else {
                core::array::from_fn(|j| start.q[j] + (q[j] - start.q[j]) * s_next)
            };
            let tolerance = if last {
                options.tolerance
            } else {
                stage_tolerance
            };
            match self.newton(&x, &sliders_at(&target), tolerance, true, &mut budget) {
                Ok((pose, c)) => {
                    if last {
                        return self.fk_solution(pose, &c, budget.used);
                    }
                    x = pose;
                    s = s_next;
                    ds = (ds * T::lit(2.0)).min(T::one());
                }
                Err(Stage::NotContracting { residual }) => {
                    ds *= T::lit(0.5);
                    if ds < min_step {
                        return Err(Error::NoConvergence {
                            iterations: budget.used,
                            residual: residual.to_f64(),
                        });
                    }
                }
                Err(stage) => return Err(stage.into_error(&budget)),
            }
        }
    }

    /// The converged pose, after the check of every link's branch.
    fn fk_solution(
        &self,
        pose: Pose<T>,
        c: &Constraints<T>,
        iterations: u32,
    ) -> Result<FkSolution<T>, Error> {
        for (j, g) in self.geometry.guides.iter().enumerate() {
            if c.e[j].dot(&g.direction) * g.branch.sign::<T>() < T::zero() {
                return Err(Error::BranchMismatch {
                    actuator: actuator_number(j),
                });
            }
        }
        Ok(FkSolution {
            pose,
            iterations,
            residual: c.residual,
        })
    }

    /// Newton's method on the constraints with the sliders at `sliders`, from
    /// `x`, until the residual is at most `tolerance`. With `contract`, every
    /// step must be at most half the previous one (a continuation stage,
    /// retried shorter otherwise); without, a backtracking line search on
    /// the residual keeps each step from leaping away.
    fn newton(
        &self,
        x: &Pose<T>,
        sliders: &[Vector3<T>; 6],
        tolerance: T,
        contract: bool,
        budget: &mut Budget,
    ) -> Result<(Pose<T>, Constraints<T>), Stage<T>> {
        let th = &self.geometry.thresholds;
        let mut x = *x;
        let mut c = self.constraints(&x, sliders);
        let mut previous_step = T::lit(f64::INFINITY);
        loop {
            if !c.residual.finite() {
                return Err(if contract {
                    Stage::NotContracting {
                        residual: T::lit(f64::INFINITY),
                    }
                } else {
                    Stage::Diverged
                });
            }
            if c.residual <= tolerance {
                return Ok((x, c));
            }
            if budget.used >= budget.max {
                return Err(Stage::Exhausted {
                    residual: c.residual,
                });
            }
            let (s1, c1) = x.psi.sin_cos();
            let (s2, c2) = x.theta.sin_cos();
            if !(c2.abs() >= th.euler) {
                return Err(Stage::Singular(Error::SingularJacobian {
                    kind: ParallelSingularity::EulerAngles,
                    iteration: budget.used,
                    margin: c2.abs().to_f64(),
                    threshold: th.euler.to_f64(),
                }));
            }
            let singular = |margin: T| {
                Stage::Singular(Error::SingularJacobian {
                    kind: ParallelSingularity::Parallel,
                    iteration: budget.used,
                    margin: margin.to_f64(),
                    threshold: th.parallel.to_f64(),
                })
            };
            let svd = Svd6::new(&self.scaled_jacobian(&c.rho, &c.e));
            let sigma_min = svd.smallest();
            if !(sigma_min >= th.parallel) {
                return Err(singular(sigma_min));
            }
            // The Newton step in (dP, L omega_F), then omega_F to the Euler angles.
            let step = svd.solve(&(-c.f));
            let w = Vector3::new(step[3], step[4], step[5]) / self.length_scale;
            let d_phi = (c1 * w.z - s1 * w.y) / c2;
            let d_theta = c1 * w.y + s1 * w.z;
            let d_psi = w.x - s2 * d_phi;
            let dx = [step[0], step[1], step[2], d_psi, d_theta, d_phi];
            let x0 = x.to_array();
            budget.used += 1;
            if contract {
                let size = step.norm();
                if !(size <= T::lit(0.5) * previous_step) {
                    return Err(Stage::NotContracting {
                        residual: c.residual,
                    });
                }
                previous_step = size;
                x = Pose::from_array(core::array::from_fn(|k| x0[k] + dx[k]));
                c = self.constraints(&x, sliders);
                continue;
            }
            // Backtracking on the merit |f|^2 (Armijo; the Newton step is a
            // descent direction): the full step near the solution.
            let mut alpha = T::one();
            let mut halvings = 0;
            loop {
                let trial = Pose::from_array(core::array::from_fn(|k| x0[k] + dx[k] * alpha));
                let ct = self.constraints(&trial, sliders);
                let armijo = T::one() - T::lit(1e-4) * alpha;
                if ct.merit <= c.merit * armijo || (halvings == 0 && ct.merit <= c.merit) {
                    x = trial;
                    c = ct;
                    break;
                }
                halvings += 1;
                if halvings > FK_MAX_HALVINGS {
                    return Err(Stage::Exhausted {
                        residual: c.residual,
                    });
                }
                alpha *= T::lit(0.5);
            }
        }
    }

    /// The constraints of the forward kinematics at the pose `x`, with the
    /// sliders at `sliders` (mm, fixed frame).
    fn constraints(&self, x: &Pose<T>, sliders: &[Vector3<T>; 6]) -> Constraints<T> {
        let rho = self.node_arms(&x.rotation());
        let p = x.position();
        let mut e = [Vector3::zeros(); 6];
        let mut f = Vector6::zeros();
        let mut residual = T::zero();
        let mut merit = T::zero();
        for (j, g) in self.geometry.guides.iter().enumerate() {
            e[j] = p + rho[j / 2] - sliders[j];
            f[j] = (e[j].norm_squared() - g.link_length * g.link_length)
                / (T::lit(2.0) * g.link_length);
            let relative = f[j] / g.link_length;
            residual = residual.max(relative.abs());
            merit += relative * relative;
        }
        Constraints {
            rho,
            e,
            f,
            residual,
            merit,
        }
    }
}

/// The forward kinematics' constraints at one iterate.
struct Constraints<T: Real> {
    /// `R a_i`, mm, fixed frame.
    rho: [Vector3<T>; 3],
    /// `e_j = A_i - B_j`, mm, fixed frame.
    e: [Vector3<T>; 6],
    /// `f_j = (|e_j|^2 - l_j^2) / (2 l_j)`, mm.
    f: Vector6<T>,
    /// `max_j |f_j| / l_j`.
    residual: T,
    /// `sum_j (f_j / l_j)^2`, the line search's merit.
    merit: T,
}

/// The most halvings of a Newton step in the line search (a step of 2^-30).
const FK_MAX_HALVINGS: u32 = 30;

/// The residual (relative) to which the intermediate stages of the
/// continuation are solved: near enough to the path for the next stage.
const FK_STAGE_TOLERANCE: f64 = 1e-8;

/// The shortest continuation step (a fraction of the way from the guess's
/// actuators to the target) before the forward kinematics gives up.
const FK_MIN_CONTINUATION_STEP: f64 = 1.0 / 1024.0;

/// The Newton steps used and allowed, over all stages.
struct Budget {
    used: u32,
    max: u32,
}

/// How a stage of Newton's method ended without converging.
enum Stage<T> {
    /// A step not at most half the previous one (or a non-finite residual):
    /// the stage was too long.
    NotContracting {
        /// The residual before the step.
        residual: T,
    },
    /// A non-finite residual, without continuation.
    Diverged,
    /// The iteration budget is spent, or the line search failed.
    Exhausted {
        /// The last residual.
        residual: T,
    },
    /// A singular Jacobian: the error to report.
    Singular(Error),
}

impl<T: Real> Stage<T> {
    fn into_error(self, budget: &Budget) -> Error {
        match self {
            Stage::NotContracting { residual } | Stage::Exhausted { residual } => {
                Error::NoConvergence {
                    iterations: budget.used,
                    residual: residual.to_f64(),
                }
            }
            Stage::Diverged => Error::NoConvergence {
                iterations: budget.used,
                residual: f64::INFINITY,
            },
            Stage::Singular(e) => e,
        }
    }
}

/// `Err(Error::NonFinite)` (`what = "frame"`) if any number of the frame is
/// NaN or infinite.
fn check_frame<T: Real>(frame: &PlatformFrame<T>) -> Result<(), Error> {
    let numbers = || {
        frame
            .rotation
            .as_slice()
            .iter()
            .chain(frame.position.as_slice())
            .chain(frame.velocity.as_slice())
            .chain(frame.acceleration.as_slice())
            .chain(frame.omega.as_slice())
            .chain(frame.alpha.as_slice())
    };
    // `v * 0` is 0 for a finite `v` and NaN for NaN or an infinity: one sum
    // over the 24 numbers, without a branch each, tells whether all are
    // finite. Written out rather than folded over `numbers()`, which costs
    // about 250 instructions more on this per-cycle path.
    let mut probe = T::zero();
    for &v in frame.rotation.as_slice() {
        probe += v * T::zero();
    }
    for v in [
        &frame.position,
        &frame.velocity,
        &frame.acceleration,
        &frame.omega,
        &frame.alpha,
    ] {
        probe += v.x * T::zero() + v.y * T::zero() + v.z * T::zero();
    }
    if probe == T::zero() {
        return Ok(());
    }
    for &v in numbers() {
        check_finite(v, "frame")?;
    }
    Ok(())
}

/// The singular value decomposition of a 6x6 matrix `M` by one-sided
/// (Hestenes) Jacobi rotations: `M V = W` with the columns of `W` orthogonal,
/// their norms the singular values, `V` orthogonal.
///
/// Written here rather than taken from nalgebra because nalgebra's SVD keeps
/// bounds-checked indexing and `unwrap`s that the optimiser cannot remove, and
/// this runs every control cycle (the parallel margin), where nothing may
/// panic: every access below is by iterator or `get`. Jacobi also gives the
/// small singular values to high relative accuracy, which is what a margin
/// near a singularity needs. At most [`JACOBI_MAX_SWEEPS`] sweeps of 15
/// rotations in the order [`JACOBI_ORDER`]; a 6x6 matrix converges in 5 to 8
/// (the margins along the paper's motion: 4 sweeps of 15 rotations, one of
/// 3 to 9, one that finds nothing left to rotate).
struct Svd6<T: Real> {
    /// `W = M V`, by columns.
    w: [Vector6<T>; 6],
    /// `V`, by columns (zeros when not asked for).
    v: [Vector6<T>; 6],
}

/// The most sweeps of the Jacobi SVD (each sweep rotates all 15 pairs).
const JACOBI_MAX_SWEEPS: usize = 30;

/// The order of the 15 pairs of a sweep: 5 rounds of 3 disjoint pairs (a
/// round-robin tournament of the 6 columns). The three rotations of a round
/// touch different columns, so the processor overlaps them; in the cyclic
/// order `(0,1), (0,2), ...` each rotation waits for the previous one's
/// square roots and division. Convergence is about the same (6 sweeps for
/// the margins along the paper's motion, about 5% more rotations); the time
/// is about 30% less on an out-of-order x86-64 core.
const JACOBI_ORDER: [[(usize, usize); 3]; 5] = [
    [(0, 1), (2, 5), (3, 4)],
    [(0, 2), (1, 3), (4, 5)],
    [(0, 3), (2, 4), (1, 5)],
    [(0, 4), (3, 5), (1, 2)],
    [(0, 5), (1, 4), (2, 3)],
];

impl<T: Real> Svd6<T> {
    /// The decomposition of `m`, `V` accumulated.
    fn new(m: &Matrix6<T>) -> Self {
        let mut w = [Vector6::zeros(); 6];
        for (dst, col) in w.iter_mut().zip(m.column_iter()) {
            *dst = col.into_owned();
        }
        Self::of_columns::<true>(w)
    }

    /// The decomposition of the matrix whose columns are `w`; `V` is
    /// accumulated only `WITH_V` (the margin needs the values only).
    fn of_columns<const WITH_V: bool>(mut w: [Vector6<T>; 6]) -> Self {
        let mut v = [Vector6::zeros(); 6];
        if WITH_V {
            for (k, col) in v.iter_mut().enumerate() {
                if let Some(x) = col.get_mut(k) {
                    *x = T::one();
                }
            }
        }
        let two = T::lit(2.0);
        for _ in 0..JACOBI_MAX_SWEEPS {
            // The squared column norms, recomputed every sweep (no drift) and
            // updated after each rotation (`|w_p|^2 - t gamma`, `|w_q|^2 + t gamma`).
            let mut norms = [T::zero(); 6];
            for (n, col) in norms.iter_mut().zip(&w) {
                *n = col.norm_squared();
            }
            let mut rotated = false;
            for &(p, q) in JACOBI_ORDER.iter().flatten() {
                let (Some(&wp), Some(&wq), Some(&alpha), Some(&beta)) =
                    (w.get(p), w.get(q), norms.get(p), norms.get(q))
                else {
                    continue;
                };
                let gamma = wp.dot(&wq);
                // Orthogonal to working precision (or a zero column):
                // |gamma| <= eps sqrt(alpha beta), without the root.
                if !(gamma * gamma > T::EPSILON * T::EPSILON * alpha * beta) {
                    continue;
                }
                rotated = true;
                // The rotation that makes the pair orthogonal, the smaller of
                // the two angles: with d = beta - alpha and
                // r = sqrt(d^2 + 4 gamma^2), t = tan = sign(d) 2 gamma / (|d| + r),
                // c = 1 / sqrt(1 + t^2) = sqrt(u / 2r) and s = c t, where
                // u = |d| + r: two roots and one division on the way to the
                // new columns (Rutishauser's form through zeta = d / 2 gamma
                // takes three divisions). No overflow: gamma != 0 here, and
                // the columns of the matrices solved (scaled Jacobians) have
                // norms of order 1.
                let d = beta - alpha;
                let g2 = two * gamma;
                let r = (d * d + g2 * g2).sqrt();
                let u = d.abs() + r;
                let sg = if d >= T::zero() { g2 } else { -g2 };
                let h = T::one() / (two * r * u).sqrt();
                let (c, s) = (u * h, sg * h);
                let t_gamma = sg / u * gamma;
                if let Some(x) = w.get_mut(p) {
                    *x = wp * c - wq * s;
                }
                if let Some(x) = w.get_mut(q) {
                    *x = wp * s + wq * c;
                }
                if let Some(n) = norms.get_mut(p) {
                    *n = alpha - t_gamma;
                }
                if let Some(n) = norms.get_mut(q) {
                    *n = beta + t_gamma;
                }
                if WITH_V {
                    let (Some(&vp), Some(&vq)) = (v.get(p), v.get(q)) else {
                        continue;
                    };
                    if let Some(x) = v.get_mut(p) {
                        *x = vp * c - vq * s;
                    }
                    if let Some(x) = v.get_mut(q) {
                        *x = vp * s + vq * c;
                    }
                }
            }
            if !rotated {
                break;
            }
        }
        Self { w, v }
    }

    /// The smallest singular value.
    fn smallest(&self) -> T {
        self.smallest_with_direction().0
    }

    /// The smallest singular value and, for a decomposition of `M = J^T`,
    /// the unit right singular vector of `J` that goes with it (the column
    /// of `W` divided by its norm; `None` if that norm is 0).
    fn smallest_with_direction(&self) -> (T, Option<[T; 6]>) {
        let mut best = (T::lit(f64::INFINITY), None);
        for col in &self.w {
            let n = col.norm();
            if n < best.0 {
                best = (n, Some(col));
            }
        }
        let (sigma, col) = best;
        let x = col
            .filter(|_| sigma > T::zero())
            .map(|col| (col / sigma).into());
        (sigma, x)
    }

    /// `M^-1 b` (`V` must have been accumulated); the components along a zero
    /// singular value are left out.
    fn solve(&self, b: &Vector6<T>) -> Vector6<T> {
        let mut x = Vector6::zeros();
        for (w, v) in self.w.iter().zip(&self.v) {
            let n2 = w.norm_squared();
            if n2 > T::zero() {
                x += v * (w.dot(b) / n2);
            }
        }
        x
    }
}

/// `j + 1` as a `u8` (the actuators are numbered 1 to 6).
fn actuator_number(j: usize) -> u8 {
    match j {
        0 => 1,
        1 => 2,
        2 => 3,
        3 => 4,
        4 => 5,
        _ => 6,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assumed_guides_follow_the_table() {
        let g = ParallelGeometry::<f64>::assumed();
        assert!((g.guides[0].point - Vector3::new(160.0, 200.0, 0.0)).norm() < 1e-12);
        assert!((g.guides[1].point - Vector3::new(-160.0, 200.0, 0.0)).norm() < 1e-12);
        let a1 = Vector3::new(-150.0 * 0.75f64.sqrt(), 75.0, 100.0);
        assert!((g.nodes[0] - a1).norm() < 1e-12);
        assert!(g.assumed);
        g.validate().expect("valid");
    }

    /// A deterministic pseudo-random matrix with entries in `[-1, 1]`.
    fn matrix(seed: u64) -> Matrix6<f64> {
        let mut x = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        Matrix6::from_fn(|_, _| {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        })
    }

    #[test]
    fn jacobi_svd_matches_nalgebra() {
        for seed in 0..200 {
            let mut m = matrix(seed);
            if seed % 4 == 0 {
                // Rank 5: one column a combination of two others.
                let c = m.column(1) * 0.3 - m.column(4) * 1.7;
                m.set_column(2, &c);
            }
            let svd = Svd6::new(&m);
            let mut ours: [f64; 6] = core::array::from_fn(|k| svd.w[k].norm());
            ours.sort_by(|a, b| b.total_cmp(a));
            let theirs = m.singular_values();
            for k in 0..6 {
                assert!(
                    (ours[k] - theirs[k]).abs() < 1e-13,
                    "seed {seed}: {ours:?} vs {theirs}"
                );
            }
            // V orthogonal, M V = W.
            let v = Matrix6::from_columns(&svd.v);
            assert!((v.transpose() * v - Matrix6::identity()).amax() < 1e-14);
            assert!((m * v - Matrix6::from_columns(&svd.w)).amax() < 1e-13);
            if seed % 4 != 0 {
                let b = matrix(seed + 1000).column(0).into_owned();
                assert!((m * svd.solve(&b) - b).amax() < 1e-10 * (1.0 / theirs[5]));
            } else {
                assert!(svd.smallest() < 1e-14);
            }
        }
    }

    #[test]
    fn length_scale_of_the_assumed_geometry_is_180_mm() {
        let r = ParallelRobot::<f64>::assumed();
        assert!((r.length_scale() - 180.277_563_773_199_47).abs() < 1e-9);
    }
}
