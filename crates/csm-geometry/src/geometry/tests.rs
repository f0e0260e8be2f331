//! Unit tests of the `geometry` module.
use crate::math::{Point, Vector};
use crate::{ErrorKind, Geometry, GeometryKind};

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

#[track_caller]
fn check_close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b}");
}

#[test]
fn new_checks_count_and_finiteness() {
    let pts = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let e = Geometry::new(GeometryKind::Triangle3D3, &pts).unwrap_err();
    assert_eq!(
        *e.kind(),
        ErrorKind::WrongNodeCount {
            expected: 3,
            found: 2
        }
    );
    let bad = [p(0.0, f64::NAN, 0.0), p(1.0, 0.0, 0.0)];
    let e = Geometry::new(GeometryKind::Line2D2, &bad).unwrap_err();
    assert_eq!(*e.kind(), ErrorKind::NonFinite);
}

#[test]
fn center_is_node_mean() {
    let pts = [p(0.0, 0.0, 0.0), p(3.0, 0.0, 0.0), p(0.0, 3.0, 3.0)];
    let g = Geometry::new(GeometryKind::Triangle3D3, &pts).unwrap();
    assert_eq!(g.center(), p(1.0, 1.0, 1.0));
}

#[test]
fn line_normal_points_right_of_direction() {
    let pts = [p(0.0, 0.0, 0.0), p(2.0, 0.0, 0.0)];
    let g = Geometry::new(GeometryKind::Line2D2, &pts).unwrap();
    assert_eq!(
        g.unit_normal(&Point::origin()).unwrap(),
        Vector::new(0.0, -1.0, 0.0)
    );
    assert_eq!(g.length().unwrap(), 2.0);
    assert_eq!(g.area().unwrap(), 2.0);
    let l = g.point_local_coordinates(&p(1.5, 7.0, 0.0)).unwrap();
    assert_eq!(l.x, 0.5);
}

#[test]
fn triangle_normal_area_length() {
    let pts = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let g = Geometry::new(GeometryKind::Triangle3D3, &pts).unwrap();
    let local = g.point_local_coordinates(&g.center()).unwrap();
    check_close(local.x, 1.0 / 3.0, 1e-15);
    assert_eq!(g.unit_normal(&local).unwrap(), Vector::new(0.0, 0.0, 1.0));
    check_close(g.area().unwrap(), 0.5, 1e-15);
    check_close(g.area_robust().unwrap(), 0.5, 1e-15);
    check_close(g.length().unwrap(), 1.0, 1e-15);
    assert_eq!(g.domain_size().unwrap(), g.area().unwrap());
}

#[test]
fn heron_vs_cross_product_on_a_sliver() {
    // A needle triangle: Heron (Kratos) loses digits (or goes NaN), the cross product does not.
    let pts = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.5, 1e-9, 0.0)];
    let g = Geometry::new(GeometryKind::Triangle3D3, &pts).unwrap();
    let robust = g.area_robust().unwrap();
    check_close(robust, 0.5e-9, 1e-24);
    match g.area() {
        Ok(heron) => assert!(
            (heron - robust).abs() / robust < 1e-3,
            "{heron} vs {robust}"
        ),
        Err(e) => assert!(matches!(e.kind(), ErrorKind::Degenerate(_))),
    }
    // Generic triangle: both agree closely.
    let pts = [p(0.1, 0.2, 0.3), p(1.4, -0.2, 0.5), p(0.3, 1.1, -0.4)];
    let g = Geometry::new(GeometryKind::Triangle3D3, &pts).unwrap();
    check_close(g.area().unwrap(), g.area_robust().unwrap(), 1e-14);
}

