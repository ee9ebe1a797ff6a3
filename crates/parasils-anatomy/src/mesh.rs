//! Triangle meshes read from STL (binary or ASCII) and OBJ files, in mm, and
//! checked before any query: at least one triangle, every coordinate a
//! finite number, every triangle with an area.
//!
//! STL is read with `stl_io`, OBJ with `tobj` (faces triangulated, one
//! index per corner; the materials an OBJ names are not read). STL stores
//! single-precision coordinates; they are widened to `f64` exactly.

use std::io::BufReader;
use std::path::Path;

use crate::error::MeshProblem;

/// A mesh file's format, from its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// `.stl`, binary or ASCII.
    Stl,
    /// `.obj` (Wavefront).
    Obj,
}

impl MeshFormat {
    /// The format of `path` by its extension (any case), or `None`.
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(MeshFormat::Stl),
            "obj" => Some(MeshFormat::Obj),
            _ => None,
        }
    }
}

/// A checked triangle mesh: vertices in mm and triangles as three vertex
/// indices each.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
}

/// A triangle whose cross product is below this fraction of its longest
/// edge squared (the sine of its smallest angle, roughly) has no area.
const DEGENERATE_SINE: f64 = 1e-12;

impl Mesh {
    /// The mesh of `vertices` (mm) and `triangles`, checked: see
    /// [`MeshProblem`] for what is refused.
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshProblem> {
        if triangles.is_empty() {
            return Err(MeshProblem::Empty);
        }
        for (vertex, v) in vertices.iter().enumerate() {
            if let Some(&value) = v.iter().find(|c| !c.is_finite()) {
                return Err(MeshProblem::NonFinite { vertex, value });
            }
        }
        for (triangle, t) in triangles.iter().enumerate() {
            let corner = |i: u32| vertices.get(i as usize).copied();
            let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
                return Err(MeshProblem::BadIndex { triangle });
            };
            if degenerate(a, b, c) {
                return Err(MeshProblem::Degenerate { triangle });
            }
        }
        Ok(Self {
            vertices,
            triangles,
        })
    }

    /// Reads and checks the mesh file `path` (its format by its extension).
    pub fn read(path: &Path) -> Result<Self, MeshProblem> {
        match MeshFormat::of(path) {
            Some(MeshFormat::Stl) => read_stl(path),
            Some(MeshFormat::Obj) => read_obj(path),
            None => Err(MeshProblem::UnknownFormat),
        }
    }

    /// The vertices, mm.
    pub fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }

    /// The triangles, three indices into [`Mesh::vertices`] each.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// A closed ellipsoid of `rings` bands from pole to pole and `segments`
    /// around its `z` axis, centred at `centre_mm` with semi-axes
    /// `radii_mm`, its triangles counter-clockwise seen from outside:
    /// `2 segments (rings - 1)` triangles (`rings = 201`, `segments = 250`
    /// give 10^5). A simple organ-like solid for examples, tests and
    /// benchmarks; [`MeshProblem::Empty`] for fewer than 2 rings or 3
    /// segments, the checks of [`Mesh::new`] otherwise.
    pub fn ellipsoid(
        centre_mm: [f64; 3],
        radii_mm: [f64; 3],
        rings: u32,
        segments: u32,
    ) -> Result<Self, MeshProblem> {
        if rings < 2 || segments < 3 {
            return Err(MeshProblem::Empty);
        }
        let point = |theta: f64, phi: f64| {
            let (s, c) = theta.sin_cos();
            [
                centre_mm[0] + radii_mm[0] * s * phi.cos(),
                centre_mm[1] + radii_mm[1] * s * phi.sin(),
                centre_mm[2] + radii_mm[2] * c,
            ]
        };
        let mut vertices = vec![point(0.0, 0.0)];
        for i in 1..rings {
            let theta = core::f64::consts::PI * f64::from(i) / f64::from(rings);
            for j in 0..segments {
                vertices.push(point(
                    theta,
                    core::f64::consts::TAU * f64::from(j) / f64::from(segments),
                ));
            }
        }
        let south = u32::try_from(vertices.len()).map_err(|_| MeshProblem::Empty)?;
        vertices.push(point(core::f64::consts::PI, 0.0));
        let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
        let mut triangles = Vec::new();
        for j in 0..segments {
            triangles.push([0, at(1, j), at(1, j + 1)]);
            for i in 1..rings - 1 {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
            triangles.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
        }
        Self::new(vertices, triangles)
    }

    /// The mesh moved by `offset` (mm).
    pub fn translated(mut self, offset: [f64; 3]) -> Self {
        for v in &mut self.vertices {
            for (c, o) in v.iter_mut().zip(offset) {
                *c += o;
            }
        }
        self
    }

    /// Whether every edge is shared by exactly two triangles, in opposite
    /// directions: a closed, consistently oriented surface, which bounds a
    /// solid (vertices compared by index; STL's repeated corners are merged
    /// when read).
    pub fn is_closed(&self) -> bool {
        use std::collections::HashMap;
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &self.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a, b)).or_default() += 1;
            }
        }
        edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }
}

