//! [`GroundTruth::score`]: a search result against the ground truth.

use std::collections::BTreeSet;

use csm_geometry::math::Real;

use csm_search::SearchResult;

use crate::compute::GroundTruth;

/// How a search result compares with the [`GroundTruth`], over the evaluated slave conditions
/// and their nodes (`docs/report.md`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Score {
    /// True pairs.
    pub true_pairs: usize,
    /// True pairs the result does not have.
    pub missed: usize,
    /// Candidates before the MappingCheck pruning (`pairs` ∪ `pruned` of the result) that are
    /// not true pairs: the work the mortar pruning had to undo.
    pub spurious_candidates: usize,
    /// Pairs of the result (after the pruning) that are not true pairs.
    pub extra_pairs: usize,
    /// Nodes whose ACTIVE flag differs from the ground truth's.
    pub wrong_active: usize,
    /// The largest `|NORMAL_GAP − exact gap|` over the nodes ACTIVE in the ground truth where
    /// the result has a gap (`None`: no such node).
    pub max_gap_error: Option<Real>,
    /// Nodes ACTIVE in the ground truth on which the result has no gap (not mapped).
    pub unmapped: usize,
}

impl Score {
    /// `missed` as a percentage of `true_pairs` (0 when there is none).
    pub fn missed_percent(&self) -> Real {
        if self.true_pairs == 0 {
            0.0
        } else {
            100.0 * self.missed as Real / self.true_pairs as Real
        }
    }
}

impl GroundTruth {
    /// Compares `result` (pair key [`GroundTruth::key`]) with the ground truth.
    pub fn score(&self, result: &SearchResult) -> Score {
        let key = self.key.to_string();
        let found = result.pairs.get(&key);
        let pruned = result.pruned.get(&key);
        let mut score = Score::default();
        for (slave, truth) in &self.pairs {
            let truth: BTreeSet<u32> = truth.iter().copied().collect();
            let kept: BTreeSet<u32> = found
                .and_then(|m| m.get(slave))
                .into_iter()
                .flatten()
                .copied()
                .collect();
            let removed = pruned.and_then(|m| m.get(slave)).into_iter().flatten();
            score.true_pairs += truth.len();
            score.missed += truth.difference(&kept).count();
            score.extra_pairs += kept.difference(&truth).count();
            let candidates: BTreeSet<u32> = kept.iter().chain(removed).copied().collect();
            score.spurious_candidates += candidates.difference(&truth).count();
        }
        for (id, exact) in &self.nodes {
            let got = result.nodes.get(id);
            if got.is_some_and(|g| g.active) != exact.active {
                score.wrong_active += 1;
            }
            if !exact.active {
                continue;
            }
            match (got.and_then(|g| g.normal_gap), exact.normal_gap) {
                (Some(g), Some(e)) if g.is_finite() => {
                    let err = (g - e).abs();
                    score.max_gap_error = Some(score.max_gap_error.map_or(err, |m| m.max(err)));
                }
                (None, Some(_)) => score.unmapped += 1,
                _ => {}
            }
        }
        score
    }
}
