//! The parallel margin from one control cycle to the next.
//!
//! The margin is `sigma_min(J)`, the smallest singular value of module 1's
//! dimensionless 6x6 Jacobian `J` (see the [module docs](crate::parallel)). From
//! scratch it takes a full singular value decomposition (one-sided Jacobi:
//! about 25 rounds of square roots and divisions). Between two cycles of a
//! control loop the platform barely moves, and neither does the weakest
//! direction `x`, the unit twist with `|J x| = sigma_min` (the eigenvector of
//! `A = J^T J` for its smallest eigenvalue `lambda = sigma_min^2`). With last
//! cycle's `x`, a [`MarginTracker`] gets this cycle's margin from one
//! factorisation:
//!
//! 1. `rho0 = x^T A x`, an upper bound of `lambda` (a Rayleigh quotient);
//! 2. the shift `mu = rho0 (1 - delta) - g`, with `delta` the certified
//!    tolerance ([`MarginTracker::TOLERANCE_F64`], [`MarginTracker::TOLERANCE_F32`])
//!    and `g = 16 eps trace(A)` the rounding of forming `A` and factorising it;
//! 3. `A - mu I = L D L^T`: if every pivot of `D` is positive, `A - mu I` is
//!    positive definite, so `lambda > mu + g` up to rounding: a **certified**
//!    lower bound (the test of Sturm's theorem, made without pivoting, which
//!    needs none for a positive definite matrix);
//! 4. two steps of inverse iteration with that shift, `z = (A - mu I)^-1 x`
//!    and `y = (A - mu I)^-1 z`, and the Rayleigh quotient
//!    `rho1 = y^T A y / y^T y = mu + y^T z / y^T y` (the second form,
//!    used here, saves a product by `A`; the two differ by rounding),
//!    the margin's square: between `mu` and `rho0`, and in practice equal to
//!    `lambda` to rounding, since each step shrinks every component of `y` off the
//!    weakest direction by `(lambda - mu) / (lambda_k - mu)` (the second step
//!    matters where the two smallest singular values nearly cross and the
//!    weakest direction turns quickly).
//!
//! The margin returned is `sqrt(rho1)`, certified to within `delta / 2 +
//! g / (2 rho1)` (relative) of the exact `sigma_min`, and equal to the full
//! decomposition's value to about `1e-14` in `f64` along the paper's motion at
//! 1 kHz. When the test of step 3 fails (the platform jumped, two singular
//! values crossed), `x` is first turned towards the weakest direction by
//! four steps of inverse iteration with the largest of the shifts
//! `0.99 rho0`, `0.9 rho0`, `0.5 rho0`, 0 under which `A` factorises (a
//! shift below `lambda`), and steps 1 to 4 are tried once more from there:
//! the cells of a reach map, 0.5 deg apart, certify this way nine times in
//! ten, where last cell's `x` alone certifies one time in six (the margin
//! is then within `1e-12` of the full decomposition's, relative, and still
//! certified). When that fails too, on the first cycle (no `x` yet), or
//! when rounding could not certify the tolerance (a margin so small that
//! `g` is more than a quarter of `delta rho0`: near a singularity, where
//! the squared `J^T J` loses the small values' relative accuracy), the
//! margin comes from the full decomposition, which also gives the next
//! cycle's `x`. The result is then the exact value, so a tracker never
//! returns a margin worse than the certified tolerance, whatever the
//! motion. A control cycle whose `x` certifies runs none of the second
//! attempt (it is kept out of line). The second attempt is built on the
//! processors with SIMD registers (x86, x86-64, AArch64), where the reach
//! maps and the studies run; the Cortex-M4F firmware, whose loop never
//! loses its direction (one full decomposition, the seed, per run), keeps
//! the full decomposition after a failed test and its code as it was (its
//! instruction counts may not grow).

use crate::linalg::{Mat6, Svd6, Vec6, dot, gram, ldl_shifted, ldl_solve, mul};
use crate::real::Real;

