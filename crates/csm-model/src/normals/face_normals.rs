//! The table of many faces' unit normals (centre and nodal), stored flat.

use csm_geometry::math::Vector;

use super::kept::{KeptFaceNormals, fingerprint, nodes_start};
use super::node_sums::{MAX_SUM_CHUNKS, NODAL_ENTRY, add_first_zero, sums_by_node_blocks};
use super::{FACES_PER_TASK, NormalsMode};
use crate::{ConditionIdx, GeometryStamp, ModelPart};

/// The unit normals of many faces ([`face_unit_normals`](super::face_unit_normals)), stored flat: one centre normal per
/// face and the nodal normals only of faces whose normal varies over the face (affine faces —
/// Line2D2, Triangle3D3 — have one normal; [`FaceNormalsRef::node`] returns it for every node).
#[derive(Debug, Clone, Default)]
pub struct FaceNormals {
    pub(super) conditions: Vec<ConditionIdx>,
    pub(super) centres: Vec<Vector>,
    /// Per face, the end of its nodal normals in `nodes` (the start is the previous end).
    pub(super) ends: Vec<u32>,
    pub(super) nodes: Vec<Vector>,
    /// The model's geometry when the normals were computed ([`KeptFaceNormals::current_subset`]).
    pub(super) stamp: GeometryStamp,
    /// The model's condition-normals stamp right after [`FaceNormals::set_condition_normals`]
    /// wrote these centre normals (0 before): while it is the same, the condition normals
    /// hold them ([`KeptFaceNormals::positions`]).
    pub(super) normals_stamp: u64,
    /// Where [`compute_unit_normals`](super::compute_unit_normals) returned this table: the `NORMAL` stamp
    /// ([`crate::NodalData::vector_stamp`]) right after it wrote the nodal normals of these
    /// faces, and the mode; while the stamp is the same, `NORMAL` holds them
    /// ([`compute_unit_normals_from_kept`](super::compute_unit_normals_from_kept)).
    pub(super) nodal_written: Option<(u64, NormalsMode)>,
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

    /// The faces, in the order they were given to [`face_unit_normals`](super::face_unit_normals) (or to
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
        let (mut sums, mut count) = (crate::zero_vectors(n_nodes), vec![0u32; n_nodes]);
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
    pub(super) fn nodal_sums_in_chunks(
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
        let (mut sums, mut count) = (crate::zero_vectors(n_nodes), vec![0u32; n_nodes]);
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
    /// Self::set_condition_normals); [`compute_unit_normals`](super::compute_unit_normals) does): on a large triangle mesh
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
