//! Reach maps: which camera orientations can be reached from the start pose
//! with both instrument tips held still (motion type 4, `P` and `phi`
//! fixed), over a grid of `(dpsi, dtheta)` increments.
//!
//! Each cell is checked by the per-cycle controller's own call,
//! [`Controller::step`](parasils::kin::Controller::step), with the platform
//! at rest at the cell's orientation, both instrument modules in assembly
//! mode A (as `parasils simulate` runs them): the constraints are exactly
//! those of `simulate`, module 1's parallel margin against the per-cycle
//! threshold `parallel_command` (see `docs/model.md`, *Singularities and
//! thresholds*). Actuator rate limits play no part: the map is about where
//! the platform can be, not how fast it gets there.
//!
//! For each cell, [`Cell`] holds:
//! - `feasible`: the controller's step succeeds;
//! - `limiting`: the first constraint it found violated, as a stable code
//!   ([`ReachMap::code`]: `ok`, `left.qs2.limit`, `right.out_of_reach`,
//!   `module1.q4.stroke`, `module1.q2.serial_singular`,
//!   `module1.parallel_singular`, ..., `clearance.left_right` with the
//!   robot file's clearance thresholds, `no_go.<region name>` with an
//!   anatomy, below);
//! - `margin`: the normalised margin, below;
//! - `reachable`: in the 4-connected region of feasible cells that holds
//!   the start (the views reachable by some continuous turn, at the grid's
//!   resolution);
//! - `line`: the straight reorientation from the start (what `simulate`
//!   does) feasible all the way, checked at points no more than a quarter
//!   of the step apart (see *Lines*).
//!
//! With the robot file's clearance thresholds, the shafts and the endoscope
//! (the robot file's `[bodies]`, the endoscope at the scenario's depth) are
//! built at each cell's joints and a gap between two of them below the stop
//! threshold limits the cell (`clearance.<pair>`); with an anatomy
//! (`Scenario::anatomy`, `parasils reach --anatomy FILE.toml`), the same
//! bodies' in-body parts are measured against each forbidden region, and a
//! gap below the stop threshold (`clearance_stop_mm`, 0.5 mm by default)
//! limits it (`no_go.<region name>`), as a run there would fail.
//!
//! The boundary between feasible and infeasible cells is refined by
//! bisection along each grid edge that crosses it, to [`TOLERANCE_RAD`]
//! (`1e-6` rad), and joined into polylines by marching squares
//! ([`Boundary`]); each point names the constraint violated just outside.
//!
//! # Margin
//! Each constraint's distance from its limit or threshold, divided by a
//! scale, so that every constraint reads on one axis:
//!
//! | constraint | normalised margin |
//! |---|---|
//! | joint limit (`qs1`, `qs2`, `qs3`), actuator stroke | distance to the nearer end / width of the range (0.5 in the middle, 0 on a bound) |
//! | `|cos qs2|`, module 1's serial and parallel margins | margin - threshold (they run from 0 to 1: the scale is 1) |
//! | `qs3` near the RCM | `(qs3 - threshold)` / width of `qs3`'s range (1 mm if unbounded) |
//! | clearance of a pair | `(gap - stop threshold)` / the two bodies' radii |
//! | forbidden region | `(gap - stop threshold)` / the radius of the body closest to it |
//!
//! A feasible cell's margin is the smallest over every constraint of the
//! three modules (positive, 0 on the boundary); an infeasible cell's is the
//! violated constraint's, negative by how far it is beyond: an instrument
//! out of reach continues `|cos qs2|` as `1 - |sin qs2|`, a module-1 leg out
//! of reach continues its serial margin as `-sqrt(-discriminant) / l`.
//!
//! # Lines
//! The cell `K (a, b)` (in steps, `(a, b)` with no common divisor) is
//! `line = 1` when the points `(j / n) (a, b)`, `j = 1..=K n`, with
//! `n = ceil(4 |(a, b)|)`, all pass the controller's step. Each ray from
//! the start is marched once, outward. Points near a cell or a point
//! already evaluated whose margin is large enough are not evaluated: a
//! margin `m` clears the points within `m / lambda`, with `lambda` a local
//! bound on the margin's rate of change per step. That bound is
//! **estimated** from the map's own cells (four times the largest
//! difference of margin between feasible neighbours nearby), not
//! certified; each point evaluated checks it against the cells around it,
//! and the lines are marched again with a larger bound when it is
//! exceeded. The tests hold whole maps against every point evaluated. The
//! lines then cost about a third of the rest of the map instead of some 50
//! times it.
//!
//! # Stiffness
//! With a load ([`ReachOptions::deflection_load_n`], `parasils reach
//! --deflection-load FX,FY,FZ`: the force each tip exerts on the tissue,
//! N, fixed frame), each feasible cell also gets how far each tip gives
//! way when it presses with that force, the other tip unloaded
//! ([`Cell::deflection_mm`]), with the robot file's actuator stiffnesses
//! (`[stiffness]`, assumed by default): where the robot is stiff and where
//! it is soft. The measure is the deflection at the tip, not an eigenvalue
//! of the platform's stiffness matrix (see `stiffness`'s docs: the matrix
//! mixes N/mm and N mm/rad, and leaves out the modules' own joints). It
//! costs two small linear solves per tip and cell, on the step the cell's
//! check has already made.
//!
//! # Threads
//! Rows of cells, rays and boundary edges are shared among threads
//! ([`ReachOptions::threads`]); each task starts from a fresh controller,
//! so the map does not depend on the number of threads.
//!
//! ```
//! use parasils_sim::Scenario;
//! use parasils_reach::{ReachMap, ReachOptions};
//!
//! let options = ReachOptions {
//!     psi_range_deg: [-5.0, 20.0],
//!     theta_range_deg: [-5.0, 30.0],
//!     step_deg: 5.0,
//!     ..ReachOptions::default()
//! };
//! let map = ReachMap::compute(&Scenario::paper(), &options)?;
//! // The paper's target, 15 and 25 deg from the start: straight there.
//! let c = map.psi.index(3).and_then(|c| map.theta.index(5).map(|r| map.index(c, r)));
//! assert!(c.is_some_and(|c| map.cells[c].line == Some(true)));
//! # Ok::<(), parasils_reach::ReachError>(())
//! ```
//!
//! # Modules
//! In import order (a module uses only those above it):
//!
//! | module | concept |
//! |---|---|
//! | `no_go` | the forbidden regions of the scenario's anatomy measured against the bodies' in-body parts |
//! | `check` | the per-cell check: [`Checker`] (the controller's own step at rest, the bodies' clearance and forbidden regions), [`Constraint`] (what failed, as a stable code), [`Verdict`] (feasible, limiting, normalised margin) |
//! | `stiffness` | the stiffness measure: each tip's deflection under a stated tip force at a feasible cell ([`tip_deflections`]) |
//! | `map` | the map's data: [`ReachOptions`], [`Axis`], [`Cell`], [`Boundary`], [`ReachMap`], [`ReachError`] |
//! | `threads` | rows, rays and edges shared among threads, each with a fresh controller |
//! | `boundary` | the boundary refined by bisection ([`bisect`]) and joined by marching squares |
//! | `line` | the straight lines from the start |
//! | `grid` | [`ReachMap::compute`]: the cells, the reachable region, then the lines and the boundary |
//! | [`csv`] | the map as CSV, one row per cell |
//! | [`summary`] | [`ReachSummary`]: the extents, the counts by constraint, the text |
//! | `plot` | the map as a picture (feature `plot`) |
//!
//! # Features
//! - `plot`: the map as SVG or PNG (`plot::render`), with `parasils-io`'s
//!   plot kit. Off by default: the `parasils` command turns it on, the
//!   Python bindings leave it off.

mod boundary;
mod check;
pub mod csv;
mod grid;
mod line;
mod map;
mod no_go;
#[cfg(feature = "plot")]
pub mod plot;
mod stiffness;
pub mod summary;
mod threads;

pub use boundary::{TOLERANCE_RAD, bisect};
pub use check::{Checker, Constraint, Verdict};
pub use map::{
    Axis, Boundary, BoundaryPoint, Cell, MAX_CELLS, Polyline, ReachError, ReachMap, ReachOptions,
};
pub use stiffness::tip_deflections;
pub use summary::{AxisExtent, ReachSummary};
