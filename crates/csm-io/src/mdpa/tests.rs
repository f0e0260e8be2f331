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

/// A file that is not UTF-8 (a Latin-1 comment and name) reads as its lossy conversion.
#[test]
fn latin_1_bytes_read_as_replacement_characters() {
    let mut bytes = b"// Dichte \xe4\nBegin Nodes\n1 0 0 0 // \xe9\nEnd Nodes\n".to_vec();
    bytes.extend_from_slice(b"Begin SubModelPart Pl\xe4te\nEnd SubModelPart\n");
    let mp = super::read_mdpa_bytes(&bytes, "m.mdpa").unwrap();
    assert_eq!(mp.nodes().len(), 1);
    assert_eq!(mp.part_paths(), ["Pl\u{fffd}te"]);
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

/// The parallel block parsing against the word-by-word reading (the oracle).
mod parallel_blocks {
    use super::super::{Parallel, read_mdpa_with};
    use csm_model::ModelPart;
    use proptest::prelude::*;

    /// What a model holds, for comparison.
    fn summary(mp: &ModelPart) -> String {
        let mut s = format!(
            "nodes {:?} {:?}\n",
            mp.nodes().ids(),
            mp.nodes().coordinates()
        );
        for (name, e) in [("elements", mp.elements()), ("conditions", mp.conditions())] {
            s += &format!("{name} {:?} {:?}\n", e.ids(), e.kinds());
            for i in 0..e.len() {
                s += &format!("{} {:?} {:?}\n", e.name(i), e.nodes(i), e.properties(i));
            }
        }
        for path in mp.part_paths() {
            let p = mp.part(mp.get_part(path).unwrap());
            s += &format!(
                "part {path} {:?} {:?} {:?}\n",
                p.nodes(),
                p.elements(),
                p.conditions()
            );
        }
        s += &format!(
            "properties {:?}\n",
            mp.properties().keys().collect::<Vec<_>>()
        );
        s
    }

    fn outcome(r: Result<ModelPart, crate::Error>) -> String {
        match r {
            Ok(mp) => summary(&mp),
            Err(e) => format!("error: {e}"),
        }
    }

    /// Numbers written in the forms files use.
    fn number() -> impl Strategy<Value = String> {
        prop_oneof![
            (-5i32..5).prop_map(|v| v.to_string()),
            (-1e3f64..1e3).prop_map(|v| v.to_string()),
            (-1e3f64..1e3).prop_map(|v| format!("{v:e}")),
            (-1e3f64..1e3).prop_map(|v| format!("{v:+.3E}")),
            Just("1.".to_owned()),
            Just(".5".to_owned()),
        ]
    }

    /// A separator between words: mostly spaces, sometimes a line end (a record split over
    /// lines).
    fn gap() -> impl Strategy<Value = &'static str> {
        prop_oneof![8 => Just(" "), 2 => Just("\t "), 1 => Just("\n"), 1 => Just("\r\n  ")]
    }

    /// A generated file: nodes, tetrahedra, triangle conditions and a sub model part with
    /// ids that may repeat or be missing.
    fn mdpa() -> impl Strategy<Value = String> {
        let nodes = prop::collection::vec(
            (1u32..40, number(), number(), number(), gap(), gap()),
            1..40,
        );
        let elements = prop::collection::vec(
            (1u32..30, 0u32..3, prop::array::uniform4(1u32..42), gap()),
            0..25,
        );
        let conditions =
            prop::collection::vec((1u32..30, prop::array::uniform3(1u32..42), gap()), 0..25);
        let part = prop::collection::vec((1u32..42, gap()), 0..30);
        (nodes, elements, conditions, part, any::<bool>()).prop_map(
            |(nodes, elements, conditions, part, crlf)| {
                let nl = if crlf { "\r\n" } else { "\n" };
                let mut t = format!("Begin Properties 0{nl}End Properties{nl}Begin Nodes{nl}");
                for (id, x, y, z, a, b) in nodes {
                    t += &format!("{id} {x}{a}{y} {z}{b}{nl}");
                }
                t += &format!("End Nodes{nl}Begin Elements Element3D4N{nl}");
                for (id, p, n, g) in elements {
                    t += &format!("{id} {p} {} {}{g}{} {}{nl}", n[0], n[1], n[2], n[3]);
                }
                t += &format!("End Elements{nl}Begin Conditions SurfaceCondition3D3N{nl}");
                for (id, n, g) in conditions {
                    t += &format!("  {id}\t0 {}{g}{} {}{nl}", n[0], n[1], n[2]);
                }
                t += &format!(
                    "End Conditions{nl}Begin SubModelPart P{nl}Begin SubModelPartNodes{nl}"
                );
                for (id, g) in part {
                    t += &format!("{id}{g}");
                }
                t += &format!("{nl}End SubModelPartNodes{nl}End SubModelPart{nl}");
                t
            },
        )
    }

    /// A word replaced by something else (a bad number, a comment, a name, another id).
    fn mutate(text: &str, at: f64, with: &str) -> String {
        let words: Vec<(usize, &str)> = text
            .split_ascii_whitespace()
            .map(|w| (w.as_ptr() as usize - text.as_ptr() as usize, w))
            .collect();
        let (pos, w) = words[((words.len() as f64 * at) as usize).min(words.len() - 1)];
        format!("{}{with}{}", &text[..pos], &text[pos + w.len()..])
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        #[test]
        fn the_parallel_reading_is_the_word_by_word_reading(
            text in mdpa(),
            mutation in prop::option::of((0.0f64..1.0, prop_oneof![
                Just("x"), Just("1e999"), Just("-1"), Just("4294967296"), Just("2.5"),
                Just("// c\n"), Just("/* c */"), Just("7"), Just("End"), Just("\u{b}"),
            ])),
            min_chunk in 1usize..64,
            window in 1usize..200,
        ) {
            let text = match mutation {
                Some((at, with)) => mutate(&text, at, with),
                None => text,
            };
            let oracle = outcome(read_mdpa_with(text.as_bytes(), "m.mdpa", None));
            let parallel = outcome(read_mdpa_with(
                text.as_bytes(),
                "m.mdpa",
                Some(Parallel { min_chunk, window }),
            ));
            prop_assert_eq!(parallel, oracle);
        }
    }

    #[test]
    fn big_blocks_are_read_in_parallel_windows() {
        // Ten thousand nodes and elements over many windows and chunks; the counts and a
        // sample against the word-by-word reading.
        let mut t = String::from("Begin Nodes\n");
        for i in 1..=10_000 {
            t += &format!(
                "{i} {} {} {}\n",
                i as f64 * 0.5,
                -(i as f64),
                1e-3 * i as f64
            );
        }
        t += "End Nodes\nBegin Elements Element3D4N\n";
        for i in 1..=9_997 {
            t += &format!("{i} 0 {i} {} {} {}\n", i + 1, i + 2, i + 3);
        }
        t += "End Elements\n";
        let sizes = Parallel {
            min_chunk: 1000,
            window: 20_000,
        };
        let parallel = read_mdpa_with(t.as_bytes(), "m.mdpa", Some(sizes)).unwrap();
        let oracle = read_mdpa_with(t.as_bytes(), "m.mdpa", None).unwrap();
        assert_eq!(parallel.nodes().len(), 10_000);
        assert_eq!(parallel.elements().len(), 9_997);
        assert_eq!(parallel.nodes().coordinates()[4_999].x, 2_500.0);
        assert_eq!(summary(&parallel), summary(&oracle));
        // A duplicate id deep in a later window is reported on its own line.
        let dup = t.replacen("\n7000 ", "\n6999 ", 1);
        let e = read_mdpa_with(dup.as_bytes(), "m.mdpa", Some(sizes)).unwrap_err();
        assert!(
            e.to_string()
                .contains("m.mdpa:7001: duplicate node id 6999"),
            "{e}"
        );
    }
}

/// The parallel UTF-8 check against `std::str::from_utf8` on texts of several pieces:
/// multi-byte characters everywhere (so across the piece boundaries), a long run without
/// ASCII, and an invalid byte early, at a boundary or at the end.
#[test]
fn the_parallel_utf8_check_is_from_utf8() {
    let rayon_pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut text = Vec::new();
    while text.len() < (3 << 20) + 7 {
        text.extend_from_slice("ab é € 𝄞 x\n".as_bytes());
    }
    let no_ascii = "é".repeat(1 << 20).into_bytes();
    let mut cases = vec![
        text.clone(),
        [text.clone(), no_ascii.clone(), text.clone()].concat(),
    ];
    for at in [3, 1 << 20, (1 << 20) + 1, text.len() - 1] {
        let mut bad = text.clone();
        bad[at] = 0xff;
        cases.push(bad);
    }
    let mut cut = text.clone();
    cut.truncate((2 << 20) + 2); // may end inside a character
    cases.push(cut);
    rayon_pool.install(|| {
        for (k, bytes) in cases.iter().enumerate() {
            assert_eq!(
                super::read_mdpa::is_utf8(bytes),
                std::str::from_utf8(bytes).is_ok(),
                "case {k}"
            );
        }
    });
}
