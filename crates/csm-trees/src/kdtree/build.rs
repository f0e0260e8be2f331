//! Construction of the kd-tree (reference §6.1): split on the axis of largest spread at the
//! median found by Kratos' Hoare quickselect, with Kratos' cut value.

use csm_geometry::math::{Point, Real};

use super::tree::Node;

/// Builds the tree over the parallel arrays `items`/`points` (permuting them) into `nodes` and
/// returns the root, `None` when there is no point.
///
/// `bucket_size >= 1` and `points.len() <= u32::MAX / 2` are checked by the caller.
pub(super) fn build<T: Copy>(
    items: &mut [T],
    points: &mut [Point],
    nodes: &mut Vec<Node>,
    bucket_size: usize,
) -> Option<u32> {
    debug_assert!(bucket_size >= 1);
    debug_assert_eq!(items.len(), points.len());
    if points.is_empty() {
        return None;
    }
    let n = points.len();
    let mut entries = Entries { items, points };
    Some(build_range(&mut entries, nodes, 0, n, bucket_size))
}

/// The two parallel arrays, swapped together.
struct Entries<'a, T> {
    items: &'a mut [T],
    points: &'a mut [Point],
}

impl<T> Entries<'_, T> {
    fn swap(&mut self, i: usize, j: usize) {
        self.items.swap(i, j);
        self.points.swap(i, j);
    }

    fn v(&self, i: usize, axis: usize) -> Real {
        self.points[i][axis]
    }
}

/// Builds the subtree over the non-empty range `b..e` and returns its node index.
fn build_range<T>(
    entries: &mut Entries<'_, T>,
    nodes: &mut Vec<Node>,
    b: usize,
    e: usize,
    bucket_size: usize,
) -> u32 {
    debug_assert!(b < e);
    let n = e - b;
    // Fits: there are fewer than 2·len nodes and the caller checked len <= u32::MAX / 2.
    let index = nodes.len() as u32;
    if n <= bucket_size {
        nodes.push(Node::Leaf {
            start: b as u32,
            end: e as u32,
        });
        return index;
    }
    let axis = widest_axis(entries.points, b, e);
    let m = b + n / 2;
    select(entries, b, e, m, axis);
    let cut = cut_value(entries, b, m, axis);
    // Placeholder, filled once the children exist.
    nodes.push(Node::Leaf { start: 0, end: 0 });
    let left = build_range(entries, nodes, b, m, bucket_size);
    let right = build_range(entries, nodes, m, e, bucket_size);
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

/// The axis of maximum spread `max p[k] − min p[k]` over `b..e`; ties go to the lowest axis
/// (Kratos compares spreads with a strict `>`, starting from axis 0).
fn widest_axis(points: &[Point], b: usize, e: usize) -> usize {
    let mut lo = points[b];
    let mut hi = points[b];
    for p in &points[b + 1..e] {
        for k in 0..3 {
            if p[k] < lo[k] {
                lo[k] = p[k];
            }
            if p[k] > hi[k] {
                hi[k] = p[k];
            }
        }
    }
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

/// Kratos' Hoare-style quickselect on `axis` over `b..e`: afterwards position `m` holds the
/// value it would hold in sorted order, everything before it is `<=` and everything after it
/// `>=` (reference §6.1, reproduced step by step so that the permutation matches Kratos').
fn select<T>(entries: &mut Entries<'_, T>, b: usize, e: usize, m: usize, axis: usize) {
    let mut left = b;
    let mut right = e - 1;
    while left < right {
        let mut i = left;
        if entries.v(i, axis) > entries.v(right, axis) {
            entries.swap(i, right);
        }
        let pivot = entries.v(i, axis);
        let mut j = right;
        loop {
            // `v(right) >= pivot` stops `i` at `right` at the latest, `v(left) == pivot`
            // stops `j` at `left` at the latest.
            loop {
                i += 1;
                if entries.v(i, axis) >= pivot {
                    break;
                }
            }
            loop {
                j -= 1;
                if entries.v(j, axis) <= pivot {
                    break;
                }
            }
            if i < j {
                entries.swap(i, j);
            } else {
                break;
            }
        }
        entries.swap(left, j);
        if j > m {
            right = j - 1;
        } else if j < m {
            left = j + 1;
        } else {
            break;
        }
    }
}

/// Kratos' cut value: the mean of the largest value left of the median (first maximum, strict
/// `>` scan from `b`) and the median, except when that maximum is at `b`, where Kratos'
/// iterator slip makes it the median itself (reference §6.1). Either is a valid separator:
/// left values are `<= cut`, right values `>= cut`.
fn cut_value<T>(entries: &Entries<'_, T>, b: usize, m: usize, axis: usize) -> Real {
    let mut k = b;
    for i in b + 1..m {
        if entries.v(i, axis) > entries.v(k, axis) {
            k = i;
        }
    }
    let median = entries.v(m, axis);
    if k == b {
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
