//! The driver: `ExecuteInitialize`, `ExecuteInitializeSolutionStep` and
//! `ExecuteFinalizeSolutionStep` of Kratos' ALMContactProcess and its search processes.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicBool, Ordering};

use csm_geometry::Aabb;
use csm_geometry::math::{EPS, Point, Real, Vector};
use csm_geometry::{Geometry, Kdop18};
use csm_model::{
    ConditionId, ConditionIdx, Flag, KeptFaceNormals, ModelPart, NodalHMode, NodeIdx, NormalsMode,
    PartIdx, ScalarVar, UnitNormalsSnapshot, VectorVar, assign_nodal_h, compute_unit_normals,
    compute_unit_normals_from_kept, write_at_ascending,
};
use csm_trees::KdTree;
use rayon::prelude::*;

use super::IdMap;
use super::candidates::{Bv, Candidate, PerMaster, QueryContext, QueryScratch, slave_candidates};
use super::globals::PairGlobals;
use super::motion::{apply_nodal_values, check_step_parts, step_positions};
use super::octree::{OctreeContext, search_octree_report};
pub use super::pairing::PairedCondition;
use super::pairing::{
    PairingContext, active_snapshot, apply_candidates, mapping_check_keeps, update_index_maps,
    update_listed_maps,
};
use super::result::{NodeResult, SearchResult};
use super::self_contact::{compute_self_contact_pairing, not_predefined_master_slave};
use super::shared_conditions::check_contact_model_parts;
use super::step_jump::compute_step_jump;
use super::tuning::{QueryOrder, SearchTuning};
use crate::error::{Error, ErrorKind};
use crate::plan::{
    Decision, NodalVariable, NormalCheck, PairPlan, Plan, Storage, VariablePlan, contact_sub_path,
    missing_contact_sub, step_jump,
};
use crate::setup::{
    CheckGap, Compatibility, ContactProcess, SearchParameters, SearchSetup, SearchTreeType,
    StepSetup,
};
use crate::stages::{
    ContactParts, InterfaceSettings, NormalCheckSettings, SKIN_PART, SearchInstance,
    assign_contact_flags, detect_skin, dispatch, generate_interface_conditions,
    master_slave_from_nodes, normal_check_normals_only_with_normals, normal_check_with_normals,
    transfer_to_contact,
};

mod check_pairing;
mod initialize;
pub use initialize::{GENERATED_CONDITIONS_PART, generate_interfaces_first, kratos_renumbering};
mod kdtree_path;
mod mortar_conditions;
mod outcome;
mod query_order;

use check_pairing::{PairingStep, check_pairing};
use kdtree_path::{KdPass, kdtree_search, self_contact_roles};
use mortar_conditions::{
    InitialNormals, clear_mortar_conditions, finish_pairs, update_mortar_conditions,
};
#[cfg(test)]
pub(crate) use outcome::by_slave;
#[cfg(test)]
pub(crate) use query_order::morton_order;
use query_order::morton_order_of_parts;
pub(crate) use query_order::{Far, reach};

/// The search of one pair key (one Kratos search process).
#[derive(Debug, Clone)]
struct PairSearch {
    key: u32,
    params: SearchParameters,
    instance: SearchInstance,
    /// `Contact.ContactSub<key>`.
    sub: PartIdx,
    /// The paired conditions (Kratos' `ComputingContactSub<key>`).
    paired: Vec<PairedCondition>,
    /// The INDEX_MAP entries (slave id, master id) the MappingCheck mortar pruning removed in
    /// the last step.
    pruned: Vec<(u32, u32)>,
    /// The kd-tree of the last step, kept for a multi-step run ([`RunMode::keep_tree`]): the
    /// next step refits it when the master-side conditions are the same.
    tree: Option<KeptTree>,
    /// Roles not predefined: Kratos' point list (`mPointListDestination`), the conditions
    /// (indices) the kd-tree is built over. Filled with the MASTER conditions when empty, then replaced
    /// by the self-contact pre-search of every step (reference §12.1).
    points: Vec<u32>,
    /// The whole problem's values given by [`ContactSearch::set_globals`] (none: this model's).
    globals: PairGlobals,
    /// The values the last step used ([`ContactSearch::globals`]).
    used: PairGlobals,
    /// A distributed run: this rank's part in it ([`ContactSearch::set_ranks`]).
    ranks: Option<csm_model::Ranks>,
    /// The slaves' masters of this step, as the result lists them (`SearchResult.pairs`),
    /// built by MappingCheck's pairing once the mapping has pruned the INDEX_MAPs (nothing
    /// after it changes their keys); taken by the step's result, cleared at every step.
    step_pairs: Option<IdMap<Vec<u32>>>,
}

