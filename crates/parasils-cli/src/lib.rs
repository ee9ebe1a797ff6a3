//! The library behind the `parasils` command: the simulation engine and its
//! writers, shared by the binary and the Python bindings so that both give
//! the same numbers to the last bit.
//!
//! Data flows one way: a [`scenario::Scenario`] is planned into a
//! [`simulate::Simulation`], whose samples ([`sample::Sample`]) stream into
//! [`sample::Sink`]s: the [`csv`] and [`mcap`] writers, the [`plot`], the
//! [`summary`]. Nothing holds the whole run in memory.
//!
//! The robot's geometry (module 1 and both instrument modules, with their
//! limits) is read from and written to TOML by [`robot_file`], where the
//! standard library is; the kinematics crate only derives `serde`. Module 1's
//! default geometry is **assumed** (its real dimensions are not published):
//! `robots/default.toml` holds it, with `assumed = true`, for users to copy
//! and edit.
//!
//! ```
//! use parasils_cli::scenario::Scenario;
//! use parasils_cli::simulate::Simulation;
//!
//! let sim = Simulation::new(Scenario::paper())?;
//! assert_eq!(sim.sample_count(), 4501);
//! let last = sim.samples().last().expect("samples")?;
//! assert_eq!(last.t, 4.5);
//! assert!(last.left.tip_err < 1e-9);
//! # Ok::<(), parasils_cli::simulate::SimulationError>(())
//! ```

pub mod cli;
pub mod csv;
pub mod mcap;
pub mod plot;
pub mod pose_cmd;
pub mod robot_file;
pub mod sample;
pub mod scenario;
pub mod simulate;
pub mod summary;
