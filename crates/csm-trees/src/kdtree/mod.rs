//! The bucketed kd-tree over points (Kratos `Tree<KDTreePartition<Bucket<3, …>>>`, reference §6):
//! construction by the cut of the widest axis with Kratos' Hoare quickselect, a strict radius
//! query and an inclusive box query, both with a result cap.

mod build;
mod query;
mod tree;

#[cfg(test)]
mod tests;

pub(crate) use query::distance2;
pub use tree::KdTree;
