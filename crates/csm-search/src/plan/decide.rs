//! [`Plan::new`]: the decisions, from the model as read and the setup.

use std::collections::{BTreeMap, BTreeSet};

use csm_geometry::math::Vector;
use csm_model::{ModelPart, NodeIdx, ScalarVar, VectorVar};

use super::types::{
    Activation, Decision, InterfaceAction, KdQuery, NodalHSource, NodalVariable, NormalCheck,
    PairPlan, Plan, Reason, StepJump, StepsPlan, Storage, VariablePlan,
};
use crate::error::{Error, ErrorKind};
use crate::setup::{CheckGap, ContactType, ObbIntersectionType, SearchParameters, SearchSetup};
use crate::setup::{PairSetup, SearchTreeType};
use crate::stages::{count_solid_elements, user_part};

impl Plan {
    /// The plan of a search of `model` (as read, before [`crate::ContactSearch::initialize`])
    /// with `setup`. Errors as `initialize` errs on the part names: a part of the setup that
    /// the mesh lacks, or a `Contact` part without the pair's `ContactSub<key>`; they point at
    /// the setup file's line.
    pub fn new(model: &ModelPart, setup: &SearchSetup) -> Result<Plan, Error> {
        Plan::decide(model, setup).map_err(|e| crate::pipeline::locate(e, setup))
    }

    /// [`Plan::new`] without locating errors (the pipeline locates them itself).
    pub(crate) fn decide(model: &ModelPart, setup: &SearchSetup) -> Result<Plan, Error> {
        let existing = model.find_part("Contact").is_some();
        let python_path = !setup.cpp_search_parameters;
        // The nodes of every pair, as its `Contact.ContactSub<key>` will hold them.
        let mut pair_nodes = BTreeMap::new();
        for (&key, pair) in &setup.pairs {
            // Sorted and deduplicated at the end (no tree insertion per node).
            let mut nodes: Vec<NodeIdx> = Vec::new();
            if existing {
                let sub = model
                    .find_part(&contact_sub_path(key))
                    .ok_or_else(|| missing_contact_sub(key))?;
                nodes.extend_from_slice(model.part(sub).nodes());
            } else {
                for path in pair.parts.iter().chain(&pair.slaves) {
                    user_part(model, path, key)?;
                }
                for path in &pair.parts {
                    let part = user_part(model, path, key)?;
                    nodes.extend_from_slice(model.part(part).nodes());
                }
            }
            nodes.sort_unstable();
            nodes.dedup();
            pair_nodes.insert(key, nodes);
        }

        let contact_parts = if existing {
            Decision::LeftOut(Reason::ContactPartInMesh)
        } else {
            Decision::Used(())
        };
        let interface = if existing {
            Decision::LeftOut(Reason::ContactPartInMesh)
        } else {
            let actions = interface_actions(model, setup, python_path)?;
            if !python_path && actions.is_empty() {
                Decision::LeftOut(Reason::CppSearchParameters)
            } else {
                Decision::Used(actions)
            }
        };
        let normal_check = if !python_path {
            Decision::LeftOut(Reason::CppSearchParameters)
        } else {
            match count_solid_elements(model) {
                0 => Decision::Used(NormalCheck::NormalsOnly),
                n => Decision::Used(NormalCheck::Full { solid_elements: n }),
            }
        };
        let master_slave_from_nodes = if existing {
            Decision::Used(())
        } else {
            Decision::LeftOut(Reason::NoContactPartInMesh)
        };
        let adapt_search = if setup.adapt_search {
            Decision::Used(())
        } else {
            Decision::LeftOut(Reason::AdaptSearchOff)
        };
        let domain_size = setup
            .process_info
            .get("DOMAIN_SIZE")
            .copied()
            .or_else(|| model.process_info().number("DOMAIN_SIZE"))
            .unwrap_or(3.0) as u32;
        let pairs: BTreeMap<u32, PairPlan> = setup
            .pairs
            .iter()
            .map(|(&key, pair)| (key, pair_plan(model, key, pair, &pair_nodes[&key])))
            .collect();
        Ok(Plan {
            domain_size,
            compatibility: setup.compatibility,
            contact_parts,
            interface,
            normal_check,
            master_slave_from_nodes,
            nodal_h: setup
                .nodal_h
                .map_or(NodalHSource::FindNodalH, NodalHSource::Constant),
            adapt_search,
            steps: if setup.steps.is_empty() {
                Decision::LeftOut(Reason::NoSteps)
            } else {
                let moved: BTreeSet<String> = setup
                    .steps
                    .iter()
                    .flat_map(|s| s.moves.iter().map(|m| m.part.clone()))
                    .collect();
                Decision::Used(StepsPlan {
                    count: setup.steps.len(),
                    moved_parts: moved.into_iter().collect(),
                    refit_tree: setup.refit_tree && setup.steps.len() > 1,
                })
            },
            variables: variables(model, setup),
            pairs,
        })
    }
}

/// `Contact.ContactSub<key>`.
pub(crate) fn contact_sub_path(key: u32) -> String {
    format!("Contact.ContactSub{key}")
}

