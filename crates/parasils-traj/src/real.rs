//! The float types the crate is generic over.
//!
//! Every profile is generic over `T: Real`, implemented for [`f32`] and [`f64`]
//! only (the trait is sealed). `f64` is the reference; `f32` is for
//! micro-controllers, with the error budget stated in the crate docs.
//!
//! [`Real`] is the workspace's one float trait, defined in `parasils-num`
//! and also re-exported as `parasils_kin::Real`: nalgebra's `RealField`
//! (whose `sqrt`, `cbrt`, `abs`, `max`, `min` the profiles call) with the
//! conversions ([`Real::lit`], [`Real::from_index`], [`Real::to_f64`]) and
//! the tests of floats ([`Real::finite`], [`Real::is_normal`],
//! [`Real::is_nan`]) the profiles need.

pub use parasils_num::Real;
