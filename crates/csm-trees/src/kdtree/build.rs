//! Construction of the kd-tree (reference §6.1): split on the axis of largest spread at the
//! median found by Kratos' Hoare quickselect, with Kratos' cut value.

use csm_geometry::Aabb;
use csm_geometry::math::{Point, Real};

use super::tree::Node;

/// Ranges of at least this many points build their two halves in parallel.
const PARALLEL_MIN: usize = 16_384;

/// Builds the tree over the parallel arrays `items`/`points` (permuting them) into `nodes` and
/// returns the root, `None` when there is no point.
///
/// Large ranges build their two halves in parallel, each into its own arena that is then
/// appended: the arena is the serial build's (pre-order: a node, its left subtree, its right
/// subtree), node for node, for any thread count.
///
/// A range of more than `bucket_size` and at most `defer_max` points becomes a
/// [`Node::Deferred`] (its entries left in their order, numbered in pre-order from 0); with
/// `defer_max <= bucket_size` none does. Returns the root, the number of deferred nodes and
/// the points' box (found once, in parallel, and giving the root's split axis).
///
/// `bucket_size >= 1` and `points.len() <= u32::MAX / 2` are checked by the caller.
pub(super) fn build<T: Copy + Send>(
    items: &mut [T],
    points: &mut [Point],
    nodes: &mut Vec<Node>,
    bucket_size: usize,
    defer_max: usize,
) -> (Option<u32>, usize, Option<Aabb>) {
    if points.is_empty() {
        return (None, 0, None);
    }
    let extent = bounds(points, PARALLEL_MIN);
    let entries = Entries {
        items,
        points,
        base: 0,
    };
    let sizes = (bucket_size, PARALLEL_MIN, defer_max);
    let root = build_range(entries, nodes, sizes, Some(&extent));
    let mut deferred = 0;
    if defer_max > bucket_size {
        number_deferred(nodes, root, &mut deferred);
    }
    (Some(root), deferred as usize, Some(extent))
}

/// [`build`] without numbering the deferred ranges; `sizes`: the bucket size, the smallest
/// range built in parallel halves and the largest deferred range.
#[cfg(test)]
pub(super) fn build_with<T: Copy + Send>(
    items: &mut [T],
    points: &mut [Point],
    nodes: &mut Vec<Node>,
    sizes: (usize, usize, usize),
) -> Option<u32> {
    debug_assert!(sizes.0 >= 1);
    debug_assert_eq!(items.len(), points.len());
    if points.is_empty() {
        return None;
    }
    let entries = Entries {
        items,
        points,
        base: 0,
    };
    Some(build_range(entries, nodes, sizes, None))
}

/// Numbers the [`Node::Deferred`] nodes of the subtree `node` in pre-order from `*next`.
fn number_deferred(nodes: &mut [Node], node: u32, next: &mut u32) {
    match &mut nodes[node as usize] {
        Node::Leaf { .. } => {}
        Node::Deferred { slot, .. } => {
            *slot = *next;
            *next += 1;
        }
        &mut Node::Inner { left, right, .. } => {
            number_deferred(nodes, left, next);
            number_deferred(nodes, right, next);
        }
    }
}

/// A range of the two parallel arrays, swapped together; `base` is the position of its first
/// entry in the whole arrays.
pub(super) struct Entries<'a, T> {
    pub(super) items: &'a mut [T],
    pub(super) points: &'a mut [Point],
    pub(super) base: usize,
}

impl<'a, T> Entries<'a, T> {
    pub(super) fn len(&self) -> usize {
        self.points.len()
    }

    pub(super) fn swap(&mut self, i: usize, j: usize) {
        self.items.swap(i, j);
        self.points.swap(i, j);
    }

    pub(super) fn v(&self, i: usize, axis: usize) -> Real {
        self.points[i][axis]
    }

