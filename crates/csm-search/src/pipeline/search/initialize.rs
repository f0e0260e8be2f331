//! `ContactSearch::initialize`: Kratos' `ExecuteInitialize` (reference §1.3, §4) — contact
//! parts, skin, interface conditions, the emulated Python state, the normal check, NODAL_H,
//! `adapt_search`, each pair's search instance and point list.

use super::*;

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
        crate::trace::start();
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
        crate::trace::mark("plan");
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
                if setup.interfaces_generated {
                    generated_roles(model, setup.compatibility == Compatibility::Kratos);
                }
                if setup.skin {
                    skin_roles(model, &setup);
                }
                if plan.interface.is_used() && !setup.interfaces_generated {
                    interface_stage(model, &setup, python_path, (&mut parts, &mut warnings))?;
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
                    write_at_ascending(col, nodes.len(), |k| nodes[k].index(), |_, g| *g = 0.0);
                }
            }
            set_flag_on(model, sub, Flag::ACTIVE, false);
            // Roles not predefined and no MASTER flag (the contact parts had conditions of
            // their own, to which Kratos gives no role): robust mode makes every condition a
            // candidate master, the self-contact pre-search then decides the roles (§12).
            // Kratos rejects below.
            let unflagged = !params.predefined_master_slave
                && model
                    .part(sub)
                    .conditions()
                    .par_iter()
                    .all(|c| !model.conditions().flags()[c.index()].is(Flag::MASTER));
            if unflagged && setup.compatibility == Compatibility::Robust {
                set_flag_on(model, sub, Flag::MASTER, true);
            }
            // CreatePointListMortar (§4.2): must not be empty.
            let check = !params.inverted_search || !params.predefined_master_slave;
            let has_points = model
                .part(sub)
                .conditions()
                .par_iter()
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
                globals: PairGlobals::default(),
                used: PairGlobals::default(),
                ranks: None,
                step_pairs: None,
            });
        }
        // TO_ERASE is reset on every Contact condition after the clones (§4.1); csm never
        // sets it, so nothing to reset.
        let kratos_ids = if setup.process.renumbers_conditions() {
            kratos_condition_ids(model, parts.contact)
        } else {
            BTreeMap::new()
        };
        crate::trace::mark("search set-up");
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
            tuning: SearchTuning::default(),
        })
    }
}

/// Stage 1 for every user part (Kratos calls GenerateInterfacePart on each: it only checks the
/// properties when the part has conditions, else generates them). On the C++ path (no Python
/// layer, `python_path` false) only parts that list nodes only get conditions, as Kratos'
/// tests that drive the C++ process do before building it (test_dynamic_search.py, reference
/// §20.2). Renumbered contact properties go to `parts`, warnings to `warnings`.
fn interface_stage(
    model: &mut ModelPart,
    setup: &SearchSetup,
    python_path: bool,
    (parts, warnings): (&mut ContactParts, &mut Vec<String>),
) -> Result<(), Error> {
    for (&key, pair) in &setup.pairs {
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
                    "part `{path}`: {} faces shared by two solids generated once (robust mode; \
                     Kratos generates them twice, Q29)",
                    report.skipped_duplicates
                ));
            }
        }
    }
    Ok(())
}

/// For a run that splits the model afterwards (`csm-distributed`): the interface conditions
/// that stage 1 generates from the elements of the contact parts without conditions, generated
/// on the whole model as [`ContactSearch::initialize`] generates them (the same ids, properties
/// and flags), with the contact parts' flags of stage 0 and the parts `Contact` and
/// `Contact.ContactSub<key>` (still empty). Returns the warnings stage 1 gives, or `None`
/// (nothing done) where no condition would be generated: every contact part has conditions,
/// the model has a `Contact` part, the setup detects the skin, or the plan leaves stage 1 out.
///
/// [`ContactSearch::initialize`] of a piece of the result (the parts then have conditions, so
/// stage 1 only checks their properties), with the warnings added to the setup's, searches as
/// the one-process run does.
pub fn generate_interfaces_first(
    model: &mut ModelPart,
    setup: &SearchSetup,
) -> Result<Option<Vec<String>>, Error> {
    if model.find_part("Contact").is_some() || setup.skin {
        return Ok(None);
    }
    let without_conditions = (setup.pairs.values().flat_map(|p| &p.parts))
        .any(|path| (model.find_part(path)).is_some_and(|p| model.part(p).conditions().is_empty()));
    if !without_conditions {
        return Ok(None);
    }
    let plan = Plan::decide(model, setup)?;
    if !plan.interface.is_used() {
        return Ok(None);
    }
    let mut parts = assign_contact_flags(model, setup)?;
    let mut warnings = Vec::new();
    let python_path = !setup.cpp_search_parameters;
    interface_stage(model, setup, python_path, (&mut parts, &mut warnings))?;
    Ok(Some(warnings))
}

