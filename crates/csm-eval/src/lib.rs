//! csm's evaluation layer. The ground truth of a scene: the exact pair set and the exact gap, found exhaustively, to
//! measure how much a search strategy misses (the error-vs-run-time report, `csm report`,
//! `docs/report.md`).
//!
//! [`GroundTruth::compute`] takes every slave × master pair of a pair key that passes the
//! orientation filter (`normal_orientation_threshold`, as stage 8) and whose exact mortar
//! segmentation (robust tolerances) overlaps the slave by more than [`MIN_OVERLAP_RATIO`] of
//! its area within the DISTANCE_THRESHOLD the setup implies (Simple: the process info's, 1e24;
//! Advanced: the larger mean NODAL_H of the two sides); then the MappingCheck mapping runs on
//! exactly those pairs (robust mode), which gives the exact gap per slave node and the ACTIVE
//! flags the setup's activation rule derives from it. A conservative prefilter (the slave's
//! box swept along its normal, [`TruthOptions::prefilter`]) keeps it fast and never drops a
//! true pair (a test compares it with the unfiltered all-pairs run); the segmentations run in
//! parallel. [`Sample`] restricts it to a seeded random subset of the slave faces for large
//! meshes. [`GroundTruth::score`] compares a [`csm_search::SearchResult`] with it ([`Score`]).
//! [`run_report`] runs the sweep of `csm report`: every strategy scored against the truth, with
//! the Pareto front of error against run time ([`Report`]; the CLI renders it).

//!
//! **Architecture Invariant:** evaluates the search from outside: it uses only the public
//! interface of `csm-search` (and the layers below); nothing in the search depends on it.

mod compute;
mod find;
mod score;
mod sweep;

pub use compute::{GroundTruth, MIN_OVERLAP_RATIO, Sample, TruthOptions};
pub use score::Score;
pub use sweep::{
    Report, ReportOptions, Row, Strategy, TruthSummary, mark_pareto, run_report, strategies,
};

#[cfg(test)]
mod tests;
