//! Kratos' Hoare quickselect (reference §6.1), the kd-tree build's median: one thread's
//! block-listing passes, and, for large ranges on a pool of several threads, passes that make
//! the same swaps in parallel (the top levels' medians are one chain of passes over every
//! point: on a mesh in grid order the first takes dozens of them).
//!
//! A pass of Kratos' partition (pivot `v(left)`, after `left` and `right` are put in order)
//! swaps, for `k = 0, 1, …`, the `k`-th left stop `L[k]` (`v >= pivot`, ascending from
//! `left + 1`) with the `k`-th right stop `R[k]` (`v <= pivot`, descending from `right − 1`)
//! while `L[k] < R[k]`, and ends at `j = max(R[K], L[K − 1])` for the first `K` where not
//! (`L[−1] = left`). Until the crossing the scans pass only positions no swap has touched, so
//! the stops are those of the values before the pass. [`select_blocks`] lists them a block at
//! a time on one thread; [`parallel_pass`] counts them in parallel, finds `K` from the counts,
//! lists the `K` pairs in parallel and swaps them in parallel (they are disjoint).
//!
//! The parallel passes first copy the values on the split axis into a column of their own,
//! swapped with the entries: a pass then reads 8 bytes a position instead of a point's 24
//! (the passes of a large range are bound by memory traffic).

use csm_geometry::math::{Point, Real};
use rayon::prelude::*;

use super::build::Entries;

/// On a pool of at least [`PARALLEL_THREADS_MIN`] threads, ranges of at least this many
/// points copy their values on the axis into a column and partition in parallel passes;
/// smaller ones, and every range on a smaller pool, in [`select_blocks`] on the points. (On
/// two threads a parallel pass, which reads the values once to count the stops and once to
/// list them, takes as long as one thread's pass, and the column's copy costs more than it
/// saves: measured on the demo 4e5, the sphere 2e5 and the blocks 1e5.)
const PARALLEL_PASS_MIN: usize = 65_536;

/// The smallest pool whose selects make parallel passes.
const PARALLEL_THREADS_MIN: usize = 4;

/// Positions per task of a parallel pass's count and listing.
const PASS_CHUNK: usize = 16_384;

/// Swaps per task of a parallel pass (fewer in all are made on the calling thread).
const SWAP_TASK: usize = 4_096;

/// When [`select_with`] copies the values into a column and makes parallel passes, and how
/// it shares a parallel pass out.
#[derive(Clone, Copy, Debug)]
pub(super) struct SelectSizes {
    /// The smallest range that copies its values on the axis into a column first.
    pub(super) keyed_min: usize,
    /// The smallest keyed range partitioned in parallel passes.
    pub(super) parallel_min: usize,
    /// Positions per counting and listing task.
    pub(super) chunk: usize,
    /// Swaps per swapping task.
    pub(super) swap_task: usize,
}

/// Kratos' quickselect on `axis` over the non-empty `entries`: afterwards position `m` holds
/// the value it would hold in sorted order, everything before it is `<=` and everything after
/// it `>=`, and the permutation is Kratos' for any thread count.
pub(super) fn select<T: Send>(entries: &mut Entries<'_, T>, m: usize, axis: usize) {
    let parallel_min = if rayon::current_num_threads() >= PARALLEL_THREADS_MIN {
        PARALLEL_PASS_MIN
    } else {
        usize::MAX
    };
    let sizes = SelectSizes {
        keyed_min: parallel_min,
        parallel_min,
        chunk: PASS_CHUNK,
        swap_task: SWAP_TASK,
    };
    select_with(entries, m, axis, sizes);
}

/// [`select`] with its sizes.
pub(super) fn select_with<T: Send>(
    entries: &mut Entries<'_, T>,
    m: usize,
    axis: usize,
    sizes: SelectSizes,
) {
    let n = entries.len();
    if n < sizes.keyed_min {
        select_blocks(&mut OnAxis { entries, axis }, m);
        return;
    }
    let mut keys: Vec<Real> = entries.points.par_iter().map(|p| p[axis]).collect();
    let mut keyed = Keyed {
        items: entries.items,
        points: entries.points,
        keys: &mut keys,
    };
    let (chunk, swap_task) = (sizes.chunk.max(1), sizes.swap_task.max(1));
    let (mut left, mut right) = (0, n - 1);
    let mut lists = PassLists::default();
    while left < right {
        let mut range = keyed.range(left, right);
        if right - left + 1 < sizes.parallel_min {
            // The passes on `left..=right` alone, as the loop below would make them.
            select_blocks(&mut range, m - left);
            return;
        }
        let j = left + parallel_pass(&mut range, (chunk, swap_task), &mut lists);
        if j > m {
            right = j - 1;
        } else if j < m {
            left = j + 1;
        } else {
            return;
        }
    }
}

