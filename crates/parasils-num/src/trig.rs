//! Sine and cosine of one angle together, in the float type's own arithmetic.
//!
//! Every rotation of the kinematics (`parasils-kin`) starts from the sine
//! and cosine of an angle (rad). libm computes them one at a time, and its `f32` versions compute in
//! `f64`, which a Cortex-M4F (single-precision FPU) emulates in software, at
//! a cost many times that of the `f32` arithmetic (see `BENCHMARKS.md`).
//! Here both come out of one range reduction and two polynomials, `f32` in
//! `f32` arithmetic only and `f64` in `f64`, without tables and without fused
//! multiply-adds (`core` has none, and baseline x86-64 lacks the
//! instruction):
//!
//! 1. **Range reduction** (Cody and Waite), skipped when `|x| < pi/4`: `k` is
//!    the integer nearest `x 2/pi` and `r = x - k pi/2`, with `pi/2` split
//!    into four constants `P1 + P2 + P3 + P4`. `k P1` and `k P3` are exact for
//!    every `k` of the range (`P1` and `P3` have few enough bits), and
//!    `P1 + P2` lies on the grid of the smallest `ulp` of `x` past `pi/4`, so
//!    `x - k P1 - k P2` is exact; the subtraction of `k P3` is made exact by a
//!    two-sum, and only the tiny `k P4` is rounded. `r` comes out as an
//!    unevaluated sum `hi + lo`, `|hi| <= pi/4` (a hair more when `x 2/pi`
//!    rounds across a half), to about `2^-120` (`f64`) and `2^-59` (`f32`)
//!    absolute: far below the closest any float of the range comes to a
//!    multiple of `pi/2` (`2^-60.5`, at `x = 45.553...` in `f64`; `2^-27.8`,
//!    at `x = 252.898...` in `f32`, found by a search over every binade), so
//!    that the results near a zero of `sin` or `cos` keep their relative
//!    accuracy.
//! 2. **Polynomials** in `z = hi^2` on `[-pi/4, pi/4]`: an odd one for the
//!    sine, `hi + S1 hi^3 + hi^5 S(z)`, and an even one for the cosine,
//!    `1 - z/2 + z^2 C(z)`, minimax for the relative error (Remez), their
//!    coefficients rounded one at a time with the later ones refitted around
//!    the rounded earlier ones. The largest term after the first adds no
//!    rounding error of its own, because it is computed exactly: for the
//!    cosine, `1 - z/2` with `z` exact (its rounding error recovered through a
//!    short head `h` of `hi`, no fused multiply-add needed) and the error of
//!    the subtraction recovered; for the sine, `S1_HI h^3` (exact: `h` and
//!    `S1_HI` have few bits) added to `hi` by a two-sum, the rest of
//!    `S1 hi^3` going with the small terms. `lo` enters both to first order
//!    (`sin += lo cos`, `cos -= lo sin`).
//! 3. **Quadrant**: `k mod 4` swaps the two and sets their signs.
//!
//! | | `f32` | `f64` |
//! |---|---|---|
//! | range (rad) | `2^-12 <= abs(x) < 2^8` | `2^-27 <= abs(x) < 2^19` |
//! | reduction | `P1`..`P4`: 12, 7, 15, 23 bits | 34, 19, 34, 53 bits |
//! | sine polynomial | degree 9 (`2^-32.5`) | degree 15 (`2^-63.2`) |
//! | cosine polynomial | degree 8 (`2^-33.0`) | degree 12 (`2^-63.9`) |
//!
//! (in brackets: the largest relative error of the polynomial, with its
//! rounded coefficients, in exact arithmetic.) Below the range `sin x = x`
//! and `cos x = 1` are the correctly rounded values (`-0` included); above
//! it, and for NaN and infinities, libm's `sin_cos` (through nalgebra)
//! answers, so no input is worse off than before. The accuracy measured is
//! in the docs of [`Real::sincos`](crate::Real::sincos).
//!
//! The `f64` constants are public so that the batched kernels in lanes
//! (`parasils-batch`) compute with the same numbers and give the same bits.

