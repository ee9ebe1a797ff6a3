//! One sample or a batch: array arguments of shape `(k,)` or `(N, k)`, a loop
//! over the rows in Rust without the GIL, and outputs of the same leading
//! shape.
//!
//! A single row broadcasts against a batch (one pose for `N` tips, say); two
//! batches must have the same `N`. With `errors="raise"` the first failing
//! row (in row order) raises; with `errors="nan"` every failing row is NaN
//! and its flag in a boolean mask is cleared.
//!
//! A batch of [`PARALLEL_MIN_ROWS`] rows or more is cut into chunks of
//! consecutive rows that [`batch_threads`] threads (the calling one and
//! scoped helpers, spawned for the call) take in row order. Each row is
//! computed by the same code whichever thread runs it, and written in place
//! into the preallocated outputs, so the result does not depend on the
//! number of threads, bit for bit; the error raised is still the first
//! failing row's, because no chunk before it is skipped.
//!
//! Scoped threads rather than a pool (rayon's): no thread outlives the call,
//! so the Python process keeps no idle threads across `os.fork()`
//! (multiprocessing), and the helpers start from the calling thread's
//! floating-point environment. The calling thread takes chunks too: a helper
//! that the OS is slow to start leaves its chunks to the others instead of
//! holding them up.

use core::num::NonZeroUsize;
use core::sync::atomic::{AtomicUsize, Ordering};
use std::borrow::Cow;
use std::sync::{Mutex, OnceLock, PoisonError};

use numpy::ndarray::IxDyn;
use numpy::{
    AllowTypeChange, PyArray1, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods,
};
use parasils_batch::{BatchError, Level, OnRowError, Strided};
use parasils_kin::Error;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors;

/// An array argument as Python passes it: anything `numpy.asarray(x, float)` takes.
pub(crate) type ArrayArg<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// Batches with fewer rows run on the calling thread alone. At about 0.1 us
/// a row (the instrument IK), 4096 rows take 0.4 ms on one thread and 0.3 ms
/// on two, starting and joining the second included; 1000 rows would gain
/// little, and lose when the other CPU is slow to pick the thread up.
pub const PARALLEL_MIN_ROWS: usize = 4096;

/// The smallest chunk handed to a thread, in rows.
const MIN_CHUNK_ROWS: usize = 1024;

/// The largest chunk handed to a thread, in rows: small enough that the
/// threads end together on a loaded machine, large enough that taking a
/// chunk (a mutex) costs nothing next to its rows.
const MAX_CHUNK_ROWS: usize = 16384;

/// Chunks per thread, at least (when the chunks are not at their minimum).
const CHUNKS_PER_THREAD: usize = 8;

/// The environment variable that sets the number of threads of a batch.
pub const THREADS_VAR: &str = "PARASILS_NUM_THREADS";

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
    /// Values from one row to the next: `width` for a batch, 0 for a single
    /// row (which then goes with every row).
    stride: usize,
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
        Ok(Self {
            data,
            width,
            stride: if batch.is_some() { width } else { 0 },
            batch,
        })
    }

    /// A row of zeros: an optional argument left out.
    pub(crate) fn zeros(width: usize) -> Self {
        Self {
            data: Cow::Owned(vec![0.0; width]),
            width,
            stride: 0,
            batch: None,
        }
    }

    /// Row `i` (the single row, whatever `i`, when not a batch).
    #[inline]
    pub(crate) fn row(&self, i: usize) -> &[f64] {
        let start = i * self.stride;
        &self.data[start..start + self.width]
    }

    /// The rows as the vector kernels read them (`W` must be the width).
    pub(crate) fn strided<const W: usize>(&self) -> Strided<'_, W> {
        Strided::new(&self.data, self.stride)
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

/// The number of threads a batch of [`PARALLEL_MIN_ROWS`] rows or more runs
/// on: `PARASILS_NUM_THREADS` when set (a positive integer), else the
/// number of CPUs this process may use (affinity and cgroup quota).
///
/// Read at each call (with the GIL held), so that `os.environ` changes it.
pub(crate) fn threads() -> PyResult<usize> {
    match std::env::var(THREADS_VAR) {
        Ok(text) if !text.trim().is_empty() => match text.trim().parse::<usize>() {
            Ok(n) if n > 0 => Ok(n),
            _ => Err(PyValueError::new_err(format!(
                "{THREADS_VAR} must be a positive integer (or unset), got {text:?}"
            ))),
        },
        Ok(_) | Err(std::env::VarError::NotPresent) => Ok(available_cpus()),
        Err(std::env::VarError::NotUnicode(text)) => Err(PyValueError::new_err(format!(
            "{THREADS_VAR} must be a positive integer (or unset), got {text:?}"
        ))),
    }
}