/// What a pass of the partition reads and swaps.
trait Partition {
    /// The number of positions.
    fn len(&self) -> usize;
    /// The value at position `i` on the split axis.
    fn v(&self, i: usize) -> Real;
    /// Swaps positions `i` and `j`.
    fn swap(&mut self, i: usize, j: usize);
}

/// The entries, their values read from the points.
struct OnAxis<'e, 'a, T> {
    entries: &'e mut Entries<'a, T>,
    axis: usize,
}

impl<T> Partition for OnAxis<'_, '_, T> {
    fn len(&self) -> usize {
        self.entries.len()
    }

    fn v(&self, i: usize) -> Real {
        self.entries.v(i, self.axis)
    }

    fn swap(&mut self, i: usize, j: usize) {
        self.entries.swap(i, j);
    }
}

/// The entries with their values on the split axis in a column of their own.
struct Keyed<'a, T> {
    items: &'a mut [T],
    points: &'a mut [Point],
    keys: &'a mut [Real],
}

impl<T> Keyed<'_, T> {
    /// The positions `left..=right`.
    fn range(&mut self, left: usize, right: usize) -> Keyed<'_, T> {
        Keyed {
            items: &mut self.items[left..=right],
            points: &mut self.points[left..=right],
            keys: &mut self.keys[left..=right],
        }
    }
}

impl<T> Partition for Keyed<'_, T> {
    fn len(&self) -> usize {
        self.keys.len()
    }

    fn v(&self, i: usize) -> Real {
        self.keys[i]
    }

    fn swap(&mut self, i: usize, j: usize) {
        self.items.swap(i, j);
        self.points.swap(i, j);
        self.keys.swap(i, j);
    }
}

/// The buffers of [`parallel_pass`], kept between the passes of one select.
#[derive(Default)]
struct PassLists {
    /// The pass's left stops `L[0..K]`.
    lefts: Vec<u32>,
    /// The pass's right stops `R[0..=K]`.
    rights: Vec<u32>,
}

