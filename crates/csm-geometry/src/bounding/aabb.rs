//! [`Aabb`]: axis-aligned bounding box.

use crate::math::{Point, Real, Vector};

/// An axis-aligned box `[min, max]` (closed). An *empty* box has `min > max` in some component
/// ([`Aabb::EMPTY`]); every predicate on it is false.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Component-wise lower corner.
    pub min: Point,
    /// Component-wise upper corner.
    pub max: Point,
}

impl Aabb {
    /// The empty box (`min = +∞`, `max = −∞`), the identity of [`union`](Self::union).
    pub const EMPTY: Aabb = Aabb {
        min: Point::new(Real::INFINITY, Real::INFINITY, Real::INFINITY),
        max: Point::new(Real::NEG_INFINITY, Real::NEG_INFINITY, Real::NEG_INFINITY),
    };

    /// A box from its corners (not reordered).
    pub fn new(min: Point, max: Point) -> Aabb {
        Aabb { min, max }
    }

    /// The smallest box containing `points` (component-wise min/max, Kratos `BoundingBox`);
    /// [`Aabb::EMPTY`] for no points.
    pub fn from_points(points: &[Point]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.grow(p);
        }
        b
    }

    /// Extends the box to contain `p`.
    pub fn grow(&mut self, p: &Point) {
        self.min = self.min.inf(p);
        self.max = self.max.sup(p);
    }

    /// True if the box contains no point.
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// The smallest box containing both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }

    /// True if `p` lies in the closed box.
    pub fn contains(&self, p: &Point) -> bool {
        (0..3).all(|k| self.min[k] <= p[k] && p[k] <= self.max[k])
    }

    /// True if the closed boxes share a point (touching counts).
    pub fn intersects(&self, other: &Aabb) -> bool {
        (0..3).all(|k| {
            self.min[k] <= self.max[k]
                && other.min[k] <= other.max[k]
                && self.min[k] <= other.max[k]
                && other.min[k] <= self.max[k]
        })
    }

    /// The box grown by `margin` on every side (shrunk for a negative margin).
    pub fn enlarged(&self, margin: Real) -> Aabb {
        let m = Vector::repeat(margin);
        Aabb {
            min: self.min - m,
            max: self.max + m,
        }
    }

    /// The centre `(min + max)/2`.
    pub fn center(&self) -> Point {
        nalgebra::center(&self.min, &self.max)
    }

    /// The extent `max − min`.
    pub fn extents(&self) -> Vector {
        self.max - self.min
    }
}
