use super::read_msh;

#[track_caller]
fn check_err(text: &str, expect: &str) {
    let e = read_msh(text.as_bytes(), "t.msh").unwrap_err().to_string();
    assert!(e.contains(expect), "`{e}` does not contain `{expect}`");
}

const TRI: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 5 \"plate\"\n$EndPhysicalNames\n\
$Entities\n0 0 1 0\n3 0 0 0 1 1 0 1 5 0\n$EndEntities\n\
$Nodes\n1 3 1 30\n2 3 0 3\n30\n10\n20\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n\
$Elements\n1 1 7 7\n2 3 2 1\n7 30 10 20\n$EndElements\n";

#[test]
fn reads_a_2d_triangle() {
    let mp = read_msh(TRI.as_bytes(), "t.msh").unwrap();
    assert_eq!(mp.nodes().ids(), &[10, 20, 30]);
    assert_eq!(mp.elements().ids(), &[7]);
    assert_eq!(
        mp.elements().kind(0),
        csm_geometry::GeometryKind::Triangle2D3
    );
    assert_eq!(mp.process_info().number("DOMAIN_SIZE"), Some(2.0));
    let p = mp.get_part("plate").unwrap();
    assert_eq!(mp.part(p).elements().len(), 1);
    assert_eq!(mp.part(p).nodes().len(), 3);
}

#[test]
fn skips_unknown_sections() {
    let text = TRI.replace("$Nodes", "$Foo\nanything $ here\n$EndFoo\n$Nodes");
    assert!(read_msh(text.as_bytes(), "t.msh").is_ok());
}

#[test]
fn errors() {
    check_err("", "t.msh:1: expected a mesh, found an empty file");
    check_err(&TRI[..TRI.len() - 20], "found end of file");
    check_err(&TRI.replace("$Nodes", "$Foo\n"), "expected the end of $Foo");
    check_err(
        &TRI.replace("2 3 2 1", "2 3 7 1"),
        "t.msh:24: expected a Gmsh element type",
    );
    check_err(
        &TRI.replace("7 30 10 20", "7 30 10 21"),
        "refers to node 21",
    );
    check_err(&TRI.replace("\n20\n", "\n10\n"), "duplicate node id 10");
    check_err(
        &TRI.replace("1 0 0\n", "1 nan 0\n"),
        "t.msh:19: expected a y coordinate, found `nan`",
    );
    check_err(&TRI.replace("1 0 0\n", "1 x 0\n"), "found `x`");
    check_err(
        &TRI.replace("4.1 0 8", "4.1 0 4"),
        "expected the data size 8",
    );
    check_err(&TRI.replace("4.1 0 8", "3.0 0 8"), "found version 3.0");
}

#[test]
fn binary_endianness_marker() {
    let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
    b.extend_from_slice(&1i32.to_be_bytes());
    b.extend_from_slice(b"\n$EndMeshFormat\n");
    let e = read_msh(&b, "b.msh").unwrap_err().to_string();
    assert!(
        e.contains("b.msh: byte 20 in binary $MeshFormat: expected the endianness marker 1"),
        "{e}"
    );
    assert!(e.contains("big-endian"), "{e}");
}
