//! The meshes written by `tools/gen_meshes.py`.

use csm_geometry::GeometryKind;
use csm_io::read_mesh;
use csm_model::ModelPart;

use crate::data;

/// Everything that must be equal between two readings of the same mesh.
fn summary(mp: &ModelPart) -> String {
    let mut s = String::new();
    let nodes = mp.nodes();
    for (i, id) in nodes.ids().iter().enumerate() {
        let p = nodes.coordinates()[i];
        s += &format!(
            "n {id} {:?} {:?} {:?}\n",
            p.x.to_bits(),
            p.y.to_bits(),
            p.z.to_bits()
        );
    }
    for (tag, ents) in [("e", mp.elements()), ("c", mp.conditions())] {
        for i in 0..ents.len() {
            let conn: Vec<u32> = ents
                .nodes(i)
                .iter()
                .map(|n| nodes.ids()[n.index()])
                .collect();
            s += &format!("{tag} {} {:?} {:?}\n", ents.ids()[i], ents.kind(i), conn);
        }
    }
    s += &part_counts(mp);
    s += &format!(
        "DOMAIN_SIZE {:?}\n",
        mp.process_info().number("DOMAIN_SIZE")
    );
    s
}

/// `path nodes elements conditions` per part.
fn part_counts(mp: &ModelPart) -> String {
    let mut s = String::new();
    for path in mp.part_paths() {
        let p = mp.part(mp.find_part(path).unwrap());
        s += &format!(
            "part {path} {} {} {}\n",
            p.nodes().len(),
            p.elements().len(),
            p.conditions().len()
        );
    }
    s
}

