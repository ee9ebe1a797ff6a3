//! What a reach map says in a few lines: the reachable region's extent, and
//! the constraints met on its boundary.

use core::fmt::Write;
use std::collections::BTreeMap;

use parasils_io::{Fixed, Shortest};

use crate::check::Constraint;
use crate::map::ReachMap;

/// The reachable region's extent along one axis through the start: how far
/// the camera turns about that axis alone before the first infeasible cell,
/// refined on the boundary where there is one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisExtent {
    /// The farthest reachable increment below 0, deg (the grid's end if
    /// nothing stops it there).
    pub min_deg: f64,
    /// What stops it below 0 (`None` at the grid's end).
    pub min_limiting: Option<Constraint>,
    /// The farthest reachable increment above 0, deg.
    pub max_deg: f64,
    /// What stops it above 0.
    pub max_limiting: Option<Constraint>,
}

/// A reach map's summary.
#[derive(Debug, Clone, PartialEq)]
pub struct ReachSummary {
    /// Cells in all, feasible, reachable, with a feasible straight line.
    pub counts: [usize; 4],
    /// The bounding box of the reachable cells: `[[dpsi min, max],
    /// [dtheta min, max]]`, deg.
    pub reachable_box_deg: Option<[[f64; 2]; 2]>,
    /// Along `dpsi` with `dtheta = 0`.
    pub psi_axis: Option<AxisExtent>,
    /// Along `dtheta` with `dpsi = 0`.
    pub theta_axis: Option<AxisExtent>,
    /// The constraints violated just outside the reachable region's
    /// boundary, with how many refined boundary points each.
    pub boundary_constraints: Vec<(Constraint, usize)>,
    /// With a stiffness measure, each tip's deflection over the reachable
    /// cells, `[left, right]`, each `[least, most]`, mm.
    pub deflection_mm: Option<[[f64; 2]; 2]>,
}

