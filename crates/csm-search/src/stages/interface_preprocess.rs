//! Stage 1: interface conditions generated from element faces when a contact part has only
//! nodes (Kratos `InterfacePreprocessCondition::GenerateInterfacePart`, reference §13).
//!
//! When the part already has conditions only the properties check runs
//! (`CheckAndCreateProperties`). Otherwise, in order:
//! 1. `ReorderConditions`: the root conditions are numbered 1..N in container order
//!    ([`Compatibility::Kratos`]; see "Robust mode" below);
//! 2. properties: with `contact_property_id == 0` every root properties block is renumbered
//!    1..P (ascending old id) and gets a copy with id `P + k + 1` (k = 1..P, so `P + 1` is
//!    never used) holding `FRICTION_COEFFICIENT` and `THICKNESS` when present and
//!    `YOUNG_MODULUS` (0 when missing); otherwise Kratos creates the property
//!    `contact_property_id` once per element, which fails on the second element ("Property #id
//!    already existing", observed with Kratos 10.4.4);
//! 3. every root element in container order gives candidate faces: a solid its boundary
//!    entities in Kratos' order ([`GeometryKind::faces`]), a membrane/shell its own geometry; a
//!    face is accepted iff all its nodes are in the part and have `INTERFACE` defined and true.
//!    A face shared by two solids is generated twice (Q29);
//! 4. the condition kind follows the node count (2D: `LineCondition2D2N`/`2D3N`; 3D:
//!    `SurfaceCondition3D3N`/`3D4N`/`3D6N`/`3D8N`/`3D9N`); with `simplify_geometry` faces are
//!    split into 2-node lines or 3-node triangles;
//! 5. ids N+1, N+2, … in creation order; each condition is added to the root and to the part;
//!    SLAVE := true when all its nodes are SLAVE, else MASTER := true. Kratos leaves the other
//!    flag undefined (observed with Kratos 10.4.4).
//!
//! # Robust mode ([`Compatibility::Robust`])
//! * Existing condition and properties ids are kept (no renumbering); new conditions get ids
//!   above the largest existing one and property copies ids above the largest existing
//!   properties id.
//! * A face shared by two solids is generated once (the first time it is met).
//! * `simplify_geometry` splits quadratic faces with Kratos' corner-first numbering
//!   (Line2D3 `(0,2),(2,1)`; Triangle3D6 `(0,3,5),(3,1,4),(5,4,2),(3,4,5)`; Quadrilateral3D8
//!   corner triangles `(0,4,7),(4,1,5),(5,2,6),(6,3,7)` plus `(4,5,6),(6,7,4)`;
//!   Quadrilateral3D9 eight triangles around the centre node 8). Kratos' tables assume
//!   perimeter numbering (Q29) and give overlapping or missing triangles.
//! * A fixed `contact_property_id` is created once (or reused when it exists).
//! * The flag that is not set (MASTER for a slave condition, SLAVE for a master one) is set
//!   false instead of being left undefined.

use std::collections::HashSet;

use csm_geometry::GeometryKind;
use csm_model::{
    ConditionId, ConditionIdx, ElementId, Flag, ModelPart, NodeId, NodeIdx, PartIdx, Properties,
    PropertiesId, PropertyValue,
};

use rayon::prelude::*;

use crate::error::{Error, ErrorKind};
use crate::setup::Compatibility;

/// Settings of [`generate_interface_conditions`] (the `Parameters` of Kratos'
/// `GenerateInterfacePart`; defaults `{"simplify_geometry": false, "contact_property_id": 0}`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct InterfaceSettings {
    /// Split faces into linear lines/triangles (`simplify_geometry`).
    pub simplify_geometry: bool,
    /// Properties id of the new conditions; 0 = a contact copy of each element properties
    /// block (`contact_property_id`).
    pub contact_property_id: u32,
    /// Kratos' behaviour or the documented fixes (module docs).
    pub compatibility: Compatibility,
}

