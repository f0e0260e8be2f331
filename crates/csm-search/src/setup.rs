//! The search setup: the `Parameters` of a Kratos contact process parsed once, at the
//! boundary, into typed values (STYLE.md 9). Stages `match` on the enums and never compare
//! strings.

mod defaults;
mod parse;
mod types;
mod validate;

pub use parse::parse_setup;
pub use types::{
    CheckGap, Compatibility, ContactType, ObbIntersectionType, OctreeSearchParameters, PairSetup,
    SearchParameters, SearchSetup, SearchTreeType, SetupSource,
};

#[cfg(test)]
mod tests;
