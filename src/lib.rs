//! csm: finite-element contact search.
//!
//! Given the surface meshes of bodies that may touch, csm finds every slave/master face pair
//! that can come into contact, computes the normal gap and decides which slave nodes are
//! active, following the contact detection pipeline of Kratos Multiphysics'
//! ContactStructuralMechanicsApplication (see `docs/ARCHITECTURE.md`).
//!
//! This facade re-exports the layers and holds only the composition (the command-line
//! tool's commands). No algorithm lives here.
//!
//! | layer | what it is |
//! |---|---|
//! | [`geometry`] | face and solid geometries, AABB, bounding sphere, OBB with SAT/Direct tests |
//! | [`trees`] | kd-tree, octree, brute-force reference |
//! | [`model`] | `ModelPart`, tri-state flags, sub model parts, nodal data, NODAL_H |
//! | [`io`] | Gmsh `.msh` and Kratos `.mdpa` readers, VTU writer (feature `io`) |
//! | [`search`] | the contact search, stages 0–8 (not implemented yet) |
//! | [`activation`] | the mapped gap and activation, stage 9 (not implemented yet) |
#![deny(missing_docs)]

pub use csm_activation as activation;
pub use csm_geometry as geometry;
#[cfg(feature = "io")]
pub use csm_io as io;
pub use csm_model as model;
pub use csm_search as search;
pub use csm_trees as trees;

pub mod cli;

/// The types most users need, in one import.
pub mod prelude {
    pub use csm_geometry::GeometryKind;
    pub use csm_geometry::math::{Point, Real, Vector};
    pub use csm_model::{
        ConditionId, ElementId, Flag, Flags, ModelPart, NodeId, PartIdx, PropertiesId,
    };
}
