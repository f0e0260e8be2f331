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

/// Items from which [`merge_sorted`] merges on rayon's pool.
const PARALLEL_MERGE_ITEMS: usize = 1 << 14;

/// Merges `items` into the sorted, duplicate-free `v`: appended when they come in ascending
/// order after `v`'s last item (the common case); merged in one pass of both lists when they
/// ascend but interleave with `v` (two parts added to one: their union, on rayon's pool when
/// long); else appended and re-sorted — never one insertion per item.
pub(crate) fn merge_sorted<T: Ord + Copy + Send + Sync>(v: &mut Vec<T>, items: &[T]) {
    // (The check and the append are a few memory passes: on one thread they cost less than
    // the parallel calls would.)
    if !items.windows(2).all(|w| w[0] < w[1]) {
        v.extend_from_slice(items);
        v.sort_unstable();
        v.dedup();
        return;
    }
    match (v.last(), items.first()) {
        (Some(last), Some(first)) if last >= first => {
            *v = union(v, items, items.len().max(v.len()) >= PARALLEL_MERGE_ITEMS);
        }
        _ => v.extend_from_slice(items),
    }
}

/// The union of the ascending, duplicate-free lists `a` and `b`, ascending and duplicate-free:
/// one merge pass; on rayon's pool (`parallel`), `a` cut into pieces, each merged with the
/// items of `b` from its first value up to the next piece's, and the pieces joined.
fn union<T: Ord + Copy + Send + Sync>(a: &[T], b: &[T], parallel: bool) -> Vec<T> {
    use rayon::prelude::*;
    if !parallel || a.is_empty() {
        return merge_union(a, b);
    }
    let pieces = (a.len() / (PARALLEL_MERGE_ITEMS / 4)).clamp(1, 8 * rayon::current_num_threads());
    // Piece k: a[cuts[k]..cuts[k + 1]] and the items of b below a[cuts[k + 1]] from those
    // not below a[cuts[k]] (the first piece takes b's smaller items, the last its larger).
    let cuts: Vec<usize> = (0..=pieces).map(|k| k * a.len() / pieces).collect();
    let at = |k: usize| match k {
        0 => 0,
        _ if k == pieces => b.len(),
        _ => b.partition_point(|x| *x < a[cuts[k]]),
    };
    let merged: Vec<Vec<T>> = (0..pieces)
        .into_par_iter()
        .map(|k| merge_union(&a[cuts[k]..cuts[k + 1]], &b[at(k)..at(k + 1)]))
        .collect();
    crate::concat_parts_with(&merged, |x| *x)
}

/// [`union`] in one serial pass.
fn merge_union<T: Ord + Copy>(a: &[T], b: &[T]) -> Vec<T> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => {
                out.push(a[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                out.push(b[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                out.push(a[i]);
                i += 1;
                j += 1;
            }
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The merge against a set: appended in order, interleaved (shared items, one list inside
    /// the other, before it or around it), repeated, and items in no order, on short and long
    /// lists (merged from [`PARALLEL_MERGE_ITEMS`] on rayon's pool, cut into pieces).
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
            ((0..10).collect(), (10..big).collect()),
            ((0..10).collect(), (0..big).map(|i| i / 3).collect()),
            (Vec::new(), (0..big).map(|i| i.div_ceil(2)).collect()),
            (
                (0..big).map(|i| 3 * i).collect(),
                (0..big).map(|i| 2 * i).collect(),
            ),
            ((big..2 * big).collect(), (0..big + 7).collect()),
            ((0..big + 5).collect(), (7..9).collect()),
            ((5..9).collect(), (0..big).collect()),
            (
                (0..big).map(|i| 4 * i + 1).collect(),
                (0..3 * big).collect(),
            ),
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
