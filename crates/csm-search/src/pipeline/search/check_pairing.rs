//! `CheckPairing` of MappingCheck (reference §10.1): the mortar mapping, the paired
//! conditions, the weighted gap and the activation.

use super::*;

/// Entries from which the lists after the mapping are built in parallel passes.
const PARALLEL_FROM: usize = 1 << 14;

/// What [`check_pairing`] works with besides the model, the pair and the run mode.
pub(super) struct PairingStep<'a> {
    pub(super) params: &'a SearchParameters,
    pub(super) plan: &'a PairPlan,
    /// The dynamic shift to undo after the mapping, if the nodes were moved.
    pub(super) restore: Option<&'a [Vector]>,
    /// The unit normals of the sub's faces on the current coordinates (the step's
    /// [`compute_unit_normals`], kept), which the mapping's mean normals take instead of
    /// computing them.
    pub(super) face_normals: Option<KeptFaceNormals>,
    /// The id after which paired conditions are numbered.
    pub(super) condition_id: u32,
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
pub(super) fn check_pairing(
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
    let activation_error = |e: act::Error| Error::from(ErrorKind::Activation(e));
    let mode = match compatibility {
        Compatibility::Kratos => act::MortarMode::Kratos,
        Compatibility::Robust => act::MortarMode::Robust,
    };
    if !p.simple_search {
        let h = match (pair.globals.mean_nodal_h, &pair.ranks) {
            (Some(h), _) => h,
            (None, Some(ranks)) => {
                act::mean_h_shared(model, sub, inverted, ranks).map_err(activation_error)?
            }
            (None, None) => act::mean_h(model, sub, inverted),
        };
        pair.used.mean_nodal_h = Some(h);
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
        tuning: run.tuning.mapping,
        ranks: pair.ranks.clone(),
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
    // The slaves' masters are final now (what follows changes the INDEX_MAPs' paired ids,
    // not their keys): their map, for the step's result.
    pair.step_pairs = Some(super::outcome::slave_map(model, sub, inverted));
    crate::trace::mark("result entries");
    let mapping_warnings = report.warnings(mode);
    let ids = model.conditions().ids();
    // (In parallel where they are many: a parallel pass costs more than a few entries.)
    let many = report.removed.len() >= PARALLEL_FROM;
    let pruned = |r: &act::RemovedEntry| (ids[r.slave.index()], r.master.get());
    pair.pruned = if many {
        report.removed.par_iter().map(pruned).collect()
    } else {
        report.removed.iter().map(pruned).collect()
    };
    // TO_ERASE: the paired conditions of removed entries (kept from an earlier step) go.
    let to_erase = |r: &act::RemovedEntry| r.paired.is_some();
    let any_to_erase = if many {
        report.removed.par_iter().any(to_erase)
    } else {
        report.removed.iter().any(to_erase)
    };
    if any_to_erase {
        let erased: BTreeSet<u32> = report
            .removed
            .iter()
            .filter_map(|r| r.paired.map(ConditionId::get))
            .collect();
        pair.paired.retain(|pc| !erased.contains(&pc.id.get()));
    }
    if let Some(d) = restore {
        shift_nodes(model, sub, d, -1.0);
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
    crate::trace::mark("unit normals after mapping");
    // CreateAuxiliaryConditions: slave side, entries without a paired condition.
    if p.create_auxiliar_conditions {
        // The entries are gathered in parallel, in the part's order: `finish_pairs`
        // sorts them by slave and master id.
        let m = &*model;
        let created: Vec<(ConditionIdx, ConditionIdx)> = (m.part(sub).conditions())
            .par_iter()
            .copied()
            .filter(|s| m.conditions().flags()[s.index()].is(Flag::SLAVE) != inverted)
            .flat_map_iter(|s| {
                m.index_map(s).iter().filter_map(move |(master, paired)| {
                    let found = m.conditions().index_of(master.get());
                    found
                        .filter(|_| paired.is_none())
                        .map(|mi| (s, ConditionIdx(mi as u32)))
                })
            })
            .collect();
        finish_pairs(model, pair, created, condition_id);
    }
    crate::trace::mark("auxiliary conditions");
    // ComputeWeightedReaction: only the Advanced activation reads WEIGHTED_GAP.
    if plan.weighted_gap.is_used() {
        let many = pair.paired.len() >= PARALLEL_FROM;
        let of = |pc: &PairedCondition| (pc.slave, pc.master);
        let paired: Vec<_> = if many {
            pair.paired.par_iter().map(of).collect()
        } else {
            pair.paired.iter().map(of).collect()
        };
        let isolated = act::compute_weighted_gap(
            model,
            sub,
            &paired,
            (mode, distance_threshold),
            dim,
            known_gaps,
        )
        .map_err(activation_error)?;
        let set = |(pc, isolated): (&mut PairedCondition, bool)| pc.isolated = isolated;
        if many {
            pair.paired.par_iter_mut().zip(isolated).for_each(set);
        } else {
            pair.paired.iter_mut().zip(isolated).for_each(set);
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
