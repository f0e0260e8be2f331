//! The tree of sub model parts, addressed by full path (`Contact.ContactSub0`).

use crate::write_at::par_clone;
use crate::{ConditionIdx, ElementIdx, NodeIdx, PartIdx};

/// One sub model part: its name, its parent, and the entities it holds (sorted dense
/// indices, no duplicates). An entity can belong to several parts; adding an entity to a
/// part also adds it to every ancestor, as Kratos does.
#[derive(Debug, Default)]
pub struct SubModelPart {
    pub(crate) name: String,
    pub(crate) path: String,
    pub(crate) parent: Option<PartIdx>,
    pub(crate) children: Vec<PartIdx>,
    pub(crate) nodes: Vec<NodeIdx>,
    pub(crate) elements: Vec<ElementIdx>,
    pub(crate) conditions: Vec<ConditionIdx>,
}

/// A copy whose lists are copied on rayon's pool where they are long.
impl Clone for SubModelPart {
    fn clone(&self) -> SubModelPart {
        let SubModelPart {
            name,
            path,
            parent,
            children,
            nodes,
            elements,
            conditions,
        } = self;
        SubModelPart {
            name: name.clone(),
            path: path.clone(),
            parent: *parent,
            children: children.clone(),
            nodes: par_clone(nodes),
            elements: par_clone(elements),
            conditions: par_clone(conditions),
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The merge against a set: appended in order, interleaved, repeated, and items in no
    /// order, on short and long lists.
    #[test]
    fn merging_gives_the_sorted_union() {
        let big = 3 * (1 << 14);
        let cases: Vec<(Vec<u32>, Vec<u32>)> = vec![
            ((0..10).collect(), (10..20).collect()),
            (
                (0..10).map(|i| 2 * i).collect(),
                (0..10).map(|i| 2 * i + 1).collect(),
            ),
            (
                (0..big).map(|i| 2 * i).collect(),
                (0..big).map(|i| 2 * i + 1).collect(),
            ),
            ((0..big).collect(), (big / 2..big + 10).collect()),
            (
                Vec::new(),
                (0..big).rev().map(|i| (i * 7919) % big).collect(),
            ),
        ];
        for (k, (v, items)) in cases.into_iter().enumerate() {
            let mut expected: std::collections::BTreeSet<u32> = v.iter().copied().collect();
            expected.extend(&items);
            let mut merged = v;
            merge_sorted(&mut merged, &items);
            assert!(merged.iter().copied().eq(expected), "case {k}");
        }
    }
}
