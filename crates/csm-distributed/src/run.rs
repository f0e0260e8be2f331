//! One rank of a distributed search ([`search_rank`]): its part of the mesh searched with the
//! values the ranks share, its owned results gathered and merged on rank 0.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use std::time::Instant;

use csm_model::{MeshArrays, ModelPart, Ranks, Transport};
use csm_search::{ContactSearch, IdMap, SearchResult, SearchSetup, SearchTreeType, StepResult};

use crate::codec::{decode_result, encode_result};
use crate::{RankPart, Reach, split_rank};

/// Why a distributed run failed: the message of the lowest rank that failed, the same on
/// every rank (each rank returns it, none is left waiting).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunError(pub String);

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for RunError {}

/// What stopped a rank: its own error, or another rank's.
pub(crate) enum Stop {
    Failed(String),
    Aborted,
}

impl From<csm_model::Aborted> for Stop {
    fn from(_: csm_model::Aborted) -> Stop {
        Stop::Aborted
    }
}

impl From<csm_search::Error> for Stop {
    fn from(e: csm_search::Error) -> Stop {
        if e.is_aborted() {
            Stop::Aborted
        } else {
            Stop::Failed(e.to_string())
        }
    }
}

/// How a distributed run splits a setup's contact area (`docs/distributed.md`, "What runs").
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DistributedPlan {
    /// The parts whose conditions the ranks own (each condition one rank, by the recursive
    /// coordinate bisection; a node goes with its lowest-id condition there): the pairs' slave
    /// parts, or every contact part where every rank holds the whole area.
    pub owned_parts: Vec<String>,
    /// Every contact part of the pairs.
    pub contact_parts: Vec<String>,
    /// Why every rank searches the whole mesh, where a pair depends on a decision over the
    /// whole contact area (the ranks then own the contact conditions of their bisection and
    /// rank 0 the conditions the search makes); `None`: a rank holds its owned conditions
    /// and what they read.
    pub whole_area: Option<&'static str>,
}

/// How a distributed run takes `setup`, or why it cannot run distributed yet
/// (`docs/distributed.md`, "What runs").
pub fn distributed_plan(setup: &SearchSetup) -> Result<DistributedPlan, String> {
    let refuse = |what: &str| Err(format!("a distributed run does not support {what} yet"));
    if setup.pairs.is_empty() {
        return refuse("a setup without contact pairs");
    }
    let automatic = setup.pairs.values().any(|p| p.slaves.is_empty());
    let whole_area = if setup.skin {
        // The contact faces are found on the whole mesh's skin.
        Some("skin detection")
    } else if !setup.steps.is_empty() {
        // The bodies move: what a slave reaches changes from step to step.
        Some("multi-step runs")
    } else if setup.adapt_search {
        // The search factor comes from NODAL_H over every node.
        Some("`adapt_search`")
    } else if setup.pairs.values().any(|p| p.search.inverted_search) {
        // Its pairs are keyed by the master-side conditions.
        Some("`inverted_search`")
    } else if setup.pairs.len() > 1 {
        // A later pair searches the paired conditions the earlier ones made.
        Some("several contact pairs")
    } else if automatic {
        // The roles come from a search over the whole pair and a walk over its conditions
        // in adjacency order (reference §12).
        Some("roles decided automatically")
    } else if setup.compatibility == csm_search::Compatibility::Kratos
        && (setup.pairs.values()).any(|p| p.search.type_search == SearchTreeType::OctreeWithObb)
    {
        // Kratos' loop carries SELECTED flags from condition to condition in id order: a
        // master still SELECTED by an earlier slave pairs with the SELECTED masters of its
        // leaves (Q14), so a pair depends on slaves anywhere before it.
        Some("kratos mode's octree")
    } else {
        None
    };
    let mut owned_parts: Vec<String> = Vec::new();
    let mut contact_parts: Vec<String> = Vec::new();
    for pair in setup.pairs.values() {
        // Holding the whole area, the ranks own every contact condition (Kratos' octree
        // also pairs master conditions with masters: their paired conditions count too).
        let owned = if whole_area.is_some() {
            &pair.parts
        } else {
            &pair.slaves
        };
        for name in owned {
            if !owned_parts.contains(name) {
                owned_parts.push(name.clone());
            }
        }
        for name in &pair.parts {
            if !contact_parts.contains(name) {
                contact_parts.push(name.clone());
            }
        }
    }
    Ok(DistributedPlan {
        owned_parts,
        contact_parts,
        whole_area,
    })
}

