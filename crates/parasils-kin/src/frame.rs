//! Frames: the platform pose, its X-Y-Z Euler rotation, and the rotation's rates.
//!
//! The fixed base frame `OXYZ` belongs to module 1, with `-Z` towards the
//! patient. The platform frame `O'X'Y'Z'` has its origin at `P`, the
//! endoscope's remote centre of motion. A [`Pose`] places the platform:
//!
//! ```text
//! p_fixed = R * p_platform + P,     R = R_X(psi) * R_Y(theta) * R_Z(phi)
//! ```
//!
//! The angles are intrinsic X-Y-Z Euler angles: first `psi` about `X`, then
//! `theta` about the new `Y'`, then `phi` about the new `Z'`. This is **not**
//! nalgebra's `Rotation3::from_euler_angles(roll, pitch, yaw)`, which builds
//! `R_Z(yaw) R_Y(pitch) R_X(roll)`. The order is proven here:
//!
//! ```
//! use nalgebra::{Rotation3, Vector3};
//! use parasils_kin::frame::rotation;
//!
//! let (psi, theta, phi) = (0.3_f64, -0.7, 1.1);
//! let rx = Rotation3::from_axis_angle(&Vector3::x_axis(), psi);
//! let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), theta);
//! let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), phi);
//! let expected = (rx * ry * rz).into_inner();
//! assert!((rotation(psi, theta, phi) - expected).norm() < 1e-15);
//!
//! // nalgebra's own Euler constructor is the reverse order: not the same matrix.
//! let other = Rotation3::from_euler_angles(psi, theta, phi).into_inner();
//! assert!((rotation(psi, theta, phi) - other).norm() > 0.1);
//! ```
//!
//! The rates of the rotation come from the Euler rates. In the platform frame
//! the angular velocity `omega` and acceleration `alpha` satisfy
//! `R^T Rdot = [omega]x` and `R^T Rddot = [alpha]x + [omega]x^2`
//! ([`PlatformFrame`]), which is how every solver of this crate applies
//! `Rdot` and `Rddot` without forming them. See `docs/model.md`, *Frames and
//! conventions* and *The platform pose*.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, check_finite};
use crate::presets;
use crate::real::Real;

/// The platform pose `(X_P, Y_P, Z_P, psi, theta, phi)`.
///
/// Position of `P` in the fixed frame in mm; orientation as intrinsic X-Y-Z
/// Euler angles in rad (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Pose<T> {
    /// `X_P`, mm.
    pub x: T,
    /// `Y_P`, mm.
    pub y: T,
    /// `Z_P`, mm.
    pub z: T,
    /// `psi`, rotation about `X`, rad.
    pub psi: T,
    /// `theta`, rotation about `Y'`, rad.
    pub theta: T,
    /// `phi`, rotation about `Z''`, rad.
    pub phi: T,
}

impl<T: Real> Pose<T> {
    /// A pose from its position (mm) and Euler angles (rad).
    pub const fn new(x: T, y: T, z: T, psi: T, theta: T, phi: T) -> Self {
        Self {
            x,
            y,
            z,
            psi,
            theta,
            phi,
        }
    }

    /// A pose from its position in mm and its Euler angles in **degrees**.
    pub fn from_mm_deg(x: f64, y: f64, z: f64, psi: f64, theta: f64, phi: f64) -> Self {
        Self {
            x: T::lit(x),
            y: T::lit(y),
            z: T::lit(z),
            psi: T::lit(psi.to_radians()),
            theta: T::lit(theta.to_radians()),
            phi: T::lit(phi.to_radians()),
        }
    }

    /// The paper's initial pose `P0 = (15, 20, -500 mm, -15, 10, -60 deg)`
    /// ([`presets::START_POSE_MM_DEG`]; see `docs/model.md`, *Check values*).
    pub fn paper_start() -> Self {
        let [x, y, z, psi, theta, phi] = presets::START_POSE_MM_DEG;
        Self::from_mm_deg(x, y, z, psi, theta, phi)
    }

