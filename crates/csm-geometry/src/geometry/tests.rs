//! Unit tests of the `geometry` module.
use crate::math::{Point, Vector};
use crate::test_support::uniform;
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

/// A warped (non-planar) quadrilateral used by the Kratos-order local-coordinates tests.
fn warped_quad() -> [Point; 4] {
    [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.1),
        p(1.1, 1.0, -0.05),
        p(0.0, 0.9, 0.2),
    ]
}

#[test]
fn quad_local_coordinates_planar_by_hand() {
    // Rectangle [0, 2] × [0, 1]: x = 1 + ξ, y = 0.5 + 0.5 η. For p = (1.5, 0.25, 3): the first
    // step has D = [[1, 0], [0, 0.5], [0, 0]], DᵀD = diag(1, 0.25), Dᵀr = (0.5, −0.125), so
    // Δξ = (0.5, −0.5) exactly; the second step is zero. The offset along z is ignored.
    let rect = [
        p(0.0, 0.0, 0.0),
        p(2.0, 0.0, 0.0),
        p(2.0, 1.0, 0.0),
        p(0.0, 1.0, 0.0),
    ];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &rect).unwrap();
    let l = g.point_local_coordinates(&p(1.5, 0.25, 3.0)).unwrap();
    assert_eq!((l.x, l.y, l.z), (0.5, -0.5, 0.0));
    let newton = g
        .point_local_coordinates_kratos_quadrilateral(&p(1.5, 0.25, 3.0))
        .unwrap();
    assert_eq!(
        newton.outcome,
        super::local_coordinates::NewtonOutcome::Converged
    );
    // Nodes map to the reference corners.
    for (x, (a, b)) in rect
        .iter()
        .zip([(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)])
    {
        let l = g.point_local_coordinates(x).unwrap();
        check_close(l.x, a, 1e-15);
        check_close(l.y, b, 1e-15);
    }
    // A planar trapezoid (not a parallelogram): the bilinear map of a known ξ comes back.
    let trap = [
        p(0.0, 0.0, 1.0),
        p(4.0, 0.0, 1.0),
        p(3.0, 2.0, 1.0),
        p(1.0, 2.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &trap).unwrap();
    // ξ = (0.5, 0.5): N = (1/16, 3/16, 9/16, 3/16) → x = (0 + 12 + 27 + 3)/16 = 2.625, y = 1.5.
    let l = g.point_local_coordinates(&p(2.625, 1.5, -2.0)).unwrap();
    check_close(l.x, 0.5, 1e-12);
    check_close(l.y, 0.5, 1e-12);
}

#[test]
fn quad_local_coordinates_match_kratos_bits() {
    // Values computed by Kratos 10.4.4's `Quadrilateral3D4::PointLocalCoordinatesImplementation`
    // (called in the pip build's libKratosCore.so) for the same inputs.
    let quad = warped_quad();
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &quad).unwrap();
    for (x, (a, b)) in [
        (
            p(0.3, 0.4, 0.5),
            (-0.486294003022787_f64, -0.02583163821308055_f64),
        ),
        (
            p(0.3, 0.4, 0.05),
            (-0.42250668889971377, -0.14368731625353295),
        ),
        (
            p(0.55, 0.5, 0.0625),
            (0.044927894693266274, 0.05020746332380995),
        ),
    ] {
        let l = g.point_local_coordinates(&x).unwrap();
        assert_eq!(
            (l.x.to_bits(), l.y.to_bits()),
            (a.to_bits(), b.to_bits()),
            "{x:?}"
        );
        assert_eq!(l.z, 0.0);
    }
}

