//! Unit normals of conditions and nodes (Kratos `NormalCalculationUtils::CalculateUnitNormals`,
//! reference §17.2).
//!
//! 1. The historical nodal `NORMAL` of every node of the part's conditions is reset to zero.
//! 2. Every face condition (lines in 2D, surfaces in 3D) gets the unit normal at the local
//!    coordinates of its centre.
//! 3. Every node of every face condition accumulates the condition's unit normal at that
//!    node's local coordinates (not area weighted).
//! 4. Nodal normals are normalised. Kratos' serial branch normalises a node once per adjacent
//!    condition (Q38: repeated division by a number within a few ulp of 1, which can change
//!    last bits); [`NormalsMode::Kratos`] does the same, [`NormalsMode::Once`] normalises once.
//!
//! A condition of zero area or a node whose summed normal vanishes (opposite faces cancel) is
//! an error here; Kratos produces NaN or raises for INTERFACE nodes.

use csm_geometry::Geometry;
use csm_geometry::math::{EPS, Vector};
use rayon::prelude::*;

use crate::error::{EntityKind, Error, ErrorKind};
use crate::{
    ConditionIdx, Flag, GATHER_BLOCK, GatheredPoints, GeometryStamp, ModelPart, NodeIdx, PartIdx,
    VectorVar,
};

/// How nodal normals are normalised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NormalsMode {
    /// Once per adjacent condition, in condition order, as Kratos' serial branch (Q38).
    #[default]
    Kratos,
    /// Once per node.
    Once,
}

/// The conditions of `part`, or of the whole model when `None`, in ascending index order.
fn conditions_of(model: &ModelPart, part: Option<PartIdx>) -> Vec<ConditionIdx> {
    match part {
        Some(p) => model.part(p).conditions().to_vec(),
        None => (0..model.conditions().len() as u32)
            .map(ConditionIdx)
            .collect(),
    }
}

fn geometry_error(c: ConditionIdx, model: &ModelPart, source: csm_geometry::Error) -> Error {
    ErrorKind::Geometry {
        entity: EntityKind::Condition,
        id: model.conditions().ids()[c.index()],
        source,
    }
    .into()
}

/// The unit normals of many faces ([`face_unit_normals`]), stored flat: one centre normal per
/// face and the nodal normals only of faces whose normal varies over the face (affine faces —
/// Line2D2, Triangle3D3 — have one normal; [`FaceNormalsRef::node`] returns it for every node).
#[derive(Debug, Clone, Default)]
pub struct FaceNormals {
    conditions: Vec<ConditionIdx>,
    centres: Vec<Vector>,
    /// Per face, the end of its nodal normals in `nodes` (the start is the previous end).
    ends: Vec<u32>,
    nodes: Vec<Vector>,
    /// The model's geometry when the normals were computed ([`KeptFaceNormals::current_subset`]).
    stamp: GeometryStamp,
    /// The model's condition-normals stamp right after [`FaceNormals::set_condition_normals`]
    /// wrote these centre normals (0 before): while it is the same, the condition normals
    /// hold them ([`KeptFaceNormals::positions`]).
    normals_stamp: u64,
    /// Where [`compute_unit_normals`] returned this table: the `NORMAL` stamp
    /// ([`crate::NodalData::vector_stamp`]) right after it wrote the nodal normals of these
    /// faces, and the mode; while the stamp is the same, `NORMAL` holds them
    /// ([`compute_unit_normals_from_kept`]).
    nodal_written: Option<(u64, NormalsMode)>,
}

impl PartialEq for FaceNormals {
    /// The same faces with the same normals (wherever they were computed).
    fn eq(&self, other: &FaceNormals) -> bool {
        self.conditions == other.conditions
            && self.centres == other.centres
            && self.ends == other.ends
            && self.nodes == other.nodes
    }
}

/// One face of a [`FaceNormals`] table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceNormalsRef<'a> {
    /// The condition.
    pub condition: ConditionIdx,
    /// The unit normal at the local coordinates of the centre.
    pub centre: Vector,
    nodes: &'a [Vector],
    /// The position of `nodes` in the table's nodal normals.
    nodes_start: usize,
}

impl FaceNormalsRef<'_> {
    /// The unit normal at the local coordinates of the face's node `k` (node order).
    pub fn node(&self, k: usize) -> Vector {
        self.nodes.get(k).copied().unwrap_or(self.centre)
    }
}

