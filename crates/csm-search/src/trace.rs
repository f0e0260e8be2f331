//! Stage timings, for profiling long runs: `tracing` events of target `csm::stages` at level
//! `debug` (the binary prints them with `RUST_LOG=csm::stages=debug`). Every stage mark gives
//! the wall time since the previous mark of the same thread (field `seconds`) and, on Linux,
//! the minor page faults of the whole process since then (field `faults`, from
//! `/proc/self/stat`: fresh memory touched for the first time, which costs about 2 µs a page
//! on a virtual machine) and the resident memory and its peak so far (`/proc/self/status`),
//! e.g. `stage slave queries 0.451 s, 172 page faults (RSS 310 MiB, peak 351 MiB)`. When
//! nothing listens a mark costs one check of tracing's cached interest.

use std::cell::Cell;
use std::time::Instant;

fn enabled() -> bool {
    tracing::enabled!(target: "csm::stages", tracing::Level::DEBUG)
}

/// A point of the stage trace: when, and the process's minor page faults by then (where the
/// system says).
#[derive(Debug, Clone, Copy)]
struct Mark {
    at: Instant,
    faults: Option<u64>,
}

impl Mark {
    fn now() -> Mark {
        Mark {
            at: Instant::now(),
            faults: minor_faults(),
        }
    }
}

thread_local! {
    static LAST: Cell<Option<Mark>> = const { Cell::new(None) };
}

/// The minor page faults of the process so far (each a page of fresh memory touched for the
/// first time): `/proc/self/stat`'s tenth field on Linux, `None` where it cannot be read. The
/// stage trace's `faults` are differences of it; a profiler counts its own stages with it.
pub fn minor_faults() -> Option<u64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command name, which is in parentheses and may hold spaces: state,
    // ppid, pgrp, session, tty_nr, tpgid, flags, minflt.
    let (_, fields) = stat.rsplit_once(')')?;
    fields.split_whitespace().nth(7)?.parse().ok()
}

/// Starts the timing of the stages that follow (no output).
pub(crate) fn start() {
    if enabled() {
        LAST.with(|last| last.set(Some(Mark::now())));
    }
}

/// Ends stage `name`: prints its wall time since the previous mark (or [`start`]) and the
/// page faults since then.
pub(crate) fn mark(name: &str) {
    if !enabled() {
        return;
    }
    let now = Mark::now();
    LAST.with(|last| {
        if let Some(before) = last.replace(Some(now)) {
            let seconds = (now.at - before.at).as_secs_f64();
            match now.faults.zip(before.faults) {
                Some((n, b)) => {
                    let faults = n.saturating_sub(b);
                    tracing::debug!(
                        target: "csm::stages",
                        stage = name,
                        seconds,
                        faults,
                        "stage {name} {seconds:.3} s, {faults} page faults{}",
                        memory()
                    );
                }
                None => tracing::debug!(
                    target: "csm::stages",
                    stage = name,
                    seconds,
                    "stage {name} {seconds:.3} s{}",
                    memory()
                ),
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The counter is the kernel's: touching fresh pages raises it by about one a page.
    #[cfg(target_os = "linux")]
    #[test]
    fn touching_fresh_pages_counts_their_faults() {
        const PAGES: usize = 4096;
        let before = minor_faults().expect("/proc/self/stat has minflt");
        // Fresh memory from the kernel (a large allocation is mapped, not reused), written
        // once a page.
        let mut fresh = vec![0u8; PAGES * 4096];
        for page in fresh.chunks_mut(4096) {
            page[0] = 1;
        }
        let after = minor_faults().expect("/proc/self/stat has minflt");
        assert_eq!(fresh.iter().map(|&b| usize::from(b)).sum::<usize>(), PAGES);
        // Huge pages would take fewer faults: at least one per 2 MiB, and never fewer than
        // before.
        let faults = after - before;
        assert!(
            faults >= (PAGES * 4096 / (2 << 20)) as u64 && faults < 100 * PAGES as u64,
            "{faults} faults for {PAGES} fresh pages"
        );
    }
}