    /// The entries before `m` and those from `m` on.
    fn split_at(self, m: usize) -> (Entries<'a, T>, Entries<'a, T>) {
        let (items_lo, items_hi) = self.items.split_at_mut(m);
        let (points_lo, points_hi) = self.points.split_at_mut(m);
        (
            Entries {
                items: items_lo,
                points: points_lo,
                base: self.base,
            },
            Entries {
                items: items_hi,
                points: points_hi,
                base: self.base + m,
            },
        )
    }
}

/// Builds the subtree over the non-empty `entries`, appending its nodes to `nodes` (in
/// pre-order), and returns its node index.
/// `sizes`: the bucket size, the smallest range built in parallel halves and the largest
/// deferred range.
fn build_range<T: Send>(
    mut entries: Entries<'_, T>,
    nodes: &mut Vec<Node>,
    sizes: (usize, usize, usize),
    known: Option<&Aabb>,
) -> u32 {
    let (bucket_size, parallel_min, defer_max) = sizes;
    let n = entries.len();
    debug_assert!(n > 0);
    // Fits: there are fewer than 2·len nodes and the caller checked len <= u32::MAX / 2.
    let index = nodes.len() as u32;
    if n <= bucket_size {
        nodes.push(Node::Leaf {
            start: entries.base as u32,
            end: (entries.base + n) as u32,
        });
        return index;
    }
    if n <= defer_max {
        nodes.push(Node::Deferred {
            slot: 0,
            start: entries.base as u32,
            end: (entries.base + n) as u32,
        });
        return index;
    }
    let axis = match known {
        Some(aabb) => widest_axis(aabb),
        None => widest_axis(&bounds(entries.points, parallel_min)),
    };
    let m = n / 2;
    select_blocks(&mut entries, m, axis);
    let cut = cut_value(&entries, m, axis);
    // Placeholder, filled once the children exist.
    nodes.push(Node::Leaf { start: 0, end: 0 });
    let (lo, hi) = entries.split_at(m);
    let (left, right) = if n >= parallel_min {
        let (mut left_nodes, mut right_nodes) = (Vec::new(), Vec::new());
        rayon::join(
            || build_range(lo, &mut left_nodes, sizes, None),
            || build_range(hi, &mut right_nodes, sizes, None),
        );
        (append(nodes, left_nodes), append(nodes, right_nodes))
    } else {
        (
            build_range(lo, nodes, sizes, None),
            build_range(hi, nodes, sizes, None),
        )
    };
    nodes[index as usize] = Node::Inner {
        axis: axis as u8,
        cut,
        left_max: cut,
        right_min: cut,
        left,
        right,
    };
    index
}

/// Appends the arena `sub` of a subtree (root at its index 0) to `nodes`, shifting its child
/// links, and returns the subtree's root index in `nodes`.
fn append(nodes: &mut Vec<Node>, sub: Vec<Node>) -> u32 {
    let offset = nodes.len() as u32;
    // The leaves' entry ranges are already the whole arrays'.
    nodes.extend(sub.into_iter().map(|node| node.shifted(offset, 0)));
    offset
}

/// The box of the non-empty `points`; in parallel blocks from `parallel_min` points on.
pub(super) fn bounds(points: &[Point], parallel_min: usize) -> Aabb {
    crate::aabb::bounds_in_blocks(points, parallel_min).expect("non-empty points")
}

/// The axis of maximum spread `max p[k] − min p[k]` of the points of box `aabb`; ties go to
/// the lowest axis (Kratos compares spreads with a strict `>`, starting from axis 0).
fn widest_axis(aabb: &Aabb) -> usize {
    let (lo, hi) = (aabb.min, aabb.max);
    let mut axis = 0;
    let mut max_spread = hi[0] - lo[0];
    for k in 1..3 {
        let spread = hi[k] - lo[k];
        if spread > max_spread {
            max_spread = spread;
            axis = k;
        }
    }
    axis
}

/// Positions scanned per block by [`select_blocks`].
const SCAN_BLOCK: usize = 64;