/// A kd-tree kept from one step to the next, with the condition ids it was built over (in
/// container order).
#[derive(Debug, Clone)]
struct KeptTree {
    ids: Vec<u32>,
    tree: KdTree<u32>,
}

/// A contact search over a model: created by [`ContactSearch::initialize`], run step by step.
/// A clone, together with a clone of the model it was initialized on, runs independently (the
/// error-vs-run-time report initializes once and runs many strategies from there).
#[derive(Debug, Clone)]
pub struct ContactSearch {
    setup: SearchSetup,
    /// What runs, decided at the start of `initialize` (the step jump again every step).
    plan: Plan,
    parts: ContactParts,
    pairs: Vec<PairSearch>,
    database_step: u32,
    /// Calls of [`ContactSearch::step`] so far (a multi-step run advances the time step from
    /// the second step on).
    steps_run: u32,
    warnings: Vec<String>,
    /// The faces' unit normals of the normal check, until the first step's pairs compute
    /// theirs from them (where the geometry has not changed since:
    /// [`csm_model::compute_unit_normals_from_kept`]); dropped then.
    initial_normals: Option<KeptFaceNormals>,
    /// The ids Kratos' contact process gives the contact conditions whose file id differs
    /// (file id → Kratos id): `ALMFastInit` renumbers every condition of the model 1..N in id
    /// order during `ExecuteInitialize` (reference §1.3 step 11), and Kratos' INDEX_MAPs hold
    /// the new ids. RESULT.json keeps the file ids and writes this map beside them.
    kratos_ids: BTreeMap<u32, u32>,
    /// How the work is organised ([`SearchTuning::default`] unless set).
    tuning: SearchTuning,
}

fn model_error(e: csm_model::Error) -> Error {
    Error::model_data("", e)
}

impl ContactSearch {
    /// Makes later steps use the whole problem's values `globals` (by pair key; a pair not
    /// listed, or a value `None`, takes its own model's): for a search of one rank's part of a
    /// larger mesh ([`PairGlobals`], `csm-distributed`).
    pub fn set_globals(&mut self, globals: &BTreeMap<u32, PairGlobals>) {
        for pair in &mut self.pairs {
            pair.globals = globals.get(&pair.key).copied().unwrap_or_default();
        }
    }

    /// Makes later steps one rank's part of a distributed run (`csm-distributed`): the model
    /// is the rank's part of the mesh, and the whole problem's values (the largest and the
    /// mean NODAL_H, the mapper's reference area, counts and convergence sums, its ghost slave
    /// nodes' values) are shared with the other ranks through `ranks`, so that the pairs of
    /// the slave conditions it owns and the results of the slave nodes it owns are those of
    /// the one-process run. Values given by [`set_globals`](Self::set_globals) take
    /// precedence.
    pub fn set_ranks(&mut self, ranks: Option<csm_model::Ranks>) {
        for pair in &mut self.pairs {
            pair.ranks.clone_from(&ranks);
        }
    }

    /// The values of the whole problem the last step took from the model, by pair key (or
    /// those [`set_globals`](Self::set_globals) gave): what a search of one part of a larger
    /// mesh must be given ([`PairGlobals`]).
    pub fn globals(&self) -> BTreeMap<u32, PairGlobals> {
        self.pairs.iter().map(|p| (p.key, p.used)).collect()
    }

    /// Sets how the search organises its work (the order of the slave queries, the mapping's
    /// streaming): never a result. Production leaves [`SearchTuning::default`].
    pub fn set_tuning(&mut self, tuning: SearchTuning) {
        self.tuning = tuning;
    }

    /// How the search organises its work.
    pub fn tuning(&self) -> SearchTuning {
        self.tuning
    }