    /// The position of `P` in the fixed frame, mm.
    pub fn position(&self) -> Vector3<T> {
        Vector3::new(self.x, self.y, self.z)
    }

    /// `R = R_X(psi) R_Y(theta) R_Z(phi)`: platform-frame vectors to fixed-frame vectors.
    pub fn rotation(&self) -> Matrix3<T> {
        rotation(self.psi, self.theta, self.phi)
    }

    /// The six values as an array `[x, y, z, psi, theta, phi]` (mm, rad).
    pub fn to_array(&self) -> [T; 6] {
        [self.x, self.y, self.z, self.psi, self.theta, self.phi]
    }

    /// A pose from `[x, y, z, psi, theta, phi]` (mm, rad).
    pub fn from_array(a: [T; 6]) -> Self {
        Self::new(a[0], a[1], a[2], a[3], a[4], a[5])
    }

    /// The mirror image across the fixed `YZ` plane: `(-X, Y, Z, psi, -theta, -phi)`.
    ///
    /// With `S = diag(-1, 1, 1)`, `S R(psi, theta, phi) S = R(psi, -theta, -phi)`:
    /// the mirrored platform carries the mirror image of everything on it.
    pub fn mirrored(&self) -> Self {
        Self::new(-self.x, self.y, self.z, self.psi, -self.theta, -self.phi)
    }

    /// `Err(Error::NonFinite)` naming the first NaN or infinite component.
    pub fn check_finite(&self) -> Result<(), Error> {
        check_finite(self.x, "pose.x")?;
        check_finite(self.y, "pose.y")?;
        check_finite(self.z, "pose.z")?;
        check_finite(self.psi, "pose.psi")?;
        check_finite(self.theta, "pose.theta")?;
        check_finite(self.phi, "pose.phi")
    }
}

/// A time derivative of a [`Pose`], component by component.
///
/// As a velocity: mm/s and rad/s (the Euler rates, not an angular velocity).
/// As an acceleration: mm/s^2 and rad/s^2.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PoseRate<T> {
    /// Rate of `X_P`.
    pub x: T,
    /// Rate of `Y_P`.
    pub y: T,
    /// Rate of `Z_P`.
    pub z: T,
    /// Rate of `psi`.
    pub psi: T,
    /// Rate of `theta`.
    pub theta: T,
    /// Rate of `phi`.
    pub phi: T,
}

impl<T: Real> PoseRate<T> {
    /// A rate from its six components (mm/s or mm/s^2, rad/s or rad/s^2).
    pub const fn new(x: T, y: T, z: T, psi: T, theta: T, phi: T) -> Self {
        Self {
            x,
            y,
            z,
            psi,
            theta,
            phi,
        }
    }

    /// All zero: a platform at rest.
    pub fn zero() -> Self {
        let z = T::zero();
        Self::new(z, z, z, z, z, z)
    }

    /// A pure reorientation (motion type 4): `P` still, `phi` constant.
    pub fn euler(psi: T, theta: T) -> Self {
        let z = T::zero();
        Self::new(z, z, z, psi, theta, z)
    }

    /// The rate of `P`, mm/s (or mm/s^2).
    pub fn linear(&self) -> Vector3<T> {
        Vector3::new(self.x, self.y, self.z)
    }

    /// The mirror image, as [`Pose::mirrored`]: `(-x, y, z, psi, -theta, -phi)`.
    pub fn mirrored(&self) -> Self {
        Self::new(-self.x, self.y, self.z, self.psi, -self.theta, -self.phi)
    }

    /// `Err(Error::NonFinite)` naming the first NaN or infinite component;
    /// `what` names the quantity ("platform velocity", ...).
    pub fn check_finite(&self, what: &'static [&'static str; 6]) -> Result<(), Error> {
        for (v, name) in [self.x, self.y, self.z, self.psi, self.theta, self.phi]
            .into_iter()
            .zip(what.iter())
        {
            check_finite(v, name)?;
        }
        Ok(())
    }
}