use nalgebra::ComplexField;

// ---------------------------------------------------------------- f64

/// `|x|` (bits) from which `f64` goes through the polynomials: `2^-27`. Below
/// it, `sin x = x` and `cos x = 1` are the correctly rounded values.
pub const TINY_F64: u64 = 0x3e40_0000_0000_0000;
/// `|x|` (bits) below which `f64` needs no reduction: the largest `f64`
/// below `pi/4`.
const PIO4_F64: u64 = 0x3fe9_21fb_5444_2d18;
/// `|x|` (bits) from which `f64` goes to libm: `2^19` rad, so `|k| < 2^19`.
pub const LIMIT_F64: u64 = 0x4120_0000_0000_0000;

/// `1.5 * 2^52`: adding and subtracting it rounds an `f64` of magnitude below
/// `2^51` to the nearest integer, whose low bits the sum holds.
pub const ROUND_F64: f64 = 6_755_399_441_055_744.0;
/// `pi/2 = P1 + P2 + P3 + P4` to `2^-145`: `P1` and `P3` have 34 bits (`k P1`,
/// `k P3` exact for `|k| < 2^19`), `P1 + P2` is a multiple of `2^-53`.
pub const P1_F64: f64 = 1.570_796_326_850_541;
/// The second part of `pi/2` (see `P1_F64`).
pub const P2_F64: f64 = -5.564_426_697_191_038_3e-11;
/// The third part of `pi/2` (see `P1_F64`).
pub const P3_F64: f64 = -4.978_996_250_543_838e-17;
/// The fourth part of `pi/2` (see `P1_F64`).
pub const P4_F64: f64 = 2.903_855_973_979_360_5e-28;
/// The sign, exponent and first 12 fraction bits: `hi` cut to a 13-bit head.
pub const HEAD_F64: u64 = 0xffff_ff00_0000_0000;

/// `sin r = r + S1 r^3 + r^5 (S2 + S3 z + ... + S7 z^5)`, `z = r^2`,
/// `|r| <= pi/4`: relative error `2^-63.2`.
pub const S1_F64: f64 = -0.166_666_666_666_666_66;
/// `S1` rounded to 14 bits: `S1_HI h^3` is exact for a 13-bit `h`.
pub const S1_HI_F64: f64 = -0.166_671_752_929_687_5;
/// `S1 - S1_HI`.
pub const S1_LO_F64: f64 = 5.086_263_020_842_585e-6;
/// The sine polynomial's coefficient of `r^5`.
pub const S2_F64: f64 = 0.008_333_333_333_333_04;
/// The sine polynomial's coefficient of `r^7`.
pub const S3_F64: f64 = -0.000_198_412_698_409_592_85;
/// The sine polynomial's coefficient of `r^9`.
pub const S4_F64: f64 = 2.755_731_907_188_010_3e-6;
/// The sine polynomial's coefficient of `r^11`.
pub const S5_F64: f64 = -2.505_207_028_340_994e-8;
/// The sine polynomial's coefficient of `r^13`.
pub const S6_F64: f64 = 1.605_422_047_752_635e-10;
/// The sine polynomial's coefficient of `r^15`.
pub const S7_F64: f64 = -7.384_541_003_486_797e-13;
/// `cos r = 1 - z/2 + z^2 (C1 + C2 z + ... + C6 z^5)`, `|r| <= pi/4`:
/// relative error `2^-63.9`. `C1` is the coefficient of `r^4`.
pub const C1_F64: f64 = 0.041_666_666_666_666_595;
/// The cosine polynomial's coefficient of `r^6`.
pub const C2_F64: f64 = -0.001_388_888_888_887_334_2;
/// The cosine polynomial's coefficient of `r^8`.
pub const C3_F64: f64 = 2.480_158_728_900_208e-5;
/// The cosine polynomial's coefficient of `r^10`.
pub const C4_F64: f64 = -2.755_731_421_703_885_5e-7;
/// The cosine polynomial's coefficient of `r^12`.
pub const C5_F64: f64 = 2.087_570_539_602_715_5e-9;
/// The cosine polynomial's coefficient of `r^14`.
pub const C6_F64: f64 = -1.135_874_923_973_675_7e-11;

