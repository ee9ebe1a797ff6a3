//! One perturbed robot: the deviations of sample `i`, drawn from a
//! counter-based generator, and the geometry they give.
//!
//! The deviations of sample `i` for family `f` come from a SplitMix64
//! stream whose seed is a hash of `(seed, i, f)` alone: any chunking of the
//! samples, any number of threads or workers and any order give the same
//! robots bit for bit, and adding or removing a family leaves the others'
//! draws unchanged.
//!
//! Module 1's deviations live in the calibration's parameter vector
//! ([`parasils_calib::params`]): the guide points, the two tangent
//! components of each guide direction, the link lengths, the encoder
//! offsets and the nodes, so that a tolerance study and a calibration speak
//! of the same 51 numbers. A tilt by `a` towards the azimuth `w` of the
//! plane perpendicular to the nominal direction is the tangent pair
//! `tan(a) (cos w, sin w)`.
//!
//! ```
//! use parasils_tolerance::{Perturbation, Spec};
//!
//! let spec = Spec::default();
//! let a = Perturbation::draw(&spec, 7, 1_000_000);
//! // The same seed and sample: the same robot, whatever was drawn before.
//! let _ = Perturbation::draw(&spec, 7, 3);
//! assert_eq!(Perturbation::draw(&spec, 7, 1_000_000), a);
//! assert_ne!(Perturbation::draw(&spec, 8, 1_000_000), a);
//! ```

use nalgebra::Vector3;
use parasils_calib::params::{NODES_START, PER_GUIDE};
use parasils_calib::{PARAMETERS, ParameterMap};
use parasils_io::Rng;
use parasils_kin::RobotGeometry;

use crate::spec::{Distribution, Family, Spec};

/// The number of coordinates of a perturbation: module 1's 51 parameters,
/// then per instrument module (left, right) `alpha`, `beta` (rad) and the
/// port's x, y, z (mm).
pub const COORDINATES: usize = PARAMETERS + 10;

/// The deviations of one instrument module.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InstrumentDeviation {
    /// Added to `alpha`, rad.
    pub alpha_rad: f64,
    /// Added to `beta`, rad.
    pub beta_rad: f64,
    /// Added to the port, mm, platform frame.
    pub rcm_mm: [f64; 3],
}

/// The deviations of one perturbed robot from the nominal one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Perturbation {
    /// Added to module 1's nominal parameter vector
    /// ([`ParameterMap::nominal_vector`]).
    pub module1: [f64; PARAMETERS],
    /// The left module's.
    pub left: InstrumentDeviation,
    /// The right module's.
    pub right: InstrumentDeviation,
}

/// SplitMix64's output function: a bijective mix of 64 bits.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The stream of family `family` of sample `sample`.
fn stream(seed: u64, sample: u64, family: Family) -> Rng {
    let a = mix(seed.wrapping_add(0x9E37_79B9_7F4A_7C15));
    let b = mix(a ^ sample.wrapping_mul(0xD1B5_4A32_D192_ED03));
    let c = mix(b ^ (family.index() as u64 + 1).wrapping_mul(0x8CB9_2BA7_2F3D_8DD7));
    Rng::new(c)
}

/// One deviation: a standard normal and a uniform variate are both drawn
/// (so that the stream's position does not depend on the distribution),
/// and the distribution reads the one it uses.
fn draw(rng: &mut Rng, d: Distribution) -> f64 {
    let normal = rng.normal();
    let unit = rng.unit();
    d.deviation(normal, unit)
}

impl Perturbation {
    /// No deviation at all.
    pub fn zero() -> Self {
        Self {
            module1: [0.0; PARAMETERS],
            left: InstrumentDeviation::default(),
            right: InstrumentDeviation::default(),
        }
    }