/// The platform's pose with its first and second time derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PlatformState<T> {
    /// The pose (mm, rad).
    pub pose: Pose<T>,
    /// Its rate (mm/s, rad/s).
    pub velocity: PoseRate<T>,
    /// Its second rate (mm/s^2, rad/s^2).
    pub acceleration: PoseRate<T>,
}

impl<T: Real> PlatformState<T> {
    /// A platform at rest at `pose`.
    pub fn at_rest(pose: Pose<T>) -> Self {
        Self {
            pose,
            velocity: PoseRate::zero(),
            acceleration: PoseRate::zero(),
        }
    }

    /// Motion type 4: `P` frozen and `phi` constant, `psi` and `theta` moving
    /// with the given rates (rad/s) and accelerations (rad/s^2).
    pub fn reorientation(pose: Pose<T>, rates: [T; 2], accelerations: [T; 2]) -> Self {
        Self {
            pose,
            velocity: PoseRate::euler(rates[0], rates[1]),
            acceleration: PoseRate::euler(accelerations[0], accelerations[1]),
        }
    }

    /// The mirror image (see [`Pose::mirrored`]).
    pub fn mirrored(&self) -> Self {
        Self {
            pose: self.pose.mirrored(),
            velocity: self.velocity.mirrored(),
            acceleration: self.acceleration.mirrored(),
        }
    }

    /// Evaluates the frame: rotation, angular velocity and acceleration.
    ///
    /// Fails with [`Error::NonFinite`] naming the first NaN or infinite input.
    pub fn frame(&self) -> Result<PlatformFrame<T>, Error> {
        self.pose.check_finite()?;
        self.velocity.check_finite(&[
            "velocity.x",
            "velocity.y",
            "velocity.z",
            "velocity.psi",
            "velocity.theta",
            "velocity.phi",
        ])?;
        self.acceleration.check_finite(&[
            "acceleration.x",
            "acceleration.y",
            "acceleration.z",
            "acceleration.psi",
            "acceleration.theta",
            "acceleration.phi",
        ])?;
        Ok(PlatformFrame::new(self))
    }
}

/// The platform frame evaluated at one instant: what every solver needs of
/// the platform, computed once per control cycle and shared.
///
/// `omega` and `alpha` are the angular velocity (rad/s) and acceleration
/// (rad/s^2) in **platform** coordinates, so that for a point `c` fixed on the
/// platform (mm, platform frame):
///
/// ```text
/// R^T Rdot  c = omega x c
/// R^T Rddot c = alpha x c + omega x (omega x c)
/// ```
///
/// For `R = R_X(psi) R_Y(theta) R_Z(phi)`:
///
/// ```text
/// omega = ( c(theta) c(phi) psi' + s(phi) theta',
///          -c(theta) s(phi) psi' + c(phi) theta',
///           s(theta) psi' + phi' )
/// alpha = d omega / dt
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlatformFrame<T: Real> {
    /// `R`, platform to fixed.
    pub rotation: Matrix3<T>,
    /// `P`, mm, fixed frame.
    pub position: Vector3<T>,
    /// `Pdot`, mm/s, fixed frame.
    pub velocity: Vector3<T>,
    /// `Pddot`, mm/s^2, fixed frame.
    pub acceleration: Vector3<T>,
    /// Angular velocity, rad/s, platform frame.
    pub omega: Vector3<T>,
    /// Angular acceleration, rad/s^2, platform frame.
    pub alpha: Vector3<T>,
}

