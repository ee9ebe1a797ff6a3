//! The robot file's `[dynamics]` and `[stiffness]` tables: the platform as
//! one rigid body (its mass, centre of mass and inertia, and gravity) and
//! each actuator's stiffness, both **assumed** (the paper gives neither).
//!
//! ```toml
//! [dynamics] # the platform with its modules as one rigid body (ASSUMED)
//! platform_mass_kg = 6.0
//! platform_com_mm = [0.0, 0.0, 120.0]
//! platform_inertia_kg_mm2 = [[53750.0, 0.0, 0.0], [0.0, 53750.0, 0.0], [0.0, 0.0, 67500.0]]
//! gravity_mm_s2 = [0.0, 0.0, -9810.0]
//!
//! [stiffness] # each actuator as a spring (ASSUMED)
//! slider_n_mm = [200.0, 200.0, 200.0, 200.0, 200.0, 200.0]
//! left_qs1_nmm_rad = 200000.0
//! ```

use nalgebra::{Matrix3, Vector3};
use parasils::kin::{ActuatorStiffness, Payload};
use serde::{Deserialize, Deserializer, Serialize};

/// `[dynamics]`: the platform with the modules it carries as one rigid
/// body. Every key is required but `gravity_mm_s2` (standard gravity along
/// `-Z` when missing); a mass of 0 is pure statics (no weight, no inertia).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsFile {
    /// The mass, kg (at least 0).
    #[serde(deserialize_with = "non_negative")]
    pub platform_mass_kg: f64,
    /// The centre of mass, mm, platform frame.
    #[serde(deserialize_with = "finite3")]
    pub platform_com_mm: [f64; 3],
    /// The inertia tensor about the centre of mass, kg mm^2, platform axes,
    /// row by row: symmetric, positive semi-definite, its principal moments
    /// meeting the triangle inequality (checked on loading).
    #[serde(deserialize_with = "finite3x3")]
    pub platform_inertia_kg_mm2: [[f64; 3]; 3],
    /// The acceleration of gravity, mm/s^2, fixed frame (default
    /// `[0, 0, -9810]`).
    #[serde(default = "standard_gravity", deserialize_with = "finite3")]
    pub gravity_mm_s2: [f64; 3],
}

fn standard_gravity() -> [f64; 3] {
    [0.0, 0.0, -Payload::<f64>::STANDARD_GRAVITY_MM_S2]
}

impl DynamicsFile {
    /// The file's table of `payload`.
    pub fn from_payload(payload: &Payload<f64>) -> Self {
        let i = &payload.inertia;
        Self {
            platform_mass_kg: payload.mass,
            platform_com_mm: payload.com.into(),
            platform_inertia_kg_mm2: core::array::from_fn(|r| core::array::from_fn(|c| i[(r, c)])),
            gravity_mm_s2: payload.gravity.into(),
        }
    }

    /// The body the table gives.
    pub fn to_payload(&self) -> Payload<f64> {
        let i = &self.platform_inertia_kg_mm2;
        Payload {
            mass: self.platform_mass_kg,
            com: Vector3::from(self.platform_com_mm),
            gravity: Vector3::from(self.gravity_mm_s2),
            inertia: Matrix3::from_fn(|r, c| i[r][c]),
        }
    }

    /// What is wrong with the inertia tensor, if anything: the key's
    /// message and the offending value (an off-diagonal mismatch or a
    /// principal moment).
    pub(super) fn inertia_problem(&self) -> Option<(&'static str, f64)> {
        let i = Matrix3::from_fn(|r, c| self.platform_inertia_kg_mm2[r][c]);
        let scale = i.abs().max().max(f64::MIN_POSITIVE);
        let tol = 1e-9 * scale;
        for (r, c) in [(0, 1), (0, 2), (1, 2)] {
            let gap = i[(r, c)] - i[(c, r)];
            if gap.abs() > tol {
                return Some((
                    "dynamics.platform_inertia_kg_mm2 (not symmetric: [r][c] - [c][r])",
                    gap,
                ));
            }
        }
        let moments = i.symmetric_eigenvalues();
        if let Some(m) = moments.iter().find(|m| **m < -tol) {
            return Some((
                "dynamics.platform_inertia_kg_mm2 (a negative principal moment)",
                *m,
            ));
        }
        let [a, b, c] = [moments[0], moments[1], moments[2]];
        for (x, y, z) in [(a, b, c), (b, c, a), (c, a, b)] {
            if x + y < z - tol {
                return Some((
                    "dynamics.platform_inertia_kg_mm2 (a principal moment above the sum of the other two)",
                    z,
                ));
            }
        }
        None
    }
}

