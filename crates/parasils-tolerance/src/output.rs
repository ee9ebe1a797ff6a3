//! A study's results as a file: CSV or Parquet, chosen by the extension,
//! one row per sample with the columns [`COLUMNS`]. Written to a temporary
//! file beside the target and renamed at the end: a failed write leaves
//! nothing behind and the previous file untouched.

use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::Arc;

use parasils_io::file::{AtomicFile, WriteError, check_bytes, written_directly};
use parquet::data_type::{BoolType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::parser::parse_message_type;

use crate::study::Results;

/// The columns, in file order.
pub const COLUMNS: [&str; 6] = [
    "sample",
    "left_tip_dev_mm",
    "right_tip_dev_mm",
    "pose_position_err_mm",
    "pose_rotation_err_deg",
    "failed",
];

/// The formats of a study's table of results (not a simulation's output
/// formats, `parasils_sim::Format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableFormat {
    /// Comma-separated text, `failed` as 0 or 1, failed rows' deviations
    /// `NaN`.
    Csv,
    /// Apache Parquet, uncompressed: `sample` INT64, the deviations DOUBLE
    /// (NaN on failed rows), `failed` BOOLEAN.
    Parquet,
}

impl TableFormat {
    /// The format of `path`'s extension (`.csv`, `.parquet`), `None` for
    /// any other.
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "csv" => Some(TableFormat::Csv),
            "parquet" => Some(TableFormat::Parquet),
            _ => None,
        }
    }
}

/// An upper bound on a row's size, bytes: CSV (the largest index, four
/// shortest round-trip doubles, the flag, separators), and uncompressed
/// Parquet (8 bytes per number, a bit for the flag, page overhead).
const fn row_bytes(format: TableFormat) -> u64 {
    match format {
        TableFormat::Csv => 20 + 4 * 25 + 7,
        TableFormat::Parquet => 48,
    }
}

/// The estimated size of a file of `rows` rows, bytes (at or above the real
/// size).
pub fn estimate_bytes(format: TableFormat, rows: u64) -> u64 {
    rows.saturating_mul(row_bytes(format))
        .saturating_add(64 * 1024)
}

/// Checks, before a study runs, that its file of `rows` rows fits: within
/// the free space of the target's file system, and within the output cap
/// (10 GB by default, as every output of the workspace) unless `force`
/// ([`check_bytes`]). A target written directly (a FIFO, a device) is not
/// checked. Returns the estimate.
///
/// # Errors
/// [`WriteError::IsFolder`], [`WriteError::NoSpace`],
/// [`WriteError::OverCap`].
pub fn check_size(
    path: &Path,
    format: TableFormat,
    rows: u64,
    force: bool,
) -> Result<u64, WriteError> {
    let estimate = estimate_bytes(format, rows);
    if written_directly(path)? {
        return Ok(estimate);
    }
    check_bytes(
        path,
        usize::try_from(rows).unwrap_or(usize::MAX),
        estimate,
        force,
    )
}

/// Writes `results` to `path` in `format`, atomically ([`AtomicFile`]).
///
/// # Errors
/// [`WriteError`]: the target is a folder, its folder cannot be written in,
/// or a write fails.
pub fn write(results: &Results, path: &Path, format: TableFormat) -> Result<(), WriteError> {
    let (atomic, file) = AtomicFile::create(path)?;
    let io = |error: std::io::Error| WriteError::Io {
        path: path.to_owned(),
        error,
    };
    let sync = file.try_clone().map_err(io)?;
    match format {
        TableFormat::Csv => {
            let mut w = BufWriter::new(file);
            write_csv(results, &mut w).map_err(io)?;
            w.flush().map_err(io)?;
        }
        TableFormat::Parquet => write_parquet(results, file)
            .map_err(|e| io(std::io::Error::other(format!("the Parquet writer: {e}"))))?,
    }
    if atomic.is_replaced() {
        sync.sync_all().map_err(io)?;
    }
    atomic.persist()?;
    Ok(())
}

/// The results as CSV text into `w`: shortest round-trip decimals.
///
/// # Errors
/// The writer's.
pub fn write_csv(results: &Results, w: &mut impl Write) -> std::io::Result<()> {
    writeln!(w, "{}", COLUMNS.join(","))?;
    for i in 0..results.len() {
        writeln!(
            w,
            "{},{:?},{:?},{:?},{:?},{}",
            results.sample[i],
            results.left_tip_dev_mm[i],
            results.right_tip_dev_mm[i],
            results.pose_position_err_mm[i],
            results.pose_rotation_err_deg[i],
            u8::from(results.failed[i])
        )?;
    }
    Ok(())
}

fn write_parquet(results: &Results, file: std::fs::File) -> parquet::errors::Result<()> {
    let schema = Arc::new(parse_message_type(
        "message tolerance {
            REQUIRED INT64 sample;
            REQUIRED DOUBLE left_tip_dev_mm;
            REQUIRED DOUBLE right_tip_dev_mm;
            REQUIRED DOUBLE pose_position_err_mm;
            REQUIRED DOUBLE pose_rotation_err_deg;
            REQUIRED BOOLEAN failed;
        }",
    )?);
    let props = Arc::new(WriterProperties::builder().build());
    let mut writer = SerializedFileWriter::new(BufWriter::new(file), schema, props)?;
    // Row groups of at most a million rows: a reader can stream a large study.
    let rows = results.len();
    let group = 1 << 20;
    let mut start = 0;
    while start < rows || (rows == 0 && start == 0) {
        let end = (start + group).min(rows);
        let mut rg = writer.next_row_group()?;
        let mut k = 0;
        while let Some(mut col) = rg.next_column()? {
            match k {
                0 => {
                    let v: Vec<i64> = results.sample[start..end]
                        .iter()
                        .map(|&s| i64::try_from(s).unwrap_or(i64::MAX))
                        .collect();
                    col.typed::<Int64Type>().write_batch(&v, None, None)?;
                }
                1..=4 => {
                    let c = [
                        &results.left_tip_dev_mm,
                        &results.right_tip_dev_mm,
                        &results.pose_position_err_mm,
                        &results.pose_rotation_err_deg,
                    ][k - 1];
                    col.typed::<DoubleType>()
                        .write_batch(&c[start..end], None, None)?;
                }
                _ => {
                    col.typed::<BoolType>()
                        .write_batch(&results.failed[start..end], None, None)?;
                }
            }
            col.close()?;
            k += 1;
        }
        rg.close()?;
        if rows == 0 {
            break;
        }
        start = end;
    }
    writer.close()?;
    Ok(())
}
