//! The commands of the `csm` binary, as library functions over explicit data so that tests
//! can call them without a process.

mod info;
mod search;

pub use info::{MeshInfo, PartInfo, mesh_info};
pub use search::{Timings, default_setup, load_setup, run_search};
