//! Parallel writes at ascending positions of an array ([`write_at_ascending`]): the scatter
//! of a part's values (its nodes and conditions are listed in ascending dense index) into a
//! column of the whole model, without a serial pass.

use rayon::prelude::*;

/// Items below which [`write_at_ascending`] writes on one thread.
const SERIAL_ITEMS: usize = 1 << 12;

/// Calls `write(k, &mut target[at(k)])` for every `k` in `0..n`, in parallel on rayon's pool
/// where the positions `at(0) < at(1) < …` ascend (the target is cut between them, so each
/// task owns its piece), else in order on one thread. Each position is written once, by its
/// own `k`: the result does not depend on the order, and is that of the loop
/// `for k in 0..n { write(k, &mut target[at(k)]) }`.
///
/// Panics where a position is out of `target` (as the loop would).
pub fn write_at_ascending<T: Send>(
    target: &mut [T],
    n: usize,
    at: impl Fn(usize) -> usize + Sync,
    write: impl Fn(usize, &mut T) + Sync,
) {
    // (One thread writes in order without checking the order first.)
    let serial = n < SERIAL_ITEMS
        || rayon::current_num_threads() < 2
        || !(1..n).into_par_iter().all(|k| at(k - 1) < at(k));
    if serial {
        for k in 0..n {
            write(k, &mut target[at(k)]);
        }
        return;
    }
    split_writes(target, (0, 0..n), &at, &write);
}

/// [`write_at_ascending`] of the items `items` into `target`, the piece of the whole array
/// that starts at position `offset`.
fn split_writes<T: Send>(
    target: &mut [T],
    (offset, items): (usize, std::ops::Range<usize>),
    at: &(impl Fn(usize) -> usize + Sync),
    write: &(impl Fn(usize, &mut T) + Sync),
) {
    if items.len() <= SERIAL_ITEMS {
        for k in items {
            write(k, &mut target[at(k) - offset]);
        }
        return;
    }
    let mid = items.start + items.len() / 2;
    // Every item before `mid` is below `at(mid)`, every other at or above it.
    let cut = (at(mid) - offset).min(target.len());
    let (low, high) = target.split_at_mut(cut);
    rayon::join(
        || split_writes(low, (offset, items.start..mid), at, write),
        || split_writes(high, (offset + cut, mid..items.end), at, write),
    );
}

/// Copies `parts`, one after the other, into `out` (as long as they are together), each part
/// by a task of its own on rayon's pool: a fresh list's pages are first touched by the thread
/// that copies into them, not by one thread for all.
///
/// Panics where `out` is not as long as the parts together.
pub fn copy_parts_into<T: Copy + Send + Sync>(out: &mut [T], parts: &[Vec<T>]) {
    assert_eq!(out.len(), parts.iter().map(Vec::len).sum::<usize>());
    let mut rest = out;
    let mut places = Vec::with_capacity(parts.len());
    for part in parts {
        let (place, tail) = rest.split_at_mut(part.len());
        places.push((place, part.as_slice()));
        rest = tail;
    }
    places
        .into_par_iter()
        .for_each(|(place, part)| place.copy_from_slice(part));
}

/// The items of `parts`, one part after the other, each mapped by `map`, as one list written
/// in one parallel pass: its pages are first touched by the threads that write them, where a
/// serial join of the parts would copy every item on one thread into fresh memory. Each task
/// finds the part of its first position, then the next part as it passes the end of one.
pub fn concat_parts_with<P, T, U>(parts: &[P], map: impl Fn(&T) -> U + Sync + Send) -> Vec<U>
where
    P: AsRef<[T]> + Sync,
    U: Send,
{
    // `starts[r]`: the position of part `r`'s first item in the list.
    let mut starts = Vec::with_capacity(parts.len() + 1);
    starts.push(0);
    for part in parts {
        starts.push(starts[starts.len() - 1] + part.as_ref().len());
    }
    let total = starts[parts.len()];
    (0..total)
        .into_par_iter()
        .map_init(
            || 0,
            |r: &mut usize, k| {
                // (Positions come in order within a task: past the end of its part, the
                // next part with items; where the task starts, a search.)
                if k == starts[*r + 1] {
                    while starts[*r + 1] <= k {
                        *r += 1;
                    }
                } else if !(starts[*r] <= k && k < starts[*r + 1]) {
                    *r = starts.partition_point(|&start| start <= k) - 1;
                }
                map(&parts[*r].as_ref()[k - starts[*r]])
            },
        )
        .collect()
}

