//! The parameters of one spherical instrument module.

use nalgebra::Vector3;

use super::types::{JointLimits, Thresholds};
use crate::error::{Error, check_finite};
use crate::presets;
use crate::real::{Real, deg};
use crate::side::Side;

/// The parameters of one spherical instrument module.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct InstrumentGeometry<T: Real> {
    /// Left or right (the right is the mirror image of the left).
    pub side: Side,
    /// `alpha`, the tilt of the first joint axis, rad (paper: 10 deg).
    pub alpha: T,
    /// `beta`, the angle between the tool and the second joint's plane, rad
    /// (paper: 10 deg). Must be in `[0, 90) deg`.
    pub beta: T,
    /// `R`, the radius of the spherical linkage, mm (paper: 110 mm). Used for
    /// drawing and collision checks; the tip does not depend on it.
    pub radius: T,
    /// The RCM (the port) in the platform frame, mm (paper: `(-10, 0, 0)` left,
    /// `(10, 0, 0)` right).
    pub rcm: Vector3<T>,
    /// Joint limits.
    pub limits: JointLimits<T>,
    /// Error thresholds.
    pub thresholds: Thresholds<T>,
}

impl<T: Real> InstrumentGeometry<T> {
    /// The paper's module: `alpha = beta = 10 deg`, `R = 110 mm`, port at
    /// `(-10, 0, 0)` mm (left) or `(10, 0, 0)` mm (right), the default
    /// (assumed) limits and thresholds.
    pub fn paper(side: Side) -> Self {
        let [x, y, z] = presets::LEFT_RCM_MM;
        let x = match side {
            Side::Left => x,
            Side::Right => -x,
        };
        Self {
            side,
            alpha: deg(presets::INSTRUMENT_ALPHA_DEG),
            beta: deg(presets::INSTRUMENT_BETA_DEG),
            radius: T::lit(presets::INSTRUMENT_RADIUS_MM),
            rcm: Vector3::new(T::lit(x), T::lit(y), T::lit(z)),
            limits: JointLimits::default(),
            thresholds: Thresholds::default(),
        }
    }

    /// Checks the parameters: all finite (limits may be infinite), `beta` in
    /// `[0, 90) deg`, `R > 0`, each limit `min <= max`, thresholds positive,
    /// and `qs3_min |cos qs2|_min cos(beta)` with a finite inverse.
    pub fn validate(&self) -> Result<(), Error> {
        let invalid = |what, value: T| Error::InvalidParameter {
            what,
            value: value.to_f64(),
        };
        check_finite(self.alpha, "instrument.alpha")?;
        check_finite(self.beta, "instrument.beta")?;
        check_finite(self.radius, "instrument.radius")?;
        check_finite(self.rcm.x, "instrument.rcm.x")?;
        check_finite(self.rcm.y, "instrument.rcm.y")?;
        check_finite(self.rcm.z, "instrument.rcm.z")?;
        if !(self.beta >= T::zero() && self.beta < T::frac_pi_2()) {
            return Err(invalid("instrument.beta", self.beta));
        }
        if !(self.radius > T::zero()) {
            return Err(invalid("instrument.radius", self.radius));
        }
        for (what, r) in [
            ("instrument.limits.qs1", &self.limits.qs1),
            ("instrument.limits.qs2", &self.limits.qs2),
            ("instrument.limits.qs3", &self.limits.qs3),
        ] {
            if !(r.min <= r.max) {
                return Err(invalid(what, r.min));
            }
        }
        for (what, t) in [
            ("instrument.thresholds.reach", self.thresholds.reach),
            ("instrument.thresholds.cos_qs2", self.thresholds.cos_qs2),
            ("instrument.thresholds.qs3", self.thresholds.qs3),
        ] {
            if !(t > T::zero() && t.finite()) {
                return Err(invalid(what, t));
            }
        }
        // The Jacobian's inverse and the rates divide by
        // `qs3 cos(qs2) cos(beta)`, which the two singularity thresholds bound
        // from below: that bound must keep a finite inverse, with room for
        // rounding (thresholds near the float type's smallest numbers would
        // not).
        let floor = self.thresholds.qs3 * self.thresholds.cos_qs2 * self.beta.cos();
        if !(T::lit(4.0) / floor).finite() {
            return Err(invalid(
                "instrument.thresholds.cos_qs2",
                self.thresholds.cos_qs2,
            ));
        }
        Ok(())
    }
}
