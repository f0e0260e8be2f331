//! The octree holding objects in its leaves (Kratos `OctreeBinary`, reference §8): refined to
//! the minimum level around given points, objects (boxes) stored in every leaf they overlap
//! (with Kratos' absolute cell tolerance, Q17), queried by box.

mod insert;
mod query;
mod refine;
mod tree;

#[cfg(test)]
mod tests;

pub use tree::{LeafId, Octree, OctreeParams};
