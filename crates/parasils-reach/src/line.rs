//! The straight lines from the start ([`Cell::line`](crate::Cell::line)).
//!
//! # What is checked
//! The cell `K (a, b)` (in steps from the start, `(a, b)` with no common
//! divisor) is `line = 1` when every point `(j / n) (a, b)`, `j = 1..=K n`,
//! with `n = ceil(4 |(a, b)|)`, passes the controller's per-cycle check:
//! points no more than a quarter of a step apart, the cells `k (a, b)` on
//! the way among them (their verdicts are the map's own). The points of a
//! cell include those of every nearer cell of its ray, so each ray is
//! marched once, outward, up to its first infeasible cell: the first point
//! that fails decides every farther cell on it.
//!
//! # Points cleared by the margin
//! Most points are not evaluated. A point is cleared when it lies within
//! `m / lambda` of a cell or an evaluated point of margin `m > 0`, with
//! `lambda` a bound on how fast the normalised margin changes per step
//! there; the march jumps to the first point past the disc's chord along
//! the ray. `lambda` is local: the grid is cut into tiles of [`TILE`]
//! cells a side, and a disc drawn from a tile's bound over its neighbours 1,
//! 4 or 16 tiles away reaches no farther than those neighbours (over the
//! whole grid, no limit). Only the points no disc covers go through the
//! controller's step: a handful per ray, near the boundary. Before
//! evaluating a point that no disc covers, the march first evaluates the
//! point of the same segment (between two cells) farthest inside the first
//! run of points whose nearest cell is infeasible, when one is near: if it
//! fails, the segment fails and the ray ends there without approaching the
//! boundary point by point (a failure found at any point of a segment
//! decides the same cells as the first one).
//!
//! **The bound is estimated, not certified.** It is [`SAFETY`] times the
//! largest difference of margin between feasible neighbouring cells in the
//! tiles it covers (the norm of a cell's differences to its next cells
//! along both axes, per step). Every point evaluated also measures the
//! margin's rate of change between it and the feasible cells at the corners
//! of its square; if one exceeds the local bound, every bound is raised by
//! twice the excess and the lines are marched again (after three such
//! passes, every point is evaluated). A margin that changes faster than
//! that between the grid's points, without showing it at any point
//! evaluated, could clear a point that fails. On the paper's setup the
//! fastest rate measured at the points evaluated is about 1.25 times the
//! grid's, under a third of the bound, and the tests compare whole maps
//! with every point evaluated.

use crate::check::Checker;
use crate::map::{Cell, ReachMap};
use crate::threads::parallel_map_items;

/// The factor between the largest rate of change of the margin measured on
/// the grid and the bound the lines use.
const SAFETY: f64 = 4.0;

/// The greatest common divisor of `a` and `b`, `>= 0`.
fn gcd(mut a: i64, mut b: i64) -> i64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.abs()
}

/// The number of segments between consecutive cells of the ray `(a, b)`:
/// `ceil(4 |(a, b)|)`, so that its points are at most a quarter step apart.
fn segments(a: i64, b: i64) -> i64 {
    // Exact for any grid that fits in memory: a^2 + b^2 < 2^53.
    #[allow(clippy::cast_possible_truncation)]
    let n = (4.0 * ((a * a + b * b) as f64).sqrt()).ceil() as i64;
    n.max(1)
}

/// The point `j` of `n` per cell along the ray `(a, b)`, `[dpsi, dtheta]`,
/// rad from the start, for a grid of `step_deg`.
fn point(a: i64, b: i64, j: i64, n: i64, step_deg: f64) -> [f64; 2] {
    let t = j as f64 / n as f64;
    [
        (t * a as f64 * step_deg).to_radians(),
        (t * b as f64 * step_deg).to_radians(),
    ]
}

/// How many points ahead a probe is looked for.
const PROBE_AHEAD: i64 = 64;

/// Cells a side of the tiles the local bounds are taken over.
const TILE: usize = 8;

/// The bounds on the margin's rate of change, per step, around each tile:
/// over its neighbours 1, 4 and 16 tiles away and over the whole grid, each
/// with the radius within which it holds.
struct Bounds {
    /// Tiles per row.
    tiles: usize,
    /// Per level: the radius (cells) within which the bound holds, and the
    /// bound at each tile (with [`SAFETY`] and the scale).
    levels: Vec<(f64, Vec<f64>)>,
}

