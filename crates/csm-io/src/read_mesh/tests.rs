//! `read_mesh` with every combination of the reader features: a compiled-in format reads, a
//! left-out one is a clear error naming its feature (run by `cargo xtask ci` with
//! `--no-default-features`).

use std::path::PathBuf;

use super::*;

fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data")).join(name)
}

#[track_caller]
fn check(name: &str, compiled_in: bool) {
    let result = read_mesh(&data(name));
    if compiled_in {
        let model = result.unwrap();
        assert!(!model.nodes().is_empty(), "{name}");
    } else {
        let e = result.unwrap_err();
        assert!(
            matches!(e.kind(), ErrorKind::FormatNotCompiled(_)),
            "{name}: {e}"
        );
        assert!(e.to_string().contains("built without the"), "{e}");
    }
}

#[test]
fn each_format_reads_exactly_when_its_feature_is_on() {
    check("boxes.mdpa", cfg!(feature = "mdpa"));
    check("boxes_22_ascii.msh", cfg!(feature = "msh"));
}

#[test]
fn other_extensions_are_refused_whatever_the_features() {
    let e = read_mesh(&data("boxes.vtu")).unwrap_err();
    assert!(
        matches!(e.kind(), ErrorKind::UnsupportedExtension(_)),
        "{e}"
    );
}

/// A large file read in parallel pieces is byte for byte what `std::fs::read` gives (a length
/// that is not a multiple of the piece); one thread, or a small file, reads it whole.
#[cfg(all(unix, feature = "mdpa"))]
#[test]
fn a_large_file_read_in_pieces_is_the_file() {
    let path = std::env::temp_dir().join(format!("csm_read_in_pieces_{}.bin", std::process::id()));
    let mut state = 0x1234_5678_9ABC_DEF1u64;
    let bytes: Vec<u8> = (0..(9 << 20) + 12_345)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 56) as u8
        })
        .collect();
    std::fs::write(&path, &bytes).unwrap();
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let pieces = pool(2).install(|| read_file_in_pieces(&path)).unwrap();
    assert!(
        pieces.as_ref() == Some(&bytes),
        "the pieces differ from the file"
    );
    assert!(pool(2).install(|| read_file(&path)).unwrap() == bytes);
    assert_eq!(
        pool(1).install(|| read_file_in_pieces(&path)).unwrap(),
        None
    );
    std::fs::write(&path, &bytes[..1000]).unwrap();
    assert_eq!(
        pool(2).install(|| read_file_in_pieces(&path)).unwrap(),
        None
    );
    assert!(pool(2).install(|| read_file(&path)).unwrap() == bytes[..1000]);
    std::fs::remove_file(&path).unwrap();
}
