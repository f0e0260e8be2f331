//! `SearchUsingKDTree` (reference §5.3) and the self-contact pre-search (§12.1): the kd-tree
//! over the point list, the parallel per-slave queries and the serial, ordered application.

use super::*;

/// SearchUsingKDTree (§5.3): the kd-tree over the point list, the parallel per-slave queries
/// and tests, then the serial, ordered application.
///
/// In a multi-step run (`keep_tree`) the tree of the last step is refitted to the moved
/// centres instead of rebuilt when the master-side conditions are the same and the result
/// order cannot change the pairs (not Kratos-mode DirectCheck, whose node counting follows
/// the candidate order). A refitted tree finds the same masters; if a query reaches the
/// result cap (`max_number_results`), where the traversal order decides which are kept, the
/// tree is rebuilt and every query run again.
pub(super) fn kdtree_search(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    (p, pass): (&SearchParameters, KdPass),
    plan: &PairPlan,
    (compatibility, keep_tree, query_order): (Compatibility, bool, QueryOrder),
    delta: Option<&[Vector]>,
    created: &mut Vec<(ConditionIdx, ConditionIdx)>,
) -> Result<(), Error> {
    let inverted = p.inverted_search;
    let sub = pair.sub;
    let dim = usize::from(pair.instance.dim);
    let check = !inverted || !p.predefined_master_slave;
    let pre_search = matches!(pass, KdPass::SelfContact { .. });
    let keep_tree = keep_tree && !pre_search;
    let conditions = model.part_conditions_by_id(sub);
    // The masters in id order and their centres, in two lists the tree takes as its own (no
    // list of pairs to copy: fresh memory is a large part of this stage's cost).
    let flags = model.conditions().flags();
    let (points, with_obb) = match pass {
        KdPass::Main { points, with_obb } | KdPass::SelfContact { points, with_obb } => {
            (points, with_obb)
        }
    };
    let master_list: Vec<u32> = match points {
        Some(list) => list,
        None => conditions
            .par_iter()
            .filter(|c| flags[c.index()].is(Flag::MASTER) == check)
            .map(|c| c.get())
            .collect(),
    };
    let centres_of = |list: &[u32]| -> Vec<Point> {
        let coords = model.nodes().coordinates();
        list.par_iter()
            .map(|&c| {
                let nodes = model.conditions().nodes(c as usize);
                let mut center = Point::origin();
                for n in nodes {
                    center.coords += coords[n.index()].coords;
                }
                Point::from(center.coords / nodes.len() as Real)
            })
            .collect()
    };
    let centres = centres_of(&master_list);
    crate::trace::mark("master centres");
    let tree_error = |e: csm_trees::Error| Error::tree("kd-tree of the master conditions", e);
    let new_tree = |list: Vec<u32>, centres: Vec<Point>| {
        KdTree::from_parts(list, centres, p.bucket_size, TREE_DEFER_MAX).map_err(tree_error)
    };
    let order_free = p.check_gap != CheckGap::DirectCheck || compatibility == Compatibility::Robust;
    // Kept only for a multi-step run: the next step refits the tree if its masters are these.
    let ids: Vec<u32> = if keep_tree {
        master_list.clone()
    } else {
        Vec::new()
    };
    let kept = if pre_search { None } else { pair.tree.take() };
    // The slave side, and which slaves are queried first, found beside the tree's build
    // (whose first split is one thread's work): the far test needs only the centres' box,
    // the tree's own. (The tree finds it again, one parallel pass: `from_parts` takes no
    // box, and one handed in would be a second source of truth for its extent.)
    let slaves: Vec<ConditionIdx> = conditions
        .par_iter()
        .copied()
        .filter(|c| {
            let f = model.conditions().flags()[c.index()];
            pre_search || (f.is_defined(Flag::ACTIVE) && f.is(Flag::SLAVE) != inverted)
        })
        .collect();
    let far = Far::new(csm_trees::par_bounds_of(&centres), p.search_factor);
    let shared: &ModelPart = model;
    let classify = || Classified::new(shared, &slaves, &far, query_order);
    let (built, classified) = rayon::join(
        || -> Result<(KdTree<u32>, bool), Error> {
            match kept {
                Some(mut kept) if keep_tree && order_free && kept.ids == ids => {
                    let mut at = vec![Point::origin(); shared.conditions().len()];
                    for (&c, x) in master_list.iter().zip(&centres) {
                        at[c as usize] = *x;
                    }
                    kept.tree.refit(|c| at[c as usize]).map_err(tree_error)?;
                    Ok((kept.tree, true))
                }
                _ => Ok((new_tree(master_list, centres)?, false)),
            }
        },
        classify,
    );
    let (mut tree, refitted): (KdTree<u32>, bool) = built?;
    crate::trace::mark("kd-tree");
    // Read in place: the model is only read until the serial pairing below.
    let h_col = model
        .nodal_data()
        .scalar(ScalarVar::NodalH, 0)
        .unwrap_or(&[]);
    let hmax = match pair.globals.largest_nodal_h {
        Some(h) => h,
        None => {
            // (A maximum in any grouping is the serial one.)
            let here = (model.part(sub).nodes().par_iter())
                .map(|n| h_col[n.index()])
                .reduce(|| 0.0, Real::max);
            // Every held contact node's NODAL_H is whole (its elements are held): the
            // largest of the ranks' is the whole problem's.
            match &pair.ranks {
                Some(ranks) => ranks.max(here)?,
                None => here,
            }
        }
    };
    pair.used.largest_nodal_h = Some(hmax);
    let hmax = if hmax < EPS { 1.0 } else { hmax };
    let bbf = p.octree.bounding_box_factor * hmax;
    let with_kdop = plan.kdop.is_used();
    // Master boxes, once per step (Kratos rebuilds one per candidate); No/DirectCheck build
    // them with build_from_bounding_box = true (Q4). Allocated only for the OBB test.
    let master_bfb = p.check_gap != CheckGap::MappingCheck || p.octree.build_from_bounding_box;
    // In the tree's stored order: a block of consecutive masters lies in one region of space,
    // so a query near a few masters computes the boxes of its neighbours, not of masters
    // anywhere (the conditions' own order need not be spatial).
    let masters: Vec<ConditionIdx> = tree
        .stored_items()
        .par_iter()
        .map(|&c| ConditionIdx(c))
        .collect();
    // Built when first asked for by a query, which holds the model: both are dropped before
    // the pairing changes it.
    let master_bvs = if with_obb {
        PerMaster::new(shared, &masters, move |c, points| {
            Geometry::new(shared.conditions().kind(c.index()), points)
                .and_then(|g| Bv::build(&g, dim, bbf, master_bfb, compatibility))
        })
    } else {
        PerMaster::none()
    };
    crate::trace::mark("master boxes");
    let master_kdops = if with_kdop {
        PerMaster::new(shared, &masters, move |_, points| {
            Kdop18::from_points(points).enlarged(bbf)
        })
    } else {
        PerMaster::none()
    };
    let nodal_normals = model
        .nodal_data()
        .vector(VectorVar::Normal, 0)
        .unwrap_or(&[]);
    let acf = model
        .process_info()
        .number("ACTIVE_CHECK_FACTOR")
        .unwrap_or(0.0);
    let candidates: SlaveCandidates = {
        let cx = QueryContext {
            model,
            params: p,
            obb_test: with_obb,
            kdop: with_kdop,
            bbf,
            dim,
            slave_nodes: usize::from(pair.instance.slave_nodes),
            compatibility,
            delta,
            nodal_normals,
            nodal_h: h_col,
            active_check_factor: acf,
            master_bvs: &master_bvs,
            master_kdops: &master_kdops,
        };
        // The queries of the slaves far from the tree run in slave order, in their blocks;
        // the others along a Morton curve of the slave centres (neighbouring queries visit the
        // same tree nodes and masters). The results go back to the slave order.
        let query_all = |tree: &KdTree<u32>| -> (Vec<QueryChunk>, bool) {
            let truncated = AtomicBool::new(false);
            let query = |scratch: &mut QueryScratch, k: usize, out: &mut QueryChunk| {
                match slave_candidates(&cx, tree, slaves[k], scratch) {
                    Ok(capped) => {
                        if capped {
                            truncated.store(true, Ordering::Relaxed);
                        }
                        out.list.extend_from_slice(&scratch.candidates);
                        out.counts.push(scratch.candidates.len() as u32);
                    }
                    Err(e) => {
                        out.counts.push(0);
                        if out.error.as_ref().is_none_or(|(first, _)| k < *first) {
                            out.error = Some((k, e));
                        }
                    }
                }
            };
            let run = |scratch: &mut QueryScratch, positions: &[usize]| {
                let mut out = QueryChunk::default();
                for &k in positions {
                    query(scratch, k, &mut out);
                }
                out
            };
            let mut chunks: Vec<QueryChunk> = (classified.first.par_iter())
                .map_init(QueryScratch::default, |scratch, positions| {
                    run(scratch, positions)
                })
                .collect();
            // Where many slaves come near the masters, most masters' boxes will be asked for:
            // computed first, in master order.
            if classified.curve.len() >= slaves.len() / 4 {
                master_bvs.compute_all();
                master_kdops.compute_all();
            }
            chunks.par_extend(
                (classified.curve.par_chunks(QUERY_CHUNK))
                    .map_init(QueryScratch::default, |scratch, positions| {
                        run(scratch, positions)
                    }),
            );
            (chunks, truncated.into_inner())
        };
        let (mut chunks, truncated) = query_all(&tree);
        if refitted && truncated {
            // A capped query keeps the first masters in traversal order: take a rebuilt
            // tree's order, as a step without a kept tree does.
            let mut by_id: Vec<u32> = tree.stored_items().to_vec();
            by_id.sort_unstable_by_key(|&c| model.conditions().ids()[c as usize]);
            let centres = centres_of(&by_id);
            tree = new_tree(by_id, centres)?;
            (chunks, _) = query_all(&tree);
        }
        SlaveCandidates::in_slave_order(&classified.positions(), chunks)
    };
    drop((master_bvs, master_kdops));
    crate::trace::mark("slave queries");
    if keep_tree {
        pair.tree = Some(KeptTree { ids, tree });
    }
    let active_before = (compatibility == Compatibility::Robust).then(|| active_snapshot(model));
    let pcx = PairingContext {
        params: p,
        inverted,
        slave_nodes: usize::from(pair.instance.slave_nodes),
        active_before: active_before.as_deref(),
    };
    if let Some(e) = candidates.error {
        return Err(e);
    }
    // On one thread the parallel form's extra passes cost more than they save.
    let parallel = p.check_gap == CheckGap::MappingCheck
        && rayon::current_num_threads() > 1
        && mapping_check_in_parallel(model, &pcx, &slaves, &candidates);
    if !parallel {
        for (k, s) in slaves.iter().enumerate() {
            apply_candidates(model, &pcx, *s, candidates.of(k), created);
        }
    }
    Ok(())
}

