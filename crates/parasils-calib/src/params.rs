//! The identification parameters of module 1 and their mapping to and from
//! a [`ParallelGeometry`]: one vector of [`PARAMETERS`] numbers, each named
//! with the robot file's vocabulary.
//!
//! Per actuator `j` (0-based, file order, `q_(j+1)`), seven numbers at
//! `7 j ..`: the guide point `guides[j].point_mm.{x,y,z}` (mm), the guide
//! direction's two tangent components `guides[j].direction.{t1,t2}`
//! (dimensionless), the link length `guides[j].link_length_mm` and the
//! encoder offset `guides[j].encoder_offset_mm` (mm). Then per leg `i`,
//! at `42 + 3 i ..`, the platform node `legs[i].node_mm.{x,y,z}` (mm).
//!
//! The direction is `u_j = (u0_j + t1 T1_j + t2 T2_j) / |...|`: `u0_j` the
//! nominal (unit) direction and `T1_j`, `T2_j` an orthonormal basis of the
//! plane perpendicular to it (`T1_j` along the coordinate axis least
//! aligned with `u0_j`, projected; `T2_j = u0_j x T1_j`). So `(t1, t2) = 0`
//! is the nominal direction, `t1` is the tangent of the tilt towards `T1_j`,
//! and the map back from a direction is exact ([`ParameterMap::vector`]).
//!
//! Each parameter has a scale ([`ParameterMap::scales`]): 1 mm for the
//! lengths, `1 mm / l_j` for a direction's components (the tilt that moves
//! the far end of the link by 1 mm), so that the scaled identification
//! Jacobian compares parameters by the millimetres they move.

use nalgebra::Vector3;
use parasils_kin::{Error as KinError, ParallelGeometry};

/// The number of identification parameters: 7 per actuator, 3 per leg.
pub const PARAMETERS: usize = 51;

/// Parameters per actuator.
pub const PER_GUIDE: usize = 7;

/// The index of the first node parameter.
pub const NODES_START: usize = 6 * PER_GUIDE;

/// One identification parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// A coordinate (`axis` 0, 1, 2: x, y, z) of the point `G_j` of guide
    /// `guide`, mm.
    GuidePoint {
        /// 0 to 5.
        guide: usize,
        /// 0 to 2.
        axis: usize,
    },
    /// A tangent component (`tangent` 0 or 1: `t1`, `t2`) of guide `guide`'s
    /// direction, dimensionless.
    GuideDirection {
        /// 0 to 5.
        guide: usize,
        /// 0 or 1.
        tangent: usize,
    },
    /// The link length `l_j`, mm.
    LinkLength {
        /// 0 to 5.
        guide: usize,
    },
    /// The encoder offset `o_j`, mm.
    EncoderOffset {
        /// 0 to 5.
        guide: usize,
    },
    /// A coordinate of leg `leg`'s node `a_i`, mm, platform frame.
    Node {
        /// 0 to 2.
        leg: usize,
        /// 0 to 2.
        axis: usize,
    },
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Parameter {
    /// The parameter at `index` of the vector, `None` beyond [`PARAMETERS`].
    pub fn from_index(index: usize) -> Option<Self> {
        if index < NODES_START {
            let (guide, k) = (index / PER_GUIDE, index % PER_GUIDE);
            Some(match k {
                0..=2 => Parameter::GuidePoint { guide, axis: k },
                3 | 4 => Parameter::GuideDirection {
                    guide,
                    tangent: k - 3,
                },
                5 => Parameter::LinkLength { guide },
                _ => Parameter::EncoderOffset { guide },
            })
        } else if index < PARAMETERS {
            let k = index - NODES_START;
            Some(Parameter::Node {
                leg: k / 3,
                axis: k % 3,
            })
        } else {
            None
        }
    }

    /// Its index in the vector.
    pub fn index(self) -> usize {
        match self {
            Parameter::GuidePoint { guide, axis } => PER_GUIDE * guide + axis,
            Parameter::GuideDirection { guide, tangent } => PER_GUIDE * guide + 3 + tangent,
            Parameter::LinkLength { guide } => PER_GUIDE * guide + 5,
            Parameter::EncoderOffset { guide } => PER_GUIDE * guide + 6,
            Parameter::Node { leg, axis } => NODES_START + 3 * leg + axis,
        }
    }

    /// Its name in the robot file's vocabulary: `guides[2].point_mm.y`,
    /// `guides[0].direction.t1`, `guides[5].link_length_mm`,
    /// `guides[4].encoder_offset_mm`, `legs[0].node_mm.z`.
    pub fn name(self) -> String {
        let axis = |a: usize| AXES.get(a).copied().unwrap_or("?");
        match self {
            Parameter::GuidePoint { guide, axis: a } => {
                format!("guides[{guide}].point_mm.{}", axis(a))
            }
            Parameter::GuideDirection { guide, tangent } => {
                format!("guides[{guide}].direction.t{}", tangent + 1)
            }
            Parameter::LinkLength { guide } => format!("guides[{guide}].link_length_mm"),
            Parameter::EncoderOffset { guide } => format!("guides[{guide}].encoder_offset_mm"),
            Parameter::Node { leg, axis: a } => format!("legs[{leg}].node_mm.{}", axis(a)),
        }
    }

    /// The parameter of a name as [`Parameter::name`] writes it.
    pub fn from_name(name: &str) -> Option<Self> {
        (0..PARAMETERS)
            .filter_map(Parameter::from_index)
            .find(|p| p.name() == name)
    }

    /// `"mm"` or `"1"` (a direction's components).
    pub fn unit(self) -> &'static str {
        match self {
            Parameter::GuideDirection { .. } => "1",
            _ => "mm",
        }
    }
}

