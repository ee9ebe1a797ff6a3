//! One sample or a batch: array arguments of shape `(k,)` or `(N, k)`, a loop
//! over the rows in Rust without the GIL, and outputs of the same leading
//! shape.
//!
//! A single row broadcasts against a batch (one pose for `N` tips, say); two
//! batches must have the same `N`. On the first failing row the loop stops
//! and raises (`errors="raise"`), or fills the row with NaN and clears its
//! flag in a boolean mask (`errors="nan"`).

use std::borrow::Cow;

use numpy::ndarray::Array2;
use numpy::{AllowTypeChange, IntoPyArray, PyArrayLikeDyn, PyUntypedArrayMethods};
use parasils_kin::Error;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors;

/// An array argument as Python passes it: anything `numpy.asarray(x, float)` takes.
pub(crate) type ArrayArg<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// What to do with a failing row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OnError {
    /// Raise the row's error (the default).
    Raise,
    /// NaN in the row, `False` in the mask.
    Nan,
}

impl OnError {
    /// `"raise"` or `"nan"`.
    pub(crate) fn parse(s: &str) -> PyResult<Self> {
        match s {
            "raise" => Ok(OnError::Raise),
            "nan" => Ok(OnError::Nan),
            _ => Err(PyValueError::new_err(format!(
                "errors must be 'raise' or 'nan', got {s:?}"
            ))),
        }
    }
}

/// One array argument: a single row of `width` values, or `N` rows, in C order.
#[derive(Debug)]
pub(crate) struct Rows<'a> {
    data: Cow<'a, [f64]>,
    width: usize,
    /// `Some(N)` for a batch `(N, width)`, `None` for one row `(width,)`.
    batch: Option<usize>,
}

impl<'a> Rows<'a> {
    /// Checks the shape of `array` (the argument `name`): `(width,)` or `(N, width)`.
    pub(crate) fn new(array: &'a ArrayArg<'_>, name: &str, width: usize) -> PyResult<Self> {
        let shape = array.shape();
        let batch = match *shape {
            [w] if w == width => None,
            [n, w] if w == width => Some(n),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{name} must have shape ({width},) or (N, {width}), got {}",
                    shape_text(shape)
                )));
            }
        };
        // `as_slice` also accepts Fortran order, in memory order: only C order
        // is read in place, anything else is copied in C order.
        let data = match array.as_slice() {
            Ok(s) if array.is_c_contiguous() => Cow::Borrowed(s),
            _ => Cow::Owned(array.as_array().iter().copied().collect()),
        };
        Ok(Self { data, width, batch })
    }

    /// A row of zeros: an optional argument left out.
    pub(crate) fn zeros(width: usize) -> Self {
        Self {
            data: Cow::Owned(vec![0.0; width]),
            width,
            batch: None,
        }
    }

    /// Row `i` (the single row, whatever `i`, when not a batch).
    #[inline]
    pub(crate) fn row(&self, i: usize) -> &[f64] {
        match self.batch {
            Some(_) => &self.data[i * self.width..(i + 1) * self.width],
            None => &self.data[..self.width],
        }
    }

    /// Row `i` as an array of `N` values (`N` must be the width).
    #[inline]
    pub(crate) fn get<const N: usize>(&self, i: usize) -> [f64; N] {
        let mut out = [0.0; N];
        out.copy_from_slice(self.row(i));
        out
    }
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => {
            let parts: Vec<String> = shape.iter().map(ToString::to_string).collect();
            format!("({})", parts.join(", "))
        }
    }
}

/// The batch size of the arguments: `None` when every one is a single row,
/// `Some(N)` when the batches all have `N` rows.
pub(crate) fn batch_size(args: &[(&str, &Rows<'_>)]) -> PyResult<Option<usize>> {
    let mut size: Option<(&str, usize)> = None;
    for &(name, rows) in args {
        if let Some(n) = rows.batch {
            match size {
                None => size = Some((name, n)),
                Some((first, m)) if m != n => {
                    return Err(PyValueError::new_err(format!(
                        "{first} has {m} rows but {name} has {n}: batches must have the same length \
                         (a single row of shape (k,) goes with every row)"
                    )));
                }
                Some(_) => {}
            }
        }
    }
    Ok(size.map(|(_, n)| n))
}

/// The first failing row and its error.
#[derive(Debug)]
pub(crate) struct Failure {
    row: usize,
    error: Error,
}

/// Runs `f` on rows `0..n` (a single row when `batch` is `None`) without the
/// GIL; each row gives `W` values. Returns the values (`n * W`, row-major)
/// and the mask of the rows that succeeded.
pub(crate) fn run<const W: usize, F>(
    py: Python<'_>,
    batch: Option<usize>,
    on_error: OnError,
    f: F,
) -> PyResult<(Vec<f64>, Vec<bool>)>
where
    F: Fn(usize) -> Result<[f64; W], Error> + Sync,
{
    let n = batch.unwrap_or(1);
    let result = py.detach(|| {
        let mut out = Vec::with_capacity(n * W);
        let mut ok = Vec::with_capacity(n);
        for i in 0..n {
            match f(i) {
                Ok(v) => {
                    out.extend_from_slice(&v);
                    ok.push(true);
                }
                Err(error) => match on_error {
                    OnError::Raise => return Err(Failure { row: i, error }),
                    OnError::Nan => {
                        out.extend_from_slice(&[f64::NAN; W]);
                        ok.push(false);
                    }
                },
            }
        }
        Ok((out, ok))
    });
    result.map_err(|Failure { row, error }| match batch {
        Some(_) => errors::kinematics(py, &error, Some(row), None, &format!("row {row}: ")),
        None => errors::kinematics(py, &error, None, None, ""),
    })
}

/// The Python result of a batch: the output arrays (row-major `values`, split
/// in blocks of columns of the given `widths`), shaped `(width,)` for a single
/// row or `(N, width)`, then the mask with `errors="nan"` (a `bool` for a
/// single row). One array alone is returned as such, several as a tuple.
pub(crate) fn output<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    ok: Vec<bool>,
    widths: &[usize],
    batch: Option<usize>,
    on_error: OnError,
) -> PyResult<Bound<'py, PyAny>> {
    let n = batch.unwrap_or(1);
    let total: usize = widths.iter().sum();
    let shaped = |v: Vec<f64>, w: usize| -> PyResult<Bound<'py, PyAny>> {
        Ok(match batch {
            Some(_) => Array2::from_shape_vec((n, w), v)
                .map_err(|e| PyValueError::new_err(e.to_string()))?
                .into_pyarray(py)
                .into_any(),
            None => v.into_pyarray(py).into_any(),
        })
    };
    let mut items: Vec<Bound<'py, PyAny>> = Vec::with_capacity(widths.len() + 1);
    if let [w] = *widths {
        items.push(shaped(values, w)?);
    } else {
        let mut start = 0;
        for &w in widths {
            let mut block = Vec::with_capacity(n * w);
            for row in values.chunks_exact(total) {
                block.extend_from_slice(&row[start..start + w]);
            }
            items.push(shaped(block, w)?);
            start += w;
        }
    }
    if on_error == OnError::Nan {
        items.push(match batch {
            Some(_) => ok.into_pyarray(py).into_any(),
            None => ok
                .first()
                .copied()
                .unwrap_or(false)
                .into_pyobject(py)?
                .to_owned()
                .into_any(),
        });
    }
    if items.len() == 1 {
        Ok(items.remove(0))
    } else {
        Ok(PyTuple::new(py, items)?.into_any())
    }
}
