//! The endoscope's camera: where it looks, what it sees, and the turn that
//! aims it at a point (see `docs/model.md`, *The camera*).
//!
//! The camera sits at the endoscope's tip `E = P + R (0, 0, -depth)`. A
//! straight scope looks along `-Z'`, its image's `u` axis along `X'` and `v`
//! along `Y'`; an oblique scope's view is tilted from `-Z'` by `oblique`
//! towards the direction at `oblique_direction` from `X'` in the `X'Y'`
//! plane, its image axes turned with it (the rotation about
//! `(-Z') x view` that takes `-Z'` to the view). A point `p` seen from `E`,
//! in the camera's axes `(x, y)` across and `z` ahead, has the normalised
//! image coordinates
//!
//! ```text
//! u = x / z / tan(hfov / 2)        v = y / z / (tan(hfov / 2) / aspect)
//! ```
//!
//! and is in view when it is ahead (`z > 0`), `|u| <= 1` and `|v| <= 1`.
//!
//! [`Camera::look_at`] gives, in closed form, the `(psi, theta)` (with `phi`
//! held, as the paper requires once the instruments are in) that puts a
//! target on the view axis, the solution nearest the current orientation.
//! With `Q = R_X(psi) R_Y(theta)`, `a = R_Z(phi) view` and `r = target - P`,
//! the target is on the axis when `r = Q (lambda a - depth e3)` for some
//! `lambda > 0`: the length gives `lambda` (a quadratic), the `Y` row of
//! `R_X(-psi) r = R_Y(theta) b` gives `psi` (two solutions), and the `X`,
//! `Z` rows give `theta`.
//!
//! ```
//! use parasils_kin::nalgebra::Vector3;
//! use parasils_kin::{Camera, PlatformState, Pose};
//!
//! let camera = Camera::<f64>::assumed();
//! let pose = Pose::paper_start();
//! // A point 100 mm beyond the endoscope's tip (60 mm in), off to one side.
//! let target = Vector3::new(40.0, 50.0, -650.0);
//! let [psi, theta] = camera.look_at(&pose, 60.0, &target)?;
//! let aimed = Pose { psi, theta, ..pose };
//! let frame = PlatformState::at_rest(aimed).frame()?;
//! assert!(camera.aim_error(&frame, 60.0, &target) < 1e-12);
//! let seen = camera.project(&frame, 60.0, &target);
//! assert!(seen.u.abs() < 1e-12 && seen.v.abs() < 1e-12 && seen.in_view());
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

use nalgebra::{Matrix3, Vector3};
use parasils_num::Num;

use crate::frame::{PlatformFrame, Pose};
use crate::real::Real;

/// A camera at the endoscope's tip. Angles in rad.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Camera<T> {
    /// The horizontal field of view, rad, in `(0, pi)` (**assumed** 70 deg,
    /// a typical laparoscope).
    pub horizontal_fov: T,
    /// Width over height of the image (**assumed** 16:9).
    pub aspect_ratio: T,
    /// The view's tilt from `-Z'`, rad, in `[0, pi / 2)` (0: a straight
    /// scope; 30 deg for the common oblique ones).
    pub oblique: T,
    /// The direction of the tilt in the `X'Y'` plane, rad from `X'`.
    pub oblique_direction: T,
}

/// Why a camera cannot be built or aimed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CameraError {
    /// A parameter out of its range.
    #[error("camera: {what} = {} is not valid: {why}", Num::new(*value))]
    InvalidParameter {
        /// Which parameter.
        what: &'static str,
        /// Its value (rad for angles).
        value: f64,
        /// The range it must be in.
        why: &'static str,
    },
    /// A NaN or an infinity in the input.
    #[error("camera: non-finite input: {what} = {}", Num::new(*value))]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The target is not ahead of the camera however the platform turns:
    /// nearer the port than the endoscope's tip (a straight scope).
    #[error(
        "camera: the target is {} mm from the port, not beyond the endoscope's tip ({} mm in): it cannot be looked at",
        Num::new(*distance_mm),
        Num::new(*depth_mm)
    )]
    Behind {
        /// The target's distance from `P`, mm.
        distance_mm: f64,
        /// The endoscope's depth, mm.
        depth_mm: f64,
    },
    /// No `(psi, theta)` with this `phi` aims the view at the target (an
    /// oblique scope whose tilt points the wrong way for it).
    #[error(
        "camera: no psi, theta with phi = {} deg aims the view at the target",
        Num::new(*phi_deg)
    )]
    Unreachable {
        /// The `phi` held, deg.
        phi_deg: f64,
    },
    /// The aim needs `cos theta = 0`, where the Euler angles lose `psi`.
    #[error("camera: aiming at the target needs theta = +-90 deg, where psi is not defined")]
    Gimbal,
}

