//! The queries of the kd-tree, one file each.

mod in_box;
mod in_radius;

pub(crate) use in_radius::distance2;