#[test]
fn quad_inside_uses_kratos_last_iterate() {
    // kratos_double_curvature_quadrilateral, DirectCheck: slave node 76 projected (along the
    // slave normal) onto the plane of master condition 332 (nodes 110, 93, 90, 116). The point
    // is far from that quad; Kratos' Gauss–Newton iteration does not converge in its 500
    // iterations and its last iterate happens to lie inside, so Kratos reports the node inside
    // (and ACTIVE). The trajectory is chaotic: only a bit-for-bit reproduction gets it.
    let master = [
        p(58.1268144291, 10.8028316162, 4.1060288525),
        p(59.4881925172, 9.8519425071, 3.8687421806),
        p(60.3329854057, 9.2206450044, 5.6201095797),
        p(58.8399156420, 10.5999827513, 6.5493501723),
    ];
    let q = p(60.04688035266929, 8.939035794520148, 0.04976625339083992);
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &master).unwrap();
    let newton = g.point_local_coordinates_kratos_quadrilateral(&q).unwrap();
    assert_eq!(
        newton.outcome,
        super::local_coordinates::NewtonOutcome::MaxIterations
    );
    let (a, b) = (-0.6246259051769698_f64, -0.9368648261830903_f64);
    assert_eq!(
        (newton.local.x.to_bits(), newton.local.y.to_bits()),
        (a.to_bits(), b.to_bits())
    );
    let inside = g.is_inside(&q, f64::EPSILON).unwrap().unwrap();
    assert_eq!(inside, newton.local);
    // The strict API still reports the failure to converge.
    assert_eq!(
        *g.point_local_coordinates(&q).unwrap_err().kind(),
        ErrorKind::NotConverged
    );
}

#[test]
fn quad_local_coordinates_invariances() {
    let quad = warped_quad();
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &quad).unwrap();
    let x = p(0.7, 0.3, 0.4);
    let l = g.point_local_coordinates(&x).unwrap();
    // Least squares: the residual is orthogonal to both tangents at the solution.
    let r = x - g.global_coordinates(&l);
    let j = g.jacobian(&l);
    for c in 0..2 {
        let t = Vector::new(j[(0, c)], j[(1, c)], j[(2, c)]);
        assert!(r.dot(&t).abs() < 1e-9 * t.norm() * r.norm().max(1.0));
    }
    // The same iteration as the generic least-squares one, up to the convergence tolerance.
    let m = g.point_local_coordinates_least_squares(&x).unwrap();
    assert!((m - l).norm() < 1e-8);
    // Cyclic relabelling (node k+1 first) rotates the reference square: ξ' = η, η' = −ξ.
    let rolled = [quad[1], quad[2], quad[3], quad[0]];
    let g2 = Geometry::new(GeometryKind::Quadrilateral3D4, &rolled).unwrap();
    let l2 = g2.point_local_coordinates(&x).unwrap();
    check_close(l2.x, l.y, 1e-9);
    check_close(l2.y, -l.x, 1e-9);
    // Rigid motion (translation plus a rotation) of nodes and point together.
    let rot = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0);
    let shift = Vector::new(-7.0, 3.0, 11.0);
    let moved: Vec<Point> = quad.iter().map(|q| rot * q + shift).collect();
    let g3 = Geometry::new(GeometryKind::Quadrilateral3D4, &moved).unwrap();
    let l3 = g3.point_local_coordinates(&(rot * x + shift)).unwrap();
    check_close(l3.x, l.x, 1e-9);
    check_close(l3.y, l.y, 1e-9);
}