/// One pass of Kratos' partition over the whole `entries` (at least two), in parallel: the
/// same swaps as [`select_blocks`]' pass, then the pivot's to `j`; returns `j`.
/// `(chunk, swap_task)`: positions per counting and listing task, swaps per swapping task.
fn parallel_pass<T: Send>(
    entries: &mut Keyed<'_, T>,
    (chunk, swap_task): (usize, usize),
    lists: &mut PassLists,
) -> usize {
    let len = entries.len();
    let last = len - 1;
    if entries.v(0) > entries.v(last) {
        entries.swap(0, last);
    }
    let pivot = entries.v(0);
    let keys: &[Real] = entries.keys;
    // Left stops lie in 1..=last, right stops in 0..last.
    let is_left = |p: usize| usize::from(p != 0 && keys[p] >= pivot);
    let is_right = |p: usize| usize::from(p != last && keys[p] <= pivot);
    // Per chunk: its left and right stops, counted without branches (position 0, the pivot,
    // is a right stop and no left stop; position `last` a left stop and no right stop).
    let mut counts: Vec<(usize, usize)> = (keys.par_chunks(chunk))
        .map(|block| {
            let (mut l, mut r) = (0, 0);
            for &v in block {
                l += usize::from(v >= pivot);
                r += usize::from(v <= pivot);
            }
            (l, r)
        })
        .collect();
    let n_chunks = counts.len();
    counts[0].0 -= 1;
    counts[n_chunks - 1].1 -= usize::from(keys[last] <= pivot);
    // Stops before each chunk.
    let mut before = Vec::with_capacity(n_chunks + 1);
    let (mut sum_l, mut sum_r) = (0, 0);
    for &(l, r) in &counts {
        before.push((sum_l, sum_r));
        sum_l += l;
        sum_r += r;
    }
    before.push((sum_l, sum_r));
    // `L[k] < R[k]` iff `φ(L[k] + 1) >= 0`, φ(b) = (right stops at `>= b`) − (left stops at
    // `< b`), which never grows with `b`: the pairs swapped are those of the left stops before
    // `b*`, the last `b` with φ(b) >= 0 (φ(0) >= 0). Found between the chunks' bounds, then
    // position by position in the chunk where φ turns negative.
    let phi = |c: usize| (sum_r - before[c].1) as isize - before[c].0 as isize;
    let c = (0..=n_chunks).rev().find(|&c| phi(c) >= 0).unwrap_or(0);
    let (mut b, mut f, mut k) = (c * chunk, phi(c), before[c].0);
    while b <= last {
        let (l, r) = (is_left(b), is_right(b));
        let next = f - (l + r) as isize;
        if next < 0 {
            break;
        }
        (f, k, b) = (next, k + l, b + 1);
    }
    // `K = k` pairs swapped; the pass ends at `max(R[K], L[K − 1])`. (`K` is below the number
    // of right stops: the right stop at 0 is below `b*` unless `b* = 0`, where `K = 0`.)
    let swaps = k;
    let PassLists { lefts, rights } = lists;
    lefts.clear();
    lefts.resize(swaps, 0);
    rights.clear();
    rights.resize(swaps + 1, 0);
    // Each chunk's share of the lists: its left stops of rank `< K` (ranks ascending from
    // position 0) and its right stops of rank `<= K` (ranks ascending from `last − 1` down).
    let mut parts: Vec<(&mut [u32], &mut [u32])> = Vec::with_capacity(n_chunks);
    let mut rest = lefts.as_mut_slice();
    for c in 0..n_chunks {
        let n = before[c + 1].0.min(swaps) - before[c].0.min(swaps);
        let (part, tail) = std::mem::take(&mut rest).split_at_mut(n);
        parts.push((part, Default::default()));
        rest = tail;
    }
    let mut rest = rights.as_mut_slice();
    for c in (0..n_chunks).rev() {
        let above = sum_r - before[c + 1].1;
        let n = (above + counts[c].1).min(swaps + 1) - above.min(swaps + 1);
        let (part, tail) = std::mem::take(&mut rest).split_at_mut(n);
        parts[c].1 = part;
        rest = tail;
    }
    (parts.into_par_iter().enumerate())
        .filter(|(_, (ls, rs))| !ls.is_empty() || !rs.is_empty())
        .for_each(|(c, (ls, rs))| {
            let (start, end) = (c * chunk, ((c + 1) * chunk).min(len));
            // (Positions fit in u32: the tree's caller checked the length.)
            let mut filled = 0;
            for p in start..end {
                if filled == ls.len() {
                    break;
                }
                if is_left(p) == 1 {
                    ls[filled] = p as u32;
                    filled += 1;
                }
            }
            let mut filled = 0;
            for p in (start..end).rev() {
                if filled == rs.len() {
                    break;
                }
                if is_right(p) == 1 {
                    rs[filled] = p as u32;
                    filled += 1;
                }
            }
        });
    let j = (rights[swaps] as usize).max(lefts.last().map_or(0, |&l| l as usize));
    swap_pairs(entries, (lefts, &rights[..swaps]), b, swap_task);
    entries.swap(0, j);
    j
}