/// The environment variable that forces the vector kernels' level.
pub const KERNEL_VAR: &str = "PARASILS_BATCH_KERNEL";

/// The level the vector kernels run at: `PARASILS_BATCH_KERNEL` when set
/// (`scalar`, `baseline`, `avx2` or `avx512`, one this CPU supports), else
/// the widest this CPU supports. Read at each call, as [`threads`].
pub(crate) fn kernel_level() -> PyResult<Level> {
    let refuse = |text: &dyn core::fmt::Debug| {
        let supported: Vec<&str> = Level::supported().map(Level::name).collect();
        PyValueError::new_err(format!(
            "{KERNEL_VAR} must name a kernel level this CPU supports ({}), or be unset; got {text:?}",
            supported.join(", ")
        ))
    };
    match std::env::var(KERNEL_VAR) {
        Ok(text) if !text.trim().is_empty() => match Level::from_name(text.trim()) {
            Some(level) if level.is_supported() => Ok(level),
            _ => Err(refuse(&text)),
        },
        Ok(_) | Err(std::env::VarError::NotPresent) => Ok(Level::detect()),
        Err(std::env::VarError::NotUnicode(text)) => Err(refuse(&text)),
    }
}

/// The CPUs this process may use, found once (the lookup reads cgroup files).
fn available_cpus() -> usize {
    static CPUS: OnceLock<usize> = OnceLock::new();
    *CPUS.get_or_init(|| std::thread::available_parallelism().map_or(1, NonZeroUsize::get))
}

/// batch_threads() -> int
///
/// The number of threads a batch of 4096 rows or more runs on (smaller
/// batches run on the calling thread): the environment variable
/// PARASILS_NUM_THREADS when set (a positive integer; read at each call, so
/// os.environ changes it), else the number of CPUs this process may use.
/// The results do not depend on it, bit for bit.
///
/// Raises ValueError when PARASILS_NUM_THREADS is set to anything else than
/// a positive integer (and so does every batch method then).
#[pyfunction]
pub fn batch_threads() -> PyResult<usize> {
    threads()
}

/// The first failing row and its error.
#[derive(Debug)]
pub(crate) struct Failure {
    /// The row.
    pub(crate) row: usize,
    /// Its error.
    pub(crate) error: Error,
}

impl OnError {
    /// The vector kernels' name for it.
    pub(crate) fn on_row_error(self) -> OnRowError {
        match self {
            OnError::Raise => OnRowError::Stop,
            OnError::Nan => OnRowError::Nan,
        }
    }
}

/// A vector kernel's error on a chunk as the batch's failure. The
/// bindings hand the kernels whole rows of their own arrays, so a shape
/// error is a bug of the bindings, reported (with its row) rather than a panic.
pub(crate) fn kernel_failure(error: BatchError, chunk_start: usize) -> Failure {
    match error {
        BatchError::Row { row, error } => Failure { row, error },
        _ => Failure {
            row: chunk_start,
            error: Error::InvalidParameter {
                what: "batch rows (internal: an array shorter than its rows)",
                value: chunk_start as f64,
            },
        },
    }
}

/// Consecutive rows `start..start + ok.len()` and their place in each output block.
pub(crate) struct Chunk<'a> {
    /// The first row.
    pub(crate) start: usize,
    /// The rows' values in each output block (`ok.len() * width`).
    pub(crate) blocks: Vec<&'a mut [f64]>,
    /// The rows' flags.
    pub(crate) ok: &'a mut [bool],
}

/// Row `row` by `f`: its values (`flag` set), NaN (`errors="nan"`), or the
/// failure to raise (`errors="raise"`).
#[inline]
fn row_values<const W: usize, F>(
    f: &F,
    row: usize,
    on_error: OnError,
    flag: &mut bool,
) -> Result<[f64; W], Failure>
where
    F: Fn(usize) -> Result<[f64; W], Error>,
{
    match f(row) {
        Ok(v) => {
            *flag = true;
            Ok(v)
        }
        Err(error) => match on_error {
            OnError::Raise => Err(Failure { row, error }),
            OnError::Nan => Ok([f64::NAN; W]),
        },
    }
}