impl<T: Real> PlatformFrame<T> {
    /// Evaluates the frame of `state` (no finiteness check: see [`PlatformState::frame`]).
    pub fn new(state: &PlatformState<T>) -> Self {
        let p = &state.pose;
        let (v, a) = (&state.velocity, &state.acceleration);
        let (s1, c1) = p.psi.sincos();
        let (s2, c2) = p.theta.sincos();
        let (s3, c3) = p.phi.sincos();
        let rotation = rotation_from_sin_cos(s1, c1, s2, c2, s3, c3);
        let omega = Vector3::new(
            c2 * c3 * v.psi + s3 * v.theta,
            -c2 * s3 * v.psi + c3 * v.theta,
            s2 * v.psi + v.phi,
        );
        let alpha = Vector3::new(
            c2 * c3 * a.psi + s3 * a.theta - v.psi * (s2 * c3 * v.theta + c2 * s3 * v.phi)
                + c3 * v.phi * v.theta,
            -c2 * s3 * a.psi + c3 * a.theta + v.psi * (s2 * s3 * v.theta - c2 * c3 * v.phi)
                - s3 * v.phi * v.theta,
            s2 * a.psi + c2 * v.theta * v.psi + a.phi,
        );
        Self {
            rotation,
            position: p.position(),
            velocity: v.linear(),
            acceleration: a.linear(),
            omega,
            alpha,
        }
    }

    /// The frame of the platform at rest at `pose` (no finiteness check):
    /// the rotation and position of [`PlatformFrame::new`] for a
    /// [`PlatformState::at_rest`], bit for bit, with every rate and
    /// acceleration zero, without evaluating the rate formulas.
    pub fn at_rest(pose: &Pose<T>) -> Self {
        let (s1, c1) = pose.psi.sincos();
        let (s2, c2) = pose.theta.sincos();
        let (s3, c3) = pose.phi.sincos();
        let zero = Vector3::zeros();
        Self {
            rotation: rotation_from_sin_cos(s1, c1, s2, c2, s3, c3),
            position: pose.position(),
            velocity: zero,
            acceleration: zero,
            omega: zero,
            alpha: zero,
        }
    }

    /// `Rdot = R [omega]x`, 1/s.
    pub fn rotation_rate(&self) -> Matrix3<T> {
        self.rotation * self.omega.cross_matrix()
    }

    /// `Rddot = R ([alpha]x + [omega]x^2)`, 1/s^2.
    pub fn rotation_acceleration(&self) -> Matrix3<T> {
        let w = self.omega.cross_matrix();
        self.rotation * (self.alpha.cross_matrix() + w * w)
    }

    /// A platform-frame point (mm) in the fixed frame: `R c + P`.
    #[inline]
    pub fn to_fixed(&self, c: &Vector3<T>) -> Vector3<T> {
        self.rotation * c + self.position
    }

    /// A fixed-frame point (mm) in the platform frame: `R^T (p - P)`.
    #[inline]
    pub fn to_platform(&self, p: &Vector3<T>) -> Vector3<T> {
        self.rotation.tr_mul(&(p - self.position))
    }

    /// The fixed-frame velocity (mm/s) of a point `c` fixed on the platform
    /// (mm, platform frame): `Pdot + Rdot c`.
    #[inline]
    pub fn point_velocity(&self, c: &Vector3<T>) -> Vector3<T> {
        self.velocity + self.rotation * self.omega.cross(c)
    }

