//! Model layer of csm: the [`ModelPart`] every stage reads and writes, in dense storage with
//! the external (file) ids kept beside it.
//!
//! Main types: [`ModelPart`] (nodes, elements, conditions, properties, process info and a tree
//! of sub model parts addressed by full path), [`Flags`] (Kratos' tri-state flags: undefined /
//! true / false), [`NodalData`] (historical variables with a buffer of two steps and plain
//! ones), [`IndexMap`] (the per-condition map of candidate masters). Between two search steps
//! [`ModelPart::advance_time_step`] and [`ModelPart::prescribe_motion`] advance the model as
//! Kratos' analysis stage and solver do (buffer shift, new coordinates, DISPLACEMENT, VELOCITY,
//! ACCELERATION).
//!
//! **Architecture Invariant:** `csm-model` depends only on `csm-geometry`. It knows nothing of
//! files, trees or the search: readers (`csm-io`) fill it, stages (`csm-search`,
//! `csm-activation`) compute on it.
//!
//! **Architecture Invariant:** internal indices (`NodeIdx`, `ConditionIdx`, …) are dense and
//! never leave the process; external ids (`NodeId`, `ConditionId`, …) are what files and
//! outputs show. Conversions happen in [`ModelPart`] only.
#![deny(missing_docs)]

mod arrays;
pub mod collective;
mod entities;
mod error;
mod flags;
mod gathered_points;
mod ids;
mod index_map;
mod model_part;
mod nodal_data;
mod nodal_h;
mod normals;
mod ordered_output;
mod parts;
mod process_info;
mod properties;
mod time_step;
mod write_at;

pub use arrays::{EntityArrays, MeshArrays, PartArrays};
pub use collective::{Aborted, Ranks, Transport};
pub use entities::{Entities, IdOrder, Nodes};
pub use error::{EntityKind, Error, ErrorKind};
pub use flags::{Flag, Flags};
pub use gathered_points::{GATHER_BLOCK, GatheredPoints};
pub use ids::{
    ConditionId, ConditionIdx, ElementId, ElementIdx, NodeId, NodeIdx, PartIdx, PropertiesId,
};
pub use index_map::IndexMap;
pub use model_part::{GeometryStamp, ModelPart};
pub use nodal_data::{NodalData, ScalarVar, VectorVar, zero_vectors};
pub use nodal_h::{NodalHMode, assign_nodal_h, compute_nodal_h};
pub use normals::{
    FaceNormals, FaceNormalsRef, KeptFaceNormals, KeptPositions, NormalsMode, UnitNormalsSnapshot,
    compute_unit_normals, compute_unit_normals_from_kept, compute_unit_normals_reusing,
    face_unit_normals,
};
pub use ordered_output::write_in_order;
pub use parts::SubModelPart;
pub use process_info::ProcessInfo;
pub use properties::{Properties, PropertyValue};
pub use write_at::{concat_parts_with, copy_parts_into, write_at_ascending};