/// One rank of a distributed search of `mesh` with `setup`: every rank passes the same whole
/// mesh and setup and its own `transport`. Each rank builds its part ([`split_rank`]: the
/// recursive coordinate bisection of the slave conditions for the transport's rank count,
/// with the halo its owned values read), searches it sharing the whole problem's values with
/// the others ([`ContactSearch::set_ranks`]), and sends its owned slave conditions' pairs and
/// owned slave nodes' results to rank 0, which merges them: rank 0 returns the result of the
/// one-process search of `mesh` (`Some`), the other ranks `None`. Any rank's error stops
/// every rank with the lowest failed rank's message. A setup whose pairs depend on the whole
/// contact area ([`DistributedPlan::whole_area`]) is searched whole by every rank, each
/// owning a share of the results; a multi-step setup runs its steps as `csm search` does.
///
/// The mesh's nodes must be numbered in ascending id order (the order the global sums are
/// taken in, that of the one-process run).
pub fn search_rank(
    transport: Arc<dyn Transport>,
    mesh: &MeshArrays,
    setup: &SearchSetup,
) -> Result<Option<SearchResult>, RunError> {
    search_rank_timed(transport, mesh, setup).map(|(result, _)| result)
}

/// This rank's wall times of a distributed search, in seconds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RankTimes {
    /// Its part of the mesh and the search's initialisation on it.
    pub initialize: f64,
    /// The search step and the gathering of the results.
    pub search: f64,
}

/// [`search_rank`] with this rank's times.
pub fn search_rank_timed(
    transport: Arc<dyn Transport>,
    mesh: &MeshArrays,
    setup: &SearchSetup,
) -> Result<(Option<SearchResult>, RankTimes), RunError> {
    let mut times = RankTimes::default();
    let start = Instant::now();
    let prepared = with_interfaces(mesh, setup).map_err(|e| stopped(&transport, e))?;
    let (mesh, setup) = match &prepared {
        Some((mesh, setup)) => (mesh, setup),
        None => (mesh, setup),
    };
    times.initialize += start.elapsed().as_secs_f64();
    let (rank, all) = gathered_results(&transport, mesh, setup, &mut times)?;
    if rank != 0 {
        return Ok((None, times));
    }
    let parts: Vec<SearchResult> = all.iter().map(|b| decode_result(b)).collect();
    Ok((Some(merge(parts, mesh, setup)), times))
}

/// The part [`with_interfaces`] adds for the split: the generated slave conditions.
const GENERATED_SLAVES: &str = "CsmGeneratedSlaveConditions";

