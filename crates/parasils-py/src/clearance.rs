//! `parasils.segment_distance_mm`: `parasils-kin`'s segment distance kernel
//! (the clearance between shafts) on NumPy batches.

use parasils_kin::nalgebra::Vector3;
use parasils_kin::{Segment, segment_distance};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::batch::{self, ArrayArg, OnError, Rows};

/// segment_distance_mm(a0, a1, b0, b1, *, errors="raise")
///
/// The closest points of the segments a0-a1 and b0-b1 and their distance,
/// by the kinematics library's closed-form kernel (exact for crossing,
/// parallel, near-parallel and zero-length segments; never NaN).
///
/// a0, a1, b0, b1: the segments' ends, mm, each of shape (3,) or (N, 3)
///     (a single row goes with every row of a batch).
/// errors: "raise" or "nan" (then a mask of the rows computed is returned
///     last).
///
/// Returns (distance, point_a, point_b): distance in mm, a float or shape
/// (N,); the closest points of each segment, mm, shape (3,) or (N, 3).
///
/// Raises NonFiniteError naming the first NaN or infinite coordinate
/// ("segment a.start.x" ...), or "segment distance (overflow)" for
/// coordinates so large that the distance overflows.
#[pyfunction]
#[pyo3(signature = (a0, a1, b0, b1, *, errors = "raise"))]
pub fn segment_distance_mm<'py>(
    py: Python<'py>,
    a0: ArrayArg<'py>,
    a1: ArrayArg<'py>,
    b0: ArrayArg<'py>,
    b1: ArrayArg<'py>,
    errors: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let on_error = OnError::parse(errors)?;
    let a0 = Rows::new(&a0, "a0", 3)?;
    let a1 = Rows::new(&a1, "a1", 3)?;
    let b0 = Rows::new(&b0, "b0", 3)?;
    let b1 = Rows::new(&b1, "b1", 3)?;
    let n = batch::batch_size(&[("a0", &a0), ("a1", &a1), ("b0", &b0), ("b1", &b1)])?;
    let out = batch::solve::<7, _>(py, n, on_error, &[1, 3, 3], |i| {
        let a = Segment::new(Vector3::from(a0.get::<3>(i)), Vector3::from(a1.get::<3>(i)));
        let b = Segment::new(Vector3::from(b0.get::<3>(i)), Vector3::from(b1.get::<3>(i)));
        let c = segment_distance(&a, &b)?;
        let (pa, pb) = (c.point_a, c.point_b);
        Ok([c.distance, pa.x, pa.y, pa.z, pb.x, pb.y, pb.z])
    })?;
    // The distance block has one column: shape (N,) for a batch, a float
    // for a single row.
    let items = out.cast::<PyTuple>()?;
    let distance = items.get_item(0)?;
    let distance = match n {
        Some(_) => distance.call_method1("reshape", (-1,))?,
        None => distance.get_item(0)?,
    };
    let mut rest: Vec<Bound<'py, PyAny>> = vec![distance];
    rest.extend(items.iter().skip(1));
    Ok(PyTuple::new(py, rest)?.into_any())
}
