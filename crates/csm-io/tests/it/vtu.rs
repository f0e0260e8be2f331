//! The VTU writer: well-formed XML (a small hand-written check) with the right counts.

use csm_io::{DataArray, VtuWriter, read_mesh};
use csm_model::NodeIdx;

use crate::data;

/// Checks that tags nest and close, and returns the names of the opened elements in order.
fn check_well_formed(xml: &str) -> Vec<String> {
    let mut stack: Vec<String> = Vec::new();
    let mut opened = Vec::new();
    let mut rest = xml;
    assert!(rest.starts_with("<?xml"));
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unclosed tag") + start;
        let tag = &rest[start + 1..end];
        assert!(!rest[..start].contains('>'), "stray `>`");
        if tag.starts_with('?') {
        } else if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop().as_deref(), Some(name), "mismatched </{name}>");
        } else {
            let name = tag
                .split_whitespace()
                .next()
                .unwrap()
                .trim_end_matches('/')
                .to_owned();
            assert_eq!(
                tag.matches('"').count() % 2,
                0,
                "unbalanced quotes in <{tag}>"
            );
            opened.push(name.clone());
            if !tag.ends_with('/') {
                stack.push(name);
            }
        }
        rest = &rest[end + 1..];
    }
    assert!(stack.is_empty(), "unclosed {stack:?}");
    opened
}

/// The text of the first `<DataArray … Name="name" …>`.
fn array<'a>(xml: &'a str, name: &str) -> Vec<&'a str> {
    let key = format!("Name=\"{name}\"");
    let at = xml.find(&key).unwrap_or_else(|| panic!("no array {name}"));
    let body_start = xml[at..].find('>').unwrap() + at + 1;
    let body_end = xml[body_start..].find("</DataArray>").unwrap() + body_start;
    xml[body_start..body_end].split_whitespace().collect()
}

#[test]
fn boxes_vtu_is_well_formed_with_the_right_counts() {
    let mp = read_mesh(&data("boxes_41_ascii.msh")).unwrap();
    let n_points = mp.nodes().len();
    let mut w = VtuWriter::new(&mp);
    w.line_cells(&[[NodeIdx(0), NodeIdx(1)], [NodeIdx(2), NodeIdx(3)]]);
    let n_cells = w.n_cells();
    assert_eq!(n_cells, mp.elements().len() + mp.conditions().len() + 2);
    w.point_data(
        "gap",
        DataArray::F64 {
            components: 1,
            values: (0..n_points).map(|i| i as f64 / 3.0).collect(),
        },
    );
    w.cell_data(
        "flag",
        DataArray::I64 {
            components: 1,
            values: vec![7; n_cells],
        },
    );
    let xml = w.to_xml("boxes.vtu").unwrap();
    let opened = check_well_formed(&xml);
    assert_eq!(opened.iter().filter(|n| *n == "DataArray").count(), 9);
    assert!(xml.contains(&format!(
        "NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\""
    )));
    assert_eq!(array(&xml, "Points").len(), 3 * n_points);
    assert_eq!(array(&xml, "gap").len(), n_points);
    assert_eq!(array(&xml, "flag").len(), n_cells);
    let types = array(&xml, "types");
    assert_eq!(types.len(), n_cells);
    assert_eq!(types.iter().filter(|t| **t == "10").count(), 234);
    assert_eq!(types.iter().filter(|t| **t == "12").count(), 32);
    assert_eq!(types.iter().filter(|t| **t == "5").count(), 44);
    assert_eq!(types.iter().filter(|t| **t == "9").count(), 16);
    assert_eq!(types.iter().filter(|t| **t == "3").count(), 2);
    let offsets = array(&xml, "offsets");
    let conn = array(&xml, "connectivity");
    assert_eq!(
        offsets.last().unwrap().parse::<usize>().unwrap(),
        conn.len()
    );
    // Round-trip floats: 1/3 reads back exactly.
    assert_eq!(array(&xml, "gap")[1].parse::<f64>().unwrap(), 1.0 / 3.0);
    // Stable: the same input gives the same bytes.
    assert_eq!(w.to_xml("boxes.vtu").unwrap(), xml);
}

#[test]
fn wrong_array_length_is_an_error() {
    let mp = read_mesh(&data("rects_41_ascii.msh")).unwrap();
    let mut w = VtuWriter::new(&mp);
    w.cell_data(
        "x",
        DataArray::F64 {
            components: 3,
            values: vec![0.0; 3],
        },
    );
    let e = w.to_xml("r.vtu").unwrap_err().to_string();
    assert!(e.starts_with("r.vtu: expected "), "{e}");
    assert!(e.contains("values in data array `x`, found 3"), "{e}");
}
