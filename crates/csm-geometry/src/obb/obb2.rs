//! [`Obb2`]: the 2D oriented bounding box.

use crate::bounding::Aabb;
use crate::intersection::{ObbIntersection, SatMode, direct_obb2_obb2, sat_obb2_obb2};
use crate::math::{EPS, Point, Real, Vector};

/// Vertex sign table of Kratos' 2D OBB (the node order of the equivalent Quadrilateral2D4).
pub(crate) const SIGNS_2D: [[Real; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// A 2D oriented bounding box in the xy plane (three components, z = 0 for 2D data): centre
/// `c`, axes `A_0, A_1` and half-lengths `h_0, h_1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb2 {
    /// Centre `c`.
    pub center: Point,
    /// Axes `A_0, A_1`.
    pub axes: [Vector; 2],
    /// Half-lengths `h_0, h_1`.
    pub half_lengths: [Real; 2],
}

impl Obb2 {
    /// A box from centre, axes and half-lengths (Kratos' direct constructor; no checks).
    pub fn new(center: Point, axes: [Vector; 2], half_lengths: [Real; 2]) -> Obb2 {
        Obb2 {
            center,
            axes,
            half_lengths,
        }
    }

    /// The 4 vertices `c + s_x h_0 A_0 + s_y h_1 A_1` in Kratos' sign order.
    pub fn vertices(&self) -> [Point; 4] {
        core::array::from_fn(|i| {
            let s = SIGNS_2D[i];
            let mut p = self.center;
            for c in 0..3 {
                p[c] = self.center[c]
                    + s[0] * self.axes[0][c] * self.half_lengths[0]
                    + s[1] * self.axes[1][c] * self.half_lengths[1];
            }
            p
        })
    }

    /// Kratos `CheckIsInside2D`: rotates `p` about `c` by `−atan2(A_0.y, A_0.x)` (skipped when
    /// that angle is below ε in magnitude), then tests `|x' − c_x| ≤ h_0 + ε` and
    /// `|y' − c_y| ≤ h_1 + ε` (ε = f64::EPSILON).
    pub fn contains_point(&self, p: &Point) -> bool {
        let c = self.center;
        let angle = -self.axes[0].y.atan2(self.axes[0].x);
        let (x, y) = if angle.abs() < EPS {
            (p.x, p.y)
        } else {
            let dx = p.x - c.x;
            let dy = p.y - c.y;
            (
                angle.cos() * dx - angle.sin() * dy + c.x,
                angle.cos() * dy + angle.sin() * dx + c.y,
            )
        };
        (x - c.x).abs() <= self.half_lengths[0] + EPS
            && (y - c.y).abs() <= self.half_lengths[1] + EPS
    }

    /// The axis-aligned box of the vertices.
    pub fn aabb(&self) -> Aabb {
        Aabb::from_points(&self.vertices())
    }

    /// Kratos `HasIntersection(other, type)` in 2D: [`sat_obb2_obb2`] or [`direct_obb2_obb2`].
    pub fn intersects(&self, other: &Obb2, kind: ObbIntersection, mode: SatMode) -> bool {
        match kind {
            ObbIntersection::Sat => sat_obb2_obb2(self, other, mode),
            ObbIntersection::Direct => direct_obb2_obb2(self, other),
        }
    }
}