/// `face_unit_normals` and `centre_unit_normal` are bit-identical to evaluating the unit
/// normal at the local coordinates of the centre and of every node (the affine shortcut
/// included), and refuse solids.
#[test]
fn face_unit_normals_equal_the_per_point_normals_bit_for_bit() {
    let tri = [p(0.1, 0.2, 0.3), p(1.3, 0.1, 0.7), p(0.2, 1.1, -0.4)];
    let warped_quad = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.1, 0.2),
        p(1.1, 0.9, -0.1),
        p(-0.1, 1.0, 0.3),
    ];
    let line = [p(0.3, -0.2, 0.0), p(1.7, 0.4, 0.0)];
    let tri6 = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.1),
        p(0.0, 1.0, 0.0),
        p(0.5, 0.0, 0.1),
        p(0.5, 0.5, 0.2),
        p(0.0, 0.5, 0.0),
    ];
    for (kind, points) in [
        (GeometryKind::Triangle3D3, &tri[..]),
        (GeometryKind::Quadrilateral3D4, &warped_quad[..]),
        (GeometryKind::Line2D2, &line[..]),
        (GeometryKind::Triangle3D6, &tri6[..]),
    ] {
        let g = Geometry::new(kind, points).unwrap();
        let at = |q: &Point| {
            g.unit_normal(&g.point_local_coordinates(q).unwrap())
                .unwrap()
        };
        let normals = g.face_unit_normals().unwrap();
        assert_eq!(normals.centre, at(&g.center()), "{kind:?}");
        assert_eq!(g.centre_unit_normal().unwrap(), at(&g.center()), "{kind:?}");
        let expected: Vec<Vector> = points.iter().map(at).collect();
        assert_eq!(normals.nodes(), &expected[..], "{kind:?}");
        // Without the table: the nodal normals appended only where they can differ.
        let mut nodal = vec![Vector::x()];
        assert_eq!(
            g.face_unit_normals_into(&mut nodal).unwrap(),
            normals.centre
        );
        let appended = if normals.is_uniform() {
            &[][..]
        } else {
            normals.nodes()
        };
        assert_eq!(&nodal[1..], appended, "{kind:?}");
        assert_eq!(normals.is_uniform(), nodal.len() == 1, "{kind:?}");
    }
    let tet = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Tetrahedra3D4, &tet).unwrap();
    assert!(matches!(
        g.face_unit_normals().unwrap_err().kind(),
        ErrorKind::Unsupported(_)
    ));
    let mut nodal = vec![Vector::x()];
    assert!(matches!(
        g.face_unit_normals_into(&mut nodal).unwrap_err().kind(),
        ErrorKind::Unsupported(_)
    ));
    assert_eq!(nodal, [Vector::x()]);
    assert!(matches!(
        g.centre_unit_normal().unwrap_err().kind(),
        ErrorKind::Unsupported(_)
    ));
}

/// Linear geometries of every kind with a fast path (warped 3D faces, flat 2D faces), and
/// local points inside and outside their reference elements, for the bit-identity tests.
fn linear_samples() -> (Vec<(GeometryKind, Vec<Point>)>, Vec<Point>) {
    let quad = vec![
        p(0.1, 0.0, 0.3),
        p(1.2, 0.1, 0.2),
        p(1.1, 0.9, -0.1),
        p(-0.1, 1.3, 0.3),
    ];
    let tri = vec![p(0.1, 0.2, 0.3), p(1.3, 0.1, 0.7), p(0.2, 1.1, -0.4)];
    let tet = vec![
        p(0.0, 0.1, 0.0),
        p(1.0, 0.0, 0.2),
        p(0.1, 1.0, 0.0),
        p(0.0, 0.3, 1.0),
    ];
    let prism = vec![
        p(0.0, 0.0, 0.0),
        p(1.0, 0.1, 0.0),
        p(0.0, 1.0, 0.1),
        p(0.1, 0.0, 1.0),
        p(1.2, 0.0, 1.1),
        p(0.0, 1.1, 0.9),
    ];
    let flat_quad = vec![
        p(0.0, 0.0, 0.0),
        p(2.0, 0.0, 0.0),
        p(2.0, 1.0, 0.0),
        p(0.0, 1.5, 0.0),
    ];
    let flat_tri = vec![p(0.0, 0.0, 0.0), p(2.0, 0.5, 0.0), p(0.3, 1.0, 0.0)];
    let locals = vec![
        p(0.0, 0.0, 0.0),
        p(0.3, -0.7, 0.0),
        p(-1.0, 1.0, 0.0),
        p(0.25, 0.25, 0.25),
        p(-0.0, -0.0, 0.5),
        p(1e-17, -0.3333333333333333, 0.1),
    ];
    let geometries = vec![
        (GeometryKind::Quadrilateral3D4, quad),
        (GeometryKind::Quadrilateral2D4, flat_quad),
        (GeometryKind::Triangle3D3, tri),
        (GeometryKind::Triangle2D3, flat_tri),
        (GeometryKind::Tetrahedra3D4, tet),
        (GeometryKind::Prism3D6, prism),
    ];
    (geometries, locals)
}