/// Every parameter's name, in vector order.
pub fn names() -> Vec<String> {
    (0..PARAMETERS)
        .filter_map(Parameter::from_index)
        .map(Parameter::name)
        .collect()
}

/// The map between parameter vectors and geometries around a nominal one.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterMap {
    nominal: ParallelGeometry<f64>,
    tangents: [[Vector3<f64>; 2]; 6],
}

/// The basis `T1`, `T2` of the plane perpendicular to the unit `u`.
fn tangent_basis(u: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let mut axis = 0;
    for k in 1..3 {
        if u[k].abs() < u[axis].abs() {
            axis = k;
        }
    }
    let mut a = Vector3::zeros();
    a[axis] = 1.0;
    let t1 = (a - u * u.dot(&a)).normalize();
    let t2 = u.cross(&t1);
    [t1, t2]
}

impl ParameterMap {
    /// The map around `nominal` (validated; its directions are normalised).
    pub fn new(nominal: &ParallelGeometry<f64>) -> Result<Self, KinError> {
        nominal.validate()?;
        let mut nominal = *nominal;
        for g in nominal.guides.iter_mut() {
            g.direction /= g.direction.norm();
        }
        let tangents = nominal.guides.map(|g| tangent_basis(&g.direction));
        Ok(Self { nominal, tangents })
    }

    /// The nominal geometry (directions normalised).
    pub fn nominal(&self) -> &ParallelGeometry<f64> {
        &self.nominal
    }

    /// `T1_j`, `T2_j` of guide `j`.
    pub fn tangents(&self) -> &[[Vector3<f64>; 2]; 6] {
        &self.tangents
    }

    /// The nominal geometry's vector.
    pub fn nominal_vector(&self) -> [f64; PARAMETERS] {
        self.vector(&self.nominal).unwrap_or([0.0; PARAMETERS])
    }

    /// The vector of a geometry, `None` when a guide direction is at 90 deg
    /// or more from its nominal one (no tangent components reach it).
    pub fn vector(&self, g: &ParallelGeometry<f64>) -> Option<[f64; PARAMETERS]> {
        let mut x = [0.0; PARAMETERS];
        for (j, (guide, nominal)) in g.guides.iter().zip(&self.nominal.guides).enumerate() {
            let b = PER_GUIDE * j;
            let along = guide.direction.dot(&nominal.direction);
            if !(along > 0.0) {
                return None;
            }
            x[b..b + 3].copy_from_slice(guide.point.as_slice());
            x[b + 3] = guide.direction.dot(&self.tangents[j][0]) / along;
            x[b + 4] = guide.direction.dot(&self.tangents[j][1]) / along;
            x[b + 5] = guide.link_length;
            x[b + 6] = guide.encoder_offset;
        }
        for (i, a) in g.nodes.iter().enumerate() {
            x[NODES_START + 3 * i..NODES_START + 3 * i + 3].copy_from_slice(a.as_slice());
        }
        Some(x)
    }