impl Bounds {
    /// The bounds of `map`, multiplied by `scale`, rows of tiles shared among
    /// `threads` threads.
    fn new(map: &ReachMap, scale: f64, threads: usize) -> Self {
        let (cols, rows) = (map.psi.count, map.theta.count);
        let (tiles, tile_rows) = (cols.div_ceil(TILE), rows.div_ceil(TILE));
        // Each tile's largest rate, a row of tiles per task.
        let rate = parallel_map_items(tile_rows, threads, |ty| {
            let mut rate = vec![0.0_f64; tiles];
            for r in ty * TILE..((ty + 1) * TILE).min(rows) {
                for c in 0..cols {
                    let here = &map.cells[map.index(c, r)];
                    if !(here.feasible && here.margin.is_finite()) {
                        continue;
                    }
                    let diff = |other: Option<&Cell>| {
                        other
                            .filter(|o| o.feasible && o.margin.is_finite())
                            .map_or(0.0, |o| o.margin - here.margin)
                    };
                    let dx = diff((c + 1 < cols).then(|| &map.cells[map.index(c + 1, r)]));
                    let dy = diff((r + 1 < rows).then(|| &map.cells[map.index(c, r + 1)]));
                    let t = &mut rate[c / TILE];
                    *t = t.max(dx.hypot(dy));
                }
            }
            rate
        })
        .concat();
        // The largest rate within `w` tiles, along the rows then along the
        // columns (the same maximum as over the square, in fewer steps).
        let around = |w: usize| {
            let mut along = vec![0.0_f64; rate.len()];
            for ty in 0..tile_rows {
                for tx in 0..tiles {
                    let row = &rate[ty * tiles..(ty + 1) * tiles];
                    along[ty * tiles + tx] = row[tx.saturating_sub(w)..(tx + w + 1).min(tiles)]
                        .iter()
                        .fold(0.0_f64, |m, &r| m.max(r));
                }
            }
            let mut out = vec![0.0_f64; rate.len()];
            for ty in 0..tile_rows {
                for tx in 0..tiles {
                    let m = (ty.saturating_sub(w)..(ty + w + 1).min(tile_rows))
                        .fold(0.0_f64, |m, y| m.max(along[y * tiles + tx]));
                    out[ty * tiles + tx] = SAFETY * scale * m;
                }
            }
            out
        };
        let all = SAFETY * scale * rate.iter().fold(0.0_f64, |a, &b| a.max(b));
        #[allow(clippy::cast_precision_loss)]
        let levels = vec![
            ((TILE - 1) as f64, around(1)),
            ((4 * TILE - 1) as f64, around(4)),
            ((16 * TILE - 1) as f64, around(16)),
            (f64::INFINITY, vec![all; rate.len()]),
        ];
        Self { tiles, levels }
    }

    /// The tile of the cell at column `c`, row `r`.
    fn tile(&self, c: usize, r: usize) -> usize {
        (r / TILE) * self.tiles + c / TILE
    }

    /// The radius (steps) a margin `m` clears around a point of the square
    /// whose lower corner is in `tile`: 0 unless `m` is positive and the
    /// bound known.
    fn radius(&self, tile: usize, m: f64) -> f64 {
        if !(m > 0.0 && m.is_finite()) {
            return 0.0;
        }
        self.levels.iter().fold(0.0, |best, (cap, bound)| {
            let b = bound[tile];
            if b > 0.0 && b.is_finite() {
                best.max((m / b).min(*cap))
            } else {
                best
            }
        })
    }

    /// The tightest bound at `tile`.
    fn local(&self, tile: usize) -> f64 {
        self.levels[0].1[tile]
    }
}

/// Each cell's disc: the radius (steps) its margin clears around it, 0 for
/// an infeasible cell, on the grid with a row and a column of zeros past its
/// last ones (a point's square may have its upper corners there).
struct Discs {
    /// Row by row, `width` a row.
    radii: Vec<f64>,
    /// Cells a row, the padding's included.
    width: usize,
    /// The `k` of the grid's first column and first row.
    k_min: (i64, i64),
}