/// Where a point falls in the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImagePoint<T> {
    /// Across, `-1` at the image's left edge, `+1` at its right (along the
    /// camera's `x`: `X'` for a straight scope).
    pub u: T,
    /// Up the image, `-1` to `+1` (along the camera's `y`: `Y'`).
    pub v: T,
    /// Whether the point is ahead of the camera (`u`, `v` mean nothing
    /// otherwise).
    pub in_front: bool,
}

impl<T: Real> ImagePoint<T> {
    /// Ahead and within the image: `|u| <= 1`, `|v| <= 1`.
    pub fn in_view(&self) -> bool {
        self.in_front && self.u.abs() <= T::one() && self.v.abs() <= T::one()
    }
}

/// The camera at one cycle ([`Camera::projection`]): where points fall in
/// its image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection<T: Real> {
    /// `R`, platform to fixed.
    rotation: Matrix3<T>,
    /// The camera's axes in the platform frame, as rows (an oblique
    /// scope's; `None` for a straight one, whose axes are `X'`, `Y'`,
    /// `-Z'`).
    tilt: Option<Matrix3<T>>,
    /// The camera's position, mm, fixed frame.
    eye: Vector3<T>,
    /// `tan(hfov / 2)`, and over the aspect ratio.
    tan: T,
    tan_up: T,
}

impl<T: Real> Projection<T> {
    /// Where `point` (mm, fixed frame) falls in the image: with `(x, y, z)`
    /// the point in the camera's axes, `u = x / z / tan(hfov / 2)` and
    /// `v = y / z / (tan(hfov / 2) / aspect)`.
    pub fn project(&self, point: &Vector3<T>) -> ImagePoint<T> {
        let w = self.rotation.tr_mul(&(point - self.eye));
        let (x, y, z) = match &self.tilt {
            Some(tilt) => {
                let c = tilt * w;
                (c.x, c.y, c.z)
            }
            None => (w.x, w.y, -w.z),
        };
        ImagePoint {
            u: x / z / self.tan,
            v: y / z / self.tan_up,
            in_front: z > T::zero(),
        }
    }

    /// The camera's position, the endoscope's tip (mm, fixed frame).
    pub fn eye(&self) -> Vector3<T> {
        self.eye
    }
}

fn finite<T: Real>(what: &'static str, v: T) -> Result<T, CameraError> {
    if v.finite() {
        Ok(v)
    } else {
        Err(CameraError::NonFinite {
            what,
            value: v.to_f64(),
        })
    }
}

/// The nearest to `reference` of the angles `x + 2 pi k`. Within 3 rad of
/// it (under half a turn, so `k = 0` for sure) `x` itself, without the
/// division and rounding.
fn nearest<T: Real>(x: T, reference: T) -> T {
    let gap = reference - x;
    if gap.abs() < T::lit(3.0) {
        return x;
    }
    let turn = T::two_pi();
    let k = (gap / turn).round();
    x + k * turn
}

impl<T: Real> Camera<T> {
    /// A camera, its parameters checked.
    ///
    /// # Errors
    /// [`CameraError::InvalidParameter`] for a field of view outside
    /// `(0, pi)`, an aspect ratio that is not positive and finite, a tilt
    /// outside `[0, pi / 2)`, or a non-finite tilt direction.
    pub fn new(
        horizontal_fov: T,
        aspect_ratio: T,
        oblique: T,
        oblique_direction: T,
    ) -> Result<Self, CameraError> {
        let c = Self {
            horizontal_fov,
            aspect_ratio,
            oblique,
            oblique_direction,
        };
        c.validate()?;
        Ok(c)
    }

