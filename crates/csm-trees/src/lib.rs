//! Spatial trees of csm: a bucketed kd-tree over points (radius and box queries), an octree
//! holding objects in its leaves, and a brute-force reference for both.
//!
//! Main types: [`KdTree`] (Kratos' bucketed kd-tree over condition centres: strict radius
//! query, inclusive box query, result cap with [`QueryStatus::truncated`]), [`Octree`] (Kratos'
//! `OctreeBinary`: refined around points, objects stored in every leaf they overlap, box
//! queries deduplicated or per leaf) and [`Aabb`] (the box type of both). The [`brute_force`]
//! module holds the O(n) oracles the trees are tested against.
//!
//! Queries write into a caller-owned `&mut Vec<T>` that is cleared and filled, so a search
//! loop allocates nothing per query. Degenerate input (NaN coordinates, zero bucket size,
//! empty root box) gives an [`Error`], never a panic.
//!
//! Fidelity: the kd-tree reproduces Kratos' split rule (widest axis, Hoare quickselect, cut
//! value) and traversal order; the octree reproduces Kratos' levels (12/11/2), key arithmetic,
//! leaf walk and absolute cell tolerance (reference §6, §8, Q13, Q17). The *sets* found are
//! the contract; the order is Kratos' where the same input order is given.
//!
//! **Architecture Invariant:** `csm-trees` knows nothing about contact, model parts or
//! conditions; it is generic over items and uses only the point and box types of
//! `csm-geometry`. `csm-search` owns the meaning of the queries.
#![deny(missing_docs)]

mod aabb;
pub mod brute_force;
mod error;
mod kdtree;
mod octree;
mod query_status;

pub use aabb::{Aabb, bounds_of, par_bounds_of};
pub use error::{Error, ErrorKind};
pub use kdtree::KdTree;
pub use octree::{LeafId, Octree, OctreeParams};
pub use query_status::QueryStatus;
