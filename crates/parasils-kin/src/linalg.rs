//! The 6x6 linear algebra of module 1, without a panicking branch: a
//! one-sided Jacobi singular value decomposition, the Gram product `J^T J`,
//! a shifted `L D L^T` factorisation and its triangular solves.
//!
//! One representation throughout: a 6-vector is `[T; 6]` and a 6x6 matrix is
//! `[[T; 6]; 6]`, six such vectors, which each function says are rows or
//! columns. Plain arrays, rather than nalgebra's `Matrix6`, because the
//! callers build and read their matrices row by row and column by column
//! (the Jacobian's rows, the decomposition's columns), and because every
//! access to an array is visible to the optimiser: these kernels run every
//! control cycle (the parallel margin), where nothing may panic, and the
//! firmware links only if no panicking branch is left (see
//! `examples/firmware/README.md`).
//!
//! The rule that keeps them panic-free: an array is indexed directly only by
//! a loop counter over a constant range (`0..6`, `0..j` with `j < 6`), which
//! the optimiser proves in bounds; an index read from data (the Jacobi
//! rotation order) goes through `get` and `get_mut`. Sums are taken in index
//! order from zero, the order nalgebra's `dot` and `norm_squared` use for
//! 6-vectors, so the results are those of the nalgebra expressions they
//! replace, bit for bit.

use crate::real::Real;

/// A 6-vector.
pub(crate) type Vec6<T> = [T; 6];

/// A 6x6 matrix as six 6-vectors (rows or columns: see each use).
pub(crate) type Mat6<T> = [[T; 6]; 6];

/// `u . v`, summed in index order.
#[inline(always)]
pub(crate) fn dot<T: Real>(u: &Vec6<T>, v: &Vec6<T>) -> T {
    u.iter().zip(v).fold(T::zero(), |s, (&a, &b)| s + a * b)
}

/// `|u|^2`.
#[inline(always)]
pub(crate) fn norm_squared<T: Real>(u: &Vec6<T>) -> T {
    dot(u, u)
}

/// `(u c - v s, u s + v c)`: the pair of vectors `(u, v)` turned by the
/// plane rotation of cosine `c` and sine `s`.
#[inline(always)]
fn rotate<T: Real>(u: &Vec6<T>, v: &Vec6<T>, c: T, s: T) -> (Vec6<T>, Vec6<T>) {
    let (mut p, mut q) = (*u, *v);
    for ((p, q), (&a, &b)) in p.iter_mut().zip(q.iter_mut()).zip(u.iter().zip(v)) {
        *p = a * c - b * s;
        *q = a * s + b * c;
    }
    (p, q)
}

/// The transpose of `m`: its rows as columns.
#[allow(clippy::needless_range_loop)]
pub(crate) fn transpose<T: Real>(m: &Mat6<T>) -> Mat6<T> {
    let mut t = [[T::zero(); 6]; 6];
    for i in 0..6 {
        for k in 0..6 {
            t[i][k] = m[k][i];
        }
    }
    t
}

/// `A v` for `A` by rows.
#[inline]
pub(crate) fn mul<T: Real>(a: &Mat6<T>, v: &Vec6<T>) -> Vec6<T> {
    a.map(|row| dot(&row, v))
}

/// `A = J^T J` (both triangles) from the rows `r_j` of `J`: `sum_j r_j r_j^T`,
/// every entry summed over the rows in order.
///
/// Where the processor has SIMD registers (x86, x86-64, AArch64) the whole
/// square is summed: `r_i r_k` and `r_k r_i` are the same product, so the
/// result is the same bits as the triangle's mirror, and the six products of
/// a row of `A` form whole vectors (two `f64` lanes on the x86-64 baseline:
/// 330 instructions fewer a control step, see `BENCHMARKS.md`). Elsewhere
/// (the Cortex-M4F of the firmware, scalar) the lower triangle is summed and
/// mirrored, 21 products a row instead of 36.
#[cfg(any(target_arch = "x86_64", target_arch = "x86", target_arch = "aarch64"))]
#[allow(clippy::needless_range_loop)]
#[inline(always)]
pub(crate) fn gram<T: Real>(rows: &Mat6<T>) -> Mat6<T> {
    let mut a = [[T::zero(); 6]; 6];
    for r in rows {
        for i in 0..6 {
            let ri = r[i];
            for k in 0..6 {
                a[i][k] += ri * r[k];
            }
        }
    }
    a
}