    /// The setup in force (after `adapt_search`).
    pub fn setup(&self) -> &SearchSetup {
        &self.setup
    }

    /// The plan the search follows: made at the start of [`ContactSearch::initialize`] from
    /// the model as read ([`Plan::new`]), with the step jump of every pair as the last step
    /// decided it.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The paired conditions of pair `key` after the last step.
    pub fn paired_conditions(&self, key: u32) -> &[PairedCondition] {
        self.pairs
            .iter()
            .find(|p| p.key == key)
            .map_or(&[], |p| &p.paired)
    }

    /// Replaces the search strategy of pair `key` for the next steps: `type_search`,
    /// `search_factor` and the `octree_search_parameters` (`bounding_box_factor`, the OBB
    /// test) of `params` are taken, and the pair's plan is decided again for them, so that
    /// the next [`ContactSearch::step`] runs as if [`ContactSearch::initialize`] had been
    /// given them (checked by a test). The value in force is used as given (`adapt_search`
    /// scaled the initial one already).
    ///
    /// Errors ([`ErrorKind::InvalidValue`]): an unknown `key`; `params` that differ from the
    /// pair's in anything `initialize` depends on (`check_gap`, `simple_search`,
    /// `inverted_search`, `predefined_master_slave`, `dynamic_search`, the activation keys); a
    /// non-finite or negative `search_factor` or `bounding_box_factor`; and, in `kratos` mode,
    /// the octree with `inverted_search` (Kratos rejects it).
    pub fn set_search_parameters(
        &mut self,
        model: &ModelPart,
        key: u32,
        params: &SearchParameters,
    ) -> Result<(), Error> {
        let invalid = |what: &str, found: String| -> Error {
            ErrorKind::InvalidValue {
                key: format!("search_parameters.{what}"),
                expected: "a value the initialized search supports".to_owned(),
                found,
            }
            .into()
        };
        let Some(i) = self.pairs.iter().position(|p| p.key == key) else {
            return Err(invalid("<pair key>", key.to_string()));
        };
        let old = &self.pairs[i].params;
        let strategy_only = SearchParameters {
            type_search: old.type_search,
            search_factor: old.search_factor,
            octree: old.octree,
            ..params.clone()
        };
        if strategy_only != *old {
            return Err(invalid(
                "*",
                "a change beyond type_search, search_factor and octree_search_parameters"
                    .to_owned(),
            ));
        }
        for (what, v) in [
            ("search_factor", params.search_factor),
            (
                "octree_search_parameters.bounding_box_factor",
                params.octree.bounding_box_factor,
            ),
        ] {
            if !v.is_finite() || v < 0.0 {
                return Err(invalid(what, v.to_string()));
            }
        }
        if params.type_search == SearchTreeType::OctreeWithObb
            && params.inverted_search
            && self.setup.compatibility == Compatibility::Kratos
        {
            return Err(invalid(
                "type_search",
                "octree_with_obb with inverted_search (Kratos rejects it)".to_owned(),
            ));
        }
        let Some(pair_setup) = self.setup.pairs.get_mut(&key) else {
            return Err(invalid("<pair key>", key.to_string()));
        };
        pair_setup.search = params.clone();
        self.pairs[i].params = params.clone();
        let nodes = model.part(self.pairs[i].sub).nodes().to_vec();
        let plan = crate::plan::pair_plan(model, key, pair_setup, &nodes);
        self.plan.pairs.insert(key, plan);
        Ok(())
    }

