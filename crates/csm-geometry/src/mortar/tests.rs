use super::*;
use crate::math::{Point, Real, Vector};
use crate::{ErrorKind, Geometry, GeometryKind};

fn p(x: Real, y: Real, z: Real) -> Point {
    Point::new(x, y, z)
}

const UP: Vector = Vector::new(0.0, 0.0, 1.0);
const DOWN: Vector = Vector::new(0.0, 0.0, -1.0);

fn kind_of(points: &[Point]) -> GeometryKind {
    match points.len() {
        2 => GeometryKind::Line2D2,
        3 => GeometryKind::Triangle3D3,
        _ => GeometryKind::Quadrilateral3D4,
    }
}

#[track_caller]
fn segment(
    slave: &[Point],
    n_s: Vector,
    master: &[Point],
    n_m: Vector,
    mode: MortarMode,
) -> Option<Segmentation> {
    let s = MortarFace::new(Geometry::new(kind_of(slave), slave).unwrap(), n_s).unwrap();
    let m = MortarFace::new(Geometry::new(kind_of(master), master).unwrap(), n_m).unwrap();
    let settings = SegmentationSettings {
        mode,
        distance_threshold: 1e24,
    };
    exact_segmentation(&s, &m, &settings).unwrap()
}

#[track_caller]
fn area(seg: &Option<Segmentation>) -> Real {
    seg.as_ref().map_or(0.0, |s| s.overlap_area())
}

#[track_caller]
fn assert_close(a: Real, b: Real, tol: Real) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (tol {tol})");
}

const MODES: [MortarMode; 2] = [MortarMode::Kratos, MortarMode::Robust];

#[test]
fn identical_triangles_give_the_full_slave() {
    let t = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let master = [t[0], t[2], t[1]]; // facing the other way
    for mode in MODES {
        let seg = segment(&t, UP, &master, DOWN, mode).unwrap();
        assert_eq!(seg.cells().len(), 1);
        assert_close(seg.overlap_area(), 0.5, 1e-15);
    }
}

#[test]
fn overlapping_triangles_match_the_hand_computed_area() {
    // Slave: unit right triangle; master: the same shifted by (0.5, 0, 0.1).
    // Overlap: triangle (0.5,0), (1,0), (0.5,0.5) of area 0.125.
    let s = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let m = [p(0.5, 0.0, 0.1), p(0.5, 1.0, 0.1), p(1.5, 0.0, 0.1)];
    for mode in MODES {
        assert_close(area(&segment(&s, UP, &m, DOWN, mode)), 0.125, 1e-14);
    }
}

#[test]
fn disjoint_faces_have_no_segmentation() {
    let s = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let m = [p(2.0, 0.0, 0.0), p(2.0, 1.0, 0.0), p(3.0, 0.0, 0.0)];
    for mode in MODES {
        assert!(segment(&s, UP, &m, DOWN, mode).is_none());
    }
}

// See: reference Q48 (plane–cylinder master 16 / slave 7).
#[test]
fn touching_along_an_edge_is_no_overlap() {
    let s = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(0.0, 1.0, 0.0),
    ];
    let m = [
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(2.0, 1.0, 0.0),
        p(2.0, 0.0, 0.0),
    ];
    for mode in MODES {
        assert!(segment(&s, UP, &m, DOWN, mode).is_none(), "{mode:?}");
    }
    // A gap of 4.4e-16 (below the 1e-15 duplicate tolerance) is merged in Kratos mode.
    let x = 6.0 * (std::f64::consts::PI / 6.0).sin();
    assert!(x < 3.0);
    let s = [
        p(2.0, 0.0, 0.0),
        p(3.0, 0.0, 0.0),
        p(3.0, 1.0, 0.0),
        p(2.0, 1.0, 0.0),
    ];
    let m = [
        p(x, 0.0, 0.0),
        p(x, 1.0, 0.0),
        p(4.0, 1.0, 0.0),
        p(4.0, 0.0, 0.0),
    ];
    for mode in MODES {
        assert!(segment(&s, UP, &m, DOWN, mode).is_none(), "{mode:?}");
    }
}

