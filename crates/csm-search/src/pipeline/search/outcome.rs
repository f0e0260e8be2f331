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
            let node_results = by_id(&marked, |&i| {
                let i = i as usize;
                // NORMAL_GAP is never written by No/DirectCheck (null); MappingCheck's 1e12
                // "not mapped" sentinel is null too.
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
            });
            // The slaves' masters: the map the pairing built, or built here.
            let slaves = (built.take()).unwrap_or_else(|| slave_map(model, pair.sub, inverted));
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

/// The slave conditions of ContactSub `sub`'s slave side, each with its INDEX_MAP's masters
/// (ascending, none for most): the map of `SearchResult.pairs`.
pub(super) fn slave_map(model: &ModelPart, sub: PartIdx, inverted: bool) -> IdMap<Vec<u32>> {
    let ids = model.conditions().ids();
    let cflags = model.conditions().flags();
    let is_slave = |c: &ConditionIdx| cflags[c.index()].is(Flag::SLAVE) != inverted;
    let slaves: Vec<ConditionIdx> = (model.part(sub).conditions().par_iter())
        .copied()
        .filter(is_slave)
        .collect();
    // (A slave without masters collects an empty list: no allocation.)
    by_id(&slaves, |c| {
        let masters = model
            .index_map(*c)
            .masters()
            .map(ConditionId::get)
            .collect();
        (ids[c.index()], masters)
    })
}

/// The map of the entries `entry` gives for `items` (distinct ids): written in one parallel
/// pass in the items' order into the map's list, sorted after in parallel where the ids do
/// not ascend already (a part's conditions usually come in id order).
fn by_id<T: Sync, V: Send + Sync>(
    items: &[T],
    entry: impl Fn(&T) -> (u32, V) + Sync + Send,
) -> IdMap<V> {
    let mut entries: Vec<(u32, V)> = items.par_iter().map(entry).collect();
    sort_by_id(&mut entries);
    IdMap::from_sorted_unchecked(entries)
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

    /// The map of entries in a scrambled order, on pools of 1–3 threads, is the one a
    /// `BTreeMap` collects; ascending entries stay as they are.
    #[test]
    fn entries_become_the_map_in_id_order_on_any_pool() {
        // Sparse ids, masters on every seventh.
        let entry = |k: &u32| {
            let id = 3 * k + 1;
            let masters = if k.is_multiple_of(7) {
                vec![id + 5, id + 9]
            } else {
                Vec::new()
            };
            (id, masters)
        };
        let ascending: Vec<u32> = (0..20_000).collect();
        let scrambled: Vec<u32> = (0..20_000u32).map(|k| (k * 7919) % 20_000).collect();
        let oracle: BTreeMap<u32, Vec<u32>> = ascending.iter().map(entry).collect();
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for items in [&ascending, &scrambled] {
                let map = pool.install(|| by_id(items, entry));
                assert_eq!(map, oracle, "{threads} threads");
            }
        }
        assert!(by_id(&[] as &[u32], entry).is_empty());
    }
}