/// One condition created by [`generate_interface_conditions`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedCondition {
    /// External id.
    pub id: ConditionId,
    /// Dense index in the model.
    pub idx: ConditionIdx,
    /// Kratos' condition name (`SurfaceCondition3D4N`, …).
    pub name: &'static str,
    /// Geometry kind.
    pub kind: GeometryKind,
    /// Node ids, in condition order.
    pub nodes: Vec<NodeId>,
    /// True for a slave condition (all nodes SLAVE), false for a master one.
    pub slave: bool,
    /// Properties id.
    pub properties: PropertiesId,
    /// The element whose face (or own geometry) it was made from.
    pub element: ElementId,
}

/// What [`generate_interface_conditions`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct InterfaceReport {
    /// The part already had conditions: only the properties check ran.
    pub used_existing_conditions: bool,
    /// The created conditions, in creation order.
    pub created: Vec<GeneratedCondition>,
    /// Properties blocks renumbered as `(old, new)` (Kratos mode, `contact_property_id` 0);
    /// element and condition references were updated, other holders of old ids (e.g. the
    /// pair properties of stage 0) must be remapped by the caller.
    pub renumbered_properties: Vec<(PropertiesId, PropertiesId)>,
    /// Properties blocks created, in creation order.
    pub created_properties: Vec<PropertiesId>,
    /// Faces skipped because they were already generated (robust mode only).
    pub skipped_duplicates: usize,
}

/// Stage 1: creates the interface conditions of `part` from the faces of the root elements
/// (Kratos `GenerateInterfacePart`; module docs).
///
/// Errors: the part has neither nodes nor conditions, or no condition results (Kratos' errors
/// too); Kratos mode with a fixed `contact_property_id` and two or more elements (Kratos fails
/// on the second element; the conditions of the first stay in the model, as in Kratos). In
/// Kratos mode the root conditions are first renumbered `1..N` in id order (ReorderConditions).
pub fn generate_interface_conditions(
    model: &mut ModelPart,
    part: PartIdx,
    settings: &InterfaceSettings,
) -> Result<InterfaceReport, Error> {
    let mut report = InterfaceReport::default();
    let n_part_nodes = model.part(part).nodes().len();
    if !model.part(part).conditions().is_empty() {
        report.used_existing_conditions = true;
        check_and_create_properties(model, part, &mut report)?;
        if n_part_nodes == 0 {
            return Err(no_nodes_error());
        }
        return Ok(report);
    }
    if n_part_nodes == 0 {
        return Err(ErrorKind::Model(
            "Nor conditions or nodes on the interface. Check your flags".into(),
        )
        .into());
    }
    let kratos = settings.compatibility == Compatibility::Kratos;
    let mut next_id = if kratos {
        reorder_conditions(model)?
    } else {
        model.conditions().max_id()
    };
    let copies = if settings.contact_property_id == 0 {
        Some(create_contact_properties(model, kratos, &mut report)?)
    } else {
        None
    };
    let mut in_part = vec![false; model.nodes().len()];
    for n in model.part(part).nodes() {
        in_part[n.index()] = true;
    }
    let mut seen: HashSet<Vec<NodeIdx>> = HashSet::new();
    let mut fixed_created = false;
    for e in model.elements().id_order().iter() {
        let properties = match &copies {
            Some(copies) => {
                let own = model.elements().properties(e);
                copies
                    .iter()
                    .find(|(old, _)| *old == own)
                    .map(|&(_, new)| new)
                    .ok_or_else(|| {
                        Error::from(ErrorKind::Model(format!(
                            "element {} refers to properties {own}, which do not exist",
                            model.elements().ids()[e]
                        )))
                    })?
            }
            None => fixed_property(
                model,
                settings.contact_property_id,
                kratos,
                &mut fixed_created,
                &mut report,
            )?,
        };
        let kind = model.elements().kind(e);
        let element_nodes = model.elements().nodes(e).to_vec();
        let faces: Vec<(GeometryKind, Vec<NodeIdx>)> = if kind.is_solid() {
            kind.faces()
                .iter()
                .map(|(fk, local)| (*fk, local.iter().map(|&l| element_nodes[l]).collect()))
                .collect()
        } else {
            vec![(kind, element_nodes.clone())]
        };
        let two_d = kind.working_dim() == 2;
        for (face_kind, face_nodes) in faces {
            let flags = model.nodes().flags();
            let accepted = face_nodes
                .iter()
                .all(|n| in_part[n.index()] && flags[n.index()].is(Flag::INTERFACE));
            if !accepted {
                continue;
            }
            if !kratos {
                let mut key = face_nodes.clone();
                key.sort_unstable();
                if !seen.insert(key) {
                    report.skipped_duplicates += 1;
                    continue;
                }
            }
            let pieces = split_face(face_kind, two_d, settings, &face_nodes)?;
            for (piece_kind, name, nodes) in pieces {
                next_id += 1;
                let created = create_condition(
                    model,
                    part,
                    ConditionId(next_id),
                    piece_kind,
                    name,
                    &nodes,
                    properties,
                    ElementId(model.elements().ids()[e]),
                    kratos,
                )?;
                report.created.push(created);
            }
        }
    }
    if report.created.is_empty() {
        return Err(ErrorKind::Model(
            "No interface conditions found. Please check that nodes on both sides of the \
             interface have been assigned Is(INTERFACE) = true and that the contact surfaces \
             have been assigned conditions."
                .into(),
        )
        .into());
    }
    Ok(report)
}

