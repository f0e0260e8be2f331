//! The contact search of csm: stages 0–8 of the pipeline (contact model parts and flags,
//! interface conditions, normal check, master/slave flags, broad phase over every
//! `type_search`, OBB narrow phase, pair filters and pairing).
//!
//! **Status:** the setup layer and the first stages exist: [`parse_setup`] turns the
//! `Parameters` of a Kratos contact process (or a whole `ProjectParameters.json`) into a typed
//! [`SearchSetup`] with Kratos' defaults, aliases, fallbacks and dropped keys (DESIGN.md §2);
//! [`assign_contact_flags`] / [`transfer_to_contact`] build the contact parts and flags
//! (stage 0); [`master_slave_from_nodes`] is stage 3; [`dispatch`] chooses the search
//! instance (stage 4). Stages 1, 2 and 5–8 are not implemented yet.
//!
//! **Architecture Invariant:** `csm-search` depends on `csm-activation`, `csm-model`,
//! `csm-trees` and `csm-geometry`, never on `csm-io` or the facade: it works on a
//! `ModelPart` in memory and knows nothing of files (the setup text is given to it).
#![deny(missing_docs)]

mod error;
mod setup;
mod stages;

pub use error::{Error, ErrorKind};
pub use setup::{
    CheckGap, Compatibility, ContactType, ObbIntersectionType, OctreeSearchParameters, PairSetup,
    SearchParameters, SearchSetup, SearchTreeType, parse_setup,
};
pub use stages::*;
mod pipeline;
pub use pipeline::*;