/// The Jacobian's fast paths for the linear kinds are bit-identical to the generic
/// accumulation over `shape_derivatives`.
#[test]
fn jacobian_fast_paths_equal_the_generic_rows_bit_for_bit() {
    let (geometries, locals) = linear_samples();
    for (kind, points) in &geometries {
        let (kind, points) = (*kind, &points[..]);
        let g = Geometry::new(kind, points).unwrap();
        for local in &locals {
            let mut generic = crate::math::Matrix3::zeros();
            for (row, q) in g.shape_derivatives(local).rows().iter().zip(points) {
                for (k, dk) in row.iter().enumerate().take(kind.local_dim()) {
                    for c in 0..3 {
                        generic[(c, k)] += q[c] * dk;
                    }
                }
            }
            let fast = g.jacobian(local);
            for (a, b) in fast.iter().zip(generic.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "{kind:?} at {local:?}");
            }
        }
    }
}

/// `global_coordinates`' fast paths for the linear kinds are bit-identical to `Σ N_i X_i`
/// over `shape_functions`.
#[test]
fn global_coordinates_fast_paths_equal_the_shape_functions_bit_for_bit() {
    let (geometries, mut locals) = linear_samples();
    locals.push(p(0.1, 0.2, 0.30000000000000004));
    let three_d = geometries.iter().filter(|(kind, _)| {
        matches!(
            kind,
            GeometryKind::Quadrilateral3D4
                | GeometryKind::Triangle3D3
                | GeometryKind::Tetrahedra3D4
                | GeometryKind::Prism3D6
        )
    });
    for (kind, points) in three_d {
        let g = Geometry::new(*kind, points).unwrap();
        for local in &locals {
            let mut generic = Vector::zeros();
            for (ni, q) in g.shape_functions(local).iter().zip(points) {
                generic += q.coords * *ni;
            }
            let fast = g.global_coordinates(local);
            for (a, b) in fast.iter().zip(generic.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "{kind:?} at {local:?}");
            }
        }
    }
}