fn no_nodes_error() -> Error {
    ErrorKind::Model(
        "No interface nodes found. Please check that nodes on both sides of the interface have \
         been assigned Is(INTERFACE) = true."
            .into(),
    )
    .into()
}

/// Kratos `ReorderConditions`: the root conditions are renumbered 1..N in container order
/// (ascending id); returns N. INDEX_MAPs are keyed by id, so this runs before any search.
fn reorder_conditions(model: &mut ModelPart) -> Result<u32, Error> {
    let ids = model.conditions().ids();
    let mut order: Vec<usize> = (0..ids.len()).collect();
    order.sort_by_key(|&i| ids[i]);
    let mut new_ids = vec![0u32; ids.len()];
    for (rank, &i) in order.iter().enumerate() {
        new_ids[i] = rank as u32 + 1;
    }
    if !model.conditions_mut().set_ids(&new_ids) {
        return Err(ErrorKind::Model("renumbering the conditions 1..N failed".into()).into());
    }
    Ok(new_ids.len() as u32)
}

/// The values Kratos copies into a contact properties block (`CopyProperties`).
fn contact_copy(original: Option<&Properties>, id: PropertiesId) -> Properties {
    let mut copy = Properties::new(id);
    if let Some(original) = original {
        for name in ["FRICTION_COEFFICIENT", "THICKNESS"] {
            if let Some(v) = original.values.get(name) {
                copy.values.insert(name.to_owned(), v.clone());
            }
        }
    }
    let young = original
        .and_then(|p| p.values.get("YOUNG_MODULUS").cloned())
        .unwrap_or(PropertyValue::Number(0.0));
    copy.values.insert("YOUNG_MODULUS".to_owned(), young);
    copy
}

