//! The objects sharing a leaf with a box: deduplicated, or listed per leaf as Kratos does.

use crate::aabb::Aabb;
use crate::error::Error;
use crate::octree::tree::Octree;

impl<T: Copy> Octree<T> {
    /// Collects into `out` (cleared first) every object stored in a leaf that `aabb` reaches
    /// (see [`Octree::intersected_leaves`]), each once, sorted (deterministic whatever the
    /// traversal order).
    ///
    /// This is a superset of the objects whose box overlaps `aabb`: an object is also found
    /// when it merely shares a leaf (grown by the cell tolerance) with `aabb`.
    ///
    /// Errors: [`crate::ErrorKind::NonFinite`], [`crate::ErrorKind::InvertedBox`].
    pub fn query_aabb(&self, aabb: &Aabb, out: &mut Vec<T>) -> Result<(), Error>
    where
        T: Ord,
    {
        self.query_aabb_per_leaf(aabb, out)?;
        out.sort_unstable();
        out.dedup();
        Ok(())
    }

    /// Collects into `out` (cleared first) the objects of every leaf that `aabb` reaches,
    /// leaf by leaf in traversal order and, within a leaf, in insertion order, **with
    /// duplicates**: an object stored in several of those leaves is listed once per leaf.
    /// This is what Kratos' octree + NoCheck pairing iterates over (a master is paired once
    /// per leaf it shares with the slave, Q15).
    ///
    /// Errors: [`crate::ErrorKind::NonFinite`], [`crate::ErrorKind::InvertedBox`].
    pub fn query_aabb_per_leaf(&self, aabb: &Aabb, out: &mut Vec<T>) -> Result<(), Error> {
        out.clear();
        crate::aabb::validate(aabb)?;
        let query = *aabb;
        self.for_each_intersected_leaf(aabb, &mut |cell: &Aabb| cell.intersects(&query), |leaf| {
            out.extend_from_slice(&self.cells[leaf as usize].objects)
        });
        Ok(())
    }
}