/// Computes the rows of `chunk` with `f`, writing each row's `W` values
/// into the chunk's blocks (`widths`, adding up to `W`). Stops at the first
/// failing row with `errors="raise"` and returns it.
#[inline]
fn fill<const W: usize, F>(
    chunk: Chunk<'_>,
    widths: &[usize],
    on_error: OnError,
    f: &F,
) -> Option<Failure>
where
    F: Fn(usize) -> Result<[f64; W], Error>,
{
    let Chunk {
        start,
        mut blocks,
        ok,
    } = chunk;
    if let [block] = &mut blocks[..] {
        // One output: rows of exactly W values, no splitting.
        for ((k, flag), out) in ok.iter_mut().enumerate().zip(block.chunks_exact_mut(W)) {
            let values = match row_values(f, start + k, on_error, flag) {
                Ok(v) => v,
                Err(failure) => return Some(failure),
            };
            out.copy_from_slice(&values);
        }
        return None;
    }
    let mut rows: Vec<_> = blocks
        .into_iter()
        .zip(widths)
        .map(|(block, &w)| block.chunks_exact_mut(w))
        .collect();
    for (k, flag) in ok.iter_mut().enumerate() {
        let values = match row_values(f, start + k, on_error, flag) {
            Ok(v) => v,
            Err(failure) => return Some(failure),
        };
        let mut rest: &[f64] = &values;
        for out in rows.iter_mut().filter_map(Iterator::next) {
            let (head, tail) = rest.split_at(out.len());
            out.copy_from_slice(head);
            rest = tail;
        }
    }
    None
}

/// Runs `fill_chunk` on the chunks of rows `0..ok.len()`, whose outputs go
/// to `blocks` (one per block of `widths` columns, row-major) and `ok`, on
/// up to `threads` threads (see the module's documentation). Returns the
/// first failing row with `errors="raise"`.
fn compute<G>(
    mut blocks: Vec<&mut [f64]>,
    widths: &[usize],
    ok: &mut [bool],
    threads: usize,
    fill_chunk: &G,
) -> Option<Failure>
where
    G: Fn(Chunk<'_>) -> Option<Failure> + Sync,
{
    let n = ok.len();
    let threads = if n < PARALLEL_MIN_ROWS {
        1
    } else {
        threads.max(1)
    };
    let chunk_rows = if threads == 1 {
        n.max(1)
    } else {
        n.div_ceil(threads * CHUNKS_PER_THREAD)
            .clamp(MIN_CHUNK_ROWS, MAX_CHUNK_ROWS)
    };
    let mut chunks: Vec<Chunk<'_>> = ok
        .chunks_mut(chunk_rows)
        .enumerate()
        .map(|(c, ok)| Chunk {
            start: c * chunk_rows,
            blocks: Vec::with_capacity(widths.len()),
            ok,
        })
        .collect();
    for (block, &w) in blocks.iter_mut().zip(widths) {
        let block: &mut [f64] = block;
        for (chunk, part) in chunks.iter_mut().zip(block.chunks_mut(chunk_rows * w)) {
            chunk.blocks.push(part);
        }
    }
    let threads = threads.min(chunks.len());
    if threads <= 1 {
        chunks.into_iter().find_map(fill_chunk)
    } else {
        // The chunks in row order; a thread takes the next one until none is
        // left, or until the next one starts after a row known to fail.
        let queue = Mutex::new(chunks.into_iter());
        let first_failure = AtomicUsize::new(usize::MAX);
        let work = || -> Option<Failure> {
            loop {
                let chunk = queue
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .next()?;
                if chunk.start > first_failure.load(Ordering::Relaxed) {
                    return None;
                }
                if let Some(failure) = fill_chunk(chunk) {
                    // Only with errors="raise". Every chunk before this row is
                    // still computed (their start is below it), so the
                    // smallest failing row over the threads is the batch's first.
                    first_failure.fetch_min(failure.row, Ordering::Relaxed);
                    return Some(failure);
                }
            }
        };
        std::thread::scope(|scope| {
            let helpers: Vec<_> = (1..threads)
                .filter_map(|_| {
                    // A thread that cannot be spawned leaves its share to the others.
                    std::thread::Builder::new()
                        .name("parasils-batch".to_owned())
                        .spawn_scoped(scope, work)
                        .ok()
                })
                .collect();
            let mut failures = vec![work()];
            for helper in helpers {
                match helper.join() {
                    Ok(failure) => failures.push(failure),
                    Err(panic) => std::panic::resume_unwind(panic),
                }
            }
            failures.into_iter().flatten().min_by_key(|f| f.row)
        })
    }
}

/// Runs `f` on rows `0..N` (a single row when `batch` is `None`) without the
/// GIL, each row giving `W` values, and returns the Python result: the
/// output arrays (the row's values cut in blocks of columns of the given
/// `widths`, adding up to `W`), shaped `(width,)` for a single row or
/// `(N, width)`, then the mask with `errors="nan"` (a `bool` for a single
/// row). One array alone is returned as such, several as a tuple.
///
/// With `errors="raise"`, the error of the first failing row is raised,
/// its `row` set for a batch.
pub(crate) fn solve<'py, const W: usize, F>(
    py: Python<'py>,
    batch: Option<usize>,
    on_error: OnError,
    widths: &[usize],
    f: F,
) -> PyResult<Bound<'py, PyAny>>
where
    F: Fn(usize) -> Result<[f64; W], Error> + Sync,
{
    assert_eq!(
        widths.iter().sum::<usize>(),
        W,
        "output blocks must add up to a row"
    );
    run(py, batch, on_error, widths, &|chunk| {
        fill(chunk, widths, on_error, &f)
    })
}

