//! Finiteness checks on the solvers' inputs, naming the first bad number.
//!
//! One number at a time is [`check_finite`](crate::error::check_finite); the
//! helpers here apply it to vectors and to an evaluated platform frame.

use nalgebra::Vector3;

use crate::error::{Error, check_finite};
use crate::frame::PlatformFrame;
use crate::real::Real;

/// `Err(Error::NonFinite)` naming the first NaN or infinite component of `v`
/// (`names` are those of `x`, `y`, `z`).
pub(crate) fn check_vector<T: Real>(v: &Vector3<T>, names: [&'static str; 3]) -> Result<(), Error> {
    check_finite(v.x, names[0])?;
    check_finite(v.y, names[1])?;
    check_finite(v.z, names[2])
}

/// `Err(Error::NonFinite)` (`what = "frame"`) if any number of the frame is
/// NaN or infinite.
pub(crate) fn check_frame<T: Real>(frame: &PlatformFrame<T>) -> Result<(), Error> {
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

/// `Err(Error::NonFinite)` naming `what` when a computed result is not
/// finite: finite inputs so large that the rates or accelerations derived
/// from them overflow the float type. One sum over the values, as
/// [`check_frame`] does, with the first bad one reported.
pub(crate) fn check_results<T: Real>(values: &[T], what: &'static str) -> Result<(), Error> {
    let mut probe = T::zero();
    for &v in values {
        probe += v * T::zero();
    }
    if probe == T::zero() {
        return Ok(());
    }
    let value = values
        .iter()
        .copied()
        .find(|v| !v.finite())
        .unwrap_or(probe);
    Err(Error::NonFinite {
        what,
        value: value.to_f64(),
    })
}
