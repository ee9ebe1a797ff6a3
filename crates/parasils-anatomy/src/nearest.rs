//! The distance from a segment (a body's axis) to a triangle mesh, mm:
//! parry's bounding-volume hierarchy of the mesh walked with lower bounds of
//! the segment's own, each triangle left measured in closed form.
//!
//! # The node bounds
//! parry's own shape-to-mesh distance bounds each node by the shape's
//! axis-aligned box, which for a long slanted shaft covers much of an
//! organ; and a node's own axis-aligned box is a poor fit for a patch of
//! surface that is not aligned with the axes (a 2 mm patch tilted at 45 deg
//! fills a box 1.4 mm thick). Each node is bounded here by the larger of
//! two lower bounds. Projection onto a unit axis is 1-Lipschitz, so the gap
//! between the segment's and the node's projections onto any unit axis is
//! a lower bound of their distance:
//! - **the boxes**: the distance between the segment's axis-aligned box and
//!   the node's (the three axis gaps, orthogonal, combined in a norm; exact
//!   for a node straight below a segment's end, so that triangles tied at a
//!   shared vertex are skipped);
//! - **the patch**: each node also holds a cylinder around its triangles
//!   ([`Hierarchy`]: axis `nu` the patch's mean normal, radius `rho` across
//!   it, half-height `tau` along it, centred on the node's box). Along the
//!   direction `n` from the segment's point `q` closest to the centre `c`
//!   to `c`, every point of the segment lies below `q . n` and the cylinder
//!   above `c . n - rho |n x nu| - tau |n . nu|`: the gap between is
//!   `|c - q| - rho |n x nu| - tau |n . nu|`, nearly the distance for a
//!   patch facing the segment whatever its tilt.
//!
//! # The triangles
//! The distance `f(s)` from the segment's point `a + s (b - a)` to a
//! triangle is convex in `s`, with slope `(p - q) . (b - a) / f` at a point
//! `p` whose nearest point of the triangle is `q`. So when the slope at an
//! end points away from the triangle, that end is the closest point and
//! one projection (parry's) gives the distance: the common case of a shaft
//! whose tip is nearest an organ. Otherwise the minimum is inside the
//! segment: 0 where the segment crosses the triangle (parry's ray cast),
//! else the smallest of the ends' distances and the segment's distances to
//! the three edges (`parasils_kin`'s closed-form segment kernel).
//!
//! # Exact, whatever the start
//! The walk returns the smallest distance over every triangle: a node is
//! skipped only when its bound is not below a distance already found, and a
//! bound is never above the distance of a triangle inside its node. The
//! start only seeds the best distance found: the triangle nearest at the
//! previous cycle (a warm start), else the first triangle reached by
//! descending from the root into the child of smaller box bound.

use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{BvhNode, BvhNodeIndex, TraversalAction};
use parry3d_f64::query::{PointQuery, PointQueryWithLocation, Ray, RayCast};
use parry3d_f64::shape::{TriMesh, Triangle, TrianglePointLocation};

use parasils_kin::{Segment, segment_distance};

/// A segment, with what every node bound of one walk shares.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Axis {
    a: Vector,
    b: Vector,
    lo: Vector,
    hi: Vector,
}

impl Axis {
    /// The segment `a`-`b`.
    pub(crate) fn new(a: Vector, b: Vector) -> Self {
        Self {
            a,
            b,
            lo: a.min(b),
            hi: a.max(b),
        }
    }

