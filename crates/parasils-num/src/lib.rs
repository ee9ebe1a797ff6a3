//! The number vocabulary shared by the kinematics (`parasils-kin`) and the
//! motion profiles (`parasils-traj`): the one float trait both are generic
//! over, and numbers as their error messages write them.
//!
//! - [`Real`]: `f32` (firmware) or `f64` (host), nalgebra's
//!   [`RealField`](nalgebra::RealField) plus the few conversions, constants
//!   and tests the two crates need, each under one name, and the crate's own
//!   sine and cosine ([`Real::sincos`]). `parasils_kin::Real`,
//!   `parasils_traj::Real` and `parasils::Real` are this trait, so code
//!   generic over both crates needs one bound and no disambiguation.
//! - [`Num`]: up to six significant digits (more only where a value would
//!   otherwise read as its limit: `320.0000001 mm is outside [0, 320]
//!   mm`), plain for `1e-3 <= |x| < 1e6` and in exponent form otherwise
//!   (`1e308`, not three hundred digits).
//!
//! `#![no_std]`, no allocation, no panicking branch: the kinematics and the
//! profiles use it in firmware.
//!
//! ```
//! use parasils_num::{Num, Real};
//!
//! assert_eq!(Num::new(-80.0078671).to_string(), "-80.0079");
//! assert_eq!(Num::new(1e308).to_string(), "1e308");
//! assert_eq!(Num::outside(320.000_000_1, 0.0, 320.0).to_string(), "320.0000001");
//!
//! fn half_turn<T: Real>() -> T {
//!     T::lit(core::f64::consts::PI)
//! }
//! assert_eq!(half_turn::<f32>().to_f64(), f64::from(core::f32::consts::PI));
//! ```
//!
//! Modules, in import order: `trig` (private: the sine and cosine), `real`
//! ([`Real`]), `format` ([`Num`]).
#![no_std]
#![deny(missing_docs)]

pub mod format;
pub mod real;
pub mod trig;

pub use format::Num;
pub use real::Real;
