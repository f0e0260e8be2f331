//! Mutated, truncated and spliced real files never panic a reader: it returns `Ok` or `Err`.

use proptest::prelude::*;

use csm_io::{read_mdpa, read_msh};

use crate::{data, kratos};

fn sources() -> Vec<Vec<u8>> {
    let mut v: Vec<Vec<u8>> = [
        "boxes_41_ascii.msh",
        "boxes_41_bin.msh",
        "boxes_22_ascii.msh",
        "boxes_22_bin.msh",
        "rects_41_bin.msh",
        "rects.mdpa",
    ]
    .iter()
    .map(|f| std::fs::read(data(f)).unwrap())
    .collect();
    v.push(
        std::fs::read(kratos(
            "3D_contact_simplest_patch_matching_triquad_test.mdpa",
        ))
        .unwrap(),
    );
    v
}

/// One mutation of a source file.
#[derive(Debug, Clone)]
enum Mutation {
    /// Byte flips at (fraction of the length, new byte).
    Flip(Vec<(f64, u8)>),
    /// Truncation at a fraction of the length.
    Truncate(f64),
    /// The head of one file and the tail of another.
    Splice(usize, f64, f64),
    /// A line repeated (fraction of the length selects it).
    DuplicateLine(f64),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        prop::collection::vec((0.0..1.0f64, any::<u8>()), 1..8).prop_map(Mutation::Flip),
        (0.0..1.0f64).prop_map(Mutation::Truncate),
        (0..7usize, 0.0..1.0f64, 0.0..1.0f64).prop_map(|(o, a, b)| Mutation::Splice(o, a, b)),
        (0.0..1.0f64).prop_map(Mutation::DuplicateLine),
    ]
}

fn at(len: usize, f: f64) -> usize {
    ((len as f64 * f) as usize).min(len)
}

fn apply(src: &[Vec<u8>], which: usize, m: &Mutation) -> Vec<u8> {
    let mut b = src[which].clone();
    match m {
        Mutation::Flip(flips) => {
            for &(f, byte) in flips {
                let i = at(b.len() - 1, f);
                b[i] = byte;
            }
        }
        Mutation::Truncate(f) => b.truncate(at(b.len(), *f)),
        Mutation::Splice(other, f, g) => {
            let o = &src[*other];
            b.truncate(at(b.len(), *f));
            b.extend_from_slice(&o[at(o.len(), *g)..]);
        }
        Mutation::DuplicateLine(f) => {
            let i = at(b.len(), *f);
            let start = b[..i]
                .iter()
                .rposition(|&c| c == b'\n')
                .map_or(0, |p| p + 1);
            let end = b[i..]
                .iter()
                .position(|&c| c == b'\n')
                .map_or(b.len(), |p| i + p + 1);
            let line = b[start..end].to_vec();
            b.splice(end..end, line);
        }
    }
    b
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn readers_never_panic(which in 0..7usize, m in mutation()) {
        let src = sources();
        let bytes = apply(&src, which, &m);
        let _ = read_msh(&bytes, "fuzz.msh");
        let _ = read_mdpa(&String::from_utf8_lossy(&bytes), "fuzz.mdpa");
    }
}