    /// The point of the segment closest to `p`.
    fn closest(&self, p: Vector) -> Vector {
        let d = self.b - self.a;
        let len2 = d.length_squared();
        let s = if len2 > 0.0 {
            ((p - self.a).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.a + d * s
    }

    /// The distance between the segment's axis-aligned box and the box
    /// `mins`-`maxs`: a lower bound of the segment's distance to it.
    pub(crate) fn box_bound(&self, mins: Vector, maxs: Vector) -> f64 {
        (mins - self.hi)
            .max(self.lo - maxs)
            .max(Vector::ZERO)
            .length()
    }

    /// A lower bound of the distance between the segment and the box
    /// `mins`-`maxs`: their separation along the direction from the
    /// segment's point closest to the box's centre to the centre (the
    /// patch bound of the box's own axes, half-extents `h`: `|c - q| - h .
    /// |n|`).
    fn direction_bound(&self, mins: Vector, maxs: Vector) -> f64 {
        let (c, h) = ((mins + maxs) * 0.5, (maxs - mins) * 0.5);
        let w = c - self.closest(c);
        let dist = w.length();
        if dist > 0.0 {
            dist - h.dot(w.abs()) / dist
        } else {
            0.0
        }
    }

    /// A lower bound of the distance between the segment and the cylinder
    /// `patch` centred at `c` (see the [module docs](self)).
    fn patch_bound(&self, c: Vector, patch: &Patch) -> f64 {
        let w = c - self.closest(c);
        let dist = w.length();
        if dist > 0.0 {
            dist - (patch.rho * w.cross(patch.nu).length() + patch.tau * w.dot(patch.nu).abs())
                / dist
        } else {
            0.0
        }
    }

    /// The distance between the segment and `triangle`, and the point of
    /// the segment where it is reached (see the [module docs](self));
    /// `None` for a coordinate that is not finite.
    pub(crate) fn triangle(&self, triangle: &Triangle) -> Option<(f64, Vector)> {
        let (a, b) = (self.a, self.b);
        let along = b - a;
        let end = |p: Vector, away: Vector| {
            let off = p - triangle.project_local_point(p, true).point;
            (off.length(), off.dot(away) >= 0.0)
        };
        let (da, a_nearest) = end(a, along);
        if !da.is_finite() {
            return None;
        }
        if a_nearest || da == 0.0 {
            return Some((da, a));
        }
        let (db, b_nearest) = end(b, -along);
        if b_nearest || db == 0.0 {
            return db.is_finite().then_some((db, b));
        }
        if let Some(toi) = triangle.cast_local_ray(&Ray::new(a, along), 1.0, true) {
            return Some((0.0, a + along * toi));
        }
        let to_nalgebra = |v: Vector| nalgebra::Vector3::new(v.x, v.y, v.z);
        let axis = Segment::new(to_nalgebra(a), to_nalgebra(b));
        let mut best = if da <= db { (da, a) } else { (db, b) };
        for (p, q) in [
            (triangle.a, triangle.b),
            (triangle.b, triangle.c),
            (triangle.c, triangle.a),
        ] {
            let edge = Segment::new(to_nalgebra(p), to_nalgebra(q));
            let c = segment_distance(&axis, &edge).ok()?;
            if c.distance < best.0 {
                let p = c.point_a;
                best = (c.distance, Vector::new(p.x, p.y, p.z));
            }
        }
        best.0.is_finite().then_some(best)
    }
}

/// A cylinder around a node's triangles: axis `nu` (unit), radius `rho`
/// across it, half-height `tau` along it, centred on the node's box.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Patch {
    nu: Vector,
    rho: f64,
    tau: f64,
}

impl Patch {
    /// The cylinder centred at `c` around `triangles`: its axis their
    /// area-weighted mean normal (`z` where they cancel, as on a closed
    /// surface), its radius and half-height the largest distances of their
    /// corners from `c` across and along it, each widened by a relative
    /// 1e-12 against rounding.
    fn around(c: Vector, triangles: &[Triangle]) -> Self {
        let sum = triangles
            .iter()
            .fold(Vector::ZERO, |s, t| s + t.scaled_normal());
        let nu = sum.try_normalize().unwrap_or(Vector::Z);
        let (mut rho, mut tau) = (0.0_f64, 0.0_f64);
        for v in triangles.iter().flat_map(|t| [t.a, t.b, t.c]) {
            let r = v - c;
            rho = rho.max(r.cross(nu).length());
            tau = tau.max(r.dot(nu).abs());
        }
        let widen = |x: f64| x * (1.0 + 1e-12) + 1e-12;
        Self {
            nu,
            rho: widen(rho),
            tau: widen(tau),
        }
    }
}

/// parry's hierarchy of a mesh, each node with a cylinder around its
/// triangles ([`Patch`]), indexed as parry indexes its nodes
/// (`BvhNodeIndex`). Built once with the mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Hierarchy {
    patches: Vec<Patch>,
}