    /// The assumed straight laparoscope: 70 deg across, 16:9.
    pub fn assumed() -> Self {
        Self {
            horizontal_fov: T::lit(70f64.to_radians()),
            aspect_ratio: T::lit(16.0 / 9.0),
            oblique: T::zero(),
            oblique_direction: T::zero(),
        }
    }

    /// Checks the parameters (see [`Camera::new`]).
    ///
    /// # Errors
    /// As [`Camera::new`].
    pub fn validate(&self) -> Result<(), CameraError> {
        let bad = |what, value: T, why| CameraError::InvalidParameter {
            what,
            value: value.to_f64(),
            why,
        };
        let h = self.horizontal_fov;
        if !(h.finite() && h > T::zero() && h < T::pi()) {
            return Err(bad("horizontal_fov", h, "in (0, 180) deg"));
        }
        let a = self.aspect_ratio;
        if !(a.finite() && a > T::zero()) {
            return Err(bad("aspect_ratio", a, "a positive number"));
        }
        let o = self.oblique;
        if !(o.finite() && o >= T::zero() && o < T::frac_pi_2()) {
            return Err(bad("oblique", o, "in [0, 90) deg"));
        }
        if !self.oblique_direction.finite() {
            return Err(bad(
                "oblique_direction",
                self.oblique_direction,
                "a finite angle",
            ));
        }
        Ok(())
    }

    /// The camera's axes in the platform frame, as columns: the image's
    /// `u` direction, its `v` direction, and the view direction.
    pub fn axes(&self) -> Matrix3<T> {
        if self.oblique == T::zero() {
            // A straight scope: X', Y', -Z' (no rotation to compute).
            let (o, z) = (T::one(), T::zero());
            return Matrix3::new(o, z, z, z, o, z, z, z, -o);
        }
        let (sa, ca) = self.oblique.sincos();
        let (sb, cb) = self.oblique_direction.sincos();
        // Rodrigues' rotation by `oblique` about k = (sin b, -cos b, 0),
        // which takes -Z' to the view.
        let k = Vector3::new(sb, -cb, T::zero());
        let kx = Matrix3::new(
            T::zero(),
            -k.z,
            k.y,
            k.z,
            T::zero(),
            -k.x,
            -k.y,
            k.x,
            T::zero(),
        );
        let tilt = Matrix3::identity() * ca + kx * sa + (k * k.transpose()) * (T::one() - ca);
        Matrix3::from_columns(&[
            tilt.column(0).into_owned(),
            tilt.column(1).into_owned(),
            -tilt.column(2).into_owned(),
        ])
    }

    /// The view direction in the platform frame: `(sin o cos d, sin o sin d,
    /// -cos o)` for a tilt `o` towards `d`.
    pub fn view(&self) -> Vector3<T> {
        self.axes().column(2).into_owned()
    }

    /// The camera's position, the endoscope's tip `P + R (0, 0, -depth)`
    /// (mm, fixed frame).
    pub fn eye(frame: &PlatformFrame<T>, depth: T) -> Vector3<T> {
        frame.to_fixed(&Vector3::new(T::zero(), T::zero(), -depth))
    }

    /// Where `point` (mm, fixed frame) falls in the image of the camera at
    /// `depth` (mm) on the platform `frame`: [`Camera::projection`]'s
    /// [`Projection::project`]. To place several points at one cycle, build
    /// the projection once.
    pub fn project(&self, frame: &PlatformFrame<T>, depth: T, point: &Vector3<T>) -> ImagePoint<T> {
        self.projection(frame, depth).project(point)
    }

