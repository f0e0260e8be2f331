//! The pipeline stages, as functions over explicit data (STYLE.md 8). Each returns data a test
//! can print.

mod contact_parts;
mod dispatch;

pub use contact_parts::{ContactParts, assign_contact_flags, transfer_to_contact};
pub use dispatch::{SearchInstance, dispatch};