/// [`solve`] with a function that computes a whole chunk of rows at once
/// (a vector kernel): `fill_chunk` writes the chunk's rows into its blocks
/// and flags (NaN and `false` for a failing row with `errors="nan"`), and
/// returns the first failing row with `errors="raise"`.
pub(crate) fn solve_chunks<'py, G>(
    py: Python<'py>,
    batch: Option<usize>,
    on_error: OnError,
    widths: &[usize],
    fill_chunk: G,
) -> PyResult<Bound<'py, PyAny>>
where
    G: Fn(Chunk<'_>) -> Option<Failure> + Sync,
{
    run(py, batch, on_error, widths, &fill_chunk)
}

/// What [`solve`] and [`solve_chunks`] share.
fn run<'py, G>(
    py: Python<'py>,
    batch: Option<usize>,
    on_error: OnError,
    widths: &[usize],
    fill_chunk: &G,
) -> PyResult<Bound<'py, PyAny>>
where
    G: Fn(Chunk<'_>) -> Option<Failure> + Sync,
{
    let n = batch.unwrap_or(1);
    let threads = match batch {
        Some(_) => threads()?,
        None => 1,
    };
    // The outputs are NumPy's own arrays, written in place: NumPy allocates
    // large arrays on huge pages (madvise), so the threads' first writes
    // fault a few 2 MiB pages instead of thousands of 4 KiB ones (10^6
    // rows of the instrument IK: 13.3 -> 6.7 ms, half of it page faults,
    // when the outputs came from Rust's allocator after NumPy's run).
    let arrays: Vec<Bound<'py, PyArrayDyn<f64>>> = widths
        .iter()
        .map(|&w| {
            let dims = match batch {
                Some(_) => IxDyn(&[n, w]),
                None => IxDyn(&[w]),
            };
            PyArrayDyn::<f64>::zeros(py, dims, false)
        })
        .collect();
    let ok_array = PyArray1::<bool>::zeros(py, n, false);
    let mut writers = arrays
        .iter()
        .map(|a| a.try_readwrite())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let mut ok_writer = ok_array
        .try_readwrite()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let blocks = writers
        .iter_mut()
        .map(|w| w.as_slice_mut())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let ok = ok_writer
        .as_slice_mut()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let failure = py.detach(|| compute(blocks, widths, ok, threads, fill_chunk));
    if let Some(Failure { row, error }) = failure {
        return Err(match batch {
            Some(_) => errors::kinematics(py, &error, Some(row), None, &format!("row {row}: ")),
            None => errors::kinematics(py, &error, None, None, ""),
        });
    }
    let first_ok = ok.first().copied().unwrap_or(false);
    drop(writers);
    drop(ok_writer);
    let mut items: Vec<Bound<'py, PyAny>> = arrays.into_iter().map(Bound::into_any).collect();
    if on_error == OnError::Nan {
        items.push(match batch {
            Some(_) => ok_array.into_any(),
            None => first_ok.into_pyobject(py)?.to_owned().into_any(),
        });
    }
    if items.len() == 1 {
        Ok(items.remove(0))
    } else {
        Ok(PyTuple::new(py, items)?.into_any())
    }
}