/// `(sin x, cos x)` for an `f64` angle in rad.
#[inline]
pub(crate) fn sincos_f64(x: f64) -> (f64, f64) {
    let above_tiny = (x.to_bits() & !(1 << 63)).wrapping_sub(TINY_F64);
    // One comparison for each of `TINY <= |x| < pi/4` and `TINY <= |x| <
    // LIMIT`; NaN lies above LIMIT.
    if above_tiny < PIO4_F64 - TINY_F64 {
        kernel_f64::<false>(x, 0.0)
    } else if above_tiny < LIMIT_F64 - TINY_F64 {
        let (hi, lo, quadrant) = reduce_f64(x);
        let (sin, cos) = kernel_f64::<true>(hi, lo);
        quadrant_f64(sin, cos, quadrant)
    } else {
        outside_f64(x)
    }
}

/// `|x| < 2^-27`, `|x| >= 2^19`, infinities and NaN.
#[cold]
#[inline(never)]
fn outside_f64(x: f64) -> (f64, f64) {
    if x.to_bits() & !(1 << 63) < TINY_F64 {
        (x, 1.0)
    } else {
        ComplexField::sin_cos(x)
    }
}

/// `x - k pi/2 = hi + lo` and `k` in the low bits of the third, for
/// `|x| < 2^19`.
#[inline(always)]
fn reduce_f64(x: f64) -> (f64, f64, u64) {
    // k = x 2/pi rounded; its low bits are those of `t`.
    let t = x * core::f64::consts::FRAC_2_PI + ROUND_F64;
    let k = t - ROUND_F64;
    // b = x - k (P1 + P2) exactly, then hi + e = b - k P3 exactly (two-sum).
    let b = (x - k * P1_F64) - k * P2_F64;
    let c = k * P3_F64;
    let hi = b - c;
    let b_virtual = hi + c;
    let c_virtual = hi - b_virtual;
    let e = (b - b_virtual) + (-c - c_virtual);
    (hi, e - k * P4_F64, t.to_bits())
}

/// `(sin, cos)` of `hi + lo` for `2^-61 < |hi| <= pi/4` (a hair more
/// allowed) and a small correction `lo` (`|lo| < 2^-12 |hi|`), or `lo = 0`
/// when not `REDUCED`.
#[inline(always)]
fn kernel_f64<const REDUCED: bool>(hi: f64, lo: f64) -> (f64, f64) {
    // hi = h + l, h its 13-bit head (cut, not rounded: |l| < 2^-12 |hi|);
    // z + zl = hi^2 to 2^-77 relative: h^2 and 2 h l are exact, h^2 - z and
    // the sum cancel exactly (Sterbenz), only l^2 < 2^-24 z is rounded.
    let z = hi * hi;
    let h = f64::from_bits(hi.to_bits() & HEAD_F64);
    let l = hi - h;
    let h2 = h * h;
    let zl = ((h2 - z) + 2.0 * h * l) + l * l;
    let z2 = z * z;
    let z4 = z2 * z2;

    // sin hi = hi + S1 hi^3 + hi z^2 S(z): hi + S1_HI h^3 exactly as s0 + e0
    // (S1_HI h has 27 bits, times h^2 53: exact; a fast two-sum, as
    // |S1_HI h^3| < |hi|), the rest is small.
    let h3 = h2 * h;
    let cube = (h * S1_HI_F64) * h2;
    let s0 = hi + cube;
    let e0 = (hi - s0) + cube;
    // hi^3 - h^3 = l (hi^2 + hi h + h^2)
    let cube_rest = l * ((z + hi * h) + h2);
    let ps = (S2_F64 + z * S3_F64) + z2 * (S4_F64 + z * S5_F64) + z4 * (S6_F64 + z * S7_F64);
    // cos hi = 1 - z/2 + z^2 C(z), 1 - z/2 = w + ((1 - w) - z/2) exactly.
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let pc = (C1_F64 + z * C2_F64) + z2 * (C3_F64 + z * C4_F64) + z4 * (C5_F64 + z * C6_F64);

    // sin(hi + lo) = sin hi + lo cos hi, cos(hi + lo) = cos hi - lo sin hi
    // to first order in lo; zl enters -z/2 and, to first order, C1 z^2.
    let mut sin_small = (S1_LO_F64 * h3 + S1_F64 * cube_rest) + hi * z2 * ps;
    let mut cos_small = zl * (0.5 - (2.0 * C1_F64) * z);
    if REDUCED {
        sin_small += lo * w;
        cos_small += hi * lo;
    }
    let sin = s0 + (e0 + sin_small);
    let cos_small = z2 * pc - cos_small;
    let cos = w + (((1.0 - w) - hz) + cos_small);
    (sin, cos)
}