/// Kratos `CreateNewProperties` (renumbering in Kratos mode); returns (element properties id
/// after renumbering, copy id) pairs.
fn create_contact_properties(
    model: &mut ModelPart,
    kratos: bool,
    report: &mut InterfaceReport,
) -> Result<Vec<(PropertiesId, PropertiesId)>, Error> {
    let old_ids: Vec<PropertiesId> = model.properties().keys().copied().collect();
    let n = old_ids.len() as u32;
    let base = if kratos {
        let renumbered: Vec<(PropertiesId, PropertiesId)> = old_ids
            .iter()
            .enumerate()
            .map(|(k, &old)| (old, PropertiesId(k as u32 + 1)))
            .collect();
        if renumbered.iter().any(|(old, new)| old != new) {
            renumber_properties(model, &renumbered);
            report.renumbered_properties = renumbered.into_iter().filter(|(o, n)| o != n).collect();
        }
        // Kratos: `number_properties + count + 1` with count starting at 1.
        n + 1
    } else {
        model.properties().keys().next_back().map_or(0, |id| id.0)
    };
    let current: Vec<PropertiesId> = model.properties().keys().copied().collect();
    let mut copies = Vec::with_capacity(current.len());
    for (k, &id) in current.iter().enumerate() {
        let copy_id = PropertiesId(base + k as u32 + 1);
        let copy = contact_copy(model.properties().get(&id), copy_id);
        model
            .add_properties(copy)
            .map_err(|e| Error::from(ErrorKind::RejectedByKratos(e.to_string())))?;
        report.created_properties.push(copy_id);
        copies.push((id, copy_id));
    }
    Ok(copies)
}

fn renumber_properties(model: &mut ModelPart, map: &[(PropertiesId, PropertiesId)]) {
    let lookup = |id: PropertiesId| map.iter().find(|(o, _)| *o == id).map_or(id, |&(_, n)| n);
    let old = std::mem::take(model.properties_mut());
    for (id, mut p) in old {
        p.id = lookup(id);
        model.properties_mut().insert(p.id, p);
    }
    for i in 0..model.elements().len() {
        let id = lookup(model.elements().properties(i));
        model.elements_mut().set_properties(i, id);
    }
    for i in 0..model.conditions().len() {
        let id = lookup(model.conditions().properties(i));
        model.conditions_mut().set_properties(i, id);
    }
}

/// `contact_property_id != 0`: Kratos calls `CreateNewProperties(id)` per element, which fails
/// when the id exists (so from the second element on); robust mode creates it once.
fn fixed_property(
    model: &mut ModelPart,
    id: u32,
    kratos: bool,
    created: &mut bool,
    report: &mut InterfaceReport,
) -> Result<PropertiesId, Error> {
    let id = PropertiesId(id);
    if model.properties().contains_key(&id) {
        if kratos {
            return Err(ErrorKind::RejectedByKratos(format!(
                "Property #{id} already existing. Please use pGetProperties() instead \
                 (Kratos creates contact_property_id once per element)"
            ))
            .into());
        }
        return Ok(id);
    }
    model.ensure_properties(id);
    if !*created {
        report.created_properties.push(id);
        *created = true;
    }
    Ok(id)
}

/// Local node indices of the pieces a face is split into.
type Split = &'static [&'static [usize]];

const KRATOS_LINE3: Split = &[&[0, 1], &[1, 2]];
const ROBUST_LINE3: Split = &[&[0, 2], &[2, 1]];
const QUAD4: Split = &[&[0, 1, 2], &[2, 3, 0]];
const KRATOS_TRI6: Split = &[&[0, 1, 5], &[1, 2, 3], &[1, 3, 5], &[3, 4, 5]];
const ROBUST_TRI6: Split = &[&[0, 3, 5], &[3, 1, 4], &[5, 4, 2], &[3, 4, 5]];
const KRATOS_QUAD8: Split = &[
    &[0, 1, 7],
    &[1, 5, 7],
    &[1, 3, 5],
    &[1, 2, 3],
    &[3, 4, 5],
    &[5, 6, 7],
];
const ROBUST_QUAD8: Split = &[
    &[0, 4, 7],
    &[4, 1, 5],
    &[5, 2, 6],
    &[6, 3, 7],
    &[4, 5, 6],
    &[6, 7, 4],
];
const KRATOS_QUAD9: Split = &[
    &[0, 1, 8],
    &[1, 2, 3],
    &[1, 3, 8],
    &[8, 3, 4],
    &[8, 4, 5],
    &[5, 6, 7],
    &[5, 7, 8],
    &[0, 8, 7],
];
const ROBUST_QUAD9: Split = &[
    &[0, 4, 8],
    &[4, 1, 8],
    &[1, 5, 8],
    &[5, 2, 8],
    &[2, 6, 8],
    &[6, 3, 8],
    &[3, 7, 8],
    &[7, 0, 8],
];

