//! What can go wrong while writing an MCAP file.

use parasils_io::Shortest;

/// What can go wrong while writing an MCAP file.
///
/// When this happens, the file is incomplete (no summary): discard it.
/// [`OutputFile`](crate::output::OutputFile) writes to a temporary file and
/// renames it only on success.
///
/// Each message is complete on its own: the underlying errors are in the
/// text, not chained as `source()`, so that a report of the chain does not
/// repeat them.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum McapError {
    /// The MCAP library failed, most often an I/O error of the writer.
    #[error("MCAP: {}", mcap_text(.0))]
    Mcap(mcap::McapError),
    /// The robot's geometry is invalid (the scene cannot be drawn).
    #[error("robot geometry: {0}")]
    Geometry(parasils::kin::Error),
    /// The scenario or the geometry could not be turned into JSON.
    #[error("scenario to JSON: {0}")]
    Json(serde_json::Error),
    /// A value is NaN or infinite: JSON has no such number, and the schema
    /// asks for one.
    #[error("{field} = {} on {topic} at t = {} s: JSON numbers must be finite", Shortest(*value), Shortest(*t))]
    NonFinite {
        /// The channel.
        topic: &'static str,
        /// The field (or the part of a 3D message).
        field: &'static str,
        /// The record's time, s.
        t: f64,
        /// The value.
        value: f64,
    },
    /// A record's time is negative, non-finite or too large for a `u64` of
    /// nanoseconds.
    #[error("sample time t = {} s cannot be a log time (finite, >= 0, < 1.8e10 s)", Shortest(*t))]
    InvalidTime {
        /// The record's time, s.
        t: f64,
    },
    /// A record's time is not after the previous record's, to the
    /// nanosecond: log times must increase strictly on each channel.
    #[error("sample time t = {} s is not after the previous sample's, {} s (to the ns)", Shortest(*t), Shortest(*previous))]
    TimeNotIncreasing {
        /// The record's time, s.
        t: f64,
        /// The previous record's time, s.
        previous: f64,
    },
    /// An option is out of range.
    #[error("MCAP option {what} = {} is invalid", Shortest(*value))]
    InvalidOption {
        /// The option.
        what: &'static str,
        /// Its value.
        value: f64,
    },
}

/// The MCAP library's message; for an I/O error, the operating system's
/// (which the library keeps as the source).
fn mcap_text(e: &mcap::McapError) -> String {
    match e {
        mcap::McapError::Io(io) => io.to_string(),
        other => other.to_string(),
    }
}

impl From<mcap::McapError> for McapError {
    fn from(e: mcap::McapError) -> Self {
        McapError::Mcap(e)
    }
}

impl From<serde_json::Error> for McapError {
    fn from(e: serde_json::Error) -> Self {
        McapError::Json(e)
    }
}

impl McapError {
    /// The I/O error underneath, if any (the writer's).
    pub fn io_error(&self) -> Option<&std::io::Error> {
        match self {
            McapError::Mcap(mcap::McapError::Io(e)) => Some(e),
            _ => None,
        }
    }

    /// An I/O error of the MCAP writer with this message.
    pub(crate) fn io(message: &str) -> Self {
        McapError::Mcap(std::io::Error::other(message.to_owned()).into())
    }
}
