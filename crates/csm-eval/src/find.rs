//! The exhaustive pair search of the ground truth: sample, prefilter, orientation filter and
//! exact segmentation of every remaining slave × master pair, in parallel.

use std::collections::BTreeSet;

use csm_activation as act;
use csm_geometry::math::{Point, Real, Vector};
use csm_geometry::{Aabb, MortarMode, SegmentationSettings};
use csm_model::{ConditionIdx, Flag, ModelPart};
use csm_trees::KdTree;
use rayon::prelude::*;

use csm_search::{Error, ErrorKind, TruthScene, passes_orientation};

use crate::compute::{MIN_OVERLAP_RATIO, Sample};

/// What [`find_true_pairs`] is asked to do.
pub(super) struct FindOptions {
    pub prefilter: bool,
    pub sample: Option<Sample>,
}

/// What [`find_true_pairs`] found.
pub(super) struct Found {
    /// The true pairs of every slave searched (the evaluated ones and, with a sample, their
    /// neighbours).
    pub pairs: Vec<(ConditionIdx, ConditionIdx)>,
    /// The evaluated slave conditions, in id order.
    pub evaluated: Vec<ConditionIdx>,
    /// Slave-side conditions of the pair.
    pub n_slaves: usize,
    /// Segmentations computed.
    pub overlap_tests: usize,
}

/// One slave's true pairs and the number of overlap tests made for it.
type SlavePairs = (Vec<(ConditionIdx, ConditionIdx)>, usize);

fn model_error(e: &act::Error) -> Error {
    ErrorKind::Activation(e.clone()).into()
}

/// The true pairs of the ContactSub of `scene` (see the module docs of `truth`). The model's
/// condition normals are those the orientation filter reads (the search's unit normals); the
/// mapping's normals are computed here for the segmentation.
pub(super) fn find_true_pairs(
    model: &mut ModelPart,
    scene: &TruthScene,
    options: &FindOptions,
) -> Result<Found, Error> {
    let ids = model.conditions().ids();
    let mut conditions = model.part(scene.sub).conditions().to_vec();
    conditions.sort_by_key(|c| ids[c.index()]);
    let flags = model.conditions().flags();
    let slaves: Vec<ConditionIdx> = conditions
        .iter()
        .copied()
        .filter(|c| flags[c.index()].is(Flag::SLAVE) != scene.inverted)
        .collect();
    let masters: Vec<ConditionIdx> = conditions
        .iter()
        .copied()
        .filter(|c| flags[c.index()].is(Flag::MASTER) == scene.master_check)
        .collect();
    let evaluated = match options.sample {
        Some(sample) if sample.size < slaves.len() => sample_of(&slaves, sample),
        _ => slaves.clone(),
    };
    let searched = if evaluated.len() < slaves.len() {
        with_neighbours(model, &slaves, &evaluated)
    } else {
        evaluated.clone()
    };
    // The orientation filter reads the search's normals; the segmentation the mapping's.
    let orientation_normals = model.condition_normals().to_vec();
    act::mapping_normals(model, scene.sub, scene.inverted).map_err(|e| model_error(&e))?;
    let model = &*model;
    let prefilter = (options.prefilter && scene.dim == 3)
        .then(|| Prefilter::new(model, &masters))
        .transpose()?;
    let settings = SegmentationSettings {
        mode: MortarMode::Robust,
        distance_threshold: scene.distance_threshold,
    };
    let ids = model.conditions().ids();
    let per_slave: Vec<Result<SlavePairs, Error>> = searched
        .par_iter()
        .map_init(Vec::new, |found, &s| {
            let candidates: &[ConditionIdx] = match &prefilter {
                Some(f) => {
                    f.candidates(model, s, scene.distance_threshold, found)?;
                    found
                }
                None => &masters,
            };
            let mut pairs = Vec::new();
            let mut tests = 0;
            for &m in candidates {
                if !passes_orientation(
                    ids[s.index()],
                    ids[m.index()],
                    &orientation_normals[s.index()],
                    &orientation_normals[m.index()],
                    scene.normal_orientation_threshold,
                ) {
                    continue;
                }
                tests += 1;
                let (overlap, slave_measure) =
                    act::overlap_measure(model, s, m, &settings).map_err(|e| model_error(&e))?;
                if overlap.is_some_and(|a| a > MIN_OVERLAP_RATIO * slave_measure) {
                    pairs.push((s, m));
                }
            }
            Ok((pairs, tests))
        })
        .collect();
    let mut pairs = Vec::new();
    let mut overlap_tests = 0;
    for r in per_slave {
        let (p, t) = r?;
        pairs.extend(p);
        overlap_tests += t;
    }
    Ok(Found {
        pairs,
        evaluated,
        n_slaves: slaves.len(),
        overlap_tests,
    })
}

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, seedable generator, so the sample is the same
/// on every platform and version.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// `sample.size` of `slaves` (partial Fisher–Yates), in the original (id) order.
fn sample_of(slaves: &[ConditionIdx], sample: Sample) -> Vec<ConditionIdx> {
    let mut rng = SplitMix64(sample.seed);
    let mut pool: Vec<usize> = (0..slaves.len()).collect();
    let k = sample.size.min(pool.len());
    for i in 0..k {
        let span = (pool.len() - i) as u64;
        let j = i + (rng.next() % span) as usize;
        pool.swap(i, j);
    }
    let mut chosen = pool[..k].to_vec();
    chosen.sort_unstable();
    chosen.into_iter().map(|i| slaves[i]).collect()
}

