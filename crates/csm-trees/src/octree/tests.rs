//! Unit tests of the octree: Kratos' parameters and refinement, leaf order, the per-leaf
//! listing with duplicates, the absolute cell tolerance (Q17), the insertion split into walk
//! and store, and typed errors.

use csm_geometry::math::{Point, Real, Vector};

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
    assert!(leaf.contains(&point));
    let size = leaf.max - leaf.min;
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
    let mins: Vec<Point> = leaves.iter().map(|l| octree.leaf_aabb(*l).min).collect();
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
        .insert_with(5u32, &aabb, |cell| cell.min.x + cell.max.x > 2.0)
        .unwrap();
    let mut leaves = Vec::new();
    octree.intersected_leaves(&aabb, &mut leaves).unwrap();
    let holding: Vec<LeafId> = leaves
        .iter()
        .copied()
        .filter(|l| !octree.leaf_items(*l).is_empty())
        .collect();
    assert_eq!(holding.len(), 4);
    assert!(holding.iter().all(|l| octree.leaf_aabb(*l).min.x == 1.0));
    octree
        .intersected_leaves_with(&aabb, |_| false, &mut leaves)
        .unwrap();
    assert!(leaves.is_empty());
}

/// Walking every object first (read-only) and storing them afterwards in the same order fills
/// every leaf as inserting them one by one does: the same objects in the same order.
#[test]
fn walk_then_store_is_insert_with() {
    let params = OctreeParams {
        min_level: 7,
        ..OctreeParams::default()
    };
    let new = || {
        let mut octree = Octree::new(p(-1.0, -1.0, -1.0), p(1.0, 1.0, 1.0), params).unwrap();
        for i in 0..40 {
            let t = Real::from(i) * 0.37;
            octree
                .insert_point(&p(0.9 * t.sin(), 0.8 * (2.0 * t).cos(), 0.1 * t - 0.9))
                .unwrap();
        }
        octree
    };
    // Boxes of several sizes, some reaching outside the root box, and an object test that
    // keeps only some of the leaves a box reaches.
    let objects: Vec<(u32, Aabb)> = (0..60u32)
        .map(|i| {
            let t = Real::from(i) * 0.61;
            let c = p(
                0.95 * t.cos(),
                0.95 * (1.3 * t).sin(),
                0.9 * (0.7 * t).cos(),
            );
            let h = 0.02 + 0.3 * Real::from(i % 7) / 7.0;
            (i, Aabb::new(c - Vector::repeat(h), c + Vector::repeat(h)))
        })
        .collect();
    let test = |cell: &Aabb| cell.min.x + cell.min.y < 0.8;
    let mut one_by_one = new();
    for (item, aabb) in &objects {
        one_by_one.insert_with(*item, aabb, test).unwrap();
    }
    let mut split = new();
    let walks: Vec<Vec<LeafId>> = objects
        .iter()
        .map(|(_, aabb)| {
            let mut leaves = Vec::new();
            split
                .intersected_leaves_with(aabb, test, &mut leaves)
                .unwrap();
            leaves
        })
        .collect();
    for ((item, _), leaves) in objects.iter().zip(&walks) {
        split.insert_in_leaves(*item, leaves).unwrap();
    }
    assert_eq!(split.n_objects(), one_by_one.n_objects());
    assert_eq!(split.n_leaves(), one_by_one.n_leaves());
    let all = Aabb::new(p(-1.0, -1.0, -1.0), p(1.0, 1.0, 1.0));
    let mut leaves = Vec::new();
    one_by_one.intersected_leaves(&all, &mut leaves).unwrap();
    let mut stored = 0;
    for leaf in &leaves {
        assert_eq!(split.leaf_items(*leaf), one_by_one.leaf_items(*leaf));
        stored += split.leaf_items(*leaf).len();
    }
    // The objects reach many leaves, and the test drops some of them.
    assert!(stored > 2 * objects.len());
    let unfiltered: usize = objects
        .iter()
        .map(|(_, aabb)| {
            one_by_one.intersected_leaves(aabb, &mut leaves).unwrap();
            leaves.len()
        })
        .sum();
    assert!(stored < unfiltered);
}

/// A leaf id of a cell refined since, or past the arena, is refused and nothing stored.
#[test]
fn storing_in_a_cell_that_is_no_leaf_fails() {
    let params = OctreeParams::default();
    let mut octree = Octree::<u32>::new(p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0), params).unwrap();
    let mut before = Vec::new();
    octree
        .intersected_leaves(&cube(0.1, 0.2), &mut before)
        .unwrap();
    assert_eq!(before.len(), 1);
    octree.insert_point(&p(0.15, 0.15, 0.15)).unwrap();
    let err = octree.insert_in_leaves(7, &before).unwrap_err();
    assert_eq!(err.kind(), &ErrorKind::NotALeaf);
    assert!(!err.to_string().is_empty());
    // A valid leaf beside an id past the arena (another, larger octree's).
    let mut fresh = Vec::new();
    octree
        .intersected_leaves(&cube(0.1, 0.2), &mut fresh)
        .unwrap();
    let mut err_leaves = fresh.clone();
    err_leaves.push(LeafId(u32::MAX));
    assert!(octree.insert_in_leaves(7, &err_leaves).is_err());
    assert_eq!(octree.n_objects(), 0);
    assert!(fresh.iter().all(|l| octree.leaf_items(*l).is_empty()));
    // Still refinable: nothing was stored.
    octree.insert_point(&p(0.16, 0.16, 0.16)).unwrap();
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