impl Discs {
    /// The discs of `map`'s cells under `bounds` (without, every radius 0),
    /// rows shared among `threads` threads.
    fn new(map: &ReachMap, bounds: Option<&Bounds>, threads: usize) -> Self {
        let (cols, rows) = (map.psi.count, map.theta.count);
        let width = cols + 1;
        let mut radii: Vec<f64> = match bounds {
            Some(b) => parallel_map_items(rows, threads, |r| {
                (0..width)
                    .map(|c| match map.cells.get(map.index(c, r)) {
                        Some(cell) if c < cols && cell.feasible => {
                            b.radius(b.tile(c, r), cell.margin)
                        }
                        _ => 0.0,
                    })
                    .collect::<Vec<_>>()
            })
            .concat(),
            None => vec![0.0; width * rows],
        };
        radii.resize(width * (rows + 1), 0.0);
        Self {
            radii,
            width,
            k_min: (map.psi.k_min, map.theta.k_min),
        }
    }

    /// The radii at the corners of the square whose lower corner is the cell
    /// `(x, y)` (in steps from the start): `(x, y)`, `(x + 1, y)`,
    /// `(x, y + 1)`, `(x + 1, y + 1)`; 0 off the grid.
    fn corners(&self, (x, y): (i64, i64)) -> [f64; 4] {
        let (Ok(c), Ok(r)) = (
            usize::try_from(x - self.k_min.0),
            usize::try_from(y - self.k_min.1),
        ) else {
            return [0.0; 4];
        };
        if c + 1 >= self.width {
            return [0.0; 4];
        }
        let at = r * self.width + c;
        match (
            self.radii.get(at..at + 2),
            self.radii.get(at + self.width..at + self.width + 2),
        ) {
            (Some(&[r00, r10]), Some(&[r01, r11])) => [r00, r10, r01, r11],
            _ => [0.0; 4],
        }
    }
}

/// `x` rounded down (`f64::floor`, which needs a call on the x86-64
/// baseline), for `|x| < 2^62`.
#[allow(clippy::cast_possible_truncation, clippy::cast_precision_loss)]
fn floor(x: f64) -> i64 {
    let t = x as i64;
    if t as f64 > x { t - 1 } else { t }
}

/// One ray's outcome: the cells it reaches straight from the start, and
/// the largest ratio of a rate of change of the margin measured on it to
/// the local bound.
struct Ray {
    cells: Vec<usize>,
    excess: f64,
}

impl ReachMap {
    /// Fills every cell's `line` (see the [module docs](self)).
    pub(super) fn lines(
        &mut self,
        base: &Checker,
        threads: usize,
        directions: &[Option<[f64; 6]>],
    ) {
        for cell in &mut self.cells {
            cell.line = Some(false);
        }
        let start = self.start_index();
        if !self.cells[start].feasible {
            return;
        }
        self.cells[start].line = Some(true);
        let (kp, kt) = (
            [self.psi.k_min, self.psi.k_min + self.psi.count as i64 - 1],
            [
                self.theta.k_min,
                self.theta.k_min + self.theta.count as i64 - 1,
            ],
        );
        // The primitive directions (a, b) whose first cell is feasible.
        let this = &*self;
        let rays = parallel_map_items(self.theta.count, threads, |row| {
            let b = kt[0] + row as i64;
            (kp[0]..=kp[1])
                .filter(|&a| (a, b) != (0, 0) && gcd(a, b) == 1 && this.feasible_at(a, b).is_some())
                .map(|a| (a, b))
                .collect::<Vec<_>>()
        })
        .concat();
        let mut scale = 1.0;
        // Each pass keeps its result or raises the bounds; the last one
        // evaluates every point.
        for pass in 0..4 {
            let bounds = (pass < 3).then(|| Bounds::new(self, scale, threads));
            let discs = Discs::new(self, bounds.as_ref(), threads);
            let this = &*self;
            let marched = parallel_map_items(rays.len(), threads, |i| {
                let (a, b) = rays[i];
                this.march(base, a, b, bounds.as_ref(), &discs, directions)
            });
            let excess = marched.iter().fold(0.0_f64, |r, ray| r.max(ray.excess));
            if excess <= 1.0 {
                for index in marched.into_iter().flat_map(|ray| ray.cells) {
                    self.cells[index].line = Some(true);
                }
                return;
            }
            scale *= 2.0 * excess;
        }
    }

    /// The index of the cell `(a, b)` (in steps from the start), if it is on
    /// the grid and feasible.
    fn feasible_at(&self, a: i64, b: i64) -> Option<usize> {
        let (c, r) = (self.psi.index(a)?, self.theta.index(b)?);
        let index = self.index(c, r);
        self.cells[index].feasible.then_some(index)
    }

