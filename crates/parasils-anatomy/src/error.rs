//! What can be wrong with an anatomy file or a query, each error naming
//! the file, the region and the key.
//!
//! # When this happens, how to handle it
//! - [`AnatomyError::Read`], [`AnatomyError::Syntax`]: the file cannot be
//!   read or is not TOML; fix the path or the line the message gives.
//! - [`AnatomyError::Key`]: a key of a region is missing, unknown or has a
//!   bad value; the message names the region and the key.
//! - [`AnatomyError::Mesh`]: a region's mesh file cannot be used (empty,
//!   a degenerate triangle, a coordinate that is not a number); fix or
//!   re-export the mesh.
//! - [`AnatomyError::Query`]: a body's axis was not finite, or a query gave
//!   no finite distance; this is a bug upstream of the anatomy.

use core::fmt;
use std::path::PathBuf;

/// What is wrong with a region's mesh file.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum MeshProblem {
    /// The file cannot be opened or read, or is not STL/OBJ (the reader's
    /// message).
    Unreadable(String),
    /// The file's extension is neither `.stl` nor `.obj`.
    UnknownFormat,
    /// The file holds no triangle.
    Empty,
    /// A vertex coordinate is NaN or infinite.
    NonFinite {
        /// The vertex's index, from 0.
        vertex: usize,
        /// The coordinate, mm.
        value: f64,
    },
    /// A triangle has no area (two corners equal, or all three on a line).
    Degenerate {
        /// The triangle's index, from 0.
        triangle: usize,
    },
    /// A triangle names a vertex the file does not have.
    BadIndex {
        /// The triangle's index, from 0.
        triangle: usize,
    },
    /// parry refused the mesh (its message).
    Rejected(String),
}

impl fmt::Display for MeshProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshProblem::Unreadable(m) => write!(f, "cannot be read: {m}"),
            MeshProblem::UnknownFormat => f.write_str("is neither STL (.stl) nor OBJ (.obj)"),
            MeshProblem::Empty => f.write_str("has no triangle"),
            MeshProblem::NonFinite { vertex, value } => {
                write!(
                    f,
                    "vertex {vertex} has a coordinate {value} that is not a finite number"
                )
            }
            MeshProblem::Degenerate { triangle } => {
                write!(f, "triangle {triangle} is degenerate (no area)")
            }
            MeshProblem::BadIndex { triangle } => {
                write!(
                    f,
                    "triangle {triangle} names a vertex the file does not have"
                )
            }
            MeshProblem::Rejected(m) => write!(f, "was refused: {m}"),
        }
    }
}

/// Why an anatomy file cannot be used, or a query failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AnatomyError {
    /// The anatomy file cannot be read.
    #[error("anatomy file {}: cannot be read: {message}", file.display())]
    Read {
        /// The file.
        file: PathBuf,
        /// The system's message.
        message: String,
    },
    /// The anatomy file is not valid TOML, or its top level is wrong.
    #[error("anatomy file {}: {message}", file.display())]
    Syntax {
        /// The file.
        file: PathBuf,
        /// The parser's message (with the line), or what is wrong.
        message: String,
    },
    /// A key of a region is missing, unknown or has a bad value.
    #[error("anatomy file {}: region {region}: {key}: {problem}", file.display())]
    Key {
        /// The file.
        file: PathBuf,
        /// The region: its name, or `#n` (from 1) before its name is known.
        region: String,
        /// The key.
        key: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A region's mesh file cannot be used.
    #[error("anatomy file {}: region {region}: mesh {}: {problem}", file.display(), mesh.display())]
    Mesh {
        /// The anatomy file.
        file: PathBuf,
        /// The region's name.
        region: String,
        /// The mesh file.
        mesh: PathBuf,
        /// What is wrong.
        problem: MeshProblem,
    },
    /// A clearance query was given a body that is not finite, or gave no
    /// finite distance.
    #[error("anatomy: region {region}, {body}: {what}")]
    Query {
        /// The region's name.
        region: String,
        /// The body.
        body: crate::body::Body,
        /// What was not finite.
        what: &'static str,
    },
}