impl FaceNormals {
    /// The number of faces.
    pub fn len(&self) -> usize {
        self.conditions.len()
    }

    /// Whether the table has no face.
    pub fn is_empty(&self) -> bool {
        self.conditions.is_empty()
    }

    /// The faces, in the order they were given to [`face_unit_normals`] (or to
    /// [`KeptFaceNormals::subset`]).
    pub fn iter(&self) -> impl Iterator<Item = FaceNormalsRef<'_>> + '_ {
        (0..self.conditions.len()).map(move |i| {
            let start = self.nodes_start(i);
            FaceNormalsRef {
                condition: self.conditions[i],
                centre: self.centres[i],
                nodes: &self.nodes[start..self.ends[i] as usize],
                nodes_start: start,
            }
        })
    }

    /// Per node of `model`, the sum of the nodal normals of its faces, added in the table's
    /// face order (Kratos' order), and the number of its faces (0: a node of no face).
    ///
    /// Cache-friendly and parallel, with the serial sums bit for bit: the (node, normal)
    /// contributions of each chunk of consecutive faces are first sorted by blocks of
    /// consecutive node indices, keeping the face order within each block (sequential writes;
    /// the chunks in parallel); each block then adds its contributions, chunk after chunk, into
    /// its own small slice of the sums (in parallel). Every node receives its faces' normals in
    /// face order, as a serial loop adds them.
    pub fn nodal_sums(&self, model: &ModelPart) -> (Vec<Vector>, Vec<u32>) {
        let n_nodes = model.nodes().len();
        let (mut sums, mut count) = (vec![Vector::zeros(); n_nodes], vec![0u32; n_nodes]);
        self.nodal_sums_into(model, &mut sums, &mut count);
        (sums, count)
    }

    /// [`FaceNormals::nodal_sums`] written into `sums` and `count` (by node index; `count`
    /// zero on entry): a node of no face keeps its value in `sums`, the others' are replaced.
    pub fn nodal_sums_into(&self, model: &ModelPart, sums: &mut [Vector], count: &mut [u32]) {
        // At most MAX_SUM_CHUNKS chunks: each has a start per node block, so that their
        // number times the blocks' stays small on a large mesh (any chunk size gives the
        // same sums).
        let faces = FACES_PER_TASK.max(self.conditions.len().div_ceil(MAX_SUM_CHUNKS));
        self.nodal_sums_in_chunks(model, faces, (sums, count));
    }

    /// [`FaceNormals::nodal_sums_into`] with the contributions sorted by chunks of
    /// `faces_per_chunk` faces (in parallel): each chunk sorts its own contributions by
    /// block, and each block then takes the chunks' contributions in chunk order — the face
    /// order.
    fn nodal_sums_in_chunks(
        &self,
        model: &ModelPart,
        faces_per_chunk: usize,
        (sums, count): (&mut [Vector], &mut [u32]),
    ) {
        if self.centres.len() >= NODAL_ENTRY as usize || self.nodes.len() >= NODAL_ENTRY as usize {
            return self.nodal_sums_serial_into(model, sums, count);
        }
        let conditions = model.conditions();
        // A contribution's normal is the face's centre normal (uniform faces) or an entry of
        // the nodal table, told apart by the top bit.
        let reference = |face: usize, k: usize| {
            if self.ends[face] == self.nodes_start(face) as u32 {
                face as u32
            } else {
                (self.nodes_start(face) + k) as u32 | NODAL_ENTRY
            }
        };
        let normal = |r: u32| {
            if r & NODAL_ENTRY == 0 {
                self.centres[r as usize]
            } else {
                self.nodes[(r & !NODAL_ENTRY) as usize]
            }
        };
        sums_by_node_blocks(
            (sums, count),
            (self.conditions.len(), None),
            |f| conditions.nodes(self.conditions[f].index()),
            (reference, normal),
            faces_per_chunk,
        );
    }

    /// The start of face `face`'s nodal normals in `nodes` (the previous face's end).
    fn nodes_start(&self, face: usize) -> usize {
        nodes_start(&self.ends, face)
    }

    /// [`FaceNormals::nodal_sums`] as one serial loop over the faces (the reference the
    /// blocked sums reproduce; used for tables too large for their references).
    pub fn nodal_sums_serial(&self, model: &ModelPart) -> (Vec<Vector>, Vec<u32>) {
        let n_nodes = model.nodes().len();
        let (mut sums, mut count) = (vec![Vector::zeros(); n_nodes], vec![0u32; n_nodes]);
        self.nodal_sums_serial_into(model, &mut sums, &mut count);
        (sums, count)
    }