/// The solver prepared once per geometry answers bit for bit as the geometry itself, for
/// every kind it specialises (warped and far-translated quadrilaterals, triangles,
/// tetrahedra), the others, and degenerate geometries (the same error); so does its inside
/// test.
#[test]
fn local_coordinates_solver_matches_the_geometry_bit_for_bit() {
    use crate::LocalCoordinatesSolver;
    let mut next = uniform(0x9E37_79B9_7F4A_7C15);
    let kinds = [
        (GeometryKind::Quadrilateral3D4, 4),
        (GeometryKind::Triangle3D3, 3),
        (GeometryKind::Triangle2D3, 3),
        (GeometryKind::Tetrahedra3D4, 4),
        (GeometryKind::Quadrilateral3D8, 8),
    ];
    let mut compared = 0;
    for case in 0..400 {
        let (kind, n) = kinds[case % kinds.len()];
        let offset = if case % 7 == 0 { 1e6 } else { 0.0 };
        let reference: Vec<Point> = match kind {
            GeometryKind::Quadrilateral3D4 | GeometryKind::Quadrilateral3D8 => vec![
                p(-1.0, -1.0, 0.0),
                p(1.0, -1.0, 0.0),
                p(1.0, 1.0, 0.0),
                p(-1.0, 1.0, 0.0),
                p(0.0, -1.0, 0.0),
                p(1.0, 0.0, 0.0),
                p(0.0, 1.0, 0.0),
                p(-1.0, 0.0, 0.0),
            ],
            GeometryKind::Tetrahedra3D4 => vec![
                p(0.0, 0.0, 0.0),
                p(1.0, 0.0, 0.0),
                p(0.0, 1.0, 0.0),
                p(0.0, 0.0, 1.0),
            ],
            _ => vec![p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)],
        };
        let flat = kind == GeometryKind::Triangle2D3;
        let mut pts: Vec<Point> = reference[..n]
            .iter()
            .map(|q| {
                let z = if flat { 0.0 } else { q.z + 0.3 * next() };
                p(q.x + 0.3 * next() + offset, q.y + 0.3 * next(), z)
            })
            .collect();
        if case % 50 == 3 {
            // Coincident nodes: a degenerate geometry.
            pts[1] = pts[0];
        }
        let g = Geometry::new(kind, &pts).unwrap();
        let solver = LocalCoordinatesSolver::new(g);
        for _ in 0..10 {
            let z = if flat { 0.0 } else { 0.5 * next() };
            let x = p(2.0 * next() + offset, 2.0 * next(), z);
            let expected = g.point_local_coordinates(&x);
            let got = solver.local_coordinates(&x);
            match (&expected, &got) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a.coords.map(f64::to_bits), b.coords.map(f64::to_bits));
                    compared += 1;
                }
                (Err(a), Err(b)) => assert_eq!(a.kind(), b.kind()),
                _ => panic!("{kind:?}: {expected:?} vs {got:?}"),
            }
            if kind == GeometryKind::Quadrilateral3D4 {
                let a = g
                    .point_local_coordinates_kratos_quadrilateral(&x)
                    .map(|k| k.local);
                let b = solver.kratos_last_iterate(&x);
                match (a, b) {
                    (Ok(a), Ok(b)) => {
                        assert_eq!(a.coords.map(f64::to_bits), b.coords.map(f64::to_bits));
                    }
                    (Err(a), Err(b)) => assert_eq!(a.kind(), b.kind()),
                    (a, b) => panic!("last iterate {a:?} vs {b:?}"),
                }
            }
        }
    }
    assert!(compared > 3000, "only {compared} converged comparisons");
}

/// The inside tests' certificate (`quad_outside`) never changes an answer: on plane
/// quadrilaterals from near-parallelograms to strongly distorted, bow-tie and degenerate
/// ones, far from the origin and not, the solver with the certificate gives what Kratos'
/// iteration gives for every point (inside, outside, near the edges, far away, off the plane,
/// non-finite), errors included; and it does skip the iteration for most far points of the
/// regular ones.
#[test]
fn the_outside_certificate_gives_the_iterations_answer() {
    use super::quad_outside::QuadOutside;
    use crate::LocalCoordinatesSolver;
    use crate::math::EPS;
    let mut next = uniform(0x2545_F491_4F6C_DD1D);
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let (mut certified, mut outside, mut compared) = (0, 0, 0);
    for case in 0..600 {
        // Distortion from none to large; every 13th a bow-tie, every 29th degenerate.
        let warp = [0.0, 0.02, 0.1, 0.3, 0.8][case % 5];
        let offset = [0.0, 1e3, -7.5, 1e6][case % 4];
        let scale = [1.0, 1e-3, 40.0][case % 3];
        let z = offset + next();
        let mut pts: Vec<Point> = corners
            .iter()
            .map(|&(x, y)| {
                p(
                    offset + scale * (x + warp * next()),
                    offset + scale * (y + warp * next()),
                    z,
                )
            })
            .collect();
        if case % 13 == 5 {
            pts.swap(2, 3);
        }
        if case % 29 == 7 {
            pts[2] = pts[1];
        }
        let g = Geometry::new(GeometryKind::Quadrilateral3D4, &pts).unwrap();
        let plain = LocalCoordinatesSolver::new(g);
        let with = LocalCoordinatesSolver::new(g).with_outside_certificate();
        let certificate = QuadOutside::new(&pts);
        for k in 0..60 {
            let reach = [1.02, 1.5, 4.0, 30.0, 1e3][k % 5];
            let mut x = p(
                offset + scale * reach * 2.0 * next(),
                offset + scale * reach * 2.0 * next(),
                z,
            );
            match k % 20 {
                3 => x.z = z + scale * 0.1,
                7 => x = pts[k % 4],
                11 => x.x = f64::NAN,
                13 => x.y = f64::INFINITY,
                17 => x = Point::from((pts[0].coords + pts[1].coords) * 0.5),
                _ => {}
            }
            let expected = plain.is_inside(&x, EPS);
            let got = with.is_inside(&x, EPS);
            match (&expected, &got) {
                (Ok(a), Ok(b)) => assert_eq!(
                    a.map(|q| q.coords.map(f64::to_bits)),
                    b.map(|q| q.coords.map(f64::to_bits)),
                    "case {case}, point {k}"
                ),
                (Err(a), Err(b)) => assert_eq!(a.kind(), b.kind()),
                _ => panic!("case {case}, point {k}: {expected:?} vs {got:?}"),
            }
            compared += 1;
            // Near-parallelograms (not bow-ties) and points a few sizes away: the
            // neighbours the clipping tests.
            let mild = warp <= 0.02 && case % 13 != 5 && (1..=2).contains(&(k % 5));
            if mild && matches!(expected, Ok(None)) {
                outside += 1;
                certified += usize::from(
                    certificate
                        .as_ref()
                        .is_some_and(|c| c.certainly_outside(&x, EPS)),
                );
            }
        }
    }
    assert_eq!(compared, 600 * 60);
    // The certificate decides nearly all of those (the proof needs `κR ≤ 1/8`: farther
    // points or more distortion are left to the iteration).
    assert!(
        certified * 5 > outside * 4,
        "{certified} of {outside} outside points certified"
    );
}

