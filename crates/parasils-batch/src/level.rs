//! The kernel levels and the run-time choice among them.
//!
//! A [`Level`] is how many rows one instruction carries: the scalar
//! reference (one row at a time through `parasils-kin`), two `f64` lanes on
//! the target's baseline (SSE2 on x86-64, NEON on aarch64), four on AVX2
//! with FMA (x86-64-v3), eight on AVX-512F (x86-64-v4). [`Level::detect`]
//! picks the widest the CPU has, once per process; [`Level::is_supported`]
//! tells whether a forced level can run here.
//!
//! The lane code is written once, generic over the number of lanes `L`, on
//! fixed arrays that LLVM vectorises; [`dispatch`] instantiates it inside
//! pulp's target-feature context of the chosen level, so the one binary
//! holds the three versions.

use core::fmt;
use std::sync::OnceLock;

/// How a batch is evaluated: the scalar reference, or lanes of one width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Level {
    /// One row at a time through the scalar `parasils-kin` solver (the
    /// reference, and the firmware's path).
    Scalar,
    /// Two `f64` lanes in the target's baseline instructions (SSE2 on
    /// x86-64, NEON on aarch64, plain scalar code elsewhere).
    Baseline,
    /// Four `f64` lanes, AVX2 and FMA (x86-64-v3).
    Avx2,
    /// Eight `f64` lanes, AVX-512F with VL, DQ, BW and CD (x86-64-v4).
    Avx512,
}

impl Level {
    /// Every level, narrowest first.
    pub const ALL: [Level; 4] = [Level::Scalar, Level::Baseline, Level::Avx2, Level::Avx512];

    /// Rows per instruction: 1, 2, 4 or 8.
    pub fn lanes(self) -> usize {
        match self {
            Level::Scalar => 1,
            Level::Baseline => 2,
            Level::Avx2 => 4,
            Level::Avx512 => 8,
        }
    }

    /// The level's name: `scalar`, `baseline`, `avx2` or `avx512`.
    pub fn name(self) -> &'static str {
        match self {
            Level::Scalar => "scalar",
            Level::Baseline => "baseline",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }

    /// The level named `name` (as [`Level::name`] writes it), if any.
    pub fn from_name(name: &str) -> Option<Level> {
        Level::ALL.into_iter().find(|l| l.name() == name)
    }

    /// Whether this CPU can run the level (the scalar and baseline levels
    /// run everywhere).
    pub fn is_supported(self) -> bool {
        match self {
            Level::Scalar | Level::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => pulp::x86::V3::is_available(),
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => pulp::x86::V4::is_available(),
            #[cfg(not(target_arch = "x86_64"))]
            Level::Avx2 | Level::Avx512 => false,
        }
    }

    /// The widest level this CPU supports, detected on the first call and
    /// kept for the process.
    pub fn detect() -> Level {
        static DETECTED: OnceLock<Level> = OnceLock::new();
        *DETECTED.get_or_init(|| {
            [Level::Avx512, Level::Avx2]
                .into_iter()
                .find(|l| l.is_supported())
                .unwrap_or(Level::Baseline)
        })
    }

    /// The levels this CPU supports, narrowest first.
    pub fn supported() -> impl Iterator<Item = Level> {
        Level::ALL.into_iter().filter(|l| l.is_supported())
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A computation written once for any number of lanes.
pub(crate) trait Kernel {
    /// What it returns.
    type Output;
    /// The computation in blocks of `L` rows, `L` a multiple of the
    /// level's lanes (inlined into the level's context: every function it
    /// calls on the hot path must be `#[inline(always)]`).
    fn lanes<const L: usize>(self) -> Self::Output;
    /// The scalar reference.
    fn scalar(self) -> Self::Output;
}

/// Rows per block: four vectors of the level's width (8 rows on the
/// baseline, 16 on AVX2, 32 on AVX-512), four independent chains of
/// dependent operations in flight. One vector per block left the lanes
/// waiting on each other's divisions and square roots: 1.5 times slower
/// on AVX-512 (see BENCHMARKS.md).
const VECTORS_PER_BLOCK: usize = 4;

/// Runs `kernel` at `level`; a level the CPU lacks runs at the baseline
/// (callers check [`Level::is_supported`] first).
#[inline]
pub(crate) fn dispatch<K: Kernel>(level: Level, kernel: K) -> K::Output {
    match level {
        Level::Scalar => return kernel.scalar(),
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 => {
            if let Some(simd) = pulp::x86::V4::try_new() {
                return simd.vectorize(
                    #[inline(always)]
                    move || kernel.lanes::<{ 8 * VECTORS_PER_BLOCK }>(),
                );
            }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 => {
            if let Some(simd) = pulp::x86::V3::try_new() {
                return simd.vectorize(
                    #[inline(always)]
                    move || kernel.lanes::<{ 4 * VECTORS_PER_BLOCK }>(),
                );
            }
        }
        _ => {}
    }
    kernel.lanes::<{ 2 * VECTORS_PER_BLOCK }>()
}