/// `evaluated` and every slave condition that shares a node with one of them (the mapped gap
/// of a node depends on all the slave faces around it), in the order of `slaves`.
fn with_neighbours(
    model: &ModelPart,
    slaves: &[ConditionIdx],
    evaluated: &[ConditionIdx],
) -> Vec<ConditionIdx> {
    let nodes: BTreeSet<usize> = evaluated
        .iter()
        .flat_map(|c| {
            model
                .conditions()
                .nodes(c.index())
                .iter()
                .map(|n| n.index())
        })
        .collect();
    slaves
        .iter()
        .copied()
        .filter(|c| {
            model
                .conditions()
                .nodes(c.index())
                .iter()
                .any(|n| nodes.contains(&n.index()))
        })
        .collect()
}

/// The conservative 3D prefilter. The segmentation projects the master along the slave's unit
/// normal `n` onto the plane through the slave centre `C` and rejects the pair when a master
/// node lies farther than the threshold `d` in front (`(X − C)·n > d`). So a master that
/// overlaps has a point `X = P + τ n` with `P` in the projected slave polygon and `τ ≤ d`;
/// the projected slave nodes lie within `ℓ` (the slave box's diagonal) of the slave's box `S`
/// along `n`, hence `X ∈ S ⊕ [τ_lo, d + ℓ]·n`; and `X` lies in the box `B` of all masters,
/// which bounds `τ_lo`. Every master whose box meets that swept box (enlarged by a relative
/// 1e-9 for rounding) is tested; no other can overlap.
struct Prefilter {
    tree: KdTree<u32>,
    boxes: Vec<Aabb>,
    /// The largest half extent of a master box per axis (the tree holds the centres).
    half: Vector,
    /// The box of every master, enlarged by `margin`.
    all: Aabb,
    margin: Real,
}

fn aabb_of(model: &ModelPart, c: ConditionIdx) -> Aabb {
    let mut b = Aabb::EMPTY;
    for n in model.conditions().nodes(c.index()) {
        b.grow(&model.nodes().coordinates()[n.index()]);
    }
    b
}

impl Prefilter {
    fn new(model: &ModelPart, masters: &[ConditionIdx]) -> Result<Prefilter, Error> {
        let mut boxes = vec![Aabb::EMPTY; model.conditions().len()];
        let mut all = Aabb::EMPTY;
        let mut half = Vector::zeros();
        let mut points = Vec::with_capacity(masters.len());
        for &m in masters {
            let b = aabb_of(model, m);
            all = all.union(&b);
            half = half.sup(&((b.max - b.min) / 2.0));
            points.push((m.get(), Point::from((b.min.coords + b.max.coords) / 2.0)));
            boxes[m.index()] = b;
        }
        let margin = if masters.is_empty() {
            0.0
        } else {
            1e-9 * (all.max - all.min).norm() + 1e-300
        };
        let tree = KdTree::new(&points, 16).map_err(|e| Error::tree("ground truth kd-tree", e))?;
        let m = Vector::repeat(margin);
        Ok(Prefilter {
            tree,
            boxes,
            half,
            all: Aabb::new(all.min - m, all.max + m),
            margin,
        })
    }

    /// The masters that may overlap slave `s` (see the type's docs), into `out`.
    fn candidates(
        &self,
        model: &ModelPart,
        s: ConditionIdx,
        distance_threshold: Real,
        out: &mut Vec<ConditionIdx>,
    ) -> Result<(), Error> {
        out.clear();
        let sb = aabb_of(model, s);
        let n = model.condition_normals()[s.index()];
        let ell = (sb.max - sb.min).norm();
        let mut lo = Real::NEG_INFINITY;
        let mut hi = distance_threshold + ell;
        for k in 0..3 {
            let (a0, a1) = (self.all.min[k], self.all.max[k]);
            if n[k] == 0.0 || !n[k].is_finite() {
                if !n[k].is_finite() {
                    lo = Real::NEG_INFINITY;
                    hi = Real::INFINITY;
                    break;
                }
                if sb.max[k] < a0 || sb.min[k] > a1 {
                    return Ok(());
                }
                continue;
            }
            // sb.min + τ n ≤ a1 and sb.max + τ n ≥ a0.
            let (t1, t2) = ((a1 - sb.min[k]) / n[k], (a0 - sb.max[k]) / n[k]);
            let (tl, th) = if n[k] > 0.0 { (t2, t1) } else { (t1, t2) };
            lo = lo.max(tl);
            hi = hi.min(th);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            // A non-finite normal: test every master.
            out.extend(
                self.boxes
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| !b.is_empty())
                    .map(|(i, _)| ConditionIdx(i as u32)),
            );
            return Ok(());
        }
        if lo > hi {
            return Ok(());
        }
        let (e0, e1) = (n * lo, n * hi);
        let m = Vector::repeat(self.margin + 1e-9 * ell);
        let qmin = sb.min + e0.inf(&e1) - m;
        let qmax = sb.max + e0.sup(&e1) + m;
        let mut found = Vec::new();
        self.tree
            .in_box(
                &(qmin - self.half),
                &(qmax + self.half),
                usize::MAX,
                &mut found,
            )
            .map_err(|e| Error::tree("ground truth query", e))?;
        found.sort_unstable();
        for c in found {
            let b = &self.boxes[c as usize];
            let meets = (0..3).all(|k| b.min[k] <= qmax[k] && b.max[k] >= qmin[k]);
            if meets {
                out.push(ConditionIdx(c));
            }
        }
        Ok(())
    }
}