/// MappingCheck's INDEX_MAP updates ([`apply_candidates`]) of every slave in parallel, where
/// that gives the maps of the serial pass in slave order: when no candidate is itself a slave
/// with candidates, no test reads a map the pass writes ([`mapping_check_keeps`] reads the
/// candidate's), so the order of the slaves does not matter. Returns false, having changed
/// nothing, otherwise (such a candidate, or a slave with candidates listed twice).
///
/// Only the slaves with candidates are visited (most slaves of a per-face scene have none):
/// their conditions sorted, the maps are taken in blocks of consecutive conditions.
fn mapping_check_in_parallel(
    model: &mut ModelPart,
    cx: &PairingContext<'_>,
    slaves: &[ConditionIdx],
    candidates: &SlaveCandidates,
) -> bool {
    let Ok(count) = u32::try_from(slaves.len()) else {
        return false;
    };
    let start = &candidates.start;
    // The slaves with candidates: (condition index, slave position), by condition.
    let mut with: Vec<(u32, u32)> = (0..count)
        .into_par_iter()
        .filter(|&k| start[k as usize + 1] > start[k as usize])
        .map(|k| (slaves[k as usize].0, k))
        .collect();
    with.par_sort_unstable();
    // Their conditions as bits, a word per 64 conditions, filled in blocks of words.
    const WORDS: usize = 1024;
    let mut bits = vec![0u64; model.conditions().len().div_ceil(64)];
    bits.par_chunks_mut(WORDS)
        .enumerate()
        .for_each(|(b, words)| {
            let first = b * WORDS * 64;
            let from = with.partition_point(|&(s, _)| (s as usize) < first);
            let to = with.partition_point(|&(s, _)| (s as usize) < first + words.len() * 64);
            for &(s, _) in &with[from..to] {
                let at = s as usize - first;
                words[at / 64] |= 1 << (at % 64);
            }
        });
    let is_slave = |c: ConditionIdx| bits[c.index() / 64] & (1 << (c.index() % 64)) != 0;
    if with.par_windows(2).any(|w| w[0].0 == w[1].0)
        || candidates.list.par_iter().any(|c| is_slave(c.master))
    {
        return false;
    }
    let m = &*model;
    let ids = m.conditions().ids();
    // Per candidate, its master's id where the slave keeps it; written in blocks of slaves.
    let mut kept: Vec<Option<ConditionId>> = (0..candidates.list.len())
        .into_par_iter()
        .map(|_| None)
        .collect();
    slave_blocks(start, &mut kept).for_each(|(block, out)| {
        let mut to = 0;
        for k in block {
            let of_slave = candidates.of(k);
            if of_slave.is_empty() {
                continue;
            }
            let s = slaves[k];
            let slave_id = ConditionId(ids[s.index()]);
            for c in of_slave {
                if mapping_check_keeps(m, cx, (s, slave_id), c.master) {
                    out[to] = Some(ConditionId(ids[c.master.index()]));
                }
                to += 1;
            }
        }
    });
    update_listed_maps(model, &with, |map, &k| {
        let k = k as usize;
        let of_slave = &kept[start[k] as usize..start[k + 1] as usize];
        // One allocation per map (the entries would grow it a few times each).
        map.reserve(of_slave.iter().flatten().count());
        for &master in of_slave.iter().flatten() {
            map.add_id(master);
        }
    });
    true
}

