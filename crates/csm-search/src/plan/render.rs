//! The plan as people read it (`Display`, what `csm plan` prints) and as JSON
//! ([`Plan::to_json`], `csm plan --json`). Both come from one list of items, so they say the
//! same.

use std::fmt;

use serde_json::{Value, json};

use super::types::{
    Activation, Decision, InterfaceAction, KdQuery, NodalHSource, NormalCheck, PairPlan, Plan,
    Reason, Storage, VariablePlan,
};
use crate::setup::CheckGap;

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::ContactPartInMesh => {
                f.write_str("the mesh has a `Contact` part, which Kratos reuses")
            }
            Reason::NoContactPartInMesh => {
                f.write_str("the mesh has no `Contact` part (stage 0 sets the condition flags)")
            }
            Reason::CppSearchParameters => f.write_str(
                "cpp_search_parameters: the C++ search process runs without the Python layer",
            ),
            Reason::NoSolidElements => f.write_str("no solid elements"),
            Reason::AdaptSearchOff => f.write_str("adapt_search false"),
            Reason::TypeSearch(t) => write!(f, "type_search {}", t.name()),
            Reason::CheckGap(g) => write!(f, "check_gap {}", g.name()),
            Reason::NoBoundingBoxFactor => {
                f.write_str("bounding_box_factor ≤ 0 (the octree tests the faces themselves)")
            }
            Reason::DynamicSearchOff => f.write_str("dynamic_search false"),
            Reason::NoVelocities => f.write_str(
                "no velocities (VELOCITY and ACCELERATION are zero on every node of the pair: \
                 the predicted increment is zero)",
            ),
            Reason::SimpleActivation => {
                f.write_str("simple_search true (the Simple activation reads only NORMAL_GAP)")
            }
            Reason::NoConditionName => f.write_str("C++ parameters without a condition_name (Q18)"),
            Reason::NotRead => f.write_str("no stage of csm reads it"),
            Reason::NoSteps => f.write_str("the setup has no `steps` (one search step)"),
            Reason::NoMultiplierValues => f.write_str(
                "no solver gives the multipliers values: the activation's guesses would only \
                 read and write zeros",
            ),
            Reason::NoDynamicPair => f.write_str("no pair has dynamic_search"),
            Reason::NoAdvancedActivation => f.write_str(
                "no pair runs the Advanced activation (MappingCheck with simple_search false)",
            ),
            Reason::NoMappingCheck => f.write_str("no pair has check_gap mapping_check"),
        }
    }
}

/// How a left-out item is said: a stage is skipped, a structure not built, a variable not
/// allocated.
#[derive(Clone, Copy)]
enum Kind {
    Stage,
    Structure,
    Variable,
}

impl Kind {
    fn left_out(self) -> &'static str {
        match self {
            Kind::Stage => "skipped",
            Kind::Structure => "not built",
            Kind::Variable => "not allocated",
        }
    }
}

/// One line of the plan.
struct Item {
    /// Stable id (JSON).
    id: String,
    /// What people read.
    name: String,
    used: bool,
    /// What is done (used) or why not (left out).
    text: String,
}

fn item<T>(
    id: &str,
    name: &str,
    kind: Kind,
    decision: &Decision<T>,
    what: impl FnOnce(&T) -> String,
) -> Item {
    match decision {
        Decision::Used(t) => Item {
            id: id.to_owned(),
            name: name.to_owned(),
            used: true,
            text: what(t),
        },
        Decision::LeftOut(r) => left_out(id, name, kind, r.to_string()),
    }
}

fn used(id: &str, name: &str, text: String) -> Item {
    Item {
        id: id.to_owned(),
        name: name.to_owned(),
        used: true,
        text,
    }
}

fn left_out(id: &str, name: &str, kind: Kind, why: String) -> Item {
    Item {
        id: id.to_owned(),
        name: name.to_owned(),
        used: false,
        text: format!("{} — {why}", kind.left_out()),
    }
}

