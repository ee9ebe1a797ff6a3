//! What went wrong with a robot file, and where.

use core::fmt;
use std::path::PathBuf;

/// What went wrong with a robot file.
///
/// The message is complete on its own (file, line, column, key, the line's
/// text, and the parser's or the kinematics' words); the underlying errors
/// are kept in the fields, not chained as `source()`, so that a report of
/// the chain does not repeat them.
///
/// # When this happens, how to handle it
/// - [`RobotFileError::Io`]: the file cannot be read or written: check the path.
/// - [`RobotFileError::Parse`]: fix the file at the line and key it names.
/// - [`RobotFileError::Invalid`]: the values parse but do not make a robot
///   (for instance a guide direction of zero length): fix the parameter it
///   names (guides and legs are counted from 0 in file order).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RobotFileError {
    /// The file could not be read or written.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },

    /// Malformed TOML, a missing, unknown or mistyped key, or a value out of
    /// its range.
    #[error("{origin}{}: {}{}", Location(*line, *column, key.as_deref()), error.message().trim_end(), Excerpt(*line, text.as_deref()))]
    Parse {
        /// The file's path, or `"robot file"` for text.
        origin: Box<str>,
        /// The line (1-based), when the parser gave a position.
        line: Option<usize>,
        /// The column (1-based, in characters), when the parser gave a position.
        column: Option<usize>,
        /// The key on that line, if the line holds one (`link_length_mm`).
        key: Option<Box<str>>,
        /// The text of that line.
        text: Option<Box<str>>,
        /// The TOML parser's error; its message says what is wrong
        /// (`missing field ...`, `invalid type ...`).
        error: Box<toml::de::Error>,
    },

    /// The values parse but do not make a valid robot.
    #[error("{origin}{}: invalid robot geometry: {error}{}", Location(*line, None, key.as_deref()), Excerpt(*line, text.as_deref()))]
    Invalid {
        /// The file's path, or `"robot file"` for text.
        origin: Box<str>,
        /// The line (1-based) of the parameter, when the file shows it.
        line: Option<usize>,
        /// The parameter's key in the file, with its table
        /// (`[[module1.guides]] #3 (q3) direction`).
        key: Option<Box<str>>,
        /// The text of that line.
        text: Option<Box<str>>,
        /// The kinematics' error, naming the parameter.
        error: parasils::kin::Error,
    },

    /// The geometry could not be written as TOML.
    #[error("cannot write the robot geometry as TOML: {0}")]
    Serialize(Box<toml::ser::Error>),
}

impl From<toml::ser::Error> for RobotFileError {
    fn from(e: toml::ser::Error) -> Self {
        RobotFileError::Serialize(Box::new(e))
    }
}

/// `", line L, column C, key `k`"` of a parse error.
struct Location<'a>(Option<usize>, Option<usize>, Option<&'a str>);

impl fmt::Display for Location<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.0 {
            write!(f, ", line {line}")?;
        }
        if let Some(column) = self.1 {
            write!(f, ", column {column}")?;
        }
        if let Some(key) = self.2 {
            write!(f, ", key `{key}`")?;
        }
        Ok(())
    }
}

/// The offending line, quoted after the message.
struct Excerpt<'a>(Option<usize>, Option<&'a str>);

impl fmt::Display for Excerpt<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.0, self.1) {
            (Some(line), Some(text)) => write!(f, "\n  {line} | {text}"),
            _ => Ok(()),
        }
    }
}
