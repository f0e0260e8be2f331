//! Refinement of the octree around a point (Kratos `OctreeBinary::Insert(point)`).

use csm_geometry::math::Point;

use crate::error::{Error, ErrorKind, check_point};

use super::tree::Octree;

impl<T> Octree<T> {
    /// Refines the octree around `point`: starting at the root, every leaf on the way to the
    /// cell of `point` is split, down to a cell of level `min_level` (Kratos inserts every
    /// master node this way, so the leaves around the nodes are 1/512 of the root box).
    ///
    /// Refine before inserting objects, as Kratos inserts nodes before conditions.
    ///
    /// Errors: [`ErrorKind::NonFinite`], [`ErrorKind::OutsideRootBox`] (faces of the root box
    /// belong to it), [`ErrorKind::RefineAfterInsert`] once an object has been inserted.
    pub fn insert_point(&mut self, point: &Point) -> Result<(), Error> {
        check_point(point, "point")?;
        if self.n_objects > 0 {
            return Err(Error::new(ErrorKind::RefineAfterInsert));
        }
        let x = self.normalize(point);
        if !x.iter().all(|c| (0.0..=1.0).contains(c)) {
            return Err(Error::new(ErrorKind::OutsideRootBox));
        }
        let keys = x.map(|c| self.key(c));
        let mut cell = 0u32;
        for _ in self.params.min_level..self.params.root_level {
            self.subdivide(cell);
            let c = &self.cells[cell as usize];
            let Some(first) = c.children else {
                // Unreachable: `subdivide` just gave it children (level > min_level >= 0).
                break;
            };
            cell = first + Self::child_index(c.level, keys);
        }
        Ok(())
    }
}
