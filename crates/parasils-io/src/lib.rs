//! The plumbing the parasils crates share, in one small crate so that none
//! of them borrows another's: files written atomically, numbers in
//! messages, a seeded random generator, and the plot kit.
//!
//! # Modules
//! In import order (a module uses only those above it; none uses another):
//!
//! | module | concept |
//! |---|---|
//! | [`numbers`] | numbers in messages, readable whatever their size: [`Shortest`] (every digit a value needs to read back the same), [`Fixed`] (a set count of decimals), [`AtTime`] (`at t = 1.234 s: `) |
//! | [`rng`] | [`Rng`]: SplitMix64, the same numbers from the same seed on every platform |
//! | [`file`](mod@file) | [`AtomicFile`]: a temporary file beside the target, renamed on success; stale temporary files of dead processes removed; a writer's size estimate checked against the free space and a 10 GB cap ([`file::check_bytes`]) |
//! | `plot` | the plot kit (feature `plot`): the embedded font, the image formats, SVG or PNG from any `Figure`, legend rows, the palette |
//!
//! ```
//! use std::io::Write;
//!
//! use parasils_io::AtomicFile;
//!
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("out.csv");
//! let (file, mut handle) = AtomicFile::create(&path)?;
//! handle.write_all(b"t_s\n0.0\n")?;
//! assert!(!path.exists()); // written under a temporary name until now
//! file.persist()?;
//! assert_eq!(std::fs::read_to_string(&path)?, "t_s\n0.0\n");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Features
//! - `plot`: the plot kit, with plotters, a PNG encoder and the DejaVu Sans
//!   font embedded. Off by default: the Python bindings leave it off.

pub mod file;
pub mod numbers;
#[cfg(feature = "plot")]
pub mod plot;
pub mod rng;

pub use file::{AtomicFile, Bytes, WriteError};
pub use numbers::{AtTime, Fixed, Shortest};
#[cfg(feature = "plot")]
pub use plot::{Figure, ImageFormat, PlotError};
pub use rng::Rng;
