//! Segment–box overlap against hand cases and a sampling oracle.

use super::*;
use crate::math::Vector;

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

#[track_caller]
fn check(a: Point, b: Point, aabb: &Aabb, expected: bool) {
    assert_eq!(
        segment_aabb_intersect(&a, &b, aabb),
        expected,
        "{a:?} {b:?}"
    );
    assert_eq!(
        segment_aabb_intersect(&b, &a, aabb),
        expected,
        "{b:?} {a:?}"
    );
}

#[test]
fn hand_cases() {
    let b = Aabb::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 0.0));
    // 2D data: z = 0 on the segment and a box of zero thickness.
    check(p(-1.0, 0.5, 0.0), p(2.0, 0.5, 0.0), &b, true);
    check(p(0.2, 0.2, 0.0), p(0.3, 0.3, 0.0), &b, true);
    check(p(-1.0, -1.0, 0.0), p(2.0, 2.0, 0.0), &b, true);
    // Touching a corner, and missing it by a hair.
    check(
        p(1.0, 2.0, 0.0),
        p(2.0, 1.0, 0.0),
        &Aabb::new(p(0.0, 0.0, 0.0), p(1.5, 1.5, 0.0)),
        true,
    );
    check(p(1.0, 2.0, 0.0), p(2.0, 1.0, 0.0), &b, false);
    check(p(1.5, 0.5, 0.0), p(1.5, 3.0, 0.0), &b, false);
    // Ending on a face.
    check(p(1.0, 0.5, 0.0), p(3.0, 0.5, 0.0), &b, true);
    // Out of the plane of the flat box.
    check(p(0.5, 0.5, 1e-12), p(0.6, 0.5, 1e-12), &b, false);
    // A point segment.
    check(p(0.5, 0.5, 0.0), p(0.5, 0.5, 0.0), &b, true);
    check(p(0.5, 0.5, 0.0), p(0.5, 0.5, 0.0), &Aabb::EMPTY, false);
    check(p(f64::NAN, 0.5, 0.0), p(0.5, 0.5, 0.0), &b, false);
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

#[test]
fn agrees_with_the_sampling_oracle() {
    let mut rng = Rng::new(0x00C7_0EE5);
    let (mut hits, mut misses) = (0, 0);
    let n = 2000;
    for case in 0..3000 {
        let center = rng.point(-1.0, 1.0);
        let mut half = Vector::new(
            rng.uniform(0.0, 0.6),
            rng.uniform(0.0, 0.6),
            rng.uniform(0.0, 0.6),
        );
        let (mut a, mut b) = (rng.point(-1.5, 1.5), rng.point(-1.5, 1.5));
        if case % 3 == 0 {
            // 2D: everything in z = 0.
            half.z = 0.0;
            let mut c = center;
            c.z = 0.0;
            a.z = 0.0;
            b.z = 0.0;
            let aabb = Aabb::new(c - half, c + half);
            run(&aabb, &a, &b, n, case, &mut hits, &mut misses);
        } else {
            let aabb = Aabb::new(center - half, center + half);
            run(&aabb, &a, &b, n, case, &mut hits, &mut misses);
        }
    }
    assert!(hits > 300 && misses > 300, "{hits} hits, {misses} misses");
}

fn run(
    aabb: &Aabb,
    a: &Point,
    b: &Point,
    n: usize,
    case: usize,
    hits: &mut usize,
    misses: &mut usize,
) {
    let samples: Vec<Point> = (0..=n)
        .map(|i| a + (b - a) * (i as f64 / n as f64))
        .collect();
    let delta = (b - a).norm() / n as f64;
    let got = segment_aabb_intersect(a, b, aabb);
    if samples.iter().any(|q| aabb.contains(q)) {
        assert!(got, "case {case}: a sample is in the box");
    }
    if got {
        let grown = aabb.enlarged(delta * (1.0 + 1e-9));
        assert!(
            samples.iter().any(|q| grown.contains(q)),
            "case {case}: no sample near the box"
        );
        *hits += 1;
    } else {
        *misses += 1;
    }
}
