//! Extra points and line cells over them: counts, padding, offsets, errors, determinism.

use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ConditionId, ElementId, ModelPart, NodeId, NodeIdx, PropertiesId};

use super::{DataArray, VtuWriter};

/// One tetrahedron (nodes 1–4) with its bottom face as a condition.
fn tet() -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    let props = PropertiesId(0);
    mp.ensure_properties(props);
    for (id, p) in [
        (1, [0.0, 0.0, 0.0]),
        (2, [1.0, 0.0, 0.0]),
        (3, [0.0, 1.0, 0.0]),
        (4, [0.0, 0.0, 1.0]),
    ] {
        mp.add_node(NodeId(id), Point::from(p)).unwrap();
    }
    let nodes = [NodeId(1), NodeId(2), NodeId(3), NodeId(4)];
    mp.add_element(ElementId(7), GeometryKind::Tetrahedra3D4, "", &nodes, props)
        .unwrap();
    mp.add_condition(
        ConditionId(9),
        GeometryKind::Triangle3D3,
        "",
        &[NodeId(1), NodeId(3), NodeId(2)],
        props,
    )
    .unwrap();
    mp
}

/// The whitespace-separated values of the first `<DataArray … Name="name" …>`.
fn array<'a>(xml: &'a str, name: &str) -> Vec<&'a str> {
    let key = format!("Name=\"{name}\"");
    let at = xml.find(&key).unwrap_or_else(|| panic!("no array {name}"));
    let body_start = xml[at..].find('>').unwrap() + at + 1;
    let body_end = xml[body_start..].find("</DataArray>").unwrap() + body_start;
    xml[body_start..body_end].split_whitespace().collect()
}

#[test]
fn extra_points_and_their_line_cells() {
    let mp = tet();
    let mut w = VtuWriter::new(&mp);
    w.line_cells(&[[NodeIdx(0), NodeIdx(3)]]);
    assert_eq!(w.n_points(), 4);
    w.extra_points(&[Point::new(0.25, 0.25, 0.0), Point::new(0.5, 0.5, 0.5)]);
    w.point_line_cells(&[[4, 5], [0, 5]]);
    assert_eq!((w.n_points(), w.n_cells()), (6, 5));
    // One tuple per node: padded; one per point: as given.
    w.point_data(
        "per_node",
        DataArray::I64 {
            components: 1,
            values: vec![1, 0, 1, 0],
        },
    );
    w.point_data(
        "per_point",
        DataArray::F64 {
            components: 3,
            values: (0..18).map(f64::from).collect(),
        },
    );
    w.cell_data(
        "c",
        DataArray::I64 {
            components: 1,
            values: vec![5; 5],
        },
    );
    let xml = w.to_xml("t.vtu").unwrap();
    assert!(xml.contains("NumberOfPoints=\"6\" NumberOfCells=\"5\""));
    assert_eq!(array(&xml, "node_id"), ["1", "2", "3", "4", "-1", "-1"]);
    assert_eq!(array(&xml, "per_node"), ["1", "0", "1", "0", "-1", "-1"]);
    assert_eq!(array(&xml, "per_point").len(), 18);
    assert_eq!(array(&xml, "Points").len(), 18);
    assert_eq!(
        &array(&xml, "Points")[12..],
        ["2.5e-1", "2.5e-1", "0e0", "5e-1", "5e-1", "5e-1"]
    );
    assert_eq!(array(&xml, "entity_kind"), ["0", "1", "2", "2", "2"]);
    assert_eq!(array(&xml, "entity_id"), ["7", "9", "0", "1", "2"]);
    assert_eq!(array(&xml, "types"), ["10", "5", "3", "3", "3"]);
    assert_eq!(array(&xml, "offsets"), ["4", "7", "9", "11", "13"]);
    assert_eq!(
        array(&xml, "connectivity"),
        [
            "0", "1", "2", "3", "0", "2", "1", "0", "3", "4", "5", "0", "5"
        ]
    );
    assert_eq!(w.to_xml("t.vtu").unwrap(), xml);
}

#[test]
fn padding_of_float_arrays_is_nan() {
    let mp = tet();
    let mut w = VtuWriter::new(&mp);
    w.extra_points(&[Point::origin()]);
    w.point_data(
        "gap",
        DataArray::F64 {
            components: 1,
            values: vec![0.5; 4],
        },
    );
    let xml = w.to_xml("t.vtu").unwrap();
    assert_eq!(array(&xml, "gap"), ["5e-1", "5e-1", "5e-1", "5e-1", "nan"]);
}

