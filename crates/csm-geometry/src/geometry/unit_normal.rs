//! Unit normal of a face geometry at local coordinates (Kratos `UnitNormal`, reference §17.1).

use super::Geometry;
use crate::math::{Point, Real, Vector, cross_kratos, is_finite_vector, norm_kratos};
use crate::{Error, ErrorKind};

/// Relative size below which a tangent or normal vector counts as zero: `|v| ≤ 1e-14 · L^d`
/// with `L` the bounding-box diagonal and `d` the local dimension.
pub(crate) const DEGENERATE_REL: Real = 1e-14;

impl Geometry<'_> {
    /// The non-normalised normal of a face at `local`: for a 2D line, `(t_y, −t_x, 0)` with
    /// `t = ∂x/∂ξ` (pointing to the right of the direction 0 → 1); for a surface,
    /// `∂x/∂ξ × ∂x/∂η` (triangle: `(x1−x0)×(x2−x0)`). Its length is the area (length) element.
    ///
    /// Errors: [`ErrorKind::Unsupported`] for solids.
    pub fn normal(&self, local: &Point) -> Result<Vector, Error> {
        if !self.kind().is_face() {
            return Err(Error::new(ErrorKind::Unsupported(
                "normal of a non-face geometry",
            )));
        }
        let j = self.jacobian(local);
        let t0: Vector = j.column(0).into_owned();
        Ok(if self.kind().local_dim() == 1 {
            Vector::new(t0.y, -t0.x, 0.0)
        } else {
            let t1: Vector = j.column(1).into_owned();
            cross_kratos(&t0, &t1)
        })
    }

    /// The unit normal at the local coordinates of the centre (the node mean), Kratos'
    /// `UnitNormal(PointLocalCoordinates(Center()))`: where both succeed, bit for bit
    /// `unit_normal(&point_local_coordinates(&center())?)`. Affine faces (Line2D2,
    /// Triangle3D3) have one normal everywhere, so their centre's local coordinates are not
    /// computed (a non-finite centre is still refused).
    ///
    /// Errors: as [`unit_normal`](Self::unit_normal) and
    /// [`point_local_coordinates`](Self::point_local_coordinates). A degenerate affine face is
    /// refused by the normal's own test ("zero-length normal") rather than by the local
    /// coordinates' (a singular Jacobian); the two tests round differently, so a sliver at the
    /// very edge of degeneracy may pass one and fail the other.
    pub fn centre_unit_normal(&self) -> Result<Vector, Error> {
        let centre = self.center();
        if self.is_affine_face() {
            if !crate::math::is_finite_point(&centre) {
                return Err(Error::new(ErrorKind::NonFinite));
            }
            return self.unit_normal(&self.reference_center());
        }
        self.unit_normal(&self.point_local_coordinates(&centre)?)
    }

    /// The unit normal of a face at `local` (Kratos conventions, see [`normal`](Self::normal)),
    /// normalised by division by its norm.
    ///
    /// Errors: [`ErrorKind::Degenerate`] where the normal has zero (or rounding-noise) length,
    /// e.g. zero-length lines, zero-area faces, coincident nodes — never NaN;
    /// [`ErrorKind::Unsupported`] for solids; [`ErrorKind::NonFinite`] for a non-finite `local`.
    pub fn unit_normal(&self, local: &Point) -> Result<Vector, Error> {
        if !(local.x.is_finite() && local.y.is_finite() && local.z.is_finite()) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        let n = self.normal(local)?;
        let norm = norm_kratos(&n);
        let scale = self.scale().powi(self.kind().local_dim() as i32);
        if norm.is_nan() || norm <= DEGENERATE_REL * scale || norm.is_infinite() {
            return Err(Error::degenerate("zero-length normal"));
        }
        let u = Vector::new(n.x / norm, n.y / norm, n.z / norm);
        debug_assert!(is_finite_vector(&u));
        Ok(u)
    }
}

/// The most nodes a face geometry has (Quadrilateral3D9).
pub const MAX_FACE_NODES: usize = 9;