/// The whole mesh with the interface conditions the search generates from the elements of
/// contact parts without conditions (stage 1, [`csm_search::generate_interfaces_first`]),
/// before it is split: the part of a rank holds no whole body to generate them from, nor the
/// ids the whole model gives them. With the setup that carries stage 1's warnings. `None`
/// where nothing is generated. Every rank computes the same.
pub(crate) fn with_interfaces(
    mesh: &MeshArrays,
    setup: &SearchSetup,
) -> Result<Option<(MeshArrays, SearchSetup)>, Stop> {
    let empty_part = (setup.pairs.values().flat_map(|p| &p.parts)).any(|path| {
        mesh.parts
            .get(path)
            .is_some_and(|p| p.conditions.is_empty())
    });
    // (A setup a distributed run refuses is refused after this, with its reason.)
    if !empty_part || distributed_plan(setup).is_err() {
        return Ok(None);
    }
    let mut model = ModelPart::from_arrays(&setup.model_part_name, mesh)
        .map_err(|e| Stop::Failed(e.to_string()))?;
    let Some(warnings) = csm_search::generate_interfaces_first(&mut model, setup)? else {
        return Ok(None);
    };
    let mut arrays = model.to_arrays();
    // The contact parts are made again by each rank's search, from the user parts.
    arrays
        .parts
        .retain(|path, _| path != "Contact" && !path.starts_with("Contact."));
    // The generated conditions that are slaves (all their nodes in a slave part): a slave part
    // of their own, so that the split takes them as slaves and each rank's search gives them
    // the flags the generation gave (SLAVE; MASTER false where Kratos leaves it undefined,
    // which reads the same).
    // (Told by position: the new conditions come after the mesh's, whose ids kratos mode
    // renumbers 1..N first, so a new id may be an old one.)
    let before: usize = mesh.conditions.values().map(|c| c.ids.len()).sum();
    let (ids, flags) = (model.conditions().ids(), model.conditions().flags());
    let generated_slaves: Vec<u32> = (before..ids.len())
        .filter(|&c| flags[c].is(csm_model::Flag::SLAVE))
        .map(|c| ids[c])
        .collect();
    let mut sorted = generated_slaves;
    sorted.sort_unstable();
    arrays.parts.insert(
        GENERATED_SLAVES.to_owned(),
        csm_model::PartArrays {
            conditions: sorted,
            ..Default::default()
        },
    );
    // A pair whose roles are decided automatically: its generated conditions, which the
    // ranks' searches give stage 1's roles (MASTER: no node is SLAVE then).
    if setup.pairs.values().any(|p| p.slaves.is_empty()) {
        arrays.parts.insert(
            csm_search::GENERATED_CONDITIONS_PART.to_owned(),
            csm_model::PartArrays {
                conditions: (before..ids.len()).map(|c| ids[c]).collect(),
                ..Default::default()
            },
        );
    }
    let mut setup = setup.clone();
    setup.warnings.extend(warnings);
    setup.interfaces_generated = true;
    // (A pair whose roles are decided automatically has no slave part to extend: its
    // generated conditions are in its contact parts, which the ranks own then.)
    for pair in setup.pairs.values_mut().filter(|p| !p.slaves.is_empty()) {
        pair.slaves.push(GENERATED_SLAVES.to_owned());
    }
    Ok(Some((arrays, setup)))
}

/// Every rank's owned result (as bytes, in rank order) on every rank, with this rank, or the
/// error every rank stops with.
pub(crate) fn gathered_results(
    transport: &Arc<dyn Transport>,
    mesh: &MeshArrays,
    setup: &SearchSetup,
    times: &mut RankTimes,
) -> Result<(usize, Vec<Vec<u8>>), RunError> {
    let outcome = rank_search(transport, mesh, setup, times).and_then(|(ranks, _, result)| {
        let start = Instant::now();
        let owned = owned_result(&ranks, &result);
        let all = ranks.gather_bytes(&encode_result(&owned))?;
        times.search += start.elapsed().as_secs_f64();
        Ok((ranks.rank(), all))
    });
    outcome.map_err(|stop| stopped(transport, stop))
}

/// The error every rank leaves with after `stop` on this one.
pub(crate) fn stopped(transport: &Arc<dyn Transport>, stop: Stop) -> RunError {
    let anyone = Ranks::new(Arc::clone(transport), &[], &[]);
    match stop {
        Stop::Failed(message) => RunError(anyone.agree_on_failure(Some(&message))),
        Stop::Aborted => RunError(anyone.agree_on_failure(None)),
    }
}

/// A rank that failed before it could start its part of a distributed search (it could not
/// read its input): stops every rank with the lowest failed rank's message, which it
/// returns, as [`search_rank`] does on the others.
pub fn fail_rank(transport: Arc<dyn Transport>, message: &str) -> RunError {
    RunError(Ranks::new(transport, &[], &[]).agree_on_failure(Some(message)))
}

