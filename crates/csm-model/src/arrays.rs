//! A [`ModelPart`]'s mesh as flat arrays and back: what the Python binding's
//! `Mesh.to_arrays()` and `Mesh.from_arrays(**arrays)` exchange with numpy.

use std::collections::BTreeMap;

use csm_geometry::GeometryKind;
use csm_geometry::math::Real;

use crate::error::{EntityKind, Error, ErrorKind};
use crate::ids::{ConditionId, ConditionIdx, ElementId, ElementIdx, NodeId, PropertiesId};
use crate::model_part::ModelPart;

/// The entities of one geometry kind: ids, node ids and properties ids, in one order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EntityArrays {
    /// The entity ids.
    pub ids: Vec<u32>,
    /// The node ids, `kind.n_nodes()` per entity, one entity after the other.
    pub connectivity: Vec<u32>,
    /// The properties id of every entity.
    pub properties: Vec<u32>,
}

/// The members of one sub model part, by id.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PartArrays {
    /// Node ids.
    pub nodes: Vec<u32>,
    /// Element ids.
    pub elements: Vec<u32>,
    /// Condition ids.
    pub conditions: Vec<u32>,
}

/// A mesh as flat arrays: nodes, elements and conditions by geometry kind, sub model parts by
/// full path. [`ModelPart::from_arrays`] of [`ModelPart::to_arrays`] is the same mesh: the
/// same entities in the same order (when the original's entities come in id order, as every
/// reader gives them for a file in id order), so a search gives the same result.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshArrays {
    /// The node ids.
    pub node_ids: Vec<u32>,
    /// The node coordinates, one per node id.
    pub points: Vec<[Real; 3]>,
    /// The elements, by kind.
    pub elements: BTreeMap<GeometryKind, EntityArrays>,
    /// The conditions, by kind.
    pub conditions: BTreeMap<GeometryKind, EntityArrays>,
    /// The sub model parts, by full path (`Parent.Child`).
    pub parts: BTreeMap<String, PartArrays>,
    /// ProcessInfo `DOMAIN_SIZE` (2 or 3); `None`: as the readers decide it, 2 when every
    /// element and condition is a 2D geometry, else 3.
    pub domain_size: Option<u32>,
}

impl ModelPart {
    /// The mesh's nodes (current coordinates), elements, conditions and sub model parts as
    /// flat arrays, with `DOMAIN_SIZE`. The rest of the process info, nodal data, properties'
    /// values and entity names are not part of it.
    pub fn to_arrays(&self) -> MeshArrays {
        let nodes = self.nodes();
        let by_kind = |entities: &crate::Entities| {
            let mut out: BTreeMap<GeometryKind, EntityArrays> = BTreeMap::new();
            for i in 0..entities.len() {
                let a = out.entry(entities.kind(i)).or_default();
                a.ids.push(entities.ids()[i]);
                let conn = entities.nodes(i).iter().map(|n| nodes.ids()[n.index()]);
                a.connectivity.extend(conn);
                a.properties.push(entities.properties(i).0);
            }
            out
        };
        let parts = self
            .parts()
            .iter()
            .map(|p| {
                let ids = |ids: &[u32], members: &mut dyn Iterator<Item = usize>| {
                    members.map(|i| ids[i]).collect::<Vec<u32>>()
                };
                let arrays = PartArrays {
                    nodes: ids(nodes.ids(), &mut p.nodes().iter().map(|n| n.index())),
                    elements: ids(
                        self.elements().ids(),
                        &mut p.elements().iter().map(|e| e.index()),
                    ),
                    conditions: ids(
                        self.conditions().ids(),
                        &mut p.conditions().iter().map(|c| c.index()),
                    ),
                };
                (p.path().to_owned(), arrays)
            })
            .collect();
        MeshArrays {
            node_ids: nodes.ids().to_vec(),
            points: nodes
                .coordinates()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            elements: by_kind(self.elements()),
            conditions: by_kind(self.conditions()),
            parts,
            domain_size: self.process_info().number("DOMAIN_SIZE").map(|d| d as u32),
        }
    }

