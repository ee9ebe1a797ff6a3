//! The endoscope: a straight scope through its own port at the platform's
//! origin `P`, inserted along the platform's `-Z'` axis.
//!
//! Its state is one number, the insertion depth (mm, 0 at the port, positive
//! inwards): the tip is at `P + R (0, 0, -depth)` in the fixed frame, so it
//! turns with the platform during a reorientation (motion type 4) and moves
//! on a straight line through the port during an insertion (motion type 2).
//! See `docs/model.md`, *The endoscope*.
//!
//! ```
//! use parasils_kin::{EndoscopeGeometry, PlatformState, Pose};
//!
//! let endoscope = EndoscopeGeometry::<f64>::paper();
//! let frame = PlatformState::at_rest(Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, 0.0)).frame()?;
//! let tip = endoscope.tip(&frame, 60.0)?;
//! assert_eq!(tip.z, -560.0);
//! assert!(endoscope.tip(&frame, 300.0).is_err()); // beyond the assumed 250 mm
//! # Ok::<(), parasils_kin::Error>(())
//! ```

use nalgebra::Vector3;

use crate::camera::{Camera, CameraError};
use crate::error::Error;
use crate::frame::PlatformFrame;
use crate::interval::Interval;
use crate::presets;
use crate::real::Real;

/// The endoscope's parameters: the range of its insertion depth.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EndoscopeGeometry<T> {
    /// The insertion depth's range, mm (default **assumed** `[0, 250]`).
    pub depth: Interval<T>,
    /// The camera at its tip (default [`Camera::assumed`]).
    pub camera: Camera<T>,
}

impl<T: Real> EndoscopeGeometry<T> {
    /// The default endoscope: depth in `[0, 250]` mm (assumed, see
    /// [`presets::ENDOSCOPE_DEPTH_MM`]).
    pub fn paper() -> Self {
        let [min, max] = presets::ENDOSCOPE_DEPTH_MM;
        Self {
            depth: Interval::new(T::lit(min), T::lit(max)),
            camera: Camera::assumed(),
        }
    }

    /// [`Error::InvalidParameter`] `"endoscope.depth"` unless the range's
    /// bounds are finite and `min <= max`, `"camera.*"` for an invalid
    /// camera (see [`Camera::validate`]).
    pub fn validate(&self) -> Result<(), Error> {
        let Interval { min, max } = self.depth;
        for v in [min, max] {
            if !v.finite() {
                return Err(Error::InvalidParameter {
                    what: "endoscope.depth",
                    value: v.to_f64(),
                });
            }
        }
        if !(min <= max) {
            return Err(Error::InvalidParameter {
                what: "endoscope.depth",
                value: min.to_f64(),
            });
        }
        match self.camera.validate() {
            Err(CameraError::InvalidParameter { what, value, .. }) => {
                Err(Error::InvalidParameter {
                    what: match what {
                        "horizontal_fov" => "camera.horizontal_fov",
                        "aspect_ratio" => "camera.aspect_ratio",
                        "oblique" => "camera.oblique",
                        _ => "camera.oblique_direction",
                    },
                    value,
                })
            }
            _ => Ok(()),
        }
    }

    /// [`Error::EndoscopeDepth`] when `depth` (mm) is outside its range,
    /// [`Error::NonFinite`] when it is not a number.
    pub fn check(&self, depth: T) -> Result<(), Error> {
        if !depth.finite() {
            return Err(Error::NonFinite {
                what: "endoscope depth",
                value: depth.to_f64(),
            });
        }
        if depth < self.depth.min || depth > self.depth.max {
            return Err(Error::EndoscopeDepth {
                value: depth.to_f64(),
                min: self.depth.min.to_f64(),
                max: self.depth.max.to_f64(),
            });
        }
        Ok(())
    }

    /// The tip at insertion `depth` (mm), fixed frame: `P + R (0, 0, -depth)`,
    /// the depth checked first ([`EndoscopeGeometry::check`]).
    pub fn tip(&self, frame: &PlatformFrame<T>, depth: T) -> Result<Vector3<T>, Error> {
        self.check(depth)?;
        Ok(frame.to_fixed(&Vector3::new(T::zero(), T::zero(), -depth)))
    }
}
