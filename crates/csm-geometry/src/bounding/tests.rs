//! Unit tests of the `bounding` module.
use super::*;
use crate::math::Point;

#[test]
fn aabb_basics() {
    let b = Aabb::from_points(&[Point::new(1.0, -1.0, 0.0), Point::new(-1.0, 2.0, 0.5)]);
    assert_eq!(b.min, Point::new(-1.0, -1.0, 0.0));
    assert_eq!(b.max, Point::new(1.0, 2.0, 0.5));
    assert!(b.contains(&Point::new(1.0, 2.0, 0.5)));
    assert!(!b.contains(&Point::new(1.0, 2.0, 0.6)));
    let c = Aabb::new(Point::new(1.0, 2.0, 0.5), Point::new(3.0, 3.0, 3.0));
    assert!(b.intersects(&c) && c.intersects(&b), "touching counts");
    let d = Aabb::new(Point::new(1.1, 2.0, 0.5), Point::new(3.0, 3.0, 3.0));
    assert!(!b.intersects(&d) && !d.intersects(&b));
    assert!(b.enlarged(0.1).intersects(&d));
    assert_eq!(b.union(&d).max, Point::new(3.0, 3.0, 3.0));
    assert!(Aabb::EMPTY.is_empty());
    assert!(!Aabb::EMPTY.intersects(&b));
    assert_eq!(Aabb::EMPTY.union(&b), b);
}

#[test]
fn sphere_radius_is_farthest_node() {
    let pts = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(2.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
    ];
    let s = BoundingSphere::from_points_about(Point::new(0.5, 0.0, 0.0), &pts);
    assert_eq!(s.radius, 1.5);
    assert!(s.contains(&pts[1]));
    assert!(s.intersects(&BoundingSphere::new(Point::new(3.0, 0.0, 0.0), 1.5)));
}