    /// [`FaceNormals::nodal_sums_serial`] written as [`FaceNormals::nodal_sums_into`] writes.
    fn nodal_sums_serial_into(&self, model: &ModelPart, sums: &mut [Vector], count: &mut [u32]) {
        for face in self.iter() {
            let nodes = model.conditions().nodes(face.condition.index());
            for (k, node) in nodes.iter().enumerate() {
                add_first_zero(
                    &mut sums[node.index()],
                    &mut count[node.index()],
                    face.node(k),
                );
            }
        }
    }

    /// This table without its centre normals, kept for a later use on the same coordinates
    /// by a caller that set them as the condition normals ([`set_condition_normals`](
    /// Self::set_condition_normals); [`compute_unit_normals`] does): on a large triangle mesh
    /// a quarter of the memory. [`KeptFaceNormals::subset`] reads the centre normals back.
    pub fn keep(self) -> KeptFaceNormals {
        KeptFaceNormals {
            fingerprint: fingerprint(self.centres.len(), |i| self.centres[i]),
            stamp: self.stamp,
            conditions: self.conditions,
            ends: self.ends,
            nodes: self.nodes,
            normals_stamp: self.normals_stamp,
            nodal_written: self.nodal_written,
        }
    }

    /// Sets every face's condition normal ([`ModelPart::condition_normals`]) to its centre
    /// normal.
    pub fn set_condition_normals(&mut self, model: &mut ModelPart) {
        let condition_normals = model.condition_normals_mut();
        for face in self.iter() {
            condition_normals[face.condition.index()] = face.centre;
        }
        self.normals_stamp = model.condition_normals_stamp();
    }
}

/// A [`FaceNormals`] table without its centre normals ([`FaceNormals::keep`]), which the
/// model's condition normals hold.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KeptFaceNormals {
    conditions: Vec<ConditionIdx>,
    ends: Vec<u32>,
    nodes: Vec<Vector>,
    /// [`fingerprint`] of the centre normals, in face order.
    fingerprint: u64,
    /// The model's geometry when the normals were computed ([`KeptFaceNormals::
    /// current_subset`]).
    stamp: GeometryStamp,
    /// [`FaceNormals`]' condition-normals stamp.
    normals_stamp: u64,
    /// [`FaceNormals`]' `NORMAL` stamp and mode.
    nodal_written: Option<(u64, NormalsMode)>,
}

impl KeptFaceNormals {
    /// The table of the face conditions of `conditions` (in that order; other kinds are
    /// skipped, as [`face_unit_normals`] skips them) taken from this one, with the centre
    /// normals read from [`ModelPart::condition_normals`]: on the coordinates the table was
    /// computed on, bit for bit what [`face_unit_normals`] computes, without computing it
    /// again. `None` when one of those faces is not in this table, or when the condition
    /// normals of the table's faces are no longer the centre normals it was kept with (their
    /// fingerprint differs: the caller then computes them).
    pub fn subset(&self, model: &ModelPart, conditions: &[ConditionIdx]) -> Option<FaceNormals> {
        self.positions(model)?.subset(model, conditions)
    }

    /// [`subset`](Self::subset), also after other changes of the model (conditions added,
    /// the historical variables), as long as its geometry is the one the table was computed
    /// on ([`ModelPart::geometry_stamp`]: the node coordinates and the conditions' node
    /// orders) — and, as for `subset`, the condition normals still hold the table's centre
    /// normals. `None` otherwise.
    pub fn current_subset(
        &self,
        model: &ModelPart,
        conditions: &[ConditionIdx],
    ) -> Option<FaceNormals> {
        if !self.is_current(model) {
            return None;
        }
        let mut table = self.subset(model, conditions)?;
        table.stamp = self.stamp;
        Some(table)
    }

    /// Whether `model`'s geometry is the one the table was computed on (a table without a
    /// stamp never is).
    fn is_current(&self, model: &ModelPart) -> bool {
        self.stamp != GeometryStamp::default() && self.stamp == model.geometry_stamp()
    }

