//! Integration tests of `csm-trees`: every query of the kd-tree and the octree against the
//! brute-force oracles of `csm_trees::brute_force`, on seeded proptest point clouds (duplicate,
//! collinear, coplanar, identical points, huge and tiny coordinates, empty clouds).

mod generators;
mod kdtree_vs_brute_force;
mod octree_vs_brute_force;