/// [`gram`] on a scalar processor: the lower triangle summed and mirrored.
#[cfg(not(any(target_arch = "x86_64", target_arch = "x86", target_arch = "aarch64")))]
#[allow(clippy::needless_range_loop)]
pub(crate) fn gram<T: Real>(rows: &Mat6<T>) -> Mat6<T> {
    let mut a = [[T::zero(); 6]; 6];
    for r in rows {
        for i in 0..6 {
            for k in 0..=i {
                a[i][k] += r[i] * r[k];
            }
        }
    }
    for i in 0..6 {
        for k in 0..i {
            a[k][i] = a[i][k];
        }
    }
    a
}

/// `A - mu I = L D L^T` (`L` unit lower triangular, `D` diagonal) for a
/// symmetric `A`, into `l` (below the diagonal) and `d_inv` (`D^-1`); `false`
/// as soon as a pivot is not positive (then `A - mu I` is not positive
/// definite: some eigenvalue of `A` is at most `mu`, up to rounding). No
/// pivoting: a positive definite matrix needs none.
pub(crate) fn ldl_shifted<T: Real>(
    a: &Mat6<T>,
    mu: T,
    l: &mut Mat6<T>,
    d_inv: &mut Vec6<T>,
) -> bool {
    // One column at a time, each with its index a constant, so that every
    // loop below has constant bounds and unrolls: the pivots' chain of
    // divisions is then straight-line code, without the loops' counters
    // and branches between them.
    let mut d = [T::zero(); 6];
    ldl_column::<T, 0>(a, mu, l, &mut d, d_inv)
        && ldl_column::<T, 1>(a, mu, l, &mut d, d_inv)
        && ldl_column::<T, 2>(a, mu, l, &mut d, d_inv)
        && ldl_column::<T, 3>(a, mu, l, &mut d, d_inv)
        && ldl_column::<T, 4>(a, mu, l, &mut d, d_inv)
        && ldl_column::<T, 5>(a, mu, l, &mut d, d_inv)
}

/// Column `J` of [`ldl_shifted`]: pivot `d_J` (`false` if not positive)
/// and `L`'s column `J` below the diagonal.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn ldl_column<T: Real, const J: usize>(
    a: &Mat6<T>,
    mu: T,
    l: &mut Mat6<T>,
    d: &mut Vec6<T>,
    d_inv: &mut Vec6<T>,
) -> bool {
    // w_k = L_Jk D_k for k < J, reused by every row below.
    let mut w = [T::zero(); 6];
    let mut dj = a[J][J] - mu;
    for k in 0..J {
        w[k] = l[J][k] * d[k];
        dj -= w[k] * l[J][k];
    }
    if !(dj > T::zero()) {
        return false;
    }
    d[J] = dj;
    let inv = T::one() / dj;
    d_inv[J] = inv;
    for i in J + 1..6 {
        let mut s = a[i][J];
        for k in 0..J {
            s -= l[i][k] * w[k];
        }
        l[i][J] = s * inv;
    }
    true
}

/// `(L D L^T)^-1 b`, from the `L` and `D^-1` of [`ldl_shifted`].
#[allow(clippy::needless_range_loop)]
pub(crate) fn ldl_solve<T: Real>(l: &Mat6<T>, d_inv: &Vec6<T>, b: &Vec6<T>) -> Vec6<T> {
    let mut z = *b;
    for i in 0..6 {
        for k in 0..i {
            z[i] -= l[i][k] * z[k];
        }
    }
    for i in 0..6 {
        z[i] *= d_inv[i];
    }
    for i in (0..6).rev() {
        for k in i + 1..6 {
            z[i] -= l[k][i] * z[k];
        }
    }
    z
}