impl Hierarchy {
    /// The cylinders of every node of `mesh`'s hierarchy, each around the
    /// node's triangles and centred on its box ([`Patch::around`]).
    pub(crate) fn new(mesh: &TriMesh) -> Self {
        let bvh = mesh.bvh();
        let mut nodes = Vec::new();
        bvh.traverse_indexed(None, |node, index| {
            nodes.push((index, node.center()));
            TraversalAction::Continue
        });
        let size = nodes.iter().map(|(i, _)| i.0 + 1).max().unwrap_or(0);
        let loose = Patch {
            nu: Vector::Z,
            rho: f64::INFINITY,
            tau: f64::INFINITY,
        };
        let mut patches = vec![loose; size];
        let mut under = Vec::new();
        for &(index, c) in &nodes {
            under.clear();
            bvh.traverse_indexed(Some(index), |node, _| {
                if let Some(t) = node.leaf_data() {
                    under.push(mesh.triangle(t));
                }
                TraversalAction::Continue
            });
            patches[index.0] = Patch::around(c, &under);
        }
        Self { patches }
    }

    fn patch(&self, index: BvhNodeIndex) -> Option<&Patch> {
        self.patches.get(index.0)
    }
}

/// The triangle of a mesh nearest a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Nearest {
    /// Its index in the mesh.
    pub(crate) triangle: u32,
    /// The distance between the segment and it, mm, or `floor` when it is
    /// below `floor` (see [`nearest`]).
    pub(crate) distance: f64,
    /// The point of the segment nearest it, mm.
    pub(crate) point: Vector,
}

/// The triangle of `mesh` nearest the segment `axis`, and the distance
/// between them, the walk seeded from `hint` (a triangle index, the nearest
/// at the previous cycle; any index, or none, gives the same distance).
/// Distances below `floor` (a body's radius: any distance below it is an
/// overlap) count as `floor`, so the walk ends at the first triangle within
/// it. `None` when no triangle gives a finite distance.
pub(crate) fn nearest(
    mesh: &TriMesh,
    hierarchy: &Hierarchy,
    axis: &Axis,
    floor: f64,
    hint: Option<u32>,
) -> Option<Nearest> {
    let measure = |id: u32| {
        axis.triangle(&mesh.triangle(id)).map(|(d, point)| Nearest {
            triangle: id,
            distance: d.max(floor),
            point,
        })
    };
    let seed = match hint.filter(|&id| (id as usize) < mesh.num_triangles()) {
        Some(id) => measure(id),
        None => dive(mesh, axis, floor),
    };
    let mut best = seed;
    let bvh = mesh.bvh();
    bvh.traverse_indexed(None, |node: &BvhNode, index| {
        let limit = best.map_or(f64::INFINITY, |b| b.distance);
        if axis.box_bound(node.mins(), node.maxs()).max(floor) >= limit {
            return TraversalAction::Prune;
        }
        if let Some(id) = node.leaf_data() {
            if let Some(found) = measure(id).filter(|f| f.distance < limit) {
                best = Some(found);
            }
            return TraversalAction::Prune;
        }
        match hierarchy.patch(index) {
            Some(patch) if axis.patch_bound(node.center(), patch).max(floor) >= limit => {
                TraversalAction::Prune
            }
            _ => TraversalAction::Continue,
        }
    });
    best
}

