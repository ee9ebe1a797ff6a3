//! Module 1's parameters: the guides, the symmetric layout they can be built
//! from, the thresholds and the forward kinematics' stopping rules, and
//! their validation.

use nalgebra::Vector3;

use crate::check::check_vector;
use crate::error::{Error, check_finite};
use crate::interval::Interval;
use crate::presets::module1 as assumed;
use crate::real::{Real, deg};

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

/// The largest encoder offset a guide accepts, in lengths of its link
/// ([`ParallelGeometry::validate`]).
pub const MAX_OFFSET_LINKS: f64 = 1000.0;

/// One actuator of module 1: its straight guide, its slider's stroke, and the
/// link from the slider to its leg's node.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Guide<T: Real> {
    /// `G_j`, where the slider is when its reading `q_j` equals the encoder
    /// offset (at `q_j = 0` with the default offset 0), mm, fixed frame.
    pub point: Vector3<T>,
    /// `u_j`, the direction in which `q_j` grows, fixed frame. Unit length:
    /// any non-zero vector is accepted and [`ParallelRobot::new`] normalises it.
    ///
    /// [`ParallelRobot::new`]: crate::ParallelRobot::new
    pub direction: Vector3<T>,
    /// `l_j`, the length of the link from slider to node (centre to centre), mm.
    pub link_length: T,
    /// `s_j`, which root of the inverse kinematics this actuator takes.
    pub branch: Branch,
    /// The slider's stroke, mm: the reading `q_j` must stay in it (default
    /// **assumed** `[0, 320]` mm, see `docs/model.md`, *Module 1, the
    /// parallel robot*). May be infinite.
    pub stroke: Interval<T>,
    /// `o_j`, the encoder's zero offset, mm: the reading `q_j` (what the
    /// firmware sees, and every `q_j` the solvers take or return) is the
    /// slider's position along its guide from `G_j` plus `o_j`, so that
    /// `B_j = G_j + (q_j - o_j) u_j`. Default 0; found by calibration. At
    /// most [`MAX_OFFSET_LINKS`] link lengths in size: the reading carries
    /// the slider's position to the float type's precision times
    /// `|o_j| / l_j`.
    #[cfg_attr(feature = "serde", serde(default = "zero"))]
    pub encoder_offset: T,
}

/// A file without an encoder offset reads it as 0.
#[cfg(feature = "serde")]
fn zero<T: Real>() -> T {
    T::zero()
}