impl ReachSummary {
    /// The summary of `map`.
    pub fn of(map: &ReachMap) -> Self {
        let mut counts = [map.len(), 0, 0, 0];
        let mut bbox: Option<[[f64; 2]; 2]> = None;
        for (i, c) in map.cells.iter().enumerate() {
            counts[1] += usize::from(c.feasible);
            counts[2] += usize::from(c.reachable);
            counts[3] += usize::from(c.line == Some(true));
            if c.reachable {
                let [p, t] = map.increments_deg(i);
                let b = bbox.get_or_insert([[p, p], [t, t]]);
                b[0] = [b[0][0].min(p), b[0][1].max(p)];
                b[1] = [b[1][0].min(t), b[1][1].max(t)];
            }
        }
        let mut deflection_mm: Option<[[f64; 2]; 2]> = None;
        for d in map
            .cells
            .iter()
            .filter(|c| c.reachable)
            .filter_map(|c| c.deflection_mm)
        {
            let range = deflection_mm.get_or_insert([[d[0]; 2], [d[1]; 2]]);
            for (r, v) in range.iter_mut().zip(d) {
                *r = [r[0].min(v), r[1].max(v)];
            }
        }
        let mut met: BTreeMap<usize, (Constraint, usize)> = BTreeMap::new();
        for p in map.boundary.points.iter().filter(|p| p.reachable) {
            met.entry(p.limiting.index()).or_insert((p.limiting, 0)).1 += 1;
        }
        let mut boundary_constraints: Vec<_> = met.into_values().collect();
        boundary_constraints.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.index().cmp(&b.0.index())));
        let started = map.cells[map.start_index()].reachable;
        Self {
            counts,
            reachable_box_deg: bbox,
            psi_axis: started.then(|| axis_extent(map, false)),
            theta_axis: started.then(|| axis_extent(map, true)),
            boundary_constraints,
            deflection_mm,
        }
    }

    /// The summary as text, for people.
    pub fn text(&self, map: &ReachMap) -> String {
        let mut s = String::new();
        let [all, feasible, reachable, line] = self.counts;
        let o = &map.options;
        let _ = writeln!(
            s,
            "reach map: dpsi {} to {} deg, dtheta {} to {} deg, step {} deg, from psi = {} deg, theta = {} deg",
            Shortest(map.psi.value_deg(0)),
            Shortest(map.psi.value_deg(map.psi.count - 1)),
            Shortest(map.theta.value_deg(0)),
            Shortest(map.theta.value_deg(map.theta.count - 1)),
            Shortest(o.step_deg),
            Shortest(map.start_deg[0]),
            Shortest(map.start_deg[1]),
        );
        let _ = write!(
            s,
            "cells: {all}, feasible {feasible}, reachable {reachable}"
        );
        if o.line {
            let _ = write!(s, ", straight from the start {line}");
        }
        s.push('\n');
        match self.reachable_box_deg {
            None => {
                let start = &map.cells[map.start_index()];
                let _ = writeln!(
                    s,
                    "the start itself is infeasible: {}",
                    map.code(start.limiting)
                );
            }
            Some([p, t]) => {
                let _ = writeln!(
                    s,
                    "reachable region: dpsi {} to {} deg, dtheta {} to {} deg (grid cells)",
                    Shortest(p[0]),
                    Shortest(p[1]),
                    Shortest(t[0]),
                    Shortest(t[1])
                );
            }
        }
        for (name, axis) in [("dpsi", &self.psi_axis), ("dtheta", &self.theta_axis)] {
            if let Some(a) = axis {
                let why =
                    |c: Option<Constraint>| c.map_or("end of the grid".into(), |c| map.code(c));
                let _ = writeln!(
                    s,
                    "{name} alone: {} deg ({}) to {} deg ({})",
                    Fixed(a.min_deg, 4),
                    why(a.min_limiting),
                    Fixed(a.max_deg, 4),
                    why(a.max_limiting)
                );
            }
        }
        if !self.boundary_constraints.is_empty() {
            let _ = writeln!(
                s,
                "limiting constraints on the reachable region's boundary:"
            );
            for (c, n) in &self.boundary_constraints {
                let _ = writeln!(s, "  {:<28} {n} points", map.code(*c));
            }
        }
        if let (Some([l, r]), Some(f)) = (self.deflection_mm, o.deflection_load_n) {
            let _ = writeln!(
                s,
                "tip deflection pressing with ({}, {}, {}) N, over the reachable cells: left {} to {} mm, right {} to {} mm",
                Shortest(f[0]),
                Shortest(f[1]),
                Shortest(f[2]),
                Fixed(l[0], 4),
                Fixed(l[1], 4),
                Fixed(r[0], 4),
                Fixed(r[1], 4)
            );
        }
        if map.module1_assumed || map.module1_provenance.starts_with("calibrated") {
            let _ = writeln!(s, "module 1: {}", map.module1_provenance);
        }
        s
    }
}

/// The extent along `dpsi` (`vertical = false`) or `dtheta` through the
/// start.
fn axis_extent(map: &ReachMap, vertical: bool) -> AxisExtent {
    let (c0, r0) = (map.psi.start(), map.theta.start());
    let axis = if vertical { &map.theta } else { &map.psi };
    let at = |k: usize| {
        if vertical { (c0, k) } else { (k, r0) }
    };
    let reachable = |k: usize| {
        let (c, r) = at(k);
        map.cell(c, r).is_some_and(|c| c.reachable)
    };
    let start = if vertical { r0 } else { c0 };
    let side = |up: bool| {
        let mut k = start;
        loop {
            let next = if up { k + 1 } else { k.wrapping_sub(1) };
            if next >= axis.count {
                return (axis.value_deg(k), None);
            }
            if !reachable(next) {
                let (c, r) = at(k.min(next));
                let point = map.boundary.point_on(map, c, r, vertical);
                return match point {
                    Some(p) => (p.deg()[usize::from(vertical)], Some(p.limiting)),
                    None => (axis.value_deg(k), None),
                };
            }
            k = next;
        }
    };
    let (min_deg, min_limiting) = side(false);
    let (max_deg, max_limiting) = side(true);
    AxisExtent {
        min_deg,
        min_limiting,
        max_deg,
        max_limiting,
    }
}