    /// The model part `name` holding the mesh `arrays`: the nodes in order, then the elements
    /// and then the conditions of every kind in id order, then the sub model parts (each with
    /// its ancestors), with `DOMAIN_SIZE` ([`MeshArrays::domain_size`]). Errors, the first
    /// found: the lengths of the arrays that must match ([`ErrorKind::ArrayLength`]), a
    /// duplicate id, a non-finite coordinate, a connectivity naming a missing node, a
    /// `DOMAIN_SIZE` other than 2 or 3, an invalid part path, a part member that does not
    /// exist.
    pub fn from_arrays(name: &str, arrays: &MeshArrays) -> Result<ModelPart, Error> {
        let mut model = ModelPart::new(name);
        if arrays.points.len() != arrays.node_ids.len() {
            return Err(ErrorKind::ArrayLength {
                what: "points".to_owned(),
                expected: arrays.node_ids.len(),
                found: arrays.points.len(),
            }
            .into());
        }
        model
            .add_nodes(&arrays.node_ids, &arrays.points)
            .map_err(|(_, e)| e)?;
        for conditions in [false, true] {
            let by_kind = if conditions {
                &arrays.conditions
            } else {
                &arrays.elements
            };
            let mut order: Vec<(u32, GeometryKind, usize)> = Vec::new();
            for (&kind, a) in by_kind {
                let entity = if conditions { "conditions" } else { "elements" };
                let n = a.ids.len();
                let expect = |what: &str, expected: usize, found: usize| {
                    if expected == found {
                        Ok(())
                    } else {
                        Err(Error::from(ErrorKind::ArrayLength {
                            what: format!("{entity} {}: {what}", kind.name()),
                            expected,
                            found,
                        }))
                    }
                };
                expect("connectivity", n * kind.n_nodes(), a.connectivity.len())?;
                expect("properties", n, a.properties.len())?;
                order.extend(a.ids.iter().enumerate().map(|(i, &id)| (id, kind, i)));
            }
            order.sort_unstable();
            let mut ids = [NodeId(0); 27];
            for (id, kind, i) in order {
                let a = &by_kind[&kind];
                let nn = kind.n_nodes();
                let conn = &a.connectivity[i * nn..(i + 1) * nn];
                for (slot, &n) in ids.iter_mut().zip(conn) {
                    *slot = NodeId(n);
                }
                let properties = PropertiesId(a.properties[i]);
                model.ensure_properties(properties);
                if conditions {
                    model.add_condition(ConditionId(id), kind, "", &ids[..nn], properties)?;
                } else {
                    model.add_element(ElementId(id), kind, "", &ids[..nn], properties)?;
                }
            }
        }
        let kinds = || arrays.elements.keys().chain(arrays.conditions.keys());
        let planar = kinds().next().is_some() && kinds().all(|k| k.working_dim() == 2);
        let domain_size = match arrays.domain_size {
            Some(d @ (2 | 3)) => d,
            Some(d) => return Err(ErrorKind::InvalidDomainSize(d).into()),
            None if planar => 2,
            None => 3,
        };
        model
            .process_info_mut()
            .set_number("DOMAIN_SIZE", Real::from(domain_size));
        for (path, members) in &arrays.parts {
            let part = model.create_part(path)?;
            let missing = |entity: EntityKind, id: u32| ErrorKind::MissingPartMember {
                part: path.clone(),
                entity,
                id,
            };
            let nodes = members
                .nodes
                .iter()
                .map(|&id| {
                    model
                        .nodes()
                        .index_of(id)
                        .ok_or_else(|| missing(EntityKind::Node, id))
                })
                .collect::<Result<Vec<_>, _>>()?;
            let index = |entities: &crate::Entities, entity: EntityKind, id: u32| {
                entities
                    .index_of(id)
                    .map(|i| i as u32)
                    .ok_or_else(|| missing(entity, id))
            };
            let elements = members
                .elements
                .iter()
                .map(|&id| index(model.elements(), EntityKind::Element, id).map(ElementIdx))
                .collect::<Result<Vec<_>, _>>()?;
            let conditions = members
                .conditions
                .iter()
                .map(|&id| index(model.conditions(), EntityKind::Condition, id).map(ConditionIdx))
                .collect::<Result<Vec<_>, _>>()?;
            model.add_nodes_to_part(part, &sorted(nodes));
            model.add_elements_to_part(part, &sorted(elements));
            model.add_conditions_to_part(part, &sorted(conditions));
        }
        Ok(model)
    }
}

/// `v` sorted, without repeats.
fn sorted<T: Ord>(mut v: Vec<T>) -> Vec<T> {
    v.sort_unstable();
    v.dedup();
    v
}

#[cfg(test)]
#[path = "arrays/tests.rs"]
mod tests;
