//! One forbidden region: its name, its shape as the user gave it, and the
//! parry collider built from it once.

use std::path::PathBuf;

use parry3d_f64::math::{Pose3, Rot3, Vector};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, TriMesh, TriMeshFlags};

use crate::error::MeshProblem;
use crate::mesh::Mesh;
use crate::nearest::Hierarchy;

/// A region's shape, fixed frame, mm.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Shape {
    /// A ball.
    Sphere {
        /// Its centre, mm.
        centre_mm: [f64; 3],
        /// Its radius, mm.
        radius_mm: f64,
    },
    /// A box: its centre, half its size along each of its own axes, and
    /// its axes' rotation from the fixed frame's.
    Box {
        /// Its centre, mm.
        centre_mm: [f64; 3],
        /// Half its size along its own `x`, `y`, `z`, mm.
        half_extents_mm: [f64; 3],
        /// Its rotation, `[psi, theta, phi]` deg, in the platform's
        /// convention `R = R_X(psi) R_Y(theta) R_Z(phi)` (zero: aligned
        /// with the fixed frame).
        rotation_deg: [f64; 3],
    },
    /// A capsule: every point within `radius_mm` of the segment from
    /// `start_mm` to `end_mm`.
    Capsule {
        /// One end of its axis, mm.
        start_mm: [f64; 3],
        /// The other end, mm.
        end_mm: [f64; 3],
        /// Its radius, mm.
        radius_mm: f64,
    },
    /// A triangle mesh read from a file, moved by its translation.
    Mesh {
        /// The mesh file, as resolved (relative to the anatomy file's
        /// folder).
        file: PathBuf,
        /// The translation applied to its vertices, mm.
        translation_mm: [f64; 3],
        /// Its triangles, translated, mm.
        mesh: Mesh,
        /// Whether the mesh is closed, so bounds a solid: a body inside it
        /// is then inside the region (see [`crate::clearance`]); an open
        /// mesh is a surface.
        solid: bool,
    },
}

impl Shape {
    /// The shape's kind as the anatomy file names it: `"sphere"`, `"box"`,
    /// `"capsule"`, `"mesh"`.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Box { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Mesh { .. } => "mesh",
        }
    }
}

/// parry's shape for a region, and where it sits.
#[derive(Debug, Clone)]
pub(crate) enum Collider {
    Ball(Ball),
    Cuboid(Cuboid),
    Capsule(Capsule),
    Mesh(Box<MeshCollider>),
}

/// A mesh region's collider: parry's mesh and its hierarchy's cylinders.
#[derive(Debug, Clone)]
pub(crate) struct MeshCollider {
    pub(crate) mesh: TriMesh,
    pub(crate) hierarchy: Hierarchy,
}

/// One forbidden region.
#[derive(Debug, Clone)]
pub struct Region {
    /// Its name, unique in its file.
    pub name: String,
    /// Its shape.
    pub shape: Shape,
    pub(crate) collider: Collider,
    pub(crate) pose: Pose3,
}

impl PartialEq for Region {
    /// Two regions are equal when their names and shapes are (the collider
    /// is built from the shape).
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.shape == other.shape
    }
}

/// The rotation `R_X(psi) R_Y(theta) R_Z(phi)` of `[psi, theta, phi]` deg.
pub(crate) fn rotation(deg: [f64; 3]) -> Rot3 {
    let [psi, theta, phi] = deg.map(f64::to_radians);
    Rot3::from_rotation_x(psi) * Rot3::from_rotation_y(theta) * Rot3::from_rotation_z(phi)
}

impl Region {
    /// The region `name` of `shape`, with its collider. The shape's numbers
    /// are checked by the file reader; a mesh parry refuses is
    /// [`MeshProblem::Rejected`].
    pub fn new(name: String, shape: Shape) -> Result<Self, MeshProblem> {
        let v = Vector::from_array;
        let (collider, pose) = match &shape {
            Shape::Sphere {
                centre_mm,
                radius_mm,
            } => (
                Collider::Ball(Ball::new(*radius_mm)),
                Pose3::from_translation(v(*centre_mm)),
            ),
            Shape::Box {
                centre_mm,
                half_extents_mm,
                rotation_deg,
            } => (
                Collider::Cuboid(Cuboid::new(v(*half_extents_mm))),
                Pose3::from_parts(v(*centre_mm), rotation(*rotation_deg)),
            ),
            Shape::Capsule {
                start_mm,
                end_mm,
                radius_mm,
            } => (
                Collider::Capsule(Capsule::new(v(*start_mm), v(*end_mm), *radius_mm)),
                Pose3::IDENTITY,
            ),
            Shape::Mesh { mesh, solid, .. } => {
                let vertices = mesh.vertices().iter().map(|p| v(*p)).collect();
                let flags = if *solid {
                    TriMeshFlags::ORIENTED
                } else {
                    TriMeshFlags::empty()
                };
                let trimesh = TriMesh::with_flags(vertices, mesh.triangles().to_vec(), flags)
                    .map_err(|e| MeshProblem::Rejected(e.to_string()))?;
                let hierarchy = Hierarchy::new(&trimesh);
                (
                    Collider::Mesh(Box::new(MeshCollider {
                        mesh: trimesh,
                        hierarchy,
                    })),
                    Pose3::IDENTITY,
                )
            }
        };
        Ok(Self {
            name,
            shape,
            collider,
            pose,
        })
    }

    /// The number of triangles of a mesh region (0 for the primitives).
    pub fn triangle_count(&self) -> usize {
        match &self.collider {
            Collider::Mesh(m) => m.mesh.num_triangles(),
            _ => 0,
        }
    }
}