/// Kratos' Hoare-style quickselect on `axis` over the whole range: afterwards position `m`
/// holds the value it would hold in sorted order, everything before it is `<=` and everything
/// after it `>=` (reference §6.1). The same swaps in the same order as Kratos' scalar loop
/// (so the same permutation; the tests keep that loop as the oracle), found without its
/// data-dependent scan branches: each partition pass lists, a block at a time
/// and without branches, the positions its left scan stops at (`v >= pivot`, ascending from
/// `left + 1`) and those its right scan stops at (`v <= pivot`, descending from
/// `right − 1`). Hoare's pass swaps the `k`-th of each while the left one is before the right
/// one; at the first pair where it is not, the scans have crossed and the pass ends at
/// `j = max(R[k], L[k − 1])` (`L[−1] = left`). Until the crossing, the positions between the
/// last two stops were never swapped, so listing them from their current values finds the
/// scans' stops; past it, a listed position only decides that the pass ends, which it does
/// whatever the value there (a swapped position stops either scan).
///
/// A range of at least [`SUMMARY_MIN`] positions whose pass ends within a sixteenth of either
/// end (a mesh's centres in grid order make dozens of such passes, each taking a row's ends)
/// keeps, from then on, bounds of the values of every aligned block of [`SCAN_BLOCK`]
/// positions, widened at every swap: a scan passes a block without a possible stop (all
/// values below the pivot for the left scan, above it for the right) without listing it.
/// The bounds only widen, so a passed block has no stop: the same stops, the same swaps.
pub(super) fn select_blocks<T>(entries: &mut Entries<'_, T>, m: usize, axis: usize) {
    select_blocks_with(entries, m, axis, SUMMARY_MIN);
}

/// [`select_blocks`] with the smallest range that keeps block bounds.
pub(super) fn select_blocks_with<T>(
    entries: &mut Entries<'_, T>,
    m: usize,
    axis: usize,
    summary_min: usize,
) {
    let mut left = 0;
    let mut right = entries.len() - 1;
    let mut lbuf = [0usize; SCAN_BLOCK];
    let mut rbuf = [0usize; SCAN_BLOCK];
    let mut bounds = BlockBounds::default();
    while left < right {
        if entries.v(left, axis) > entries.v(right, axis) {
            bounds.swap(entries, (left, right), axis);
        }
        let pivot = entries.v(left, axis);
        // Next position to list on each side, and the listed stops not yet paired.
        let (mut lnext, mut rnext) = (left + 1, right as isize - 1);
        let (mut lbeg, mut lend, mut rbeg, mut rend) = (0, 0, 0, 0);
        // The previous left stop (`left` before the first).
        let mut last_l = left;
        let j = loop {
            if lbeg == lend {
                // `v(right) >= pivot`: the list ends there at the latest (and its block is
                // never passed).
                lbeg = 0;
                lend = 0;
                lnext = bounds.pass_below(lnext, pivot, right);
                let stop = ((lnext / SCAN_BLOCK + 1) * SCAN_BLOCK).min(right + 1);
                for p in lnext..stop {
                    lbuf[lend] = p;
                    lend += usize::from(entries.v(p, axis) >= pivot);
                }
                lnext = stop;
            }
            if rbeg == rend {
                // `v(left) == pivot`: the list ends there at the latest (and its block is
                // never passed).
                rbeg = 0;
                rend = 0;
                rnext = bounds.pass_above(rnext, pivot, left);
                let block_start = (rnext as usize / SCAN_BLOCK * SCAN_BLOCK) as isize;
                let stop = (block_start - 1).max(left as isize - 1);
                let mut p = rnext;
                while p > stop {
                    rbuf[rend] = p as usize;
                    rend += usize::from(entries.v(p as usize, axis) <= pivot);
                    p -= 1;
                }
                rnext = stop;
            }
            if lbeg == lend || rbeg == rend {
                // A block without a stop: list the next one.
                continue;
            }
            let (l, r) = (lbuf[lbeg], rbuf[rbeg]);
            if l < r {
                bounds.swap(entries, (l, r), axis);
                last_l = l;
                lbeg += 1;
                rbeg += 1;
            } else {
                break r.max(last_l);
            }
        };
        bounds.swap(entries, (left, j), axis);
        let n = right - left + 1;
        if bounds.is_empty() && n >= summary_min && (j - left).min(right - j) < n / 16 {
            bounds = BlockBounds::of(entries, axis);
        }
        if j > m {
            right = j - 1;
        } else if j < m {
            left = j + 1;
        } else {
            break;
        }
    }
}