/// Which kd-tree search [`kdtree_search`] runs.
pub(super) enum KdPass {
    /// SearchUsingKDTree (§5.3): the slave-side conditions against `points` (the MASTER
    /// conditions when `None`).
    Main {
        points: Option<Vec<u32>>,
        with_obb: bool,
    },
    /// The self-contact pre-search (§12.1): every condition against `points`, candidates
    /// kept by CheckCondition into the INDEX_MAPs, whatever `check_gap`.
    SelfContact {
        points: Option<Vec<u32>>,
        with_obb: bool,
    },
}

/// Roles not predefined (§5 step 5, §12.1): the point list (the MASTER conditions when
/// empty), the pre-search of every condition against it, `ComputeSelfContactPairing`
/// (§12.2), then the point list becomes the conditions left without candidates (id order)
/// and every INDEX_MAP is cleared for the main search.
pub(super) fn self_contact_roles(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    p: &SearchParameters,
    plan: &PairPlan,
    (compatibility, query_order): (Compatibility, QueryOrder),
    delta: Option<&[Vector]>,
) -> Result<(), Error> {
    let sub = pair.sub;
    if pair.points.is_empty() {
        let flags = model.conditions().flags();
        pair.points = model
            .part_conditions_by_id(sub)
            .iter()
            .filter(|c| flags[c.index()].is(Flag::MASTER))
            .map(|c| c.get())
            .collect();
    }
    // CheckCondition always (MappingCheck), build_from_bounding_box for both boxes; the OBB
    // test only for the kd-tree types with OBB (the octree's pre-search is a radius search).
    let pre = SearchParameters {
        check_gap: CheckGap::MappingCheck,
        ..p.clone()
    };
    let with_obb = matches!(
        p.type_search,
        SearchTreeType::KdtreeInRadiusWithObb | SearchTreeType::KdtreeInBoxWithObb
    );
    let pass = KdPass::SelfContact {
        points: Some(pair.points.clone()),
        with_obb,
    };
    let mut none = Vec::new();
    kdtree_search(
        model,
        pair,
        (&pre, pass),
        plan,
        (compatibility, false, query_order),
        delta,
        &mut none,
    )?;
    compute_self_contact_pairing(model, sub)?;
    let conditions = model.part_conditions_by_id(sub).into_owned();
    pair.points = conditions
        .iter()
        .filter(|c| model.index_map(**c).is_empty())
        .map(|c| c.get())
        .collect();
    for c in conditions {
        model.index_map_mut(c).clear();
    }
    Ok(())
}