/// `[stiffness]`: each actuator as a spring. Every key is optional; the
/// defaults are **assumed** ([`ActuatorStiffness::assumed`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StiffnessFile {
    /// The sliders `q1` to `q6` along their guides, N/mm (assumed 200).
    #[serde(deserialize_with = "positive6")]
    pub slider_n_mm: [f64; 6],
    /// The left module's `qs1`, N mm/rad (assumed 2e5).
    #[serde(deserialize_with = "positive")]
    pub left_qs1_nmm_rad: f64,
    /// The left module's `qs2`, N mm/rad (assumed 2e5).
    #[serde(deserialize_with = "positive")]
    pub left_qs2_nmm_rad: f64,
    /// The left module's `qs3` along the shaft, N/mm (assumed 50).
    #[serde(deserialize_with = "positive")]
    pub left_qs3_n_mm: f64,
    /// The right module's `qs1`, N mm/rad (assumed 2e5).
    #[serde(deserialize_with = "positive")]
    pub right_qs1_nmm_rad: f64,
    /// The right module's `qs2`, N mm/rad (assumed 2e5).
    #[serde(deserialize_with = "positive")]
    pub right_qs2_nmm_rad: f64,
    /// The right module's `qs3` along the shaft, N/mm (assumed 50).
    #[serde(deserialize_with = "positive")]
    pub right_qs3_n_mm: f64,
}

impl Default for StiffnessFile {
    /// The assumed stiffnesses.
    fn default() -> Self {
        Self::from_stiffness(&ActuatorStiffness::assumed())
    }
}

impl StiffnessFile {
    /// The file's table of `stiffness`.
    pub fn from_stiffness(stiffness: &ActuatorStiffness<f64>) -> Self {
        let k = &stiffness.stiffness;
        Self {
            slider_n_mm: [k[0], k[1], k[2], k[3], k[4], k[5]],
            left_qs1_nmm_rad: k[6],
            left_qs2_nmm_rad: k[7],
            left_qs3_n_mm: k[8],
            right_qs1_nmm_rad: k[9],
            right_qs2_nmm_rad: k[10],
            right_qs3_n_mm: k[11],
        }
    }

    /// The stiffnesses the table gives, in [`Actuator::ALL`]'s order.
    ///
    /// [`Actuator::ALL`]: parasils::kin::Actuator::ALL
    pub fn to_stiffness(&self) -> ActuatorStiffness<f64> {
        let s = &self.slider_n_mm;
        ActuatorStiffness {
            stiffness: [
                s[0],
                s[1],
                s[2],
                s[3],
                s[4],
                s[5],
                self.left_qs1_nmm_rad,
                self.left_qs2_nmm_rad,
                self.left_qs3_n_mm,
                self.right_qs1_nmm_rad,
                self.right_qs2_nmm_rad,
                self.right_qs3_n_mm,
            ],
        }
    }
}

fn error<E: serde::de::Error>(expected: &str, got: impl core::fmt::Debug) -> E {
    E::custom(format!("expected {expected}, got {got:?}"))
}

fn non_negative<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let v = f64::deserialize(d)?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(error("a finite number >= 0", v))
    }
}

fn positive<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let v = f64::deserialize(d)?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(error("a finite number > 0", v))
    }
}

fn positive6<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 6], D::Error> {
    let v = <[f64; 6]>::deserialize(d)?;
    if v.iter().all(|x| x.is_finite() && *x > 0.0) {
        Ok(v)
    } else {
        Err(error("six finite numbers > 0", v))
    }
}

fn finite3<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    let v = <[f64; 3]>::deserialize(d)?;
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(error("three finite numbers", v))
    }
}

fn finite3x3<'de, D: Deserializer<'de>>(d: D) -> Result<[[f64; 3]; 3], D::Error> {
    let v = <[[f64; 3]; 3]>::deserialize(d)?;
    if v.iter().flatten().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(error("three rows of three finite numbers", v))
    }
}
