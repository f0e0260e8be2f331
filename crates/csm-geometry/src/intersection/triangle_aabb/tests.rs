//! Triangle–box overlap against hand cases and a sampling oracle.

use super::*;
use crate::math::Point;

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

fn unit_box() -> Aabb {
    Aabb::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0))
}

/// Both vertex rotations and both orientations give the same verdict.
#[track_caller]
fn check(tri: [Point; 3], aabb: &Aabb, expected: bool) {
    let [a, b, c] = tri;
    for t in [
        [a, b, c],
        [b, c, a],
        [c, a, b],
        [a, c, b],
        [c, b, a],
        [b, a, c],
    ] {
        assert_eq!(triangle_aabb_intersect(&t, aabb), expected, "{t:?}");
    }
}

#[test]
fn hand_cases() {
    let b = unit_box();
    // A vertex inside.
    check(
        [p(0.5, 0.5, 0.5), p(3.0, 0.0, 0.0), p(0.0, 3.0, 0.0)],
        &b,
        true,
    );
    // Slicing through the box, no vertex inside, no edge through it.
    check(
        [p(-5.0, -5.0, 0.5), p(10.0, -5.0, 0.5), p(-5.0, 10.0, 0.5)],
        &b,
        true,
    );
    // Touching a face from outside.
    check(
        [p(1.0, 0.2, 0.2), p(2.0, 0.2, 0.2), p(2.0, 0.8, 0.8)],
        &b,
        true,
    );
    // Parallel to a face, just outside.
    check(
        [
            p(-5.0, -5.0, 1.0 + 1e-9),
            p(10.0, -5.0, 1.0 + 1e-9),
            p(-5.0, 10.0, 1.0 + 1e-9),
        ],
        &b,
        false,
    );
    // In the plane x + y = 2.5, which misses the box; the same in x + y = 1.5 crosses it.
    check(
        [p(2.5, 0.0, -1.0), p(0.0, 2.5, -1.0), p(0.0, 2.5, 2.0)],
        &b,
        false,
    );
    check(
        [p(1.5, 0.0, -1.0), p(0.0, 1.5, -1.0), p(0.0, 1.5, 2.0)],
        &b,
        true,
    );
    // Its plane crosses the box but the triangle is beside it.
    check(
        [p(2.0, -1.0, 0.0), p(3.0, -1.0, 0.0), p(2.0, 3.0, 3.0)],
        &b,
        false,
    );
    // A degenerate triangle (a segment) crossing the box, and one passing beside it.
    check(
        [p(-1.0, 0.5, 0.5), p(2.0, 0.5, 0.5), p(0.5, 0.5, 0.5)],
        &b,
        true,
    );
    check(
        [p(-1.0, 1.5, 0.5), p(2.0, 1.5, 0.5), p(0.5, 1.5, 0.5)],
        &b,
        false,
    );
    // A flat box (zero thickness in z, the octree's flat root box) and a triangle in its plane.
    let flat = Aabb::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 0.0));
    check(
        [p(0.5, 0.5, 0.0), p(3.0, 0.5, 0.0), p(0.5, 3.0, 0.0)],
        &flat,
        true,
    );
    check(
        [p(0.5, 0.5, 1e-12), p(3.0, 0.5, 1e-12), p(0.5, 3.0, 1e-12)],
        &flat,
        false,
    );
    // Empty box and NaN.
    check(
        [p(0.5, 0.5, 0.5), p(0.6, 0.5, 0.5), p(0.5, 0.6, 0.5)],
        &Aabb::EMPTY,
        false,
    );
    check(
        [p(f64::NAN, 0.5, 0.5), p(0.6, 0.5, 0.5), p(0.5, 0.6, 0.5)],
        &b,
        false,
    );
}

/// xorshift64*: a seeded generator, so the cases are the same on every run.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        lo + (hi - lo) * (bits as f64 / (1u64 << 53) as f64)
    }

    fn point(&mut self, lo: f64, hi: f64) -> Point {
        p(
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        )
    }
}

/// Sampling oracle: the barycentric grid of step `1/n` on the triangle. Every point of the
/// triangle lies within `max edge / n` of a sample, so
/// * a sample in the box ⇒ the triangle meets the box;
/// * the triangle meets the box ⇒ a sample lies in the box grown by `max edge / n`.
fn samples(tri: &[Point; 3], n: usize) -> (Vec<Point>, f64) {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let mut out = Vec::new();
    for i in 0..=n {
        for j in 0..=n - i {
            out.push(tri[0] + e1 * (i as f64 / n as f64) + e2 * (j as f64 / n as f64));
        }
    }
    let longest = [e1.norm(), e2.norm(), (tri[2] - tri[1]).norm()]
        .into_iter()
        .fold(0.0, f64::max);
    (out, longest / n as f64)
}

#[test]
fn agrees_with_the_sampling_oracle() {
    let mut rng = Rng::new(0x5EED_7A1B);
    let (mut hits, mut misses) = (0, 0);
    for case in 0..3000 {
        let center = rng.point(-1.0, 1.0);
        let mut half = Vector::new(
            rng.uniform(0.0, 0.6),
            rng.uniform(0.0, 0.6),
            rng.uniform(0.0, 0.6),
        );
        if case % 5 == 0 {
            half[case % 3] = 0.0; // flat boxes
        }
        let aabb = Aabb::new(center - half, center + half);
        let mut tri = [
            rng.point(-1.5, 1.5),
            rng.point(-1.5, 1.5),
            rng.point(-1.5, 1.5),
        ];
        if case % 7 == 0 {
            tri[2] = tri[0] + (tri[1] - tri[0]) * rng.uniform(0.0, 1.0); // degenerate
        }
        let (points, delta) = samples(&tri, 60);
        let got = triangle_aabb_intersect(&tri, &aabb);
        if points.iter().any(|q| aabb.contains(q)) {
            assert!(got, "case {case}: a sample is in the box: {tri:?} {aabb:?}");
        }
        if got {
            let grown = aabb.enlarged(delta * (1.0 + 1e-9));
            assert!(
                points.iter().any(|q| grown.contains(q)),
                "case {case}: reported overlap, no sample near the box: {tri:?} {aabb:?}"
            );
            hits += 1;
        } else {
            misses += 1;
        }
    }
    assert!(hits > 300 && misses > 300, "{hits} hits, {misses} misses");
}
