//! `Real::sincos`, the crate's own sine and cosine, against libm.
//!
//! `f32` is measured against libm's `f64` sine and cosine, 29 bits more
//! precise than an `f32` ulp, so the errors below are the true errors to
//! about 2^-29 ulp: every `f32` of two binades, a stride over the whole
//! range, and the points closest to multiples of `pi/2`. `f64` is compared
//! with libm's `f64` (itself within about half an ulp): random angles and
//! special points, at most 1 ulp apart. Outside the range and for NaN and
//! infinities, the results are libm's exactly.

use nalgebra::ComplexField;
use parasils_kin::Real;

/// The `f32` ulp at the exact value `v` (its binade, not that of its rounding).
fn ulp_f32(v: f64) -> f64 {
    let e = ((v.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    2f64.powi(e.max(-126) - 23)
}

/// The `f64` ulp at `v`.
fn ulp_f64(v: f64) -> f64 {
    let e = ((v.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    2f64.powi(e.max(-1022) - 52)
}

/// splitmix64: reproducible uniform bits without a dependency.
struct Rng(u64);

impl Rng {
    fn bits(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[-1, 1)`.
    fn signed_unit(&mut self) -> f64 {
        (self.bits() >> 11) as f64 * 2f64.powi(-52) - 1.0
    }
}

/// Largest errors (ulp) of `f32` sine and cosine over some angles, with
/// the angle of each; checks `sin(-x) = -sin x`, `cos(-x) = cos x` exactly
/// and `sin^2 + cos^2 = 1` within 2 eps on the way.
#[derive(Debug, Default)]
struct Worst {
    sin: (f64, f32),
    cos: (f64, f32),
    n: u64,
}

impl Worst {
    fn f32(&mut self, x: f32) {
        let (s, c) = x.sincos();
        let (sn, cn) = (-x).sincos();
        assert_eq!(sn.to_bits(), (-s).to_bits(), "sin(-x) = -sin(x) at {x:e}");
        assert_eq!(cn.to_bits(), c.to_bits(), "cos(-x) = cos(x) at {x:e}");
        let (s, c) = (f64::from(s), f64::from(c));
        let (rs, rc) = (f64::from(x).sin(), f64::from(x).cos());
        let (es, ec) = ((s - rs).abs() / ulp_f32(rs), (c - rc).abs() / ulp_f32(rc));
        if es > self.sin.0 {
            self.sin = (es, x);
        }
        if ec > self.cos.0 {
            self.cos = (ec, x);
        }
        let unit = (s * s + c * c - 1.0).abs();
        assert!(
            unit <= 2.0 * f64::from(f32::EPSILON),
            "sin^2 + cos^2 - 1 = {unit:e} at {x:e}"
        );
        self.n += 1;
    }

    fn assert_within(&self, ulp: f64, what: &str) {
        println!("{what}: {self:?}");
        assert!(
            self.sin.0 <= ulp && self.cos.0 <= ulp,
            "{what}: sin {} ulp at {:e}, cos {} ulp at {:e}, bound {ulp}",
            self.sin.0,
            self.sin.1,
            self.cos.0,
            self.cos.1
        );
    }
}

/// The largest error of `f32` `sincos` over every `f32` of its range is
/// 0.567 ulp (sine; 0.563 for the cosine), as the docs of `Real::sincos`
/// state; the angles here must not exceed it.
const F32_ULP: f64 = 0.567;

#[test]
fn f32_every_angle_in_two_binades() {
    // [0.5, 2): both polynomials up to pi/4 and the first reduction.
    let mut w = Worst::default();
    for bits in 0.5_f32.to_bits()..2.0_f32.to_bits() {
        w.f32(f32::from_bits(bits));
    }
    assert_eq!(w.n, 1 << 24);
    w.assert_within(F32_ULP, "f32 [0.5, 2)");
}

#[test]
fn f32_stride_over_the_range() {
    // Every 11th f32 from 2^-13 to 2^8, past both ends of the own range.
    let mut w = Worst::default();
    let (lo, hi) = (2f32.powi(-13).to_bits(), 256.5_f32.to_bits());
    for bits in (lo..hi).step_by(11) {
        w.f32(f32::from_bits(bits));
    }
    assert!(w.n > 15_000_000);
    w.assert_within(F32_ULP, "f32 every 11th of [2^-13, 256.5)");
}

#[test]
fn f32_near_multiples_of_half_pi() {
    // In each binade up to 2^8, the f32 closest to a multiple of pi/2
    // (x = n 2^e, |x - k pi/2| down to 2^-27.8), and its neighbours.
    const CLOSEST: [(u32, i32); 8] = [
        (13_176_795, -23),
        (13_176_795, -22),
        (9_882_596, -21),
        (9_882_596, -20),
        (9_882_596, -19),
        (9_882_596, -18),
        (9_882_596, -17),
        (16_573_937, -16),
    ];
    let mut w = Worst::default();
    for (n, e) in CLOSEST {
        let x = n as f32 * 2f32.powi(e);
        for d in -2..=2 {
            w.f32(f32::from_bits(x.to_bits().wrapping_add_signed(d)));
        }
    }
    // And every multiple of pi/4 rounded to f32, with its neighbours.
    for k in 1..326 {
        let x = k as f32 * core::f32::consts::FRAC_PI_4;
        for d in -1..=1 {
            w.f32(f32::from_bits(x.to_bits().wrapping_add_signed(d)));
        }
    }
    w.assert_within(F32_ULP, "f32 near multiples of pi/4 and pi/2");
}

#[test]
fn f32_edges() {
    // Zeros keep their sign, tiny angles are exact.
    for x in [0.0_f32, -0.0] {
        let (s, c) = x.sincos();
        assert_eq!((s.to_bits(), c), (x.to_bits(), 1.0));
    }
    for x in [
        f32::from_bits(1),
        -f32::MIN_POSITIVE,
        1e-30,
        2f32.powi(-12) * (1.0 - f32::EPSILON),
    ] {
        assert_eq!(x.sincos(), (x, 1.0), "{x:e}");
    }
    // The own range ends below 2^8; from there on, libm's values exactly.
    let mut w = Worst::default();
    for x in [2f32.powi(-12), 256.0 * (1.0 - f32::EPSILON / 2.0)] {
        w.f32(x);
    }
    w.assert_within(F32_ULP, "f32 ends of the range");
    for x in [256.0_f32, 256.000_03, -1000.0, 1e6, 3.4e38, -f32::MAX] {
        let (s, c) = x.sincos();
        let (ls, lc) = ComplexField::sin_cos(x);
        assert_eq!(
            (s.to_bits(), c.to_bits()),
            (ls.to_bits(), lc.to_bits()),
            "{x:e}"
        );
    }
    for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let (s, c) = x.sincos();
        assert!(s.is_nan() && c.is_nan(), "{x}");
    }
}

/// Largest difference (in ulp of libm's value) between `f64` `sincos` and
/// libm, with the angle; checks symmetry and `sin^2 + cos^2 = 1` within 2 eps.
#[derive(Debug, Default)]
struct Apart {
    sin: (f64, f64),
    cos: (f64, f64),
    differ: u64,
    n: u64,
}

impl Apart {
    fn f64(&mut self, x: f64) {
        let (s, c) = x.sincos();
        let (sn, cn) = (-x).sincos();
        assert_eq!(sn.to_bits(), (-s).to_bits(), "sin(-x) = -sin(x) at {x:e}");
        assert_eq!(cn.to_bits(), c.to_bits(), "cos(-x) = cos(x) at {x:e}");
        let (ls, lc) = (x.sin(), x.cos());
        let (ds, dc) = ((s - ls).abs() / ulp_f64(ls), (c - lc).abs() / ulp_f64(lc));
        if ds > self.sin.0 {
            self.sin = (ds, x);
        }
        if dc > self.cos.0 {
            self.cos = (dc, x);
        }
        self.differ += u64::from(s != ls) + u64::from(c != lc);
        // s^2 + c^2 - 1 with one rounding.
        let unit = s.mul_add(s, c.mul_add(c, -1.0)).abs();
        assert!(
            unit <= 2.0 * f64::EPSILON,
            "sin^2 + cos^2 - 1 = {unit:e} at {x:e}"
        );
        self.n += 1;
    }

    fn assert_within_one_ulp(&self, what: &str) {
        println!("{what}: {self:?}");
        assert!(
            self.sin.0 <= 1.0 && self.cos.0 <= 1.0,
            "{what}: sin {} ulp from libm at {:e}, cos {} ulp at {:e}",
            self.sin.0,
            self.sin.1,
            self.cos.0,
            self.cos.1
        );
    }
}

#[test]
fn f64_random_angles_within_an_ulp_of_libm() {
    let mut rng = Rng(0x5eed);
    for (scale, what) in [
        (core::f64::consts::PI, "|x| < pi"),
        (100.0, "|x| < 100"),
        (524_288.0, "|x| < 2^19"),
    ] {
        let mut a = Apart::default();
        for _ in 0..1_000_000 {
            a.f64(scale * rng.signed_unit());
        }
        a.assert_within_one_ulp(what);
    }
    // Log-uniform magnitudes from 2^-30 to 2^20, across both ends.
    let mut a = Apart::default();
    for _ in 0..1_000_000 {
        let e = 50.0 * (rng.signed_unit() + 1.0) / 2.0 - 30.0;
        a.f64(2f64.powf(e).copysign(rng.signed_unit()));
    }
    a.assert_within_one_ulp("2^-30 <= |x| < 2^20");
}

#[test]
fn f64_near_multiples_of_half_pi() {
    // In each binade up to 2^19, the f64 closest to a multiple of pi/2
    // (x = n 2^e, |x - k pi/2| down to 2^-60.5 at x = 45.55), and its
    // neighbours: sin or cos there is tiny and must keep its relative accuracy.
    const CLOSEST: [(u64, i32); 19] = [
        (7_074_237_752_028_440, -52),
        (7_074_237_752_028_440, -51),
        (5_305_678_314_021_330, -50),
        (5_305_678_314_021_330, -49),
        (8_400_657_330_533_773, -48),
        (6_411_027_962_775_774, -47),
        (6_411_027_962_775_774, -46),
        (6_411_027_962_775_774, -45),
        (6_411_027_962_775_774, -44),
        (6_411_027_962_775_774, -43),
        (6_411_027_962_775_774, -42),
        (6_411_027_962_775_774, -41),
        (6_411_027_962_775_774, -40),
        (6_411_027_962_775_774, -39),
        (6_251_702_173_560_778, -38),
        (6_331_365_068_168_276, -37),
        (6_291_533_620_864_527, -36),
        (7_874_374_887_906_596, -35),
        (5_520_028_710_995_367, -34),
    ];
    let mut a = Apart::default();
    for (n, e) in CLOSEST {
        let x = n as f64 * 2f64.powi(e);
        for d in -2..=2 {
            a.f64(f64::from_bits(x.to_bits().wrapping_add_signed(d)));
        }
    }
    // Multiples of pi/4 and pi/2 rounded to f64, with their neighbours.
    for k in 1..100_000_u32 {
        let x = f64::from(k) * core::f64::consts::FRAC_PI_4;
        for d in -1..=1 {
            a.f64(f64::from_bits(x.to_bits().wrapping_add_signed(d)));
        }
    }
    a.assert_within_one_ulp("f64 near multiples of pi/4 and pi/2");
}

#[test]
fn f64_edges() {
    for x in [0.0_f64, -0.0] {
        let (s, c) = x.sincos();
        assert_eq!((s.to_bits(), c), (x.to_bits(), 1.0));
    }
    for x in [
        f64::from_bits(1),
        -f64::from_bits(0x000f_ffff_ffff_ffff),
        f64::MIN_POSITIVE,
        1e-300,
        2f64.powi(-27) * (1.0 - f64::EPSILON),
    ] {
        assert_eq!(x.sincos(), (x, 1.0), "{x:e}");
    }
    let mut a = Apart::default();
    for x in [2f64.powi(-27), 524_288.0 * (1.0 - f64::EPSILON / 2.0)] {
        a.f64(x);
    }
    a.assert_within_one_ulp("f64 ends of the range");
    for x in [
        524_288.0_f64,
        524_288.000_000_1,
        -1e6,
        1e22,
        1e300,
        f64::MAX,
    ] {
        let (s, c) = x.sincos();
        let (ls, lc) = ComplexField::sin_cos(x);
        assert_eq!(
            (s.to_bits(), c.to_bits()),
            (ls.to_bits(), lc.to_bits()),
            "{x:e}"
        );
    }
    for x in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let (s, c) = x.sincos();
        assert!(s.is_nan() && c.is_nan(), "{x}");
    }
}
