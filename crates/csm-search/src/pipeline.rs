//! The search driver: Kratos' life cycle (reference §1.3–§1.4, §4, §5) composed from the
//! stages — `ExecuteInitialize` ([`ContactSearch::initialize`]), `ExecuteInitializeSolutionStep`
//! ([`ContactSearch::step`]) and `ExecuteFinalizeSolutionStep`
//! ([`ContactSearch::finalize_step`]), and between steps of a multi-step run the time step and
//! the prescribed motion ([`ContactSearch::advance`]).
//!
//! The slave loop runs in parallel (rayon): every per-slave computation that does not depend
//! on the order (tree query, bounding volumes, geometric tests) is done in parallel, and the
//! order-dependent part (INDEX_MAP updates, ACTIVE flags, pair creation) is applied serially in
//! slave order afterwards — so the result is identical for any thread count and equal to
//! Kratos' serial loop.

mod candidates;
mod filters;
mod globals;
mod id_map;
mod motion;
mod octree;
mod pairing;
mod result;
mod result_text;
mod search;
mod self_contact;
mod shared_conditions;
mod step_jump;
mod tuning;

pub use filters::passes_orientation;
pub use globals::PairGlobals;
pub use id_map::IdMap;
pub use result::{NodeResult, SearchResult, StepResult};
pub use search::TruthScene;
pub(crate) use search::locate;
pub use search::{
    ContactSearch, GENERATED_CONDITIONS_PART, PairedCondition, generate_interfaces_first,
    kratos_renumbering,
};
#[cfg(test)]
pub(crate) use search::{by_slave, morton_order};
pub use tuning::{MappingTuning, QueryOrder, SearchTuning};

#[cfg(test)]
pub(crate) mod tests;
