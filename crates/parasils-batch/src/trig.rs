//! Sine, cosine and arctangent in `L` lanes: straight-line code, selects
//! for branches.
//!
//! **Sine and cosine** are `parasils-num`'s (the kinematics' own, see
//! `parasils_num::Real::sincos`): the same Cody–Waite reduction with `pi/2`
//! in four parts, the same Remez polynomials and the same operations in the
//! same order, without fused multiply-adds, so each lane gives the scalar
//! path's bits. The scalar code branches three ways on `|x|`; here every
//! lane takes the reduced branch (which for `|x| < pi/4` has `k = 0`,
//! `lo = +0` and gives the same bits as the unreduced one) and `|x| < 2^-27`
//! selects `(x, 1)`. Lanes with `|x| >= 2^19`, infinities and NaN are
//! flagged: their rows go to the scalar solver.
//!
//! **Arctangent** `atan2(y, x)`: the quotient of the smaller magnitude by
//! the larger, `t` in `[0, 1]`; past `t = 0.66`, `atan t = pi/4 +
//! atan((t - 1)/(t + 1))` (computed as `(min - max)/(min + max)`, one
//! division); then `atan r = r + r z P(z)/Q(z)`, `z = r^2`, with the
//! rational function of Cephes' `atan.c` (S. L. Moshier, Cephes
//! Mathematical Library, its published coefficients: relative error
//! 1.8e-16 on its range). The octant and the signs are restored with
//! `pi/4`, `pi/2` and `pi` each in two parts. Measured against libm's
//! `atan2` over random and edge arguments (`tests/agreement.rs`): at most 2
//! ulps. No fused multiply-adds either, so every level gives the same bits.

use core::f64::consts::{FRAC_2_PI, FRAC_PI_2, FRAC_PI_4, PI};

use parasils_kin::Real;

use crate::lanes::{M, V};
use crate::level::{Kernel, Level, dispatch};
use crate::rows::{BatchError, check_output};

// ------------------------------------------------------- sine and cosine
// The constants are parasils-num's, where their derivation is written.

use parasils_num::trig::{
    C1_F64 as C1, C2_F64 as C2, C3_F64 as C3, C4_F64 as C4, C5_F64 as C5, C6_F64 as C6,
    HEAD_F64 as HEAD, P1_F64 as P1, P2_F64 as P2, P3_F64 as P3, P4_F64 as P4, ROUND_F64 as ROUND,
    S1_F64 as S1, S1_HI_F64 as S1_HI, S1_LO_F64 as S1_LO, S2_F64 as S2, S3_F64 as S3, S4_F64 as S4,
    S5_F64 as S5, S6_F64 as S6, S7_F64 as S7,
};

/// `|x|` from which the polynomials apply: `2^-27`.
const TINY: f64 = f64::from_bits(parasils_num::trig::TINY_F64);
/// `|x|` from which the scalar path goes to libm: `2^19`.
const LIMIT: f64 = f64::from_bits(parasils_num::trig::LIMIT_F64);

const SIGN: u64 = 1 << 63;

