//! Skin detection on solids built in code: brute-force oracle (a face is skin iff no other
//! element has the same node set), outward normals, ids, flags.

use csm_geometry::math::{Point, Vector};
use csm_geometry::{Geometry, GeometryKind};
use csm_model::{ConditionId, ElementId, Flag, ModelPart, NodeId, PropertiesId};

use super::{SKIN_PART, detect_skin};

/// `n` unit hexahedra in a row along x (ids 1..), with one existing condition (id 7) so the
/// skin ids start after it; element k has properties k.
fn row_of_hexahedra(n: u32) -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    let id = |i: u32, j: u32, k: u32| NodeId(1 + i * 4 + j * 2 + k);
    for i in 0..=n {
        for j in 0..2 {
            for k in 0..2 {
                let p = Point::new(f64::from(i), f64::from(j), f64::from(k));
                mp.add_node(id(i, j, k), p).unwrap();
            }
        }
    }
    for e in 0..n {
        let (a, b) = (e, e + 1);
        let nodes = [
            id(a, 0, 0),
            id(b, 0, 0),
            id(b, 1, 0),
            id(a, 1, 0),
            id(a, 0, 1),
            id(b, 0, 1),
            id(b, 1, 1),
            id(a, 1, 1),
        ];
        mp.add_element(
            ElementId(e + 1),
            GeometryKind::Hexahedra3D8,
            "Element3D8N",
            &nodes,
            PropertiesId(e + 1),
        )
        .unwrap();
    }
    mp.add_condition(
        ConditionId(7),
        GeometryKind::Quadrilateral3D4,
        "SurfaceCondition3D4N",
        &[id(0, 0, 0), id(0, 1, 0), id(0, 1, 1), id(0, 0, 1)],
        PropertiesId(0),
    )
    .unwrap();
    mp
}

#[test]
fn the_skin_is_every_face_of_one_element_only_facing_out() {
    let mut mp = row_of_hexahedra(3);
    let report = detect_skin(&mut mp).unwrap();
    // 3 hexahedra: 18 faces, 2 internal faces counted twice → 14 skin faces.
    assert_eq!(report.conditions.len(), 14);
    assert_eq!(
        report.conditions,
        (8..22).map(ConditionId).collect::<Vec<_>>()
    );
    let part = mp.part(report.part);
    assert_eq!(mp.find_part(SKIN_PART), Some(report.part));
    assert_eq!(part.conditions().len(), 14);
    assert_eq!(part.nodes().len(), 16);
    let centre = Point::new(1.5, 0.5, 0.5);
    for c in part.conditions() {
        let nodes = mp.conditions().nodes(c.index());
        let points: Vec<Point> = nodes
            .iter()
            .map(|n| mp.nodes().coordinates()[n.index()])
            .collect();
        let g = Geometry::new(GeometryKind::Quadrilateral3D4, &points).unwrap();
        let n = g.unit_normal(&Point::origin()).unwrap();
        let outward: Vector = g.center() - centre;
        assert!(n.dot(&outward) > 0.0, "condition {c:?} faces inwards");
        // No internal face (x = 1 or x = 2 on all four nodes).
        let x = points[0].x;
        let internal = (x == 1.0 || x == 2.0) && points.iter().all(|p| p.x == x);
        assert!(!internal, "internal face {c:?}");
        assert!(mp.conditions().flags()[c.index()].is(Flag::INTERFACE));
        assert_eq!(mp.conditions().name(c.index()), "SurfaceCondition3D4N");
    }
    // The element's properties go with its faces: the first skin face is element 1's.
    let first = mp.conditions().index_of(8).unwrap();
    assert_eq!(mp.conditions().properties(first), PropertiesId(1));
    assert!(mp.nodes().flags().iter().all(|f| f.is(Flag::INTERFACE)));
}

#[test]
fn a_second_skin_part_or_no_solid_is_refused() {
    let mut mp = row_of_hexahedra(1);
    mp.create_part(SKIN_PART).unwrap();
    let e = detect_skin(&mut mp).unwrap_err();
    assert!(e.to_string().contains("already has a part"), "{e}");
    let mut empty = ModelPart::new("Structure");
    let e = detect_skin(&mut empty).unwrap_err();
    assert!(e.to_string().contains("no element has a face"), "{e}");
}
