//! [`GroundTruth::compute`]: the robust pipeline with the broad and narrow phases replaced by
//! the exhaustive search of [`crate::find`].

use std::collections::{BTreeMap, BTreeSet};

use csm_geometry::math::Real;
use csm_model::{Flag, ModelPart};

use csm_search::{
    CheckGap, Compatibility, ContactSearch, Error, ErrorKind, NodeResult, SearchSetup,
};

use crate::find::{FindOptions, find_true_pairs};

/// A pair is true when its overlap exceeds this fraction of the slave's area (length in 2D).
pub const MIN_OVERLAP_RATIO: Real = 1e-9;

/// A seeded random sample of the slave faces (for meshes too large for the exhaustive truth).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sample {
    /// How many slave faces (all of them when there are fewer).
    pub size: usize,
    /// The seed of the generator (SplitMix64): the same seed gives the same sample.
    pub seed: u64,
}

/// How [`GroundTruth::compute_with`] searches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TruthOptions {
    /// Test only the masters whose bounding box meets the slave's box swept along the slave
    /// normal over every distance the segmentation accepts (3D; 2D tests every master). Never
    /// drops a true pair; `false` tests every slave × master pair (the oracle of the tests).
    pub prefilter: bool,
    /// Evaluate only a random sample of the slave faces.
    pub sample: Option<Sample>,
}

impl Default for TruthOptions {
    /// Prefilter on, no sample.
    fn default() -> TruthOptions {
        TruthOptions {
            prefilter: true,
            sample: None,
        }
    }
}

/// The exact pairs and gaps of one pair key (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct GroundTruth {
    /// The pair key.
    pub key: u32,
    /// The setup's `simple_search` (the activation rule and distance threshold used).
    pub simple_search: bool,
    /// The DISTANCE_THRESHOLD the segmentation used.
    pub distance_threshold: Real,
    /// Slave-side conditions of the pair.
    pub n_slaves: usize,
    /// Whether `pairs` holds a sample of the slave conditions rather than all of them.
    pub sampled: bool,
    /// The evaluated slave conditions (all, or the sample) → their true masters (ascending).
    pub pairs: BTreeMap<u32, Vec<u32>>,
    /// The nodes of the evaluated slave conditions: the exact NORMAL_GAP (`None`: nothing is
    /// mapped onto the node) and the ACTIVE flag the setup's activation gives with it. With a
    /// sample, the true pairs of the faces around the sampled ones are used too, so the gap
    /// of every reported node is exact.
    pub nodes: BTreeMap<u32, NodeResult>,
    /// Slave × master pairs whose segmentation was computed (after the prefilter).
    pub overlap_tests: usize,
}

impl GroundTruth {
    /// The ground truth of pair `key` of `setup` on `model` (as read, before any search), with
    /// the prefilter, optionally on a [`Sample`] of the slave faces.
    ///
    /// Errors: an unknown key; anything [`ContactSearch::initialize`] refuses; a face the
    /// mortar routines refuse (e.g. quadratic faces, which MappingCheck cannot map either).
    pub fn compute(
        model: &ModelPart,
        setup: &SearchSetup,
        key: u32,
        sample: Option<Sample>,
    ) -> Result<GroundTruth, Error> {
        GroundTruth::compute_with(
            model,
            setup,
            key,
            &TruthOptions {
                prefilter: true,
                sample,
            },
        )
    }

    /// [`GroundTruth::compute`] with every option. The setup is run in `robust` mode with
    /// MappingCheck, no dynamic search and no steps; its other keys (the parts, `simple_search`,
    /// `normal_orientation_threshold`, the activation keys) are kept.
    pub fn compute_with(
        model: &ModelPart,
        setup: &SearchSetup,
        key: u32,
        options: &TruthOptions,
    ) -> Result<GroundTruth, Error> {
        GroundTruth::compute_owned(model.clone(), setup, key, options)
    }

    /// [`GroundTruth::compute_with`] on `model` itself, which it searches and drops: no copy
    /// of the model, for a caller that has one to give (as read, before any search).
    pub fn compute_owned(
        mut model: ModelPart,
        setup: &SearchSetup,
        key: u32,
        options: &TruthOptions,
    ) -> Result<GroundTruth, Error> {
        let mut setup = setup.clone();
        setup.compatibility = Compatibility::Robust;
        setup.steps.clear();
        let pair = setup.pairs.get_mut(&key).ok_or_else(|| {
            Error::from(ErrorKind::InvalidValue {
                key: "<pair key>".to_owned(),
                expected: "a pair key of the setup".to_owned(),
                found: key.to_string(),
            })
        })?;
        pair.search.check_gap = CheckGap::MappingCheck;
        pair.search.dynamic_search = false;
        let simple_search = pair.search.simple_search;
        let mut search = ContactSearch::initialize(&mut model, &setup)?;
        let mut evaluated = Vec::new();
        let mut distance_threshold = 0.0;
        let mut overlap_tests = 0;
        let mut n_slaves = 0;
        let find = FindOptions {
            prefilter: options.prefilter,
            sample: options.sample,
        };
        let result = search.step_with_pairs(&mut model, key, |model, scene| {
            let found = find_true_pairs(model, scene, &find)?;
            evaluated = found.evaluated;
            distance_threshold = scene.distance_threshold;
            overlap_tests = found.overlap_tests;
            n_slaves = found.n_slaves;
            Ok(found.pairs)
        })?;
        let ids = model.conditions().ids();
        let node_ids = model.nodes().ids();
        let mut pairs = BTreeMap::new();
        let mut nodes = BTreeSet::new();
        let all = result.pairs.get(&key.to_string());
        for &s in &evaluated {
            let id = ids[s.index()];
            let masters = all.and_then(|m| m.get(&id)).cloned().unwrap_or_default();
            pairs.insert(id, masters);
            for n in model.conditions().nodes(s.index()) {
                if model.nodes().flags()[n.index()].is(Flag::SLAVE) != scene_inverted(&setup, key) {
                    nodes.insert(node_ids[n.index()]);
                }
            }
        }
        let nodes = nodes
            .into_iter()
            .filter_map(|id| result.nodes.get(&id).map(|r| (id, *r)))
            .collect();
        Ok(GroundTruth {
            key,
            simple_search,
            distance_threshold,
            n_slaves,
            sampled: evaluated.len() < n_slaves,
            pairs,
            nodes,
            overlap_tests,
        })
    }

    /// True pairs over the evaluated slave conditions.
    pub fn n_pairs(&self) -> usize {
        self.pairs.values().map(Vec::len).sum()
    }
}

fn scene_inverted(setup: &SearchSetup, key: u32) -> bool {
    setup
        .pairs
        .get(&key)
        .is_some_and(|p| p.search.inverted_search)
}