fn degenerate(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let (u, v, w) = (sub(b, a), sub(c, a), sub(c, b));
    let cross = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let norm2 = |x: [f64; 3]| x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    let longest = norm2(u).max(norm2(v)).max(norm2(w));
    !(norm2(cross).sqrt() > DEGENERATE_SINE * longest)
}

fn unreadable(e: impl core::fmt::Display) -> MeshProblem {
    MeshProblem::Unreadable(e.to_string())
}

fn read_stl(path: &Path) -> Result<Mesh, MeshProblem> {
    let file = std::fs::File::open(path).map_err(unreadable)?;
    let mut reader = BufReader::new(file);
    let stl = stl_io::read_stl(&mut reader).map_err(unreadable)?;
    let vertices = stl
        .vertices
        .iter()
        .map(|v| v.0.map(f64::from))
        .collect::<Vec<_>>();
    let index = |i: usize| u32::try_from(i).unwrap_or(u32::MAX);
    let triangles = stl.faces.iter().map(|f| f.vertices.map(index)).collect();
    Mesh::new(vertices, triangles)
}

fn read_obj(path: &Path) -> Result<Mesh, MeshProblem> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(unreadable)?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in &models {
        let base = u32::try_from(vertices.len()).map_err(unreadable)?;
        let m = &model.mesh;
        vertices.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]),
        );
        triangles.extend(m.indices.chunks_exact(3).map(|t| {
            [
                t[0].saturating_add(base),
                t[1].saturating_add(base),
                t[2].saturating_add(base),
            ]
        }));
    }
    Mesh::new(vertices, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let v = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let t = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        (v, t)
    }

    #[test]
    fn a_closed_tetrahedron_is_closed_and_an_open_one_is_not() {
        let (v, t) = tetrahedron();
        assert!(Mesh::new(v.clone(), t.clone()).map(|m| m.is_closed()) == Ok(true));
        assert!(Mesh::new(v, t[..3].to_vec()).map(|m| m.is_closed()) == Ok(false));
    }

    #[test]
    fn empty_degenerate_non_finite_and_bad_indices_are_refused() {
        let (v, t) = tetrahedron();
        assert_eq!(Mesh::new(v.clone(), vec![]), Err(MeshProblem::Empty));
        let mut nan = v.clone();
        nan[2][1] = f64::NAN;
        assert!(matches!(
            Mesh::new(nan, t.clone()),
            Err(MeshProblem::NonFinite { vertex: 2, .. })
        ));
        let mut flat = t.clone();
        flat[1] = [0, 1, 1];
        assert_eq!(
            Mesh::new(v.clone(), flat),
            Err(MeshProblem::Degenerate { triangle: 1 })
        );
        let mut line = v.clone();
        line.push([2.0, 0.0, 0.0]);
        assert_eq!(
            Mesh::new(line, vec![[0, 1, 4]]),
            Err(MeshProblem::Degenerate { triangle: 0 })
        );
        assert_eq!(
            Mesh::new(v, vec![[0, 1, 9]]),
            Err(MeshProblem::BadIndex { triangle: 0 })
        );
    }
}