/// The error of a mesh whose `Contact` part lacks the pair's sub part (Kratos' search
/// processes fail without it).
pub(crate) fn missing_contact_sub(key: u32) -> Error {
    let path = contact_sub_path(key);
    ErrorKind::RejectedByKratos(format!(
        "the mesh has a `Contact` part but no `{path}`: Kratos reuses an existing `Contact` and \
         its search process fails without the pair's sub part"
    ))
    .into()
}

/// Stage 1 in the pipeline's order: every part of every pair; a part generated for an
/// earlier pair has conditions by then. On the C++ path (`python_path` false) only parts that
/// list nodes only get conditions, as Kratos' tests that drive the C++ process do before
/// building it (test_dynamic_search.py, reference §20.2); parts with conditions are used as
/// they are and not listed.
fn interface_actions(
    model: &ModelPart,
    setup: &SearchSetup,
    python_path: bool,
) -> Result<Vec<(u32, String, InterfaceAction)>, Error> {
    let mut generated = BTreeSet::new();
    let mut actions = Vec::new();
    for (&key, pair) in &setup.pairs {
        for path in &pair.parts {
            let part = user_part(model, path, key)?;
            let conditions = model.part(part).conditions().len();
            if !python_path && conditions > 0 {
                continue;
            }
            let action = if conditions == 0 && generated.insert(part) {
                InterfaceAction::Generate
            } else {
                InterfaceAction::CheckProperties { conditions }
            };
            actions.push((key, path.clone(), action));
        }
    }
    Ok(actions)
}

/// The step jump of the dynamic search for a pair whose `Contact.ContactSub<key>` holds
/// `nodes`: it runs when `dynamic_search` is on and some node has a non-zero VELOCITY (this
/// step or the previous one) or previous ACCELERATION, the only values Kratos'
/// `ComputeStepJump` reads. Otherwise the predicted increment is zero on every node: the
/// prediction would move nothing, so it is left out.
pub fn step_jump(
    params: &SearchParameters,
    model: &ModelPart,
    nodes: &[NodeIdx],
) -> Decision<StepJump> {
    if !params.dynamic_search {
        return Decision::LeftOut(Reason::DynamicSearchOff);
    }
    let data = model.nodal_data();
    let columns: Vec<&[Vector]> = [
        data.vector(VectorVar::Velocity, 0),
        data.vector(VectorVar::Velocity, 1),
        data.vector(VectorVar::Acceleration, 1),
    ]
    .into_iter()
    .flatten()
    .collect();
    let zero = Vector::zeros();
    let moving_nodes = nodes
        .iter()
        .filter(|n| {
            columns
                .iter()
                .any(|c| c.get(n.index()).is_some_and(|v| *v != zero))
        })
        .count();
    if moving_nodes == 0 {
        return Decision::LeftOut(Reason::NoVelocities);
    }
    Decision::Used(StepJump {
        moving_nodes,
        moves_nodes: params.check_gap == CheckGap::MappingCheck,
    })
}

pub(crate) fn pair_plan(
    model: &ModelPart,
    key: u32,
    pair: &PairSetup,
    nodes: &[NodeIdx],
) -> PairPlan {
    let p = &pair.search;
    let t = p.type_search;
    let gap = p.check_gap;
    let kd_tree = match t {
        SearchTreeType::OctreeWithObb => Decision::LeftOut(Reason::TypeSearch(t)),
        SearchTreeType::KdtreeInBox | SearchTreeType::KdtreeInBoxWithObb => {
            Decision::Used(KdQuery::Box)
        }
        SearchTreeType::KdtreeInRadius
        | SearchTreeType::KdtreeInRadiusWithObb
        | SearchTreeType::Kdop => Decision::Used(KdQuery::Radius),
    };
    let octree = match t {
        SearchTreeType::OctreeWithObb => Decision::Used(()),
        _ => Decision::LeftOut(Reason::TypeSearch(t)),
    };
    let obb_test = match t {
        // The kd-tree path always tests with SAT.
        SearchTreeType::KdtreeInRadiusWithObb | SearchTreeType::KdtreeInBoxWithObb => {
            Decision::Used(ObbIntersectionType::SeparatingAxisTheorem)
        }
        SearchTreeType::OctreeWithObb if p.octree.bounding_box_factor > 0.0 => {
            Decision::Used(p.octree.obb_intersection_type)
        }
        SearchTreeType::OctreeWithObb => Decision::LeftOut(Reason::NoBoundingBoxFactor),
        SearchTreeType::KdtreeInRadius | SearchTreeType::KdtreeInBox | SearchTreeType::Kdop => {
            Decision::LeftOut(Reason::TypeSearch(t))
        }
    };
    let kdop = match t {
        SearchTreeType::Kdop => Decision::Used(()),
        _ => Decision::LeftOut(Reason::TypeSearch(t)),
    };
    let mapping = gap == CheckGap::MappingCheck;
    let by_gap = |used: bool| {
        if used {
            Decision::Used(())
        } else {
            Decision::LeftOut(Reason::CheckGap(gap))
        }
    };
    let weighted_gap = match (mapping, p.simple_search) {
        (true, false) => Decision::Used(()),
        (true, true) => Decision::LeftOut(Reason::SimpleActivation),
        (false, _) => Decision::LeftOut(Reason::CheckGap(gap)),
    };
    let activation = match (mapping, p.simple_search) {
        (true, true) => Decision::Used(Activation::Simple),
        (true, false) => Decision::Used(Activation::Advanced {
            static_check_movement: p.static_check_movement,
        }),
        (false, _) => Decision::LeftOut(Reason::CheckGap(gap)),
    };
    let paired_conditions = if p.create_auxiliar_conditions {
        Decision::Used(())
    } else {
        Decision::LeftOut(Reason::NoConditionName)
    };
    PairPlan {
        key,
        slave_parts: pair.slaves.clone(),
        master_parts: pair
            .parts
            .iter()
            .filter(|path| !pair.slaves.contains(path))
            .cloned()
            .collect(),
        type_search: t,
        check_gap: gap,
        inverted_search: p.inverted_search,
        step_jump: step_jump(p, model, nodes),
        kd_tree,
        octree,
        obb_test,
        kdop,
        mortar_mapping: by_gap(mapping),
        paired_conditions,
        weighted_gap,
        activation,
    }
}

