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
//! | layer | what it is | feature |
//! |---|---|---|
//! | `geometry` | face and solid geometries, AABB, bounding sphere, OBB with SAT/Direct tests, mortar segmentation | `geometry` |
//! | `trees` | kd-tree, octree, brute-force reference | `trees` |
//! | `model` | `ModelPart`, tri-state flags, sub model parts, nodal data, NODAL_H | `model` |
//! | `io` | Gmsh `.msh` and Kratos `.mdpa` readers, VTU writer | `msh`, `mdpa`, `vtk` (all: `io`) |
//! | `search` | the contact search, stages 0–8, and its `Plan` | `search` |
//! | `activation` | the mapped gap and activation, stage 9 | `activation` |
//! | `distributed` | the search split across ranks: threads, or MPI (`mpirun -np N csm search`) | `distributed`, `mpi` (not default) |
//! | `cli` | the commands of the `csm` binary | `cli` |
//!
//! Every feature but `distributed` and `mpi` is on by default. With `default-features = false` a user of one layer or one
//! format compiles only it and the layers below it (e.g. `features = ["geometry"]` builds
//! `csm-geometry` and nalgebra alone).
#![deny(missing_docs)]

#[cfg(feature = "activation")]
pub use csm_activation as activation;
#[cfg(feature = "distributed")]
pub use csm_distributed as distributed;
#[cfg(feature = "eval")]
pub use csm_eval as eval;
#[cfg(feature = "geometry")]
pub use csm_geometry as geometry;
#[cfg(any(feature = "msh", feature = "mdpa", feature = "vtk"))]
pub use csm_io as io;
#[cfg(feature = "model")]
pub use csm_model as model;
#[cfg(feature = "search")]
pub use csm_search as search;
#[cfg(feature = "trees")]
pub use csm_trees as trees;

#[cfg(feature = "cli")]
pub mod cli;

/// The types most users need, in one import.
#[cfg(feature = "model")]
pub mod prelude {
    pub use csm_geometry::GeometryKind;
    pub use csm_geometry::math::{Point, Real, Vector};
    pub use csm_model::{
        ConditionId, ElementId, Flag, Flags, ModelPart, NodeId, PartIdx, PropertiesId,
    };
}
