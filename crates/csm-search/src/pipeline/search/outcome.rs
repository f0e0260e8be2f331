//! The RESULT.json content of the current state (`ContactSearch::result`).

use std::sync::atomic::{AtomicBool, Ordering};

use super::*;

impl ContactSearch {
    /// The RESULT.json content of the current state.
    pub fn result(&self, model: &ModelPart) -> SearchResult {
        self.assemble(model, self.pairs.iter().map(|_| None).collect())
    }

    /// [`ContactSearch::result`] at the end of a step: the slaves' masters of a pair whose
    /// pairing built them already (`PairSearch::step_pairs`) are taken from there.
    pub(super) fn result_of_step(&mut self, model: &ModelPart) -> SearchResult {
        let built = (self.pairs.iter_mut())
            .map(|pair| pair.step_pairs.take())
            .collect();
        let result = self.assemble(model, built);
        debug_assert!(
            result == self.result(model),
            "the step's result is the state's"
        );
        result
    }

    /// The result, with `built[i]`, where given, as pair `i`'s slaves and their masters.
    fn assemble(&self, model: &ModelPart, mut built: Vec<Option<IdMap<Vec<u32>>>>) -> SearchResult {
        let mut result = SearchResult {
            warnings: self.warnings.clone(),
            kratos_condition_ids: self.kratos_ids.clone(),
            ..Default::default()
        };
        let node_ids = model.nodes().ids();
        for (pair, built) in self.pairs.iter().zip(&mut built) {
            let inverted = pair.params.inverted_search;
            // The slave side's nodes, by node index (no sort of every face's nodes), marked in
            // parallel (every mark is `true`: the order of the writes does not matter).
            let on_slave_side: Vec<AtomicBool> = (0..model.nodes().len())
                .into_par_iter()
                .map(|_| AtomicBool::new(false))
                .collect();
            let gaps = if pair.params.check_gap == CheckGap::MappingCheck {
                model.nodal_data().scalar(ScalarVar::NormalGap, 0)
            } else {
                None
            };
            // The slave conditions' nodes marked (in parallel: the marks are all `true`).
            let cflags = model.conditions().flags();
            let is_slave = |c: &ConditionIdx| cflags[c.index()].is(Flag::SLAVE) != inverted;
            let conditions = model.part(pair.sub).conditions();
            conditions.par_iter().filter(|c| is_slave(c)).for_each(|c| {
                for n in model.conditions().nodes(c.index()) {
                    on_slave_side[n.index()].store(true, Ordering::Relaxed);
                }
            });
            let node_flags = model.nodes().flags();
            let marked: Vec<u32> = (0..on_slave_side.len() as u32)
                .into_par_iter()
                .filter(|&i| on_slave_side[i as usize].load(Ordering::Relaxed))
                .collect();
            let mut node_results: Vec<(u32, NodeResult)> = marked
                .par_iter()
                .map(|&i| {
                    let i = i as usize;
                    // NORMAL_GAP is never written by No/DirectCheck (null); MappingCheck's
                    // 1e12 "not mapped" sentinel is null too.
                    let normal_gap = gaps
                        .and_then(|g| g.get(i).copied())
                        .filter(|g| *g != csm_activation::NORMAL_GAP_SENTINEL);
                    (
                        node_ids[i],
                        NodeResult {
                            normal_gap,
                            active: node_flags[i].is(Flag::ACTIVE),
                        },
                    )
                })
                .collect();
            sort_by_id(&mut node_results);
            let node_results = IdMap::from_sorted_unchecked(node_results);
            // The slaves' masters: the map the pairing built, or built here.
            let slaves = (built.take())
                .unwrap_or_else(|| SlaveEntries::of(model, pair.sub, inverted).into_map());
            if result.nodes.is_empty() {
                result.nodes = node_results;
            } else {
                result.nodes.extend(node_results);
            }
            let pruned = by_slave(&pair.pruned);
            result.pruned.insert(pair.key.to_string(), pruned);
            result.pairs.insert(pair.key.to_string(), slaves);
            result.paired_conditions += pair.paired.len();
        }
        if self.setup.process == ContactProcess::Mpc {
            // MPCContactSearchProcess::AddPairing: one constraint per paired condition.
            result.master_slave_constraints = Some(result.paired_conditions);
        }
        result
    }
}

/// The slave conditions of a ContactSub with their INDEX_MAPs' masters: the content of
/// `SearchResult.pairs` before it becomes its map. Most slaves have no master: their ids are
/// listed alone (4 B each), and only the others carry their masters.
pub(super) struct SlaveEntries {
    /// Every slave's id, ascending.
    ids: Vec<u32>,
    /// The slaves with masters, by id: their masters, ascending.
    masters: Vec<(u32, Vec<u32>)>,
}

