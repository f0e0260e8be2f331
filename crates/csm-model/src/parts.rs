//! The tree of sub model parts, addressed by full path (`Contact.ContactSub0`).

use crate::{ConditionIdx, ElementIdx, NodeIdx, PartIdx};

/// One sub model part: its name, its parent, and the entities it holds (sorted dense
/// indices, no duplicates). An entity can belong to several parts; adding an entity to a
/// part also adds it to every ancestor, as Kratos does.
#[derive(Debug, Clone, Default)]
pub struct SubModelPart {
    pub(crate) name: String,
    pub(crate) path: String,
    pub(crate) parent: Option<PartIdx>,
    pub(crate) children: Vec<PartIdx>,
    pub(crate) nodes: Vec<NodeIdx>,
    pub(crate) elements: Vec<ElementIdx>,
    pub(crate) conditions: Vec<ConditionIdx>,
}

impl SubModelPart {
    /// The part's own name (last path segment).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The full path from the root model part, segments joined by `.`.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// The parent part, `None` for a part directly under the root.
    pub fn parent(&self) -> Option<PartIdx> {
        self.parent
    }

    /// The children, in creation order.
    pub fn children(&self) -> &[PartIdx] {
        &self.children
    }

    /// Nodes, ascending dense index.
    pub fn nodes(&self) -> &[NodeIdx] {
        &self.nodes
    }

    /// Elements, ascending dense index.
    pub fn elements(&self) -> &[ElementIdx] {
        &self.elements
    }

    /// Conditions, ascending dense index.
    pub fn conditions(&self) -> &[ConditionIdx] {
        &self.conditions
    }
}

/// Inserts `x` into the sorted, duplicate-free `v`; cheap when `x` comes in ascending order.
pub(crate) fn insert_sorted<T: Ord + Copy>(v: &mut Vec<T>, x: T) {
    match v.last() {
        None => v.push(x),
        Some(last) if *last < x => v.push(x),
        Some(_) => {
            if let Err(pos) = v.binary_search(&x) {
                v.insert(pos, x);
            }
        }
    }
}