    /// The deviations of sample `sample` under `spec` with `seed`.
    pub fn draw(spec: &Spec, seed: u64, sample: u64) -> Self {
        let mut p = Self::zero();
        for (family, d) in spec.iter() {
            let mut rng = stream(seed, sample, family);
            match family {
                Family::GuidePoint => {
                    for j in 0..6 {
                        for axis in 0..3 {
                            p.module1[PER_GUIDE * j + axis] = draw(&mut rng, d);
                        }
                    }
                }
                Family::GuideDirection => {
                    for j in 0..6 {
                        let tilt = draw(&mut rng, d).to_radians();
                        let azimuth = core::f64::consts::TAU * rng.unit();
                        let t = tilt.tan();
                        p.module1[PER_GUIDE * j + 3] = t * azimuth.cos();
                        p.module1[PER_GUIDE * j + 4] = t * azimuth.sin();
                    }
                }
                Family::LinkLength => {
                    for j in 0..6 {
                        p.module1[PER_GUIDE * j + 5] = draw(&mut rng, d);
                    }
                }
                Family::EncoderOffset => {
                    for j in 0..6 {
                        p.module1[PER_GUIDE * j + 6] = draw(&mut rng, d);
                    }
                }
                Family::LegNode => {
                    for k in 0..9 {
                        p.module1[NODES_START + k] = draw(&mut rng, d);
                    }
                }
                Family::Alpha => {
                    p.left.alpha_rad = draw(&mut rng, d).to_radians();
                    p.right.alpha_rad = draw(&mut rng, d).to_radians();
                }
                Family::Beta => {
                    p.left.beta_rad = draw(&mut rng, d).to_radians();
                    p.right.beta_rad = draw(&mut rng, d).to_radians();
                }
                Family::Rcm => {
                    for side in [&mut p.left, &mut p.right] {
                        for axis in 0..3 {
                            side.rcm_mm[axis] = draw(&mut rng, d);
                        }
                    }
                }
            }
        }
        p
    }

    /// The deviations as one vector of [`COORDINATES`] numbers (module 1's
    /// parameters, then the left and the right module's `alpha`, `beta`,
    /// port): the variables of the first-order model.
    pub fn coordinates(&self) -> [f64; COORDINATES] {
        let mut z = [0.0; COORDINATES];
        z[..PARAMETERS].copy_from_slice(&self.module1);
        for (k, side) in [&self.left, &self.right].into_iter().enumerate() {
            let b = PARAMETERS + 5 * k;
            z[b] = side.alpha_rad;
            z[b + 1] = side.beta_rad;
            z[b + 2..b + 5].copy_from_slice(&side.rcm_mm);
        }
        z
    }

    /// The perturbed robot: `nominal` with these deviations. `map` is the
    /// parameter map around `nominal.module1`. Not validated.
    pub fn apply(&self, map: &ParameterMap, nominal: &RobotGeometry<f64>) -> RobotGeometry<f64> {
        let mut x = map.nominal_vector();
        for (v, d) in x.iter_mut().zip(&self.module1) {
            *v += d;
        }
        let mut robot = *nominal;
        robot.module1 = map.geometry(&x);
        for (g, d) in [
            (&mut robot.left, &self.left),
            (&mut robot.right, &self.right),
        ] {
            g.alpha += d.alpha_rad;
            g.beta += d.beta_rad;
            g.rcm += Vector3::from(d.rcm_mm);
        }
        robot
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_draws_have_the_specified_spread() {
        // 4000 robots: every guide point coordinate N(0, 0.05^2), every
        // encoder offset U(-0.01, 0.01), every tilt of 0.02 deg.
        let spec = Spec::default();
        let n = 4000;
        let (mut s2, mut umax, mut u2, mut tilt2) = (0.0, 0.0f64, 0.0, 0.0);
        for i in 0..n {
            let p = Perturbation::draw(&spec, 11, i);
            for j in 0..6 {
                for axis in 0..3 {
                    s2 += p.module1[PER_GUIDE * j + axis].powi(2);
                }
                let o = p.module1[PER_GUIDE * j + 6];
                umax = umax.max(o.abs());
                u2 += o * o;
                let t = p.module1[PER_GUIDE * j + 3].hypot(p.module1[PER_GUIDE * j + 4]);
                tilt2 += t.atan().to_degrees().powi(2);
            }
        }
        let sigma = (s2 / (18.0 * n as f64)).sqrt();
        // 72,000 draws: the sample sigma's relative standard error is 0.26%.
        assert!((sigma / 0.05 - 1.0).abs() < 0.01, "{sigma}");
        assert!(umax <= 0.01 && umax > 0.0099, "{umax}");
        let u_sd = (u2 / (6.0 * n as f64)).sqrt();
        assert!((u_sd / (0.01 / 3f64.sqrt()) - 1.0).abs() < 0.02, "{u_sd}");
        let tilt_sd = (tilt2 / (6.0 * n as f64)).sqrt();
        assert!((tilt_sd / 0.02 - 1.0).abs() < 0.02, "{tilt_sd}");
    }

    #[test]
    fn families_draw_from_their_own_streams() {
        let full = Spec::default();
        let only = Spec::none().with(Family::LegNode, full.get(Family::LegNode));
        let a = Perturbation::draw(&full, 3, 42);
        let b = Perturbation::draw(&only, 3, 42);
        assert_eq!(a.module1[NODES_START..], b.module1[NODES_START..]);
        assert!(b.module1[..NODES_START].iter().all(|&v| v == 0.0));
        assert_eq!(b.left, InstrumentDeviation::default());
    }
}
