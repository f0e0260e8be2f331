//! Shared helpers: a seeded RNG, random rotations and boxes, the parry oracle.

use csm_geometry::Obb;
use csm_geometry::math::{Matrix3, Point, Vector};
use parry3d_f64::na::{Isometry3, Translation3, UnitQuaternion};
use parry3d_f64::query;
use parry3d_f64::shape::Cuboid;

/// SplitMix64: small, seeded, reproducible.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    pub fn vector(&mut self, lo: f64, hi: f64) -> Vector {
        Vector::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }

    pub fn unit_vector(&mut self) -> Vector {
        loop {
            let v = self.vector(-1.0, 1.0);
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }

    pub fn rotation(&mut self) -> UnitQuaternion<f64> {
        let axis = self.unit_vector();
        let angle = self.range(-std::f64::consts::PI, std::f64::consts::PI);
        UnitQuaternion::from_scaled_axis(axis * angle)
    }
}

/// A box as both csm and parry see it.
#[derive(Debug, Clone, Copy)]
pub struct TestBox {
    pub center: Point,
    pub rotation: UnitQuaternion<f64>,
    pub half: [f64; 3],
}

impl TestBox {
    pub fn obb(&self) -> Obb {
        let m: Matrix3 = *self.rotation.to_rotation_matrix().matrix();
        Obb::new(
            self.center,
            [
                m.column(0).into_owned(),
                m.column(1).into_owned(),
                m.column(2).into_owned(),
            ],
            self.half,
        )
    }

    fn iso(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.center.coords), self.rotation)
    }

    fn cuboid(&self) -> Cuboid {
        Cuboid::new(Vector::new(self.half[0], self.half[1], self.half[2]))
    }

    /// Rigid motion `x ↦ R x + T` applied to the box.
    pub fn moved(&self, r: &UnitQuaternion<f64>, t: &Vector) -> TestBox {
        TestBox {
            center: Point::from(r * self.center.coords + t),
            rotation: r * self.rotation,
            half: self.half,
        }
    }
}

/// parry's verdict and distance (0 when intersecting).
pub fn parry(a: &TestBox, b: &TestBox) -> (bool, f64) {
    let hit = query::intersection_test(&a.iso(), &a.cuboid(), &b.iso(), &b.cuboid())
        .expect("cuboid-cuboid is supported");
    let d = if hit {
        0.0
    } else {
        query::distance(&a.iso(), &a.cuboid(), &b.iso(), &b.cuboid()).expect("supported")
    };
    (hit, d)
}

/// The largest gap between the projections of the two boxes over the 15 SAT axes (normalised;
/// cross axes of (near-)parallel pairs skipped), computed independently of the crate in box 1's
/// frame. A lower bound of the distance, positive iff separated (up to rounding). Used to widen
/// the touching band where parry's own distance is unreliable (parry reports e.g. a distance of
/// 0.17 for exactly touching aligned boxes).
pub fn sat_gap(a: &TestBox, b: &TestBox) -> f64 {
    let ra = a.rotation.to_rotation_matrix();
    let rb = a.rotation.inverse() * b.rotation;
    let mb = rb.to_rotation_matrix();
    let t = ra.inverse() * (b.center - a.center);
    let ea = [Vector::x(), Vector::y(), Vector::z()];
    let eb: [Vector; 3] = core::array::from_fn(|k| mb.matrix().column(k).into_owned());
    let mut axes: Vec<Vector> = ea.iter().chain(&eb).copied().collect();
    for x in &ea {
        for y in &eb {
            let c = x.cross(y);
            if c.norm() > 1e-12 {
                axes.push(c.normalize());
            }
        }
    }
    axes.iter()
        .map(|n| {
            let r: f64 = (0..3)
                .map(|k| a.half[k] * ea[k].dot(n).abs() + b.half[k] * eb[k].dot(n).abs())
                .sum();
            t.dot(n).abs() - r
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The length scale of a pair (as in the robust SAT's tolerance).
pub fn scale(a: &TestBox, b: &TestBox) -> f64 {
    a.half.iter().chain(&b.half).sum::<f64>()
        + (b.center - a.center).norm()
        + a.center.coords.amax()
        + b.center.coords.amax()
}

/// The touching band used by the oracle comparisons: pairs whose parry distance is positive
/// but at most `BAND · scale` are not compared (documented touching tolerance of the robust
/// SAT is 1e-9 · scale; the band adds margin for parry's own GJK tolerance).
pub const BAND: f64 = 1e-8;

/// The kinds of random pairs.
#[derive(Debug, Clone, Copy)]
pub enum PairKind {
    /// Independent random boxes.
    Generic,
    /// Box 2 rotated from box 1 by a tiny angle 10^u, u ∈ [−12, −6].
    NearlyParallel,
    /// Box 2 with exactly the same axes as box 1.
    Aligned,
    /// Box 2 with the same (or nearly the same) axes placed face-to-face with box 1, with a gap
    /// of 0 or ± a tiny amount.
    Touching,
}

pub fn random_pair(rng: &mut Rng, kind: PairKind) -> (TestBox, TestBox) {
    let half = |rng: &mut Rng| {
        [
            rng.range(0.02, 2.0),
            rng.range(0.02, 2.0),
            rng.range(0.02, 2.0),
        ]
    };
    let a = TestBox {
        center: Point::from(rng.vector(-2.0, 2.0)),
        rotation: rng.rotation(),
        half: half(rng),
    };
    let tiny = |rng: &mut Rng| {
        let angle = 10f64.powf(rng.range(-12.0, -6.0));
        UnitQuaternion::from_scaled_axis(rng.unit_vector() * angle)
    };
    let b = match kind {
        PairKind::Generic => TestBox {
            center: Point::from(rng.vector(-3.0, 3.0)),
            rotation: rng.rotation(),
            half: half(rng),
        },
        PairKind::NearlyParallel => TestBox {
            center: Point::from(a.center.coords + rng.vector(-3.0, 3.0)),
            rotation: a.rotation * tiny(rng),
            half: half(rng),
        },
        PairKind::Aligned => TestBox {
            center: Point::from(a.center.coords + rng.vector(-3.0, 3.0)),
            rotation: a.rotation,
            half: half(rng),
        },
        PairKind::Touching => {
            let h2 = half(rng);
            let k = (rng.next_u64() % 3) as usize;
            let sign = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
            let gap = match rng.next_u64() % 3 {
                0 => 0.0,
                1 => 10f64.powf(rng.range(-14.0, -4.0)),
                _ => -(10f64.powf(rng.range(-14.0, -4.0))),
            };
            let m = a.rotation.to_rotation_matrix();
            let axis: Vector = m.matrix().column(k).into_owned();
            let mut offset = axis * (sign * (a.half[k] + h2[k] + gap));
            for (j, (ha, hb)) in a.half.iter().zip(&h2).enumerate() {
                if j != k {
                    let lateral: Vector = m.matrix().column(j).into_owned();
                    offset += lateral * rng.range(-(ha + hb), ha + hb) * 0.9;
                }
            }
            let rotation = if rng.unit() < 0.5 {
                a.rotation
            } else {
                a.rotation * tiny(rng)
            };
            TestBox {
                center: Point::from(a.center.coords + offset),
                rotation,
                half: h2,
            }
        }
    };
    (a, b)
}

pub const ALL_KINDS: [PairKind; 4] = [
    PairKind::Generic,
    PairKind::NearlyParallel,
    PairKind::Aligned,
    PairKind::Touching,
];
