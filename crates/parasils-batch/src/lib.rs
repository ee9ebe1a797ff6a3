//! Batched kinematics of PARA-SILSROB in SIMD lanes, the kernel chosen at
//! run time for the CPU: the instrument modules' inverse kinematics
//! ([`InstrumentIk`]) and module 1's six legs' ([`Module1Ik`]) over many
//! rows, as `parasils.Robot().instrument_ik` and `module1_ik` compute them
//! on NumPy batches.
//!
//! | level | lanes | instructions |
//! |---|---|---|
//! | [`Level::Scalar`] | 1 | the scalar `parasils-kin` solver, row by row (the reference) |
//! | [`Level::Baseline`] | 2 `f64` | the target's baseline: SSE2 on x86-64, NEON on aarch64 |
//! | [`Level::Avx2`] | 4 `f64` | AVX2 and FMA (x86-64-v3) |
//! | [`Level::Avx512`] | 8 `f64` | AVX-512F (x86-64-v4) |
//!
//! **How.** The lane code is written once, generic over the number of lanes
//! `L`: straight-line code per row (selects for branches) in a loop over
//! `L` lanes held in fixed arrays, which LLVM vectorises. The `pulp` crate
//! (the run-time dispatch faer uses) supplies the CPU check and runs the
//! `L = 4` and `L = 8` versions with AVX2 or AVX-512 enabled; the CPU is
//! probed once per process ([`Level::detect`]). One binary serves every
//! x86-64; other targets build the baseline. Why this and not the
//! alternatives: `std::simd` is nightly only; `wide` picks its instructions
//! at compile time (one wheel for every x86-64 would be SSE2 only);
//! `multiversion` generates `unsafe` code in the caller's crate, which the
//! workspace forbids; pulp keeps its `unsafe` inside, and its token types
//! let a test force each level.
//!
//! **Math.** Sine and cosine are the kinematics' own (`parasils-num`),
//! rewritten without branches: each lane gives the scalar path's bits. The
//! arctangent is Cephes' rational function with the project's own range
//! reduction (see [`atan2_slice`]). No fused multiply-add is used, so every
//! level gives the same bits, and the results do not depend on the CPU.
//! Module 1's IK needs only those sines and cosines and square roots: its
//! lanes give the scalar path's bits. The instrument IK's `qs3` too; its
//! `qs1` and `qs2` come from the lanes' `atan2`, within 3 ulps.
//!
//! **Errors.** A row that could fail, or sits within [`LIMIT_GUARD_RAD`]
//! of a joint limit, is solved again by the scalar solver: a failing row
//! has the scalar path's typed error (or NaN and a cleared flag), never a
//! silent NaN.
//!
//! ```
//! use parasils_batch::{InstrumentIk, Level, OnRowError, Strided};
//! use parasils_kin::{AssemblyMode, Instrument, Pose, Side};
//! use parasils_kin::nalgebra::Vector3;
//!
//! let module = Instrument::<f64>::paper(Side::Left);
//! let ik = InstrumentIk::new(module, AssemblyMode::A);
//! let pose = Pose::<f64>::paper_start().to_array();
//! let tips = [50.0, -50.0, -620.0, 52.0, -48.0, -615.0];
//! let (mut q, mut ok) = ([0.0; 6], [false; 2]);
//! ik.solve(0..2, Strided::broadcast(&pose), Strided::rows(&tips), &mut q, &mut ok, OnRowError::Stop)
//!     .expect("both tips in reach");
//! let scalar = module
//!     .ik(&Pose::from_array(pose), &Vector3::new(50.0, -50.0, -620.0), AssemblyMode::A)
//!     .expect("in reach");
//! assert_eq!(q[2], scalar.qs3); // the same bits
//! assert!((q[0] - scalar.qs1).abs() <= 4.0 * f64::EPSILON);
//! assert!(ok[0] && ok[1]);
//! assert!(Level::detect().is_supported());
//! ```

mod instrument;
mod lanes;
mod level;
mod parallel;
mod rows;
mod trig;

pub use instrument::{InstrumentIk, LIMIT_GUARD_RAD};
pub use level::Level;
pub use parallel::Module1Ik;
pub use rows::{BatchError, OnRowError, Strided};
pub use trig::{atan2_slice, sin_cos_slice};
