//! The [`Geometry`] view type and its interpolation basics.

use crate::bounding::{Aabb, BoundingSphere};
use crate::math::{Matrix3, Point, Real, Vector, is_finite_point};
use crate::shape::{self, ShapeDerivatives, ShapeValues};
use crate::{Error, ErrorKind, GeometryKind};

/// A validated view of one geometry's node coordinates: a [`GeometryKind`] plus exactly
/// `kind.n_nodes()` finite points in Kratos' node order.
///
/// Construction checks the node count and finiteness only; degeneracy (zero length/area/volume)
/// is reported by the operations that need extent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry<'a> {
    kind: GeometryKind,
    points: &'a [Point],
}

impl<'a> Geometry<'a> {
    /// Checks that `points` has `kind.n_nodes()` entries and that every coordinate is finite.
    pub fn new(kind: GeometryKind, points: &'a [Point]) -> Result<Geometry<'a>, Error> {
        if points.len() != kind.n_nodes() {
            return Err(Error::new(ErrorKind::WrongNodeCount {
                expected: kind.n_nodes(),
                found: points.len(),
            }));
        }
        if !points.iter().all(is_finite_point) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        Ok(Geometry { kind, points })
    }

    /// The geometry kind.
    pub fn kind(&self) -> GeometryKind {
        self.kind
    }

    /// The node coordinates, in node order.
    pub fn points(&self) -> &'a [Point] {
        self.points
    }

    /// Kratos' `Center()`: the arithmetic mean of the nodes, summed in node order starting from
    /// node 0, then divided by the node count.
    pub fn center(&self) -> Point {
        // Every kind has at least 2 nodes and `new` checked the count, so `points[0]` exists.
        let mut sum = self.points[0].coords;
        for p in &self.points[1..] {
            sum += p.coords;
        }
        let n = self.points.len() as Real;
        Point::new(sum.x / n, sum.y / n, sum.z / n)
    }

    /// Shape-function values at the local point `local`.
    #[inline]
    pub fn shape_functions(&self, local: &Point) -> ShapeValues {
        shape::shape_functions(self.kind, local)
    }

    /// Local shape-function derivatives `∂N_i/∂ξ_k` at `local`.
    #[inline]
    pub fn shape_derivatives(&self, local: &Point) -> ShapeDerivatives {
        shape::shape_derivatives(self.kind, local)
    }