// See: reference Q49.
#[test]
fn quad_master_inside_triangle_slave_differs_between_modes() {
    let s = [p(0.0, 0.0, 0.0), p(4.0, 0.0, 0.0), p(0.0, 4.0, 0.0)];
    let m = [
        p(0.5, 0.5, 0.0),
        p(0.5, 1.5, 0.0),
        p(1.5, 1.5, 0.0),
        p(1.5, 0.5, 0.0),
    ];
    let kratos = segment(&s, UP, &m, DOWN, MortarMode::Kratos).unwrap();
    let robust = segment(&s, UP, &m, DOWN, MortarMode::Robust).unwrap();
    assert_eq!(kratos.cells().len(), 2);
    assert_eq!(robust.cells().len(), 2);
    assert_close(robust.overlap_area(), 1.0, 1e-14);
    // (0,1,2) and (1,2,3): two halves of the square, (1,2,3) ≠ (0,2,3) — area still 1 for a
    // square, but the cells overlap on triangle (1,2,x) and miss part of (0,2,3).
    let k1 = kratos.cells()[1].global_vertices();
    assert_eq!(k1[0], m[1]);
    let r1 = robust.cells()[1].global_vertices();
    assert_eq!(r1[0], m[0]);
    // For a non-parallelogram quadrilateral the areas differ.
    let m = [
        p(0.5, 0.5, 0.0),
        p(0.5, 1.0, 0.0),
        p(2.0, 1.5, 0.0),
        p(1.5, 0.5, 0.0),
    ];
    let true_area = 0.5
        * ((0.5f64 * 1.0 - 0.5 * 0.5)
            + (0.5 * 1.5 - 2.0 * 1.0)
            + (2.0 * 0.5 - 1.5 * 1.5)
            + (1.5 * 0.5 - 0.5 * 0.5))
            .abs();
    let kratos = segment(&s, UP, &m, DOWN, MortarMode::Kratos).unwrap();
    let robust = segment(&s, UP, &m, DOWN, MortarMode::Robust).unwrap();
    assert_close(robust.overlap_area(), true_area, 1e-14);
    assert!((kratos.overlap_area() - true_area).abs() > 1e-3);
}

#[test]
fn distance_threshold_3d_rejects_masters_in_front_only() {
    let s = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let front = [p(0.0, 0.0, 0.5), p(0.0, 1.0, 0.5), p(1.0, 0.0, 0.5)];
    let behind = [p(0.0, 0.0, -0.5), p(0.0, 1.0, -0.5), p(1.0, 0.0, -0.5)];
    let slave = face(&s, UP).unwrap();
    let settings = SegmentationSettings {
        mode: MortarMode::Kratos,
        distance_threshold: 0.25,
    };
    let f = face(&front, DOWN).unwrap();
    let b = face(&behind, DOWN).unwrap();
    assert!(exact_segmentation(&slave, &f, &settings).unwrap().is_none());
    assert!(exact_segmentation(&slave, &b, &settings).unwrap().is_some());
}

fn face(pts: &[Point], n: Vector) -> Result<MortarFace<'_>, crate::Error> {
    MortarFace::new(Geometry::new(kind_of(pts), pts)?, n)
}

fn line_face<'a>(pts: &'a [Point], nodal: &'a [Vector]) -> MortarFace<'a> {
    let g = Geometry::new(GeometryKind::Line2D2, pts).unwrap();
    let n = g.unit_normal(&Point::origin()).unwrap();
    MortarFace::new(g, n)
        .unwrap()
        .with_nodal_normals(nodal)
        .unwrap()
}

#[test]
fn lines_2d_overlap_and_threshold() {
    // Slave along +x (normal (0,-1)), master above it running −x (normal (0,1)).
    let s = [p(0.0, 0.0, 0.0), p(2.0, 0.0, 0.0)];
    let sn = [Vector::new(0.0, -1.0, 0.0); 2];
    let m = [p(3.0, -0.1, 0.0), p(1.0, -0.1, 0.0)];
    let mn = [Vector::new(0.0, 1.0, 0.0); 2];
    let slave = line_face(&s, &sn);
    let master = line_face(&m, &mn);
    assert_eq!(slave.normal(), Vector::new(0.0, -1.0, 0.0));
    let seg = exact_segmentation(&slave, &master, &SegmentationSettings::default())
        .unwrap()
        .unwrap();
    let c = seg.cells()[0].local_vertices();
    assert_close(c[0].x, 0.0, 1e-12);
    assert_close(c[1].x, 1.0, 1e-12);
    assert_close(seg.overlap_area(), 1.0, 1e-12);
    // Open gap 0.1: d = −0.1, kept even by a threshold of 0.05 (3D would reject it, Q21).
    let small = SegmentationSettings {
        mode: MortarMode::Kratos,
        distance_threshold: 0.05,
    };
    assert!(
        exact_segmentation(&slave, &master, &small)
            .unwrap()
            .is_some()
    );
    // Penetration 0.1 (master on the other side of the slave): d = +0.1, rejected.
    let m = [p(3.0, 0.1, 0.0), p(1.0, 0.1, 0.0)];
    let master = line_face(&m, &mn);
    assert!(
        exact_segmentation(&slave, &master, &small)
            .unwrap()
            .is_none()
    );
    let large = SegmentationSettings {
        mode: MortarMode::Kratos,
        distance_threshold: 0.2,
    };
    assert!(
        exact_segmentation(&slave, &master, &large)
            .unwrap()
            .is_some()
    );
}

