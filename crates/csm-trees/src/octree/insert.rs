//! Insertion of objects into the leaves they overlap (Kratos `OctreeBinary::Insert(object)`).

use crate::aabb::Aabb;
use crate::error::Error;

use super::tree::{LeafId, Octree};

impl<T: Copy> Octree<T> {
    /// Stores `item` in every leaf whose box, grown by the cell tolerance, overlaps `aabb`
    /// (inclusive). The candidate leaves are found as in Kratos: from the smallest cell
    /// containing the keys of the box corners, down through the children whose normalised
    /// boxes overlap the normalised `aabb` (inclusive). A box outside the root box is stored
    /// nowhere; one partly outside is stored in the boundary leaves it overlaps.
    ///
    /// Errors: [`crate::ErrorKind::NonFinite`], [`crate::ErrorKind::InvertedBox`].
    pub fn insert(&mut self, item: T, aabb: &Aabb) -> Result<(), Error> {
        let query = *aabb;
        self.insert_with(item, aabb, |cell| cell.intersects(&query))
    }

    /// [`Octree::insert`] with the caller's object-vs-cell test in place of the box test:
    /// `item` is stored in every candidate leaf (found with `aabb`, the object's bounding
    /// box) for which `overlaps(cell)` holds, `cell` being the leaf box in real coordinates
    /// grown by the cell tolerance (Kratos: `IsIntersected` → triangle/box, segment/box, …).
    pub fn insert_with(
        &mut self,
        item: T,
        aabb: &Aabb,
        mut overlaps: impl FnMut(&Aabb) -> bool,
    ) -> Result<(), Error> {
        crate::aabb::validate(aabb)?;
        // The leaves are collected first (read-only walk), then filled.
        let mut hits = Vec::new();
        self.for_each_intersected_leaf(aabb, &mut overlaps, |leaf| hits.push(leaf));
        for leaf in hits {
            self.cells[leaf as usize].objects.push(item);
        }
        self.n_objects += 1;
        Ok(())
    }

    /// Stores `item` in `leaves`, as [`Octree::insert_with`] stores it in the leaves its walk
    /// finds: an insertion split in two, the walk ([`Octree::intersected_leaves_with`], the
    /// same walk, read-only, so the objects' walks may run in parallel) and this store, made
    /// in the objects' order so that each leaf lists them as the insertions in that order
    /// would. Counts as one inserted object; afterwards the octree can no longer be refined.
    ///
    /// Errors: [`crate::ErrorKind::NotALeaf`] when some id is not a leaf of this octree (an
    /// id from another octree, or from before a refinement); nothing is stored then.
    pub fn insert_in_leaves(&mut self, item: T, leaves: &[LeafId]) -> Result<(), Error> {
        let is_leaf = |leaf: &LeafId| {
            self.cells
                .get(leaf.0 as usize)
                .is_some_and(|cell| cell.children.is_none())
        };
        if !leaves.iter().all(is_leaf) {
            return Err(Error::new(crate::ErrorKind::NotALeaf));
        }
        for leaf in leaves {
            self.cells[leaf.0 as usize].objects.push(item);
        }
        self.n_objects += 1;
        Ok(())
    }
}