/// The singular value decomposition of a 6x6 matrix `M` by one-sided
/// (Hestenes) Jacobi rotations: `M V = W` with the columns of `W` orthogonal,
/// their norms the singular values, `V` orthogonal.
///
/// Written here rather than taken from nalgebra because nalgebra's SVD keeps
/// bounds-checked indexing and `unwrap`s that the optimiser cannot remove.
/// Jacobi also gives the small singular values to high relative accuracy,
/// which is what a margin near a singularity needs. At most
/// [`JACOBI_MAX_SWEEPS`] sweeps of 15 rotations in the order
/// [`JACOBI_ORDER`]; a 6x6 matrix converges in 5 to 8 (the margins along the
/// paper's motion: 4 sweeps of 15 rotations, one of 3 to 9, one that finds
/// nothing left to rotate).
pub(crate) struct Svd6<T> {
    /// `W = M V`, by columns.
    w: Mat6<T>,
    /// `V`, by columns (zeros when not asked for).
    v: Mat6<T>,
}

/// The most sweeps of the Jacobi SVD (each sweep rotates all 15 pairs).
const JACOBI_MAX_SWEEPS: usize = 30;

/// The order of the 15 pairs of a sweep: 5 rounds of 3 disjoint pairs (a
/// round-robin tournament of the 6 columns). The three rotations of a round
/// touch different columns, so an out-of-order processor overlaps them; in
/// the cyclic order `(0,1), (0,2), ...` each rotation waits for the previous
/// one's square roots and division. Convergence is about the same (6 sweeps
/// for the margins along the paper's motion, about 5% more rotations); for
/// the time saved, see `BENCHMARKS.md`.
const JACOBI_ORDER: [[(usize, usize); 3]; 5] = [
    [(0, 1), (2, 5), (3, 4)],
    [(0, 2), (1, 3), (4, 5)],
    [(0, 3), (2, 4), (1, 5)],
    [(0, 4), (3, 5), (1, 2)],
    [(0, 5), (1, 4), (2, 3)],
];

impl<T: Real> Svd6<T> {
    /// The decomposition of the matrix whose columns are `w`; `V` is
    /// accumulated only `WITH_V` (a margin needs the values only).
    pub(crate) fn of_columns<const WITH_V: bool>(mut w: Mat6<T>) -> Self {
        let mut v = [[T::zero(); 6]; 6];
        if WITH_V {
            for (k, col) in v.iter_mut().enumerate() {
                if let Some(x) = col.get_mut(k) {
                    *x = T::one();
                }
            }
        }
        let two = T::lit(2.0);
        for _ in 0..JACOBI_MAX_SWEEPS {
            // The squared column norms, recomputed every sweep (no drift) and
            // updated after each rotation (`|w_p|^2 - t gamma`, `|w_q|^2 + t gamma`).
            let mut norms = [T::zero(); 6];
            for (n, col) in norms.iter_mut().zip(&w) {
                *n = norm_squared(col);
            }
            let mut rotated = false;
            for &(p, q) in JACOBI_ORDER.iter().flatten() {
                let (Some(&wp), Some(&wq), Some(&alpha), Some(&beta)) =
                    (w.get(p), w.get(q), norms.get(p), norms.get(q))
                else {
                    continue;
                };
                let gamma = dot(&wp, &wq);
                // Orthogonal to working precision (or a zero column):
                // |gamma| <= eps sqrt(alpha beta), without the root.
                if !(gamma * gamma > T::EPSILON * T::EPSILON * alpha * beta) {
                    continue;
                }
                rotated = true;
                // The rotation that makes the pair orthogonal, the smaller of
                // the two angles: with d = beta - alpha and
                // r = sqrt(d^2 + 4 gamma^2), t = tan = sign(d) 2 gamma / (|d| + r),
                // c = 1 / sqrt(1 + t^2) = sqrt(u / 2r) and s = c t, where
                // u = |d| + r: two roots and one division on the way to the
                // new columns (Rutishauser's form through zeta = d / 2 gamma
                // takes three divisions). No overflow: gamma != 0 here, and
                // the columns of the matrices solved (scaled Jacobians) have
                // norms of order 1.
                let d = beta - alpha;
                let g2 = two * gamma;
                let r = (d * d + g2 * g2).sqrt();
                let u = d.abs() + r;
                let sg = if d >= T::zero() { g2 } else { -g2 };
                let h = T::one() / (two * r * u).sqrt();
                let (c, s) = (u * h, sg * h);
                let t_gamma = sg / u * gamma;
                let (new_p, new_q) = rotate(&wp, &wq, c, s);
                if let Some(x) = w.get_mut(p) {
                    *x = new_p;
                }
                if let Some(x) = w.get_mut(q) {
                    *x = new_q;
                }
                if let Some(n) = norms.get_mut(p) {
                    *n = alpha - t_gamma;
                }
                if let Some(n) = norms.get_mut(q) {
                    *n = beta + t_gamma;
                }
                if WITH_V {
                    let (Some(&vp), Some(&vq)) = (v.get(p), v.get(q)) else {
                        continue;
                    };
                    let (new_p, new_q) = rotate(&vp, &vq, c, s);
                    if let Some(x) = v.get_mut(p) {
                        *x = new_p;
                    }
                    if let Some(x) = v.get_mut(q) {
                        *x = new_q;
                    }
                }
            }
            if !rotated {
                break;
            }
        }
        Self { w, v }
    }