#[test]
fn unsupported_and_degenerate_inputs_are_errors() {
    let line = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let tri = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let l = MortarFace::new(Geometry::new(GeometryKind::Line2D2, &line).unwrap(), UP).unwrap();
    let t = MortarFace::new(Geometry::new(GeometryKind::Triangle3D3, &tri).unwrap(), UP).unwrap();
    let e = exact_segmentation(&l, &t, &SegmentationSettings::default()).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Unsupported(_)));
    let flat = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(2.0, 0.0, 0.0)];
    let f = MortarFace::new(Geometry::new(GeometryKind::Triangle3D3, &flat).unwrap(), UP).unwrap();
    let e = exact_segmentation(&f, &t, &SegmentationSettings::default()).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::Degenerate(_)));
    let z = MortarFace::new(*t.geometry(), Vector::zeros()).unwrap();
    assert!(exact_segmentation(&z, &t, &SegmentationSettings::default()).is_err());
    // A flat (degenerate) master is no overlap, not an error, in both modes when it crosses
    // the slave boundary.
    let crossing = [p(-1.0, 0.5, 0.0), p(2.0, 0.5, 0.0), p(0.5, 0.5, 1.0)];
    let c = MortarFace::new(
        Geometry::new(GeometryKind::Triangle3D3, &crossing).unwrap(),
        UP,
    )
    .unwrap();
    for mode in MODES {
        let settings = SegmentationSettings {
            mode,
            distance_threshold: 1e24,
        };
        assert!(exact_segmentation(&t, &c, &settings).unwrap().is_none());
    }
}

#[test]
fn dual_basis_of_a_full_triangle_is_the_classic_one() {
    let t = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    let m = [t[0], t[2], t[1]];
    let slave = MortarFace::new(Geometry::new(GeometryKind::Triangle3D3, &t).unwrap(), UP).unwrap();
    let master =
        MortarFace::new(Geometry::new(GeometryKind::Triangle3D3, &m).unwrap(), DOWN).unwrap();
    let seg = exact_segmentation(&slave, &master, &SegmentationSettings::default())
        .unwrap()
        .unwrap();
    let gps = integration_points(&slave, &master, &seg, &OperatorSettings::mapper()).unwrap();
    assert_eq!(gps.len(), 3);
    let basis = dual_basis(&slave, &gps);
    assert!(basis.is_dual());
    // Popp: Φ_i = 3 N_i − Σ_{j≠i} N_j on a full linear triangle.
    for i in 0..3 {
        for j in 0..3 {
            let expect = if i == j { 3.0 } else { -1.0 };
            assert_close(basis.ae()[(i, j)], expect, 1e-12);
        }
    }
    let ops = mortar_operators(&slave, &master, &gps, Some(&basis));
    for i in 0..3 {
        assert_close(ops.d[(i, i)], 1.0 / 6.0, 1e-14);
        for j in 0..3 {
            if i != j {
                assert_close(ops.d[(i, j)], 0.0, 1e-14);
            }
        }
    }
    // Matching master: M = D with the master node permutation (0, 2, 1).
    for i in 0..3 {
        assert_close(ops.m[(i, 0)], ops.d[(i, 0)], 1e-14);
        assert_close(ops.m[(i, 1)], ops.d[(i, 2)], 1e-14);
        assert_close(ops.m[(i, 2)], ops.d[(i, 1)], 1e-14);
    }
    let xs: Vec<Real> = t.iter().map(|q| q.x).collect();
    let xm: Vec<Real> = m.iter().map(|q| q.x).collect();
    for r in ops.residual(&xm, &xs) {
        assert_close(r, 0.0, 1e-15);
    }
}