/// Items from which [`par_clone`] copies on rayon's pool.
const PARALLEL_CLONE_ITEMS: usize = 1 << 15;

/// A copy of `items`, made by rayon's pool where they are many: a fresh list's pages are
/// first touched by the threads that copy into them (as in [`copy_parts_into`]). The big
/// columns of a model are cloned this way.
pub(crate) fn par_clone<T: Clone + Send + Sync>(items: &[T]) -> Vec<T> {
    if items.len() < PARALLEL_CLONE_ITEMS {
        return items.to_vec();
    }
    items.par_iter().cloned().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The serial loop: the oracle.
    fn serial(len: usize, positions: &[usize]) -> Vec<u64> {
        let mut v = vec![0u64; len];
        for (k, &p) in positions.iter().enumerate() {
            v[p] = v[p] * 31 + k as u64 + 1;
        }
        v
    }

    fn parallel(len: usize, positions: &[usize], threads: usize) -> Vec<u64> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut v = vec![0u64; len];
        pool.install(|| {
            write_at_ascending(
                &mut v,
                positions.len(),
                |k| positions[k],
                |k, x| *x = *x * 31 + k as u64 + 1,
            );
        });
        v
    }

    #[test]
    fn ascending_positions_get_the_loops_values_on_any_pool() {
        // Every third position of a large array, and a dense run at its end.
        let mut positions: Vec<usize> = (0..40_000).map(|k| 3 * k + 1).collect();
        positions.extend(120_000..130_000);
        for threads in [1, 2, 3] {
            assert_eq!(
                parallel(130_001, &positions, threads),
                serial(130_001, &positions)
            );
        }
    }

    #[test]
    fn positions_out_of_order_or_repeated_fall_back_to_the_loop() {
        // Repeated positions: the loop's last-wins-after-combining order matters here.
        let mut positions: Vec<usize> = (0..20_000).map(|k| (k * 7919) % 10_007).collect();
        positions.extend(0..5_000);
        for threads in [1, 2] {
            assert_eq!(
                parallel(10_007, &positions, threads),
                serial(10_007, &positions)
            );
        }
    }

    #[test]
    fn parts_are_copied_in_order() {
        let parts: Vec<Vec<u32>> = (0..50)
            .map(|k| (0..k * 37).map(|i| i + k).collect())
            .collect();
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = vec![0u32; parts.iter().map(Vec::len).sum()];
            pool.install(|| copy_parts_into(&mut out, &parts));
            assert_eq!(out, parts.concat());
        }
    }

    /// The parts joined in parallel are the parts one after the other, mapped: empty parts
    /// among them, parts of one item and of thousands, on pools of 1–3 threads.
    #[test]
    fn parts_are_joined_in_order_on_any_pool() {
        let sizes = [0, 3, 1, 0, 5000, 17, 0, 1, 2048, 9000, 0];
        let mut next = 0u32;
        let parts: Vec<Vec<u32>> = sizes
            .iter()
            .map(|&n| {
                let part = (next..next + n).map(|v| v * 7 % 10_007).collect();
                next += n;
                part
            })
            .collect();
        let expected: Vec<u64> = parts.iter().flatten().map(|&v| u64::from(v) * 3).collect();
        let triple = |v: &u32| u64::from(*v) * 3;
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| concat_parts_with(&parts, triple)), expected);
            assert!(
                pool.install(|| concat_parts_with(&parts[..1], triple))
                    .is_empty()
            );
            assert!(
                pool.install(|| concat_parts_with(&[] as &[Vec<u32>], triple))
                    .is_empty()
            );
        }
    }

    #[test]
    #[should_panic]
    fn a_position_past_the_end_panics_as_the_loop_does() {
        let positions: Vec<usize> = (0..10_000).map(|k| 2 * k).collect();
        parallel(15_000, &positions, 2);
    }
}