    /// Whether the model's condition normals hold this table's centre normals: nothing
    /// wrote them since this table set them, or else every condition has one and their
    /// fingerprint is the table's.
    fn holds_centres(&self, model: &ModelPart) -> bool {
        if self.normals_stamp != 0 && self.normals_stamp == model.condition_normals_stamp() {
            return true;
        }
        let centres = model.condition_normals();
        self.conditions.iter().all(|c| c.index() < centres.len())
            && fingerprint(self.conditions.len(), |i| {
                centres[self.conditions[i].index()]
            }) == self.fingerprint
    }

    /// Where this table's faces are, to take lists of its faces without a check each
    /// ([`KeptPositions`]); `None` when the condition normals no longer hold the table's
    /// centre normals (as for [`subset`](Self::subset)).
    pub fn positions(&self, model: &ModelPart) -> Option<KeptPositions<'_>> {
        if !self.holds_centres(model) {
            return None;
        }
        self.positions_checked(model)
    }

    /// [`positions`](Self::positions) once the condition normals are known to hold the
    /// table's centre normals (`None` where one of its faces is not a condition of `model`).
    fn positions_checked(&self, model: &ModelPart) -> Option<KeptPositions<'_>> {
        // A table of every condition in index order (the normal check's) is its own
        // position table.
        let n = model.conditions().len();
        let every = self.conditions.len() == n
            && self
                .conditions
                .iter()
                .enumerate()
                .all(|(i, c)| c.index() == i);
        let position = if every {
            None
        } else {
            let mut position = vec![ABSENT; n];
            for (i, c) in self.conditions.iter().enumerate() {
                *position.get_mut(c.index())? = i as u32;
            }
            Some(position)
        };
        Some(KeptPositions {
            table: self,
            position,
        })
    }
}

/// A condition's position in [`KeptPositions`] when it is not in the table.
const ABSENT: u32 = u32::MAX;

/// The position of every face of a [`KeptFaceNormals`] table, by condition index
/// ([`KeptFaceNormals::positions`]), checked against the condition normals once.
#[derive(Debug)]
pub struct KeptPositions<'a> {
    table: &'a KeptFaceNormals,
    /// By condition index; `None` where the table holds every condition in index order.
    position: Option<Vec<u32>>,
}

impl KeptPositions<'_> {
    /// The table position of condition `c`, if it is one of its faces.
    fn of(&self, c: ConditionIdx) -> Option<usize> {
        match &self.position {
            None => (c.index() < self.table.conditions.len()).then_some(c.index()),
            Some(position) => position
                .get(c.index())
                .filter(|&&i| i != ABSENT)
                .map(|&i| i as usize),
        }
    }

    /// [`KeptFaceNormals::subset`] of `conditions` (the checks done).
    fn subset(&self, model: &ModelPart, conditions: &[ConditionIdx]) -> Option<FaceNormals> {
        let (kinds, centres) = (model.conditions(), model.condition_normals());
        let kept = self.table;
        let mut table = FaceNormals::default();
        table.conditions.reserve(conditions.len());
        table.centres.reserve(conditions.len());
        table.ends.reserve(conditions.len());
        let mut end = 0u32;
        for &c in conditions {
            if !kinds.kind(c.index()).is_face() {
                continue;
            }
            let i = self.of(c)?;
            let nodes = &kept.nodes[nodes_start(&kept.ends, i)..kept.ends[i] as usize];
            table.conditions.push(c);
            table.centres.push(centres[c.index()]);
            table.nodes.extend_from_slice(nodes);
            end += nodes.len() as u32;
            table.ends.push(end);
        }
        Some(table)
    }

    /// [`FaceNormals::nodal_sums_into`] of the [`subset`](KeptFaceNormals::subset) of
    /// `conditions`, bit for bit, without building that table (its centre normals are the
    /// condition normals: nothing to set either). False, with nothing written, when one of
    /// the face conditions is not in the table. With `wanted`, the nodes it marks (by node
    /// index) at least, each with all its faces (others may be left out).
    pub fn nodal_sums_into(
        &self,
        model: &ModelPart,
        (conditions, wanted): (&[ConditionIdx], Option<&[bool]>),
        (sums, count): (&mut [Vector], &mut [u32]),
    ) -> bool {
        let (kinds, centres) = (model.conditions(), model.condition_normals());
        let kept = self.table;
        let is_face = |c: ConditionIdx| kinds.kind(c.index()).is_face();
        if conditions
            .iter()
            .any(|&c| is_face(c) && self.of(c).is_none())
        {
            return false;
        }
        if centres.len() >= NODAL_ENTRY as usize || kept.nodes.len() >= NODAL_ENTRY as usize {
            return self
                .subset(model, conditions)
                .map(|table| table.nodal_sums_into(model, sums, count))
                .is_some();
        }
        // Other kinds have no normal: no nodes to add to.
        let face_nodes = |f: usize| {
            let c = conditions[f];
            if is_face(c) {
                kinds.nodes(c.index())
            } else {
                &[]
            }
        };
        // A uniform face's normal is its condition normal (by condition index); a nodal
        // one, an entry of the kept table.
        let reference = |f: usize, k: usize| {
            let c = conditions[f];
            match self.of(c) {
                Some(i) if kept.ends[i] as usize != nodes_start(&kept.ends, i) => {
                    (nodes_start(&kept.ends, i) + k) as u32 | NODAL_ENTRY
                }
                _ => c.0,
            }
        };
        let normal = |r: u32| {
            if r & NODAL_ENTRY == 0 {
                centres[r as usize]
            } else {
                kept.nodes[(r & !NODAL_ENTRY) as usize]
            }
        };
        sums_by_node_blocks(
            (sums, count),
            (conditions.len(), wanted),
            face_nodes,
            (reference, normal),
            FACES_PER_TASK.max(conditions.len().div_ceil(MAX_SUM_CHUNKS)),
        );
        true
    }
}