/// The weakest direction of module 1 from the previous control cycle, so
/// that the next parallel margin costs one factorisation instead of a full
/// singular value decomposition (see the [module docs](self)).
///
/// A control loop keeps one per module 1 and passes it to every
/// [`Controller::step`](crate::controller::Controller::step) (or to
/// [`ParallelRobot::solve_tracking`](crate::ParallelRobot::solve_tracking)):
/// the controller itself holds no state. A new tracker knows nothing yet:
/// its first margin is the full decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarginTracker<T> {
    /// The unit eigenvector of `J^T J` for the smallest eigenvalue last cycle
    /// (scaled twist `(Pdot, L omega_F)`), if any.
    weakest: Option<[T; 6]>,
    /// Margins computed, and how many by the full decomposition.
    margins: u64,
    full: u64,
}

impl<T: Real> Default for MarginTracker<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> MarginTracker<T> {
    /// The certified relative tolerance `delta` of a tracked margin in `f64`
    /// (about `6e-5`); see the [module docs](self).
    pub const TOLERANCE_F64: f64 = 1.0 / 16_384.0;
    /// The certified relative tolerance `delta` of a tracked margin in `f32`
    /// (about `2e-3`): `f32` rounding alone makes `g` about `2e-5` of the
    /// paper's margins' squares.
    pub const TOLERANCE_F32: f64 = 1.0 / 512.0;

    /// A tracker with no direction yet (its first margin is the full
    /// decomposition).
    pub const fn new() -> Self {
        Self {
            weakest: None,
            margins: 0,
            full: 0,
        }
    }

    /// A tracker starting from `direction` (a scaled twist `(Pdot, L
    /// omega_F)`, normalised here), as if the previous margin had found it:
    /// a margin taken near where another tracker found `direction` (a
    /// neighbouring cell of a reach map, say) starts from it instead of the
    /// full decomposition. The margin is certified as any tracked one (a
    /// poor direction only falls back to the full decomposition). A
    /// direction of zero length or with a NaN or an infinity gives a new
    /// tracker ([`new`](Self::new)).
    pub fn from_direction(direction: [T; 6]) -> Self {
        let nn = dot(&direction, &direction);
        if !(nn > T::zero() && nn.finite()) {
            return Self::new();
        }
        let inv = T::one() / nn.sqrt();
        Self {
            weakest: Some(direction.map(|v| v * inv)),
            ..Self::new()
        }
    }

    /// The weakest direction found last: the unit scaled twist
    /// `(Pdot, L omega_F)` (dimensionless) that module 1's links resist least,
    /// `|J x| = sigma_min`. `None` before the first margin, and after a margin
    /// of exactly 0. Its sign is arbitrary.
    pub fn weakest(&self) -> Option<[T; 6]> {
        self.weakest
    }

    /// How many margins this tracker has computed, and how many of those took
    /// the full singular value decomposition (the first one, and any cycle
    /// whose margin could not be certified from the previous direction).
    pub fn counts(&self) -> (u64, u64) {
        (self.margins, self.full)
    }

    /// The smallest singular value of the matrix whose rows are `rows`
    /// (module 1's scaled Jacobian), from the previous direction when it
    /// certifies, or from it sharpened, else from the full decomposition.
    pub(super) fn margin(&mut self, rows: &Mat6<T>) -> T {
        self.margins = self.margins.saturating_add(1);
        if let Some(x) = self.weakest
            && let Some((sigma, y)) = refine(&gram(rows), &x)
        {
            self.weakest = Some(y);
            return sigma;
        }
        #[cfg(any(target_arch = "x86_64", target_arch = "x86", target_arch = "aarch64"))]
        if let Some(x) = self.weakest
            && let Some((sigma, y)) = sharpened(rows, &x)
        {
            self.weakest = Some(y);
            return sigma;
        }
        self.full = self.full.saturating_add(1);
        // The singular values of J are those of J^T: the rows serve as the
        // columns of the one-sided Jacobi, without a transposed copy.
        let svd = Svd6::of_columns::<false>(*rows);
        let (sigma, x) = svd.smallest_with_direction();
        self.weakest = x;
        sigma
    }
}

