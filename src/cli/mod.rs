//! The commands of the `csm` binary, as library functions over explicit data so that tests
//! can call them without a process.

mod info;

pub use info::{MeshInfo, PartInfo, mesh_info};
