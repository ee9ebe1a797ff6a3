//! Rows in, rows out: strided input arrays, what to do with a failing row,
//! and the batch's errors.

// Indexed loops over the lanes are the point (see `lanes`).
#![allow(clippy::needless_range_loop)]

use core::fmt;
use core::ops::Range;

use parasils_kin::Error;

use crate::lanes::V;

/// Rows of `W` values in a slice, `stride` values apart: `W` for a
/// row-major `(N, W)` array, 0 for one row that goes with every row of a
/// batch (broadcast).
#[derive(Debug, Clone, Copy)]
pub struct Strided<'a, const W: usize> {
    data: &'a [f64],
    stride: usize,
}

impl<'a, const W: usize> Strided<'a, W> {
    /// Rows `stride` values apart in `data`.
    pub fn new(data: &'a [f64], stride: usize) -> Self {
        Self { data, stride }
    }

    /// A row-major `(N, W)` array.
    pub fn rows(data: &'a [f64]) -> Self {
        Self::new(data, W)
    }

    /// One row for every row of a batch.
    pub fn broadcast(row: &'a [f64; W]) -> Self {
        Self::new(row, 0)
    }

    /// Whether rows `0..end` are all in the slice.
    fn covers(&self, end: usize) -> bool {
        end == 0
            || (end - 1)
                .checked_mul(self.stride)
                .and_then(|s| s.checked_add(W))
                .is_some_and(|last| last <= self.data.len())
    }

    /// Rows `first..first + count` in columns of `L` lanes (`1 <= count <=
    /// L`; the last row repeated past `count`). A whole block of a
    /// row-major array is read from one slice, with no bounds check per
    /// value, so that the compiler can shuffle it into columns.
    #[inline(always)]
    pub(crate) fn gather<const L: usize>(&self, first: usize, count: usize) -> [V<L>; W] {
        let mut out = [V([0.0; L]); W];
        if self.stride == 0 {
            let row = self.row(0);
            for j in 0..W {
                out[j] = V::splat(row[j]);
            }
            return out;
        }
        if count == L && self.stride == W {
            let start = first * W;
            if let Some(block) = self.data.get(start..start + L * W) {
                for l in 0..L {
                    for j in 0..W {
                        out[j].0[l] = block[l * W + j];
                    }
                }
                return out;
            }
        }
        for l in 0..L {
            let row = self.row(first + l.min(count.max(1) - 1));
            for j in 0..W {
                out[j].0[l] = row[j];
            }
        }
        out
    }

    /// Row `i`; rows past the slice (which [`check_input`] rules out) read as NaN.
    #[inline(always)]
    pub(crate) fn row(&self, i: usize) -> [f64; W] {
        let start = i * self.stride;
        match self.data.get(start..start + W) {
            Some(s) => {
                let mut out = [0.0; W];
                out.copy_from_slice(s);
                out
            }
            None => [f64::NAN; W],
        }
    }
}

/// What a batch does with a row that fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnRowError {
    /// Stop at the first failing row (in row order) and return its error.
    Stop,
    /// Write NaN in the row, clear its flag and go on.
    Nan,
}

impl OnRowError {
    /// Writes row `row` as the scalar solver left it: its values with its
    /// flag set, or, when it failed, what this policy does (NaN and the
    /// flag cleared, or the row's error).
    pub(crate) fn write<const W: usize>(
        self,
        row: usize,
        solved: Result<[f64; W], Error>,
        out: &mut [f64],
        ok: &mut bool,
    ) -> Result<(), BatchError> {
        match solved {
            Ok(values) => {
                out.copy_from_slice(&values);
                *ok = true;
                Ok(())
            }
            Err(error) => match self {
                OnRowError::Stop => Err(BatchError::Row { row, error }),
                OnRowError::Nan => {
                    out.fill(f64::NAN);
                    *ok = false;
                    Ok(())
                }
            },
        }
    }
}

/// Why a batch stopped.
///
/// *When this happens:* a row failed with [`OnRowError::Stop`] (its
/// typed error, the scalar solver's), or the slices do not hold the rows
/// asked for (a caller's bug). *How to handle it:* report the row; fix the
/// slices' lengths.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum BatchError {
    /// Row `row` (counted from the start of the batch) failed with `error`.
    Row {
        /// The row's index.
        row: usize,
        /// Its error, as the scalar solver reports it.
        error: Error,
    },
    /// An argument does not hold the rows asked for.
    Shape {
        /// The argument.
        what: &'static str,
        /// The values it needs.
        needed: usize,
        /// The values it has.
        got: usize,
    },
}

impl fmt::Display for BatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BatchError::Row { row, error } => write!(f, "row {row}: {error}"),
            BatchError::Shape { what, needed, got } => {
                write!(f, "{what} holds {got} values where {needed} are needed")
            }
        }
    }
}

impl core::error::Error for BatchError {}

/// `Err(Shape)` unless `input` holds rows `rows` (named `what`).
pub(crate) fn check_input<const W: usize>(
    input: &Strided<'_, W>,
    rows: &Range<usize>,
    what: &'static str,
) -> Result<(), BatchError> {
    if input.covers(rows.end) {
        Ok(())
    } else {
        Err(BatchError::Shape {
            what,
            needed: rows.end.saturating_sub(1).saturating_mul(input.stride) + W,
            got: input.data.len(),
        })
    }
}

/// `Err(Shape)` unless an output holds `needed` values.
pub(crate) fn check_output(
    what: &'static str,
    needed: usize,
    got: usize,
) -> Result<(), BatchError> {
    if needed == got {
        Ok(())
    } else {
        Err(BatchError::Shape { what, needed, got })
    }
}