    /// The smallest singular value.
    pub(crate) fn smallest(&self) -> T {
        self.smallest_with_direction().0
    }

    /// The smallest singular value and, for a decomposition of `M = J^T`,
    /// the unit right singular vector of `J` that goes with it (the column
    /// of `W` divided by its norm; `None` if that norm is 0).
    pub(crate) fn smallest_with_direction(&self) -> (T, Option<Vec6<T>>) {
        let mut best = (T::lit(f64::INFINITY), None);
        for col in &self.w {
            let n = norm_squared(col).sqrt();
            if n < best.0 {
                best = (n, Some(col));
            }
        }
        let (sigma, col) = best;
        let x = col
            .filter(|_| sigma > T::zero())
            .map(|col| col.map(|x| x / sigma));
        (sigma, x)
    }

    /// `M^-1 b` (`V` must have been accumulated); the components along a zero
    /// singular value are left out.
    pub(crate) fn solve(&self, b: &Vec6<T>) -> Vec6<T> {
        let mut x = [T::zero(); 6];
        for (w, v) in self.w.iter().zip(&self.v) {
            let n2 = norm_squared(w);
            if n2 > T::zero() {
                let s = dot(w, b) / n2;
                for (xk, &vk) in x.iter_mut().zip(v) {
                    *xk += vk * s;
                }
            }
        }
        x
    }
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

    /// A deterministic pseudo-random matrix with entries in `[-1, 1]`.
    fn matrix(seed: u64) -> Matrix6<f64> {
        let mut x = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        Matrix6::from_fn(|_, _| next(&mut x))
    }

    fn rows(seed: u64) -> Mat6<f64> {
        let mut x = seed;
        core::array::from_fn(|_| core::array::from_fn(|_| next(&mut x)))
    }

    fn columns(m: &Matrix6<f64>) -> Mat6<f64> {
        core::array::from_fn(|k| m.column(k).into_owned().into())
    }

    fn eigenvalues(a: &Mat6<f64>) -> [f64; 6] {
        let m = Matrix6::from_fn(|i, k| a[i][k]);
        let mut e: [f64; 6] = SymmetricEigen::new(m).eigenvalues.into();
        e.sort_by(f64::total_cmp);
        e
    }

