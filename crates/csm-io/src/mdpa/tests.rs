use csm_geometry::GeometryKind as G;
use csm_model::{ScalarVar, VectorVar};

use super::read_mdpa;

#[track_caller]
fn check_err(text: &str, expect: &str) {
    let e = read_mdpa(text, "m.mdpa").unwrap_err().to_string();
    assert!(e.contains(expect), "`{e}` does not contain `{expect}`");
}

const SMALL: &str = "// a comment\r\nBegin ModelPartData\r\n  TIME 1.5 // x\r\nEnd ModelPartData\r\n\
Begin Properties 1\r\n\tYOUNG_MODULUS 2e11\r\n\tBODY [3] (0.0, 1.0,2.0)\r\n\
Begin Table 1 TEMPERATURE YOUNG_MODULUS\r\n0 1\r\nEnd Table\r\nEnd Properties\r\n\
/* block\r\n comment */\r\nBegin Nodes\r\n 1 0 0 0\r\n 2 1 0 0\r\n 3 0 1 0\r\n 4 0 0 1\r\nEnd Nodes\r\n\
Begin Elements SmallDisplacementElement3D4N\r\n 5 1 1 2 3 4\r\nEnd Elements\r\n\
Begin Conditions SurfaceCondition3D3N\r\n 9 1 1 2 3\r\nEnd Conditions\r\n\
Begin Elements MembraneElement3D3N\r\n 6 1 2 3 4\r\nEnd Elements\r\n\
Begin NodalData DISPLACEMENT_Y\r\n 2 0 0.25\r\nEnd NodalData\r\n\
Begin NodalData NODAL_H\r\n 3 0 0.5\r\nEnd NodalData\r\n\
Begin NodalData VELOCITY\r\n 4 0 [3] (1.0, 2.0, 3.0)\r\nEnd NodalData\r\n\
Begin NodalData TEMPERATURE\r\n 4 0 300\r\nEnd NodalData\r\n\
Begin ElementalData X\r\n 5 1\r\nEnd ElementalData\r\n\
Begin SubModelPart Contact\r\n Begin SubModelPartData\r\n A 1\r\n End SubModelPartData\r\n\
 Begin SubModelPartNodes\r\n 1\r\n 2\r\n End SubModelPartNodes\r\n\
 Begin SubModelPart Slave\r\n  Begin SubModelPartConditions\r\n 9\r\n  End SubModelPartConditions\r\n\
 Begin SubModelPartElements\r\n 6\r\n End SubModelPartElements\r\n End SubModelPart\r\nEnd SubModelPart\r\n";

#[test]
fn reads_every_block() {
    let mp = read_mdpa(SMALL, "m.mdpa").unwrap();
    assert_eq!(mp.nodes().len(), 4);
    assert_eq!(mp.elements().kinds(), &[G::Tetrahedra3D4, G::Triangle3D3]);
    assert_eq!(mp.conditions().kinds(), &[G::Triangle3D3]);
    assert_eq!(mp.process_info().number("TIME"), Some(1.5));
    assert_eq!(mp.process_info().number("DOMAIN_SIZE"), Some(3.0));
    let p = &mp.properties()[&csm_model::PropertiesId(1)];
    assert_eq!(p.number("YOUNG_MODULUS"), Some(2e11));
    assert_eq!(
        p.values["BODY"],
        csm_model::PropertyValue::Vector(vec![0.0, 1.0, 2.0])
    );
    let nd = mp.nodal_data();
    assert_eq!(nd.vector(VectorVar::Displacement, 0).unwrap()[1].y, 0.25);
    assert_eq!(nd.scalar(ScalarVar::NodalH, 0).unwrap()[2], 0.5);
    assert_eq!(nd.vector(VectorVar::Velocity, 0).unwrap()[3].z, 3.0);
    let contact = mp.part(mp.get_part("Contact").unwrap());
    // The child's conditions and elements are in the parent too.
    assert_eq!(
        (
            contact.nodes().len(),
            contact.elements().len(),
            contact.conditions().len()
        ),
        (2, 1, 1)
    );
    let slave = mp.part(mp.get_part("Contact.Slave").unwrap());
    assert_eq!(slave.conditions().len(), 1);
}

#[test]
fn domain_size_2_for_2d_names() {
    let text = "Begin Nodes\n1 0 0 0\n2 1 0 0\n3 0 1 0\nEnd Nodes\n\
Begin Elements Element2D3N\n1 0 1 2 3\nEnd Elements\nBegin Conditions LineCondition2D2N\n2 0 1 2\nEnd Conditions\n";
    let mp = read_mdpa(text, "m.mdpa").unwrap();
    assert_eq!(mp.process_info().number("DOMAIN_SIZE"), Some(2.0));
    assert_eq!(mp.elements().kind(0), G::Triangle2D3);
    assert_eq!(mp.conditions().kind(0), G::Line2D2);
}

#[test]
fn errors() {
    check_err("", "m.mdpa:1: expected a mesh, found an empty file");
    check_err("  // only a comment\n", "found an empty file");
    check_err(
        &SMALL[..SMALL.find(" 4 0 0 1").unwrap()],
        "found end of file",
    );
    check_err("Begin Foo\nEnd Foo\n", "m.mdpa:1: expected a known block");
    check_err(
        "Begin Nodes\n1 0 0 0\nEnd Nodes\nBegin Elements Element3D\nEnd Elements\n",
        "m.mdpa:4: expected an element/condition name ending in a known geometry suffix",
    );
    check_err(
        "Begin Nodes\n1 0 0 0\n1 0 0 0\nEnd Nodes\n",
        "m.mdpa:3: duplicate node id 1",
    );
    check_err(
        "Begin Nodes\n1 0 nan 0\nEnd Nodes\n",
        "m.mdpa:2: expected a finite y coordinate, found `nan`",
    );
    check_err("Begin Nodes\n1 0 abc 0\nEnd Nodes\n", "found `abc`");
    check_err(
        "Begin Nodes\n1 0 0 0\nEnd Nodes\nBegin Conditions LineCondition2D2N\n\n7 0 1 2\nEnd Conditions\n",
        "m.mdpa:6: condition 7 refers to node 2, which does not exist",
    );
    check_err("/* open", "expected the end of the comment");
    check_err(
        "Begin Table 1 A B\n1 2\n",
        "expected the end of `Begin Table`",
    );
}