/// The rank's part, its search with the ranks' shared values, and its result.
fn rank_search(
    transport: &Arc<dyn Transport>,
    mesh: &MeshArrays,
    setup: &SearchSetup,
    times: &mut RankTimes,
) -> Result<(Ranks, RankPart, SearchResult), Stop> {
    let start = Instant::now();
    let plan = distributed_plan(setup).map_err(Stop::Failed)?;
    if let Some(w) = mesh.node_ids.windows(2).find(|w| w[0] >= w[1]) {
        return Err(Stop::Failed(format!(
            "a distributed run needs the nodes in ascending id order (the order of the global \
             sums); node {} follows node {}",
            w[1], w[0]
        )));
    }
    // The normal check computes the unit normal of every condition of the mesh and stops at
    // the first it cannot compute, contact condition or not; a rank holds only the contact
    // conditions near its own.
    if !setup.cpp_search_parameters
        && let Some(message) = first_degenerate_condition(mesh)
    {
        return Err(Stop::Failed(message));
    }
    let slaves: Vec<&str> = plan.owned_parts.iter().map(String::as_str).collect();
    let contact: Vec<&str> = plan.contact_parts.iter().map(String::as_str).collect();
    let factor = (setup.pairs.values())
        .map(|p| p.search.search_factor)
        .fold(0.0, f64::max);
    let reach = Reach::for_search_factor(factor);
    // Kratos' DirectCheck reads the ACTIVE flags its earlier candidates set, in the kd-tree's
    // candidate order: the tree over every master gives each rank the one-process order.
    let kratos = setup.compatibility == csm_search::Compatibility::Kratos;
    let kratos_direct = kratos
        && (setup.pairs.values()).any(|p| p.search.check_gap == csm_search::CheckGap::DirectCheck);
    // The octree is refined around every master node and holds every master condition: with
    // all of them (and the ranks' common root box) each rank builds the one-process octree.
    let octree =
        (setup.pairs.values()).any(|p| p.search.type_search == SearchTreeType::OctreeWithObb);
    // (A run searched whole takes from its split only the ownership, which the reach does
    // not change.)
    let reach = if kratos_direct || octree {
        reach.with_every_master()
    } else {
        reach
    };
    // With fewer slave conditions than ranks, the ranks past them search a copy of another
    // rank's part and own nothing: every rank takes part in every exchange.
    let (ranks, rank) = (transport.ranks(), transport.rank());
    let owners = slave_condition_count(mesh, &slaves);
    // A run searched whole: the mesh's condition ids (the others are made by the search).
    let listed = plan.whole_area.map(|_| condition_ids(mesh));
    let mut part = if listed.is_some() && owners == 0 {
        // No condition of the mesh is a contact one before the search (skin detection):
        // rank 0 owns every condition and node.
        let first = rank == 0;
        RankPart {
            mesh: MeshArrays::default(),
            owned_conditions: match (&listed, first) {
                (Some(ids), true) => ids.clone(),
                _ => Vec::new(),
            },
            owned_nodes: if first {
                mesh.node_ids.clone()
            } else {
                Vec::new()
            },
        }
    } else {
        let with_slaves = owners.clamp(1, ranks);
        split_rank(
            mesh,
            (&slaves, &contact),
            (with_slaves, rank % with_slaves),
            reach,
        )
        .map(|mut part| {
            if rank >= with_slaves {
                part.owned_conditions.clear();
                part.owned_nodes.clear();
            }
            part
        })
        .map_err(|e| match e {
            crate::SplitError::NoSlaves => Stop::Failed(
                "a distributed run does not support slave parts without conditions yet \
                 (Kratos generates their interface conditions from the elements: give the \
                 contact conditions in the mesh)"
                    .to_owned(),
            ),
            e => Stop::Failed(e.to_string()),
        })?
    };
    let mut ranks = Ranks::new(
        Arc::clone(transport),
        &part.owned_nodes,
        &part.owned_conditions,
    );
    if let Some(listed) = &listed {
        // Every rank searches the whole mesh: the same model, the same ids for the
        // conditions the search makes (a later pair searches the paired conditions an
        // earlier one made), which are rank 0's.
        part.mesh = mesh.clone();
        ranks = ranks.with_made_conditions_on_first(listed);
    }
    // The part's arrays are not needed once its model is built (the owned ids are kept).
    let arrays = std::mem::take(&mut part.mesh);
    let mut model = ModelPart::from_arrays(&setup.model_part_name, &arrays)
        .map_err(|e| Stop::Failed(e.to_string()))?;
    drop(arrays);
    let mut search = ContactSearch::initialize(&mut model, setup)?;
    search.set_ranks(Some(ranks.clone()));
    times.initialize += start.elapsed().as_secs_f64();
    // Where a stage profile is kept (`csm search --profile`), the search phase begins here.
    tracing::debug!(target: "csm::stages", phase = "search");
    let start = Instant::now();
    // The paired conditions of the owned slaves (a result counts every one).
    let owned_paired = |search: &ContactSearch, model: &ModelPart| {
        let ids = model.conditions().ids();
        (setup.pairs.keys())
            .flat_map(|&key| search.paired_conditions(key))
            .filter(|pc| ranks.owns_condition(ids[pc.slave.index()]))
            .count()
    };
    let result = if setup.steps.is_empty() {
        let mut result = search.step(&mut model)?;
        result.paired_conditions = owned_paired(&search, &model);
        result
    } else {
        // The steps as `csm search` runs them (whole mesh on every rank).
        search.run_steps(&mut model, &setup.steps, |search, model, result| {
            result.paired_conditions = owned_paired(search, model);
        })?
    };
    times.search = start.elapsed().as_secs_f64();
    Ok((ranks, part, result))
}