    /// The map from the fixed frame to the image of the camera at `depth`
    /// (mm) on the platform `frame`: the platform's rotation, the camera's
    /// axes, the eye, and `tan(hfov / 2)` (one sine and cosine), so that
    /// each point then costs a 3x3 product (two for an oblique scope) and
    /// four divisions.
    pub fn projection(&self, frame: &PlatformFrame<T>, depth: T) -> Projection<T> {
        let (s, c) = (self.horizontal_fov / T::lit(2.0)).sincos();
        let tan = s / c;
        Projection {
            rotation: frame.rotation,
            tilt: (self.oblique != T::zero()).then(|| self.axes().transpose()),
            eye: Self::eye(frame, depth),
            tan,
            tan_up: tan / self.aspect_ratio,
        }
    }

    /// The angle (rad) between the view axis and the direction from the
    /// camera to `target`: 0 when the target is at the image's centre.
    pub fn aim_error(&self, frame: &PlatformFrame<T>, depth: T, target: &Vector3<T>) -> T {
        let view = frame.rotation * self.view();
        let to = target - Self::eye(frame, depth);
        // atan2 of |cross| and dot: accurate at small angles too.
        view.cross(&to).norm().atan2(view.dot(&to))
    }

    /// The image's roll about the view axis from the platform's orientation
    /// `start` to `now` (rotations from the platform frame to the fixed
    /// frame), rad: the angle, right-handed about the current view
    /// direction `b`, from the start image's `u` axis carried to the
    /// current view to the current `u` axis. "Carried" is the smallest
    /// rotation taking the start's view `a` to `b` (about `a x b`), so a
    /// turn about an axis across the view rolls nothing. With `c = a . b`,
    /// `w = a x b` and the start's `u` axis `u0`, the carried axis is
    ///
    /// ```text
    /// u0' = c u0 + w x u0 + w (w . u0) / (1 + c)
    /// roll = atan2(b . (u0' x u1), u0' . u1)
    /// ```
    ///
    /// (see `docs/model.md`, *What the camera sees*). The roll is not
    /// defined once the view has turned half a turn (`c = -1`); there
    /// `1 + c` is held at `EPSILON` and the value is one of the many.
    pub fn roll(&self, start: &Matrix3<T>, now: &Matrix3<T>) -> T {
        let axes = self.axes();
        let (u0, a) = (start * axes.column(0), start * axes.column(2));
        let (u1, b) = (now * axes.column(0), now * axes.column(2));
        let c = a.dot(&b);
        let w = a.cross(&b);
        let carried = u0 * c + w.cross(&u0) + w * (w.dot(&u0) / (T::one() + c).max(T::EPSILON));
        // `+ 0`: no roll is written `0`, not `-0`.
        b.dot(&carried.cross(&u1)).atan2(carried.dot(&u1)) + T::zero()
    }

    /// The first of `look_at`'s inputs that is not finite, as an error.
    fn find_non_finite(
        &self,
        pose: &Pose<T>,
        depth: T,
        target: &Vector3<T>,
    ) -> Result<(), CameraError> {
        for (what, v) in [
            ("pose.x", pose.x),
            ("pose.y", pose.y),
            ("pose.z", pose.z),
            ("pose.psi", pose.psi),
            ("pose.theta", pose.theta),
            ("pose.phi", pose.phi),
            ("depth", depth),
            ("target.x", target.x),
            ("target.y", target.y),
            ("target.z", target.z),
        ] {
            finite(what, v)?;
        }
        Ok(())
    }