/// The relative tolerance `delta` of the type.
fn tolerance<T: Real>() -> T {
    if T::EPSILON.to_f64() < 1e-10 {
        T::lit(MarginTracker::<T>::TOLERANCE_F64)
    } else {
        T::lit(MarginTracker::<T>::TOLERANCE_F32)
    }
}

/// The margin of the matrix whose rows are `rows` from `x` [`sharpen`]ed, when `x` itself does not certify
/// (a larger move than a control cycle's: the cells of a reach map); kept
/// out of line, so that a control cycle's path stays as short as it was.
#[cfg(any(target_arch = "x86_64", target_arch = "x86", target_arch = "aarch64"))]
#[cold]
#[inline(never)]
fn sharpened<T: Real>(rows: &Mat6<T>, x: &Vec6<T>) -> Option<(T, Vec6<T>)> {
    let a = gram(rows);
    refine(&a, &sharpen(&a, x)?)
}

/// `x` turned towards the weakest direction of `a` by four steps of
/// inverse iteration, `(a - s I)^-4 x` (unit), with the largest shift `s`
/// of `0.99 rho`, `0.9 rho`, `0.5 rho` and 0 (`rho` the Rayleigh quotient of `x`, an
/// upper bound of the smallest eigenvalue `lambda`) for which `a - s I` is
/// positive definite, so that `s < lambda`: each step shrinks the
/// components off the weakest direction by `(lambda - s) / (lambda_k - s)`.
/// `None` when no shift factorises (then only the full decomposition can
/// tell).
#[cfg(any(target_arch = "x86_64", target_arch = "x86", target_arch = "aarch64"))]
fn sharpen<T: Real>(a: &Mat6<T>, x: &Vec6<T>) -> Option<Vec6<T>> {
    let rho = dot(x, &mul(a, x)) / dot(x, x);
    let mut l = [[T::zero(); 6]; 6];
    let mut d_inv = [T::zero(); 6];
    let factorised = [T::lit(0.99), T::lit(0.9), T::lit(0.5), T::zero()]
        .into_iter()
        .any(|f| ldl_shifted(a, f * rho, &mut l, &mut d_inv));
    if !factorised {
        return None;
    }
    let mut y = *x;
    for _ in 0..2 {
        y = ldl_solve(&l, &d_inv, &ldl_solve(&l, &d_inv, &y));
        let yy = dot(&y, &y);
        if !(yy > T::zero() && yy.finite()) {
            return None;
        }
        let inv = T::one() / yy.sqrt();
        y = y.map(|v| v * inv);
    }
    Some(y)
}

