//! The leaves a box (and optionally an exact object test) reaches, in Kratos' order
//! (`OctreeBinary::GetIntersectedLeaves`).

use csm_geometry::math::Real;

use crate::aabb::Aabb;
use crate::error::Error;
use crate::octree::tree::{LeafId, Octree};

/// The traversal stack bound: each of at most 31 levels leaves at most 7 siblings on the
/// stack, plus the 8 children of the last cell.
const STACK: usize = 8 * 32;

impl<T> Octree<T> {
    /// Collects into `out` (cleared first) the leaves whose box, grown by the cell tolerance,
    /// overlaps `aabb` (inclusive), in Kratos' traversal order (depth first, children
    /// visited from 7 down to 0). The same walk as [`Octree::insert`].
    ///
    /// Errors: [`crate::ErrorKind::NonFinite`], [`crate::ErrorKind::InvertedBox`].
    pub fn intersected_leaves(&self, aabb: &Aabb, out: &mut Vec<LeafId>) -> Result<(), Error> {
        let query = *aabb;
        self.intersected_leaves_with(aabb, |cell| cell.intersects(&query), out)
    }

    /// [`Octree::intersected_leaves`] with the caller's object-vs-cell test (see
    /// [`Octree::insert_with`]); `aabb` is the object's bounding box.
    pub fn intersected_leaves_with(
        &self,
        aabb: &Aabb,
        mut overlaps: impl FnMut(&Aabb) -> bool,
        out: &mut Vec<LeafId>,
    ) -> Result<(), Error> {
        out.clear();
        crate::aabb::validate(aabb)?;
        self.for_each_intersected_leaf(aabb, &mut overlaps, |leaf| out.push(LeafId(leaf)));
        Ok(())
    }

    /// The walk shared by insertion and queries; `aabb` must be valid.
    pub(crate) fn for_each_intersected_leaf(
        &self,
        aabb: &Aabb,
        overlaps: &mut impl FnMut(&Aabb) -> bool,
        mut emit: impl FnMut(u32),
    ) {
        let tolerance = self.params.cell_tolerance();
        let lo = self.normalize(&aabb.min);
        let hi = self.normalize(&aabb.max);
        let range_cell = self.range_cell(&lo, &hi);

        let mut stack = [0u32; STACK];
        stack[0] = range_cell;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let cell = stack[top];
            match self.cells[cell as usize].children {
                Some(first) => {
                    for child in first..first + 8 {
                        let (low, high) = self.cell_box_normalized(child);
                        if collides(&lo, &hi, &low, &high) {
                            stack[top] = child;
                            top += 1;
                        }
                    }
                }
                None => {
                    let (low, high) = self.cell_box_normalized(cell);
                    let leaf_box =
                        Aabb::new(self.scale_back(low), self.scale_back(high)).enlarged(tolerance);
                    if overlaps(&leaf_box) {
                        emit(cell);
                    }
                }
            }
        }
    }

    /// The smallest existing cell containing the keys of both normalised corners: the level
    /// just above the highest bit in which the keys differ (axes scanned x, y, z as Kratos
    /// does), reached from the root along the keys of `lo`, stopping early at a leaf.
    fn range_cell(&self, lo: &[Real; 3], hi: &[Real; 3]) -> u32 {
        let root_level = self.params.root_level;
        let min_level = self.params.min_level;
        let lo_keys = lo.map(|x| self.key(x));
        let hi_keys = hi.map(|x| self.key(x));
        let delta: [u32; 3] = std::array::from_fn(|k| lo_keys[k] ^ hi_keys[k]);
        let bit_set = |d: u32, l: u32| d & (1u32 << l) != 0;
        let mut level_x = root_level;
        while !bit_set(delta[0], level_x) && level_x > min_level {
            level_x -= 1;
        }
        let mut level_y = root_level;
        while !bit_set(delta[1], level_y) && level_y > level_x {
            level_y -= 1;
        }
        let mut level = root_level;
        while !bit_set(delta[2], level) && level > level_y {
            level -= 1;
        }
        level += 1;

        let mut cell = 0u32;
        for _ in level..root_level {
            let c = &self.cells[cell as usize];
            let Some(first) = c.children else {
                break;
            };
            cell = first + Self::child_index(c.level, lo_keys);
        }
        cell
    }
}

/// Kratos' `Collides`: inclusive overlap of two normalised boxes.
fn collides(lo1: &[Real; 3], hi1: &[Real; 3], lo2: &[Real; 3], hi2: &[Real; 3]) -> bool {
    (0..3).all(|k| lo1[k] <= hi2[k] && lo2[k] <= hi1[k])
}