    /// The `[psi, theta]` (rad) that put `target` (mm, fixed frame) on the
    /// view axis of the camera at `depth` (mm), `P` and `phi` of `pose`
    /// held: of the two solutions, the one nearest `pose`'s angles (each
    /// angle within half a turn of the current one).
    ///
    /// # Errors
    /// [`CameraError::NonFinite`] for a non-finite input,
    /// [`CameraError::Behind`] when the target is not beyond the tip,
    /// [`CameraError::Unreachable`] when no turn with this `phi` aims at it,
    /// [`CameraError::Gimbal`] when the aim needs `theta = +-90 deg`, and
    /// [`CameraError::InvalidParameter`] for an invalid camera.
    pub fn look_at(
        &self,
        pose: &Pose<T>,
        depth: T,
        target: &Vector3<T>,
    ) -> Result<[T; 2], CameraError> {
        self.validate()?;
        // `x * 0` is 0 for every finite `x` and NaN otherwise: one sum says
        // whether all ten are finite; the names are looked for only then.
        let zero = T::zero();
        let all = pose.x * zero
            + pose.y * zero
            + pose.z * zero
            + pose.psi * zero
            + pose.theta * zero
            + pose.phi * zero
            + depth * zero
            + target.x * zero
            + target.y * zero
            + target.z * zero;
        if !(all == zero) {
            self.find_non_finite(pose, depth, target)?;
        }

        let r = target - pose.position();
        let rho = r.norm();
        // a = R_Z(phi) view: the view in the frame turned by psi, theta
        // only (a straight scope's view, -Z', is unmoved by phi).
        let d = self.view();
        let a = if self.oblique == T::zero() {
            d
        } else {
            let (sp, cp) = pose.phi.sincos();
            Vector3::new(cp * d.x - sp * d.y, sp * d.x + cp * d.y, d.z)
        };
        // |lambda a - depth e3| = rho, lambda > 0.
        let disc = depth * depth * (a.z * a.z - T::one()) + rho * rho;
        let behind = CameraError::Behind {
            distance_mm: rho.to_f64(),
            depth_mm: depth.to_f64(),
        };
        if !(disc >= T::zero()) {
            return Err(behind);
        }
        let lambda = depth * a.z + disc.sqrt();
        if !(lambda > T::zero()) {
            return Err(behind);
        }
        let b = a * lambda - Vector3::new(T::zero(), T::zero(), depth);
        // The Y row: r_y cos psi + r_z sin psi = b_y.
        let m = (r.y * r.y + r.z * r.z).sqrt();
        if !(m > T::EPSILON * rho) {
            return Err(CameraError::Gimbal);
        }
        let ratio = b.y / m;
        let slack = T::lit(64.0) * T::EPSILON;
        if ratio.abs() > T::one() + slack {
            return Err(CameraError::Unreachable {
                phi_deg: pose.phi.to_f64().to_degrees(),
            });
        }
        // psi = base +- spread, base = atan2(r_z, r_y), cos spread = ratio:
        // their sines and cosines by the addition formulas, so that the
        // rows below need no further sine or cosine.
        let cs = ratio.max(-T::one()).min(T::one());
        let ss = (T::one() - cs * cs).max(T::zero()).sqrt();
        let (cb, sb) = (r.y / m, r.z / m);
        let (spread, base) = (cs.acos(), r.z.atan2(r.y));
        let solve = |psi: T, s: T, c: T| {
            // c = R_X(-psi) r; theta turns (b_z, b_x) onto (c_z, c_x):
            // theta = atan2(y, x), so cos theta = x / hypot(x, y).
            let (cx, cz) = (r.x, -s * r.y + c * r.z);
            let (y, x) = (cx * b.z - cz * b.x, cz * b.z + cx * b.x);
            let angles = [nearest(psi, pose.psi), nearest(y.atan2(x), pose.theta)];
            (angles, [x, y])
        };
        let one = solve(base + spread, sb * cs + cb * ss, cb * cs - sb * ss);
        let two = solve(base - spread, sb * cs - cb * ss, cb * cs + sb * ss);
        let distance = |s: &[T; 2]| {
            let (dp, dt) = (s[0] - pose.psi, s[1] - pose.theta);
            dp * dp + dt * dt
        };
        let (best, [x, y]) = if distance(&two.0) < distance(&one.0) {
            two
        } else {
            one
        };
        // |cos theta| > sqrt(EPSILON), squared, without the cosine
        // (atan2(0, 0) = 0: cos theta = 1).
        let (xx, yy) = (x * x, y * y);
        if !(xx > T::EPSILON * (xx + yy) || (x == T::zero() && y == T::zero())) {
            return Err(CameraError::Gimbal);
        }
        Ok(best)
    }
}