/// `(sin x, cos x)` from `(sin r, cos r)`, `x = r + k pi/2`, `q = k mod 4`
/// in the low bits.
#[inline(always)]
fn quadrant_f64(sin: f64, cos: f64, q: u64) -> (f64, f64) {
    let (sin, cos) = if q & 1 == 0 { (sin, cos) } else { (cos, sin) };
    // sin changes sign in quadrants 2 and 3, cos in 1 and 2.
    let sin = f64::from_bits(sin.to_bits() ^ ((q & 2) << 62));
    let cos = f64::from_bits(cos.to_bits() ^ ((q.wrapping_add(1) & 2) << 62));
    (sin, cos)
}

// ---------------------------------------------------------------- f32

/// `|x|` (bits) from which `f32` goes through the polynomials: `2^-12`.
const TINY_F32: u32 = 0x3980_0000;
/// `|x|` (bits) below which `f32` needs no reduction: the `f32` below `pi/4`.
const PIO4_F32: u32 = 0x3f49_0fda;
/// `|x|` (bits) from which `f32` goes to libm: `2^8` rad, so `|k| <= 163`.
const LIMIT_F32: u32 = 0x4380_0000;

/// `1.5 * 2^23`, as [`ROUND_F64`].
const ROUND_F32: f32 = 12_582_912.0;
/// `pi/2 = P1 + P2 + P3 + P4` to `2^-68`: `P1` has 12 bits and `P3` 15
/// (`k P1`, `k P3` exact for `|k| < 2^8`), `P1 + P2` is a multiple of `2^-24`.
const P1_F32: f32 = 1.570_800_8;
const P2_F32: f32 = -4.470_348_4e-6;
const P3_F32: f32 = 1.589_342e-8;
const P4_F32: f32 = -1.651_399_6e-13;
/// The sign, exponent and first 4 fraction bits: `hi` cut to a 5-bit head.
const HEAD_F32: u32 = 0xfff8_0000;

/// `sin r = r + S1 r^3 + r^5 (S2 + S3 z + S4 z^2)`: relative error `2^-32.5`.
const S1_F32: f32 = -0.166_666_67;
/// `S1` rounded to 9 bits: `S1_HI h^3` is exact for a 5-bit `h`.
const S1_HI_F32: f32 = -0.166_503_9;
/// `S1 - S1_HI`.
const S1_LO_F32: f32 = -1.627_653_8e-4;
const S2_F32: f32 = 0.008_333_379;
const S3_F32: f32 = -1.985_306_4e-4;
const S4_F32: f32 = 2.832_51e-6;
/// `cos r = 1 - z/2 + z^2 (C1 + C2 z + C3 z^2)`: relative error `2^-33.0`.
const C1_F32: f32 = 0.041_666_646;
const C2_F32: f32 = -0.001_388_731;
const C3_F32: f32 = 2.443_232_7e-5;