/// The smallest range of [`select_blocks`] that keeps block bounds after a lopsided pass.
const SUMMARY_MIN: usize = 4_096;

/// Per aligned block of [`SCAN_BLOCK`] positions, a lower and an upper bound of its values
/// (empty: none kept).
#[derive(Default)]
struct BlockBounds {
    lo: Vec<Real>,
    hi: Vec<Real>,
}

impl BlockBounds {
    /// The blocks' least and greatest values on `axis`.
    fn of<T>(entries: &Entries<'_, T>, axis: usize) -> BlockBounds {
        let (lo, hi) = (entries.points.chunks(SCAN_BLOCK))
            .map(|block| {
                block
                    .iter()
                    .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p[axis]), hi.max(p[axis]))
                    })
            })
            .unzip();
        BlockBounds { lo, hi }
    }

    fn is_empty(&self) -> bool {
        self.lo.is_empty()
    }

    /// Swaps positions `i` and `j`, widening their blocks' bounds to their new values.
    fn swap<T>(&mut self, entries: &mut Entries<'_, T>, (i, j): (usize, usize), axis: usize) {
        entries.swap(i, j);
        if self.is_empty() {
            return;
        }
        for p in [i, j] {
            let (v, b) = (entries.v(p, axis), p / SCAN_BLOCK);
            self.lo[b] = self.lo[b].min(v);
            self.hi[b] = self.hi[b].max(v);
        }
    }

    /// The left scan's next position from `next`: past every whole block starting there whose
    /// values are all below `pivot`, before the block of `right` (whose value is at least the
    /// pivot: the scan ends there whatever the bounds say).
    fn pass_below(&self, mut next: usize, pivot: Real, right: usize) -> usize {
        while next.is_multiple_of(SCAN_BLOCK)
            && next + SCAN_BLOCK <= right
            && self.hi.get(next / SCAN_BLOCK).is_some_and(|&h| h < pivot)
        {
            next += SCAN_BLOCK;
        }
        next
    }

    /// The right scan's next position from `next` (descending): past every whole block ending
    /// there whose values are all above `pivot`, after the block of `left`.
    fn pass_above(&self, mut next: isize, pivot: Real, left: usize) -> isize {
        while next >= (left + SCAN_BLOCK) as isize
            && next as usize % SCAN_BLOCK == SCAN_BLOCK - 1
            && self
                .lo
                .get(next as usize / SCAN_BLOCK)
                .is_some_and(|&l| l > pivot)
        {
            next -= SCAN_BLOCK as isize;
        }
        next
    }
}

/// Kratos' cut value: the mean of the largest value left of the median (first maximum, strict
/// `>` scan from the start) and the median, except when that maximum is the first entry, where Kratos'
/// iterator slip makes it the median itself (reference §6.1). Either is a valid separator:
/// left values are `<= cut`, right values `>= cut`.
fn cut_value<T>(entries: &Entries<'_, T>, m: usize, axis: usize) -> Real {
    let mut k = 0;
    for i in 1..m {
        if entries.v(i, axis) > entries.v(k, axis) {
            k = i;
        }
    }
    let median = entries.v(m, axis);
    if k == 0 {
        return median;
    }
    let below = entries.v(k, axis);
    let mean = (below + median) / 2.0;
    if mean.is_finite() {
        mean
    } else {
        // Overflow of the sum near Real::MAX; stays within [below, median].
        below / 2.0 + median / 2.0
    }
}
