//! The map's data: what it covers ([`ReachOptions`], [`Axis`]), its cells
//! ([`Cell`]) and the refined boundary ([`Boundary`]), gathered in
//! [`ReachMap`]. [`grid`](crate::grid) fills them, [`boundary`](crate::boundary)
//! refines the boundary.

use std::collections::HashMap;

use parasils_io::Shortest;
use parasils_sim::SimulationError;

use crate::check::Constraint;

/// The most cells a map may have (a 0.01 deg grid of 100 x 100 deg).
pub const MAX_CELLS: usize = 100_000_000;

/// What a map covers and computes, in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReachOptions {
    /// The range of `dpsi`, `[min, max]`, deg; it must contain 0.
    pub psi_range_deg: [f64; 2],
    /// The range of `dtheta`, `[min, max]`, deg; it must contain 0.
    pub theta_range_deg: [f64; 2],
    /// The grid step, deg: the cells are at whole multiples of it.
    pub step_deg: f64,
    /// Whether to check the straight line from the start to each cell
    /// ([`Cell::line`]; see the [module docs](super), *Lines*).
    pub line: bool,
    /// Threads to use; 0 for as many as the machine has.
    pub threads: usize,
    /// The stiffness measure: the force each tip exerts on the tissue, N,
    /// fixed frame, under which each feasible cell gets both tips'
    /// deflections ([`Cell::deflection_mm`]; see the crate docs,
    /// *Stiffness*); `None`: not computed.
    pub deflection_load_n: Option<[f64; 3]>,
}

impl Default for ReachOptions {
    /// `dpsi` and `dtheta` from -45 to 45 deg by 0.5 deg, with the lines,
    /// on every core.
    fn default() -> Self {
        Self {
            psi_range_deg: [-45.0, 45.0],
            theta_range_deg: [-45.0, 45.0],
            step_deg: 0.5,
            line: true,
            threads: 0,
            deflection_load_n: None,
        }
    }
}

/// Why a map cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ReachError {
    /// The stiffness measure's load is not three finite numbers.
    #[error(
        "reach map: the deflection load [{}, {}, {}] N must be three finite numbers",
        Shortest(load[0]),
        Shortest(load[1]),
        Shortest(load[2])
    )]
    DeflectionLoad {
        /// The load, N.
        load: [f64; 3],
    },
    /// The step is not a positive finite number.
    #[error("reach map: the step {} deg must be a positive finite number", Shortest(*step))]
    Step {
        /// The step, deg.
        step: f64,
    },
    /// A range is not finite, or does not contain 0 (the start).
    #[error(
        "reach map: the {axis} range [{}, {}] deg must be finite and contain 0 (the start)",
        Shortest(*min),
        Shortest(*max)
    )]
    Range {
        /// `"psi"` or `"theta"`.
        axis: &'static str,
        /// Its lower end, deg.
        min: f64,
        /// Its upper end, deg.
        max: f64,
    },
    /// The grid has more than [`MAX_CELLS`] cells.
    #[error(
        "reach map: {cells} cells is more than {MAX_CELLS}: use a coarser step or smaller ranges"
    )]
    TooManyCells {
        /// The number of cells asked for.
        cells: u128,
    },
    /// The scenario's robot, start pose or tips are invalid.
    #[error(transparent)]
    Scenario(#[from] SimulationError),
}

/// One axis of the grid: the cells at `k * step` for `k` in `k_min..=k_max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// The index of the first cell (`k_min <= 0`).
    pub k_min: i64,
    /// The number of cells.
    pub count: usize,
    /// The step, deg.
    pub step_deg: f64,
    /// `1 / step` when it is a whole number (then a cell's value is
    /// `k / (1 / step)`, which prints as people write it: `0.3`, not
    /// `0.30000000000000004`).
    per_deg: Option<f64>,
}

impl Axis {
    pub(super) fn new(
        axis: &'static str,
        [min, max]: [f64; 2],
        step: f64,
    ) -> Result<Self, ReachError> {
        if !(min.is_finite() && max.is_finite() && min <= 0.0 && max >= 0.0) {
            return Err(ReachError::Range { axis, min, max });
        }
        // A hair of slack, so that -45 / 0.5 is -90 whatever the rounding.
        let k_min = (min / step - 1e-9).ceil();
        let k_max = (max / step + 1e-9).floor();
        let count = k_max - k_min + 1.0;
        if !(count <= MAX_CELLS as f64) {
            return Err(ReachError::TooManyCells { cells: u128::MAX });
        }
        let per = 1.0 / step;
        // In range: checked just above.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        Ok(Self {
            k_min: k_min as i64,
            count: count as usize,
            step_deg: step,
            per_deg: ((per - per.round()).abs() < 1e-9 * per).then(|| per.round()),
        })
    }

    /// The value of cell `i` (from 0), deg from the start.
    pub fn value_deg(&self, i: usize) -> f64 {
        self.at_deg(self.k_min + i as i64)
    }

    /// The value of multiple `k` of the step, deg.
    pub fn at_deg(&self, k: i64) -> f64 {
        match self.per_deg {
            Some(per) => k as f64 / per,
            None => k as f64 * self.step_deg,
        }
    }

    /// The index (from 0) of the start, `k = 0`.
    pub fn start(&self) -> usize {
        usize::try_from(-self.k_min).unwrap_or(0)
    }

    /// The index (from 0) of multiple `k`, if on the grid.
    pub fn index(&self, k: i64) -> Option<usize> {
        usize::try_from(k - self.k_min)
            .ok()
            .filter(|&i| i < self.count)
    }
}