/// The error of the normal check's unit normals of every condition of `mesh`
/// (`compute_unit_normals` over the whole model: the first face it cannot compute, whose
/// message the one-process run gives), the conditions taken kind by kind and, in each, in the
/// mesh's order (the one-process order where the mesh has one condition kind, else the first
/// failing kind's first). `None` where every face has its normal.
fn first_degenerate_condition(mesh: &MeshArrays) -> Option<String> {
    let point = |id: u32| -> Option<csm_geometry::math::Point> {
        let at = mesh.node_ids.binary_search(&id).ok()?;
        let [x, y, z] = mesh.points[at];
        Some(csm_geometry::math::Point::new(x, y, z))
    };
    let mut points = Vec::new();
    let mut normals = Vec::new();
    for (&kind, conditions) in mesh.conditions.iter().filter(|(k, _)| k.is_face()) {
        let n = kind.n_nodes().max(1);
        for (&id, nodes) in conditions.ids.iter().zip(conditions.connectivity.chunks(n)) {
            points.clear();
            // (A missing node is the split's error, with its own message.)
            let Some(found) = nodes
                .iter()
                .map(|&node| point(node))
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            points.extend(found);
            normals.clear();
            let normal = csm_geometry::Geometry::new(kind, &points)
                .and_then(|g| g.face_unit_normals_into(&mut normals));
            if let Err(e) = normal {
                let error = csm_search::ErrorKind::Geometry {
                    condition: id,
                    message: e.to_string(),
                };
                return Some(csm_search::Error::from(error).to_string());
            }
        }
    }
    None
}

/// The number of conditions of the parts `slaves` (each once).
fn slave_condition_count(mesh: &MeshArrays, slaves: &[&str]) -> usize {
    let ids: BTreeSet<u32> = (slaves.iter())
        .filter_map(|name| mesh.parts.get(*name))
        .flat_map(|p| p.conditions.iter().copied())
        .collect();
    ids.len()
}