/// `(sin x, cos x, in_range)` lane by lane: the scalar path's bits where
/// `in_range` (`|x| < 2^19`, not NaN), anything elsewhere.
#[inline(always)]
pub(crate) fn sincos<const L: usize>(x: V<L>) -> (V<L>, V<L>, M<L>) {
    // Compared as floats (64-bit unsigned integer compares are not in SSE2
    // or AVX2): the same as the scalar path's compares of the bits, NaN
    // included (neither tiny nor in range).
    let ax = x.abs();
    let tiny = ax.lt(V::splat(TINY));
    let in_range = ax.lt(V::splat(LIMIT));
    // Reduction: x - k pi/2 = hi + lo, k in the low bits of t.
    let t = x * FRAC_2_PI + ROUND;
    let k = t - ROUND;
    let b = (x - k * P1) - k * P2;
    let c = k * P3;
    let hi = b - c;
    let b_virtual = hi + c;
    let c_virtual = hi - b_virtual;
    let e = (b - b_virtual) + (-c - c_virtual);
    let lo = e - k * P4;
    let q = t.bits();
    // The polynomials on hi + lo.
    let z = hi * hi;
    let h = hi.bits().and(HEAD).float();
    let l = hi - h;
    let h2 = h * h;
    let zl = ((h2 - z) + 2.0 * h * l) + l * l;
    let z2 = z * z;
    let z4 = z2 * z2;
    let h3 = h2 * h;
    let cube = (h * S1_HI) * h2;
    let s0 = hi + cube;
    let e0 = (hi - s0) + cube;
    let cube_rest = l * ((z + hi * h) + h2);
    let ps = (S2 + z * S3) + z2 * (S4 + z * S5) + z4 * (S6 + z * S7);
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let pc = (C1 + z * C2) + z2 * (C3 + z * C4) + z4 * (C5 + z * C6);
    let sin_small = ((S1_LO * h3 + S1 * cube_rest) + hi * z2 * ps) + lo * w;
    let cos_small = zl * (0.5 - (2.0 * C1) * z) + hi * lo;
    let sin = s0 + (e0 + sin_small);
    let cos_small = z2 * pc - cos_small;
    let cos = w + (((1.0 - w) - hz) + cos_small);
    // The quadrant: odd k swaps the two; bit 1 of k (of k + 1) flips the
    // sine's (the cosine's) sign.
    let odd = q.odd();
    let (sin, cos) = (odd.select(cos, sin), odd.select(sin, cos));
    let sin = sin.bits().xor(q.and(2).shl(62)).float();
    let cos = cos.bits().xor(q.add(1).and(2).shl(62)).float();
    (
        tiny.select(x, sin),
        tiny.select(V::splat(1.0), cos),
        in_range,
    )
}

// ------------------------------------------------------------ arctangent

/// Cephes `atan.c`: `atan r = r + r z P(z) / Q(z)`, `z = r^2`, `|r| <= 0.66`.
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AP0: f64 = -8.750_608_600_031_904_122_785e-1;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AP1: f64 = -1.615_753_718_733_365_076_637e1;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AP2: f64 = -7.500_855_792_314_704_667_340e1;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AP3: f64 = -1.228_866_684_490_136_173_410e2;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AP4: f64 = -6.485_021_904_942_025_371_773e1;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AQ0: f64 = 2.485_846_490_142_306_297_962e1;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AQ1: f64 = 1.650_270_098_316_988_542_046e2;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AQ2: f64 = 4.328_810_604_912_902_668_951e2;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AQ3: f64 = 4.853_903_996_359_136_964_868e2;
#[allow(clippy::excessive_precision)] // Cephes' digits, as published
const AQ4: f64 = 1.945_506_571_482_613_964_425e2;
/// `pi/4 - FRAC_PI_4`, `pi/2 - FRAC_PI_2`, `pi - PI` (the low parts).
const PIO4_LO: f64 = 3.061_616_997_868_383e-17;
const PIO2_LO: f64 = 6.123_233_995_736_766e-17;
const PI_LO: f64 = 1.224_646_799_147_353_2e-16;

/// `atan2(y, x)` lane by lane, for finite `(x, y)` not both zero (and
/// below `1e300` in magnitude), rad in `[-pi, pi]`, with libm's signs of
/// zero (`atan2(-0, x > 0) = -0`, `atan2(+0, x < 0) = pi`).
#[inline(always)]
pub(crate) fn atan2<const L: usize>(y: V<L>, x: V<L>) -> V<L> {
    let (ay, ax) = (y.abs(), x.abs());
    let swap = ay.gt(ax);
    let big = swap.select(ay, ax);
    let small = swap.select(ax, ay);
    // t = small / big > 0.66: the second range.
    let far = small.gt(0.66 * big);
    let num = far.select(small - big, small);
    let den = far.select(small + big, big);
    let r = num / den;
    let z = r * r;
    let p = (((AP0 * z + AP1) * z + AP2) * z + AP3) * z + AP4;
    let qz = ((((z + AQ0) * z + AQ1) * z + AQ2) * z + AQ3) * z + AQ4;
    let a = r + r * z * (p / qz);
    let a = far.select(FRAC_PI_4 + (a + PIO4_LO), a);
    let a = swap.select((PIO2_LO - a) + FRAC_PI_2, a);
    let a = x.lt(V::splat(0.0)).select((PI_LO - a) + PI, a);
    a.bits().or(y.bits().and(SIGN)).float()
}

