//! Unit tests of the `projection` module.
use super::*;
use crate::math::{Point, Vector};

#[test]
fn fast_project_signed_distance() {
    let (q, d) = fast_project(
        &Point::new(0.0, 0.0, 1.0),
        &Point::new(0.3, 0.2, 3.0),
        &Vector::new(0.0, 0.0, 1.0),
    );
    assert_eq!(d, 2.0);
    assert_eq!(q, Point::new(0.3, 0.2, 1.0));
    let (_, d) = fast_project(
        &Point::new(0.0, 0.0, 1.0),
        &Point::new(0.3, 0.2, 0.5),
        &Vector::new(0.0, 0.0, 1.0),
    );
    assert_eq!(d, -0.5);
}

#[test]
fn fast_project_direction_cases() {
    let o = Point::new(0.0, 0.0, 0.0);
    let n = Vector::new(0.0, 0.0, 1.0);
    let p = Point::new(1.0, 0.0, 2.0);
    // Oblique direction lands on the plane.
    let (q, d) = fast_project_direction(&o, &p, &n, &Vector::new(1.0, 0.0, -1.0));
    assert_eq!(d, 2.0);
    assert_eq!(q, Point::new(3.0, 0.0, 0.0));
    // Along the normal: same as FastProject.
    let (q, d) = fast_project_direction(&o, &p, &n, &-n);
    assert_eq!((q, d), (Point::new(1.0, 0.0, 0.0), 2.0));
    // Parallel direction: Kratos gives distance 0 and the point itself.
    let (q, d) = fast_project_direction(&o, &p, &n, &Vector::new(1.0, 0.0, 0.0));
    assert_eq!((q, d), (p, 0.0));
    // Zero direction: distance along the normal, point unchanged.
    let (q, d) = fast_project_direction(&o, &p, &n, &Vector::zeros());
    assert_eq!((q, d), (p, -2.0));
}
