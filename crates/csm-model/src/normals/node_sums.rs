//! The nodal sums of the faces' normals, blocked by node and in parallel.

use csm_geometry::math::Vector;
use rayon::prelude::*;

use crate::NodeIdx;

/// Adds `normal` to a node's sum `sum`, of which `count` normals were added before: the first
/// one to zero (the sum's old value is not a sum of these faces).
pub(super) fn add_first_zero(sum: &mut Vector, count: &mut u32, normal: Vector) {
    if *count == 0 {
        *sum = Vector::zeros();
    }
    *sum += normal;
    *count += 1;
}

/// Per node, the sum of the normals of its faces in face order (into `sums`, where a node of
/// no face keeps its value) and the number of its faces (into `count`, zero on entry): the
/// blocked, parallel sums of [`FaceNormals::nodal_sums`] over `n_faces` faces, face `f` with
/// the nodes `face_nodes(f)`, its node `k` with the normal `normal(reference(f, k))` (a
/// reference fits 32 bits, so the contributions stay small). With `wanted`, only the nodes
/// it marks (by node index) are summed and counted.
pub(super) fn sums_by_node_blocks<'a>(
    (sums, count): (&mut [Vector], &mut [u32]),
    (n_faces, wanted): (usize, Option<&[bool]>),
    face_nodes: impl Fn(usize) -> &'a [NodeIdx] + Sync,
    (reference, normal): (
        impl Fn(usize, usize) -> u32 + Sync,
        impl Fn(u32) -> Vector + Sync,
    ),
    faces_per_chunk: usize,
) {
    let block_of = |node: usize| node >> NODE_BLOCK_BITS;
    let n_blocks = block_of(sums.len()) + 1;
    let faces = faces_per_chunk.max(1);
    let chunks: Vec<SortedChunk> = (0..n_faces.div_ceil(faces))
        .into_par_iter()
        .map(|chunk| {
            let range = chunk * faces..((chunk + 1) * faces).min(n_faces);
            // A counting pass, then the contributions placed in face order per block. With
            // `wanted`, the counting pass lists the faces with a wanted node (usually few),
            // and only these are read again.
            let mut start = vec![0usize; n_blocks + 1];
            let is_wanted = |node: &NodeIdx| wanted.is_none_or(|w| w[node.index()]);
            let mut hit = Vec::new();
            for f in range.clone() {
                let mut any = false;
                for node in face_nodes(f).iter().filter(|n| is_wanted(n)) {
                    start[block_of(node.index()) + 1] += 1;
                    any = true;
                }
                if any && wanted.is_some() {
                    hit.push(f);
                }
            }
            for b in 0..n_blocks {
                start[b + 1] += start[b];
            }
            let mut next = start.clone();
            let mut contributions = vec![(0u32, 0u32); start[n_blocks]];
            let mut place = |f: usize| {
                for (k, node) in face_nodes(f).iter().enumerate() {
                    if !is_wanted(node) {
                        continue;
                    }
                    let slot = &mut next[block_of(node.index())];
                    contributions[*slot] = (node.get(), reference(f, k));
                    *slot += 1;
                }
            };
            match wanted {
                Some(_) => hit.into_iter().for_each(&mut place),
                None => range.for_each(&mut place),
            }
            SortedChunk {
                start,
                contributions,
            }
        })
        .collect();
    let add_block = |b: usize, (sums, count): (&mut [Vector], &mut [u32])| {
        let first = b << NODE_BLOCK_BITS;
        for chunk in &chunks {
            for &(node, r) in &chunk.contributions[chunk.start[b]..chunk.start[b + 1]] {
                let i = node as usize - first;
                add_first_zero(&mut sums[i], &mut count[i], normal(r));
            }
        }
    };
    // A few contributions (the wanted nodes of a side) are added on this thread: handing the
    // blocks to the pool costs more than the additions.
    let total: usize = chunks.iter().map(|c| c.contributions.len()).sum();
    let size = 1 << NODE_BLOCK_BITS;
    if total < SERIAL_CONTRIBUTIONS {
        (sums.chunks_mut(size).zip(count.chunks_mut(size)))
            .enumerate()
            .for_each(|(b, block)| add_block(b, block));
    } else {
        (sums.par_chunks_mut(size).zip(count.par_chunks_mut(size)))
            .enumerate()
            .for_each(|(b, block)| add_block(b, block));
    }
}

/// Below this many contributions [`sums_by_node_blocks`] adds them on one thread.
pub(super) const SERIAL_CONTRIBUTIONS: usize = 1 << 15;

/// One chunk of faces' (node, normal) contributions of [`FaceNormals::nodal_sums`], sorted by
/// node block (face order within a block): block `b`'s are `contributions[start[b]..start[b + 1]]`.
pub(super) struct SortedChunk {
    start: Vec<usize>,
    contributions: Vec<(u32, u32)>,
}

/// log2 of the nodes per block of [`FaceNormals::nodal_sums`] (a block's sums and counts,
/// ~230 KB, stay in a core's cache).
pub(super) const NODE_BLOCK_BITS: u32 = 13;

/// The top bit of a contribution's normal reference in [`FaceNormals::nodal_sums`]: set for
/// an entry of the nodal table, clear for a face's centre normal.
pub(super) const NODAL_ENTRY: u32 = 1 << 31;

/// The most chunks of faces [`FaceNormals::nodal_sums`] sorts its contributions in.
pub(super) const MAX_SUM_CHUNKS: usize = 64;