/// Slave queries per parallel task.
pub(super) const QUERY_CHUNK: usize = 256;

/// Subtrees of the step's kd-tree over at most this many master centres are built when a
/// slave query first reaches them ([`KdTree::new_deferred`]: the same tree, the same query
/// results): where the bodies touch in a small region, most are never built (sphere 2e5:
/// the tree 0.093 → 0.045 s on one thread; 256 and 4096 points measured alike or worse).
pub(super) const TREE_DEFER_MAX: usize = 1024;

/// The candidates of consecutive queries (along the Morton curve) of one task.
#[derive(Default)]
pub(super) struct QueryChunk {
    /// Per query, its number of candidates.
    counts: Vec<u32>,
    list: Vec<Candidate>,
    /// The error of the query with the smallest slave position, if any.
    error: Option<(usize, Error)>,
}

/// Which slaves' queries run first, in slave order, and which along a Morton curve of their
/// centres (`query_order`; [`Far`]).
pub(super) struct Classified {
    /// Per block of [`QUERY_CHUNK`] consecutive slaves, the positions of those queried first.
    first: Vec<Vec<usize>>,
    /// The positions of the others, along the curve.
    curve: Vec<usize>,
}

impl Classified {
    fn new(model: &ModelPart, slaves: &[ConditionIdx], far: &Far, order: QueryOrder) -> Self {
        // Per block: the positions queried first, and the others with their centres.
        type Block = (Vec<usize>, Vec<(usize, Point)>);
        let blocks: Vec<Block> = slaves
            .par_chunks(QUERY_CHUNK)
            .enumerate()
            .map(|(i, chunk)| {
                let (mut first, mut near) = (Vec::new(), Vec::new());
                for (j, &c) in chunk.iter().enumerate() {
                    let k = i * QUERY_CHUNK + j;
                    let (centre, radius) = reach(model, c);
                    let is_first = match order {
                        QueryOrder::Estimate => far.is_far(&centre, radius),
                        QueryOrder::AllFirst => true,
                        QueryOrder::AllAlongCurve => false,
                    };
                    if is_first {
                        first.push(k);
                    } else {
                        near.push((k, centre));
                    }
                }
                (first, near)
            })
            .collect();
        // The near slaves' curve from the blocks' lists as they are (no list of them joined
        // on one thread).
        let near: Vec<&[(usize, Point)]> = blocks.iter().map(|(_, n)| n.as_slice()).collect();
        let curve = morton_order_of_parts(&near);
        drop(near);
        let first = blocks.into_iter().map(|(f, _)| f).collect();
        Classified { first, curve }
    }