    /// The ground truth's step (`csm_eval::GroundTruth`, the evaluation layer): [`ContactSearch::step`] for pair
    /// `key` alone, with the broad and narrow phases replaced by `find`, which is given the
    /// model after the unit normals of ContactSub are computed (the normals the orientation
    /// filter reads) and returns the (slave, master) pairs to put in the INDEX_MAPs; then
    /// MappingCheck's CheckPairing runs as usual (mortar mapping, paired conditions, weighted
    /// gap, activation). Requires a MappingCheck pair and no dynamic search.
    pub fn step_with_pairs<F>(
        &mut self,
        model: &mut ModelPart,
        key: u32,
        find: F,
    ) -> Result<SearchResult, Error>
    where
        F: FnOnce(&mut ModelPart, &TruthScene) -> Result<Vec<(ConditionIdx, ConditionIdx)>, Error>,
    {
        let Some(i) = self.pairs.iter().position(|p| p.key == key) else {
            return Err(ErrorKind::InvalidValue {
                key: "<pair key>".to_owned(),
                expected: "a pair key of the setup".to_owned(),
                found: key.to_string(),
            }
            .into());
        };
        self.steps_run += 1;
        self.reset_marker(model);
        for pair in &mut self.pairs {
            pair.step_pairs = None;
        }
        let run = RunMode::of(&self.setup, self.tuning);
        let pair = &mut self.pairs[i];
        let Some(pair_plan) = self.plan.pairs.get(&key) else {
            return Err(ErrorKind::Model(format!("pair {key}: no plan")).into());
        };
        clear_mortar_conditions(model, pair, run.compatibility)?;
        pair.pruned.clear();
        let p = pair.params.clone();
        let normals_mode = match run.compatibility {
            Compatibility::Kratos => NormalsMode::Kratos,
            Compatibility::Robust => NormalsMode::Once,
        };
        let face_normals = compute_unit_normals(model, Some(pair.sub), normals_mode)
            .map_err(model_error)?
            .keep();
        let max_paired = pair.paired.iter().map(|pc| pc.id.get()).max().unwrap_or(0);
        let condition_id = model.conditions().max_id().max(max_paired);
        let distance_threshold = if p.simple_search {
            model
                .process_info()
                .number("DISTANCE_THRESHOLD")
                .unwrap_or(1e24)
        } else {
            csm_activation::mean_h(model, pair.sub, p.inverted_search)
        };
        let scene = TruthScene {
            sub: pair.sub,
            inverted: p.inverted_search,
            master_check: !p.inverted_search || !p.predefined_master_slave,
            dim: usize::from(pair.instance.dim),
            distance_threshold,
            normal_orientation_threshold: p.normal_orientation_threshold,
        };
        let mut found = find(model, &scene)?;
        let ids = model.conditions().ids();
        found.sort_by_key(|(s, m)| (ids[s.index()], ids[m.index()]));
        for (s, m) in found {
            let master_id = ConditionId(model.conditions().ids()[m.index()]);
            model.index_map_mut(s).add_id(master_id);
        }
        let step = PairingStep {
            params: &p,
            plan: pair_plan,
            restore: None,
            face_normals: Some(face_normals),
            condition_id,
        };
        check_pairing(model, pair, step, run)?;
        self.reset_marker(model);
        Ok(self.result_of_step(model))
    }

    /// The search instance (Kratos template class) chosen for pair `key`.
    pub fn instance(&self, key: u32) -> Option<SearchInstance> {
        self.pairs.iter().find(|p| p.key == key).map(|p| p.instance)
    }

    /// Kratos' `ExecuteInitializeSolutionStep` (§1.4): searches when inside the interval and
    /// `database_step_update` says so (always at STEP 1); otherwise sets ACTIVE false on every
    /// `Contact` node and condition (Q36). Returns the result of the step.
    pub fn step(&mut self, model: &mut ModelPart) -> Result<SearchResult, Error> {
        let time = model.process_info().number("TIME").unwrap_or(1.0);
        let step = model.process_info().number("STEP").unwrap_or(1.0);
        let (start, end) = self.setup.interval;
        let in_interval = time >= start && time <= end;
        let mut searched = false;
        if in_interval {
            self.database_step += 1;
            if self.database_step >= self.setup.database_step_update || step == 1.0 {
                searched = true;
            }
        }
        let contact = self.parts.contact;
        self.steps_run += 1;
        for pair in &mut self.pairs {
            pair.pruned.clear();
            pair.step_pairs = None;
        }
        if searched {
            self.reset_marker(model);
            let n_pairs = self.pairs.len();
            for i in 0..n_pairs {
                let run = RunMode::of(&self.setup, self.tuning);
                let pair = &mut self.pairs[i];
                // Every key of the setup has its pair plan (both come from `setup.pairs`).
                let Some(pair_plan) = self.plan.pairs.get_mut(&pair.key) else {
                    continue;
                };
                clear_mortar_conditions(model, pair, run.compatibility)?;
                // The normal check's face normals serve every pair of the first step; the
                // last one drops them (before its search).
                let initial = InitialNormals {
                    table: &mut self.initial_normals,
                    last_user: i + 1 == n_pairs,
                };
                let step_warnings = update_mortar_conditions(model, pair, pair_plan, run, initial)?;
                for w in step_warnings {
                    let w = format!("pair {}: {w}", pair.key);
                    if !self.warnings.contains(&w) {
                        self.warnings.push(w);
                    }
                }
            }
            self.reset_marker(model);
        } else {
            // (The stage trace starts here: no pair stage ran.)
            crate::trace::start();
            set_node_flag_on(model, contact, Flag::ACTIVE, false);
            initialize::set_flag_on(model, contact, Flag::ACTIVE, false);
        }
        let result = self.result_of_step(model);
        crate::trace::mark("result");
        Ok(result)
    }

