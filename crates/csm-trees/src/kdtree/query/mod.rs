//! The queries of the kd-tree, one file each.

mod in_box;
pub(super) mod in_radius;

pub(crate) use in_radius::distance2;