/// The part that lists, in a mesh whose interface conditions were generated before
/// ([`generate_interfaces_first`], [`SearchSetup::interfaces_generated`]), the generated
/// conditions whose roles no slave part gives (a pair whose roles are decided
/// automatically): the search gives them the roles stage 1 gave them.
pub const GENERATED_CONDITIONS_PART: &str = "CsmGeneratedConditions";

/// Stage 1's roles ([`crate::stages::assign_generated_role`]) for the conditions of
/// [`GENERATED_CONDITIONS_PART`], where the model has that part.
fn generated_roles(model: &mut ModelPart, kratos: bool) {
    let Some(part) = model.find_part(GENERATED_CONDITIONS_PART) else {
        return;
    };
    for c in model.part(part).conditions().to_vec() {
        crate::stages::assign_generated_role(model, c.index(), kratos);
    }
}

/// Sets `flag` to `value` on every condition of `part` (in parallel: the part lists its
/// conditions in ascending index).
pub(super) fn set_flag_on(model: &mut ModelPart, part: PartIdx, flag: Flag, value: bool) {
    let conditions = model.part(part).conditions().to_vec();
    let flags = model.conditions_mut().flags_mut();
    let at = |k: usize| conditions[k].index();
    write_at_ascending(flags, conditions.len(), at, |_, f| f.set(flag, value));
}

/// Robust skin detection with predefined roles: the skin conditions are all MASTER after the
/// flags of stage 0 (the skin part is the listed part); those whose nodes are all SLAVE (in
/// the `assume_master_slave` parts) become SLAVE, as stage 1 decides for the conditions it
/// generates.
pub(super) fn skin_roles(model: &mut ModelPart, setup: &SearchSetup) {
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
pub(super) fn kratos_condition_ids(model: &ModelPart, contact: PartIdx) -> BTreeMap<u32, u32> {
    let ids = model.conditions().ids();
    let contact: Vec<u32> = (model.part(contact).conditions().iter())
        .map(|c| ids[c.index()])
        .collect();
    kratos_renumbering(ids.to_vec(), &contact)
}

/// Kratos' `ALMFastInit` numbering of conditions: every condition of the model (`all`, the
/// ids of every condition, each once) gets its position in id order plus one. The result
/// holds the conditions of `contact` whose id that changes, file id → new id
/// (`SearchResult::kratos_condition_ids`).
pub fn kratos_renumbering(mut all: Vec<u32>, contact: &[u32]) -> BTreeMap<u32, u32> {
    all.par_sort_unstable();
    // Ids are unique: the position is the new id minus one (looked up in parallel).
    let renumbered: Vec<(u32, u32)> = contact
        .par_iter()
        .filter_map(|&id| {
            let at = all.binary_search(&id).ok()? as u32 + 1;
            (at != id).then_some((id, at))
        })
        .collect();
    renumbered.into_iter().collect()
}

/// The parts of a pre-existing `Contact`: every pair needs its `Contact.ContactSub<key>`, as
/// Kratos' search processes do (they fail without it).
pub(super) fn existing_contact_parts(
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
pub(super) fn emulate_python_state(
    model: &mut ModelPart,
    setup: &SearchSetup,
    variables: &[VariablePlan],
) {
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