#[test]
fn degenerate_2d_cells_are_skipped_by_the_length_check() {
    // A 1e-9 overlap at the end of a unit slave: kept by the segmentation (> ε), skipped by
    // the mapper (1e-6 · Length) but not by the explicit contribution (1e-12 · Length).
    let s = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    let sn = [Vector::new(0.0, -1.0, 0.0); 2];
    let m = [p(2.0, 0.0, 0.0), p(1.0 - 1e-9, 0.0, 0.0)];
    let mn = [Vector::new(0.0, 1.0, 0.0); 2];
    let slave = line_face(&s, &sn);
    let master = line_face(&m, &mn);
    let seg = exact_segmentation(&slave, &master, &SegmentationSettings::default())
        .unwrap()
        .unwrap();
    assert_close(seg.overlap_area(), 1e-9, 1e-15);
    let mapper = integration_points(&slave, &master, &seg, &OperatorSettings::mapper()).unwrap();
    assert!(mapper.is_empty());
    let explicit =
        integration_points(&slave, &master, &seg, &OperatorSettings::explicit()).unwrap();
    assert_eq!(explicit.len(), 2);
}

#[test]
fn dual_ae_follows_the_condition_number_not_the_determinant() {
    use super::FaceMatrix;
    use nalgebra::DMatrix;
    let diag = |v: [Real; 4]| {
        let mut a = FaceMatrix::zeros(4, 4);
        for (i, x) in v.into_iter().enumerate() {
            a[(i, i)] = x;
        }
        a
    };
    let de = FaceMatrix::identity(4);
    // det(Me/f) ≈ 1e-17 < ε but condition number ≈ 1e7: dual (Kratos 10.4.4 does the same).
    let me = diag([1.0, 1e-5, 1e-5, 1e-7]);
    let dense = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![1.0, 1e-5, 1e-5, 1e-7]));
    let scaled: DMatrix<Real> = &dense / dense.norm();
    assert!(scaled.determinant().abs() < crate::math::EPS);
    let ae = dual_ae(&de, &me).expect("well enough conditioned");
    assert_close(ae[(3, 3)] * 1e-7, 1.0, 1e-12);
    // Condition number ≈ 1e12 > 1e-4/ε: standard basis, whatever the determinant.
    assert!(dual_ae(&de, &diag([1.0, 1.0, 1.0, 1e-12])).is_none());
    // Exactly singular (an infinite inverse: Kratos would carry the inf/NaN on) and zero
    // matrices; sizes that differ.
    assert!(dual_ae(&de, &diag([1.0, 1.0, 1.0, 0.0])).is_none());
    assert!(dual_ae(&de, &FaceMatrix::zeros(4, 4)).is_none());
    assert!(dual_ae(&FaceMatrix::identity(3), &me).is_none());
}

mod with_normals {
    use super::*;
    use proptest::prelude::*;

    /// A warped face of `n` nodes around the unit square (triangle: three of its corners),
    /// at height `z`, with node offsets `d`.
    fn face(n: usize, z: Real, d: &[Real; 12]) -> Vec<Point> {
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        (0..n)
            .map(|i| {
                let (x, y) = corners[i];
                p(
                    x + 0.2 * d[3 * i],
                    y + 0.2 * d[3 * i + 1],
                    z + 0.05 * d[3 * i + 2],
                )
            })
            .collect()
    }

    fn normals(n: usize, up: Real, tilt: &[Real; 12]) -> Vec<Vector> {
        (0..n)
            .map(|i| Vector::new(0.3 * tilt[3 * i], 0.3 * tilt[3 * i + 1], up).normalize())
            .collect()
    }

