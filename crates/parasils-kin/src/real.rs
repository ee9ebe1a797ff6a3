//! The float types the crate is generic over: [`Real`], the workspace's one
//! float trait (defined in `parasils-num`, shared with `parasils-traj`), and
//! degrees to radians.
//!
//! Everything in the crate is generic over `T: Real`: nalgebra's
//! `RealField` plus the conversions the solvers need (constants written in
//! `f64` into `T`, values of `T` out to `f64` for error reports) and the
//! crate's own sine and cosine, [`Real::sincos`], which every rotation of
//! the kinematics starts from.

pub use parasils_num::Real;

/// `x` degrees in radians, as `T`.
#[inline]
pub fn deg<T: Real>(x: f64) -> T {
    T::lit(x.to_radians())
}
