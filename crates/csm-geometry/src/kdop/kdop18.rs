//! The 18-DOP: the intersection of 9 slabs, along x, y, z, x ± y, y ± z and x ± z.

use crate::math::{Point, Real, Vector};

const S: Real = std::f64::consts::FRAC_1_SQRT_2;

/// The 9 unit slab directions of the 18-DOP: x, y, z, (x+y), (x−y), (y+z), (y−z), (x+z),
/// (x−z), the diagonal ones normalised.
pub const KDOP18_DIRECTIONS: [[Real; 3]; 9] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [S, S, 0.0],
    [S, -S, 0.0],
    [0.0, S, S],
    [0.0, S, -S],
    [S, 0.0, S],
    [S, 0.0, -S],
];

fn project(p: &Point, d: &[Real; 3]) -> Real {
    p.x * d[0] + p.y * d[1] + p.z * d[2]
}

/// An 18-DOP: for each of the 9 [`KDOP18_DIRECTIONS`], the interval `[min, max]` of the
/// projections of the enclosed points. Empty (`min > max`) until a point is added.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kdop18 {
    /// Lower end of every slab.
    pub min: [Real; 9],
    /// Upper end of every slab.
    pub max: [Real; 9],
}

impl Kdop18 {
    /// The empty 18-DOP.
    pub const EMPTY: Kdop18 = Kdop18 {
        min: [Real::INFINITY; 9],
        max: [Real::NEG_INFINITY; 9],
    };

    /// The tightest 18-DOP around `points` (empty for no point).
    pub fn from_points(points: &[Point]) -> Kdop18 {
        let mut k = Kdop18::EMPTY;
        for p in points {
            k.grow(p);
        }
        k
    }

    /// Extends the slabs to contain `p`.
    pub fn grow(&mut self, p: &Point) {
        for (i, d) in KDOP18_DIRECTIONS.iter().enumerate() {
            let x = project(p, d);
            self.min[i] = self.min[i].min(x);
            self.max[i] = self.max[i].max(x);
        }
    }

    /// Every slab widened by `margin` on both sides (the OBB-like enlargement: the search
    /// uses `bounding_box_factor × hmax`, as for the OBB half-lengths).
    pub fn enlarged(&self, margin: Real) -> Kdop18 {
        let mut k = *self;
        for i in 0..9 {
            k.min[i] -= margin;
            k.max[i] += margin;
        }
        k
    }

    /// The 18-DOP of `points` swept along `direction` from `−depth` to `+depth`: it contains
    /// every point `p + t·direction` with `|t| ≤ depth` (`direction` need not be unit). Used by
    /// the robust k-DOP search so that a master lying up to `depth` in front of or behind the
    /// slave face (penetration) stays a candidate.
    pub fn swept(points: &[Point], direction: &Vector, depth: Real) -> Kdop18 {
        let mut k = Kdop18::EMPTY;
        let offset = direction * depth;
        for p in points {
            k.grow(&(p + offset));
            k.grow(&(p - offset));
        }
        k
    }

    /// True when the two 18-DOPs overlap on every slab (touching counts). An 18-DOP test is
    /// conservative: overlapping DOPs may enclose disjoint shapes, never the reverse.
    pub fn intersects(&self, other: &Kdop18) -> bool {
        (0..9).all(|i| self.min[i] <= other.max[i] && other.min[i] <= self.max[i])
    }

    /// True when `p` lies in every slab.
    pub fn contains(&self, p: &Point) -> bool {
        KDOP18_DIRECTIONS.iter().enumerate().all(|(i, d)| {
            let x = project(p, d);
            self.min[i] <= x && x <= self.max[i]
        })
    }

    /// True when no point has been added.
    pub fn is_empty(&self) -> bool {
        self.min[0] > self.max[0]
    }
}
