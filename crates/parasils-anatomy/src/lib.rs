//! Forbidden regions for PARA-SILSROB: what of the patient the instruments
//! and the endoscope must keep out of, in the fixed frame, mm.
//!
//! An anatomy file (TOML) lists regions, each named: a sphere, a box (centre,
//! half-extents, an optional rotation), a capsule, or a triangle mesh read
//! from an STL (binary or ASCII) or OBJ file (an organ segmented from a
//! scan). [`Anatomy::load`] reads it once and refuses a bad file with an
//! [`AnatomyError`] that names the file, the region and the key.
//! [`Anatomy::clearance`] then gives, at one instant, the gap between the
//! in-body part of each shaft and of the endoscope ([`InBody`]: from its tip
//! back to its port) and every region.
//!
//! # Why parry
//! The queries are [parry](https://parry.rs)'s (`parry3d-f64`): it is
//! maintained (the collision library of the Rapier physics engine), pure
//! Rust (no C++ toolchain, builds wherever the workspace does), and its
//! triangle meshes carry a bounding-volume hierarchy, so the distance from
//! a shaft to a mesh of 10^5 triangles visits a few of them, not all.
//! The hierarchy (its build), the triangles' point projections, ray casts,
//! pseudo-normals and contacts are parry's. The walk is ours: parry's
//! shape-to-mesh distance bounds each node by the shaft capsule's
//! axis-aligned box, far too loose for a long slanted shaft, so the mesh
//! distance walks parry's hierarchy with bounds of the shaft's own (each
//! node also holding a cylinder around its patch of surface), from the
//! triangle nearest at the previous cycle when the caller keeps one
//! ([`WarmStart`]), and measures each triangle left in closed form (see
//! `nearest`, private).
//!
//! | module | concept |
//! |---|---|
//! | [`body`] | the in-body part of a shaft or of the endoscope ([`InBody`], [`Body`]) |
//! | [`error`] | [`AnatomyError`]: what is wrong with a file, where |
//! | [`mesh`] | triangle meshes read from STL and OBJ, checked ([`Mesh`]) |
//! | `nearest` (private) | the distance from a segment to a mesh: parry's hierarchy with a cylinder per node, walked with the segment's own bounds, the triangles in closed form |
//! | [`region`] | one forbidden region: its shape and parry's collider ([`Region`], [`Shape`]) |
//! | [`file`](mod@file) | the anatomy file ([`Anatomy`]) |
//! | [`clearance`] | the gaps of the in-body parts to the regions ([`NoGoClearance`], [`RegionGap`]), from the last cycle's nearest triangles ([`WarmStart`]) |
//! | [`online`] | the anatomy as the online controller's forbidden regions ([`Anatomy`] implements [`parasils::ForbiddenRegions`]) |

pub mod body;
pub mod clearance;
pub mod error;
pub mod file;
pub mod mesh;
mod nearest;
pub mod online;
pub mod region;

pub use body::{Body, InBody};
pub use clearance::{NoGoClearance, RegionGap, WarmStart};
pub use error::{AnatomyError, MeshProblem};
pub use file::Anatomy;
pub use mesh::{Mesh, MeshFormat};
pub use region::{Region, Shape};