    proptest! {
        /// The Gauss points with other nodal normals from those of the first pass are the
        /// points of a new integration, bit for bit (what the mapping's weighted gap relies on).
        #[test]
        fn reintegration_is_integration_bit_for_bit(
            ns in 3usize..5,
            nm in 3usize..5,
            ds in prop::array::uniform12(-1.0f64..1.0),
            dm in prop::array::uniform12(-1.0f64..1.0),
            t1 in prop::array::uniform12(-1.0f64..1.0),
            t2 in prop::array::uniform12(-1.0f64..1.0),
            shift in (-0.7f64..0.7, -0.7f64..0.7),
        ) {
            let sp = face(ns, 0.0, &ds);
            let mut mp = face(nm, 0.01, &dm);
            mp.reverse();
            for q in &mut mp {
                q.x += shift.0;
                q.y += shift.1;
            }
            let (n1, n2) = (normals(ns, 1.0, &t1), normals(ns, 1.0, &t2));
            let (m1, m2) = (normals(nm, -1.0, &t2), normals(nm, -1.0, &t1));
            let sg = Geometry::new(kind_of(&sp), &sp).unwrap();
            let mg = Geometry::new(kind_of(&mp), &mp).unwrap();
            let s1 = MortarFace::new(sg, UP).unwrap().with_nodal_normals(&n1).unwrap();
            let s2 = MortarFace::new(sg, UP).unwrap().with_nodal_normals(&n2).unwrap();
            let ma1 = MortarFace::new(mg, DOWN).unwrap().with_nodal_normals(&m1).unwrap();
            let ma2 = MortarFace::new(mg, DOWN).unwrap().with_nodal_normals(&m2).unwrap();
            for mode in [MortarMode::Kratos, MortarMode::Robust] {
                let settings = SegmentationSettings { mode, distance_threshold: 1e24 };
                let Some(seg) = exact_segmentation(&s1, &ma1, &settings).unwrap() else {
                    continue;
                };
                for ops in [OperatorSettings::mapper(), OperatorSettings::explicit()] {
                    // A first integration that fails (a Gauss point's projection onto a
                    // badly distorted master whose local coordinates do not converge) is
                    // the pair's error: the mapping never integrates it again.
                    let Ok(first) = integration_points(&s1, &ma1, &seg, &ops) else {
                        continue;
                    };
                    let again = integration_points_with_normals(&s2, &ma2, &first);
                    let fresh = integration_points(&s2, &ma2, &seg, &ops);
                    prop_assert_eq!(format!("{again:?}"), format!("{fresh:?}"));
                    prop_assert!(!first.is_empty());
                    // The dual basis and D depend on the slave side only.
                    let fresh = fresh.unwrap();
                    prop_assert_eq!(dual_basis(&s1, &first), dual_basis(&s2, &fresh));
                    let b = dual_basis(&s2, &fresh);
                    prop_assert_eq!(
                        mortar_operators(&s1, &ma1, &first, Some(&b)).d,
                        mortar_operators(&s2, &ma2, &fresh, Some(&b)).d
                    );
                }
            }
        }
    }
}

/// Packed operators give the residual of the operators themselves, bit for bit, for every
/// size of slave and master face, and `packed_len` is what `pack_into` appends; so do the
/// operators packed with the master values' products.
#[test]
fn packed_operators_give_the_same_residual() {
    // A deterministic spread of values over many magnitudes and both signs.
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        let unit = (state >> 11) as Real / (1u64 << 53) as Real;
        (unit - 0.5) * (10.0 as Real).powi((state % 9) as i32 - 4)
    };
    for (ns, nm) in [(2, 2), (3, 3), (3, 4), (4, 3), (4, 4)] {
        let mut ops = MortarOperators {
            d: FaceMatrix::zeros(ns, ns),
            m: FaceMatrix::zeros(ns, nm),
        };
        for i in 0..ns {
            for j in 0..ns {
                ops.d[(i, j)] = next();
            }
            for j in 0..nm {
                ops.m[(i, j)] = next();
            }
        }
        let mut packed = vec![7.0];
        ops.pack_into(&mut packed);
        assert_eq!(packed.len(), 1 + MortarOperators::packed_len(ns, nm));
        let mv: Vec<Real> = (0..nm).map(|_| next()).collect();
        let sv: Vec<Real> = (0..ns).map(|_| next()).collect();
        let mut a = [0.0; 4];
        let mut b = [0.0; 4];
        ops.residual_into(&mv, &sv, &mut a[..ns]);
        MortarOperators::packed_residual_into(&packed[1..], &mv, &sv, &mut b[..ns]);
        // With the products of three components' master values, the second being `mv`.
        let other: Vec<Vec<Real>> = (0..2).map(|_| (0..nm).map(|_| next()).collect()).collect();
        let mut with_products = vec![7.0];
        ops.pack_with_products_into(&[&other[0], &mv, &other[1]], &mut with_products);
        let len = MortarOperators::packed_with_products_len(ns, 3);
        assert_eq!(with_products.len(), 1 + len);
        let mut c = [0.0; 4];
        MortarOperators::packed_products_residual_into(
            &with_products[1..],
            (1, 3),
            &sv,
            &mut c[..ns],
        );
        for i in 0..ns {
            assert_eq!(a[i].to_bits(), b[i].to_bits(), "{ns}x{nm} row {i}");
            assert_eq!(
                a[i].to_bits(),
                c[i].to_bits(),
                "{ns}x{nm} row {i}, products"
            );
            // Both are the residual M·v − D·s.
            let direct: Real = (0..nm).map(|j| ops.m[(i, j)] * mv[j]).sum::<Real>()
                - (0..ns).map(|j| ops.d[(i, j)] * sv[j]).sum::<Real>();
            assert!((a[i] - direct).abs() <= 1e-12 * (1.0 + direct.abs()));
        }
    }
}
