//! The partitioned-mesh API ([`search_partitioned`]): a host code whose mesh is already split
//! across its ranks passes each rank's piece; csm exchanges what the search needs and gives
//! each rank the results of its own conditions and nodes.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use csm_geometry::GeometryKind;
use csm_model::{EntityArrays, MeshArrays, Ranks, Transport};
use csm_search::{SearchResult, SearchSetup};

use crate::codec::{decode_mesh, decode_result, encode_mesh};
use crate::run::{RankTimes, RunError, Stop, gathered_results, merge, stopped, with_interfaces};

/// One rank of a search of a mesh already split across the ranks of `transport` (its
/// communicator): `local` is this rank's piece, with global ids — its nodes, elements,
/// contact conditions and parts. Pieces may overlap (a node on a partition boundary given by
/// every rank that uses it), but what two ranks both give must agree. Every rank calls it
/// with the same `setup`.
///
/// csm gathers the pieces, splits the contact problem by its own bisection of the slave
/// conditions (`docs/distributed.md`), searches each rank's share with the values the ranks
/// share, and returns to each rank the result for what it passed: the pairs of its slave
/// conditions, the NORMAL_GAP and ACTIVE flag of its slave nodes, with the whole run's
/// warnings and counters (paired conditions, Kratos' condition ids). Every value is the one
/// the one-process search of the whole mesh gives. Any rank's error stops every rank with
/// the lowest failed rank's message.
///
/// This first version gathers every piece on every rank (the whole mesh's memory on each);
/// the exchange by reach is the design's next step.
pub fn search_partitioned(
    transport: Arc<dyn Transport>,
    local: &MeshArrays,
    setup: &SearchSetup,
) -> Result<SearchResult, RunError> {
    let anyone = Ranks::new(Arc::clone(&transport), &[], &[]);
    let pieces = anyone
        .gather_bytes(&encode_mesh(local))
        .map_err(|a| stopped(&transport, Stop::from(a)))?;
    // Every rank merges the same pieces: an error is every rank's, the same.
    let whole = pieces
        .iter()
        .map(|b| decode_mesh(b))
        .collect::<Result<Vec<_>, _>>()
        .and_then(|pieces| join(&pieces))
        .map_err(|e| stopped(&transport, Stop::Failed(e)))?;
    // Conditions generated from the elements would belong to no piece, and their pairs to no
    // rank: the pieces must bring the contact conditions (every rank decides alike).
    if with_interfaces(&whole, setup)
        .map_err(|e| stopped(&transport, e))?
        .is_some()
    {
        return Err(stopped(
            &transport,
            Stop::Failed(
                "the partitioned search needs the contact conditions in the pieces: a contact \
                 part without conditions would have them generated from the elements, and they \
                 would belong to no piece"
                    .to_owned(),
            ),
        ));
    }
    let mut times = RankTimes::default();
    let (_, all) = gathered_results(&transport, &whole, setup, &mut times)?;
    let parts: Vec<SearchResult> = all.iter().map(|b| decode_result(b)).collect();
    let result = merge(parts, &whole, setup);
    Ok(restricted(result, local))
}

/// The pieces as one mesh: every entity once (in ascending id order, as the serial order of
/// the global sums needs), the parts' members together; an entity two pieces give
/// differently is an error.
fn join(pieces: &[MeshArrays]) -> Result<MeshArrays, String> {
    let mut nodes: BTreeMap<u32, [f64; 3]> = BTreeMap::new();
    let mut elements = Entities::default();
    let mut conditions = Entities::default();
    let mut parts: BTreeMap<String, [BTreeSet<u32>; 3]> = BTreeMap::new();
    let mut domain_size = None;
    for (rank, piece) in pieces.iter().enumerate() {
        for (&id, p) in piece.node_ids.iter().zip(&piece.points) {
            if let Some(q) = nodes.insert(id, *p)
                && q.map(f64::to_bits) != p.map(f64::to_bits)
            {
                return Err(format!(
                    "node {id}: rank {rank} gives {p:?}, an earlier rank {q:?}"
                ));
            }
        }
        elements.add(&piece.elements, ("element", rank))?;
        conditions.add(&piece.conditions, ("condition", rank))?;
        for (name, p) in &piece.parts {
            let sets = parts.entry(name.clone()).or_default();
            sets[0].extend(&p.nodes);
            sets[1].extend(&p.elements);
            sets[2].extend(&p.conditions);
        }
        domain_size = domain_size.or(piece.domain_size);
    }
    let (node_ids, points) = nodes.into_iter().unzip();
    Ok(MeshArrays {
        node_ids,
        points,
        elements: elements.arrays(),
        conditions: conditions.arrays(),
        parts: parts
            .into_iter()
            .map(|(name, [n, e, c])| {
                let part = csm_model::PartArrays {
                    nodes: n.into_iter().collect(),
                    elements: e.into_iter().collect(),
                    conditions: c.into_iter().collect(),
                };
                (name, part)
            })
            .collect(),
        domain_size,
    })
}

/// Entities by id: kind, nodes, properties.
#[derive(Default)]
struct Entities(BTreeMap<u32, (GeometryKind, Vec<u32>, u32)>);

impl Entities {
    fn add(
        &mut self,
        by_kind: &BTreeMap<GeometryKind, EntityArrays>,
        (what, rank): (&str, usize),
    ) -> Result<(), String> {
        for (&kind, a) in by_kind {
            let n = kind.n_nodes();
            for (k, &id) in a.ids.iter().enumerate() {
                let nodes = a.connectivity.get(k * n..(k + 1) * n).ok_or_else(|| {
                    format!(
                        "{what} {id}: rank {rank} gives fewer nodes than a {}",
                        kind.name()
                    )
                })?;
                let entry = (
                    kind,
                    nodes.to_vec(),
                    a.properties.get(k).copied().unwrap_or(0),
                );
                if let Some(other) = self.0.insert(id, entry.clone())
                    && other != entry
                {
                    return Err(format!(
                        "{what} {id}: rank {rank} gives {:?}, an earlier rank {:?}",
                        entry, other
                    ));
                }
            }
        }
        Ok(())
    }

    fn arrays(self) -> BTreeMap<GeometryKind, EntityArrays> {
        let mut out: BTreeMap<GeometryKind, EntityArrays> = BTreeMap::new();
        for (id, (kind, nodes, properties)) in self.0 {
            let a = out.entry(kind).or_default();
            a.ids.push(id);
            a.connectivity.extend(nodes);
            a.properties.push(properties);
        }
        out
    }
}

/// The result for what `local` holds: the pairs of its conditions, the results of its
/// nodes; the warnings and counters of the whole run.
fn restricted(mut result: SearchResult, local: &MeshArrays) -> SearchResult {
    let conditions: BTreeSet<u32> = (local.conditions.values())
        .flat_map(|a| a.ids.iter().copied())
        .collect();
    let nodes: BTreeSet<u32> = local.node_ids.iter().copied().collect();
    for maps in [&mut result.pairs, &mut result.pruned] {
        for map in maps.values_mut() {
            map.retain(|id, _| conditions.contains(id));
        }
    }
    result.nodes.retain(|id, _| nodes.contains(id));
    result
}