/// `(sin x, cos x)` for an `f32` angle in rad, in `f32` arithmetic only.
#[inline]
pub(crate) fn sincos_f32(x: f32) -> (f32, f32) {
    let above_tiny = (x.to_bits() & !(1 << 31)).wrapping_sub(TINY_F32);
    if above_tiny < PIO4_F32 - TINY_F32 {
        kernel_f32::<false>(x, 0.0)
    } else if above_tiny < LIMIT_F32 - TINY_F32 {
        let (hi, lo, quadrant) = reduce_f32(x);
        let (sin, cos) = kernel_f32::<true>(hi, lo);
        quadrant_f32(sin, cos, quadrant)
    } else {
        outside_f32(x)
    }
}

/// `|x| < 2^-12`, `|x| >= 2^8`, infinities and NaN.
#[cold]
#[inline(never)]
fn outside_f32(x: f32) -> (f32, f32) {
    if x.to_bits() & !(1 << 31) < TINY_F32 {
        (x, 1.0)
    } else {
        ComplexField::sin_cos(x)
    }
}

/// As [`reduce_f64`], for `|x| < 2^8`.
#[inline(always)]
fn reduce_f32(x: f32) -> (f32, f32, u32) {
    let t = x * core::f32::consts::FRAC_2_PI + ROUND_F32;
    let k = t - ROUND_F32;
    let b = (x - k * P1_F32) - k * P2_F32;
    let c = k * P3_F32;
    let hi = b - c;
    let b_virtual = hi + c;
    let c_virtual = hi - b_virtual;
    let e = (b - b_virtual) + (-c - c_virtual);
    (hi, e - k * P4_F32, t.to_bits())
}

/// As [`kernel_f64`], for `2^-28 < |hi| <= pi/4` and `|lo| < 2^-7 |hi|`.
#[inline(always)]
fn kernel_f32<const REDUCED: bool>(hi: f32, lo: f32) -> (f32, f32) {
    // hi = h + l, h its 5-bit head (|l| < 2^-4 |hi|); z + zl = hi^2 to 2^-32
    // relative.
    let z = hi * hi;
    let h = f32::from_bits(hi.to_bits() & HEAD_F32);
    let l = hi - h;
    let h2 = h * h;
    let zl = ((h2 - z) + 2.0 * h * l) + l * l;

    let h3 = h2 * h;
    let cube = (h * S1_HI_F32) * h2;
    let s0 = hi + cube;
    let e0 = (hi - s0) + cube;
    let cube_rest = l * ((z + hi * h) + h2);
    let ps = S2_F32 + z * (S3_F32 + z * S4_F32);
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let pc = C1_F32 + z * (C2_F32 + z * C3_F32);

    let z2 = z * z;
    let mut sin_small = (S1_LO_F32 * h3 + S1_F32 * cube_rest) + hi * z2 * ps;
    let mut cos_small = zl * (0.5 - (2.0 * C1_F32) * z);
    if REDUCED {
        sin_small += lo * w;
        cos_small += hi * lo;
    }
    let sin = s0 + (e0 + sin_small);
    let cos_small = z2 * pc - cos_small;
    let cos = w + (((1.0 - w) - hz) + cos_small);
    (sin, cos)
}

/// As [`quadrant_f64`].
#[inline(always)]
fn quadrant_f32(sin: f32, cos: f32, q: u32) -> (f32, f32) {
    let (sin, cos) = if q & 1 == 0 { (sin, cos) } else { (cos, sin) };
    let sin = f32::from_bits(sin.to_bits() ^ ((q & 2) << 30));
    let cos = f32::from_bits(cos.to_bits() ^ ((q.wrapping_add(1) & 2) << 30));
    (sin, cos)
}
