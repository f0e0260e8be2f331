//! The inputs of the mortar routines: a face with its normals, the mode and the settings.

use crate::math::{EPS, Real, Vector, is_finite_vector};
use crate::{Error, ErrorKind, Geometry};

/// Kratos' duplicate-point tolerance of the 3D segmentation (`CheckPoints`, absolute, on the
/// rotated coordinates) and the tolerance of `Clipping2D` (denominator and edge parameters).
/// [`MortarMode::Robust`] applies the same numbers to coordinates divided by the slave size.
pub const DUPLICATE_POINT_TOLERANCE: Real = 1e-15;
/// Kratos' `Clipping2D` tolerance: `|denominator| < tol` → parallel edges; parameters accepted
/// in `[−tol, 1 + tol]`.
pub const CLIPPING_TOLERANCE: Real = 1e-15;
/// 2D segmentation tolerance (`1e3 · ZeroTolerance`): the master inside test and the Newton
/// convergence test `|Δξ − Δξ_old| < tol` of `ProjectIterativeLine2D`.
pub const NEWTON_2D_TOLERANCE: Real = 1e3 * EPS;
/// Newton iterations of `ProjectIterativeLine2D` (Kratos: 20; [`MortarMode::Robust`] allows
/// five times as many before giving a master node up, Q44).
pub const NEWTON_2D_MAX_ITERATIONS: usize = 20;
/// [`MortarMode::Robust`] only: cells whose area (length in 2D) is at most this fraction of
/// the slave's area (length) are dropped, so that a master that only touches the slave along an
/// edge or at a corner never survives (the robust answer to Q48).
pub const ROBUST_AREA_FACTOR: Real = 1e-12;

/// Which numerical rules the segmentation follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MortarMode {
    /// Kratos' algorithm with its absolute tolerances and quirks, for pair-for-pair fidelity:
    /// the normals are used as given (not normalised), the in-plane frame `t_ξ`, `t_η = n × t_ξ`
    /// is not orthogonalised, points closer than 1e-15 (absolute) are merged — which is what
    /// removes masters that only touch the slave (Q48) —, a triangle slave with a quadrilateral
    /// master lying inside it gets the overlapping cells (0,1,2), (1,2,3) (Q49), the 2D Newton
    /// projection clamps to the slave and drops a master node after 20 iterations (Q44), the
    /// overlap area uses Heron's formula (Q45).
    #[default]
    Kratos,
    /// The same algorithm with the fixes: the slave normal is normalised and `t_ξ`
    /// orthogonalised against it; the clipping runs on in-plane coordinates divided by the
    /// slave's size `L` (bounding-box diagonal), so every tolerance is relative and the cells
    /// are invariant under uniform scaling (and rigid motions) up to rounding; cells of area at
    /// most [`ROBUST_AREA_FACTOR`] × slave area are dropped (touching pairs never survive,
    /// whatever the rounding); the `<3,3,4>` master-inside cells are (0,1,2), (0,2,3) (a
    /// partition of a convex quadrilateral); the 2D Newton projection may use 100 iterations;
    /// the area uses the cross product. The distance threshold keeps Kratos' meaning (Q21): it
    /// is an absolute length supplied by the caller.
    Robust,
}

/// Settings of [`exact_segmentation`](super::exact_segmentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentationSettings {
    /// Kratos fidelity or the robust variant.
    pub mode: MortarMode,
    /// Kratos' `DISTANCE_THRESHOLD` (default 1e24). 3D: a master node farther than this *in
    /// front of* the slave (`(X_m − C)·n_s > threshold`) rejects the pair; 2D: a slave node
    /// whose projection distance along `−n_i` onto the master exceeds it rejects the pair, i.e.
    /// penetrations deeper than the threshold (Q21, opposite meanings).
    pub distance_threshold: Real,
}

impl Default for SegmentationSettings {
    /// Kratos mode, distance threshold 1e24 (the value Python puts in `ProcessInfo`).
    fn default() -> SegmentationSettings {
        SegmentationSettings {
            mode: MortarMode::Kratos,
            distance_threshold: 1e24,
        }
    }
}

/// One side of a mortar pair: a face geometry (Line2D2, Triangle3D3 or Quadrilateral3D4), the
/// condition normal (Kratos: the condition's `NORMAL`, the unit normal at the local centre) and
/// the nodal normals (Kratos: the historical nodal `NORMAL`, the mapper's mean normals).
///
/// The nodal normals are used by the 2D segmentation (slave side) and by the Gauss-point
/// normal of the operators; when none are given, every node uses the condition normal (the
/// right value for a flat interface).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MortarFace<'a> {
    geometry: Geometry<'a>,
    normal: Vector,
    nodal_normals: &'a [Vector],
}

impl<'a> MortarFace<'a> {
    /// A face whose nodes all use the condition normal `normal`.
    ///
    /// Errors: [`ErrorKind::Unsupported`] for a geometry of more than
    /// [`MAX_MORTAR_FACE_NODES`](super::MAX_MORTAR_FACE_NODES) nodes (the mortar routines integrate linear
    /// faces only); [`ErrorKind::NonFinite`] for a non-finite normal.
    pub fn new(geometry: Geometry<'a>, normal: Vector) -> Result<MortarFace<'a>, Error> {
        if geometry.kind().n_nodes() > super::MAX_MORTAR_FACE_NODES {
            return Err(Error::new(ErrorKind::Unsupported(
                "mortar faces of more than four nodes",
            )));
        }
        if !is_finite_vector(&normal) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        Ok(MortarFace {
            geometry,
            normal,
            nodal_normals: &[],
        })
    }

    /// The same face with explicit nodal normals, one per node in node order.
    ///
    /// Errors: [`ErrorKind::WrongNodeCount`] if the count differs from the node count;
    /// [`ErrorKind::NonFinite`] for a non-finite normal.
    pub fn with_nodal_normals(self, nodal_normals: &'a [Vector]) -> Result<MortarFace<'a>, Error> {
        let expected = self.geometry.kind().n_nodes();
        if nodal_normals.len() != expected {
            return Err(Error::new(ErrorKind::WrongNodeCount {
                expected,
                found: nodal_normals.len(),
            }));
        }
        if !nodal_normals.iter().all(is_finite_vector) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        Ok(MortarFace {
            nodal_normals,
            ..self
        })
    }

    /// The face geometry.
    pub fn geometry(&self) -> &Geometry<'a> {
        &self.geometry
    }

    /// The condition normal.
    pub fn normal(&self) -> Vector {
        self.normal
    }

    /// The normal of node `i`: the given nodal normal, or the condition normal if none were
    /// given. Panics if `i` is not a node index (plain slice indexing).
    pub fn nodal_normal(&self, i: usize) -> Vector {
        if self.nodal_normals.is_empty() {
            debug_assert!(i < self.geometry.kind().n_nodes());
            self.normal
        } else {
            self.nodal_normals[i]
        }
    }
}
