//! The IK batches on `parasils-batch`'s vector kernels, chunk by chunk on
//! the batch threads (see [`crate::batch`]).
//!
//! `Robot.module1_ik` solves each chunk in SIMD lanes, to the scalar
//! solver's bits. `Robot.instrument_ik` solves each chunk in SIMD lanes; a
//! row that could fail is solved by the scalar `Instrument::ik`, so its
//! error is the scalar path's (and so for module 1). `Robot.instrument_rates` gives the same joints (the
//! kernel's, to the bit) and the scalar solver's rates and accelerations,
//! computed as before; its errors are the scalar solver's.

use core::ops::Range;

use parasils_batch::{BatchError, InstrumentIk, Level, Module1Ik, OnRowError};
use parasils_kin::{AssemblyMode, Error, Instrument, InstrumentSolution, ParallelRobot};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::batch::{self, Chunk, Failure, OnError, Rows};

/// The kernel of `module` in `mode` at the level `PARASILS_BATCH_KERNEL`
/// names, else the CPU's widest.
pub(crate) fn instrument_ik(
    module: &Instrument<f64>,
    mode: AssemblyMode,
) -> PyResult<InstrumentIk> {
    let level = batch::kernel_level()?;
    InstrumentIk::new(*module, mode)
        .at_level(level)
        .ok_or_else(|| unsupported(level))
}

/// Module 1's kernel at the level `PARASILS_BATCH_KERNEL` names, else the
/// CPU's widest.
pub(crate) fn module1_ik(robot: &ParallelRobot<f64>) -> PyResult<Module1Ik> {
    let level = batch::kernel_level()?;
    Module1Ik::new(*robot)
        .at_level(level)
        .ok_or_else(|| unsupported(level))
}

/// The error for a kernel level this CPU lacks.
fn unsupported(level: Level) -> PyErr {
    PyValueError::new_err(format!("kernel level {level} not supported by this CPU"))
}

/// `chunk`'s one output block solved by `solve` (given the chunk's rows,
/// the block and the rows' flags); a batch error becomes the chunk's
/// failure.
fn one_block(
    chunk: Chunk<'_>,
    solve: impl FnOnce(Range<usize>, &mut [f64], &mut [bool]) -> Result<(), BatchError>,
) -> Option<Failure> {
    let Chunk { start, blocks, ok } = chunk;
    let out = blocks.into_iter().next()?;
    solve(start..start + ok.len(), out, ok)
        .err()
        .map(|e| batch::kernel_failure(e, start))
}

/// One chunk of `module1_ik`: the sliders in the chunk's one block.
pub(crate) fn module1_chunk(
    kernel: &Module1Ik,
    pose: &Rows<'_>,
    on_error: OnError,
    chunk: Chunk<'_>,
) -> Option<Failure> {
    // One block (widths [6]).
    one_block(chunk, |rows, out, ok| {
        kernel.solve(rows, pose.strided(), out, ok, on_error.on_row_error())
    })
}

/// One chunk of `instrument_ik`: the joints in the chunk's one block.
pub(crate) fn ik_chunk(
    kernel: &InstrumentIk,
    pose: &Rows<'_>,
    tip: &Rows<'_>,
    on_error: OnError,
    chunk: Chunk<'_>,
) -> Option<Failure> {
    // One block (widths [3]).
    one_block(chunk, |rows, out, ok| {
        kernel.solve(
            rows,
            pose.strided(),
            tip.strided(),
            out,
            ok,
            on_error.on_row_error(),
        )
    })
}

/// One chunk of `instrument_rates`: the joints by the kernel into the first
/// block, then each row's `solve` (the scalar solver) for the rates and
/// accelerations (second and third blocks) and for the row's outcome.
pub(crate) fn rates_chunk<F>(
    kernel: &InstrumentIk,
    pose: &Rows<'_>,
    tip: &Rows<'_>,
    on_error: OnError,
    chunk: Chunk<'_>,
    solve: F,
) -> Option<Failure>
where
    F: Fn(usize) -> Result<InstrumentSolution<f64>, Error>,
{
    let Chunk { start, blocks, ok } = chunk;
    let [q, qd, qdd]: [&mut [f64]; 3] = blocks.try_into().ok()?;
    let rows = start..start + ok.len();
    // The kernel's flags are not the rows' outcome: `solve` checks more
    // (the rates' inputs, the rates themselves). NaN rows do not stop it.
    let mut joints_ok = vec![false; ok.len()];
    if let Err(e) = kernel.solve(
        rows,
        pose.strided(),
        tip.strided(),
        q,
        &mut joints_ok,
        OnRowError::Nan,
    ) {
        return Some(batch::kernel_failure(e, start));
    }
    for (k, flag) in ok.iter_mut().enumerate() {
        let at = 3 * k..3 * k + 3;
        match solve(start + k) {
            Ok(s) => {
                if !joints_ok[k] {
                    // Not expected (the kernel's IK is the scalar one for
                    // any row that could fail); the scalar joints then.
                    q[at.clone()].copy_from_slice(&s.q.to_array());
                }
                qd[at.clone()].copy_from_slice(&s.q_dot.to_array());
                qdd[at].copy_from_slice(&s.q_ddot.to_array());
                *flag = true;
            }
            Err(error) => match on_error {
                OnError::Raise => {
                    return Some(Failure {
                        row: start + k,
                        error,
                    });
                }
                OnError::Nan => {
                    q[at.clone()].fill(f64::NAN);
                    qd[at.clone()].fill(f64::NAN);
                    qdd[at].fill(f64::NAN);
                }
            },
        }
    }
    None
}