/// The first triangle reached from the root by always entering the child of
/// smaller box bound: a first distance, near the smallest, for a walk with
/// no warm start.
fn dive(mesh: &TriMesh, axis: &Axis, floor: f64) -> Option<Nearest> {
    let reached = core::cell::Cell::new(false);
    mesh.bvh()
        .find_best(
            f64::MAX,
            |node: &BvhNode, _| {
                if reached.get() {
                    f64::MAX
                } else {
                    axis.box_bound(node.mins(), node.maxs())
                        .max(axis.direction_bound(node.mins(), node.maxs()))
                }
            },
            |id, _| {
                reached.set(true);
                axis.triangle(&mesh.triangle(id)).map(|(d, point)| {
                    (
                        d.max(floor),
                        Nearest {
                            triangle: id,
                            distance: d.max(floor),
                            point,
                        },
                    )
                })
            },
        )
        .map(|(_, (_, n))| n)
}

/// Whether `near`'s point, off the closed mesh's surface, is inside the
/// mesh: parry's pseudo-normal test (the offset from the nearest point of
/// the surface against the angle-weighted pseudo-normal of the vertex, edge
/// or face it lies on) at the nearest triangle, which holds the surface's
/// point nearest the segment's. `None` for a mesh without pseudo-normals
/// (open or not oriented).
pub(crate) fn inside(mesh: &TriMesh, near: &Nearest) -> Option<bool> {
    let normals = mesh.pseudo_normals_if_oriented()?;
    let id = near.triangle;
    let triangle = mesh.triangle(id);
    let (proj, location) = triangle.project_local_point_and_get_location(near.point, true);
    let normal = match location {
        TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => {
            Some(triangle.scaled_normal())
        }
        TrianglePointLocation::OnEdge(i, _) => normals
            .edges_pseudo_normal
            .get(id as usize)
            .and_then(|pn| pn.get(i as usize).copied()),
        TrianglePointLocation::OnVertex(i) => mesh
            .indices()
            .get(id as usize)
            .and_then(|t| t.get(i as usize))
            .and_then(|&v| normals.vertices_pseudo_normal.get(v as usize).copied()),
    }?;
    Some((near.point - proj.point).dot(normal) <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (SplitMix64) for the tests.
    struct Mix(u64);

    impl Mix {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64
        }

        fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }

        fn vector(&mut self, half: f64) -> Vector {
            Vector::new(
                self.uniform(-half, half),
                self.uniform(-half, half),
                self.uniform(-half, half),
            )
        }
    }

    /// The distance from `p` to the box `c`, `h` (0 inside).
    fn point_box(p: Vector, c: Vector, h: Vector) -> f64 {
        ((p - c).abs() - h).max(Vector::ZERO).length()
    }

    /// The distance from the segment `a`-`b` to the box `c`, `h`, by a
    /// golden-section search along the segment: the point-to-box distance
    /// is convex along it.
    fn segment_box(a: Vector, b: Vector, c: Vector, h: Vector) -> f64 {
        let f = |s: f64| point_box(a + (b - a) * s, c, h);
        let g = (5.0_f64.sqrt() - 1.0) / 2.0;
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..200 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if f(x1) <= f(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0))
    }

    /// A random triangle of sides up to `size` mm around `centre`.
    fn triangle(rng: &mut Mix, centre: Vector, size: f64) -> Triangle {
        let mut corner = || centre + rng.vector(size / 2.0);
        Triangle::new(corner(), corner(), corner())
    }

    #[test]
    fn the_box_bound_is_below_the_distance_to_the_box() {
        let mut rng = Mix(3);
        for i in 0..20_000 {
            let (a, b) = (rng.vector(40.0), rng.vector(40.0));
            // A point now and then.
            let b = if i % 10 == 0 { a } else { b };
            let centre = rng.vector(30.0);
            let half = Vector::new(
                rng.uniform(0.01, 10.0),
                rng.uniform(0.01, 10.0),
                rng.uniform(0.0, 10.0),
            );
            let truth = segment_box(a, b, centre, half);
            let axis = Axis::new(a, b);
            for bound in [
                axis.box_bound(centre - half, centre + half),
                axis.direction_bound(centre - half, centre + half),
            ] {
                assert!(
                    bound <= truth + 1e-9,
                    "{a:?} {b:?} {centre:?} {half:?}: {bound} > {truth}"
                );
            }
        }
        // A segment above a box's top face, parallel to it: exact.
        let axis = Axis::new(Vector::new(-3.0, 1.0, 7.0), Vector::new(4.0, -0.5, 7.0));
        let bound = axis.box_bound(Vector::new(-1.0, -1.0, -1.0), Vector::new(1.0, 1.0, 2.0));
        assert_eq!(bound, 5.0);
    }

    #[test]
    fn the_patch_bound_is_below_every_triangle_s_distance_and_exact_for_a_facing_plane() {
        let mut rng = Mix(8);
        for _ in 0..5_000 {
            let (a, b) = (rng.vector(60.0), rng.vector(60.0));
            let axis = Axis::new(a, b);
            let c = rng.vector(20.0);
            let size = rng.uniform(0.5, 8.0);
            let triangles: Vec<Triangle> = (0..4).map(|_| triangle(&mut rng, c, size)).collect();
            let patch = Patch::around(c, &triangles);
            let bound = axis.patch_bound(c, &patch);
            let truth = triangles
                .iter()
                .filter_map(|t| axis.triangle(t))
                .map(|(d, _)| d)
                .fold(f64::INFINITY, f64::min);
            assert!(bound <= truth, "{bound} > {truth}");
        }
        // A flat patch of the plane z = 0, tilted by 45 deg about y, seen
        // from 20 mm along its normal: its axis-aligned box is 1.4 mm
        // thick, its cylinder flat, so the patch bound is the distance.
        let tilt = |x: f64, y: f64| Vector::new(x * 0.5_f64.sqrt(), y, x * 0.5_f64.sqrt());
        let patch_triangles = [
            Triangle::new(tilt(-1.0, -1.0), tilt(1.0, -1.0), tilt(1.0, 1.0)),
            Triangle::new(tilt(-1.0, -1.0), tilt(1.0, 1.0), tilt(-1.0, 1.0)),
        ];
        let normal = Vector::new(-0.5_f64.sqrt(), 0.0, 0.5_f64.sqrt());
        let tip = normal * 20.0;
        let axis = Axis::new(tip, tip + Vector::new(3.0, 40.0, 60.0));
        let patch = Patch::around(Vector::ZERO, &patch_triangles);
        let bound = axis.patch_bound(Vector::ZERO, &patch);
        assert!((bound - 20.0).abs() < 1e-9, "{bound}");
        let boxed = axis.direction_bound(tilt(-1.0, -1.0), tilt(1.0, 1.0));
        assert!(boxed < 19.5, "{boxed}");
    }

    #[test]
    fn an_end_nearest_a_triangle_is_found_by_one_projection_and_agrees_with_the_edges() {
        // The tip 3 mm above the face's interior, the shaft going up: the
        // tip is the closest point. The shaft lying across an edge 2 mm
        // above it: the interior point over the edge.
        let t = Triangle::new(
            Vector::new(0.0, 0.0, 0.0),
            Vector::new(10.0, 0.0, 0.0),
            Vector::new(0.0, 10.0, 0.0),
        );
        let up = Axis::new(Vector::new(2.0, 2.0, 3.0), Vector::new(-20.0, 5.0, 40.0));
        assert_eq!(up.triangle(&t), Some((3.0, Vector::new(2.0, 2.0, 3.0))));
        let across = Axis::new(Vector::new(-5.0, 5.0, 2.0), Vector::new(5.0, -5.0, 2.0));
        let (d, p) = across.triangle(&t).expect("finite");
        assert!((d - 2.0).abs() < 1e-12, "{d}");
        assert!((p - Vector::new(0.0, 0.0, 2.0)).length() < 1e-12, "{p:?}");
        // Through the face: 0, at the crossing point.
        let through = Axis::new(Vector::new(1.0, 1.0, 5.0), Vector::new(3.0, 3.0, -5.0));
        assert_eq!(
            through.triangle(&t),
            Some((0.0, Vector::new(2.0, 2.0, 0.0)))
        );
    }
}