/// The split table `simplify_geometry` uses for a face of `n` nodes, or `None` when the face
/// is kept whole (reference §13; Kratos' tables in Kratos mode, corner-first ones in robust
/// mode).
pub fn simplify_split(
    n_nodes: usize,
    two_d: bool,
    compatibility: Compatibility,
) -> Option<&'static [&'static [usize]]> {
    let kratos = compatibility == Compatibility::Kratos;
    match (two_d, n_nodes) {
        (true, 3) => Some(if kratos { KRATOS_LINE3 } else { ROBUST_LINE3 }),
        (false, 4) => Some(QUAD4),
        (false, 6) => Some(if kratos { KRATOS_TRI6 } else { ROBUST_TRI6 }),
        (false, 8) => Some(if kratos { KRATOS_QUAD8 } else { ROBUST_QUAD8 }),
        (false, 9) => Some(if kratos { KRATOS_QUAD9 } else { ROBUST_QUAD9 }),
        _ => None,
    }
}

/// Kratos' condition name for a face of `n_nodes` nodes (not simplified).
pub fn interface_condition_name(n_nodes: usize, two_d: bool) -> &'static str {
    match (two_d, n_nodes) {
        (true, 2) => "LineCondition2D2N",
        (true, _) => "LineCondition2D3N",
        (false, 3) => "SurfaceCondition3D3N",
        (false, 4) => "SurfaceCondition3D4N",
        (false, 6) => "SurfaceCondition3D6N",
        (false, 8) => "SurfaceCondition3D8N",
        (false, _) => "SurfaceCondition3D9N",
    }
}

