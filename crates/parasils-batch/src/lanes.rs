//! `L` lanes of `f64` and their masks, every operation a loop over the
//! lanes that LLVM unrolls and turns into vector instructions (the
//! operations are IEEE's, lane by lane: no fused multiply-add, no
//! reassociation, so a lane gives the bits of the same scalar code).

// Indexed loops over the lanes are the point: LLVM unrolls them into
// vector instructions.
#![allow(clippy::needless_range_loop)]

use core::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// `L` values, one per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct V<const L: usize>(pub(crate) [f64; L]);

/// `L` lane masks: all ones (true) or zero.
#[derive(Debug, Clone, Copy)]
pub(crate) struct M<const L: usize>(pub(crate) [u64; L]);

/// `L` 64-bit patterns.
#[derive(Debug, Clone, Copy)]
pub(crate) struct U<const L: usize>(pub(crate) [u64; L]);

#[inline(always)]
fn map<const L: usize, T: Copy, R: Copy + Default>(a: [T; L], f: impl Fn(T) -> R) -> [R; L] {
    let mut out = [R::default(); L];
    for l in 0..L {
        out[l] = f(a[l]);
    }
    out
}

#[inline(always)]
fn zip<const L: usize, T: Copy, R: Copy + Default>(
    a: [T; L],
    b: [T; L],
    f: impl Fn(T, T) -> R,
) -> [R; L] {
    let mut out = [R::default(); L];
    for l in 0..L {
        out[l] = f(a[l], b[l]);
    }
    out
}

impl<const L: usize> V<L> {
    /// `x` in every lane.
    #[inline(always)]
    pub(crate) fn splat(x: f64) -> Self {
        Self([x; L])
    }
    #[inline(always)]
    pub(crate) fn sqrt(self) -> Self {
        Self(map(self.0, f64::sqrt))
    }
    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        Self(map(self.0, f64::abs))
    }
    #[inline(always)]
    pub(crate) fn bits(self) -> U<L> {
        U(map(self.0, f64::to_bits))
    }
    #[inline(always)]
    pub(crate) fn lt(self, o: Self) -> M<L> {
        M(zip(self.0, o.0, |a, b| mask(a < b)))
    }
    #[inline(always)]
    pub(crate) fn le(self, o: Self) -> M<L> {
        M(zip(self.0, o.0, |a, b| mask(a <= b)))
    }
    #[inline(always)]
    pub(crate) fn gt(self, o: Self) -> M<L> {
        M(zip(self.0, o.0, |a, b| mask(a > b)))
    }
    #[inline(always)]
    pub(crate) fn ge(self, o: Self) -> M<L> {
        M(zip(self.0, o.0, |a, b| mask(a >= b)))
    }
    #[inline(always)]
    pub(crate) fn eq(self, o: Self) -> M<L> {
        M(zip(self.0, o.0, |a, b| mask(a == b)))
    }
}

#[inline(always)]
fn mask(b: bool) -> u64 {
    u64::from(b).wrapping_neg()
}

impl<const L: usize> U<L> {
    #[inline(always)]
    pub(crate) fn float(self) -> V<L> {
        V(map(self.0, f64::from_bits))
    }
    #[inline(always)]
    pub(crate) fn and(self, m: u64) -> Self {
        Self(map(self.0, |a| a & m))
    }
    #[inline(always)]
    pub(crate) fn or(self, o: Self) -> Self {
        Self(zip(self.0, o.0, |a, b| a | b))
    }
    #[inline(always)]
    pub(crate) fn xor(self, o: Self) -> Self {
        Self(zip(self.0, o.0, |a, b| a ^ b))
    }
    #[inline(always)]
    pub(crate) fn add(self, k: u64) -> Self {
        Self(map(self.0, |a| a.wrapping_add(k)))
    }
    #[inline(always)]
    pub(crate) fn shl(self, k: u32) -> Self {
        Self(map(self.0, |a| a << k))
    }
    /// All ones where the pattern is odd, zero elsewhere.
    #[inline(always)]
    pub(crate) fn odd(self) -> M<L> {
        M(map(self.0, |a| (a & 1).wrapping_neg()))
    }
}

impl<const L: usize> M<L> {
    /// `a` where set, `b` elsewhere.
    #[inline(always)]
    pub(crate) fn select(self, a: V<L>, b: V<L>) -> V<L> {
        let mut out = [0.0; L];
        for l in 0..L {
            out[l] =
                f64::from_bits((a.0[l].to_bits() & self.0[l]) | (b.0[l].to_bits() & !self.0[l]));
        }
        V(out)
    }
    /// Lane `l` set.
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> bool {
        self.0[l] != 0
    }
}

impl<const L: usize> BitAnd for M<L> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        Self(zip(self.0, o.0, |a, b| a & b))
    }
}

impl<const L: usize> BitOr for M<L> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        Self(zip(self.0, o.0, |a, b| a | b))
    }
}

impl<const L: usize> Not for M<L> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        Self(map(self.0, |a| !a))
    }
}

macro_rules! binary {
    ($trait:ident, $f:ident, $op:tt) => {
        impl<const L: usize> $trait for V<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                Self(zip(self.0, o.0, |a, b| a $op b))
            }
        }
        impl<const L: usize> $trait<f64> for V<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: f64) -> Self {
                Self(map(self.0, |a| a $op o))
            }
        }
        impl<const L: usize> $trait<V<L>> for f64 {
            type Output = V<L>;
            #[inline(always)]
            fn $f(self, o: V<L>) -> V<L> {
                V(map(o.0, |b| self $op b))
            }
        }
    };
}

binary!(Add, add, +);
binary!(Sub, sub, -);
binary!(Mul, mul, *);
binary!(Div, div, /);

impl<const L: usize> Neg for V<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self(map(self.0, |a| -a))
    }
}
