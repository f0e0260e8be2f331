//! The driver: `ExecuteInitialize`, `ExecuteInitializeSolutionStep` and
//! `ExecuteFinalizeSolutionStep` of Kratos' ALMContactProcess and its search processes.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicBool, Ordering};

use csm_geometry::math::{EPS, Point, Real, Vector};
use csm_geometry::{Geometry, Kdop18};
use csm_model::{
    ConditionId, ConditionIdx, Flag, KeptFaceNormals, ModelPart, NodalHMode, NodeIdx, NormalsMode,
    PartIdx, ScalarVar, UnitNormalsSnapshot, VectorVar, assign_nodal_h, compute_unit_normals,
    compute_unit_normals_from_kept,
};
use csm_trees::{Aabb, KdTree};
use rayon::prelude::*;

use super::candidates::{Bv, Candidate, PerMaster, QueryContext, QueryScratch, slave_candidates};
use super::motion::{apply_nodal_values, check_step_parts, step_positions};
use super::octree::{OctreeContext, search_octree_report};
pub use super::pairing::PairedCondition;
use super::pairing::{PairingContext, active_snapshot, apply_candidates};
use super::result::{NodeResult, SearchResult};
use super::self_contact::{compute_self_contact_pairing, not_predefined_master_slave};
use super::shared_conditions::check_contact_model_parts;
use super::step_jump::compute_step_jump;
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
}

fn model_error(e: csm_model::Error) -> Error {
    ErrorKind::Model(e.to_string()).into()
}

/// Conditions of `part` in Kratos' container order (ascending external id).
fn conditions_by_id(model: &ModelPart, part: PartIdx) -> Vec<ConditionIdx> {
    let mut v = model.part(part).conditions().to_vec();
    let ids = model.conditions().ids();
    // Ids are unique: one order, whatever the sort.
    v.par_sort_unstable_by_key(|c| ids[c.index()]);
    v
}

impl ContactSearch {
    /// Kratos' `ExecuteInitialize` (reference §1.3 and §4) on a model without a `Contact`
    /// part: contact parts and flags (stage 0), NODAL_H, the emulated Python state (process
    /// info, nodal variables), `adapt_search`, the instance of every pair (stage 4), the
    /// search processes' construction and the point lists.
    pub fn initialize(model: &mut ModelPart, setup: &SearchSetup) -> Result<ContactSearch, Error> {
        ContactSearch::initialize_inner(model, setup).map_err(|e| locate(e, setup))
    }

