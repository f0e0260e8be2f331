//! The gap and activation layer of csm (stage 9): the mortar NormalGap mapping (the
//! MappingCheck narrow phase, reference §10.2), the explicit weighted gap (§10.3) and the Simple
//! and Advanced activation (§10.6).
//!
//! * [`normal_gap_process`]: Kratos' `NormalGapProcess` with its `SimpleMortarMapperProcess`:
//!   nodal mean normals, the exact segmentation of every `INDEX_MAP` entry (entries without
//!   overlap are removed — this *is* the MappingCheck pruning), the iterated dual-mortar mapping
//!   of `AUXILIAR_COORDINATES` and `ComputeNormalGap` (`NORMAL_GAP`, sentinel 1e12, Q39).
//! * [`overlap_measure`] (with [`mapping_normals`]): the overlap of one pair as the mapping
//!   segments it, for callers that decide pairs themselves (the ground truth).
//! * [`compute_weighted_gap`]: `ComputeWeightedReaction` for the paired conditions.
//! * [`compute_active_inactive_nodes`]: `ComputeActiveInactiveNodes` (Simple / Advanced,
//!   `SetActiveNode` / `SetInactiveNode`, Q24).
//!
//! The Lagrange-multiplier guesses of the activation (Simple's `ε·A·g`, Advanced's
//! predict/correct regression) are written into the model's nodal data as Kratos writes them;
//! `RESULT.json` does not carry them. Robust mode guards the NaN/inf cases (Q25, Q26).
//!
//! **Architecture Invariant:** `csm-activation` depends only on `csm-model` and
//! `csm-geometry`; it never sees trees, the search configuration or files.

mod activation;
mod error;
mod face;
mod mapping;
mod multiplier;
mod overlap;
mod weighted_gap;

#[cfg(test)]
mod tests;

pub use activation::{
    ActivationReport, ActivationRule, ActivationSettings, compute_active_inactive_nodes,
};
pub use error::{Error, ErrorKind};
pub use mapping::{
    GATHER_FROM_THREADS, MAPPER_ABSOLUTE_TOLERANCE, MAPPER_MAX_ITERATIONS,
    MAPPER_RELATIVE_TOLERANCE, MappingReport, MappingSettings, MappingTuning, NORMAL_GAP_SENTINEL,
    RemovedEntry, mean_h, mean_h_shared, normal_gap_process, normal_gap_process_keeping,
};
pub use multiplier::{MultiplierKind, MultiplierSettings};
pub use overlap::{mapping_normals, overlap_measure};
pub use weighted_gap::{KnownGaps, WEIGHTED_GAP_AREA_RATIO, compute_weighted_gap};

/// Re-exported so that callers can choose the segmentation rules without naming
/// `csm-geometry`.
pub use csm_geometry::MortarMode;
