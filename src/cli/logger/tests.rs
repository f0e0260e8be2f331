//! `RUST_LOG` parsing.

use super::{Level, parse_filter};

#[test]
fn rust_log_values() {
    for (value, level) in [
        (None, Level::Warn),
        (Some(""), Level::Warn),
        (Some("info"), Level::Info),
        (Some("DEBUG"), Level::Debug),
        (Some("trace"), Level::Debug),
        (Some("off"), Level::Off),
        (Some("error"), Level::Error),
        (Some("csm=info"), Level::Info),
        (Some("warn,csm=debug"), Level::Debug),
        (Some("rayon=debug"), Level::Warn),
        (Some("nonsense"), Level::Warn),
    ] {
        assert_eq!(parse_filter(value), level, "RUST_LOG={value:?}");
    }
}