    fn initialize_inner(
        model: &mut ModelPart,
        setup: &SearchSetup,
    ) -> Result<ContactSearch, Error> {
        // No contact part named: the skin of the mesh (robust mode; Kratos 10.4.4 loses it).
        let with_skin;
        let setup = if setup.skin && model.find_part("Contact").is_none() {
            if setup.compatibility == Compatibility::Kratos {
                return Err(ErrorKind::RejectedByKratos(
                    "every `contact_model_part` list is empty, so Kratos detects the skin, but \
                     into `Structure.ContactSub0` instead of `Contact.ContactSub0`: its search \
                     finds no contact condition (\"mPointListDestination not initialized\"). \
                     Name the contact parts, or use \"compatibility\": \"robust\", which \
                     searches the skin"
                        .to_owned(),
                )
                .into());
            }
            let report = detect_skin(model)?;
            let mut s = setup.clone();
            if let Some(pair) = s.pairs.get_mut(&0) {
                pair.parts = vec![model.part(report.part).path().to_owned()];
            }
            with_skin = s;
            &with_skin
        } else {
            setup
        };
        // What runs; every decision below that the plan makes is taken from it.
        let plan = Plan::decide(model, setup)?;
        crate::trace::start();
        let python_path = !setup.cpp_search_parameters;
        let mut setup = setup.clone();
        let mut warnings = setup.warnings.clone();
        // A `Contact` part in the mesh is reused (Kratos' path without preprocessing): no
        // stage 0 or 1, and the condition flags come from the nodal ones (stage 3,
        // MasterSlaveProcess, after the normal check).
        let existing = model.find_part("Contact");
        let parts = match existing {
            Some(contact) => existing_contact_parts(model, contact, &setup)?,
            None => {
                let mut parts = assign_contact_flags(model, &setup)?;
                if setup.skin {
                    skin_roles(model, &setup);
                }
                // Stage 1 for every user part (Kratos calls GenerateInterfacePart on each: it only
                // checks the properties when the part has conditions, else generates them). On
                // the C++ path (no Python layer) only parts that list nodes only get conditions,
                // as Kratos' tests that drive the C++ process do before building it
                // (test_dynamic_search.py, reference §20.2); the plan says which.
                let stage_1 = plan.interface.is_used();
                for (&key, pair) in setup.pairs.iter().filter(|_| stage_1) {
                    for path in &pair.parts {
                        let part = model.get_part(path).map_err(model_error)?;
                        if !python_path && !model.part(part).conditions().is_empty() {
                            continue;
                        }
                        let settings = InterfaceSettings {
                            simplify_geometry: false,
                            contact_property_id: pair.property_id,
                            compatibility: setup.compatibility,
                        };
                        let report = generate_interface_conditions(model, part, &settings)?;
                        let renumbered = &report.renumbered_properties;
                        if let Some(props) = parts.properties.get_mut(&key)
                            && let Some((_, new)) = renumbered.iter().find(|(old, _)| old == props)
                        {
                            *props = *new;
                        }
                        if report.skipped_duplicates > 0 {
                            warnings.push(format!(
                                "part `{path}`: {} faces shared by two solids generated once (robust \
                                 mode; Kratos generates them twice, Q29)",
                                report.skipped_duplicates
                            ));
                        }
                    }
                }
                transfer_to_contact(model, &setup, &parts)?;
                parts
            }
        };
        emulate_python_state(model, &setup, &plan.variables);
        crate::trace::mark("interface");
        // Stage 2 on the whole model (Python calls NormalCheckProcess on the main part).
        let normal_settings = NormalCheckSettings {
            length_proportion: setup.normal_check_proportion,
            compatibility: setup.compatibility,
            ..NormalCheckSettings::default()
        };
        let initial_normals = match plan.normal_check {
            Decision::Used(NormalCheck::Full { .. }) => {
                let (report, kept) = normal_check_with_normals(model, &normal_settings)?;
                warnings.extend(report.warnings());
                Some(kept)
            }
            Decision::Used(NormalCheck::NormalsOnly) => {
                Some(normal_check_normals_only_with_normals(model, &normal_settings)?.1)
            }
            Decision::LeftOut(_) => None,
        };
        crate::trace::mark("normal check");
        if plan.master_slave_from_nodes.is_used() {
            master_slave_from_nodes(model, parts.contact);
        }
        match setup.nodal_h {
            Some(h) => {
                if let Some(col) = model.nodal_data_mut().scalar_mut(ScalarVar::NodalH, 0) {
                    col.fill(h);
                }
            }
            None => assign_nodal_h(model, None, NodalHMode::Kratos),
        }
        crate::trace::mark("nodal h");
        apply_nodal_values(model, &setup.nodal_values)?;
        check_step_parts(model, &setup.steps)?;
        if plan.adapt_search.is_used() {
            // ContactUtilities::CalculateRelativeSizeMesh over every node (Q33: a node in no
            // element has DBL_MAX and makes the factor infinite).
            let h = model
                .nodal_data()
                .scalar(ScalarVar::NodalH, 0)
                .unwrap_or(&[]);
            let max = h.iter().copied().fold(0.0, Real::max);
            let min = h.iter().copied().fold(Real::MAX, Real::min);
            let factor = max / min;
            if !factor.is_finite() {
                return Err(ErrorKind::Model(format!(
                    "adapt_search: h_max/h_min = {max}/{min} is not finite (nodes outside every \
                     element keep NODAL_H = DBL_MAX, Q33)"
                ))
                .into());
            }
            for pair in setup.pairs.values_mut() {
                pair.search.search_factor *= factor;
            }
            setup.active_check_factor *= factor;
            model
                .process_info_mut()
                .set_number("ACTIVE_CHECK_FACTOR", setup.active_check_factor);
        }
        let domain_size = model.process_info().number("DOMAIN_SIZE").unwrap_or(0.0) as u32;
        let mut pairs = Vec::new();
        for (&key, pair) in &setup.pairs {
            let params = pair.search.clone();
            match params.type_search {
                SearchTreeType::OctreeWithObb
                    if params.inverted_search && setup.compatibility == Compatibility::Kratos =>
                {
                    return Err(ErrorKind::RejectedByKratos(
                        "the octree search does not support inverted_search (Kratos errors too)"
                            .to_owned(),
                    )
                    .into());
                }
                _ => {}
            }
            let sub = parts.subs[&key];
            check_contact_model_parts(model, sub, setup.compatibility)?;
            let instance = dispatch(
                model,
                parts.contact,
                domain_size,
                params.predefined_master_slave,
            )?;
            // Base process construction (§3): NORMAL_GAP := 0 (MappingCheck), ACTIVE := false
            // on every condition of ContactSub (this makes ACTIVE defined, §5.3).
            if params.check_gap == CheckGap::MappingCheck {
                let nodes = model.part(sub).nodes().to_vec();
                model.nodal_data_mut().add_scalar(ScalarVar::NormalGap);
                if let Some(col) = model.nodal_data_mut().scalar_mut(ScalarVar::NormalGap, 0) {
                    for n in nodes {
                        col[n.index()] = 0.0;
                    }
                }
            }
            for c in model.part(sub).conditions().to_vec() {
                model.conditions_mut().flags_mut()[c.index()].set(Flag::ACTIVE, false);
            }
            // Roles not predefined and no MASTER flag (the contact parts had conditions of
            // their own, to which Kratos gives no role): robust mode makes every condition a
            // candidate master, the self-contact pre-search then decides the roles (§12).
            // Kratos rejects below.
            let unflagged = !params.predefined_master_slave
                && model
                    .part(sub)
                    .conditions()
                    .iter()
                    .all(|c| !model.conditions().flags()[c.index()].is(Flag::MASTER));
            if unflagged && setup.compatibility == Compatibility::Robust {
                for c in model.part(sub).conditions().to_vec() {
                    model.conditions_mut().flags_mut()[c.index()].set(Flag::MASTER, true);
                }
            }
            // CreatePointListMortar (§4.2): must not be empty.
            let check = !params.inverted_search || !params.predefined_master_slave;
            let has_points = model
                .part(sub)
                .conditions()
                .iter()
                .any(|c| model.conditions().flags()[c.index()].is(Flag::MASTER) == check);
            if !has_points {
                return Err(ErrorKind::RejectedByKratos(format!(
                    "pair {key}: no master conditions to search (\"mPointListDestination not \
                     initialized\" in Kratos; with `assume_master_slave` empty the roles are not \
                     predefined and Kratos gives the conditions of the contact parts no MASTER \
                     flag, Q47): list the slave parts in `assume_master_slave`, give the contact \
                     parts nodes only (Kratos then generates the conditions, all MASTER), or use \
                     \"compatibility\": \"robust\""
                ))
                .into());
            }
            pairs.push(PairSearch {
                key,
                params,
                instance,
                sub,
                paired: Vec::new(),
                pruned: Vec::new(),
                tree: None,
                points: Vec::new(),
            });
        }
        // TO_ERASE is reset on every Contact condition after the clones (§4.1); csm never
        // sets it, so nothing to reset.
        let kratos_ids = if setup.process.renumbers_conditions() {
            kratos_condition_ids(model, parts.contact)
        } else {
            BTreeMap::new()
        };
        Ok(ContactSearch {
            setup,
            plan,
            parts,
            pairs,
            database_step: 0,
            steps_run: 0,
            warnings,
            initial_normals,
            kratos_ids,
        })
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

    /// The ground truth's step ([`crate::GroundTruth`]): [`ContactSearch::step`] for pair
    /// `key` alone, with the broad and narrow phases replaced by `find`, which is given the
    /// model after the unit normals of ContactSub are computed (the normals the orientation
    /// filter reads) and returns the (slave, master) pairs to put in the INDEX_MAPs; then
    /// MappingCheck's CheckPairing runs as usual (mortar mapping, paired conditions, weighted
    /// gap, activation). Requires a MappingCheck pair and no dynamic search.
    pub(crate) fn step_with_pairs<F>(
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
        let run = RunMode::of(&self.setup);
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
        Ok(self.result(model))
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
        }
        if searched {
            self.reset_marker(model);
            let n_pairs = self.pairs.len();
            for i in 0..n_pairs {
                let run = RunMode::of(&self.setup);
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
            for n in model.part(contact).nodes().to_vec() {
                model.nodes_mut().flags_mut()[n.index()].set(Flag::ACTIVE, false);
            }
            for c in model.part(contact).conditions().to_vec() {
                model.conditions_mut().flags_mut()[c.index()].set(Flag::ACTIVE, false);
            }
        }
        let result = self.result(model);
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

    fn reset_marker(&self, model: &mut ModelPart) {
        for n in model.part(self.parts.contact).nodes().to_vec() {
            model.nodes_mut().flags_mut()[n.index()].set(Flag::MARKER, false);
        }
    }

    /// The RESULT.json content of the current state.
    pub fn result(&self, model: &ModelPart) -> SearchResult {
        let mut result = SearchResult {
            warnings: self.warnings.clone(),
            kratos_condition_ids: self.kratos_ids.clone(),
            ..Default::default()
        };
        let ids = model.conditions().ids();
        let node_ids = model.nodes().ids();
        for pair in &self.pairs {
            let inverted = pair.params.inverted_search;
            // Collected in vectors and bulk-built into the maps (sorted input: no per-entry
            // tree insertion).
            let mut slaves: Vec<(u32, Vec<u32>)> = Vec::new();
            // The slave side's nodes, by node index (no sort of every face's nodes).
            let mut on_slave_side = vec![false; model.nodes().len()];
            let gaps = if pair.params.check_gap == CheckGap::MappingCheck {
                model.nodal_data().scalar(ScalarVar::NormalGap, 0)
            } else {
                None
            };
            for c in model.part(pair.sub).conditions() {
                if model.conditions().flags()[c.index()].is(Flag::SLAVE) == inverted {
                    continue;
                }
                let masters: Vec<u32> = model
                    .index_map(*c)
                    .masters()
                    .map(ConditionId::get)
                    .collect();
                slaves.push((ids[c.index()], masters));
                for n in model.conditions().nodes(c.index()) {
                    on_slave_side[n.index()] = true;
                }
            }
            // A part's conditions are duplicate-free, so each id comes once.
            slaves.sort_unstable_by_key(|(id, _)| *id);
            let slaves: std::collections::BTreeMap<u32, Vec<u32>> = slaves.into_iter().collect();
            let mut node_results: Vec<(u32, NodeResult)> = (0..on_slave_side.len())
                .filter(|&i| on_slave_side[i])
                .map(|i| {
                    let n = NodeIdx(i as u32);
                    let flags = model.nodes().flags()[n.index()];
                    // NORMAL_GAP is never written by No/DirectCheck (null); MappingCheck's
                    // 1e12 "not mapped" sentinel is null too.
                    let normal_gap = gaps
                        .and_then(|g| g.get(n.index()).copied())
                        .filter(|g| *g != csm_activation::NORMAL_GAP_SENTINEL);
                    (
                        node_ids[n.index()],
                        NodeResult {
                            normal_gap,
                            active: flags.is(Flag::ACTIVE),
                        },
                    )
                })
                .collect();
            node_results.sort_unstable_by_key(|(id, _)| *id);
            if result.nodes.is_empty() {
                result.nodes = node_results.into_iter().collect();
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

/// Robust skin detection with predefined roles: the skin conditions are all MASTER after the
/// flags of stage 0 (the skin part is the listed part); those whose nodes are all SLAVE (in
/// the `assume_master_slave` parts) become SLAVE, as stage 1 decides for the conditions it
/// generates.
fn skin_roles(model: &mut ModelPart, setup: &SearchSetup) {
    let Some(pair) = setup.pairs.get(&0) else {
        return;
    };
    if pair.slaves.is_empty() {
        return;
    }
    let Some(part) = model.find_part(SKIN_PART) else {
        return;
    };
    for c in model.part(part).conditions().to_vec() {
        let slave = model
            .conditions()
            .nodes(c.index())
            .iter()
            .all(|n| model.nodes().flags()[n.index()].is(Flag::SLAVE));
        if slave {
            let f = &mut model.conditions_mut().flags_mut()[c.index()];
            f.set(Flag::SLAVE, true);
            f.set(Flag::MASTER, false);
        }
    }
}

/// The conditions of `contact` whose id changes when every condition of the model is numbered
/// 1..N in id order (Kratos' `ALMFastInit`), file id → new id.
fn kratos_condition_ids(model: &ModelPart, contact: PartIdx) -> BTreeMap<u32, u32> {
    let mut all = model.conditions().ids().to_vec();
    all.par_sort_unstable();
    let mut renumbered = BTreeMap::new();
    for c in model.part(contact).conditions() {
        let id = model.conditions().ids()[c.index()];
        // Ids are unique: the position is the new id minus one.
        if let Ok(at) = all.binary_search(&id)
            && at as u32 + 1 != id
        {
            renumbered.insert(id, at as u32 + 1);
        }
    }
    renumbered
}

/// `(slave id, master id)` entries as a map from each slave id to its master ids, ascending
/// (repeated entries kept): sorted (the mapping reports them in that order already), grouped
/// by slave and bulk-built into the map, without a tree search per entry.
pub(crate) fn by_slave(entries: &[(u32, u32)]) -> std::collections::BTreeMap<u32, Vec<u32>> {
    let mut entries = entries.to_vec();
    entries.sort_unstable();
    let mut grouped: Vec<(u32, Vec<u32>)> = Vec::new();
    for (s, m) in entries {
        match grouped.last_mut() {
            Some((last, masters)) if *last == s => masters.push(m),
            _ => grouped.push((s, vec![m])),
        }
    }
    grouped.into_iter().collect()
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

/// The parts of a pre-existing `Contact`: every pair needs its `Contact.ContactSub<key>`, as
/// Kratos' search processes do (they fail without it).
fn existing_contact_parts(
    model: &mut ModelPart,
    contact: PartIdx,
    setup: &SearchSetup,
) -> Result<ContactParts, Error> {
    let mut subs = std::collections::BTreeMap::new();
    let mut properties = std::collections::BTreeMap::new();
    for (&key, pair) in &setup.pairs {
        let sub = model
            .find_part(&contact_sub_path(key))
            .ok_or_else(|| missing_contact_sub(key))?;
        subs.insert(key, sub);
        let id = if pair.property_id != 0 {
            pair.property_id
        } else {
            100 + key
        };
        model.ensure_properties(csm_model::PropertiesId(id));
        properties.insert(key, csm_model::PropertiesId(id));
    }
    Ok(ContactParts {
        contact,
        subs,
        properties,
    })
}

/// The nodal variables of the Python path (DESIGN.md §2) that the plan allocates — only those
/// a stage reads, with their history only when a stage reads it — then the process info and
/// the setup's `process_info` overrides.
fn emulate_python_state(model: &mut ModelPart, setup: &SearchSetup, variables: &[VariablePlan]) {
    let data = model.nodal_data_mut();
    for v in variables {
        match (v.variable, &v.storage) {
            (NodalVariable::Scalar(s), Decision::Used(Storage::Current)) => {
                data.add_scalar_current(s)
            }
            (NodalVariable::Vector(s), Decision::Used(Storage::Current)) => {
                data.add_vector_current(s)
            }
            (NodalVariable::Scalar(s), Decision::Used(Storage::WithHistory)) => data.add_scalar(s),
            (NodalVariable::Vector(s), Decision::Used(Storage::WithHistory)) => data.add_vector(s),
            // NORMAL_GAP (plain) is set up per MappingCheck pair; mesh data stays as read.
            (_, Decision::Used(Storage::Plain | Storage::FromMesh)) | (_, Decision::LeftOut(_)) => {
            }
        }
    }
    let pi = model.process_info_mut();
    if !pi.has("DOMAIN_SIZE") {
        pi.set_number("DOMAIN_SIZE", 3.0);
    }
    pi.set_number("STEP", 1.0);
    pi.set_number("TIME", 1.0);
    pi.set_number("DELTA_TIME", 1.0);
    pi.set_number("ZERO_TOLERANCE_FACTOR", setup.zero_tolerance_factor);
    pi.set_number("ACTIVE_CHECK_FACTOR", setup.active_check_factor);
    pi.set_number("DISTANCE_THRESHOLD", 1e24);
    for (k, v) in &setup.process_info {
        pi.set_number(k, *v);
    }
}

/// ClearMortarConditions (§4.3): ResetContactOperators — paired conditions that are not
/// ACTIVE are erased and their masters removed from the slave's INDEX_MAP — then the Lagrange
/// multiplier of ContactSub nodes that are not ACTIVE is zeroed. An entry without a paired
/// condition (no `condition_name`) makes Kratos fail (Q18): an error in `kratos` mode, dropped
/// in `robust` mode.
fn clear_mortar_conditions(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    compatibility: Compatibility,
) -> Result<(), Error> {
    let inverted = pair.params.inverted_search;
    for c in model.part(pair.sub).conditions().to_vec() {
        if model.conditions().flags()[c.index()].is(Flag::SLAVE) == inverted {
            continue;
        }
        let orphans: Vec<ConditionId> = model
            .index_map(c)
            .iter()
            .filter(|(_, paired)| paired.is_none())
            .map(|(master, _)| master)
            .collect();
        if orphans.is_empty() {
            continue;
        }
        if compatibility == Compatibility::Kratos {
            return Err(ErrorKind::RejectedByKratos(format!(
                "pair {}: condition {} keeps master {} in its INDEX_MAP without a paired \
                 condition (no `condition_name` in the C++ parameters); Kratos' \
                 ClearMortarConditions then fails (\"Condition index not found: 0.\", Q18) — \
                 a second step needs paired conditions, or \"compatibility\": \"robust\"",
                pair.key,
                model.conditions().ids()[c.index()],
                orphans[0].get()
            ))
            .into());
        }
        for m in orphans {
            model.index_map_mut(c).remove_id(m);
        }
    }
    let mut kept = Vec::new();
    for pc in pair.paired.drain(..) {
        if pc.active {
            kept.push(pc);
        } else {
            let master_id = ConditionId(model.conditions().ids()[pc.master.index()]);
            model.index_map_mut(pc.slave).remove_id(master_id);
        }
    }
    pair.paired = kept;
    let nodes = model.part(pair.sub).nodes().to_vec();
    let inactive: Vec<NodeIdx> = nodes
        .into_iter()
        .filter(|n| !model.nodes().flags()[n.index()].is(Flag::ACTIVE))
        .collect();
    let data = model.nodal_data_mut();
    if let Some(col) = data.scalar_mut(ScalarVar::LagrangeMultiplierContactPressure, 0) {
        for n in &inactive {
            col[n.index()] = 0.0;
        }
    }
    if let Some(col) = data.vector_mut(VectorVar::VectorLagrangeMultiplier, 0) {
        for n in &inactive {
            col[n.index()] = Vector::zeros();
        }
    }
    Ok(())
}

/// The normal check's face normals for a pair's step ([`ContactSearch::step`]).
struct InitialNormals<'a> {
    table: &'a mut Option<KeptFaceNormals>,
    /// No later pair takes them: dropped once used.
    last_user: bool,
}

/// UpdateMortarConditions (§5) for the kd-tree path.
/// Returns the warnings of the step (e.g. faces the octree cannot test).
fn update_mortar_conditions(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    plan: &mut PairPlan,
    run: RunMode,
    initial: InitialNormals<'_>,
) -> Result<Vec<String>, Error> {
    let compatibility = run.compatibility;
    let mut run_warnings = Vec::new();
    crate::trace::start();
    let p = pair.params.clone();
    let inverted = p.inverted_search;
    let sub = pair.sub;
    let dim = usize::from(pair.instance.dim);
    // 1. Dynamic search: the half-jump increments; MappingCheck moves the nodes (§11). Left
    // out when every increment would be zero (the plan, decided again on this step's data).
    let sub_nodes = model.part(sub).nodes().to_vec();
    pair.pruned.clear();
    plan.step_jump = step_jump(&p, model, &sub_nodes);
    let delta = if plan.step_jump.is_used() {
        let dt = model.process_info().number("DELTA_TIME").unwrap_or(1.0);
        Some(compute_step_jump(model, &sub_nodes, dt))
    } else {
        None
    };
    let moved = plan.step_jump.used().is_some_and(|s| s.moves_nodes);
    if let (true, Some(d)) = (moved, &delta) {
        shift_nodes(model, &sub_nodes, d, 1.0);
    }
    // 2. Unit normals of ContactSub.
    let normals_mode = match compatibility {
        Compatibility::Kratos => NormalsMode::Kratos,
        Compatibility::Robust => NormalsMode::Once,
    };
    // The faces' own normals are kept for MappingCheck's mapping: nothing moves the nodes or
    // changes the condition normals before it. From the normal check's table where it is
    // still current (the last pair to use it takes it).
    let mapping = p.check_gap == CheckGap::MappingCheck;
    let from_initial = match initial.table.as_ref() {
        Some(kept) => compute_unit_normals_from_kept(model, Some(sub), normals_mode, kept)
            .map_err(model_error)?,
        None => false,
    };
    let taken = if initial.last_user {
        initial.table.take()
    } else {
        None
    };
    let face_normals = if from_initial {
        mapping
            .then(|| taken.or_else(|| initial.table.clone()))
            .flatten()
    } else {
        let faces = compute_unit_normals(model, Some(sub), normals_mode).map_err(model_error)?;
        mapping.then(|| faces.keep())
    };
    crate::trace::mark("unit normals");
    // 3. The running id of created pairs: after the largest condition id of the root (the
    // paired conditions of earlier steps included).
    let max_paired = pair.paired.iter().map(|pc| pc.id.get()).max().unwrap_or(0);
    let condition_id = model.conditions().max_id().max(max_paired);

    // 5. Roles not predefined: the self-contact pre-search decides them (§12.1).
    if !p.predefined_master_slave {
        self_contact_roles(model, pair, &p, plan, compatibility, delta.as_deref())?;
    }
    // 6. SearchUsingOcTree (§8) or SearchUsingKDTree (§5.3).
    let mut created = Vec::new();
    if plan.octree.is_used() {
        let domain_size = model.process_info().number("DOMAIN_SIZE").unwrap_or(0.0) as u32;
        let ocx = OctreeContext {
            params: &p,
            sub,
            dim,
            slave_nodes: usize::from(pair.instance.slave_nodes),
            compatibility,
            domain_size,
            active_before: (compatibility == Compatibility::Robust).then(|| active_snapshot(model)),
        };
        let report = if inverted {
            // Robust mode: the octree searches from the other side by swapping the roles of
            // the ContactSub conditions (slave side = not SLAVE, master side = not MASTER),
            // then restores the flags.
            let saved = swap_roles(model, sub);
            let direct = SearchParameters {
                inverted_search: false,
                ..p.clone()
            };
            let ocx = OctreeContext {
                params: &direct,
                active_before: ocx.active_before.clone(),
                ..ocx
            };
            let report = search_octree_report(model, &ocx, &mut created);
            for (c, flags) in saved {
                model.conditions_mut().flags_mut()[c.index()] = flags;
            }
            report?
        } else {
            search_octree_report(model, &ocx, &mut created)?
        };
        run_warnings.extend(report.warnings);
    } else {
        let points = (!p.predefined_master_slave).then(|| pair.points.clone());
        let pass = KdPass::Main {
            points,
            with_obb: plan.obb_test.is_used(),
        };
        kdtree_search(
            model,
            pair,
            (&p, pass),
            plan,
            (compatibility, run.keep_tree),
            delta.as_deref(),
            &mut created,
        )?;
    }
    // 7. Roles not predefined: both sides of the maps get their flags (§12.3).
    if !p.predefined_master_slave {
        not_predefined_master_slave(model, sub);
    }
    finish_pairs(model, pair, created, condition_id);
    crate::trace::mark("pairing");
    // 8. SetOriginDestinationModelParts: both sides must have conditions.
    let (mut n_slave, mut n_master) = (0, 0);
    for c in model.part(sub).conditions() {
        let f = model.conditions().flags()[c.index()];
        n_slave += usize::from(f.is(Flag::SLAVE) != inverted);
        n_master += usize::from(f.is(Flag::MASTER) != inverted);
    }
    if n_slave == 0 || n_master == 0 {
        return Err(ErrorKind::RejectedByKratos(format!(
            "pair {}: no origin/destination conditions ({n_slave} slave-side, {n_master} \
             master-side)",
            pair.key
        ))
        .into());
    }
    // 9. MappingCheck: CheckPairing (§10.1) — the mortar mapping prunes the INDEX_MAPs and
    // gives NORMAL_GAP, then the paired conditions, the weighted gap and the activation.
    if p.check_gap == CheckGap::MappingCheck {
        let restore = if moved { delta.as_deref() } else { None };
        let step = PairingStep {
            params: &p,
            plan,
            restore,
            face_normals,
            condition_id,
        };
        let warnings = check_pairing(model, pair, step, run)?;
        run_warnings.extend(warnings);
        return Ok(run_warnings);
    }
    // No/DirectCheck with a dynamic search: Kratos subtracts the increment although the
    // nodes were never moved (Q9); robust mode does not.
    if let (Some(d), Compatibility::Kratos) = (&delta, compatibility) {
        shift_nodes(model, &sub_nodes, d, -1.0);
    }
    Ok(run_warnings)
}

/// What [`check_pairing`] works with besides the model, the pair and the run mode.
struct PairingStep<'a> {
    params: &'a SearchParameters,
    plan: &'a PairPlan,
    /// The dynamic shift to undo after the mapping, if the nodes were moved.
    restore: Option<&'a [Vector]>,
    /// The unit normals of the sub's faces on the current coordinates (the step's
    /// [`compute_unit_normals`], kept), which the mapping's mean normals take instead of
    /// computing them.
    face_normals: Option<KeptFaceNormals>,
    /// The id after which paired conditions are numbered.
    condition_id: u32,
}

/// CheckPairing (§10.1) of MappingCheck, after the search filled the INDEX_MAPs: Advanced sets
/// `DISTANCE_THRESHOLD` from the mean NODAL_H; NormalGapProcess (`NORMAL_GAP := 1e12`, the
/// mortar mapping that removes the entries without overlap and erases their paired
/// conditions); the dynamic shift is undone (`restore`); the unit normals are recomputed
/// (without `restore` the caller computed them on this sub with the same coordinates, and
/// their values are written back instead);
/// CreateAuxiliaryConditions for the surviving new entries; ComputeWeightedReaction;
/// ComputeActiveInactiveNodes (with the multiplier guesses and, for frictional contact — a
/// SLIP root model part — the SLIP rule). Returns the activation's warnings.
///
fn check_pairing(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    step: PairingStep<'_>,
    run: RunMode,
) -> Result<Vec<String>, Error> {
    let PairingStep {
        params: p,
        plan,
        restore,
        face_normals,
        condition_id,
    } = step;
    let RunMode {
        compatibility,
        frictional,
        python_path,
        ..
    } = run;
    use csm_activation as act;
    let inverted = p.inverted_search;
    let sub = pair.sub;
    let dim = usize::from(pair.instance.dim);
    let activation_error = |e: act::Error| Error::from(ErrorKind::Model(e.to_string()));
    let mode = match compatibility {
        Compatibility::Kratos => act::MortarMode::Kratos,
        Compatibility::Robust => act::MortarMode::Robust,
    };
    if !p.simple_search {
        let h = act::mean_h(model, sub, inverted);
        model.process_info_mut().set_number("DISTANCE_THRESHOLD", h);
    }
    let distance_threshold = model
        .process_info()
        .number("DISTANCE_THRESHOLD")
        .unwrap_or(1e24);
    let settings = act::MappingSettings {
        mode,
        distance_threshold,
        inverted,
        dim,
    };
    // Without a dynamic shift the coordinates are those of the step's unit normals: the
    // unit normals after the mapping are the same values, kept here rather than recomputed
    // (the mapping overwrites the nodal ones with its mean normals).
    let unit_normals = if restore.is_none() {
        UnitNormalsSnapshot::take(model, Some(sub))
    } else {
        None
    };
    // The same condition: the weighted gap's segmentation of a pair is the mapping's, so the
    // mapping computes the weighted gap of the pairs it keeps (with the kept unit normals).
    let weighted_gap =
        plan.weighted_gap.is_used() && model.nodal_data().has_scalar(ScalarVar::WeightedGap);
    let (report, known_gaps) = match &unit_normals {
        Some(kept) if weighted_gap => {
            let (report, known) =
                act::normal_gap_process_keeping(model, sub, &settings, face_normals, kept.nodal())
                    .map_err(activation_error)?;
            (report, Some(known))
        }
        _ => (
            act::normal_gap_process(model, sub, &settings, face_normals)
                .map_err(activation_error)?,
            None,
        ),
    };
    crate::trace::mark("mapping");
    let mapping_warnings = report.warnings(mode);
    let ids = model.conditions().ids();
    pair.pruned = report
        .removed
        .iter()
        .map(|r| (ids[r.slave.index()], r.master.get()))
        .collect();
    // TO_ERASE: the paired conditions of removed entries (kept from an earlier step) go.
    if report.removed.iter().any(|r| r.paired.is_some()) {
        let erased: BTreeSet<u32> = report
            .removed
            .iter()
            .filter_map(|r| r.paired.map(ConditionId::get))
            .collect();
        pair.paired.retain(|pc| !erased.contains(&pc.id.get()));
    }
    let sub_nodes = model.part(sub).nodes().to_vec();
    if let Some(d) = restore {
        shift_nodes(model, &sub_nodes, d, -1.0);
    }
    let normals_mode = match compatibility {
        Compatibility::Kratos => NormalsMode::Kratos,
        Compatibility::Robust => NormalsMode::Once,
    };
    match unit_normals {
        // The mapping changed NORMAL only on nodes of the part's conditions (its mean
        // normals): the kept column is the restored one.
        Some(kept) => kept.restore_all(model),
        None => drop(compute_unit_normals(model, Some(sub), normals_mode).map_err(model_error)?),
    }
    crate::trace::mark("unit normals");
    // CreateAuxiliaryConditions: slave side, entries without a paired condition.
    if p.create_auxiliar_conditions {
        let mut created = Vec::new();
        for s in conditions_by_id(model, sub) {
            if model.conditions().flags()[s.index()].is(Flag::SLAVE) == inverted {
                continue;
            }
            for (master, paired) in model.index_map(s).iter() {
                if paired.is_none()
                    && let Some(m) = model.conditions().index_of(master.get())
                {
                    created.push((s, ConditionIdx(m as u32)));
                }
            }
        }
        finish_pairs(model, pair, created, condition_id);
    }
    crate::trace::mark("auxiliary conditions");
    // ComputeWeightedReaction: only the Advanced activation reads WEIGHTED_GAP.
    if plan.weighted_gap.is_used() {
        let paired: Vec<_> = pair.paired.iter().map(|pc| (pc.slave, pc.master)).collect();
        let isolated = act::compute_weighted_gap(
            model,
            sub,
            &paired,
            (mode, distance_threshold),
            dim,
            known_gaps,
        )
        .map_err(activation_error)?;
        for (pc, isolated) in pair.paired.iter_mut().zip(isolated) {
            pc.isolated = isolated;
        }
    }
    crate::trace::mark("weighted gap");
    let rule = if p.simple_search {
        act::ActivationRule::Simple
    } else {
        act::ActivationRule::Advanced {
            static_check_movement: p.static_check_movement,
            consider_gap_threshold: p.consider_gap_threshold,
            distance_threshold,
            active_check_factor: model
                .process_info()
                .number("ACTIVE_CHECK_FACTOR")
                .unwrap_or(0.0),
        }
    };
    // Python's ALM path computes INITIAL_PENALTY and SCALE_FACTOR with
    // ALMVariablesCalculationProcess, which csm does not emulate: without values in the
    // setup's `process_info` the guess is skipped (with a warning) rather than guessed wrong.
    // The C++ path reads absent values as 0 (0/0 = NaN, Q25), which kratos mode reproduces.
    let initial_penalty = model.process_info().number("INITIAL_PENALTY");
    let scale_factor = model.process_info().number("SCALE_FACTOR");
    let not_emulated = python_path && (initial_penalty.is_none() || scale_factor.is_none());
    let multiplier = act::MultiplierSettings {
        kind: act::MultiplierKind::of(model),
        initial_penalty,
        scale_factor,
        predict_correct: p.predict_correct_lagrange_multiplier,
        slip: frictional,
        pure_slip: p.pure_slip,
        guarded: compatibility == Compatibility::Robust || not_emulated,
    };
    let report = act::compute_active_inactive_nodes(
        model,
        sub,
        &act::ActivationSettings {
            rule,
            inverted,
            keep_gap_on_inactive: compatibility == Compatibility::Robust,
            multiplier,
        },
    );
    crate::trace::mark("activation");
    let mut warnings = mapping_warnings;
    warnings.extend(report.warnings);
    Ok(warnings)
}

/// What the ground truth's pair finder is told about the pair it searches
/// ([`ContactSearch::step_with_pairs`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct TruthScene {
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

/// The positions in `slaves` ordered along a Morton (Z-order) curve of the slave centres
/// (node means, quantised to 21 bits per axis in their bounding box); ties by position, so the
/// order is deterministic. Only the order of the parallel queries depends on it, never a result.
#[cfg(test)]
pub(crate) fn morton_order(model: &ModelPart, slaves: &[ConditionIdx]) -> Vec<usize> {
    let centres: Vec<(usize, Point)> = slaves
        .par_iter()
        .enumerate()
        .map(|(k, c)| (k, reach(model, *c).0))
        .collect();
    morton_order_of(&centres)
}

/// The centre of condition `c` (its node mean) and the largest distance from it to a node.
pub(crate) fn reach(model: &ModelPart, c: ConditionIdx) -> (Point, Real) {
    let coords = model.nodes().coordinates();
    let nodes = model.conditions().nodes(c.index());
    let sum = nodes
        .iter()
        .fold(Vector::zeros(), |acc, n| acc + coords[n.index()].coords);
    let centre = Point::from(sum / nodes.len().max(1) as Real);
    let radius = nodes
        .iter()
        .map(|n| (coords[n.index()] - centre).norm())
        .fold(0.0, Real::max);
    (centre, radius)
}

/// The tests' override of [`Far::is_far`]: 1 takes every query as far, 2 none (0: the
/// estimate). Only the order of the queries depends on it, so other tests may run meanwhile.
#[cfg(test)]
pub(crate) static QUERY_REACH: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(0);

/// Which slave queries stay far from the kd-tree's points (and end at its root): an estimate
/// of the queries' reach, which only decides the order of the queries, never a result.
pub(crate) struct Far {
    bounds: Option<Aabb>,
    /// How far a query reaches, in slave radii (twice the search factor, at least 2).
    factor: Real,
}

impl Far {
    pub(crate) fn new(bounds: Option<Aabb>, search_factor: Real) -> Far {
        Far {
            bounds,
            factor: 2.0 * search_factor.max(1.0),
        }
    }

    /// Whether the query of a slave of centre `centre` and radius `radius` (see [`reach`]) is
    /// taken to stay far from the tree's points.
    pub(crate) fn is_far(&self, centre: &Point, radius: Real) -> bool {
        #[cfg(test)]
        match QUERY_REACH.load(Ordering::Relaxed) {
            1 => return true,
            2 => return false,
            _ => {}
        }
        self.bounds.is_some_and(|b| {
            let outside = (b.mins - centre)
                .sup(&(centre - b.maxs))
                .sup(&Vector::zeros());
            outside.norm() > self.factor * radius
        })
    }
}

/// The positions of `centres` (position, centre) ordered along a Morton curve of the centres
/// (see [`morton_order`]).
fn morton_order_of(centres: &[(usize, Point)]) -> Vec<usize> {
    let mut lo = Vector::repeat(Real::INFINITY);
    let mut hi = Vector::repeat(Real::NEG_INFINITY);
    for (_, p) in centres {
        lo = lo.inf(&p.coords);
        hi = hi.sup(&p.coords);
    }
    let cells = Real::from((1u32 << 21) - 1);
    let quantise = |x: Real, k: usize| -> u64 {
        let span = hi[k] - lo[k];
        if span.is_nan() || span <= 0.0 || !x.is_finite() {
            return 0;
        }
        (((x - lo[k]) / span * cells).clamp(0.0, cells)) as u64
    };
    let spread = |mut v: u64| -> u64 {
        // Insert two zero bits between the 21 low bits of `v`.
        v &= 0x1f_ffff;
        v = (v | v << 32) & 0x1f_0000_0000_ffff;
        v = (v | v << 16) & 0x1f_0000_ff00_00ff;
        v = (v | v << 8) & 0x100f_00f0_0f00_f00f;
        v = (v | v << 4) & 0x10c3_0c30_c30c_30c3;
        v = (v | v << 2) & 0x1249_2492_4924_9249;
        v
    };
    let mut keyed: Vec<(u64, usize)> = centres
        .par_iter()
        .map(|&(i, p)| {
            let code = spread(quantise(p.x, 0))
                | spread(quantise(p.y, 1)) << 1
                | spread(quantise(p.z, 2)) << 2;
            (code, i)
        })
        .collect();
    // The positions are unique: one order, whatever the sort.
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
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
}

impl RunMode {
    fn of(setup: &SearchSetup) -> RunMode {
        RunMode {
            compatibility: setup.compatibility,
            frictional: setup.contact_type.is_frictional(),
            python_path: !setup.cpp_search_parameters,
            keep_tree: setup.refit_tree && setup.steps.len() > 1,
        }
    }
}

/// Swaps the roles of the conditions of `sub` for an inverted octree search: SLAVE := not
/// SLAVE, MASTER := not MASTER (undefined counts as not set). Returns the original flags.
fn swap_roles(model: &mut ModelPart, sub: PartIdx) -> Vec<(ConditionIdx, csm_model::Flags)> {
    let conditions = model.part(sub).conditions().to_vec();
    let mut saved = Vec::with_capacity(conditions.len());
    for c in conditions {
        let flags = &mut model.conditions_mut().flags_mut()[c.index()];
        saved.push((c, *flags));
        let (slave, master) = (flags.is(Flag::SLAVE), flags.is(Flag::MASTER));
        flags.set(Flag::SLAVE, !slave);
        flags.set(Flag::MASTER, !master);
    }
    saved
}

/// Gives the created pairs their ids — after the largest condition id, in slave id order then
/// master id order (DESIGN.md §2) — and records them.
fn finish_pairs(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    mut created: Vec<(ConditionIdx, ConditionIdx)>,
    mut condition_id: u32,
) {
    let ids = model.conditions().ids();
    created.sort_by_key(|(s, m)| (ids[s.index()], ids[m.index()]));
    for (s, m) in created {
        condition_id += 1;
        let id = ConditionId(condition_id);
        let master_id = ConditionId(model.conditions().ids()[m.index()]);
        model.index_map_mut(s).set_new_entity_id(master_id, id);
        pair.paired.push(PairedCondition {
            id,
            slave: s,
            master: m,
            active: true,
            isolated: false,
        });
    }
}

/// SearchUsingKDTree (§5.3): the kd-tree over the point list, the parallel per-slave queries
/// and tests, then the serial, ordered application.
///
/// In a multi-step run (`keep_tree`) the tree of the last step is refitted to the moved
/// centres instead of rebuilt when the master-side conditions are the same and the result
/// order cannot change the pairs (not Kratos-mode DirectCheck, whose node counting follows
/// the candidate order). A refitted tree finds the same masters; if a query reaches the
/// result cap (`max_number_results`), where the traversal order decides which are kept, the
/// tree is rebuilt and every query run again.
fn kdtree_search(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    (p, pass): (&SearchParameters, KdPass),
    plan: &PairPlan,
    (compatibility, keep_tree): (Compatibility, bool),
    delta: Option<&[Vector]>,
    created: &mut Vec<(ConditionIdx, ConditionIdx)>,
) -> Result<(), Error> {
    let inverted = p.inverted_search;
    let sub = pair.sub;
    let dim = usize::from(pair.instance.dim);
    let check = !inverted || !p.predefined_master_slave;
    let pre_search = matches!(pass, KdPass::SelfContact { .. });
    let keep_tree = keep_tree && !pre_search;
    let conditions = conditions_by_id(model, sub);
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
            .iter()
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
    let tree_error = |e: csm_trees::Error| {
        Error::from(ErrorKind::Model(format!(
            "kd-tree of the master conditions: {e}"
        )))
    };
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
    let (mut tree, refitted) = match kept {
        Some(mut kept) if keep_tree && order_free && kept.ids == ids => {
            let mut at = vec![Point::origin(); model.conditions().len()];
            for (&c, x) in master_list.iter().zip(&centres) {
                at[c as usize] = *x;
            }
            kept.tree.refit(|c| at[c as usize]).map_err(tree_error)?;
            (kept.tree, true)
        }
        _ => (new_tree(master_list, centres)?, false),
    };
    crate::trace::mark("kd-tree");
    // Read in place: the model is only read until the serial pairing below.
    let h_col = model
        .nodal_data()
        .scalar(ScalarVar::NodalH, 0)
        .unwrap_or(&[]);
    let hmax = model
        .part(sub)
        .nodes()
        .iter()
        .map(|n| h_col[n.index()])
        .fold(0.0, Real::max);
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
        .iter()
        .map(|&c| ConditionIdx(c))
        .collect();
    // Built when first asked for by a query, which holds the model: both are dropped before
    // the pairing changes it.
    let shared: &ModelPart = model;
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
    let slaves: Vec<ConditionIdx> = conditions
        .iter()
        .copied()
        .filter(|c| {
            let f = model.conditions().flags()[c.index()];
            pre_search || (f.is_defined(Flag::ACTIVE) && f.is(Flag::SLAVE) != inverted)
        })
        .collect();
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
        // The queries of the slaves far from the tree run as their nodes are read, in slave
        // order; the others along a Morton curve of the slave centres (neighbouring queries
        // visit the same tree nodes and masters). The results go back to the slave order.
        let query_all = |tree: &KdTree<u32>| -> (Vec<usize>, Vec<QueryChunk>, bool) {
            let truncated = AtomicBool::new(false);
            let query = |scratch: &mut QueryScratch, out: &mut QueryChunk, k: usize| {
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
            let far = Far::new(tree.bounds(), p.search_factor);
            let first: Vec<FarQueries> = slaves
                .par_chunks(QUERY_CHUNK)
                .enumerate()
                .map_init(QueryScratch::default, |scratch, (i, chunk)| {
                    let mut out = FarQueries::default();
                    for (j, &c) in chunk.iter().enumerate() {
                        let k = i * QUERY_CHUNK + j;
                        let (centre, radius) = reach(model, c);
                        if far.is_far(&centre, radius) {
                            query(scratch, &mut out.chunk, k);
                            out.done.push(k);
                        } else {
                            out.near.push((k, centre));
                        }
                    }
                    out
                })
                .collect();
            let mut order = Vec::with_capacity(slaves.len());
            let mut chunks = Vec::with_capacity(first.len());
            let mut near = Vec::new();
            for queries in first {
                order.extend(queries.done);
                chunks.push(queries.chunk);
                near.extend(queries.near);
            }
            // Where many slaves come near the masters, most masters' boxes will be asked for:
            // computed first, in master order.
            if near.len() >= slaves.len() / 4 {
                master_bvs.compute_all();
                master_kdops.compute_all();
            }
            let curve = morton_order_of(&near);
            chunks.extend(
                curve
                    .par_chunks(QUERY_CHUNK)
                    .map_init(QueryScratch::default, |scratch, chunk| {
                        let mut out = QueryChunk::default();
                        for &k in chunk {
                            query(scratch, &mut out, k);
                        }
                        out
                    })
                    .collect::<Vec<_>>(),
            );
            order.extend(curve);
            (order, chunks, truncated.into_inner())
        };
        let (mut order, mut chunks, truncated) = query_all(&tree);
        if refitted && truncated {
            // A capped query keeps the first masters in traversal order: take a rebuilt
            // tree's order, as a step without a kept tree does.
            let mut by_id: Vec<u32> = tree.stored_items().to_vec();
            by_id.sort_unstable_by_key(|&c| model.conditions().ids()[c as usize]);
            let centres = centres_of(&by_id);
            tree = new_tree(by_id, centres)?;
            (order, chunks, _) = query_all(&tree);
        }
        SlaveCandidates::in_slave_order(&order, chunks)
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
    for (k, s) in slaves.iter().enumerate() {
        apply_candidates(model, &pcx, *s, candidates.of(k), created);
    }
    Ok(())
}

/// Which kd-tree search [`kdtree_search`] runs.
enum KdPass {
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
fn self_contact_roles(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    p: &SearchParameters,
    plan: &PairPlan,
    compatibility: Compatibility,
    delta: Option<&[Vector]>,
) -> Result<(), Error> {
    let sub = pair.sub;
    if pair.points.is_empty() {
        let flags = model.conditions().flags();
        pair.points = conditions_by_id(model, sub)
            .into_iter()
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
        (compatibility, false),
        delta,
        &mut none,
    )?;
    compute_self_contact_pairing(model, sub)?;
    let conditions = conditions_by_id(model, sub);
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
const QUERY_CHUNK: usize = 256;

/// Subtrees of the step's kd-tree over at most this many master centres are built when a
/// slave query first reaches them ([`KdTree::new_deferred`]: the same tree, the same query
/// results): where the bodies touch in a small region, most are never built (sphere 2e5:
/// the tree 0.093 → 0.045 s on one thread; 256 and 4096 points measured alike or worse).
const TREE_DEFER_MAX: usize = 1024;

/// The candidates of consecutive queries (along the Morton curve) of one task.
#[derive(Default)]
struct QueryChunk {
    /// Per query, its number of candidates.
    counts: Vec<u32>,
    list: Vec<Candidate>,
    /// The error of the query with the smallest slave position, if any.
    error: Option<(usize, Error)>,
}

/// The first pass of the slave queries over consecutive slaves: the queries of the far ones.
#[derive(Default)]
struct FarQueries {
    /// Their results.
    chunk: QueryChunk,
    /// Their positions, in order.
    done: Vec<usize>,
    /// The positions and centres of the others.
    near: Vec<(usize, Point)>,
}

/// The candidates of every slave, flat: slave `k`'s are `list[start[k]..start[k + 1]]`.
struct SlaveCandidates {
    start: Vec<u32>,
    list: Vec<Candidate>,
    /// The error of the first slave (in slave order) whose query failed.
    error: Option<Error>,
}

impl SlaveCandidates {
    /// From the chunks of the queries in `order` (slave positions along the curve).
    fn in_slave_order(order: &[usize], chunks: Vec<QueryChunk>) -> SlaveCandidates {
        let n = order.len();
        let mut count = vec![0u32; n];
        let mut error: Option<(usize, Error)> = None;
        let mut j = 0;
        for chunk in &chunks {
            for &c in &chunk.counts {
                count[order[j]] = c;
                j += 1;
            }
        }
        let mut start = Vec::with_capacity(n + 1);
        start.push(0u32);
        let mut total = 0u32;
        for c in &count {
            total += c;
            start.push(total);
        }
        let mut list = vec![
            Candidate {
                master: ConditionIdx(0),
                node_pass: 0
            };
            total as usize
        ];
        let mut j = 0;
        for chunk in chunks {
            let mut from = 0usize;
            for &c in &chunk.counts {
                let k = order[j];
                let to = start[k] as usize;
                list[to..to + c as usize].copy_from_slice(&chunk.list[from..from + c as usize]);
                from += c as usize;
                j += 1;
            }
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

fn shift_nodes(model: &mut ModelPart, nodes: &[NodeIdx], delta: &[Vector], sign: Real) {
    let coords = model.nodes_mut().coordinates_mut();
    for n in nodes {
        coords[n.index()] += delta[n.index()] * sign;
    }
}
