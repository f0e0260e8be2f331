//! Stage timings on standard error, for profiling long runs: with the environment variable
//! `CSM_TRACE_STAGES` set (to anything), every stage mark prints the wall time since the
//! previous mark of the same thread, e.g. `csm: stage kd-tree queries 0.451 s`. Without it a
//! mark costs one relaxed check.

use std::cell::Cell;
use std::sync::OnceLock;
use std::time::Instant;

fn enabled() -> bool {
    static ENABLED: OnceLock<bool> = OnceLock::new();
    *ENABLED.get_or_init(|| std::env::var_os("CSM_TRACE_STAGES").is_some())
}

thread_local! {
    static LAST: Cell<Option<Instant>> = const { Cell::new(None) };
}

/// Starts the timing of the stages that follow (no output).
pub(crate) fn start() {
    if enabled() {
        LAST.with(|last| last.set(Some(Instant::now())));
    }
}

/// Ends stage `name`: prints its wall time since the previous mark (or [`start`]).
pub(crate) fn mark(name: &str) {
    if !enabled() {
        return;
    }
    let now = Instant::now();
    LAST.with(|last| {
        if let Some(before) = last.replace(Some(now)) {
            eprintln!("csm: stage {name} {:.3} s", (now - before).as_secs_f64());
        }
    });
}
