//! Kratos' contact test meshes (`shared/data/kratos-tests/`, counts from its `SOURCES.md`).

use csm_geometry::GeometryKind;
use csm_io::read_mesh;
use csm_model::ModelPart;

use crate::kratos;

/// Reads `name` and checks the totals (nodes, elements, conditions).
#[track_caller]
fn check(name: &str, totals: (usize, usize, usize)) -> ModelPart {
    let mp = read_mesh(&kratos(name)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mp.name(), "Structure");
    assert_eq!(
        (mp.nodes().len(), mp.elements().len(), mp.conditions().len()),
        totals,
        "{name}"
    );
    mp
}

/// Checks (nodes, elements, conditions) of the part at `path`.
#[track_caller]
fn check_part(mp: &ModelPart, path: &str, counts: (usize, usize, usize)) {
    let p = mp.part(mp.get_part(path).unwrap());
    assert_eq!(
        (p.nodes().len(), p.elements().len(), p.conditions().len()),
        counts,
        "{path}"
    );
}

#[test]
fn shared_data_is_reachable() {
    assert!(
        kratos("SOURCES.md").is_file(),
        "{} is missing",
        kratos("SOURCES.md").display()
    );
}

#[test]
fn double_curvature_triangles() {
    let mp = check(
        "test_double_curvature_integration_triangle.mdpa",
        (1437, 2540, 0),
    );
    assert!(
        mp.elements()
            .kinds()
            .iter()
            .all(|&k| k == GeometryKind::Triangle3D3)
    );
    assert_eq!(mp.elements().name(0), "MembraneElement3D3N");
    check_part(&mp, "Parts_Parts_Auto1", (724, 1280, 0));
    check_part(&mp, "Parts_Parts_Auto2", (713, 1260, 0));
    check_part(&mp, "DISPLACEMENT_Displacement_Auto1", (330, 0, 0));
    check_part(&mp, "DISPLACEMENT_Displacement_Auto2", (1437, 0, 0));
    assert_eq!(mp.process_info().number("DOMAIN_SIZE"), Some(3.0));
}

/// This file has CRLF line endings.
#[test]
fn double_curvature_quadrilaterals_crlf() {
    let mp = check(
        "test_double_curvature_integration_quadrilateral.mdpa",
        (2016, 1849, 0),
    );
    assert!(
        mp.elements()
            .kinds()
            .iter()
            .all(|&k| k == GeometryKind::Quadrilateral3D4)
    );
    check_part(&mp, "Parts_Parts_Auto1", (1019, 935, 0));
    check_part(&mp, "Parts_Parts_Auto2", (997, 914, 0));
    check_part(&mp, "DISPLACEMENT_Displacement_Auto1", (2016, 0, 0));
    check_part(&mp, "DISPLACEMENT_Displacement_Auto2", (2016, 0, 0));
}

#[test]
fn patch_nonmatching() {
    let mp = check("3D_contact_patch_nonmatching_test.mdpa", (432, 264, 64));
    assert!(
        mp.elements()
            .kinds()
            .iter()
            .all(|&k| k == GeometryKind::Hexahedra3D8)
    );
    assert!(
        mp.conditions()
            .kinds()
            .iter()
            .all(|&k| k == GeometryKind::Quadrilateral3D4)
    );
    check_part(&mp, "Contact_Part", (18, 0, 0));
    let foundation = mp.part(mp.get_part("Parts_Part_foundation").unwrap());
    assert_eq!(foundation.elements().len(), 256);
    assert!(
        foundation
            .elements()
            .iter()
            .all(|e| mp.elements().properties(e.index()).0 == 3)
    );
    let punch = mp.part(mp.get_part("Parts_Part_punch").unwrap());
    assert_eq!(punch.elements().len(), 8);
    assert!(
        punch
            .elements()
            .iter()
            .all(|e| mp.elements().properties(e.index()).0 == 4)
    );
    assert_eq!(
        mp.part(mp.get_part("SurfaceLoad3D_SurfaceLoad").unwrap())
            .conditions()
            .len(),
        64
    );
    // Material values are written inside the mdpa.
    assert!(
        mp.properties()
            .get(&csm_model::PropertiesId(3))
            .is_some_and(|p| !p.values.is_empty())
    );
}

#[test]
fn simplest_patch_triquad() {
    let mp = check(
        "3D_contact_simplest_patch_matching_triquad_test.mdpa",
        (18, 19, 0),
    );
    let hexes = mp
        .elements()
        .kinds()
        .iter()
        .filter(|&&k| k == GeometryKind::Hexahedra3D8)
        .count();
    let tets = mp
        .elements()
        .kinds()
        .iter()
        .filter(|&&k| k == GeometryKind::Tetrahedra3D4)
        .count();
    assert_eq!((hexes, tets), (1, 18));
    check_part(&mp, "DISPLACEMENT_Displacement_Auto3", (8, 0, 0));
    assert_eq!(
        mp.part(mp.get_part("Parts_Parts_Auto2").unwrap())
            .elements()
            .len(),
        18
    );
}
