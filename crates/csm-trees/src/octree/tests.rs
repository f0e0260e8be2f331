//! Unit tests of the octree: Kratos' parameters and refinement, leaf order, the per-leaf
//! listing with duplicates, the absolute cell tolerance (Q17) and typed errors.

use csm_geometry::math::{Point, Real};

use super::tree::{LeafId, Octree, OctreeParams};
use crate::{Aabb, ErrorKind};

fn p(x: Real, y: Real, z: Real) -> Point {
    Point::new(x, y, z)
}

fn cube(lo: Real, hi: Real) -> Aabb {
    Aabb::new(p(lo, lo, lo), p(hi, hi, hi))
}

#[test]
fn default_params_are_kratos() {
    let params = OctreeParams::default();
    assert_eq!(
        (params.max_level, params.root_level, params.min_level),
        (12, 11, 2)
    );
    assert_eq!(params.cell_tolerance(), 0.001 * 4.0 / 2048.0);
}

/// One refinement point splits 9 times (levels 11 → 2): 1 + 9·8 cells, 1 + 9·7 leaves, and
/// the leaf around the point is 1/512 of the root box per axis.
#[test]
fn insert_point_refines_to_the_min_level() {
    let mut octree = Octree::<u32>::with_kratos_params(p(0.0, 0.0, 0.0), p(8.0, 4.0, 2.0)).unwrap();
    assert_eq!(octree.n_leaves(), 1);
    let point = p(3.3, 1.1, 0.7);
    octree.insert_point(&point).unwrap();
    assert_eq!(octree.n_cells(), 1 + 9 * 8);
    assert_eq!(octree.n_leaves(), 1 + 9 * 7);
    // Refining again at the same place changes nothing.
    octree.insert_point(&point).unwrap();
    assert_eq!(octree.n_cells(), 1 + 9 * 8);

    let mut leaves = Vec::new();
    octree
        .intersected_leaves(&Aabb::new(point, point), &mut leaves)
        .unwrap();
    assert_eq!(leaves.len(), 1);
    let leaf = octree.leaf_aabb(leaves[0]);
    assert_eq!(octree.leaf_level(leaves[0]), 2);
    assert!(leaf.contains_point(&point));
    let size = leaf.maxs - leaf.mins;
    assert!((size.x - 8.0 / 512.0).abs() < 1e-12);
    assert!((size.y - 4.0 / 512.0).abs() < 1e-12);
    assert!((size.z - 2.0 / 512.0).abs() < 1e-12);
}

/// Leaves come depth first with the children visited from 7 (high x, y, z) down to 0.
#[test]
fn leaves_come_in_kratos_stack_order() {
    let params = OctreeParams {
        min_level: 10,
        ..OctreeParams::default()
    };
    let mut octree = Octree::<u32>::new(p(0.0, 0.0, 0.0), p(2.0, 2.0, 2.0), params).unwrap();
    octree.insert_point(&p(0.5, 0.5, 0.5)).unwrap();
    assert_eq!(octree.n_leaves(), 8);
    let mut leaves = Vec::new();
    octree
        .intersected_leaves(&cube(0.0, 2.0), &mut leaves)
        .unwrap();
    let mins: Vec<Point> = leaves.iter().map(|l| octree.leaf_aabb(*l).mins).collect();
    let expected: Vec<Point> = (0..8u32)
        .rev()
        .map(|i| {
            p(
                (i & 1) as Real,
                ((i >> 1) & 1) as Real,
                ((i >> 2) & 1) as Real,
            )
        })
        .collect();
    assert_eq!(mins, expected);
}

/// An object spanning several leaves is listed once per shared leaf by the per-leaf query
/// (Kratos' duplicate pairing, Q15) and once by `query_aabb`.
#[test]
fn per_leaf_listing_keeps_duplicates() {
    let params = OctreeParams {
        min_level: 10,
        ..OctreeParams::default()
    };
    let mut octree = Octree::new(p(0.0, 0.0, 0.0), p(2.0, 2.0, 2.0), params).unwrap();
    octree.insert_point(&p(0.5, 0.5, 0.5)).unwrap();
    // Spans the x = 1 plane only: two leaves (low y, low z).
    octree
        .insert(7u32, &Aabb::new(p(0.5, 0.2, 0.2), p(1.5, 0.4, 0.4)))
        .unwrap();
    // Inside child 0 only.
    octree.insert(3u32, &cube(0.1, 0.3)).unwrap();
    assert_eq!(octree.n_objects(), 2);

    let query = Aabb::new(p(0.0, 0.0, 0.0), p(2.0, 0.5, 0.5));
    let mut out = Vec::new();
    octree.query_aabb_per_leaf(&query, &mut out).unwrap();
    assert_eq!(
        out,
        [7, 7, 3],
        "leaf 1 (x high) first, then leaf 0 in insertion order"
    );
    octree.query_aabb(&query, &mut out).unwrap();
    assert_eq!(out, [3, 7]);

    // A query inside child 1 only finds the spanning object, once.
    octree
        .query_aabb_per_leaf(&cube(1.6, 1.9), &mut out)
        .unwrap();
    assert!(out.is_empty(), "child 7 holds nothing");
    octree
        .query_aabb_per_leaf(&Aabb::new(p(1.6, 0.1, 0.1), p(1.9, 0.2, 0.2)), &mut out)
        .unwrap();
    assert_eq!(out, [7]);
}

