//! Turns the content of a Gmsh file into a [`ModelPart`].
//!
//! - The model dimension is the largest cell dimension. The model is 2D ("planar") when that
//!   is at most 2 and every node has z = 0; then lines become `Line2D2`/`Line2D3` conditions
//!   and triangles/quadrilaterals `…2D…` elements. Otherwise volumes become elements and
//!   triangles/quadrilaterals `…3D…` conditions (in a surface-only 3D mesh the surfaces are
//!   the elements). Points, lines in space and cells two dimensions below the model add only
//!   their nodes to their groups' parts.
//! - Element tags are the element/condition ids (MSH 2.2 as written by Gmsh 4 numbers the
//!   cells afresh and lists a cell once per physical group with a new tag each time: the
//!   copies become one entity, with the first tag, in several parts); nodes, elements and conditions are stored
//!   in ascending id order whatever the file order, so the four MSH variants of one mesh give
//!   the same model.
//! - Every physical group becomes a sub model part named by `$PhysicalNames`; an unnamed
//!   group (dimension `d`, tag `t`) is named `physical_<d>_<t>`. Groups of one name in
//!   several dimensions share one part. A name with `.` or `/` makes nested parts.
//! - Every entity uses properties 0. `DOMAIN_SIZE` is 2 for a planar model, else 3.

use std::collections::BTreeMap;

use csm_model::{
    ConditionId, ConditionIdx, ElementId, ElementIdx, EntityKind, ModelPart, NodeId, NodeIdx,
    PropertiesId,
};

use crate::cursor::Cursor;
use crate::error::{Error, ErrorKind, Location};
use crate::msh::element_type::{self, Role};
use crate::msh::raw_mesh::RawMesh;

#[derive(Default)]
struct Group {
    nodes: Vec<NodeIdx>,
    elements: Vec<ElementIdx>,
    conditions: Vec<ConditionIdx>,
}

fn location(cur: &Cursor<'_>, pos: usize, binary: bool, section: &str) -> Location {
    if binary {
        Location::Byte {
            offset: pos,
            section: section.to_owned(),
        }
    } else {
        Location::Line(cur.line_at(pos))
    }
}

/// Builds the model part `Structure` from `raw`.
pub(crate) fn build_model(raw: &RawMesh, cur: &Cursor<'_>) -> Result<ModelPart, Error> {
    let model_dim = raw
        .elements
        .iter()
        .map(|e| element_type::dim(e.gmsh_type))
        .max()
        .unwrap_or(0);
    let planar = model_dim <= 2 && raw.nodes.iter().all(|n| n.xyz[2] == 0.0);
    let mut mp = ModelPart::new("Structure");
    let props = PropertiesId(0);
    mp.ensure_properties(props);

    let mut order: Vec<usize> = (0..raw.nodes.len()).collect();
    order.sort_by_key(|&i| raw.nodes[i].tag);
    for i in order {
        let n = &raw.nodes[i];
        mp.add_node(NodeId(n.tag), n.xyz.into()).map_err(|e| {
            Error::new(
                cur.file(),
                location(cur, n.pos, n.binary, "$Nodes"),
                ErrorKind::Model(e),
            )
        })?;
    }

    let mut order: Vec<usize> = (0..raw.elements.len()).collect();
    order.sort_by_key(|&i| raw.elements[i].tag);
    let mut groups: BTreeMap<String, Group> = BTreeMap::new();
    let mut conn: Vec<NodeId> = Vec::new();
    for i in order {
        let e = &raw.elements[i];
        let tags = raw.element_nodes(e);
        conn.clear();
        match element_type::permutation(e.gmsh_type) {
            Some(perm) if perm.len() == tags.len() => {
                conn.extend(perm.iter().map(|&k| NodeId(tags[k])));
            }
            _ => conn.extend(tags.iter().map(|&t| NodeId(t))),
        }
        let err = |m: csm_model::Error| {
            Error::new(
                cur.file(),
                location(cur, e.pos, e.binary, "$Elements"),
                ErrorKind::Model(m),
            )
        };
        let role = element_type::role(e.gmsh_type, model_dim, planar);
        let mut entity = None;
        match role {
            Role::Element(kind) => {
                let idx = mp
                    .add_element(ElementId(e.tag), kind, "", &conn, props)
                    .map_err(err)?;
                entity = Some(Ok(idx));
            }
            Role::Condition(kind) => {
                let idx = mp
                    .add_condition(ConditionId(e.tag), kind, "", &conn, props)
                    .map_err(err)?;
                entity = Some(Err(idx));
            }
            Role::NodesOnly => {
                for n in &conn {
                    if mp.nodes().index_of(n.0).is_none() {
                        return Err(err(csm_model::Error::new(
                            csm_model::ErrorKind::MissingNode {
                                entity: EntityKind::Element,
                                id: e.tag,
                                node: n.0,
                            },
                        )));
                    }
                }
            }
        }
        for &(d, t) in &e.physicals {
            let name = match raw.physical_names.get(&(d, t)) {
                Some(n) if !n.trim().is_empty() => n.clone(),
                _ => format!("physical_{d}_{t}"),
            };
            let g = groups.entry(name).or_default();
            g.nodes
                .extend(conn.iter().filter_map(|n| mp.nodes().index_of(n.0)));
            match entity {
                Some(Ok(idx)) => g.elements.push(idx),
                Some(Err(idx)) => g.conditions.push(idx),
                None => {}
            }
        }
    }
    for (name, mut g) in groups {
        let part = mp
            .create_part(&name)
            .map_err(|m| Error::new(cur.file(), Location::Line(1), ErrorKind::Model(m)))?;
        g.nodes.sort_unstable();
        g.nodes.dedup();
        g.elements.sort_unstable();
        g.elements.dedup();
        g.conditions.sort_unstable();
        g.conditions.dedup();
        mp.add_nodes_to_part(part, &g.nodes);
        mp.add_elements_to_part(part, &g.elements);
        mp.add_conditions_to_part(part, &g.conditions);
    }
    mp.process_info_mut()
        .set_number("DOMAIN_SIZE", if planar { 2.0 } else { 3.0 });
    Ok(mp)
}