/// One cell of the map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Module 1 and both instrument modules solvable at this orientation,
    /// with the tips held, within every limit and threshold the per-cycle
    /// controller checks.
    pub feasible: bool,
    /// In the 4-connected region of feasible cells that holds the start.
    pub reachable: bool,
    /// The straight reorientation from the start to this cell feasible all
    /// the way (checked at no coarser than a quarter of the step); `None`
    /// when the lines were not computed.
    pub line: Option<bool>,
    /// The first constraint violated, or [`Constraint::Ok`].
    pub limiting: Constraint,
    /// On a feasible cell, the constraint nearest its limit.
    pub nearest: Constraint,
    /// On a feasible cell of a map with a stiffness measure
    /// ([`ReachOptions::deflection_load_n`]), how far each tip,
    /// `[left, right]`, gives way (mm) when it presses with that force, the
    /// other tip unloaded, with the robot file's actuator stiffnesses;
    /// `None` otherwise.
    pub deflection_mm: Option<[f64; 2]>,
    /// The normalised margin (positive feasible, negative infeasible).
    pub margin: f64,
}

/// A reach map: the grid's cells, row by row (`dtheta` rows, `dpsi`
/// columns), and the boundary between feasible and infeasible.
#[derive(Debug, Clone)]
pub struct ReachMap {
    /// The options it was made with.
    pub options: ReachOptions,
    /// The `dpsi` axis (columns).
    pub psi: Axis,
    /// The `dtheta` axis (rows).
    pub theta: Axis,
    /// The cells, `cells[row * psi.count + column]`.
    pub cells: Vec<Cell>,
    /// The boundary, refined by bisection.
    pub boundary: Boundary,
    /// The start's `psi` and `theta` as the user gave them, deg.
    pub start_deg: [f64; 2],
    /// Whether module 1's geometry is the assumed one.
    pub module1_assumed: bool,
    /// Where module 1's geometry comes from, as the summary says it:
    /// assumed, calibrated (with its RMS residual and poses), or measured.
    pub module1_provenance: String,
    /// The forbidden regions' names, in the anatomy file's order (empty
    /// without an anatomy): [`Constraint::NoGo`]`(i)` is the `i`-th.
    pub regions: Vec<String>,
}

impl ReachMap {
    /// `constraint`'s code, a forbidden region's with its name
    /// (`no_go.<name>`): [`Constraint::code_in`] with [`ReachMap::regions`].
    pub fn code(&self, constraint: Constraint) -> std::borrow::Cow<'static, str> {
        constraint.code_in(&self.regions)
    }

    /// Every constraint a cell of this map may name, in the order of
    /// [`Constraint::index`]: [`Constraint::with_regions`] of its regions.
    pub fn constraints(&self) -> Vec<Constraint> {
        Constraint::with_regions(self.regions.len())
    }
}

/// A point of the boundary, refined along one grid edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryPoint {
    /// The feasible end of the final bracket, `[dpsi, dtheta]`, rad from the
    /// start.
    pub inside: [f64; 2],
    /// The infeasible end, at most [`TOLERANCE_RAD`](crate::TOLERANCE_RAD) from `inside`.
    pub outside: [f64; 2],
    /// The constraint violated at `outside`.
    pub limiting: Constraint,
    /// The index of the feasible cell of the edge.
    pub cell: usize,
    /// Whether that cell is reachable from the start.
    pub reachable: bool,
}

impl BoundaryPoint {
    /// The middle of the bracket, `[dpsi, dtheta]`, deg from the start.
    pub fn deg(&self) -> [f64; 2] {
        [
            (0.5 * (self.inside[0] + self.outside[0])).to_degrees(),
            (0.5 * (self.inside[1] + self.outside[1])).to_degrees(),
        ]
    }
}

/// A polyline of the boundary: indices into [`Boundary::points`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Polyline {
    /// The points, in order.
    pub points: Vec<usize>,
    /// Whether the last point joins the first.
    pub closed: bool,
}

/// The refined boundary of a map.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Boundary {
    /// Every refined point, one per grid edge crossing the boundary.
    pub points: Vec<BoundaryPoint>,
    /// The points joined into polylines.
    pub polylines: Vec<Polyline>,
    /// The grid edge of each point: `edge -> point index` (see
    /// [`Boundary::point_on`]).
    pub(super) edges: HashMap<usize, usize>,
}