type Piece = (GeometryKind, &'static str, Vec<NodeIdx>);

fn split_face(
    kind: GeometryKind,
    two_d: bool,
    settings: &InterfaceSettings,
    nodes: &[NodeIdx],
) -> Result<Vec<Piece>, Error> {
    if settings.simplify_geometry
        && let Some(table) = simplify_split(nodes.len(), two_d, settings.compatibility)
    {
        let (piece_kind, name) = if two_d {
            (GeometryKind::Line2D2, "LineCondition2D2N")
        } else {
            (GeometryKind::Triangle3D3, "SurfaceCondition3D3N")
        };
        return Ok(table
            .iter()
            .map(|local| (piece_kind, name, local.iter().map(|&l| nodes[l]).collect()))
            .collect());
    }
    let face_kind = if two_d || kind.is_face() {
        kind
    } else {
        // Every solid's boundary entities are faces (GeometryKind::faces); a kind without
        // any reaches here only through a new kind added without them.
        return Err(ErrorKind::Model(format!(
            "interface conditions: a {} boundary entity is not a face kind",
            kind.name()
        ))
        .into());
    };
    Ok(vec![(
        face_kind,
        interface_condition_name(nodes.len(), two_d),
        nodes.to_vec(),
    )])
}

/// Stage 1's role for the generated condition at index `c` (Kratos'
/// `AssignMasterSlaveCondition`): SLAVE where every node of it is SLAVE, else MASTER; the other
/// flag false in robust mode and left as it is in kratos mode. Returns whether it is SLAVE.
pub(crate) fn assign_generated_role(model: &mut ModelPart, c: usize, kratos: bool) -> bool {
    let slave = (model.conditions().nodes(c).iter())
        .all(|n| model.nodes().flags()[n.index()].is(Flag::SLAVE));
    let flags = &mut model.conditions_mut().flags_mut()[c];
    let (set, other) = if slave {
        (Flag::SLAVE, Flag::MASTER)
    } else {
        (Flag::MASTER, Flag::SLAVE)
    };
    flags.set(set, true);
    if !kratos {
        flags.set(other, false);
    }
    slave
}

#[allow(clippy::too_many_arguments)]
fn create_condition(
    model: &mut ModelPart,
    part: PartIdx,
    id: ConditionId,
    kind: GeometryKind,
    name: &'static str,
    nodes: &[NodeIdx],
    properties: PropertiesId,
    element: ElementId,
    kratos: bool,
) -> Result<GeneratedCondition, Error> {
    let node_ids: Vec<NodeId> = nodes
        .iter()
        .map(|n| NodeId(model.nodes().ids()[n.index()]))
        .collect();
    let idx = model
        .add_condition(id, kind, name, &node_ids, properties)
        .map_err(|e| Error::model_data("", e))?;
    model.add_conditions_to_part(part, &[idx]);
    let slave = assign_generated_role(model, idx.index(), kratos);
    Ok(GeneratedCondition {
        id,
        idx,
        name,
        kind,
        nodes: node_ids,
        slave,
        properties,
        element,
    })
}

/// Kratos `CheckAndCreateProperties`: when the first condition's properties lack
/// `YOUNG_MODULUS`, a block `number of properties + 1` is created from the properties of the
/// first element having that condition as a face (`THICKNESS` when present, `YOUNG_MODULUS` or
/// 0; `FRICTION_COEFFICIENT` only for a SLIP root, which csm's root never is) and given to every
/// condition of the part.
fn check_and_create_properties(
    model: &mut ModelPart,
    part: PartIdx,
    report: &mut InterfaceReport,
) -> Result<(), Error> {
    let first = model.part(part).conditions()[0];
    let first_props = model.conditions().properties(first.index());
    if model
        .properties()
        .get(&first_props)
        .is_some_and(|p| p.has("YOUNG_MODULUS"))
    {
        return Ok(());
    }
    let new_id = PropertiesId(model.properties().len() as u32 + 1);
    // The first element in id order with a face (or, not solid, its own geometry) on the
    // condition's nodes: the elements are tested in parallel, the first in order is taken.
    let mut key: Vec<NodeIdx> = model.conditions().nodes(first.index()).to_vec();
    key.sort_unstable();
    let on_face = |nodes: &mut dyn Iterator<Item = NodeIdx>| {
        let mut face = [NodeIdx(0); 27];
        let mut n = 0;
        for node in nodes {
            if n == face.len() {
                return false;
            }
            face[n] = node;
            n += 1;
        }
        face[..n].sort_unstable();
        face[..n] == key[..]
    };
    let owner = model.elements().id_order().par_iter().find_first(|&e| {
        let kind = model.elements().kind(e);
        let nodes = model.elements().nodes(e);
        // A face on the condition's nodes holds its first node: most elements are
        // passed over here, without building and sorting their faces.
        if key.first().is_some_and(|k| !nodes.contains(k)) {
            return false;
        }
        if kind.is_solid() {
            kind.faces()
                .iter()
                .any(|(_, local)| on_face(&mut local.iter().map(|&l| nodes[l])))
        } else {
            on_face(&mut nodes.iter().copied())
        }
    });
    let Some(owner) = owner else {
        return Err(ErrorKind::Model("It was not possible to add a property".into()).into());
    };
    let source = model.elements().properties(owner);
    let copy = contact_copy(model.properties().get(&source), new_id);
    model
        .add_properties(copy)
        .map_err(|e| Error::from(ErrorKind::RejectedByKratos(e.to_string())))?;
    report.created_properties.push(new_id);
    for c in model.part(part).conditions().to_vec() {
        model.conditions_mut().set_properties(c.index(), new_id);
    }
    Ok(())
}

#[cfg(test)]
mod tests;