/// Swaps `entries` at `lefts[k]` and `rights[k]` for every `k`: `lefts` ascending and below
/// `split`, `rights` descending and from `split` on, so the pairs are disjoint. In tasks of
/// `swap_task` pairs, each with the two ranges of positions its pairs lie in.
fn swap_pairs<T: Send>(
    entries: &mut Keyed<'_, T>,
    (lefts, rights): (&[u32], &[u32]),
    split: usize,
    swap_task: usize,
) {
    let n = lefts.len();
    if n < 2 * swap_task {
        for (&l, &r) in lefts.iter().zip(rights) {
            entries.swap(l as usize, r as usize);
        }
        return;
    }
    let tasks = n.div_ceil(swap_task);
    let pairs = |t: usize| t * swap_task..((t + 1) * swap_task).min(n);
    // Task `t`'s positions: below `split` from its first left stop on (0 for the first task),
    // from `split` on from its last right stop on (`split` for the last task), each up to the
    // next task's.
    let bounds = Bounds {
        split,
        tasks,
        low_start: &|t| {
            if t == 0 {
                0
            } else {
                lefts[t * swap_task] as usize
            }
        },
        high_start: &|t| {
            if t + 1 == tasks {
                split
            } else {
                rights[pairs(t).end - 1] as usize
            }
        },
    };
    let items = bounds.parts(entries.items);
    let points = bounds.parts(entries.points);
    let keys = bounds.parts(entries.keys);
    (items.into_par_iter().zip(points).zip(keys).enumerate()).for_each(
        |(t, (((li, hi), (lp, hp)), (lk, hk)))| {
            let (low, high) = ((bounds.low_start)(t), (bounds.high_start)(t));
            for k in pairs(t) {
                let (a, b) = (lefts[k] as usize - low, rights[k] as usize - high);
                std::mem::swap(&mut li[a], &mut hi[b]);
                std::mem::swap(&mut lp[a], &mut hp[b]);
                std::mem::swap(&mut lk[a], &mut hk[b]);
            }
        },
    );
}

/// Where [`swap_pairs`]' tasks lie: below `split`, task `t` from `low_start(t)` to the next
/// task's start; from `split` on, from `high_start(t)` to the previous task's start (the end
/// for the first).
struct Bounds<'a> {
    split: usize,
    tasks: usize,
    low_start: &'a (dyn Fn(usize) -> usize + Sync),
    high_start: &'a (dyn Fn(usize) -> usize + Sync),
}

impl Bounds<'_> {
    /// Each task's two parts of `all`.
    fn parts<'s, U>(&self, all: &'s mut [U]) -> Vec<(&'s mut [U], &'s mut [U])> {
        let (mut low, mut high) = all.split_at_mut(self.split);
        let mut parts = Vec::with_capacity(self.tasks);
        for t in 0..self.tasks {
            let low_len = if t + 1 == self.tasks {
                low.len()
            } else {
                (self.low_start)(t + 1) - (self.low_start)(t)
            };
            let (task_low, rest) = std::mem::take(&mut low).split_at_mut(low_len);
            low = rest;
            let (rest, task_high) =
                std::mem::take(&mut high).split_at_mut((self.high_start)(t) - self.split);
            high = rest;
            parts.push((task_low, task_high));
        }
        parts
    }
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
fn select_blocks<P: Partition>(entries: &mut P, m: usize) {
    let mut left = 0;
    let mut right = entries.len() - 1;
    let mut lbuf = [0usize; SCAN_BLOCK];
    let mut rbuf = [0usize; SCAN_BLOCK];
    while left < right {
        if entries.v(left) > entries.v(right) {
            entries.swap(left, right);
        }
        let pivot = entries.v(left);
        // Next position to list on each side, and the listed stops not yet paired.
        let (mut lnext, mut rnext) = (left + 1, right as isize - 1);
        let (mut lbeg, mut lend, mut rbeg, mut rend) = (0, 0, 0, 0);
        // The previous left stop (`left` before the first).
        let mut last_l = left;
        let j = loop {
            if lbeg == lend {
                // `v(right) >= pivot`: the list ends there at the latest.
                lbeg = 0;
                lend = 0;
                let stop = (lnext + SCAN_BLOCK).min(right + 1);
                for p in lnext..stop {
                    lbuf[lend] = p;
                    lend += usize::from(entries.v(p) >= pivot);
                }
                lnext = stop;
            }
            if rbeg == rend {
                // `v(left) == pivot`: the list ends there at the latest.
                rbeg = 0;
                rend = 0;
                let stop = (rnext - SCAN_BLOCK as isize).max(left as isize - 1);
                let mut p = rnext;
                while p > stop {
                    rbuf[rend] = p as usize;
                    rend += usize::from(entries.v(p as usize) <= pivot);
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
                entries.swap(l, r);
                last_l = l;
                lbeg += 1;
                rbeg += 1;
            } else {
                break r.max(last_l);
            }
        };
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
