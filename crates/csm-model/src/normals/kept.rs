//! The face-normal cache: a table kept without its centre normals, and when it is still
//! valid (the geometry stamp, the condition normals' stamp, a fingerprint of them).

use csm_geometry::math::Vector;
use rayon::prelude::*;

use super::face_normals::FaceNormals;
use super::node_sums::{MAX_SUM_CHUNKS, NODAL_ENTRY, sums_by_node_blocks};
use super::{FACES_PER_TASK, NormalsMode};
use crate::{ConditionIdx, GeometryStamp, ModelPart};

/// A [`FaceNormals`] table without its centre normals ([`FaceNormals::keep`]), which the
/// model's condition normals hold.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KeptFaceNormals {
    pub(super) conditions: Vec<ConditionIdx>,
    pub(super) ends: Vec<u32>,
    pub(super) nodes: Vec<Vector>,
    /// [`fingerprint`] of the centre normals, in face order.
    pub(super) fingerprint: u64,
    /// The model's geometry when the normals were computed ([`KeptFaceNormals::
    /// current_subset`]).
    pub(super) stamp: GeometryStamp,
    /// [`FaceNormals`]' condition-normals stamp.
    pub(super) normals_stamp: u64,
    /// [`FaceNormals`]' `NORMAL` stamp and mode.
    pub(super) nodal_written: Option<(u64, NormalsMode)>,
}

impl KeptFaceNormals {
    /// The table of the face conditions of `conditions` (in that order; other kinds are
    /// skipped, as [`face_unit_normals`](super::face_unit_normals) skips them) taken from this one, with the centre
    /// normals read from [`ModelPart::condition_normals`]: on the coordinates the table was
    /// computed on, bit for bit what [`face_unit_normals`](super::face_unit_normals) computes, without computing it
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
    pub(super) fn is_current(&self, model: &ModelPart) -> bool {
        self.stamp != GeometryStamp::default() && self.stamp == model.geometry_stamp()
    }

    /// Whether the model's condition normals hold this table's centre normals: nothing
    /// wrote them since this table set them, or else every condition has one and their
    /// fingerprint is the table's.
    pub(super) fn holds_centres(&self, model: &ModelPart) -> bool {
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
    pub(super) fn positions_checked(&self, model: &ModelPart) -> Option<KeptPositions<'_>> {
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
pub(super) const ABSENT: u32 = u32::MAX;

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
    pub(super) fn subset(
        &self,
        model: &ModelPart,
        conditions: &[ConditionIdx],
    ) -> Option<FaceNormals> {
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
        // (A check of every face: in parallel.)
        if conditions
            .par_iter()
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
pub(super) fn nodes_start(ends: &[u32], face: usize) -> usize {
    if face == 0 {
        0
    } else {
        ends[face - 1] as usize
    }
}

/// Normals per parallel piece of [`fingerprint`].
pub(super) const FINGERPRINT_PIECE: usize = 4096;

/// A 64-bit hash of the bits of every component of the `len` normals `normal(i)`: the wrapping
/// sum over the words of SplitMix64's finaliser of the word plus its position times the golden
/// ratio (so that every input bit reaches every output bit, and the same word elsewhere counts
/// differently), the words independent of each other and the pieces of [`FINGERPRINT_PIECE`]
/// normals in parallel. Tells whether the condition normals still hold a kept table's centre
/// normals — a changed bit anywhere, or two normals exchanged, gives another hash but with a
/// chance of about 2⁻⁶⁴. The same for any thread count.
pub(super) fn fingerprint(len: usize, normal: impl Fn(usize) -> Vector + Sync) -> u64 {
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