/// The dimensions of a three-legged module 1 with a 120-degree symmetry, from
/// which [`ParallelGeometry::from_layout`] builds the six guides and three
/// nodes (see `docs/model.md`, *Module 1, the parallel robot*, assumed
/// dimensions).
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
    /// The **assumed** dimensions ([`presets::module1`](crate::presets::module1);
    /// not the real robot's, which are not published): legs at 90, 210,
    /// 330 deg, `R_b = 200 mm`, `w = 160 mm`, guides along `(0, 0, -1)` from
    /// `Z = 0`, links of 350 mm, strokes `[0, 320] mm`, nodes at
    /// `r_p = 150 mm`, `h = 100 mm`, azimuths `gamma_i + 60 deg`.
    pub fn assumed() -> Self {
        let lit = T::lit;
        let [dx, dy, dz] = assumed::GUIDE_DIRECTION;
        let [stroke_min, stroke_max] = assumed::STROKE_MM;
        Self {
            leg_azimuths: assumed::LEG_AZIMUTHS_DEG.map(deg),
            base_radius: lit(assumed::BASE_RADIUS_MM),
            half_spacing: lit(assumed::HALF_SPACING_MM),
            direction: Vector3::new(lit(dx), lit(dy), lit(dz)),
            link_length: lit(assumed::LINK_LENGTH_MM),
            stroke: Interval::new(lit(stroke_min), lit(stroke_max)),
            node_radius: lit(assumed::NODE_RADIUS_MM),
            node_height: lit(assumed::NODE_HEIGHT_MM),
            node_azimuth_offset: deg(assumed::NODE_AZIMUTH_OFFSET_DEG),
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
    ///
    /// [`ParallelRobot::ik`]: crate::ParallelRobot::ik
    /// [`ParallelRobot::rates`]: crate::ParallelRobot::rates
    /// [`ParallelRobot::solve`]: crate::ParallelRobot::solve
    pub serial: T,
    /// Smallest parallel margin (see the [module docs](crate::parallel))
    /// that the forward kinematics accepts at an iterate.
    pub parallel: T,
    /// Smallest parallel margin that [`ParallelRobot::solve`], the per-cycle
    /// call, accepts: a command closer to a parallel singularity is refused
    /// ([`Error::ParallelSingular`]). At the default `1e-2`, actuator errors
    /// are amplified at most about 100 times into platform errors. It is
    /// checked at each call, so a trajectory sampled at 1 kHz cannot step over
    /// a singularity unnoticed unless its margin changes by more than `1e-2`
    /// per sample.
    ///
    /// [`ParallelRobot::solve`]: crate::ParallelRobot::solve
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

/// The record of a calibration of module 1: its dimensions were fitted to
/// the actuator readings at measured platform poses.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Calibration {
    /// How many measured poses the fit used.
    pub poses: u32,
    /// The root-mean-square actuator residual after the fit, mm.
    pub rms_mm: f64,
}

/// Where module 1's dimensions come from, as every module-1 number printed
/// must say: [`ParallelGeometry::provenance`]. Its `Display` is the label
/// (`assumed geometry (not the real robot's)`,
/// `calibrated (RMS 0.012 mm over 50 poses)`, `measured`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Provenance {
    /// The assumed dimensions, not the real robot's.
    Assumed,
    /// Fitted to measurements ([`Calibration`]).
    Calibrated(Calibration),
    /// Given as the real robot's, without a calibration record.
    Measured,
}

impl core::fmt::Display for Provenance {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Provenance::Assumed => f.write_str("assumed geometry (not the real robot's)"),
            Provenance::Calibrated(c) => write!(
                f,
                "calibrated (RMS {} mm over {} poses)",
                parasils_num::Num::new(c.rms_mm),
                c.poses
            ),
            Provenance::Measured => f.write_str("measured"),
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
    /// The record of the calibration that fitted these dimensions to
    /// measured poses, if they were (see [`Calibration`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub calibration: Option<Calibration>,
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
    /// The **assumed** geometry (see `docs/model.md`, *Module 1, the
    /// parallel robot*): a plausible robot of the right family, **not** the
    /// real PARA-SILSROB, whose dimensions are not published
    /// ([`SymmetricLayout::assumed`]; `assumed` is `true`). Load the real
    /// dimensions from a file to replace it.
    ///
    /// The coordinates are written in closed form (with `sqrt 3`), so that
    /// the values a file shows are `160`, `200`, `75`, not `74.99999999999999`
    /// from `sin(150 deg)`; they equal those of
    /// [`ParallelGeometry::from_layout`] of [`SymmetricLayout::assumed`] to
    /// the rounding of the trigonometry. The closed form is that of the
    /// preset azimuths (legs at 90, 210, 330 deg, nodes 60 deg further on);
    /// the lengths are those of [`presets::module1`](crate::presets::module1).
    pub fn assumed() -> Self {
        let lit = T::lit;
        let r3 = lit(3.0).sqrt();
        // G_(2i-1), G_(2i) = R_b c_i -+ w t_i: at 90 deg, (+-w, R_b); at 210
        // and 330 deg, (-+R_b sqrt3/2 -+ w/2, -R_b/2 +- w sqrt3/2). The halves
        // are exact in f64.
        let (rb, w) = (assumed::BASE_RADIUS_MM, assumed::HALF_SPACING_MM);
        let (b, v) = (rb / 2.0, w / 2.0);
        let points = [
            (lit(w), lit(rb)),
            (lit(-w), lit(rb)),
            (lit(-b) * r3 - lit(v), lit(-b) + lit(v) * r3),
            (lit(-b) * r3 + lit(v), lit(-b) - lit(v) * r3),
            (lit(b) * r3 - lit(v), lit(-b) - lit(v) * r3),
            (lit(b) * r3 + lit(v), lit(-b) + lit(v) * r3),
        ];
        let [dx, dy, dz] = assumed::GUIDE_DIRECTION;
        let [stroke_min, stroke_max] = assumed::STROKE_MM;
        let guides = points.map(|(x, y)| Guide {
            point: Vector3::new(x, y, T::zero()),
            direction: Vector3::new(lit(dx), lit(dy), lit(dz)),
            link_length: lit(assumed::LINK_LENGTH_MM),
            branch: Branch::Plus,
            stroke: Interval::new(lit(stroke_min), lit(stroke_max)),
            encoder_offset: T::zero(),
        });
        // r_p at azimuths 150, 270, 30 deg: (-+r_p sqrt3/2, r_p/2) and
        // (0, -r_p); the height h.
        let rp = assumed::NODE_RADIUS_MM;
        let h = lit(assumed::NODE_HEIGHT_MM);
        let nodes = [
            Vector3::new(lit(-rp / 2.0) * r3, lit(rp / 2.0), h),
            Vector3::new(T::zero(), lit(-rp), h),
            Vector3::new(lit(rp / 2.0) * r3, lit(rp / 2.0), h),
        ];
        Self {
            assumed: true,
            calibration: None,
            guides,
            nodes,
            thresholds: ParallelThresholds::default(),
            fk: FkOptions::default(),
        }
    }