    /// The fixed-frame acceleration (mm/s^2) of a point `c` fixed on the
    /// platform (mm, platform frame): `Pddot + Rddot c`.
    #[inline]
    pub fn point_acceleration(&self, c: &Vector3<T>) -> Vector3<T> {
        let w = &self.omega;
        self.acceleration + self.rotation * (self.alpha.cross(c) + w.cross(&w.cross(c)))
    }
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)` for angles in rad (see the [module docs](self)).
pub fn rotation<T: Real>(psi: T, theta: T, phi: T) -> Matrix3<T> {
    let (s1, c1) = psi.sincos();
    let (s2, c2) = theta.sincos();
    let (s3, c3) = phi.sincos();
    rotation_from_sin_cos(s1, c1, s2, c2, s3, c3)
}

#[inline]
pub(crate) fn rotation_from_sin_cos<T: Real>(
    s1: T,
    c1: T,
    s2: T,
    c2: T,
    s3: T,
    c3: T,
) -> Matrix3<T> {
    // R_X(psi) R_Y(theta) R_Z(phi) multiplied out.
    Matrix3::new(
        c2 * c3,
        -c2 * s3,
        s2,
        c1 * s3 + s1 * s2 * c3,
        c1 * c3 - s1 * s2 * s3,
        -s1 * c2,
        s1 * s3 - c1 * s2 * c3,
        s1 * c3 + c1 * s2 * s3,
        c1 * c2,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn axis_product(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
        let rx = Rotation3::from_axis_angle(&Vector3::x_axis(), psi);
        let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), theta);
        let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), phi);
        (rx * ry * rz).into_inner()
    }

    #[test]
    fn rotation_is_the_product_of_axis_rotations() {
        for &(a, b, c) in &[(0.1, 0.2, 0.3), (-2.0, 1.4, 3.0), (0.0, -1.5, -0.7)] {
            assert!((rotation(a, b, c) - axis_product(a, b, c)).norm() < 1e-15);
        }
    }

    #[test]
    fn mirror_conjugates_the_rotation() {
        let s = Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
        let p = Pose::new(1.0, 2.0, 3.0, 0.4, -0.3, 1.2);
        let m = p.mirrored();
        assert!((s * p.rotation() * s - m.rotation()).norm() < 1e-15);
    }

    fn state_at(t: f64) -> PlatformState<f64> {
        // A smooth motion of all six coordinates.
        let pose = Pose::new(
            1.0 + t,
            2.0 * t * t,
            -500.0 + t.sin(),
            0.3 + 0.5 * t + 0.2 * t * t,
            -0.2 + (1.3 * t).sin(),
            0.1 * t * t * t - 1.0,
        );
        let velocity = PoseRate::new(
            1.0,
            4.0 * t,
            t.cos(),
            0.5 + 0.4 * t,
            1.3 * (1.3 * t).cos(),
            0.3 * t * t,
        );
        let acceleration = PoseRate::new(0.0, 4.0, -t.sin(), 0.4, -1.69 * (1.3 * t).sin(), 0.6 * t);
        PlatformState {
            pose,
            velocity,
            acceleration,
        }
    }

    #[test]
    fn rotation_rates_match_finite_differences() {
        let h = 1e-5;
        for &t in &[0.0, 0.37, 1.2, -0.8] {
            let f = state_at(t).frame().expect("finite");
            let r_p = state_at(t + h).pose.rotation();
            let r_m = state_at(t - h).pose.rotation();
            let r_0 = state_at(t).pose.rotation();
            let rdot = (r_p - r_m) / (2.0 * h);
            let rddot = (r_p - 2.0 * r_0 + r_m) / (h * h);
            assert!((f.rotation_rate() - rdot).norm() < 1e-8, "Rdot at t={t}");
            assert!(
                (f.rotation_acceleration() - rddot).norm() < 1e-4,
                "Rddot at t={t}"
            );
            // alpha is the derivative of omega.
            let w_p = state_at(t + h).frame().expect("finite").omega;
            let w_m = state_at(t - h).frame().expect("finite").omega;
            assert!((f.alpha - (w_p - w_m) / (2.0 * h)).norm() < 1e-8);
        }
    }

    #[test]
    fn non_finite_inputs_are_named() {
        let mut s = state_at(0.2);
        s.velocity.theta = f64::NAN;
        match s.frame() {
            Err(Error::NonFinite { what, .. }) => assert_eq!(what, "velocity.theta"),
            other => panic!("expected NonFinite, got {other:?}"),
        }
        let mut s = state_at(0.2);
        s.pose.z = f64::INFINITY;
        assert!(matches!(
            s.frame(),
            Err(Error::NonFinite { what: "pose.z", .. })
        ));
    }
}
