//! The grid of `(dpsi, dtheta)` increments, each cell checked, and the
//! reachable region and the straight lines from the start.

use core::sync::atomic::{AtomicUsize, Ordering};
use std::collections::VecDeque;

use super::boundary::{self, Boundary};
use super::check::{Checker, Constraint};
use crate::engine::SimulationError;
use crate::numbers::Num;
use crate::scenario::Scenario;

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
    /// ([`Cell::line`]); the most expensive part of a map.
    pub line: bool,
    /// Threads to use; 0 for as many as the machine has.
    pub threads: usize,
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
        }
    }
}

/// Why a map cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ReachError {
    /// The step is not a positive finite number.
    #[error("reach map: the step {} deg must be a positive finite number", Num(*step))]
    Step {
        /// The step, deg.
        step: f64,
    },
    /// A range is not finite, or does not contain 0 (the start).
    #[error(
        "reach map: the {axis} range [{}, {}] deg must be finite and contain 0 (the start)",
        Num(*min),
        Num(*max)
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
    fn new(axis: &'static str, [min, max]: [f64; 2], step: f64) -> Result<Self, ReachError> {
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
}

/// The threads to use for `options`.
fn threads(options: &ReachOptions) -> usize {
    if options.threads > 0 {
        options.threads
    } else {
        std::thread::available_parallelism().map_or(1, usize::from)
    }
}

/// Runs `work(i, &mut checker)` for `i` in `0..n` on `threads` threads, each
/// item with a fresh copy of `base` (so that a result does not depend on
/// which thread computed it), and returns the results in order.
pub(super) fn parallel_map<R: Send>(
    n: usize,
    threads: usize,
    base: &Checker,
    work: impl Fn(usize, &mut Checker) -> R + Sync,
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let mut parts: Vec<Vec<(usize, R)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads.clamp(1, n.max(1)))
            .map(|_| {
                s.spawn(|| {
                    let mut out = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= n {
                            break out;
                        }
                        let mut checker = base.clone();
                        out.push((i, work(i, &mut checker)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    let mut all: Vec<(usize, R)> = parts.drain(..).flatten().collect();
    all.sort_unstable_by_key(|(i, _)| *i);
    all.into_iter().map(|(_, r)| r).collect()
}

fn gcd(mut a: i64, mut b: i64) -> i64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.abs()
}

impl ReachMap {
    /// The map of `scenario`'s start pose, tips and robot (its reorientation,
    /// limits and rate are not used) over `options`' grid.
    ///
    /// # Errors
    /// [`ReachError`] for an invalid grid or scenario.
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
        };
        // The cells, a row per task.
        map.cells = parallel_map(rows, threads, &base, |r, checker| {
            let dtheta = theta.value_deg(r).to_radians();
            (0..cols)
                .map(|c| {
                    let v = checker.check(psi.value_deg(c).to_radians(), dtheta);
                    Cell {
                        feasible: v.feasible(),
                        reachable: false,
                        line: None,
                        limiting: v.limiting,
                        nearest: v.nearest,
                        margin: v.margin,
                    }
                })
                .collect::<Vec<_>>()
        })
        .into_iter()
        .flatten()
        .collect();
        map.flood_fill();
        if options.line {
            map.lines(&base, threads);
        }
        map.boundary = boundary::refine(&map, &base, threads);
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

    /// The straight lines from the start: each ray through the start is
    /// marched once, cell after cell, with `ceil(4 |(a, b)|) - 1` points
    /// between consecutive cells `k (a, b)` and `(k + 1) (a, b)` (in steps),
    /// so that no two checked points are more than a quarter of a step
    /// apart; the first infeasible point ends the ray, every farther cell on
    /// it is `line = 0`.
    fn lines(&mut self, base: &Checker, threads: usize) {
        for cell in &mut self.cells {
            cell.line = Some(false);
        }
        let start = self.start_index();
        if !self.cells[start].feasible {
            return;
        }
        self.cells[start].line = Some(true);
        let (psi, theta) = (self.psi, self.theta);
        let (kp, kt) = (
            [psi.k_min, psi.k_min + psi.count as i64 - 1],
            [theta.k_min, theta.k_min + theta.count as i64 - 1],
        );
        // The primitive directions (a, b), gcd 1, with (a, b) on the grid.
        let mut rays = Vec::new();
        for b in kt[0]..=kt[1] {
            for a in kp[0]..=kp[1] {
                if (a, b) != (0, 0) && gcd(a, b) == 1 {
                    rays.push((a, b));
                }
            }
        }
        let feasible: Vec<bool> = self.cells.iter().map(|c| c.feasible).collect();
        let this = &*self;
        let marched = parallel_map(rays.len(), threads, base, |i, checker| {
            let (a, b) = rays[i];
            let n = (4.0 * ((a * a + b * b) as f64).sqrt()).ceil() as i64;
            let mut out = Vec::new();
            for k in 1_i64.. {
                let (Some(c), Some(r)) = (psi.index(k * a), theta.index(k * b)) else {
                    break;
                };
                let index = this.index(c, r);
                if !feasible[index] {
                    break;
                }
                let clear = (1..n).all(|m| {
                    let t = (k - 1) as f64 + m as f64 / n as f64;
                    checker.feasible(
                        (t * a as f64 * psi.step_deg).to_radians(),
                        (t * b as f64 * theta.step_deg).to_radians(),
                    )
                });
                if !clear {
                    break;
                }
                out.push(index);
            }
            out
        });
        for index in marched.into_iter().flatten() {
            self.cells[index].line = Some(true);
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
