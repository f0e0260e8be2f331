//! The search setup: the `Parameters` of a Kratos contact process parsed once, at the
//! boundary, into typed values (STYLE.md 9). Stages `match` on the enums and never compare
//! strings.

mod defaults;
mod motion;
mod parse;
mod processes;
mod types;
mod validate;

pub use parse::parse_setup;
pub use types::{
    CheckGap, Compatibility, ContactProcess, ContactType, NodalValueSetup, ObbIntersectionType,
    OctreeSearchParameters, PairSetup, PartMotion, RigidMotion, Rotation, SearchParameters,
    SearchSetup, SearchTreeType, SetupSource, StepSetup,
};

#[cfg(test)]
mod tests;
