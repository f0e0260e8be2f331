//! k-DOPs (discrete oriented polytopes): the 18-DOP used as csm's narrow phase for
//! `type_search = "kdop_18"` (Kratos declares a k-DOP search but never implemented it).

mod kdop18;

pub use kdop18::{KDOP18_DIRECTIONS, Kdop18};

#[cfg(test)]
mod tests;
