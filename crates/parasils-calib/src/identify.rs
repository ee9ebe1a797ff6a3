//! Which parameters the data can see: the scaled identification Jacobian's
//! columns, normalised, taken one by one in a fixed order of preference,
//! each kept when the kept ones with it still have a smallest singular
//! value of at least the tolerance (by the triangular factor of a modified
//! Gram-Schmidt, done twice), else fixed to its nominal value and reported
//! with the combination of kept parameters it cannot be told apart from.
//!
//! The order of preference puts the encoder offsets first, then the link
//! lengths, the directions, the nodes and the guide points: so a guide point
//! moved along its own direction against its encoder offset, which no data
//! can tell apart, is resolved by fixing the point's coordinate most along
//! the guide (`guides[j].point_mm.z` for vertical guides) and identifying the
//! offset, the number a firmware needs.

use nalgebra::{DMatrix, DVector};

use crate::params::{PARAMETERS, PER_GUIDE, Parameter};

/// A parameter fixed to its nominal value.
#[derive(Debug, Clone, PartialEq)]
pub struct Fixed {
    /// Its index in the parameter vector.
    pub index: usize,
    /// The part of its scaled column independent of the kept ones, relative
    /// to the column (0 for an exact dependence).
    pub independence: f64,
    /// The smallest singular value of the kept normalised columns with it.
    pub smallest: f64,
    /// What a unit change of it is equivalent to: `(index, change)` of kept
    /// parameters, in their units, largest first (at most four).
    pub equivalent: Vec<(usize, f64)>,
}

/// The kept and fixed parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// The identified parameters' indices, in vector order.
    pub kept: Vec<usize>,
    /// The fixed ones, in vector order.
    pub fixed: Vec<Fixed>,
}

/// The order in which columns are considered.
pub fn preference() -> Vec<usize> {
    let mut order = Vec::with_capacity(PARAMETERS);
    for j in 0..6 {
        order.push(Parameter::EncoderOffset { guide: j }.index());
    }
    for j in 0..6 {
        order.push(Parameter::LinkLength { guide: j }.index());
    }
    for j in 0..6 {
        order.extend([PER_GUIDE * j + 3, PER_GUIDE * j + 4]);
    }
    for leg in 0..3 {
        order.extend((0..3).map(|axis| Parameter::Node { leg, axis }.index()));
    }
    for guide in 0..6 {
        order.extend((0..3).map(|axis| Parameter::GuidePoint { guide, axis }.index()));
    }
    order
}

/// The selection from the scaled Jacobian `j` (one column per parameter):
/// the columns, normalised, are taken in the order of [`preference`], and
/// one is kept when the kept ones with it have a smallest singular value of
/// at least `tolerance` (so that every kept combination is seen at least
/// that well, relative to its columns), else fixed. `scales` turns the
/// equivalences back into each parameter's unit.
pub fn select(j: &DMatrix<f64>, tolerance: f64, scales: &[f64; PARAMETERS]) -> Selection {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    // The kept normalised columns are `Q R`, upper-triangular `R`.
    let mut r = DMatrix::<f64>::zeros(0, 0);
    let mut kept = Vec::new();
    let mut fixed = Vec::new();
    for k in preference() {
        let column = j.column(k).into_owned();
        let norm = column.norm();
        if !(norm > 0.0) {
            fixed.push((k, 0.0, 0.0));
            continue;
        }
        let mut v = column / norm;
        let mut coefs = DVector::zeros(basis.len());
        for _ in 0..2 {
            for (i, q) in basis.iter().enumerate() {
                let c = q.dot(&v);
                coefs[i] += c;
                v.axpy(-c, q, 1.0);
            }
        }
        let independence = v.norm();
        let n = basis.len();
        let mut grown = r.clone().resize(n + 1, n + 1, 0.0);
        grown.view_mut((0, n), (n, 1)).copy_from(&coefs);
        grown[(n, n)] = independence;
        let smallest = grown.singular_values().min();
        if independence > 1e-9 && smallest >= tolerance {
            basis.push(v / independence);
            r = grown;
            kept.push(k);
        } else {
            fixed.push((k, independence, smallest));
        }
    }
    kept.sort_unstable();
    let kept_matrix = DMatrix::from_fn(j.nrows(), kept.len(), |r, c| j[(r, kept[c])]);
    let svd = kept_matrix.svd(true, true);
    let mut fixed: Vec<Fixed> = fixed
        .into_iter()
        .map(|(index, independence, smallest)| {
            let rhs = j.column(index).into_owned();
            let coef = svd
                .solve(&rhs, 1e-12 * svd.singular_values.max())
                .unwrap_or_else(|_| DVector::zeros(kept.len()));
            let mut equivalent: Vec<(usize, f64)> = kept
                .iter()
                .zip(coef.iter())
                .map(|(&p, &c)| (p, c * scales[p] / scales[index]))
                .filter(|(_, c)| c.abs() > 1e-6)
                .collect();
            equivalent.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
            equivalent.truncate(4);
            Fixed {
                index,
                independence,
                smallest,
                equivalent,
            }
        })
        .collect();
    fixed.sort_by_key(|f| f.index);
    Selection { kept, fixed }
}