    /// The index of the cell `(a, b)` (in steps from the start), if it is on
    /// the grid.
    fn at(&self, a: i64, b: i64) -> Option<(usize, usize)> {
        Some((self.psi.index(a)?, self.theta.index(b)?))
    }

    /// Module 1's weakest direction at `p` (in steps from the start) guessed
    /// from the cells at the corners of its square that have one
    /// (`directions`, one per cell): their directions weighted bilinearly
    /// (signs turned to the first's), an error of second order in the step
    /// as the rows' extrapolation (see `grid`). A poor guess only costs the
    /// tracker's further attempts: the margin is certified either way.
    fn seed(&self, p: [f64; 2], directions: &[Option<[f64; 6]>]) -> Option<[f64; 6]> {
        let corner = (floor(p[0]), floor(p[1]));
        #[allow(clippy::cast_precision_loss)]
        let (fx, fy) = (p[0] - corner.0 as f64, p[1] - corner.1 as f64);
        let weighted = [
            (0, 0, (1.0 - fx) * (1.0 - fy)),
            (1, 0, fx * (1.0 - fy)),
            (0, 1, (1.0 - fx) * fy),
            (1, 1, fx * fy),
        ];
        let mut first = None::<[f64; 6]>;
        let mut sum = [0.0_f64; 6];
        for (dx, dy, w) in weighted {
            let Some(x) = self
                .at(corner.0 + dx, corner.1 + dy)
                .and_then(|(c, r)| directions.get(self.index(c, r)).copied().flatten())
            else {
                continue;
            };
            let reference = *first.get_or_insert(x);
            let same: f64 = x.iter().zip(&reference).map(|(a, b)| a * b).sum();
            let w = if same < 0.0 { -w } else { w };
            for (s, v) in sum.iter_mut().zip(x) {
                *s += w * v;
            }
        }
        if sum.iter().any(|&v| v != 0.0) {
            Some(sum)
        } else {
            first
        }
    }

    /// Marches the ray `(a, b)` from the start (see the [module
    /// docs](self)); without bounds, every point is evaluated. Each point
    /// evaluated starts its margin from the directions of the cells around
    /// it ([`seed`](Self::seed); `directions`, one per cell).
    fn march(
        &self,
        base: &Checker,
        a: i64,
        b: i64,
        bounds: Option<&Bounds>,
        discs: &Discs,
        directions: &[Option<[f64; 6]>],
    ) -> Ray {
        let mut out = Ray {
            cells: Vec::new(),
            excess: 0.0,
        };
        // The cells k (a, b), k = 1..=last, are on the grid and feasible.
        let mut last = 0;
        while self.feasible_at((last + 1) * a, (last + 1) * b).is_some() {
            last += 1;
        }
        if last == 0 {
            return out;
        }
        let n = segments(a, b);
        let (af, bf, nf) = (a as f64, b as f64, n as f64);
        let norm = af.hypot(bf);
        let u = [af / norm, bf / norm];
        // The distance between consecutive points, in steps.
        let ds = norm / nf;
        let end = last * n;
        // A copy of `base` of the ray's own, made at its first check.
        let mut own = None::<Checker>;
        // Every point before j passes.
        let mut j = 1;
        // The segment (between cells) last probed.
        let mut probed = None;
        while j <= end {
            // Point j, in steps from the start, and the cell at the lower
            // corner of its square.
            let p = [j as f64 * af / nf, j as f64 * bf / nf];
            let corner = (floor(p[0]), floor(p[1]));
            #[allow(clippy::cast_precision_loss)]
            let (x0, y0) = (corner.0 as f64, corner.1 as f64);
            // The farthest the discs of the cells around p clear along the ray.
            // (A chord is never negative: -1 for none.)
            let [r00, r10, r01, r11] = discs.corners(corner);
            let (x1, y1) = (x0 + 1.0, y0 + 1.0);
            let farthest = chord([p[0] - x0, p[1] - y0], u, r00)
                .max(chord([p[0] - x1, p[1] - y0], u, r10))
                .max(chord([p[0] - x0, p[1] - y1], u, r01))
                .max(chord([p[0] - x1, p[1] - y1], u, r11));
            let mut cleared = (farthest >= 0.0).then_some(farthest);
            if cleared.is_none() && j % n != 0 {
                // A point of this segment beyond infeasible cells fails
                // first: if it does, so does the segment.
                let segment = j / n;
                if probed != Some(segment)
                    && let Some(probe) = self.probe(a, b, j, (segment + 1) * n)
                {
                    probed = Some(segment);
                    let [dpsi, dtheta] = point(a, b, probe, n, self.psi.step_deg);
                    let at = [probe as f64 * af / nf, probe as f64 * bf / nf];
                    let checker = seeded(&mut own, base, self.seed(at, directions));
                    if !checker.feasible(dpsi, dtheta) {
                        j = probe;
                        break;
                    }
                }
                let [dpsi, dtheta] = point(a, b, j, n, self.psi.step_deg);
                let verdict = seeded(&mut own, base, self.seed(p, directions)).check(dpsi, dtheta);
                if !verdict.feasible() {
                    break;
                }
                if let (Some(bounds), Some((c, r))) = (bounds, self.at(corner.0, corner.1)) {
                    let tile = bounds.tile(c, r);
                    let rate = self.rate_around(p, corner, verdict.margin);
                    let local = bounds.local(tile);
                    if rate > 0.0 {
                        out.excess = out.excess.max(if local > 0.0 {
                            rate / local
                        } else {
                            f64::INFINITY
                        });
                    }
                    cleared = Some(bounds.radius(tile, verdict.margin));
                }
            }
            // Point j passes (a cell of the ray is feasible), and so does
            // every point within `cleared` of it.
            // The points within `cleared` of p: a chord is never negative,
            // so truncation is the floor.
            #[allow(clippy::cast_possible_truncation)]
            let skip = (cleared.unwrap_or(0.0) / ds).min(end as f64) as i64;
            j += skip.max(0) + 1;
        }
        // The cells k (a, b) with every point up to k n passing.
        let reached = ((j - 1) / n).min(last);
        out.cells = (1..=reached)
            .filter_map(|k| self.feasible_at(k * a, k * b))
            .collect();
        out
    }