    /// The slave positions of the query chunks, in the chunks' order: the first blocks', then
    /// the curve in [`QUERY_CHUNK`]s.
    fn positions(&self) -> Vec<&[usize]> {
        (self.first.iter().map(Vec::as_slice))
            .chain(self.curve.chunks(QUERY_CHUNK))
            .collect()
    }
}

/// The candidates of every slave, flat: slave `k`'s are `list[start[k]..start[k + 1]]`.
pub(super) struct SlaveCandidates {
    start: Vec<u32>,
    list: Vec<Candidate>,
    /// The error of the first slave (in slave order) whose query failed.
    error: Option<Error>,
}

impl SlaveCandidates {
    /// From the chunks of the queries of the slave positions `positions` (chunk by chunk:
    /// together a permutation of the slave positions).
    ///
    /// In parallel, with no fresh memory touched on one thread: each query's place (its chunk
    /// and offset there) is written at its slave's position (each position once: the writes
    /// do not depend on their order), then the candidates are copied in blocks of slaves.
    fn in_slave_order(positions: &[&[usize]], chunks: Vec<QueryChunk>) -> SlaveCandidates {
        use std::sync::atomic::{AtomicU32, AtomicU64, Ordering::Relaxed};
        let n: usize = positions.iter().map(|p| p.len()).sum();
        // Per slave position: its query's chunk (high half) and offset in that chunk's list
        // (low half), and its number of candidates.
        let place: Vec<AtomicU64> = (0..n).into_par_iter().map(|_| AtomicU64::new(0)).collect();
        let count: Vec<AtomicU32> = (0..n).into_par_iter().map(|_| AtomicU32::new(0)).collect();
        chunks.par_iter().enumerate().for_each(|(ci, chunk)| {
            let mut from = 0u64;
            for (&k, &c) in positions[ci].iter().zip(&chunk.counts) {
                place[k].store(((ci as u64) << 32) | from, Relaxed);
                count[k].store(c, Relaxed);
                from += u64::from(c);
            }
        });
        let mut start = Vec::with_capacity(n + 1);
        start.push(0u32);
        let mut total = 0u32;
        for c in &count {
            total += c.load(Relaxed);
            start.push(total);
        }
        let mut list: Vec<Candidate> = (0..total as usize)
            .into_par_iter()
            .map(|_| Candidate {
                master: ConditionIdx(0),
                node_pass: 0,
            })
            .collect();
        slave_blocks(&start, &mut list).for_each(|(slaves, out)| {
            let mut to = 0;
            for k in slaves {
                let at = place[k].load(Relaxed);
                let (ci, from) = ((at >> 32) as usize, (at & u64::from(u32::MAX)) as usize);
                let c = count[k].load(Relaxed) as usize;
                out[to..to + c].copy_from_slice(&chunks[ci].list[from..from + c]);
                to += c;
            }
        });
        let mut error: Option<(usize, Error)> = None;
        for chunk in chunks {
            if let Some((k, e)) = chunk.error
                && error.as_ref().is_none_or(|(first, _)| k < *first)
            {
                error = Some((k, e));
            }
        }
        SlaveCandidates {
            start,
            list,
            error: error.map(|(_, e)| e),
        }
    }