/// `sin` and `cos` of every value of `x` (rad) at `level`: the bits of
/// `parasils-kin`'s scalar `Real::sincos`, whatever the level.
///
/// Fails with [`BatchError::Shape`] when `sin` or `cos` is not as long as `x`.
pub fn sin_cos_slice(
    level: Level,
    x: &[f64],
    sin: &mut [f64],
    cos: &mut [f64],
) -> Result<(), BatchError> {
    check_output("sin", x.len(), sin.len())?;
    check_output("cos", x.len(), cos.len())?;
    dispatch(level, SinCos { x, sin, cos });
    Ok(())
}

/// `atan2(y, x)` of every pair (rad) at `level`: libm's at
/// [`Level::Scalar`], the lanes' kernel (within 2 ulps of it) otherwise;
/// pairs with a value of magnitude `1e300` or more (infinities), a NaN or
/// both zero take libm's.
///
/// Fails with [`BatchError::Shape`] when the three slices differ in length.
pub fn atan2_slice(level: Level, y: &[f64], x: &[f64], out: &mut [f64]) -> Result<(), BatchError> {
    check_output("x", y.len(), x.len())?;
    check_output("out", y.len(), out.len())?;
    dispatch(level, Atan2 { y, x, out });
    Ok(())
}

struct SinCos<'a> {
    x: &'a [f64],
    sin: &'a mut [f64],
    cos: &'a mut [f64],
}

impl Kernel for SinCos<'_> {
    type Output = ();

    #[inline(always)]
    fn lanes<const L: usize>(self) {
        for ((x, s), c) in self
            .x
            .chunks(L)
            .zip(self.sin.chunks_mut(L))
            .zip(self.cos.chunks_mut(L))
        {
            // A short last chunk is padded with zeros.
            let mut lanes = [0.0; L];
            lanes[..x.len()].copy_from_slice(x);
            let (sv, cv, in_range) = sincos(V(lanes));
            for l in 0..x.len() {
                (s[l], c[l]) = if in_range.get(l) {
                    (sv.0[l], cv.0[l])
                } else {
                    scalar_sincos(x[l])
                };
            }
        }
    }

    fn scalar(self) {
        for ((x, s), c) in self.x.iter().zip(self.sin).zip(self.cos) {
            (*s, *c) = x.sincos();
        }
    }
}

struct Atan2<'a> {
    y: &'a [f64],
    x: &'a [f64],
    out: &'a mut [f64],
}

impl Kernel for Atan2<'_> {
    type Output = ();

    #[inline(always)]
    fn lanes<const L: usize>(self) {
        for ((y, x), o) in self
            .y
            .chunks(L)
            .zip(self.x.chunks(L))
            .zip(self.out.chunks_mut(L))
        {
            // A short last chunk is padded with (1, 1).
            let (mut yl, mut xl) = ([1.0; L], [1.0; L]);
            yl[..y.len()].copy_from_slice(y);
            xl[..x.len()].copy_from_slice(x);
            let a = atan2(V(yl), V(xl));
            for l in 0..y.len() {
                o[l] = if in_atan2_domain(y[l], x[l]) {
                    a.0[l]
                } else {
                    y[l].atan2(x[l])
                };
            }
        }
    }

    fn scalar(self) {
        for ((y, x), o) in self.y.iter().zip(self.x).zip(self.out) {
            *o = y.atan2(*x);
        }
    }
}

/// The scalar path's sine and cosine, kept out of line: inlined next to
/// the lanes, its operations (the same as theirs) would be merged with
/// them and keep LLVM from vectorising the lanes.
#[inline(never)]
fn scalar_sincos(x: f64) -> (f64, f64) {
    x.sincos()
}

/// Where the lanes' `atan2` applies: both below `1e300` in magnitude (so
/// that their sum does not overflow; NaN is not below), not both zero.
#[inline(always)]
fn in_atan2_domain(y: f64, x: f64) -> bool {
    y.abs() < 1e300 && x.abs() < 1e300 && (y != 0.0 || x != 0.0)
}