/// The start of face `face`'s nodal normals in a table's nodal list, given the faces' ends
/// (the previous face's end).
fn nodes_start(ends: &[u32], face: usize) -> usize {
    if face == 0 {
        0
    } else {
        ends[face - 1] as usize
    }
}

/// Normals per parallel piece of [`fingerprint`].
const FINGERPRINT_PIECE: usize = 4096;

/// A 64-bit hash of the bits of every component of the `len` normals `normal(i)`: the wrapping
/// sum over the words of SplitMix64's finaliser of the word plus its position times the golden
/// ratio (so that every input bit reaches every output bit, and the same word elsewhere counts
/// differently), the words independent of each other and the pieces of [`FINGERPRINT_PIECE`]
/// normals in parallel. Tells whether the condition normals still hold a kept table's centre
/// normals — a changed bit anywhere, or two normals exchanged, gives another hash but with a
/// chance of about 2⁻⁶⁴. The same for any thread count.
fn fingerprint(len: usize, normal: impl Fn(usize) -> Vector + Sync) -> u64 {
    const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;
    let mix = |word: u64, position: usize| {
        let mut z = word.wrapping_add((position as u64).wrapping_add(1).wrapping_mul(GOLDEN));
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    (0..len.div_ceil(FINGERPRINT_PIECE))
        .into_par_iter()
        .map(|k| {
            let end = ((k + 1) * FINGERPRINT_PIECE).min(len);
            (k * FINGERPRINT_PIECE..end).fold(0u64, |sum, i| {
                let n = normal(i);
                sum.wrapping_add(mix(n.x.to_bits(), 3 * i))
                    .wrapping_add(mix(n.y.to_bits(), 3 * i + 1))
                    .wrapping_add(mix(n.z.to_bits(), 3 * i + 2))
            })
        })
        .reduce(|| 0, u64::wrapping_add)
}

/// Adds `normal` to a node's sum `sum`, of which `count` normals were added before: the first
/// one to zero (the sum's old value is not a sum of these faces).
fn add_first_zero(sum: &mut Vector, count: &mut u32, normal: Vector) {
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
fn sums_by_node_blocks<'a>(
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
    sums.par_chunks_mut(1 << NODE_BLOCK_BITS)
        .zip(count.par_chunks_mut(1 << NODE_BLOCK_BITS))
        .enumerate()
        .for_each(|(b, (sums, count))| {
            let first = b << NODE_BLOCK_BITS;
            for chunk in &chunks {
                for &(node, r) in &chunk.contributions[chunk.start[b]..chunk.start[b + 1]] {
                    let i = node as usize - first;
                    add_first_zero(&mut sums[i], &mut count[i], normal(r));
                }
            }
        });
}

/// One chunk of faces' (node, normal) contributions of [`FaceNormals::nodal_sums`], sorted by
/// node block (face order within a block): block `b`'s are `contributions[start[b]..start[b + 1]]`.
struct SortedChunk {
    start: Vec<usize>,
    contributions: Vec<(u32, u32)>,
}

/// log2 of the nodes per block of [`FaceNormals::nodal_sums`] (a block's sums and counts,
/// ~230 KB, stay in a core's cache).
const NODE_BLOCK_BITS: u32 = 13;

/// The top bit of a contribution's normal reference in [`FaceNormals::nodal_sums`]: set for
/// an entry of the nodal table, clear for a face's centre normal.
const NODAL_ENTRY: u32 = 1 << 31;

/// The most chunks of faces [`FaceNormals::nodal_sums`] sorts its contributions in.
const MAX_SUM_CHUNKS: usize = 64;

/// Faces per parallel task of [`face_unit_normals`].
const FACES_PER_TASK: usize = 4096;

/// The unit normals at the centre and at the nodes ([`Geometry::face_unit_normals`]) of every
/// face condition of `conditions` (other kinds are skipped), in the order given, computed in
/// parallel. Errors: the first condition (in the order given) whose normals cannot be
/// computed.
pub fn face_unit_normals(
    model: &ModelPart,
    conditions: &[ConditionIdx],
) -> Result<FaceNormals, Error> {
    let kinds = model.conditions();
    let faces: Vec<ConditionIdx> = conditions
        .iter()
        .copied()
        .filter(|c| kinds.kind(c.index()).is_face())
        .collect();
    // Centres and per-face counts of nodal normals written in place; the nodal normals of
    // the (few) non-affine faces per task, joined afterwards.
    let mut centres = vec![Vector::zeros(); faces.len()];
    let mut ends = vec![0u32; faces.len()];
    let chunks: Vec<Result<Vec<Vector>, Error>> = faces
        .par_chunks(FACES_PER_TASK)
        .zip(centres.par_chunks_mut(FACES_PER_TASK))
        .zip(ends.par_chunks_mut(FACES_PER_TASK))
        .map(|((faces, centres), counts)| {
            let mut nodes = Vec::new();
            let mut gathered = GatheredPoints::default();
            for ((faces, centres), counts) in faces
                .chunks(GATHER_BLOCK)
                .zip(centres.chunks_mut(GATHER_BLOCK))
                .zip(counts.chunks_mut(GATHER_BLOCK))
            {
                gathered.gather(model, faces.iter().copied());
                for (k, ((&c, centre), count)) in faces.iter().zip(centres).zip(counts).enumerate()
                {
                    let before = nodes.len();
                    *centre = Geometry::new(kinds.kind(c.index()), gathered.points(k))
                        .and_then(|g| g.face_unit_normals_into(&mut nodes))
                        .map_err(|e| geometry_error(c, model, e))?;
                    *count = (nodes.len() - before) as u32;
                }
            }
            Ok(nodes)
        })
        .collect();
    let mut nodes = Vec::new();
    for chunk in chunks {
        nodes.extend(chunk?);
    }
    let mut end = 0u32;
    for e in &mut ends {
        end += *e;
        *e = end;
    }
    Ok(FaceNormals {
        conditions: faces,
        centres,
        ends,
        nodes,
        stamp: model.geometry_stamp(),
        normals_stamp: 0,
        nodal_written: None,
    })
}

/// Computes the unit normals of the conditions of `part` (all conditions when `None`) and
/// of their nodes: condition normals go to [`ModelPart::condition_normals`], nodal normals to
/// the historical variable `NORMAL` (current step), which is added if needed. Returns the
/// faces' own normals ([`face_unit_normals`] of the part's conditions), for callers that need
/// them again on the same coordinates ([`FaceNormals::keep`], [`KeptFaceNormals::subset`]).
pub fn compute_unit_normals(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
) -> Result<FaceNormals, Error> {
    compute_unit_normals_reusing(model, part, mode, None)
}

/// [`compute_unit_normals`], with the faces' own normals taken from `known` (the kept table of
/// an earlier [`compute_unit_normals`] of these faces or more) where the model's geometry and
/// condition normals have not changed since ([`KeptFaceNormals::current_subset`]): the same
/// results, without computing them again.
pub fn compute_unit_normals_reusing(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
    known: Option<&KeptFaceNormals>,
) -> Result<FaceNormals, Error> {
    unit_normals_with(model, part, mode, |model, conditions| {
        known.and_then(|k| k.current_subset(model, conditions))
    })
}

/// [`compute_unit_normals`] with the faces' own normals from `known(model, conditions)` where
/// it has them.
fn unit_normals_with(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
    known: impl FnOnce(&ModelPart, &[ConditionIdx]) -> Option<FaceNormals>,
) -> Result<FaceNormals, Error> {
    let conditions = conditions_of(model, part);
    model.nodal_data_mut().add_vector(VectorVar::Normal);
    // The per-face normals in parallel; the sums in condition order, as Kratos' serial loop
    // adds them (identical results for any thread count).
    let mut faces = match known(model, &conditions) {
        Some(faces) => faces,
        None => face_unit_normals(model, &conditions)?,
    };
    let sums = faces.nodal_sums(model);
    let nodal = normalised(model, &conditions, mode, sums)?;
    faces.set_condition_normals(model);
    write_nodal_normals(model, &conditions, nodal);
    faces.nodal_written = Some((model.nodal_data().vector_stamp(VectorVar::Normal), mode));
    Ok(faces)
}

/// [`compute_unit_normals`] from the faces' own normals in `known` (the kept table of an
/// earlier [`compute_unit_normals`] of these faces or more), without building their table:
/// where the model's geometry and condition normals have not changed since
/// ([`KeptFaceNormals::current_subset`]) and the table has every face of the part, writes
/// what [`compute_unit_normals`] writes (the condition normals hold the table's centre
/// normals already, so `known` stays current) and returns true; false, with nothing done,
/// otherwise. Where `known` is the table of a [`compute_unit_normals`] over exactly these
/// conditions in this mode and `NORMAL` has not been written since (its
/// [`NodalData::vector_stamp`](crate::NodalData::vector_stamp)), `NORMAL` already holds the
/// result: nothing is computed.
pub fn compute_unit_normals_from_kept(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
    known: &KeptFaceNormals,
) -> Result<bool, Error> {
    if !known.is_current(model) || !known.holds_centres(model) {
        return Ok(false);
    }
    let conditions = conditions_of(model, part);
    // The table's own computation over exactly these conditions, in this mode, with `NORMAL`
    // untouched since: it holds what this one would write.
    let written = model.nodal_data().vector_stamp(VectorVar::Normal);
    if known.nodal_written == Some((written, mode)) && conditions == known.conditions {
        return Ok(true);
    }
    let Some(positions) = known.positions_checked(model) else {
        return Ok(false);
    };
    let n_nodes = model.nodes().len();
    let mut sums = (vec![Vector::zeros(); n_nodes], vec![0u32; n_nodes]);
    if !positions.nodal_sums_into(model, (&conditions, None), (&mut sums.0, &mut sums.1)) {
        return Ok(false);
    }
    model.nodal_data_mut().add_vector(VectorVar::Normal);
    let nodal = normalised(model, &conditions, mode, sums)?;
    write_nodal_normals(model, &conditions, nodal);
    Ok(true)
}

/// The nodal normals from the sums of their faces' normals and the faces' count per node
/// ([`FaceNormals::nodal_sums`]): normalised as Kratos' loop does — node by node in
/// condition order, a node once per adjacent face (Q38; once in [`NormalsMode::Once`]). No
/// other node's value enters, so each node is normalised on its own, in parallel. Only the
/// first normalisation can fail (afterwards the norm is about 1): the node reported is the
/// first failing one in Kratos' order (the face conditions of `conditions`, node by node).
fn normalised(
    model: &ModelPart,
    conditions: &[ConditionIdx],
    mode: NormalsMode,
    (mut nodal, count): (Vec<Vector>, Vec<u32>),
) -> Result<(Vec<Vector>, Vec<u32>), Error> {
    let times = |i: usize| match mode {
        NormalsMode::Kratos => count[i],
        NormalsMode::Once => count[i].min(1),
    };
    let failed = nodal
        .par_iter_mut()
        .enumerate()
        .map(|(i, v)| {
            for _ in 0..times(i) {
                let norm = v.norm();
                if norm <= EPS {
                    return true;
                }
                *v /= norm;
            }
            false
        })
        .filter(|&f| f)
        .count()
        > 0;
    let kinds = model.conditions();
    let result = match (failed, mode) {
        (false, _) => Ok(()),
        (true, NormalsMode::Kratos) => conditions
            .iter()
            .filter(|c| kinds.kind(c.index()).is_face())
            .flat_map(|c| kinds.nodes(c.index()))
            .find(|n| nodal[n.index()].norm() <= EPS)
            .map_or(Ok(()), |n| Err(n.index())),
        (true, NormalsMode::Once) => (0..nodal.len())
            .find(|&i| count[i] > 0 && nodal[i].norm() <= EPS)
            .map_or(Ok(()), Err),
    };
    if let Err(i) = result {
        let what = if model.nodes().flags()[i].is(Flag::INTERFACE) {
            "the unit normals of the conditions around this interface node cancel out"
        } else {
            "the unit normals of the conditions around this node cancel out"
        };
        return Err(ErrorKind::Geometry {
            entity: EntityKind::Node,
            id: model.nodes().ids()[i],
            source: csm_geometry::Error::degenerate(what),
        }
        .into());
    }
    Ok((nodal, count))
}

/// Writes the [`normalised`] nodal normals: step 1 resets NORMAL on every node of the
/// conditions; the face nodes then get their normalised sums.
fn write_nodal_normals(
    model: &mut ModelPart,
    conditions: &[ConditionIdx],
    (nodal, count): (Vec<Vector>, Vec<u32>),
) {
    let n_nodes = model.nodes().len();
    let mut reset = vec![false; n_nodes];
    for &c in conditions {
        for n in model.conditions().nodes(c.index()) {
            reset[n.index()] = true;
        }
    }
    if let Some(column) = model.nodal_data_mut().vector_mut(VectorVar::Normal, 0) {
        for i in (0..n_nodes).filter(|&i| reset[i]) {
            column[i] = if count[i] > 0 {
                nodal[i]
            } else {
                Vector::zeros()
            };
        }
    }
}

/// The nodal `NORMAL`s that [`compute_unit_normals`] wrote on a part, kept to be written again
/// when the normals were overwritten since (the mortar mapping's mean normals) but the
/// coordinates did not move: a second [`compute_unit_normals`] would write the same values.
///
/// Only the nodal values are kept: the condition normals that the mean normals write are the
/// same unit normals at the centres ([`face_unit_normals`]) that [`compute_unit_normals`]
/// writes. Which nodes are written again is decided by the part's conditions when the
/// snapshot is restored (the nodes [`compute_unit_normals`] resets).
#[derive(Debug, Clone)]
pub struct UnitNormalsSnapshot {
    part: Option<PartIdx>,
    nodal: Vec<Vector>,
}

impl UnitNormalsSnapshot {
    /// The current nodal `NORMAL` of every node, to be restored on the nodes of the
    /// conditions of `part` (all conditions when `None`); `None` when the model has no
    /// `NORMAL`.
    pub fn take(model: &ModelPart, part: Option<PartIdx>) -> Option<UnitNormalsSnapshot> {
        let nodal = model.nodal_data().vector(VectorVar::Normal, 0)?.to_vec();
        Some(UnitNormalsSnapshot { part, nodal })
    }

    /// The kept `NORMAL`, by node index (every node of the model).
    pub fn nodal(&self) -> &[Vector] {
        &self.nodal
    }

    /// Puts the kept `NORMAL` back as the whole column (every node; no pass over the part):
    /// the same as [`UnitNormalsSnapshot::restore`] where, since the snapshot, `NORMAL` changed
    /// only on nodes of the part's conditions (e.g. the mapping's mean normals, which it
    /// writes on the nodes of the part's conditions only). Nothing happens if the model lost
    /// its `NORMAL`; where its nodes changed in number, this is [`UnitNormalsSnapshot::restore`].
    pub fn restore_all(self, model: &mut ModelPart) {
        if model.nodal_data().vector(VectorVar::Normal, 0).is_none() {
            return;
        }
        let part = self.part;
        if let Err(nodal) = model
            .nodal_data_mut()
            .set_vector(VectorVar::Normal, self.nodal)
        {
            UnitNormalsSnapshot { part, nodal }.restore(model);
        }
    }

    /// Writes the kept `NORMAL` of the nodes of the part's conditions back.
    pub fn restore(self, model: &mut ModelPart) {
        let mut written = vec![false; model.nodes().len()];
        for c in conditions_of(model, self.part) {
            for n in model.conditions().nodes(c.index()) {
                written[n.index()] = true;
            }
        }
        if let Some(column) = model.nodal_data_mut().vector_mut(VectorVar::Normal, 0) {
            for ((value, kept), w) in column.iter_mut().zip(&self.nodal).zip(&written) {
                if *w {
                    *value = *kept;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