/// No certificate for a quadrilateral whose nodes are not in one plane `z = const`, nor for a
/// degenerate one; a certificate never decides a point off its plane or a non-finite one.
#[test]
fn the_outside_certificate_applies_to_plane_quadrilaterals_only() {
    use super::quad_outside::QuadOutside;
    use crate::math::EPS;
    let square = [
        p(0.0, 0.0, 2.0),
        p(1.0, 0.0, 2.0),
        p(1.0, 1.0, 2.0),
        p(0.0, 1.0, 2.0),
    ];
    let c = QuadOutside::new(&square).expect("a plane square");
    assert!(c.certainly_outside(&p(5.0, 0.5, 2.0), EPS));
    assert!(c.certainly_outside(&p(-3.0, -3.0, 2.0), EPS));
    // Inside, on an edge, just beyond it (within the margin), off the plane, not finite.
    assert!(!c.certainly_outside(&p(0.5, 0.5, 2.0), EPS));
    assert!(!c.certainly_outside(&p(1.0, 0.5, 2.0), EPS));
    assert!(!c.certainly_outside(&p(1.0 + 1e-9, 0.5, 2.0), EPS));
    assert!(!c.certainly_outside(&p(5.0, 0.5, 2.0 + 1e-12), EPS));
    assert!(!c.certainly_outside(&p(f64::NAN, 0.5, 2.0), EPS));
    assert!(!c.certainly_outside(&p(f64::INFINITY, 0.5, 2.0), EPS));
    let mut tilted = square;
    tilted[2].z = 2.0 + 1e-15;
    assert!(QuadOutside::new(&tilted).is_none());
    let mut collapsed = square;
    collapsed[2] = collapsed[1];
    collapsed[3] = collapsed[0];
    assert!(QuadOutside::new(&collapsed).is_none());
    assert!(QuadOutside::new(&square[..3]).is_none());
}

