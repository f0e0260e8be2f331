//! The queries of the octree, one file each.

mod intersected_leaves;
mod query_aabb;
