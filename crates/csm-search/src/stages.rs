//! The pipeline stages, as functions over explicit data (STYLE.md 8). Each returns data a test
//! can print. Every stage module's public items are re-exported here (and from the crate root).

mod contact_parts;
mod dispatch;
mod interface_preprocess;
mod master_slave;
mod normal_check;
mod skin;

pub use contact_parts::*;
pub use dispatch::*;
pub use interface_preprocess::*;
pub use master_slave::*;
pub use normal_check::*;
pub use skin::*;