    /// Kratos' `ExecuteFinalizeSolutionStep`: clears the pairs of the pairs searched this
    /// step (ClearMortarConditions: paired conditions that are not ACTIVE go, with their
    /// INDEX_MAP entries; in a search-only run every paired condition stays ACTIVE, so the
    /// pairs are kept for the next search) and resets the database counter.
    ///
    /// Errors in `kratos` mode when an INDEX_MAP entry has no paired condition (C++ parameters
    /// without `condition_name`): Kratos' ResetContactOperators then fails on condition 0
    /// ("Condition index not found: 0.", Q18, observed with Kratos 10.4.4). `robust` mode drops
    /// those entries instead (the next search finds them again).
    pub fn finalize_step(&mut self, model: &mut ModelPart) -> Result<(), Error> {
        let step = model.process_info().number("STEP").unwrap_or(1.0);
        if self.database_step >= self.setup.database_step_update || step == 1.0 {
            for pair in &mut self.pairs {
                clear_mortar_conditions(model, pair, self.setup.compatibility)?;
            }
            self.database_step = 0;
        }
        Ok(())
    }

    /// Prepares the next step of a multi-step run (SETUP.json `steps`, DESIGN.md §3), before
    /// [`ContactSearch::step`]: from the second step on the time step advances
    /// ([`ModelPart::advance_time_step`]: STEP + 1, TIME + dt, the historical buffer shifts);
    /// then `DELTA_TIME := dt` and every node of the parts the step names is moved by its
    /// rigid increment ([`ModelPart::prescribe_motion`]: DISPLACEMENT accumulates, VELOCITY =
    /// increment / dt, ACCELERATION = ΔVELOCITY / dt; every other node gets a zero increment).
    ///
    /// A run is: [`ContactSearch::initialize`] once, then per step `advance`,
    /// [`ContactSearch::step`], [`ContactSearch::finalize_step`]. A model moved by other means
    /// follows the same order with its own `advance_time_step` / `prescribe_motion` calls.
    pub fn advance(&mut self, model: &mut ModelPart, step: &StepSetup) -> Result<(), Error> {
        if self.steps_run > 0 {
            model.advance_time_step(step.delta_time);
        } else {
            model
                .process_info_mut()
                .set_number("DELTA_TIME", step.delta_time);
        }
        let positions = step_positions(model, step)?;
        model.prescribe_motion(&positions, step.delta_time);
        Ok(())
    }

    /// A multi-step run of `steps` (SETUP.json `steps`) after [`ContactSearch::initialize`]:
    /// per step [`ContactSearch::finalize_step`] of the one before (from the second on),
    /// [`ContactSearch::advance`] and [`ContactSearch::step`], whose result `after` may adjust
    /// (a distributed rank counts its own paired conditions). Returns the last step's result
    /// with every step's in [`SearchResult::steps`], each with its search's wall time
    /// (`csm search` runs the same order, with progress and logging between).
    pub fn run_steps(
        &mut self,
        model: &mut ModelPart,
        steps: &[StepSetup],
        mut after: impl FnMut(&ContactSearch, &ModelPart, &mut SearchResult),
    ) -> Result<SearchResult, Error> {
        let mut done = Vec::with_capacity(steps.len());
        for (k, step_setup) in steps.iter().enumerate() {
            if k > 0 {
                self.finalize_step(model)?;
            }
            self.advance(model, step_setup)?;
            let start = std::time::Instant::now();
            let mut result = self.step(model)?;
            let search_s = start.elapsed().as_secs_f64();
            after(self, model, &mut result);
            done.push(crate::StepResult {
                step: k as u32 + 1,
                result,
                search_s,
            });
        }
        let mut last = done.last().map(|s| s.result.clone()).unwrap_or_default();
        last.steps = done;
        Ok(last)
    }

