//! The contact search of csm: stages 0–8 of the pipeline (contact model parts and flags,
//! interface conditions, normal check, master/slave flags, broad phase over every
//! `type_search`, OBB narrow phase, pair filters and pairing).
//!
//! **Status:** [`parse_setup`] turns the `Parameters` of a Kratos contact process (or a whole
//! `ProjectParameters.json`) into a typed [`SearchSetup`] with Kratos' defaults, aliases,
//! fallbacks and dropped keys (DESIGN.md §2). [`ContactSearch`] runs Kratos' life cycle over
//! the stages: contact parts and flags (stage 0, [`assign_contact_flags`]), interface
//! conditions ([`generate_interface_conditions`], stage 1), the normal check
//! ([`normal_check`], stage 2), [`master_slave_from_nodes`] (stage 3), [`dispatch`] (stage 4),
//! the life cycle with `database_step_update` (stage 5), the kd-tree broad phase (`in_radius`,
//! `in_box`), the OBB and 18-DOP narrow phases (stages 6–7), the candidate filters and the
//! No/Direct/MappingCheck pairing (stage 8), the octree path, dynamic and inverted search,
//! and through `csm-activation` the MappingCheck mortar pruning, the weighted gap and the
//! activation (stage 9).
//!
//! [`Plan`] says which stages run and which structures are built for a model and a setup, and
//! why each other one is left out (`csm plan`); [`ContactSearch`] makes the same plan and
//! follows it, so nothing a scene or setup does not need is run or allocated.
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
    SearchParameters, SearchSetup, SearchTreeType, SetupSource, parse_setup,
};
pub use stages::*;
mod pipeline;
mod plan;
pub use pipeline::*;
pub use plan::*;