    /// The unnormalised direction `u0 + t1 T1 + t2 T2` of guide `j` at `x`.
    pub fn raw_direction(&self, x: &[f64; PARAMETERS], j: usize) -> Vector3<f64> {
        let b = PER_GUIDE * j;
        self.nominal.guides[j].direction
            + self.tangents[j][0] * x[b + 3]
            + self.tangents[j][1] * x[b + 4]
    }

    /// The geometry of `x`: the nominal one (branches, strokes, thresholds)
    /// with the vector's guides and nodes, directions normalised. Not
    /// validated.
    pub fn geometry(&self, x: &[f64; PARAMETERS]) -> ParallelGeometry<f64> {
        let mut g = self.nominal;
        for j in 0..6 {
            let b = PER_GUIDE * j;
            let guide = &mut g.guides[j];
            guide.point = Vector3::new(x[b], x[b + 1], x[b + 2]);
            guide.direction = self.raw_direction(x, j).normalize();
            guide.link_length = x[b + 5];
            guide.encoder_offset = x[b + 6];
        }
        for i in 0..3 {
            let b = NODES_START + 3 * i;
            g.nodes[i] = Vector3::new(x[b], x[b + 1], x[b + 2]);
        }
        g
    }

    /// Each parameter's scale: 1 mm for lengths, `1 mm / l_j` (nominal link)
    /// for guide `j`'s direction components.
    pub fn scales(&self) -> [f64; PARAMETERS] {
        core::array::from_fn(|k| match Parameter::from_index(k) {
            Some(Parameter::GuideDirection { guide, .. }) => {
                1.0 / self.nominal.guides[guide].link_length
            }
            _ => 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_indices_round_trip() {
        let names = names();
        assert_eq!(names.len(), PARAMETERS);
        assert_eq!(names[0], "guides[0].point_mm.x");
        assert_eq!(names[7 * 2 + 1], "guides[2].point_mm.y");
        assert_eq!(names[3], "guides[0].direction.t1");
        assert_eq!(names[7 * 4 + 6], "guides[4].encoder_offset_mm");
        assert_eq!(names[42 + 2], "legs[0].node_mm.z");
        for (k, name) in names.iter().enumerate() {
            let p = Parameter::from_name(name).expect("known name");
            assert_eq!(p.index(), k);
            assert_eq!(Parameter::from_index(k), Some(p));
        }
        assert_eq!(Parameter::from_index(PARAMETERS), None);
        assert_eq!(Parameter::from_name("guides[6].link_length_mm"), None);
    }

    #[test]
    fn geometry_and_vector_are_inverse() {
        let map = ParameterMap::new(&ParallelGeometry::assumed()).expect("valid");
        let mut x = map.nominal_vector();
        // The nominal directions are (0, 0, -1): T1 = x, T2 = u0 x T1 = -y.
        assert_eq!(map.tangents()[0][0], Vector3::new(1.0, 0.0, 0.0));
        assert_eq!(map.tangents()[0][1], Vector3::new(0.0, -1.0, 0.0));
        for (k, v) in x.iter_mut().enumerate() {
            *v += 0.01 * (k as f64 + 1.0).sin();
        }
        let g = map.geometry(&x);
        let back = map.vector(&g).expect("within 90 deg");
        for k in 0..PARAMETERS {
            assert!((back[k] - x[k]).abs() < 1e-13, "{k}: {} {}", back[k], x[k]);
        }
        // t1 = tan(tilt): 0.01 tilts by atan(0.01) towards +x.
        let mut y = map.nominal_vector();
        y[3] = 0.01;
        let u = map.geometry(&y).guides[0].direction;
        assert!((u.x.atan2(-u.z) - 0.01f64.atan()).abs() < 1e-15);
    }
}
