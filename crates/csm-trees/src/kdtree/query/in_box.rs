//! Box query (reference §6.3): all points inside an axis-aligned box, faces included.

use std::ops::ControlFlow;

use csm_geometry::math::Point;

use crate::aabb::Aabb;
use crate::error::{Error, check_point};
use crate::kdtree::tree::{Arena, KdTree, Node};
use crate::query_status::QueryStatus;

impl<T: Copy + Send> KdTree<T> {
    /// Collects into `out` (cleared first) the items whose point `p` satisfies
    /// `min[k] <= p[k] <= max[k]` for k = x, y, z (**inclusive**, as Kratos' `SearchInBox`),
    /// at most `max_results` of them.
    ///
    /// Results come in tree traversal order. Truncation at `max_results` works as for
    /// [`KdTree::in_radius`]. A box with `min == max` finds the points equal to that corner;
    /// an inverted box (`min[k] > max[k]` on some axis) finds nothing, as in Kratos.
    ///
    /// Errors: [`crate::ErrorKind::NonFinite`] for a NaN or infinite corner.
    pub fn in_box(
        &self,
        min: &Point,
        max: &Point,
        max_results: usize,
        out: &mut Vec<T>,
    ) -> Result<QueryStatus, Error> {
        out.clear();
        check_point(min, "box corner")?;
        check_point(max, "box corner")?;
        let (Some(root), Some(extent)) = (self.root, &self.extent) else {
            return Ok(QueryStatus::default());
        };
        let aabb = Aabb::new(*min, *max);
        if !aabb.intersects(extent) {
            // No point lies in the query box (inclusive comparisons: exact).
            return Ok(QueryStatus::default());
        }
        let mut search = BoxSearch {
            tree: self,
            arena: self.arena(),
            aabb,
            max_results,
            out,
        };
        let flow = search.visit(root);
        Ok(QueryStatus {
            truncated: flow.is_break(),
        })
    }
}

/// The state of one box query.
struct BoxSearch<'a, T> {
    tree: &'a KdTree<T>,
    /// The arena `visit`'s nodes are in: the tree's, or a deferred subtree's.
    arena: Arena<'a, T>,
    aabb: Aabb,
    max_results: usize,
    out: &'a mut Vec<T>,
}

impl<T: Copy + Send> BoxSearch<'_, T> {
    /// Visits the subtree `node`; breaks when a hit beyond the cap is found (truncation).
    fn visit(&mut self, node: u32) -> ControlFlow<()> {
        match self.arena.nodes[node as usize] {
            Node::Leaf { start, end } => {
                let (start, end) = (start as usize, end as usize);
                for (item, p) in self.arena.items[start..end]
                    .iter()
                    .zip(&self.arena.points[start..end])
                {
                    if self.aabb.contains(p) {
                        if self.out.len() >= self.max_results {
                            return ControlFlow::Break(());
                        }
                        self.out.push(*item);
                    }
                }
                ControlFlow::Continue(())
            }
            Node::Inner {
                axis,
                left_max,
                right_min,
                left,
                right,
                ..
            } => {
                let axis = axis as usize;
                if self.aabb.min[axis] <= left_max {
                    self.visit(left)?;
                }
                if self.aabb.max[axis] >= right_min {
                    self.visit(right)?;
                }
                ControlFlow::Continue(())
            }
            Node::Deferred { slot, start, end } => {
                let outer = self.arena;
                self.arena = self.tree.subtree(slot, start, end).arena();
                let flow = self.visit(0);
                self.arena = outer;
                flow
            }
        }
    }
}