/// Steps 1 to 4 of the [module docs](self): the certified margin and the new
/// weakest direction (unit), or `None` when the previous direction `x` does
/// not certify.
// Inlined at both of its callers, as it was at its one caller before the
// second attempt: a control cycle's code does not change.
#[cfg_attr(
    any(target_arch = "x86_64", target_arch = "x86", target_arch = "aarch64"),
    inline(always)
)]
fn refine<T: Real>(a: &Mat6<T>, x: &Vec6<T>) -> Option<(T, Vec6<T>)> {
    let delta = tolerance::<T>();
    let mut trace = T::zero();
    for (k, row) in a.iter().enumerate() {
        if let Some(&akk) = row.get(k) {
            trace += akk;
        }
    }
    let g = T::lit(16.0) * T::EPSILON * trace;
    let rho0 = dot(x, &mul(a, x)) / dot(x, x);
    // Near a singularity the rounding of J^T J is a large part of the
    // margin's square: certify only what rounding leaves resolvable.
    if !(g * T::lit(4.0) < delta * rho0) {
        return None;
    }
    let mu = rho0 * (T::one() - delta) - g;
    let mut l = [[T::zero(); 6]; 6];
    let mut d_inv = [T::zero(); 6];
    if !ldl_shifted(a, mu, &mut l, &mut d_inv) {
        return None;
    }
    // Two steps: near a crossing of the two smallest singular values the
    // weakest direction turns quickly, and one step leaves it lagging.
    let z = ldl_solve(&l, &d_inv, x);
    let y = ldl_solve(&l, &d_inv, &z);
    let yy = dot(&y, &y);
    // y^T A y = y^T (A - mu I) y + mu y^T y, and (A - mu I) y = z.
    let rho1 = mu + dot(&y, &z) / yy;
    // rho1 is a Rayleigh quotient: at least lambda > mu, at most rho0 up to
    // rounding. Anything else is rounding gone wrong: decline.
    if !(rho1 > mu && rho1 <= rho0 * (T::one() + delta) && rho1.finite()) {
        return None;
    }
    let inv = T::one() / yy.sqrt();
    Some((rho1.sqrt(), y.map(|v| v * inv)))
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix6, SymmetricEigen};

    use super::*;

    /// A deterministic pseudo-random number in `[-1, 1]`.
    fn next(x: &mut u64) -> f64 {
        *x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn rows(seed: u64) -> [[f64; 6]; 6] {
        let mut x = seed;
        core::array::from_fn(|_| core::array::from_fn(|_| next(&mut x)))
    }

    /// From a direction near the weakest one, the refined margin is the
    /// exact one; from a direction near another eigenvector, it declines.
    #[test]
    fn refine_certifies_or_declines() {
        let mut s = 11u64;
        let mut certified = 0;
        for seed in 0..500 {
            let a = gram(&rows(seed));
            let m = Matrix6::from_fn(|i, k| a[i][k]);
            let eig = SymmetricEigen::new(m);
            let mut order: [usize; 6] = core::array::from_fn(|k| k);
            order.sort_by(|&p, &q| eig.eigenvalues[p].total_cmp(&eig.eigenvalues[q]));
            let (l0, l1) = (eig.eigenvalues[order[0]], eig.eigenvalues[order[1]]);
            let v0: [f64; 6] = eig.eigenvectors.column(order[0]).into_owned().into();
            let v1: [f64; 6] = eig.eigenvectors.column(order[1]).into_owned().into();
            // Slightly off the weakest direction.
            let x: [f64; 6] = core::array::from_fn(|k| v0[k] + 1e-5 * next(&mut s));
            let trace: f64 = (0..6).map(|k| a[k][k]).sum();
            let rho0 = dot(&x, &mul(&a, &x)) / dot(&x, &x);
            let delta = MarginTracker::<f64>::TOLERANCE_F64;
            let certifiable =
                rho0 - l0 < 0.5 * delta * l0 && 64.0 * f64::EPSILON * trace < 0.5 * delta * l0;
            match refine(&a, &x) {
                Some((sigma, y)) => {
                    certified += 1;
                    let err = (sigma * sigma - l0).abs();
                    assert!(
                        err <= 8.0 * f64::EPSILON * trace + 1e-12 * l0,
                        "seed {seed}: {err:e}"
                    );
                    assert!((dot(&y, &y) - 1.0).abs() < 1e-14);
                }
                None => assert!(!certifiable, "seed {seed}: {l0} {rho0}"),
            }
            // The second eigenvector is a Rayleigh quotient l1 > l0: certified
            // only if l0 is within the tolerance of l1, and then the value
            // is still within the tolerance.
            if let Some((sigma, _)) = refine(&a, &v1) {
                assert!(l1 <= l0 * (1.0 + 1e-4), "seed {seed}: {l0} {l1}");
                assert!((sigma - l0.sqrt()).abs() <= 1e-4 * l0.sqrt());
            }
        }
        // Random matrices are often nearly singular; most still certify.
        assert!(certified > 400, "{certified}");
    }
}
