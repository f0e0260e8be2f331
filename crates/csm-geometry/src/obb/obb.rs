//! [`Obb`]: the 3D oriented bounding box.

use crate::bounding::Aabb;
use crate::intersection::{ObbIntersection, SatMode, direct_obb_obb, sat_obb_obb};
use crate::math::{EPS, Matrix3, Point, Real, Vector};
use crate::{Error, Geometry};

/// Vertex sign table of Kratos' OBB (x, y, z signs of vertex `i`); the vertices are numbered
/// as the nodes of a Hexahedra3D8.
pub(crate) const SIGNS_3D: [[Real; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// A 3D oriented bounding box: centre `c`, axes `A_0, A_1, A_2` (orthonormal for boxes built
/// here) and half-lengths `h_k`: the set `{c + Σ s_k h_k A_k : |s_k| ≤ 1}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb {
    /// Centre `c`.
    pub center: Point,
    /// Axes `A_0, A_1, A_2`.
    pub axes: [Vector; 3],
    /// Half-lengths `h_0, h_1, h_2` along the axes.
    pub half_lengths: [Real; 3],
}

impl Obb {
    /// A box from centre, axes and half-lengths (Kratos' direct constructor; no checks).
    pub fn new(center: Point, axes: [Vector; 3], half_lengths: [Real; 3]) -> Obb {
        Obb {
            center,
            axes,
            half_lengths,
        }
    }

    /// Kratos' 3D construction from a geometry with enlargement `enlargement` (`f`, added to
    /// every half-length): branch A ([`build_from_aabb`](Self::build_from_aabb)) when
    /// `build_from_bounding_box` is true or the geometry is a solid, else branch B
    /// ([`build_from_normal`](Self::build_from_normal)).
    pub fn from_geometry(
        geometry: &Geometry<'_>,
        enlargement: Real,
        build_from_bounding_box: bool,
    ) -> Result<Obb, Error> {
        if build_from_bounding_box || geometry.kind().is_solid() {
            Obb::build_from_aabb(geometry, enlargement)
        } else {
            Obb::build_from_normal(geometry, enlargement)
        }
    }

    /// The 8 vertices `c + s_x h_0 A_0 + s_y h_1 A_1 + s_z h_2 A_2` in Kratos' sign order
    /// (the node order of the equivalent Hexahedra3D8), evaluated component-wise left to right
    /// as Kratos does.
    pub fn vertices(&self) -> [Point; 8] {
        core::array::from_fn(|i| {
            let s = SIGNS_3D[i];
            let mut p = self.center;
            for c in 0..3 {
                p[c] = self.center[c]
                    + s[0] * self.axes[0][c] * self.half_lengths[0]
                    + s[1] * self.axes[1][c] * self.half_lengths[1]
                    + s[2] * self.axes[2][c] * self.half_lengths[2];
            }
            p
        })
    }

    /// Kratos `CheckIsInside3D`: maps `p − c` by the inverse of the axis matrix `[A_0 A_1 A_2]`
    /// (a general inverse, not the transpose) and tests `|local_k| ≤ h_k + ε` (ε = f64::EPSILON).
    /// Returns false when the axis matrix is singular.
    pub fn contains_point(&self, p: &Point) -> bool {
        match self.inverse_axes() {
            Some(inv) => self.contains_point_with(&inv, p),
            None => false,
        }
    }

    pub(crate) fn inverse_axes(&self) -> Option<Matrix3> {
        Matrix3::from_columns(&self.axes).try_inverse()
    }

    pub(crate) fn contains_point_with(&self, inverse_axes: &Matrix3, p: &Point) -> bool {
        let local = inverse_axes * (p - self.center);
        (0..3).all(|k| local[k].abs() <= self.half_lengths[k] + EPS)
    }

    /// The axis-aligned box of the vertices.
    pub fn aabb(&self) -> Aabb {
        Aabb::from_points(&self.vertices())
    }

    /// Kratos `HasIntersection(other, type)`: [`ObbIntersection::Sat`] runs
    /// [`sat_obb_obb`] in `mode`; [`ObbIntersection::Direct`] runs [`direct_obb_obb`] (`mode`
    /// unused). True = the boxes intersect (touching counts, up to each test's tolerance).
    pub fn intersects(&self, other: &Obb, kind: ObbIntersection, mode: SatMode) -> bool {
        match kind {
            ObbIntersection::Sat => sat_obb_obb(self, other, mode),
            ObbIntersection::Direct => direct_obb_obb(self, other),
        }
    }
}