/// Without refinement the root is the only leaf: every object shares it with every query (the
/// octree is a superset filter, exactness is the caller's narrow phase).
#[test]
fn unrefined_octree_returns_everything_inside() {
    let mut octree = Octree::with_kratos_params(p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0)).unwrap();
    octree.insert(1u32, &cube(0.0, 0.1)).unwrap();
    octree.insert(2u32, &cube(0.9, 1.0)).unwrap();
    let mut out = Vec::new();
    octree.query_aabb(&cube(0.4, 0.5), &mut out).unwrap();
    assert_eq!(out, [1, 2]);
}

/// The cell tolerance is absolute (Q17): ≈1.95e-6 in real units, whatever the size of the
/// root box. An object just beyond the root face is stored in the (root) leaf when within it.
#[test]
fn cell_tolerance_is_absolute() {
    let tolerance = OctreeParams::default().cell_tolerance();
    for extent in [1e-9, 1.0, 1e6] {
        let mut octree =
            Octree::with_kratos_params(p(0.0, 0.0, 0.0), p(extent, extent, extent)).unwrap();
        let mid = extent / 2.0;
        let beyond = |gap: Real| {
            let x = extent + gap;
            Aabb::new(p(x, mid, mid), p(x, mid, mid))
        };
        octree.insert(1u32, &beyond(0.5 * tolerance)).unwrap();
        octree.insert(2u32, &beyond(2.0 * tolerance)).unwrap();
        let mut out = Vec::new();
        octree.query_aabb(&cube(0.0, extent), &mut out).unwrap();
        assert_eq!(out, [1], "extent {extent:e}");
    }
}

/// A caller's exact test replaces the box test (Kratos: triangle/box, segment/box, …).
#[test]
fn insert_with_uses_the_callers_test() {
    let params = OctreeParams {
        min_level: 10,
        ..OctreeParams::default()
    };
    let mut octree = Octree::new(p(0.0, 0.0, 0.0), p(2.0, 2.0, 2.0), params).unwrap();
    octree.insert_point(&p(0.5, 0.5, 0.5)).unwrap();
    // Only the leaves whose centre has x > 1 accept the object.
    let aabb = cube(0.5, 1.5);
    octree
        .insert_with(5u32, &aabb, |cell| cell.mins.x + cell.maxs.x > 2.0)
        .unwrap();
    let mut leaves = Vec::new();
    octree.intersected_leaves(&aabb, &mut leaves).unwrap();
    let holding: Vec<LeafId> = leaves
        .iter()
        .copied()
        .filter(|l| !octree.leaf_items(*l).is_empty())
        .collect();
    assert_eq!(holding.len(), 4);
    assert!(holding.iter().all(|l| octree.leaf_aabb(*l).mins.x == 1.0));
    octree
        .intersected_leaves_with(&aabb, |_| false, &mut leaves)
        .unwrap();
    assert!(leaves.is_empty());
}

#[test]
fn degenerate_input_gives_typed_errors() {
    let params = OctreeParams::default();
    let flat = Octree::<u32>::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 0.0), params);
    assert_eq!(flat.unwrap_err().kind(), &ErrorKind::EmptyRootBox);
    let nan = Octree::<u32>::new(p(0.0, Real::NAN, 0.0), p(1.0, 1.0, 1.0), params);
    assert!(matches!(
        nan.unwrap_err().kind(),
        ErrorKind::NonFinite { .. }
    ));
    let huge = Octree::<u32>::new(p(-Real::MAX, 0.0, 0.0), p(Real::MAX, 1.0, 1.0), params);
    assert_eq!(huge.unwrap_err().kind(), &ErrorKind::EmptyRootBox);
    let levels = OctreeParams {
        min_level: 11,
        ..params
    };
    let bad = Octree::<u32>::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0), levels);
    assert_eq!(bad.unwrap_err().kind(), &ErrorKind::InvalidLevels);

    let mut octree = Octree::<u32>::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0), params).unwrap();
    assert_eq!(
        octree.insert_point(&p(1.5, 0.5, 0.5)).unwrap_err().kind(),
        &ErrorKind::OutsideRootBox
    );
    assert!(octree.insert_point(&p(Real::NAN, 0.5, 0.5)).is_err());
    let inverted = Aabb::new(p(0.6, 0.5, 0.5), p(0.4, 0.5, 0.5));
    assert_eq!(
        octree.insert(1, &inverted).unwrap_err().kind(),
        &ErrorKind::InvertedBox
    );
    assert_eq!(octree.n_objects(), 0);
    let mut out = vec![9];
    assert!(octree.query_aabb(&inverted, &mut out).is_err());
    assert!(out.is_empty());
    octree.insert(1, &cube(0.2, 0.3)).unwrap();
    let err = octree.insert_point(&p(0.5, 0.5, 0.5)).unwrap_err();
    assert_eq!(err.kind(), &ErrorKind::RefineAfterInsert);
    assert!(!err.to_string().is_empty());
}