/// The rank's result for what it owns: its owned slave conditions' pairs (and pruned
/// entries), its owned slave nodes' results, its warnings.
fn owned_result(ranks: &Ranks, result: &SearchResult) -> SearchResult {
    let keep = |maps: &BTreeMap<String, IdMap<Vec<u32>>>| {
        maps.iter()
            .map(|(key, map)| {
                let owned = map
                    .iter()
                    .filter(|(id, _)| ranks.owns_condition(**id))
                    .map(|(id, masters)| (*id, masters.clone()))
                    .collect();
                (key.clone(), owned)
            })
            .collect()
    };
    SearchResult {
        pairs: keep(&result.pairs),
        pruned: keep(&result.pruned),
        nodes: (result.nodes.iter())
            .filter(|(id, _)| ranks.owns_node(**id))
            .map(|(id, r)| (*id, *r))
            .collect(),
        warnings: result.warnings.clone(),
        paired_conditions: result.paired_conditions,
        master_slave_constraints: result.master_slave_constraints,
        steps: (result.steps.iter())
            .map(|s| StepResult {
                step: s.step,
                result: owned_result(ranks, &s.result),
                search_s: s.search_s,
            })
            .collect(),
        ..SearchResult::default()
    }
}

/// The condition ids of `mesh`, ascending.
fn condition_ids(mesh: &MeshArrays) -> Vec<u32> {
    let mut ids: Vec<u32> = (mesh.conditions.values())
        .flat_map(|a| a.ids.iter().copied())
        .collect();
    ids.sort_unstable();
    ids
}

/// The ranks' owned results as one: pairs and nodes together, the warnings of every rank in
/// rank order, each once; the counters of the whole: the ranks' paired conditions of their
/// owned slaves, Kratos' condition ids from the whole mesh.
pub(crate) fn merge(
    mut parts: Vec<SearchResult>,
    mesh: &MeshArrays,
    setup: &SearchSetup,
) -> SearchResult {
    let mut out = SearchResult::default();
    let constraints = parts.iter().any(|p| p.master_slave_constraints.is_some());
    // Step by step, as the whole: the ranks ran the same steps.
    let mut by_rank: Vec<Vec<StepResult>> = Vec::with_capacity(parts.len());
    for part in &mut parts {
        by_rank.push(std::mem::take(&mut part.steps));
    }
    let n_steps = by_rank.iter().map(Vec::len).min().unwrap_or(0);
    out.steps = (0..n_steps)
        .map(|k| StepResult {
            step: by_rank[0][k].step,
            result: merge(
                by_rank.iter().map(|s| s[k].result.clone()).collect(),
                mesh,
                setup,
            ),
            // The slowest rank's.
            search_s: by_rank.iter().map(|s| s[k].search_s).fold(0.0, f64::max),
        })
        .collect();
    for part in parts {
        for (key, map) in part.pairs {
            out.pairs.entry(key).or_default().extend(map);
        }
        for (key, map) in part.pruned {
            out.pruned.entry(key).or_default().extend(map);
        }
        out.nodes.extend(part.nodes);
        out.paired_conditions += part.paired_conditions;
        for w in part.warnings {
            if !out.warnings.contains(&w) {
                out.warnings.push(w);
            }
        }
    }
    out.master_slave_constraints = constraints.then_some(out.paired_conditions);
    if setup.process.renumbers_conditions() {
        out.kratos_condition_ids = kratos_condition_ids(mesh, setup);
    }
    out
}

/// Kratos' numbering of the conditions 1..N in id order, for the contact conditions whose id
/// it changes (the conditions of the pairs' parts), from the whole mesh.
fn kratos_condition_ids(mesh: &MeshArrays, setup: &SearchSetup) -> BTreeMap<u32, u32> {
    let all: Vec<u32> = (mesh.conditions.values())
        .flat_map(|a| a.ids.iter().copied())
        .collect();
    let contact: BTreeSet<u32> = (setup.pairs.values())
        .flat_map(|p| &p.parts)
        .filter_map(|name| mesh.parts.get(name))
        .flat_map(|p| p.conditions.iter().copied())
        .collect();
    let contact: Vec<u32> = contact.into_iter().collect();
    csm_search::kratos_renumbering(all, &contact)
}