    /// The point of the ray `(a, b)` between `from` and `to` (excluded)
    /// most likely to fail: the middle of the first run of points whose
    /// nearest cell is infeasible, if one starts within [`PROBE_AHEAD`]
    /// points.
    fn probe(&self, a: i64, b: i64, from: i64, to: i64) -> Option<i64> {
        let n = segments(a, b);
        let (af, bf, nf) = (a as f64, b as f64, n as f64);
        let infeasible = |j: i64| {
            #[allow(clippy::cast_possible_truncation)]
            let (x, y) = (
                (j as f64 * af / nf).round() as i64,
                (j as f64 * bf / nf).round() as i64,
            );
            self.at(x, y).is_some() && self.feasible_at(x, y).is_none()
        };
        let first = (from..to.min(from + PROBE_AHEAD)).find(|&j| infeasible(j))?;
        let last = (first..to).take_while(|&j| infeasible(j)).last()?;
        Some(first + (last - first) / 2)
    }

    /// The largest rate of change of the margin, per step, between a point
    /// `p` (in steps) of margin `m` and the feasible cells at the corners of
    /// its square (`corner` the lower one).
    fn rate_around(&self, p: [f64; 2], corner: (i64, i64), m: f64) -> f64 {
        if !m.is_finite() {
            return 0.0;
        }
        let mut rate = 0.0_f64;
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let (x, y) = (corner.0 + dx, corner.1 + dy);
            let Some(index) = self.feasible_at(x, y) else {
                continue;
            };
            let mc = self.cells[index].margin;
            let d = (p[0] - x as f64).hypot(p[1] - y as f64);
            if mc.is_finite() && d > 1e-9 {
                rate = rate.max((m - mc).abs() / d);
            }
        }
        rate
    }
}

/// The ray's checker (a copy of `base` made at the first call), its margin
/// tracker restarted from `seed` when there is one.
fn seeded<'c>(
    own: &'c mut Option<Checker>,
    base: &Checker,
    seed: Option<[f64; 6]>,
) -> &'c mut Checker {
    let checker = own.get_or_insert_with(|| base.clone());
    if let Some(x) = seed {
        checker.start_from(x);
    }
    checker
}

/// How far along the unit direction `u` a point at `d` from a disc's centre
/// stays inside the disc of radius `r` (never negative); -1 when it is not
/// inside.
fn chord(d: [f64; 2], u: [f64; 2], r: f64) -> f64 {
    let dd = d[0] * d[0] + d[1] * d[1];
    if !(dd < r * r) {
        return -1.0;
    }
    let du = d[0] * u[0] + d[1] * u[1];
    -du + (du * du - dd + r * r).sqrt()
}
