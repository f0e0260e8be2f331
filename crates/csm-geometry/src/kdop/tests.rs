use super::*;
use crate::math::{Point, Vector};

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

/// A tiny deterministic generator (xorshift) so the oracle test needs no RNG crate.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn point(&mut self, scale: f64) -> Point {
        p(
            self.next() * scale,
            self.next() * scale,
            self.next() * scale,
        )
    }
}

#[test]
fn contains_its_points_and_rejects_far_ones() {
    let pts = [p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.)];
    let k = Kdop18::from_points(&pts);
    assert!(pts.iter().all(|q| k.contains(q)));
    assert!(k.contains(&p(0.25, 0.25, 0.0)));
    // Outside the triangle's hypotenuse: the x+y slab cuts it off although the AABB holds it.
    assert!(!k.contains(&p(0.9, 0.9, 0.0)));
    assert!(!k.contains(&p(0.2, 0.2, 0.1)));
    assert!(Kdop18::EMPTY.is_empty() && !k.is_empty());
}

#[test]
fn intersection_is_symmetric_and_conservative() {
    // Oracle: if two point clouds share a point, their DOPs intersect; DOPs of clouds far apart
    // do not; the verdict is symmetric.
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for _ in 0..500 {
        let a: Vec<Point> = (0..4).map(|_| rng.point(1.0)).collect();
        let mut b: Vec<Point> = (0..4)
            .map(|_| rng.point(1.0) + Vector::new(rng.next(), 0.0, 0.0))
            .collect();
        let ka = Kdop18::from_points(&a);
        let kb = Kdop18::from_points(&b);
        assert_eq!(ka.intersects(&kb), kb.intersects(&ka));
        b.push(a[0]);
        assert!(
            ka.intersects(&Kdop18::from_points(&b)),
            "a shared point must intersect"
        );
        let far: Vec<Point> = a.iter().map(|q| q + Vector::new(3.0, 0.0, 0.0)).collect();
        assert!(!ka.intersects(&Kdop18::from_points(&far)));
    }
}

#[test]
fn enlargement_and_sweep() {
    let face = [p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.)];
    let below = [p(0.2, 0.2, -0.5), p(0.3, 0.2, -0.5), p(0.2, 0.3, -0.5)];
    let k = Kdop18::from_points(&face);
    let kb = Kdop18::from_points(&below);
    assert!(!k.intersects(&kb));
    assert!(
        !k.enlarged(0.1).intersects(&kb),
        "a thin enlargement loses a deep master"
    );
    assert!(k.enlarged(0.5).intersects(&kb));
    let swept = Kdop18::swept(&face, &Vector::new(0.0, 0.0, 1.0), 0.6);
    assert!(swept.intersects(&kb), "the sweep along the normal keeps it");
    assert!(swept.contains(&p(0.1, 0.1, 0.6)) && swept.contains(&p(0.1, 0.1, -0.6)));
}
