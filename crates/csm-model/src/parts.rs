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

/// Merges `items` into the sorted, duplicate-free `v`: appended when they come in ascending
/// order after `v`'s last item (the common case), else appended and re-sorted — O(n log n)
/// for a batch, never one insertion per item.
pub(crate) fn merge_sorted<T: Ord + Copy>(v: &mut Vec<T>, items: &[T]) {
    let ascending_after = items.windows(2).all(|w| w[0] < w[1])
        && match (v.last(), items.first()) {
            (Some(last), Some(first)) => last < first,
            _ => true,
        };
    v.extend_from_slice(items);
    if !ascending_after {
        v.sort_unstable();
        v.dedup();
    }
}