#[test]
fn quad_area_by_gauss_and_length() {
    let pts = [
        p(0.0, 0.0, 0.0),
        p(2.0, 0.0, 0.0),
        p(2.0, 0.0, 1.0),
        p(0.0, 0.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &pts).unwrap();
    check_close(g.area().unwrap(), 2.0, 1e-14);
    check_close(g.length().unwrap(), 2f64.sqrt(), 1e-14);
    // dX/dxi = +x, dX/deta = +z -> x × z = -y
    let n = g.unit_normal(&Point::origin()).unwrap();
    assert_eq!(n, Vector::new(0.0, -1.0, 0.0));
    let l = g.point_local_coordinates(&p(1.5, 3.0, 0.25)).unwrap();
    check_close(l.x, 0.5, 1e-12);
    check_close(l.y, -0.5, 1e-12);
}

#[test]
fn solids_volume_and_length() {
    let tet = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Tetrahedra3D4, &tet).unwrap();
    check_close(g.volume().unwrap(), 1.0 / 6.0, 1e-15);
    check_close(
        g.length().unwrap(),
        crate::TETRAHEDRON_LENGTH_FACTOR * (1.0f64 / 6.0).cbrt(),
        1e-15,
    );
    assert!(matches!(
        g.area().unwrap_err().kind(),
        ErrorKind::Unsupported(_)
    ));
    let hexa: Vec<Point> = crate::shape::reference_node_coordinates(GeometryKind::Hexahedra3D8)
        .iter()
        .map(|a| p(a[0] + 1.0, a[1] + 1.0, a[2] + 1.0))
        .collect();
    let g = Geometry::new(GeometryKind::Hexahedra3D8, &hexa).unwrap();
    check_close(g.volume().unwrap(), 8.0, 1e-13);
    check_close(g.length().unwrap(), 1.0, 1e-14);
    let prism = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 2.0),
        p(1.0, 0.0, 2.0),
        p(0.0, 1.0, 2.0),
    ];
    let g = Geometry::new(GeometryKind::Prism3D6, &prism).unwrap();
    check_close(g.volume().unwrap(), 1.0, 1e-14);
    let tri = [p(0.0, 0.0, 0.0), p(2.0, 0.0, 0.0), p(0.0, 2.0, 0.0)];
    let g = Geometry::new(GeometryKind::Triangle2D3, &tri).unwrap();
    check_close(g.area().unwrap(), 2.0, 1e-14);
    check_close(g.length().unwrap(), 2.0, 1e-14);
    assert!(g.unit_normal(&Point::origin()).is_err());
}

#[test]
fn inside_tests_with_tolerance() {
    let tet = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Tetrahedra3D4, &tet).unwrap();
    assert!(g.is_inside(&p(0.2, 0.2, 0.2), 0.0).unwrap().is_some());
    assert!(g.is_inside(&p(0.5, 0.5, 0.01), 0.0).unwrap().is_none());
    assert!(g.is_inside(&p(0.5, 0.5, 0.01), 0.02).unwrap().is_some());
    let quad = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(0.0, 1.0, 0.0),
    ];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &quad).unwrap();
    // Off-plane points are projected.
    let l = g.is_inside(&p(0.5, 0.5, 3.0), 0.0).unwrap().unwrap();
    check_close(l.x, 0.0, 1e-12);
    assert!(g.is_inside(&p(1.05, 0.5, 0.0), 0.0).unwrap().is_none());
    assert!(g.is_inside(&p(1.05, 0.5, 0.0), 0.11).unwrap().is_some());
}

#[test]
fn degenerate_inputs_are_errors() {
    let line = [p(1.0, 1.0, 0.0), p(1.0, 1.0, 0.0)];
    let g = Geometry::new(GeometryKind::Line2D2, &line).unwrap();
    assert!(g.length().is_err());
    assert!(g.unit_normal(&Point::origin()).is_err());
    assert!(g.point_local_coordinates(&p(0.0, 0.0, 0.0)).is_err());
    let tri = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(2.0, 0.0, 0.0)];
    let g = Geometry::new(GeometryKind::Triangle3D3, &tri).unwrap();
    assert!(g.area().is_err());
    assert!(g.area_robust().is_err());
    assert!(g.length().is_err());
    assert!(g.unit_normal(&Point::origin()).is_err());
    assert!(g.point_local_coordinates(&p(0.5, 0.5, 0.0)).is_err());
    assert!(g.is_inside(&p(0.5, 0.5, 0.0), 0.0).is_err());
    let quad = [p(0.0, 0.0, 0.0); 4];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &quad).unwrap();
    assert!(g.area().is_err());
    assert!(g.unit_normal(&Point::origin()).is_err());
    let tet = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(1.0, 1.0, 0.0),
    ];
    let g = Geometry::new(GeometryKind::Tetrahedra3D4, &tet).unwrap();
    assert!(g.volume().is_err());
    assert!(g.length().is_err());
    assert!(g.is_inside(&p(0.1, 0.1, 0.0), 0.0).is_err());
    let ok = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let g = Geometry::new(GeometryKind::Triangle3D3, &ok).unwrap();
    assert!(g.point_local_coordinates(&p(f64::NAN, 0.0, 0.0)).is_err());
    assert!(g.unit_normal(&p(f64::INFINITY, 0.0, 0.0)).is_err());
    assert!(g.is_inside(&p(0.1, 0.1, 0.0), f64::NAN).is_err());
}