/// ASCII and binary give the same model (ids, bit-identical coordinates, kinds,
/// connectivity, parts); 2.2 and 4.1 the same but for the element ids (Gmsh numbers 2.2
/// cells afresh), so those are compared without ids.
#[track_caller]
fn check_variants(stem: &str) -> ModelPart {
    let read = |v: &str| read_mesh(&data(&format!("{stem}_{v}.msh"))).unwrap();
    let (a41, b41, a22, b22) = (
        read("41_ascii"),
        read("41_bin"),
        read("22_ascii"),
        read("22_bin"),
    );
    assert_eq!(
        summary(&b41),
        summary(&a41),
        "{stem}: 4.1 binary differs from ASCII"
    );
    assert_eq!(
        summary(&b22),
        summary(&a22),
        "{stem}: 2.2 binary differs from ASCII"
    );
    let no_ids = |s: String| {
        s.lines()
            .map(|l| match l.split_once(' ') {
                Some((t @ ("e" | "c"), rest)) => format!("{t} {}", rest.split_once(' ').unwrap().1),
                _ => l.to_owned(),
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(
        no_ids(summary(&a22)),
        no_ids(summary(&a41)),
        "{stem}: 2.2 differs from 4.1"
    );
    a41
}

fn count_kind(mp: &ModelPart, kind: GeometryKind) -> (usize, usize) {
    let e = mp.elements().kinds().iter().filter(|&&k| k == kind).count();
    let c = mp
        .conditions()
        .kinds()
        .iter()
        .filter(|&&k| k == kind)
        .count();
    (e, c)
}

#[test]
fn boxes_all_msh_variants_give_the_same_model() {
    let mp = check_variants("boxes");
    assert_eq!(mp.process_info().number("DOMAIN_SIZE"), Some(3.0));
    assert_eq!(mp.nodes().len(), 169);
    assert_eq!(count_kind(&mp, GeometryKind::Tetrahedra3D4).0, 234);
    assert_eq!(count_kind(&mp, GeometryKind::Hexahedra3D8).0, 32);
    assert_eq!(count_kind(&mp, GeometryKind::Triangle3D3).1, 44);
    assert_eq!(count_kind(&mp, GeometryKind::Quadrilateral3D4).1, 16);
    let part = |name: &str| mp.part(mp.get_part(name).unwrap());
    assert_eq!(part("slave").conditions().len(), 16);
    assert_eq!(part("master").conditions().len(), 44);
    // Listed twice in MSH 2.2 (slave/master and interface), one entity in two parts.
    assert_eq!(part("interface").conditions().len(), 60);
    assert_eq!(mp.conditions().len(), 60);
    assert_eq!(part("block_lower").elements().len(), 234);
    assert_eq!(part("block_upper").elements().len(), 32);
    // The unnamed curve group: nodes only.
    let edge = part("physical_1_7");
    assert!(edge.elements().is_empty() && edge.conditions().is_empty());
    assert!(edge.nodes().len() >= 2);
}

#[test]
fn rects_all_msh_variants_give_the_same_model() {
    let mp = check_variants("rects");
    assert_eq!(mp.process_info().number("DOMAIN_SIZE"), Some(2.0));
    let (tri, _) = count_kind(&mp, GeometryKind::Triangle2D3);
    let (quad, _) = count_kind(&mp, GeometryKind::Quadrilateral2D4);
    let (_, lines) = count_kind(&mp, GeometryKind::Line2D2);
    assert!(tri > 0 && quad > 0 && lines > 0);
    assert_eq!(mp.elements().len(), tri + quad);
    assert_eq!(mp.conditions().len(), lines);
}

#[test]
fn mdpa_twins_give_the_same_parts() {
    for stem in ["boxes", "rects"] {
        let msh = read_mesh(&data(&format!("{stem}_41_bin.msh"))).unwrap();
        let mdpa = read_mesh(&data(&format!("{stem}.mdpa"))).unwrap();
        let named = |mp: &ModelPart| {
            part_counts(mp)
                .lines()
                .filter(|l| !l.contains("physical_"))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(named(&mdpa), named(&msh), "{stem}");
        assert_eq!(mdpa.elements().ids(), msh.elements().ids());
        assert_eq!(mdpa.conditions().kinds(), msh.conditions().kinds());
        assert_eq!(
            mdpa.process_info().number("DOMAIN_SIZE"),
            msh.process_info().number("DOMAIN_SIZE")
        );
        // Same coordinates, bit for bit (the script writes Python's round-trip repr).
        assert_eq!(mdpa.nodes().coordinates(), msh.nodes().coordinates());
    }
}

/// Straight-sided second-order cells: every Kratos mid node must sit at the middle of its
/// Kratos edge, every face node at its face's centre — which checks the permutation.
#[test]
fn second_order_cells_are_in_kratos_node_order() {
    use GeometryKind as G;
    const TET10: &[(usize, &[usize])] = &[
        (4, &[0, 1]),
        (5, &[1, 2]),
        (6, &[2, 0]),
        (7, &[0, 3]),
        (8, &[1, 3]),
        (9, &[2, 3]),
    ];
    const HEX_EDGES: &[(usize, &[usize])] = &[
        (8, &[0, 1]),
        (9, &[1, 2]),
        (10, &[2, 3]),
        (11, &[3, 0]),
        (12, &[0, 4]),
        (13, &[1, 5]),
        (14, &[2, 6]),
        (15, &[3, 7]),
        (16, &[4, 5]),
        (17, &[5, 6]),
        (18, &[6, 7]),
        (19, &[7, 4]),
    ];
    const HEX27_FACES: &[(usize, &[usize])] = &[
        (20, &[0, 1, 2, 3]),
        (21, &[0, 1, 5, 4]),
        (22, &[1, 2, 6, 5]),
        (23, &[2, 3, 7, 6]),
        (24, &[3, 0, 4, 7]),
        (25, &[4, 5, 6, 7]),
        (26, &[0, 1, 2, 3, 4, 5, 6, 7]),
    ];
    const TRI6: &[(usize, &[usize])] = &[(3, &[0, 1]), (4, &[1, 2]), (5, &[2, 0])];
    const QUAD9: &[(usize, &[usize])] = &[
        (4, &[0, 1]),
        (5, &[1, 2]),
        (6, &[2, 3]),
        (7, &[3, 0]),
        (8, &[0, 1, 2, 3]),
    ];
    let mut seen = std::collections::BTreeSet::new();
    for file in ["boxes_order2.msh", "boxes_order2_serendipity.msh"] {
        let mp = read_mesh(&data(file)).unwrap();
        let xyz = mp.nodes().coordinates();
        for ents in [mp.elements(), mp.conditions()] {
            for i in 0..ents.len() {
                let kind = ents.kind(i);
                let rules: Vec<(usize, &[usize])> = match kind {
                    G::Tetrahedra3D10 => TET10.to_vec(),
                    G::Hexahedra3D20 => HEX_EDGES.to_vec(),
                    G::Hexahedra3D27 => [HEX_EDGES, HEX27_FACES].concat(),
                    G::Triangle3D6 => TRI6.to_vec(),
                    G::Quadrilateral3D8 => QUAD9[..4].to_vec(),
                    G::Quadrilateral3D9 => QUAD9.to_vec(),
                    k => panic!("unexpected {k:?} in {file}"),
                };
                seen.insert(kind);
                let n = ents.nodes(i);
                for (mid, corners) in rules {
                    let mut c = csm_geometry::math::Vector::zeros();
                    for &k in corners {
                        c += xyz[n[k].index()].coords;
                    }
                    c /= corners.len() as f64;
                    let d = (xyz[n[mid].index()].coords - c).norm();
                    assert!(
                        d < 1e-9,
                        "{file}: {kind:?} {} node {mid} is {d} off",
                        ents.ids()[i]
                    );
                }
            }
        }
    }
    assert_eq!(seen.len(), 6, "{seen:?}");
}
