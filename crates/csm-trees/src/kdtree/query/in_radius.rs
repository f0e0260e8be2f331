//! Radius query (reference §6.2): all points strictly closer than `radius` to a centre.

use std::ops::ControlFlow;

use csm_geometry::math::{Point, Real};

use crate::aabb::Aabb;
use crate::error::{Error, ErrorKind, check_point};
use crate::kdtree::tree::{Arena, KdTree, Node};
use crate::query_status::QueryStatus;

impl<T: Copy + Send> KdTree<T> {
    /// Collects into `out` (cleared first) the items whose point `p` satisfies
    /// `|p − center|² < radius²` (**strict**, squared distance summed over x, y, z in that
    /// order, as Kratos' `SearchInRadius`), at most `max_results` of them.
    ///
    /// Results come in tree traversal order (Kratos' order for the same build). When more
    /// than `max_results` points qualify, the first `max_results` in traversal order are kept
    /// and [`QueryStatus::truncated`] is set (Kratos drops the rest silently, §6.4). `out` is
    /// the caller's reusable buffer; no buffer of size `max_results` is allocated.
    ///
    /// A radius of 0 finds nothing. Errors: [`ErrorKind::NonFinite`] for a NaN/infinite centre
    /// or radius, [`ErrorKind::NegativeRadius`].
    pub fn in_radius(
        &self,
        center: &Point,
        radius: Real,
        max_results: usize,
        out: &mut Vec<T>,
    ) -> Result<QueryStatus, Error> {
        out.clear();
        check_point(center, "center")?;
        if !radius.is_finite() {
            return Err(Error::non_finite("radius"));
        }
        if radius < 0.0 {
            return Err(Error::new(ErrorKind::NegativeRadius));
        }
        let (Some(root), Some(extent)) = (self.root, &self.extent) else {
            return Ok(QueryStatus::default());
        };
        if box_distance2(extent, center) >= radius * radius {
            // No point is closer than the box (exactly: see `box_distance2`; both sides finite).
            return Ok(QueryStatus::default());
        }
        let mut search = RadiusSearch {
            tree: self,
            arena: self.arena(),
            center,
            radius2: radius * radius,
            max_results,
            out,
        };
        let mut residual = [0.0; 3];
        let flow = search.visit(root, &mut residual);
        Ok(QueryStatus {
            truncated: flow.is_break(),
        })
    }
}

/// The state of one radius query.
struct RadiusSearch<'a, T> {
    tree: &'a KdTree<T>,
    /// The arena `visit`'s nodes are in: the tree's, or a deferred subtree's.
    arena: Arena<'a, T>,
    center: &'a Point,
    radius2: Real,
    max_results: usize,
    out: &'a mut Vec<T>,
}

impl<T: Copy + Send> RadiusSearch<'_, T> {
    /// Visits the subtree `node`; `residual[k]` is a lower bound of the squared distance along
    /// axis `k` from the centre to any point of the subtree. Breaks when a hit beyond the cap
    /// is found (truncation).
    fn visit(&mut self, node: u32, residual: &mut [Real; 3]) -> ControlFlow<()> {
        match self.arena.nodes[node as usize] {
            Node::Leaf { start, end } => {
                let (start, end) = (start as usize, end as usize);
                for (item, p) in self.arena.items[start..end]
                    .iter()
                    .zip(&self.arena.points[start..end])
                {
                    if distance2(p, self.center) < self.radius2 {
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
                cut,
                left_max,
                right_min,
                left,
                right,
            } => {
                let axis = axis as usize;
                let saved = residual[axis];
                let c = self.center[axis];
                // The far child's distance along the axis: `c − cut` on a built tree (both
                // bounds are the cut: Kratos' δ, bit for bit); a refitted tree's bounds may
                // overlap the centre, then the far child is not pruned on this axis.
                let (near, far, gap) = if c - cut < 0.0 {
                    (left, right, (right_min - c).max(0.0))
                } else {
                    (right, left, (c - left_max).max(0.0))
                };
                self.visit(near, residual)?;
                residual[axis] = gap * gap;
                if self.radius2 >= residual[0] + residual[1] + residual[2] {
                    self.visit(far, residual)?;
                }
                residual[axis] = saved;
                ControlFlow::Continue(())
            }
            Node::Deferred { slot, start, end } => {
                let outer = self.arena;
                self.arena = self.tree.subtree(slot, start, end).arena();
                let flow = self.visit(0, residual);
                self.arena = outer;
                flow
            }
        }
    }
}

/// The squared distance from `c` to `aabb`, computed with the operations of [`distance2`]:
/// for every point `p` of the box, `distance2(p, c) >= box_distance2(aabb, c)` holds for the
/// floating-point values themselves, because rounding is monotone (`|p[k] − c[k]|` rounds to at
/// least the rounded gap to the box face, squares and sums of non-negative terms keep the
/// order). So a query whose box distance is not below `radius²` finds nothing, exactly.
pub(crate) fn box_distance2(aabb: &Aabb, c: &Point) -> Real {
    let mut sum = 0.0;
    for k in 0..3 {
        let d = if c[k] < aabb.min[k] {
            aabb.min[k] - c[k]
        } else if c[k] > aabb.max[k] {
            c[k] - aabb.max[k]
        } else {
            0.0
        };
        sum += d * d;
    }
    sum
}

/// Squared distance, accumulated over the axes in the order x, y, z (Kratos' order; the
/// brute-force reference uses the same function so that both agree bit for bit).
pub(crate) fn distance2(p: &Point, q: &Point) -> Real {
    let mut sum = 0.0;
    for k in 0..3 {
        let d = p[k] - q[k];
        sum += d * d;
    }
    sum
}