#[test]
fn bad_point_data_and_bad_line_cells_are_errors() {
    let mp = tet();
    let mut w = VtuWriter::new(&mp);
    w.extra_points(&[Point::origin()]);
    w.point_data(
        "x",
        DataArray::I64 {
            components: 1,
            values: vec![0; 3],
        },
    );
    let e = w.to_xml("t.vtu").unwrap_err().to_string();
    assert!(e.contains("values in data array `x`, found 3"), "{e}");
    let mut w = VtuWriter::new(&mp);
    w.extra_points(&[Point::origin()]);
    w.point_line_cells(&[[0, 5]]);
    let e = w.to_xml("t.vtu").unwrap_err().to_string();
    assert!(e.contains("point indices below 5"), "{e}");
}

/// The arrays of a binary (raw appended) file by name, decoded, as the ASCII form's text:
/// (type, values).
fn appended_arrays(bytes: &[u8]) -> Vec<(String, String, Vec<String>)> {
    let start = b"<AppendedData encoding=\"raw\">\n   _";
    let marker = bytes
        .windows(start.len())
        .position(|w| w == start)
        .expect("appended data")
        + start.len();
    let xml = std::str::from_utf8(&bytes[..marker]).expect("UTF-8 header");
    let data = &bytes[marker..];
    let attr = |tag: &str, key: &str| -> String {
        let at = tag.find(&format!("{key}=\"")).expect(key) + key.len() + 2;
        tag[at..at + tag[at..].find('"').unwrap()].to_owned()
    };
    let mut out = Vec::new();
    for tag in xml.split("<DataArray ").skip(1) {
        let tag = &tag[..tag.find("/>").expect("empty element")];
        assert_eq!(attr(tag, "format"), "appended");
        let (ty, name) = (attr(tag, "type"), attr(tag, "Name"));
        let offset: usize = attr(tag, "offset").parse().unwrap();
        let len = u64::from_le_bytes(data[offset..offset + 8].try_into().unwrap()) as usize;
        let body = &data[offset + 8..offset + 8 + len];
        let values: Vec<String> = match ty.as_str() {
            "Float64" => body
                .chunks(8)
                .map(|c| {
                    let x = f64::from_le_bytes(c.try_into().unwrap());
                    let mut s = String::new();
                    super::push_f64(&mut s, x);
                    s
                })
                .collect(),
            "Int64" => body
                .chunks(8)
                .map(|c| i64::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "Int32" => body
                .chunks(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "Int8" => body.iter().map(|&b| (b as i8).to_string()).collect(),
            "UInt8" => body.iter().map(|b| b.to_string()).collect(),
            other => panic!("type {other}"),
        };
        out.push((name, ty, values));
    }
    // The last array ends where the closing tags begin.
    let (_, ty, values) = out.last().expect("arrays");
    let size = match ty.as_str() {
        "Float64" | "Int64" => 8,
        "Int32" => 4,
        _ => 1,
    };
    let last = xml.rfind("offset=\"").expect("an offset") + 8;
    let offset: usize = xml[last..last + xml[last..].find('"').unwrap()]
        .parse()
        .unwrap();
    assert_eq!(
        &data[offset + 8 + values.len() * size..],
        b"\n  </AppendedData>\n</VTKFile>\n"
    );
    out
}

#[test]
fn binary_form_holds_the_ascii_forms_arrays() {
    let mp = tet();
    let mut w = VtuWriter::new(&mp);
    w.extra_points(&[Point::new(0.25, 0.25, f64::NAN)]);
    w.point_line_cells(&[[0, 4]]);
    w.point_data(
        "gap",
        DataArray::F64 {
            components: 1,
            values: vec![0.5, -1e-300, f64::INFINITY, 3.0],
        },
    );
    w.cell_data(
        "c",
        DataArray::I64 {
            components: 1,
            values: vec![-1, 2, 3],
        },
    );
    w.point_data(
        "flag",
        DataArray::I8 {
            components: 1,
            values: vec![-1, 0, 1, 1],
        },
    );
    w.cell_data(
        "key",
        DataArray::I32 {
            components: 1,
            values: vec![7, -1, i32::MAX],
        },
    );
    let xml = w.to_xml("t.vtu").unwrap();
    assert_eq!(array(&xml, "flag"), ["-1", "0", "1", "1", "-1"]);
    let mut bytes = Vec::new();
    w.write_binary("t.vtu", &mut bytes).unwrap();
    assert!(bytes.starts_with(b"<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\""));
    let arrays = appended_arrays(&bytes);
    let names: Vec<&str> = arrays.iter().map(|(n, _, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "node_id",
            "gap",
            "flag",
            "entity_id",
            "entity_kind",
            "c",
            "key",
            "Points",
            "connectivity",
            "offsets",
            "types"
        ]
    );
    for (name, ty, values) in &arrays {
        assert_eq!(values, &array(&xml, name), "{name}");
        assert!(
            xml.contains(&format!("type=\"{ty}\" Name=\"{name}\"")),
            "{name}"
        );
    }
    // Same input, same bytes.
    let mut again = Vec::new();
    w.write_binary("t.vtu", &mut again).unwrap();
    assert_eq!(again, bytes);
}

/// A row of `n` cells: hexahedra, and prisms (a permuted kind) on every third, with a
/// quadrilateral condition on each cell's top.
fn row_of_cells(n: usize) -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    let props = PropertiesId(0);
    mp.ensure_properties(props);
    let id = |i: usize, corner: usize| NodeId((4 * i + corner + 1) as u32);
    for i in 0..=n {
        for (c, (y, z)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .into_iter()
            .enumerate()
        {
            mp.add_node(id(i, c), Point::new(i as f64, y, z + 0.1 * i as f64))
                .unwrap();
        }
    }
    for i in 0..n {
        let (a, b) = (i, i + 1);
        if i % 3 == 0 {
            let nodes = [id(a, 0), id(a, 1), id(a, 2), id(b, 0), id(b, 1), id(b, 2)];
            let eid = ElementId(100 + i as u32);
            mp.add_element(eid, GeometryKind::Prism3D6, "", &nodes, props)
                .unwrap();
        } else {
            let nodes = [
                id(a, 0),
                id(b, 0),
                id(b, 1),
                id(a, 1),
                id(a, 3),
                id(b, 3),
                id(b, 2),
                id(a, 2),
            ];
            let eid = ElementId(100 + i as u32);
            mp.add_element(eid, GeometryKind::Hexahedra3D8, "", &nodes, props)
                .unwrap();
        }
        let top = [id(a, 3), id(b, 3), id(b, 2), id(a, 2)];
        let cid = ConditionId(5000 + i as u32);
        mp.add_condition(cid, GeometryKind::Quadrilateral3D4, "", &top, props)
            .unwrap();
    }
    mp
}

/// Many tasks (seven units each in the tests) and batches of them, on pools of 1–3
/// threads: the binary form's arrays are the ASCII form's, and its bytes the same on any
/// pool.
#[test]
fn binary_form_is_the_same_on_any_pool() {
    let mp = row_of_cells(61);
    let mut w = VtuWriter::new(&mp);
    w.extra_points(&[Point::new(0.5, 0.5, 0.5), Point::new(2.0, 0.0, f64::NAN)]);
    w.point_line_cells(&[[0, 248], [249, 7], [3, 4]]);
    let n_cells = w.n_cells();
    w.point_data(
        "per_node",
        DataArray::F64 {
            components: 3,
            values: (0..3 * mp.nodes().len()).map(|k| k as f64 / 7.0).collect(),
        },
    );
    w.cell_data(
        "c",
        DataArray::I32 {
            components: 1,
            values: (0..n_cells as i32).map(|k| k * 3 - 50).collect(),
        },
    );
    let xml = w.to_xml("t.vtu").unwrap();
    let mut first: Option<Vec<u8>> = None;
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut bytes = Vec::new();
        pool.install(|| w.write_binary("t.vtu", &mut bytes))
            .unwrap();
        for (name, _, values) in &appended_arrays(&bytes) {
            assert_eq!(values, &array(&xml, name), "{name}, {threads} threads");
        }
        match &first {
            Some(f) => assert_eq!(&bytes, f, "{threads} threads"),
            None => first = Some(bytes),
        }
    }
}