/// `LargestArea` gives every face's `Geometry::area` (value bit for bit, or its error) and the
/// largest of many, with the short path taken by well-shaped triangles only: random triangles
/// at scales from 1e-70 to 1e70 (beyond, the radicand overflows or underflows: an error), needles on both sides of the degeneracy floor, far
/// translations, non-finite points, wrong node counts and quadrilaterals.
#[test]
fn largest_area_is_the_largest_area_bit_for_bit() {
    use crate::LargestArea;
    let mut r = uniform(0x5eed_a4ea);
    let mut all = LargestArea::default();
    let mut expected: f64 = 0.0;
    let (mut short, mut long, mut errors) = (0, 0, 0);
    // Triangles near the floor: the long path, and an area.
    let mut needles = 0;
    // Triangles whose radicand overflows (an error: an infinite area) or whose floor
    // underflows (the long path's own floor decides).
    let (mut huge, mut tiny) = (0, 0);
    // Two halves, merged at the end (as the parallel reduction merges its parts).
    let (mut even, mut odd) = (LargestArea::default(), LargestArea::default());
    for k in 0..20_000 {
        let scale = 10f64.powf(190.0 * r());
        let offset = Vector::new(r(), r(), r()) * scale * 10f64.powf(8.0 * (r() + 0.5));
        let mut q = || offset + Vector::new(r(), r(), r()) * scale;
        let (kind, mut pts) = match k % 5 {
            // A needle near the origin (its area is then accurate in Heron's formula; far
            // off, the rounding of its points is larger than its short edge): two points
            // 10^[-15, -12] (relative) apart.
            0 => {
                let a = Vector::new(r(), r(), r()) * scale;
                let h = 10f64.powf(-13.5 + 3.0 * r());
                let b = a + Vector::new(r(), r(), r()) * scale * h;
                let c = Vector::new(r(), r(), r()) * scale;
                (GeometryKind::Triangle3D3, vec![a, b, c])
            }
            1 => (GeometryKind::Quadrilateral3D4, vec![q(), q(), q(), q()]),
            _ => (GeometryKind::Triangle3D3, vec![q(), q(), q()]),
        };
        if k % 97 == 0 {
            pts[k % 3].y = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][k % 3];
        }
        if k % 89 == 0 {
            pts.pop();
        }
        let pts: Vec<Point> = pts.into_iter().map(Point::from).collect();
        if kind == GeometryKind::Triangle3D3 && pts.len() == 3 {
            huge += usize::from(scale > 1e80);
            tiny += usize::from(scale < 1e-80);
        }
        let want = Geometry::new(kind, &pts).and_then(|g| g.area());
        let mut one = LargestArea::default();
        match (one.add(kind, &pts), &want) {
            (Ok(()), Ok(a)) => {
                assert_eq!(one.value().to_bits(), a.to_bits(), "face {k}: {pts:?}");
                expected = expected.max(*a);
                if one.radicand > 0.0 {
                    short += 1;
                } else {
                    long += 1;
                    needles += usize::from(kind == GeometryKind::Triangle3D3);
                }
            }
            (Err(got), Err(e)) => {
                assert_eq!(got.kind(), e.kind(), "face {k}");
                errors += 1;
            }
            (got, _) => panic!("face {k}: {got:?} against {want:?}"),
        }
        if all.add(kind, &pts).is_ok() && k % 2 == 0 {
            assert_eq!(all.value().to_bits(), expected.to_bits(), "after face {k}");
        }
        let half = if k % 2 == 0 { &mut even } else { &mut odd };
        // An error leaves the accumulator as it was (the caller stops at the first one).
        let before = *half;
        if half.add(kind, &pts).is_err() {
            assert_eq!(*half, before, "face {k}");
        }
    }
    assert_eq!(all.value().to_bits(), expected.to_bits());
    let merged = LargestArea::default().merge(even).merge(odd);
    assert_eq!(merged.value().to_bits(), expected.to_bits());
    assert_eq!(odd.merge(even).value().to_bits(), expected.to_bits());
    assert!(
        short > 7_000
            && long > 3_000
            && needles > 100
            && errors > 500
            && huge > 1_000
            && tiny > 1_000,
        "{short} {long} {needles} {errors} {huge} {tiny}"
    );
}
