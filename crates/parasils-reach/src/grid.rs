//! The grid of `(dpsi, dtheta)` increments, each cell checked, and the
//! reachable region; the straight lines from the start are
//! [`line`](crate::line)'s.

use std::collections::VecDeque;

use parasils::kin::nalgebra::Vector3;
use parasils_sim::Scenario;

use crate::boundary;
use crate::check::Checker;
use crate::map::{Axis, Boundary, Cell, MAX_CELLS, ReachError, ReachMap, ReachOptions};
use crate::stiffness::tip_deflections;
use crate::threads::{parallel_map, threads};

impl ReachMap {
    /// The map of `scenario`'s start pose, tips and robot (its reorientation,
    /// limits and rate are not used) over `options`' grid.
    ///
    /// # Errors
    /// [`ReachError`] for an invalid grid, deflection load or scenario.
    pub fn compute(scenario: &Scenario, options: &ReachOptions) -> Result<Self, ReachError> {
        let step = options.step_deg;
        if !(step.is_finite() && step > 0.0) {
            return Err(ReachError::Step { step });
        }
        let psi = Axis::new("psi", options.psi_range_deg, step)?;
        let theta = Axis::new("theta", options.theta_range_deg, step)?;
        let cells = (psi.count as u128) * (theta.count as u128);
        if cells > MAX_CELLS as u128 {
            return Err(ReachError::TooManyCells { cells });
        }
        let load = match options.deflection_load_n {
            Some(load) if !load.iter().all(|v| v.is_finite()) => {
                return Err(ReachError::DeflectionLoad { load });
            }
            load => load.map(Vector3::from),
        };
        let stiffness = scenario.stiffness;
        let base = Checker::new(scenario)?;
        let threads = threads(options);
        let (cols, rows) = (psi.count, theta.count);
        let mut map = Self {
            options: *options,
            psi,
            theta,
            cells: Vec::new(),
            boundary: Boundary::default(),
            start_deg: [scenario.start_mm_deg[3], scenario.start_mm_deg[4]],
            module1_assumed: scenario.robot.module1.assumed,
            module1_provenance: scenario.robot.module1.provenance().to_string(),
            regions: base.regions(),
        };
        // The cells, a row per task, each with module 1's weakest direction
        // there when its check got as far as the margin (the lines' and the
        // boundary's checks start from these).
        let checked = parallel_map(rows, threads, &base, |r, checker| {
            let dtheta = theta.value_deg(r).to_radians();
            // The weakest direction two cells back, to extrapolate the next
            // one from the last (see `extrapolated`).
            let mut before = None;
            (0..cols)
                .map(|c| {
                    let last = checker.weakest();
                    if let (Some(x0), Some(x1)) = (before, last) {
                        checker.start_from(extrapolated(x0, x1));
                    }
                    before = last;
                    let margins = checker.margins();
                    let dpsi = psi.value_deg(c).to_radians();
                    let (v, deflection_mm) = match &load {
                        // The step itself only for the stiffness measure.
                        None => (checker.check(dpsi, dtheta), None),
                        Some(load) => {
                            let (v, step) = checker.check_step(dpsi, dtheta);
                            let deflection = step.and_then(|step| {
                                tip_deflections(checker.controller(), &step, load, &stiffness)
                            });
                            (v, deflection)
                        }
                    };
                    let cell = Cell {
                        feasible: v.feasible(),
                        reachable: false,
                        line: None,
                        limiting: v.limiting,
                        nearest: v.nearest,
                        margin: v.margin,
                        deflection_mm,
                    };
                    let here = checker.margins() > margins;
                    (cell, checker.weakest().filter(|_| here))
                })
                .collect::<Vec<_>>()
        });
        let mut directions = Vec::with_capacity(cols * rows);
        map.cells.reserve_exact(cols * rows);
        for (cell, direction) in checked.into_iter().flatten() {
            map.cells.push(cell);
            directions.push(direction);
        }
        map.flood_fill();
        if options.line {
            map.lines(&base, threads, &directions);
        }
        map.boundary = boundary::refine(&map, &base, threads, &directions);
        Ok(map)
    }

    /// The index of the cell at column `c`, row `r`.
    pub fn index(&self, c: usize, r: usize) -> usize {
        r * self.psi.count + c
    }

    /// The index of the start cell.
    pub fn start_index(&self) -> usize {
        self.index(self.psi.start(), self.theta.start())
    }

    /// The cell at column `c`, row `r`.
    pub fn cell(&self, c: usize, r: usize) -> Option<&Cell> {
        self.cells.get(self.index(c, r))
    }

    /// `[dpsi, dtheta]` of the cell at `index`, deg.
    pub fn increments_deg(&self, index: usize) -> [f64; 2] {
        let (c, r) = (index % self.psi.count, index / self.psi.count);
        [self.psi.value_deg(c), self.theta.value_deg(r)]
    }

    /// Marks the 4-connected feasible region that holds the start.
    fn flood_fill(&mut self) {
        let start = self.start_index();
        if !self.cells.get(start).is_some_and(|c| c.feasible) {
            return;
        }
        let (cols, rows) = (self.psi.count, self.theta.count);
        let mut queue = VecDeque::from([start]);
        self.cells[start].reachable = true;
        while let Some(i) = queue.pop_front() {
            let (c, r) = (i % cols, i / cols);
            let mut visit = |j: usize, cells: &mut Vec<Cell>| {
                if cells[j].feasible && !cells[j].reachable {
                    cells[j].reachable = true;
                    queue.push_back(j);
                }
            };
            if c > 0 {
                visit(i - 1, &mut self.cells);
            }
            if c + 1 < cols {
                visit(i + 1, &mut self.cells);
            }
            if r > 0 {
                visit(i - cols, &mut self.cells);
            }
            if r + 1 < rows {
                visit(i + cols, &mut self.cells);
            }
        }
    }

    /// The number of cells.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether the map has no cell (never: the start is always on the grid).
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
}

/// The weakest direction of module 1 at the next cell of a row, linearly
/// extrapolated from the last two cells' (`x0` then `x1`, unit, `x0`'s sign
/// turned to `x1`'s): a cell's step moves the direction by a few hundredths
/// of a radian, which the previous direction alone leaves too far to
/// certify at the first attempt (see `MarginTracker`); the extrapolation's
/// error is of second order in the step. A poor guess only costs the
/// tracker's further attempts: the margin is certified either way.
fn extrapolated(x0: [f64; 6], x1: [f64; 6]) -> [f64; 6] {
    let same: f64 = x0.iter().zip(&x1).map(|(a, b)| a * b).sum();
    let s = if same < 0.0 { -1.0 } else { 1.0 };
    core::array::from_fn(|k| 2.0 * x1[k] - s * x0[k])
}
