//! `RUST_LOG` parsing.

use tracing::Level;
use tracing_subscriber::filter::Targets;

use super::filter;

fn enabled(t: &Targets, target: &str, level: Level) -> bool {
    t.would_enable(target, &level)
}

#[test]
fn rust_log_values() {
    // (value, csm at info?, csm at debug?, csm::stages at debug?, csm at warn?)
    for (value, info, debug, stages, warn) in [
        (None, false, false, false, true),
        (Some(""), false, false, false, true),
        (Some("info"), true, false, false, true),
        (Some("debug"), true, true, true, true),
        (Some("off"), false, false, false, false),
        (Some("csm=info"), true, false, false, true),
        (Some("warn,csm::stages=debug"), false, false, true, true),
        (Some("rayon=debug"), false, false, false, false),
        (Some("no such level=="), false, false, false, true),
    ] {
        let t = filter(value);
        assert_eq!(
            enabled(&t, "csm", Level::INFO),
            info,
            "RUST_LOG={value:?}: info"
        );
        assert_eq!(
            enabled(&t, "csm", Level::DEBUG),
            debug,
            "RUST_LOG={value:?}: debug"
        );
        assert_eq!(
            enabled(&t, "csm::stages", Level::DEBUG),
            stages,
            "RUST_LOG={value:?}: stages"
        );
        assert_eq!(
            enabled(&t, "csm", Level::WARN),
            warn,
            "RUST_LOG={value:?}: warn"
        );
    }
}
