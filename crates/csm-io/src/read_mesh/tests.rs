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