    fn reset_marker(&self, model: &mut ModelPart) {
        set_node_flag_on(model, self.parts.contact, Flag::MARKER, false);
    }
}

/// Sets `flag` to `value` on every node of `part` (in parallel: the part lists its nodes in
/// ascending index).
fn set_node_flag_on(model: &mut ModelPart, part: PartIdx, flag: Flag, value: bool) {
    let (part, nodes) = model.part_and_nodes_mut(part);
    let (nodes, flags) = (part.nodes(), nodes.flags_mut());
    let at = |k: usize| nodes[k].index();
    write_at_ascending(flags, nodes.len(), at, |_, f| f.set(flag, value));
}

/// Points an error about a setup value (e.g. an unknown part name) at the setup file's line.
pub(crate) fn locate(e: Error, setup: &SearchSetup) -> Error {
    let (Some(source), None) = (&setup.source, e.file()) else {
        return e;
    };
    let line = match e.kind() {
        // `steps[i]…` / `nodal_values[i]…`: the entry's own line.
        ErrorKind::InvalidValue { key, .. } if key.contains('[') => source.line_of_indexed_key(key),
        ErrorKind::InvalidValue { key, found, .. } => source
            .line_of(found)
            .or_else(|| source.line_of(&format!("\"{}\"", key.rsplit('.').next().unwrap_or(key)))),
        ErrorKind::UnknownKey { key } => source.line_of(key),
        _ => return e,
    };
    let file = source.file.clone();
    e.at(&file, line)
}

/// What the ground truth's pair finder is told about the pair it searches
/// ([`ContactSearch::step_with_pairs`]).
#[derive(Debug, Clone, Copy)]
pub struct TruthScene {
    /// `Contact.ContactSub<key>`.
    pub sub: PartIdx,
    /// `inverted_search`: the slave side is the conditions with `SLAVE == false`.
    pub inverted: bool,
    /// The master side is the conditions whose MASTER flag equals this (as the kd-tree's point
    /// list).
    pub master_check: bool,
    /// 2 or 3.
    pub dim: usize,
    /// The DISTANCE_THRESHOLD the mapping will use (Simple: the process info's, 1e24 by
    /// default; Advanced: the larger mean NODAL_H of the two sides).
    pub distance_threshold: Real,
    /// `normal_orientation_threshold`.
    pub normal_orientation_threshold: Real,
}

/// How a step runs, beside the pair's own parameters.
#[derive(Debug, Clone, Copy)]
struct RunMode {
    /// `kratos` or `robust`.
    compatibility: Compatibility,
    /// Frictional contact (a SLIP root model part): the activation applies the SLIP rule.
    frictional: bool,
    /// The setup came through Kratos' Python layer (not `cpp_search_parameters`).
    python_path: bool,
    /// The setup has more than one step and `refit_tree`: the kd-tree is kept and refitted.
    keep_tree: bool,
    /// The work-organisation knobs.
    tuning: SearchTuning,
}

impl RunMode {
    fn of(setup: &SearchSetup, tuning: SearchTuning) -> RunMode {
        RunMode {
            compatibility: setup.compatibility,
            frictional: setup.contact_type.is_frictional(),
            python_path: !setup.cpp_search_parameters,
            keep_tree: setup.refit_tree && setup.steps.len() > 1,
            tuning,
        }
    }
}

/// Moves every node of `part` by `sign · delta` (by node index).
fn shift_nodes(model: &mut ModelPart, part: PartIdx, delta: &[Vector], sign: Real) {
    let (part, nodes) = model.part_and_nodes_mut(part);
    let coords = nodes.coordinates_mut();
    for n in part.nodes() {
        coords[n.index()] += delta[n.index()] * sign;
    }
}