/// The unit normals of one face at its centre and at each of its nodes
/// ([`Geometry::face_unit_normals`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceUnitNormals {
    /// At the local coordinates of the centre (the node mean).
    pub centre: Vector,
    nodes: [Vector; MAX_FACE_NODES],
    n_nodes: usize,
    uniform: bool,
}

impl FaceUnitNormals {
    /// At the local coordinates of each node, in node order.
    pub fn nodes(&self) -> &[Vector] {
        &self.nodes[..self.n_nodes]
    }

    /// Whether the face is affine (Line2D2, Triangle3D3): one normal everywhere, every nodal
    /// normal equal to [`centre`](Self::centre).
    pub fn is_uniform(&self) -> bool {
        self.uniform
    }
}

impl Geometry<'_> {
    /// The unit normals Kratos' `CalculateUnitNormals` and `ComputeNodesMeanNormalModelPart`
    /// take from a face: at the local coordinates ([`point_local_coordinates`](
    /// Self::point_local_coordinates)) of its centre and of each of its nodes.
    ///
    /// Affine kinds (Line2D2, Triangle3D3) have a constant Jacobian, so the unit normal does
    /// not depend on the local point: it is computed once, at the reference centre, and is
    /// bit-identical to the per-point values (no local coordinates are computed). Every other kind evaluates each point.
    ///
    /// Errors: as [`unit_normal`](Self::unit_normal) and
    /// [`point_local_coordinates`](Self::point_local_coordinates); [`ErrorKind::Unsupported`]
    /// for solids.
    pub fn face_unit_normals(&self) -> Result<FaceUnitNormals, Error> {
        let mut nodes = [Vector::zeros(); MAX_FACE_NODES];
        let centre = self.face_unit_normals_with(|k, normal| nodes[k] = normal)?;
        let affine = self.is_affine_face();
        if affine {
            for slot in &mut nodes[..self.points().len()] {
                *slot = centre;
            }
        }
        Ok(FaceUnitNormals {
            centre,
            nodes,
            n_nodes: self.points().len(),
            uniform: affine,
        })
    }

    /// [`face_unit_normals`](Self::face_unit_normals) without its table: returns the normal at
    /// the centre and appends those at the nodes to `nodal` only where the face is not affine
    /// (where they can differ from the centre's).
    pub fn face_unit_normals_into(&self, nodal: &mut Vec<Vector>) -> Result<Vector, Error> {
        let start = nodal.len();
        let result = self.face_unit_normals_with(|_, normal| nodal.push(normal));
        if result.is_err() {
            nodal.truncate(start);
        }
        result
    }

    /// Whether the face has one normal everywhere (a constant Jacobian: Line2D2, Triangle3D3).
    fn is_affine_face(&self) -> bool {
        matches!(
            self.kind(),
            crate::GeometryKind::Line2D2 | crate::GeometryKind::Triangle3D3
        )
    }

    /// The centre normal of [`face_unit_normals`](Self::face_unit_normals); `node(k, normal)`
    /// receives the nodal normals in node order, for non-affine faces only.
    fn face_unit_normals_with(&self, mut node: impl FnMut(usize, Vector)) -> Result<Vector, Error> {
        let points = self.points();
        if !self.kind().is_face() || points.len() > MAX_FACE_NODES {
            return Err(Error::new(ErrorKind::Unsupported(
                "unit normals of a non-face geometry",
            )));
        }
        if self.is_affine_face() {
            return self.centre_unit_normal();
        }
        // Several points on one face: the point-independent work of the local coordinates
        // once (bit for bit the same local coordinates).
        let solver = super::LocalCoordinatesSolver::new(*self);
        let at = |p: &Point| -> Result<Vector, Error> {
            self.unit_normal(&solver.local_coordinates(p)?)
        };
        let centre = at(&self.center())?;
        for (k, p) in points.iter().enumerate() {
            node(k, at(p)?);
        }
        Ok(centre)
    }
}