/// The nodal variables of the emulated Python state (DESIGN.md §2), each allocated only when
/// a stage reads it, and with its history only when a stage reads the previous step.
fn variables(model: &ModelPart, setup: &SearchSetup) -> Vec<VariablePlan> {
    let data = model.nodal_data();
    let params = || setup.pairs.values().map(|p| &p.search);
    let dynamic = params().any(|p| p.dynamic_search);
    // The steps' rigid motions write DISPLACEMENT, VELOCITY and ACCELERATION (with history)
    // when they are applied (`ModelPart::prescribe_motion`).
    let moving = !setup.steps.is_empty();
    let advanced = params().any(|p| p.check_gap == CheckGap::MappingCheck && !p.simple_search);
    let wg_history = params().any(|p| {
        p.check_gap == CheckGap::MappingCheck && !p.simple_search && p.static_check_movement
    });
    let mapping = params().any(|p| p.check_gap == CheckGap::MappingCheck);
    let in_mesh = |v: NodalVariable| match v {
        NodalVariable::Scalar(s) => data.has_scalar(s),
        NodalVariable::Vector(v) => data.has_vector(v),
    };
    let when = |cond: bool, storage: Storage, reason: Reason| {
        if cond {
            Decision::Used(storage)
        } else {
            Decision::LeftOut(reason)
        }
    };
    let multiplier = match setup.contact_type {
        ContactType::Frictionless => {
            NodalVariable::Scalar(ScalarVar::LagrangeMultiplierContactPressure)
        }
        _ => NodalVariable::Vector(VectorVar::VectorLagrangeMultiplier),
    };
    let wg_storage = if wg_history {
        Storage::WithHistory
    } else {
        Storage::Current
    };
    let table = [
        (
            NodalVariable::Vector(VectorVar::Displacement),
            when(moving, Storage::WithHistory, Reason::NotRead),
            "no stage; the rigid motions of the setup's `steps` write it",
        ),
        (
            NodalVariable::Vector(VectorVar::Velocity),
            when(
                dynamic || moving,
                Storage::WithHistory,
                Reason::NoDynamicPair,
            ),
            if dynamic {
                "the step jump (this step and the previous one)"
            } else {
                "no stage; the rigid motions of the setup's `steps` write it"
            },
        ),
        (
            NodalVariable::Vector(VectorVar::Acceleration),
            when(
                dynamic || moving,
                Storage::WithHistory,
                Reason::NoDynamicPair,
            ),
            if dynamic {
                "the step jump (the previous step)"
            } else {
                "no stage; the rigid motions of the setup's `steps` write it"
            },
        ),
        (
            NodalVariable::Vector(VectorVar::Normal),
            Decision::Used(Storage::Current),
            "the normal check, the box query, the mapping (its history: nothing)",
        ),
        (
            NodalVariable::Scalar(ScalarVar::NodalH),
            Decision::Used(Storage::Current),
            "the OBB enlargement, DirectCheck, the activation (its history: nothing)",
        ),
        (
            NodalVariable::Scalar(ScalarVar::WeightedGap),
            when(advanced, wg_storage, Reason::NoAdvancedActivation),
            if wg_history {
                "the Advanced activation (the previous step: static_check_movement)"
            } else {
                "the Advanced activation (its history: nothing, no static_check_movement)"
            },
        ),
        (
            multiplier,
            Decision::LeftOut(Reason::NoMultiplierValues),
            "",
        ),
        (
            NodalVariable::Scalar(ScalarVar::NormalGap),
            when(mapping, Storage::Plain, Reason::NoMappingCheck),
            "the mortar mapping and the activation",
        ),
    ];
    table
        .into_iter()
        .map(|(variable, storage, readers)| VariablePlan {
            variable,
            storage: if in_mesh(variable) {
                Decision::Used(Storage::FromMesh)
            } else {
                storage
            },
            readers,
        })
        .collect()
}
