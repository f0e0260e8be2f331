//! The pipeline stages, as functions over explicit data (STYLE.md 8). Each returns data a test
//! can print.

mod contact_parts;
mod dispatch;
mod master_slave;

pub use contact_parts::{ContactParts, assign_contact_flags, transfer_to_contact};
pub use dispatch::{SearchInstance, dispatch};
pub use master_slave::master_slave_from_nodes;
