//! The boundary between feasible and infeasible cells: each grid edge that
//! crosses it refined by bisection, and the points joined into polylines
//! (marching squares).

use std::collections::HashMap;

use crate::check::Checker;
use crate::map::{Boundary, BoundaryPoint, Polyline, ReachMap};
use crate::threads::parallel_map;

/// The bisection's tolerance: the bracket around a boundary point is at most
/// this wide, rad.
pub const TOLERANCE_RAD: f64 = 1e-6;

impl Boundary {
    /// The point on the edge from the cell at column `c`, row `r` to its
    /// neighbour at `c + 1` (`vertical = false`) or `r + 1` (`true`), if the
    /// boundary crosses it.
    pub fn point_on(
        &self,
        map: &ReachMap,
        c: usize,
        r: usize,
        vertical: bool,
    ) -> Option<&BoundaryPoint> {
        self.edges
            .get(&edge_id(map, c, r, vertical))
            .and_then(|&i| self.points.get(i))
    }
}

/// The id of the edge from `(c, r)` to `(c + 1, r)` or `(c, r + 1)`.
fn edge_id(map: &ReachMap, c: usize, r: usize, vertical: bool) -> usize {
    2 * map.index(c, r) + usize::from(vertical)
}

/// Bisects between a feasible point `a` and an infeasible one `b` (rad)
/// down to [`TOLERANCE_RAD`]. Each check's margin starts from module 1's
/// weakest direction guessed from the checks before it (see
/// `bisect_from`).
pub fn bisect(checker: &mut Checker, a: [f64; 2], b: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    bisect_from(checker, a, b, Vec::new())
}

/// [`bisect`] knowing module 1's weakest direction at some places of the
/// line from `a` (`t = 0`) to `b` (`t = 1`): `known`, `(t, direction)`.
/// Each check's margin starts from the direction at its `t` interpolated
/// (or extrapolated) linearly from the two nearest known ones (one alone
/// when only one is known), an error of second order in their distance,
/// which halves at each step; every check that gets as far as the margin
/// adds its direction. A poor guess only costs the tracker's further
/// attempts: the margin is certified either way, and the bracket depends
/// only on which checks pass.
fn bisect_from(
    checker: &mut Checker,
    mut a: [f64; 2],
    mut b: [f64; 2],
    mut known: Vec<(f64, [f64; 6])>,
) -> ([f64; 2], [f64; 2]) {
    let (mut ta, mut tb) = (0.0, 1.0);
    // Each halving is one check; 40 halve any grid step below the tolerance.
    for _ in 0..60 {
        if (b[0] - a[0]).hypot(b[1] - a[1]) <= TOLERANCE_RAD {
            break;
        }
        let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let t = 0.5 * (ta + tb);
        if let Some(x) = guess(&known, t) {
            checker.start_from(x);
        }
        let margins = checker.margins();
        let feasible = checker.feasible(mid[0], mid[1]);
        if checker.margins() > margins
            && let Some(x) = checker.weakest()
        {
            known.push((t, x));
        }
        if feasible {
            (a, ta) = (mid, t);
        } else {
            (b, tb) = (mid, t);
        }
    }
    (a, b)
}

/// The direction at `t` on the line through the two entries of `known`
/// nearest `t` (the second's sign turned to the first's); the nearest
/// alone when there is one.
fn guess(known: &[(f64, [f64; 6])], t: f64) -> Option<[f64; 6]> {
    let mut near: [Option<(f64, [f64; 6])>; 2] = [None, None];
    for &(s, x) in known {
        let d = (s - t).abs();
        match near {
            [Some((n0, _)), _] if d < (n0 - t).abs() => near = [Some((s, x)), near[0]],
            [Some(_), Some((n1, _))] if d >= (n1 - t).abs() => {}
            [Some(_), _] => near[1] = Some((s, x)),
            [None, _] => near[0] = Some((s, x)),
        }
    }
    match near {
        [Some((t0, x0)), Some((t1, x1))] if t1 != t0 => {
            let same: f64 = x0.iter().zip(&x1).map(|(a, b)| a * b).sum();
            let s = if same < 0.0 { -1.0 } else { 1.0 };
            let f = (t - t0) / (t1 - t0);
            Some(core::array::from_fn(|k| x0[k] + f * (s * x1[k] - x0[k])))
        }
        [Some((_, x0)), _] => Some(x0),
        [None, _] => None,
    }
}