    fn of(&self, k: usize) -> &[Candidate] {
        &self.list[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

/// A list with an entry per candidate ([`SlaveCandidates`]' `start`), cut into blocks of
/// consecutive slaves for parallel tasks: each block's slave positions and its part of `list`.
fn slave_blocks<'a, T: Send>(
    start: &[u32],
    list: &'a mut [T],
) -> impl ParallelIterator<Item = (std::ops::Range<usize>, &'a mut [T])> {
    const BLOCK: usize = 2048;
    let n = start.len() - 1;
    let mut blocks = Vec::with_capacity(n.div_ceil(BLOCK));
    let mut rest = list;
    for b in (0..n).step_by(BLOCK) {
        let e = (b + BLOCK).min(n);
        let (head, tail) = std::mem::take(&mut rest).split_at_mut((start[e] - start[b]) as usize);
        blocks.push((b..e, head));
        rest = tail;
    }
    blocks.into_par_iter()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::tests::in_pool;
    use crate::scenes::{plates, plates_setup};

    /// [`mapping_check_in_parallel`] on two threads against the serial pass of
    /// [`apply_candidates`] in slave order: `lists[k]` are slave `k`'s candidates.
    /// Returns whether the parallel form ran; where it did, the maps must be the serial ones,
    /// and where it refused, the model must be unchanged.
    fn parallel_against_serial(slaves: &[ConditionIdx], lists: &[Vec<ConditionIdx>]) -> bool {
        let mut model = plates(1, -0.005, false);
        compute_unit_normals(&mut model, None, NormalsMode::Kratos).unwrap();
        // Roles not predefined: every candidate's map is read (the reverse pairs).
        let params = SearchParameters {
            predefined_master_slave: false,
            ..plates_setup("{}", "").pairs[&0].search.clone()
        };
        let cx = PairingContext {
            params: &params,
            inverted: false,
            slave_nodes: 3,
            active_before: None,
        };
        let mut start = vec![0u32];
        let mut list = Vec::new();
        for l in lists {
            list.extend(l.iter().map(|&master| Candidate {
                master,
                node_pass: 0,
            }));
            start.push(list.len() as u32);
        }
        let candidates = SlaveCandidates {
            start,
            list,
            error: None,
        };
        let before = model.clone();
        let mut serial = model.clone();
        for (k, &s) in slaves.iter().enumerate() {
            apply_candidates(&mut serial, &cx, s, candidates.of(k), &mut Vec::new());
        }
        let kept = |m: &ModelPart| slaves.iter().map(|&s| m.index_map(s).len()).sum::<usize>();
        assert!(kept(&serial) > 0, "the serial pass keeps pairs");
        let ran = in_pool(2, || {
            mapping_check_in_parallel(&mut model, &cx, slaves, &candidates)
        });
        let expected = if ran { &serial } else { &before };
        for c in 0..model.conditions().len() {
            let c = ConditionIdx(c as u32);
            assert_eq!(model.index_map(c), expected.index_map(c), "condition {c:?}");
        }
        ran
    }

    #[test]
    fn the_parallel_mapping_check_refuses_where_the_slaves_order_matters() {
        let model = plates(1, -0.005, false);
        let part = |name| {
            model
                .part(model.find_part(name).unwrap())
                .conditions()
                .to_vec()
        };
        let (s, m) = (part("Slave"), part("Master"));
        // Each other's candidate: in slave order the second pair is a reverse pair, refused.
        assert!(!parallel_against_serial(
            &[s[0], m[0]],
            &[vec![m[0]], vec![s[0]]]
        ));
        // The same slave twice, with candidates.
        assert!(!parallel_against_serial(
            &[s[0], s[0]],
            &[vec![m[0]], vec![m[1]]]
        ));
        // A candidate that is a slave without candidates: its map is not written.
        assert!(parallel_against_serial(
            &[s[0], m[0], s[1]],
            &[vec![m[0], m[1]], vec![], vec![m[1]]]
        ));
        // A slave without candidates listed twice.
        assert!(parallel_against_serial(
            &[s[0], m[0], m[0]],
            &[vec![m[1]], vec![], vec![]]
        ));
    }
}