impl SlaveEntries {
    /// The entries of ContactSub `sub`'s slave side.
    pub(super) fn of(model: &ModelPart, sub: PartIdx, inverted: bool) -> SlaveEntries {
        let ids = model.conditions().ids();
        let cflags = model.conditions().flags();
        let is_slave = |c: &ConditionIdx| cflags[c.index()].is(Flag::SLAVE) != inverted;
        let slave_list: Vec<ConditionIdx> = (model.part(sub).conditions().par_iter())
            .copied()
            .filter(is_slave)
            .collect();
        let mut slave_ids: Vec<u32> = slave_list.par_iter().map(|c| ids[c.index()]).collect();
        let mut masters: Vec<(u32, Vec<u32>)> = (slave_list.par_iter())
            .filter(|c| !model.index_map(**c).is_empty())
            .map(|c| {
                let masters = model.index_map(*c).masters().map(ConditionId::get);
                (ids[c.index()], masters.collect())
            })
            .collect();
        // A part's conditions are duplicate-free, so each id comes once. (Usually in id
        // order already: the checks run in parallel, the sorts' own would not.)
        if !slave_ids.par_windows(2).all(|w| w[0] < w[1]) {
            slave_ids.par_sort_unstable();
        }
        sort_by_id(&mut masters);
        SlaveEntries {
            ids: slave_ids,
            masters,
        }
    }

    /// The map of `SearchResult.pairs`: every slave, with its masters or none.
    ///
    /// The map's sorted entries are written in parallel, in tasks of ids each taking its
    /// masters, into the list that becomes the map.
    pub(super) fn into_map(self) -> IdMap<Vec<u32>> {
        /// Slaves per parallel task.
        const PER_TASK: usize = 4096;
        let SlaveEntries { ids, mut masters } = self;
        // Each task's ids and the masters among them (both ascend).
        let mut tasks = Vec::with_capacity(ids.len().div_ceil(PER_TASK));
        let mut rest = masters.as_mut_slice();
        for chunk in ids.chunks(PER_TASK) {
            let last = chunk[chunk.len() - 1];
            let k = rest.partition_point(|(s, _)| *s <= last);
            let (mine, tail) = std::mem::take(&mut rest).split_at_mut(k);
            tasks.push((chunk, mine));
            rest = tail;
        }
        let mut entries: Vec<(u32, Vec<u32>)> = Vec::new();
        entries.par_extend((0..ids.len()).into_par_iter().map(|_| (0, Vec::new())));
        (entries.par_chunks_mut(PER_TASK))
            .zip(tasks)
            .for_each(|(out, (chunk, mine))| {
                let mut with = mine.iter_mut().peekable();
                for (slot, &id) in out.iter_mut().zip(chunk) {
                    slot.0 = id;
                    if let Some((_, m)) = with.next_if(|(s, _)| *s == id) {
                        slot.1 = std::mem::take(m);
                    }
                }
            });
        IdMap::from_sorted_unchecked(entries)
    }
}

/// Sorts `entries` by their (distinct) ids, unless they ascend already.
fn sort_by_id<T: Send + Sync>(entries: &mut [(u32, T)]) {
    if !entries.par_windows(2).all(|w| w[0].0 < w[1].0) {
        entries.par_sort_unstable_by_key(|(id, _)| *id);
    }
}

/// `(slave id, master id)` entries as a map from each slave id to its master ids, ascending
/// (repeated entries kept): sorted in parallel where they are not already (the mapping
/// reports them in order) and grouped by slave in parallel (each slave's masters in a list of
/// their number, no regrowth) into the map's list.
pub(crate) fn by_slave(entries: &[(u32, u32)]) -> IdMap<Vec<u32>> {
    let sorted: std::borrow::Cow<'_, [(u32, u32)]> = if entries.par_windows(2).all(|w| w[0] <= w[1])
    {
        entries.into()
    } else {
        let mut owned = entries.to_vec();
        owned.par_sort_unstable();
        owned.into()
    };
    let n = sorted.len();
    let starts: Vec<usize> = (0..n)
        .into_par_iter()
        .filter(|&k| k == 0 || sorted[k].0 != sorted[k - 1].0)
        .collect();
    let grouped: Vec<(u32, Vec<u32>)> = (starts.par_iter().enumerate())
        .map(|(g, &start)| {
            let end = starts.get(g + 1).copied().unwrap_or(n);
            let masters = sorted[start..end].iter().map(|&(_, m)| m).collect();
            (sorted[start].0, masters)
        })
        .collect();
    IdMap::from_sorted_unchecked(grouped)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map, built entry by entry: the oracle.
    fn one_by_one(ids: &[u32], masters: &[(u32, Vec<u32>)]) -> BTreeMap<u32, Vec<u32>> {
        let mut map: BTreeMap<u32, Vec<u32>> = ids.iter().map(|&id| (id, Vec::new())).collect();
        for (s, m) in masters {
            map.insert(*s, m.clone());
        }
        map
    }

    #[test]
    fn the_slaves_map_holds_every_slave_with_its_masters_on_any_pool() {
        // Sparse ids over several tasks; masters on every seventh slave, a run at a task's
        // end and the last slave.
        let ids: Vec<u32> = (0..20_000).map(|k| 3 * k + 1).collect();
        let mut masters: Vec<(u32, Vec<u32>)> = (ids.iter().step_by(7))
            .map(|&s| (s, vec![s + 5, s + 9]))
            .collect();
        masters.extend((4090..4100).map(|k| (ids[k], vec![1])));
        masters.push((ids[ids.len() - 1], vec![2, 3]));
        masters.sort_unstable_by_key(|(s, _)| *s);
        masters.dedup_by_key(|(s, _)| *s);
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let entries = SlaveEntries {
                ids: ids.clone(),
                masters: masters.clone(),
            };
            let map = pool.install(|| entries.into_map());
            assert_eq!(map, one_by_one(&ids, &masters), "{threads} threads");
        }
        let none = SlaveEntries {
            ids: Vec::new(),
            masters: Vec::new(),
        };
        assert!(none.into_map().is_empty());
    }
}