/// The boundary of `map`, each crossing edge bisected on `threads` threads,
/// each bisection's margins started from the weakest directions of the
/// edge's cells and of the cell behind the feasible one (`directions`, one
/// per cell, where its check found one).
pub(super) fn refine(
    map: &ReachMap,
    base: &Checker,
    threads: usize,
    directions: &[Option<[f64; 6]>],
) -> Boundary {
    let (cols, rows) = (map.psi.count, map.theta.count);
    let mut edges = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let here = map.cells[map.index(c, r)].feasible;
            if c + 1 < cols && map.cells[map.index(c + 1, r)].feasible != here {
                edges.push((c, r, false));
            }
            if r + 1 < rows && map.cells[map.index(c, r + 1)].feasible != here {
                edges.push((c, r, true));
            }
        }
    }
    let rad = |index: usize| map.increments_deg(index).map(f64::to_radians);
    let points = parallel_map(edges.len(), threads, base, |i, checker| {
        let (c, r, vertical) = edges[i];
        let here = map.index(c, r);
        let there = if vertical {
            map.index(c, r + 1)
        } else {
            map.index(c + 1, r)
        };
        let (inner, outer) = if map.cells[here].feasible {
            (here, there)
        } else {
            (there, here)
        };
        // The directions of the edge's cells and of the cell beyond the
        // feasible one, away from the infeasible one, where their checks
        // found one.
        let direction = |i: usize| directions.get(i).copied().flatten();
        let behind = (2 * inner)
            .checked_sub(outer)
            .filter(|&i| i < map.cells.len() && adjacent(map, i, inner));
        let known = [
            (-1.0, behind.and_then(direction)),
            (0.0, direction(inner)),
            (1.0, direction(outer)),
        ]
        .into_iter()
        .filter_map(|(t, x)| Some((t, x?)))
        .collect();
        let (inside, outside) = bisect_from(checker, rad(inner), rad(outer), known);
        BoundaryPoint {
            inside,
            outside,
            limiting: checker.check(outside[0], outside[1]).limiting,
            cell: inner,
            reachable: map.cells[inner].reachable,
        }
    });
    let ids: HashMap<usize, usize> = edges
        .iter()
        .enumerate()
        .map(|(i, &(c, r, v))| (edge_id(map, c, r, v), i))
        .collect();
    let polylines = polylines(map, &ids);
    Boundary {
        points,
        polylines,
        edges: ids,
    }
}

/// Whether the cells `i` and `j` are neighbours along a row or a column
/// (so that `2 i - j` did not wrap around a row's end).
fn adjacent(map: &ReachMap, i: usize, j: usize) -> bool {
    let cols = map.psi.count;
    let (ci, ri, cj, rj) = (i % cols, i / cols, j % cols, j / cols);
    ci.abs_diff(cj) + ri.abs_diff(rj) == 1
}

/// Marching squares: in each square of four cells, the crossing edges
/// paired into segments (at a saddle, each feasible corner cut off on its
/// own, as the 4-connected regions are), then the segments chained.
fn polylines(map: &ReachMap, ids: &HashMap<usize, usize>) -> Vec<Polyline> {
    let (cols, rows) = (map.psi.count, map.theta.count);
    let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut link = |a: usize, b: usize| {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    };
    let feasible = |c: usize, r: usize| map.cells[map.index(c, r)].feasible;
    for r in 0..rows.saturating_sub(1) {
        for c in 0..cols.saturating_sub(1) {
            // Corners: bottom-left, bottom-right, top-right, top-left.
            let f = [
                feasible(c, r),
                feasible(c + 1, r),
                feasible(c + 1, r + 1),
                feasible(c, r + 1),
            ];
            if f.iter().all(|&v| v == f[0]) {
                // No crossing: most squares.
                continue;
            }
            // Sides: bottom, right, top, left (side k joins corners k, k+1).
            let side = [
                edge_id(map, c, r, false),
                edge_id(map, c + 1, r, true),
                edge_id(map, c, r + 1, false),
                edge_id(map, c, r, true),
            ];
            let crossing: Vec<usize> = (0..4).filter(|&k| f[k] != f[(k + 1) % 4]).collect();
            match crossing.as_slice() {
                [a, b] => link(ids[&side[*a]], ids[&side[*b]]),
                [_, _, _, _] => {
                    // A saddle: cut off each feasible corner k (its sides
                    // k - 1 and k).
                    for k in (0..4).filter(|&k| f[k]) {
                        link(ids[&side[(k + 3) % 4]], ids[&side[k]]);
                    }
                }
                _ => {}
            }
        }
    }
    let mut seen = vec![false; ids.len()];
    let mut out = Vec::new();
    let walk = |start: usize, seen: &mut Vec<bool>| {
        let mut line = vec![start];
        seen[start] = true;
        let mut at = start;
        loop {
            let step = next
                .get(&at)
                .and_then(|n| n.iter().copied().find(|&p| !seen[p]));
            match step {
                Some(p) => {
                    seen[p] = true;
                    line.push(p);
                    at = p;
                }
                None => break,
            }
        }
        let closed = line.len() > 2 && next.get(&at).is_some_and(|n| n.contains(&start));
        Polyline {
            points: line,
            closed,
        }
    };
    // Open lines first (from their ends on the grid's border), then loops.
    let mut order: Vec<usize> = (0..ids.len()).collect();
    order.sort_by_key(|p| next.get(p).map_or(0, Vec::len) != 1);
    for p in order {
        if !seen[p] {
            out.push(walk(p, &mut seen));
        }
    }
    out
}