    /// The global position `x(ξ) = Σ N_i(ξ) X_i` (sum in node order).
    #[inline]
    pub fn global_coordinates(&self, local: &Point) -> Point {
        // Linear kinds: the shape-function values of `shape::evaluate` without its 27-value
        // container (see `jacobian`), the same bits.
        let (x, y, z) = (local.x, local.y, local.z);
        match self.kind {
            GeometryKind::Quadrilateral3D4 | GeometryKind::Quadrilateral2D4 => {
                const CORNERS: [[Real; 2]; 4] =
                    [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
                self.global_of_values(
                    &CORNERS.map(|a| (0.5 * (1.0 + a[0] * x)) * (0.5 * (1.0 + a[1] * y))),
                )
            }
            GeometryKind::Triangle3D3 | GeometryKind::Triangle2D3 => {
                self.global_of_values(&[1.0 - (x + y), x, y])
            }
            GeometryKind::Tetrahedra3D4 => self.global_of_values(&[1.0 - (x + y + z), x, y, z]),
            GeometryKind::Prism3D6 => {
                let l = [1.0 - (x + y), x, y];
                self.global_of_values(&[
                    l[0] * (1.0 - z),
                    l[1] * (1.0 - z),
                    l[2] * (1.0 - z),
                    l[0] * z,
                    l[1] * z,
                    l[2] * z,
                ])
            }
            _ => self.global_of_values(&self.shape_functions(local)),
        }
    }

    /// `Σ N_i X_i`, summed in node order from zero.
    #[inline]
    fn global_of_values(&self, n: &[Real]) -> Point {
        let mut x = Vector::zeros();
        for (ni, p) in n.iter().zip(self.points) {
            x += p.coords * *ni;
        }
        Point::from(x)
    }

    /// The Jacobian `J = ∂x/∂ξ` at `local` as a 3×3 matrix whose column `k` is `∂x/∂ξ_k` for
    /// `k < local_dim`; the remaining columns are zero.
    #[inline]
    pub fn jacobian(&self, local: &Point) -> Matrix3 {
        // The linear kinds get their derivative rows without the 27-row container of
        // `shape_derivatives` (copied on every call: a fifth of the search's time): the same
        // values (the formulas of `shape::evaluate`), accumulated in the same order, so the
        // same bits (tested).
        match self.kind {
            GeometryKind::Quadrilateral3D4 | GeometryKind::Quadrilateral2D4 => {
                const CORNERS: [[Real; 2]; 4] =
                    [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
                let xi = [local.x, local.y];
                let rows = CORNERS.map(|a| {
                    let f = [0.5 * (1.0 + a[0] * xi[0]), 0.5 * (1.0 + a[1] * xi[1])];
                    let df = [0.5 * a[0], 0.5 * a[1]];
                    [df[0] * f[1], df[1] * f[0], 0.0]
                });
                self.jacobian_of_rows(&rows)
            }
            GeometryKind::Triangle3D3 | GeometryKind::Triangle2D3 => {
                self.jacobian_of_rows(&[[-1.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
            }
            GeometryKind::Tetrahedra3D4 => self.jacobian_of_rows(&[
                [-1.0, -1.0, -1.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ]),
            GeometryKind::Prism3D6 => {
                // Linear triangle × linear ζ ∈ [0, 1].
                let (x, y, z) = (local.x, local.y, local.z);
                let l = [1.0 - (x + y), x, y];
                let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
                let mut rows = [[0.0; 3]; 6];
                for i in 0..3 {
                    rows[i] = [dl[i][0] * (1.0 - z), dl[i][1] * (1.0 - z), -l[i]];
                    rows[i + 3] = [dl[i][0] * z, dl[i][1] * z, l[i]];
                }
                self.jacobian_of_rows(&rows)
            }
            _ => self.jacobian_of_rows(self.shape_derivatives(local).rows()),
        }
    }

    /// `J[(c, k)] = Σ_i X_i[c] · rows[i][k]` for `k < local_dim`, summed in node order from 0.
    #[inline]
    fn jacobian_of_rows(&self, rows: &[[Real; 3]]) -> Matrix3 {
        let mut j = Matrix3::zeros();
        for (row, p) in rows.iter().zip(self.points) {
            for (k, dk) in row.iter().enumerate().take(self.kind.local_dim()) {
                for c in 0..3 {
                    j[(c, k)] += p[c] * dk;
                }
            }
        }
        j
    }

    /// The axis-aligned bounding box of the nodes (Kratos' `BoundingBox`: component-wise
    /// minimum and maximum over the nodes).
    pub fn aabb(&self) -> Aabb {
        Aabb::from_points(self.points)
    }

    /// The bounding sphere used by the search: centre = [`center`](Self::center), radius =
    /// largest centre-to-node distance (Kratos' `Radius()` semantics).
    pub fn bounding_sphere(&self) -> BoundingSphere {
        BoundingSphere::from_points_about(self.center(), self.points)
    }

    /// The local coordinates of the reference element's centre (lines, quads, hexahedra: 0;
    /// triangles: (1/3, 1/3); tetrahedra: (1/4, 1/4, 1/4); prisms (1/3, 1/3, 1/2)).
    pub fn reference_center(&self) -> Point {
        let nodes = shape::reference_node_coordinates(self.kind);
        let corners = match self.kind {
            GeometryKind::Triangle3D6 | GeometryKind::Triangle2D6 => 3,
            GeometryKind::Tetrahedra3D10 => 4,
            _ => nodes.len(),
        };
        let mut c = [0.0; 3];
        for a in &nodes[..corners] {
            for k in 0..3 {
                c[k] += a[k];
            }
        }
        Point::new(
            c[0] / corners as Real,
            c[1] / corners as Real,
            c[2] / corners as Real,
        )
    }

    /// A length scale of the node cloud: the diagonal of its bounding box (0 for coincident
    /// nodes). Used for relative degeneracy tests.
    pub(crate) fn scale(&self) -> Real {
        let b = self.aabb();
        (b.max - b.min).norm()
    }
}