    #[test]
    fn jacobi_svd_matches_nalgebra() {
        for seed in 0..200 {
            let mut m = matrix(seed);
            if seed % 4 == 0 {
                // Rank 5: one column a combination of two others.
                let c = m.column(1) * 0.3 - m.column(4) * 1.7;
                m.set_column(2, &c);
            }
            let svd = Svd6::of_columns::<true>(columns(&m));
            let mut ours: [f64; 6] = svd.w.map(|w| norm_squared(&w).sqrt());
            ours.sort_by(|a, b| b.total_cmp(a));
            let theirs = m.singular_values();
            for k in 0..6 {
                assert!(
                    (ours[k] - theirs[k]).abs() < 1e-13,
                    "seed {seed}: {ours:?} vs {theirs}"
                );
            }
            // V orthogonal, M V = W.
            let v = Matrix6::from_fn(|i, k| svd.v[k][i]);
            let w = Matrix6::from_fn(|i, k| svd.w[k][i]);
            assert!((v.transpose() * v - Matrix6::identity()).amax() < 1e-14);
            assert!((m * v - w).amax() < 1e-13);
            if seed % 4 != 0 {
                let b: Vec6<f64> = columns(&matrix(seed + 1000))[0];
                let x = nalgebra::Vector6::from(svd.solve(&b));
                let r = m * x - nalgebra::Vector6::from(b);
                assert!(r.amax() < 1e-10 * (1.0 / theirs[5]));
            } else {
                assert!(svd.smallest() < 1e-14);
            }
        }
    }

    #[test]
    fn transpose_and_mul_agree_with_nalgebra() {
        let r = rows(3);
        let m = Matrix6::from_fn(|i, k| r[i][k]);
        let t = transpose(&r);
        let v: Vec6<f64> = rows(4)[0];
        let mv = m * nalgebra::Vector6::from(v);
        for i in 0..6 {
            for k in 0..6 {
                assert_eq!(t[i][k], m[(k, i)]);
            }
            assert!((mul(&r, &v)[i] - mv[i]).abs() < 1e-15);
        }
    }

    /// The whole square is the triangle summed and mirrored, bit for bit.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn gram_is_the_mirrored_triangle_to_the_bit() {
        for seed in 0..200 {
            let r = rows(seed);
            let mut mirrored = [[0.0f64; 6]; 6];
            for row in &r {
                for i in 0..6 {
                    for k in 0..=i {
                        mirrored[i][k] += row[i] * row[k];
                    }
                }
            }
            for i in 0..6 {
                for k in 0..i {
                    mirrored[k][i] = mirrored[i][k];
                }
            }
            let bits = |m: &Mat6<f64>| m.map(|row| row.map(f64::to_bits));
            assert_eq!(bits(&gram(&r)), bits(&mirrored), "{seed}");
        }
    }

    #[test]
    fn gram_is_j_transpose_j() {
        for seed in 0..50 {
            let r = rows(seed);
            let j = Matrix6::from_fn(|i, k| r[i][k]);
            let a = gram(&r);
            let want = j.transpose() * j;
            for i in 0..6 {
                for k in 0..6 {
                    assert!((a[i][k] - want[(i, k)]).abs() < 1e-14);
                }
            }
        }
    }

    /// The factorisation says "positive definite" exactly when the shift is
    /// below the smallest eigenvalue (away from it by more than rounding),
    /// and then solves the shifted system.
    #[test]
    fn shifted_factorisation_tests_the_smallest_eigenvalue() {
        let mut s = 7u64;
        for seed in 0..500 {
            let a = gram(&rows(seed));
            let lambda = eigenvalues(&a)[0];
            for f in [0.0, 0.5, 0.99, 0.999_999, 1.000_001, 1.01, 2.0] {
                let mu = lambda * f;
                let (mut l, mut d_inv) = ([[0.0; 6]; 6], [0.0; 6]);
                let positive = ldl_shifted(&a, mu, &mut l, &mut d_inv);
                assert_eq!(positive, f < 1.0, "seed {seed}, mu = {f} lambda");
                if positive {
                    let b: [f64; 6] = core::array::from_fn(|_| next(&mut s));
                    let y = ldl_solve(&l, &d_inv, &b);
                    let ay = mul(&a, &y);
                    for k in 0..6 {
                        let r = ay[k] - mu * y[k] - b[k];
                        assert!(r.abs() < 1e-9 * (1.0 + y[k].abs()), "seed {seed}");
                    }
                }
            }
        }
    }
}
