//! `ClearMortarConditions` and `UpdateMortarConditions` (reference §4.3, §5): one pair's
//! search step up to `CheckPairing`, and the numbering of the pairs it creates.

use super::*;

/// ClearMortarConditions (§4.3): ResetContactOperators — paired conditions that are not
/// ACTIVE are erased and their masters removed from the slave's INDEX_MAP — then the Lagrange
/// multiplier of ContactSub nodes that are not ACTIVE is zeroed. An entry without a paired
/// condition (no `condition_name`) makes Kratos fail (Q18): an error in `kratos` mode, dropped
/// in `robust` mode.
pub(super) fn clear_mortar_conditions(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    compatibility: Compatibility,
) -> Result<(), Error> {
    let inverted = pair.params.inverted_search;
    // The slave conditions with orphan entries, found in parallel and taken in condition
    // order (most steps have none: the first has empty INDEX_MAPs).
    let m = &*model;
    let with_orphans: Vec<(ConditionIdx, Vec<ConditionId>)> = m
        .part(pair.sub)
        .conditions()
        .par_iter()
        .filter(|c| m.conditions().flags()[c.index()].is(Flag::SLAVE) != inverted)
        .filter_map(|&c| {
            let mut orphans = m
                .index_map(c)
                .iter()
                .filter(|(_, paired)| paired.is_none())
                .map(|(master, _)| master)
                .peekable();
            orphans.peek()?;
            Some((c, orphans.collect()))
        })
        .collect();
    for (c, orphans) in with_orphans {
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
    let node_flags = model.nodes().flags();
    let inactive: Vec<NodeIdx> = (model.part(pair.sub).nodes().par_iter())
        .filter(|n| !node_flags[n.index()].is(Flag::ACTIVE))
        .copied()
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
pub(super) struct InitialNormals<'a> {
    pub(super) table: &'a mut Option<KeptFaceNormals>,
    /// No later pair takes them: dropped once used.
    pub(super) last_user: bool,
}

/// UpdateMortarConditions (§5) for the kd-tree path.
/// Returns the warnings of the step (e.g. faces the octree cannot test).
pub(super) fn update_mortar_conditions(
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
    // (The part's node list is read in place: no copy of it in every step.)
    pair.pruned.clear();
    let sub_nodes = model.part(sub).nodes();
    plan.step_jump = step_jump(&p, model, sub_nodes);
    let delta = if plan.step_jump.is_used() {
        let dt = model.process_info().number("DELTA_TIME").unwrap_or(1.0);
        Some(compute_step_jump(model, sub_nodes, dt))
    } else {
        None
    };
    let moved = plan.step_jump.used().is_some_and(|s| s.moves_nodes);
    if let (true, Some(d)) = (moved, &delta) {
        shift_nodes(model, sub, d, 1.0);
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
        let order = run.tuning.query_order;
        self_contact_roles(
            model,
            pair,
            &p,
            plan,
            (compatibility, order),
            delta.as_deref(),
        )?;
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
            largest_nodal_h: pair.globals.largest_nodal_h,
            ranks: pair.ranks.as_ref(),
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
        pair.used.largest_nodal_h = Some(report.hmax);
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
            (compatibility, run.keep_tree, run.tuning.query_order),
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
    let cflags = model.conditions().flags();
    let (n_slave, n_master) = (model.part(sub).conditions().par_iter())
        .map(|c| {
            let f = cflags[c.index()];
            (
                usize::from(f.is(Flag::SLAVE) != inverted),
                usize::from(f.is(Flag::MASTER) != inverted),
            )
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
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
        shift_nodes(model, sub, d, -1.0);
    }
    Ok(run_warnings)
}

/// Swaps the roles of the conditions of `sub` for an inverted octree search: SLAVE := not
/// SLAVE, MASTER := not MASTER (undefined counts as not set). Returns the original flags.
pub(super) fn swap_roles(
    model: &mut ModelPart,
    sub: PartIdx,
) -> Vec<(ConditionIdx, csm_model::Flags)> {
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
pub(super) fn finish_pairs(
    model: &mut ModelPart,
    pair: &mut PairSearch,
    mut created: Vec<(ConditionIdx, ConditionIdx)>,
    condition_id: u32,
) {
    let ids = model.conditions().ids();
    // Ids are unique: equal keys are equal pairs, so any sort gives one order.
    created.par_sort_unstable_by_key(|(s, m)| (ids[s.index()], ids[m.index()]));
    // The k-th pair is numbered `condition_id + 1 + k`.
    let id_of = |k: usize| {
        let k = u32::try_from(k).expect("paired condition ids fit u32");
        ConditionId(condition_id + 1 + k)
    };
    let masters: Vec<ConditionId> = created
        .par_iter()
        .map(|(_, m)| ConditionId(ids[m.index()]))
        .collect();
    // Each slave's pairs are consecutive (sorted by slave id): its INDEX_MAP takes them in
    // master id order, as one pass over the pairs would give them; slaves in parallel.
    update_index_maps(
        model,
        &created,
        |&(s, _)| s,
        |map, first, group| {
            for (k, _) in (first..).zip(group) {
                map.set_new_entity_id(masters[k], id_of(k));
            }
        },
    );
    pair.paired.reserve(created.len());
    pair.paired.par_extend(
        created
            .par_iter()
            .enumerate()
            .map(|(k, &(s, m))| PairedCondition {
                id: id_of(k),
                slave: s,
                master: m,
                active: true,
                isolated: false,
            }),
    );
}