fn quoted(parts: &[String]) -> String {
    parts
        .iter()
        .map(|p| format!("`{p}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Plan {
    fn initialize_items(&self) -> Vec<Item> {
        let mut items = vec![item(
            "contact_parts",
            "contact parts and flags (stage 0)",
            Kind::Stage,
            &self.contact_parts,
            |()| {
                "`Contact` and one `Contact.ContactSub<key>` per pair; INTERFACE, MASTER, SLAVE"
                    .to_owned()
            },
        )];
        match &self.interface {
            Decision::Used(actions) => {
                for (key, path, action) in actions {
                    let name = format!("interface conditions (stage 1) of `{path}` (pair {key})");
                    items.push(match action {
                        InterfaceAction::Generate => used(
                            "interface",
                            &name,
                            "generated from the element faces (the part has no conditions)"
                                .to_owned(),
                        ),
                        InterfaceAction::CheckProperties { conditions } => left_out(
                            "interface",
                            &name,
                            Kind::Stage,
                            if *conditions == 0 {
                                "the part got its conditions for an earlier pair (properties \
                                 check only)"
                                    .to_owned()
                            } else {
                                format!(
                                    "the part has {conditions} conditions (properties check only)"
                                )
                            },
                        ),
                    });
                }
            }
            Decision::LeftOut(r) => items.push(left_out(
                "interface",
                "interface conditions (stage 1)",
                Kind::Stage,
                r.to_string(),
            )),
        }
        let normal_check = "normal check (stage 2)";
        items.push(match &self.normal_check {
            Decision::Used(NormalCheck::Full { solid_elements }) => used(
                "normal_check",
                normal_check,
                format!("both passes over {solid_elements} solid elements"),
            ),
            Decision::Used(NormalCheck::NormalsOnly) => left_out(
                "normal_check",
                normal_check,
                Kind::Stage,
                format!(
                    "{} (only the unit normals it starts with are computed, once)",
                    Reason::NoSolidElements
                ),
            ),
            Decision::LeftOut(r) => {
                left_out("normal_check", normal_check, Kind::Stage, r.to_string())
            }
        });
        items.push(item(
            "master_slave_from_nodes",
            "master/slave flags from nodes (stage 3)",
            Kind::Stage,
            &self.master_slave_from_nodes,
            |()| "condition flags from the nodal MASTER/SLAVE flags of `Contact`".to_owned(),
        ));
        items.push(used(
            "nodal_h",
            "NODAL_H",
            match self.nodal_h {
                NodalHSource::FindNodalH => "FindNodalHProcess".to_owned(),
                NodalHSource::Constant(h) => format!("the setup's nodal_h = {h} on every node"),
            },
        ));
        items.push(item(
            "adapt_search",
            "adapt_search",
            Kind::Stage,
            &self.adapt_search,
            |()| "search_factor and active_check_factor × h_max/h_min".to_owned(),
        ));
        items.push(item("steps", "steps", Kind::Stage, &self.steps, |s| {
            format!(
                "{} search steps; rigid motions of {} (DISPLACEMENT, VELOCITY, ACCELERATION \
                     follow them)",
                s.count,
                if s.moved_parts.is_empty() {
                    "no part".to_owned()
                } else {
                    quoted(&s.moved_parts)
                }
            ) + if s.refit_tree {
                "; kd-trees refitted between steps (refit_tree), not rebuilt (except for \
                 Kratos-mode DirectCheck and where a query reaches max_number_results)"
            } else {
                "; kd-trees rebuilt every step"
            }
        }));
        items
    }

    fn variable_items(&self) -> Vec<Item> {
        self.variables.iter().map(variable_item).collect()
    }

    /// The plan as JSON: `{"format": "csm-plan/1", "domain_size", "compatibility",
    /// "initialize": [item], "variables": [item], "pairs": {"<key>": {"slave_parts",
    /// "master_parts", "type_search", "check_gap", "inverted_search", "stages": [item]}}}`,
    /// where an item is `{"id", "name", "used": true, "what"}` or `{"id", "name", "used":
    /// false, "why"}`.
    pub fn to_json(&self) -> Value {
        let items = |items: Vec<Item>| -> Value {
            items
                .into_iter()
                .map(|i| {
                    let text = if i.used { "what" } else { "why" };
                    json!({"id": i.id, "name": i.name, "used": i.used, text: i.text})
                })
                .collect()
        };
        let pairs: serde_json::Map<String, Value> = self
            .pairs
            .values()
            .map(|p| {
                (
                    p.key.to_string(),
                    json!({
                        "slave_parts": p.slave_parts,
                        "master_parts": p.master_parts,
                        "type_search": p.type_search.name(),
                        "check_gap": p.check_gap.name(),
                        "inverted_search": p.inverted_search,
                        "stages": items(pair_items(p)),
                    }),
                )
            })
            .collect();
        json!({
            "format": "csm-plan/1",
            "domain_size": self.domain_size,
            "compatibility": self.compatibility.name(),
            "initialize": items(self.initialize_items()),
            "variables": items(self.variable_items()),
            "pairs": pairs,
        })
    }
}

fn variable_item(v: &VariablePlan) -> Item {
    let name = v.variable.name();
    item(name, name, Kind::Variable, &v.storage, |s| match s {
        Storage::Current => format!("current step only; read by {}", v.readers),
        Storage::WithHistory => format!("current and previous step; read by {}", v.readers),
        Storage::Plain => format!("one value per node; read by {}", v.readers),
        Storage::FromMesh => "as read from the mesh".to_owned(),
    })
}

fn pair_header(p: &PairPlan) -> String {
    let listed = if p.master_parts.is_empty() {
        // No part named: skin detection (robust mode; kratos mode refuses, as Kratos loses it).
        "the skin of the mesh (every `contact_model_part` list empty)".to_owned()
    } else {
        format!("parts {}", quoted(&p.master_parts))
    };
    let parts = if p.slave_parts.is_empty() {
        format!("{listed} (roles decided by the self-contact pre-search)")
    } else if p.master_parts.is_empty() {
        format!("slave {}, master {listed}", quoted(&p.slave_parts))
    } else {
        format!(
            "slave {}, master {}",
            quoted(&p.slave_parts),
            quoted(&p.master_parts)
        )
    };
    format!(
        "pair {}: {parts}; type_search {}, check_gap {}{}",
        p.key,
        p.type_search.name(),
        p.check_gap.name(),
        if p.inverted_search {
            ", inverted_search"
        } else {
            ""
        }
    )
}

fn pair_items(p: &PairPlan) -> Vec<Item> {
    let tree_side = if p.inverted_search {
        "slave-side"
    } else {
        "master-side"
    };
    let mut items = vec![item(
        "step_jump",
        "step jump (dynamic search)",
        Kind::Stage,
        &p.step_jump,
        |s| {
            let how = if s.moves_nodes {
                "MappingCheck searches on the moved nodes and moves them back"
            } else {
                "the query centres are shifted"
            };
            format!(
                "half-jump prediction from VELOCITY and ACCELERATION ({} moving nodes); {how}",
                s.moving_nodes
            )
        },
    )];
    items.push(used(
        "unit_normals",
        "unit normals",
        format!(
            "of the conditions and nodes of `Contact.ContactSub{}`",
            p.key
        ),
    ));
    items.push(item(
        "kd_tree",
        "kd-tree",
        Kind::Structure,
        &p.kd_tree,
        |q| {
            let query = match q {
                KdQuery::Radius => {
                    "radius query (search_factor × the slave's bounding-sphere radius)"
                }
                KdQuery::Box => "box query (search_factor × the slave's length around its box)",
            };
            format!("over the {tree_side} condition centres; {query}")
        },
    ));
    items.push(item("octree", "octree", Kind::Structure, &p.octree, |()| {
        format!("over the {tree_side} conditions, refined around their nodes")
    }));
    let mut obb = item("obb_test", "OBB test", Kind::Structure, &p.obb_test, |t| {
        format!(
            "{} between the slave's and each candidate's OBB (enlarged by bounding_box_factor × \
             max NODAL_H)",
            t.name()
        )
    });
    if !obb.used && p.kd_tree.is_used() {
        obb.text += " (each slave's OBB is still built: Kratos builds it and fails on a \
                     zero-extent box, Q12)";
    }
    items.push(obb);
    items.push(item(
        "kdop",
        "18-DOP test",
        Kind::Structure,
        &p.kdop,
        |()| "18-DOPs of the slave and of each candidate (enlarged like the OBBs)".to_owned(),
    ));
    items.push(used(
        "pairing",
        "pairing (stage 8)",
        match p.check_gap {
            CheckGap::NoCheck => "NoCheck: every candidate becomes a pair".to_owned(),
            CheckGap::DirectCheck => {
                "DirectCheck: pairs whose slave nodes project onto the master".to_owned()
            }
            CheckGap::MappingCheck => {
                "MappingCheck: candidates facing each other enter INDEX_MAP".to_owned()
            }
        },
    ));
    items.push(item(
        "mortar_mapping",
        "mortar mapping (NormalGapProcess)",
        Kind::Stage,
        &p.mortar_mapping,
        |()| "NORMAL_GAP of the slave nodes; pairs without mortar overlap are removed".to_owned(),
    ));
    items.push(item(
        "paired_conditions",
        "paired conditions",
        Kind::Stage,
        &p.paired_conditions,
        |()| "one per pair, numbered after the largest condition id".to_owned(),
    ));
    items.push(item(
        "weighted_gap",
        "weighted gap (ComputeWeightedReaction)",
        Kind::Stage,
        &p.weighted_gap,
        |()| "WEIGHTED_GAP of the slave nodes, read by the Advanced activation".to_owned(),
    ));
    let mut activation = item(
        "activation",
        "activation (stage 9)",
        Kind::Stage,
        &p.activation,
        |a| match a {
            Activation::Simple => "Simple: NORMAL_GAP against NODAL_H".to_owned(),
            Activation::Advanced {
                static_check_movement,
            } => format!(
                "Advanced: NORMAL_GAP and WEIGHTED_GAP against DISTANCE_THRESHOLD (the mean \
                 NODAL_H of the slave side) × ACTIVE_CHECK_FACTOR{}",
                if *static_check_movement {
                    ", static_check_movement"
                } else {
                    ""
                }
            ),
        },
    );
    if !activation.used {
        activation.text += " (ACTIVE comes from the pairing)";
    }
    items.push(activation);
    items
}

fn write_items(f: &mut fmt::Formatter<'_>, items: &[Item]) -> fmt::Result {
    for i in items {
        writeln!(
            f,
            "  {} {}: {}",
            if i.used { '+' } else { '-' },
            i.name,
            i.text
        )?;
    }
    Ok(())
}

/// The text `csm plan` prints: `+` for what runs (and how), `-` for what is left out (and
/// why), by section: initialize, nodal variables, then every pair.
impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "DOMAIN_SIZE {}, compatibility {}; + used, - left out",
            self.domain_size,
            self.compatibility.name()
        )?;
        writeln!(f, "initialize:")?;
        write_items(f, &self.initialize_items())?;
        writeln!(f, "nodal variables:")?;
        write_items(f, &self.variable_items())?;
        for p in self.pairs.values() {
            writeln!(f, "{}:", pair_header(p))?;
            write_items(f, &pair_items(p))?;
        }
        Ok(())
    }
}
