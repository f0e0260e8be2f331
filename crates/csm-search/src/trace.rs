//! Stage timings, for profiling long runs: `tracing` events of target `csm::stages` at level
//! `debug` (the binary prints them with `RUST_LOG=csm::stages=debug`). Every stage mark gives
//! the wall time since the previous mark of the same thread and, where `/proc/self/status`
//! exists (Linux), the resident memory and its peak so far, e.g. `stage slave queries 0.451 s
//! (RSS 310 MiB, peak 351 MiB)`. When nothing listens a mark costs one check of tracing's
//! cached interest.

use std::cell::Cell;
use std::time::Instant;

fn enabled() -> bool {
    tracing::enabled!(target: "csm::stages", tracing::Level::DEBUG)
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

/// The time of this thread's last mark, for work that goes on on another thread (the first
/// closure of a `rayon::join` called from outside the pool runs on one of the pool's threads):
/// [`resume`] it there, and back here after.
pub(crate) fn last() -> Option<Instant> {
    LAST.with(Cell::get)
}

/// Continues the stage timing of another thread from its [`last`] mark.
pub(crate) fn resume(at: Option<Instant>) {
    LAST.with(|last| last.set(at));
}

/// Ends stage `name`: prints its wall time since the previous mark (or [`start`]).
pub(crate) fn mark(name: &str) {
    if !enabled() {
        return;
    }
    let now = Instant::now();
    LAST.with(|last| {
        if let Some(before) = last.replace(Some(now)) {
            let seconds = (now - before).as_secs_f64();
            tracing::debug!(
                target: "csm::stages",
                stage = name,
                seconds,
                "stage {name} {seconds:.3} s{}",
                memory()
            );
        }
    });
}

/// ` (RSS … MiB, peak … MiB)` from `/proc/self/status`, or nothing where it cannot be read.
fn memory() -> String {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else {
        return String::new();
    };
    let field = |key: &str| -> Option<u64> {
        let line = status.lines().find(|l| l.starts_with(key))?;
        line[key.len()..]
            .trim()
            .trim_end_matches("kB")
            .trim()
            .parse()
            .ok()
    };
    match (field("VmRSS:"), field("VmHWM:")) {
        (Some(rss), Some(peak)) => format!(" (RSS {} MiB, peak {} MiB)", rss / 1024, peak / 1024),
        _ => String::new(),
    }
}
