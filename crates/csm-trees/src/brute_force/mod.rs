//! Brute-force O(n) references of every tree query: the oracles the kd-tree and the octree are
//! tested against (kiddo's `linear_search`). Same predicates, bit for bit, no cap, results in
//! input order.

mod aabb_overlap;
mod in_box;
mod in_radius;

pub use aabb_overlap::aabb_overlap;
pub use in_box::in_box;
pub use in_radius::in_radius;
