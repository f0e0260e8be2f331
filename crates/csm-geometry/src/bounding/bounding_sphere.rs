//! [`BoundingSphere`]: centre plus radius.

use crate::math::{Point, Real};

/// A sphere `|x − center| ≤ radius`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundingSphere {
    /// The centre.
    pub center: Point,
    /// The radius (≥ 0).
    pub radius: Real,
}

impl BoundingSphere {
    /// A sphere from centre and radius.
    pub fn new(center: Point, radius: Real) -> BoundingSphere {
        BoundingSphere { center, radius }
    }

    /// The sphere about `center` through the farthest of `points` (radius 0 for none):
    /// Kratos' `Radius()` with the geometry centre.
    pub fn from_points_about(center: Point, points: &[Point]) -> BoundingSphere {
        let radius = points
            .iter()
            .map(|p| (p - center).norm())
            .fold(0.0, Real::max);
        BoundingSphere { center, radius }
    }

    /// True if `p` lies in the closed ball.
    pub fn contains(&self, p: &Point) -> bool {
        (p - self.center).norm() <= self.radius
    }

    /// True if the closed balls share a point.
    pub fn intersects(&self, other: &BoundingSphere) -> bool {
        (other.center - self.center).norm() <= self.radius + other.radius
    }
}