    /// Where the dimensions come from: assumed (`assumed` is true), else
    /// calibrated when a [`Calibration`] is recorded, else measured.
    pub fn provenance(&self) -> Provenance {
        match (self.assumed, self.calibration) {
            (true, _) => Provenance::Assumed,
            (false, Some(c)) => Provenance::Calibrated(c),
            (false, None) => Provenance::Measured,
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
            encoder_offset: zero,
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
            calibration: None,
            guides,
            nodes,
            thresholds: ParallelThresholds::default(),
            fk: FkOptions::default(),
        }
    }

    /// Checks the parameters: everything finite (strokes may be infinite,
    /// encoder offsets may not), encoder offsets at most
    /// [`MAX_OFFSET_LINKS`] times their link's length, a calibration record of at least one pose
    /// and a finite RMS `>= 0`,
    /// guide directions non-zero, links longer than zero (and than about
    /// 1e-146 mm in f64, 3e-16 mm in f32) and with a finite square (shorter
    /// than about 1.3e154 mm in f64, 1.8e19 mm in f32), each stroke
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
        const OFFSET: [&str; 6] = per_guide!("encoder_offset");
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
            // Longer than zero, and long enough that the IK's squares of
            // lengths stay normal numbers with room for rounding (past about
            // 1e-146 mm in f64, 3e-16 mm in f32); shorter ones lose the
            // IK's precision. Short enough that its square is finite (below
            // about 1.3e154 mm in f64, 1.8e19 mm in f32): the FK's
            // constraint `|e|^2 - l^2` of a longer one is NaN at every pose.
            let l = g.link_length;
            if !(l > T::zero() && l * l * T::EPSILON >= T::MIN_POSITIVE && (l * l).finite()) {
                return Err(invalid(LINK[j], g.link_length));
            }
            if !(g.stroke.min <= g.stroke.max) {
                return Err(invalid(STROKE[j], g.stroke.min));
            }
            check_finite(g.encoder_offset, OFFSET[j])?;
            // The reading `slider + o_j` rounds the slider's position to
            // the precision of `o_j`: an offset of many link lengths would
            // leave the readings, and the IK's result, meaningless.
            if !(g.encoder_offset.abs() <= T::lit(MAX_OFFSET_LINKS) * l) {
                return Err(invalid(OFFSET[j], g.encoder_offset));
            }
        }
        for (i, a) in self.nodes.iter().enumerate() {
            check_vector(a, NODE[i])?;
        }
        if let Some(c) = self.calibration {
            if c.poses == 0 {
                return Err(invalid("module1.calibration.poses", T::zero()));
            }
            if !(c.rms_mm >= 0.0 && c.rms_mm.is_finite()) {
                return Err(Error::InvalidParameter {
                    what: "module1.calibration.rms_mm",
                    value: c.rms_mm,
                });
            }
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
pub(super) fn length_scale<T: Real>(nodes: &[Vector3<T>; 3]) -> T {
    let sum = nodes
        .iter()
        .fold(T::zero(), |acc, a| acc + a.norm_squared());
    (sum / T::lit(3.0)).sqrt()
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

    use std::string::ToString;

    #[test]
    fn the_label_says_where_the_dimensions_come_from() {
        let mut g = ParallelGeometry::<f64>::assumed();
        assert_eq!(
            g.provenance().to_string(),
            "assumed geometry (not the real robot's)"
        );
        g.calibration = Some(Calibration {
            poses: 50,
            rms_mm: 0.0123,
        });
        // Assumed wins: a calibration record does not make it real.
        assert_eq!(g.provenance(), Provenance::Assumed);
        g.assumed = false;
        assert_eq!(
            g.provenance().to_string(),
            "calibrated (RMS 0.0123 mm over 50 poses)"
        );
        g.calibration = None;
        assert_eq!(g.provenance().to_string(), "measured");
    }

    #[test]
    fn a_calibration_record_is_checked() {
        let mut g = ParallelGeometry::<f64>::assumed();
        for (record, what) in [
            ((0, 0.01), "module1.calibration.poses"),
            ((50, f64::NAN), "module1.calibration.rms_mm"),
            ((50, -0.01), "module1.calibration.rms_mm"),
        ] {
            g.calibration = Some(Calibration {
                poses: record.0,
                rms_mm: record.1,
            });
            let e = g.validate().expect_err("invalid record");
            assert!(
                matches!(e, Error::InvalidParameter { what: w, .. } if w == what),
                "{e:?}"
            );
        }
    }

    #[test]
    fn a_link_whose_square_overflows_is_refused() {
        // The fuzzer's case (f32): a link of 8.6e33 mm. Its square is
        // infinite, the FK's constraint `|e|^2 - l^2` NaN at every pose, and
        // the FK's residual ignored it: an `Ok` pose that does not hold the
        // link. Refused by validation now; 1e19 mm (square 1e38) is not.
        let mut g = ParallelGeometry::<f32>::assumed();
        g.guides[3].link_length = 8.640_369e33;
        assert!(
            matches!(
                g.validate(),
                Err(Error::InvalidParameter {
                    what: "module1.guides[3].link_length",
                    ..
                })
            ),
            "{:?}",
            g.validate()
        );
        g.guides[3].link_length = 1e19;
        g.validate().expect("a square of 1e38 is finite in f32");
        let mut g = ParallelGeometry::<f64>::assumed();
        g.guides[0].link_length = 1e155;
        assert!(g.validate().is_err());
    }

    #[test]
    fn an_offset_of_more_than_a_thousand_links_is_refused() {
        let mut g = ParallelGeometry::<f64>::assumed();
        g.guides[3].encoder_offset = -350.0 * 1000.0;
        assert!(g.validate().is_ok());
        g.guides[3].encoder_offset = -350.0 * 1000.0 - 1.0;
        let e = g.validate().expect_err("too large");
        assert!(
            e.to_string().contains("module1.guides[3].encoder_offset"),
            "{e}"
        );
    }

    #[test]
    fn a_non_finite_encoder_offset_is_named() {
        let mut g = ParallelGeometry::<f64>::assumed();
        g.guides[4].encoder_offset = f64::NAN;
        let e = g.validate().expect_err("NaN offset");
        assert!(
            e.to_string().contains("module1.guides[4].encoder_offset"),
            "{e}"
        );
    }
}
