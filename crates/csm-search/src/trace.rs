//! Stage timings, for profiling long runs: `tracing` events of target `csm::stages` at level
//! `debug` (the binary prints them with `RUST_LOG=csm::stages=debug`). Every stage mark gives
//! the wall time since the previous mark of the same thread (field `seconds`) and, on Linux,
//! the minor page faults of the whole process since then (field `faults`, from
//! `/proc/self/stat`: fresh memory touched for the first time, which costs about 2 µs a page
//! on a virtual machine), the CPU time of the whole process since then (field `cpu_seconds`,
//! every thread's, user and system: `CLOCK_PROCESS_CPUTIME_ID`) and the resident memory and
//! its peak so far (`/proc/self/status`), e.g. `stage slave queries 0.451 s, 172 page faults,
//! 0.897 s CPU (RSS 310 MiB, peak 351 MiB)`. When nothing listens a mark costs one check of
//! tracing's cached interest.

use std::cell::Cell;
use std::time::Instant;

fn enabled() -> bool {
    tracing::enabled!(target: "csm::stages", tracing::Level::DEBUG)
}

/// A point of the stage trace: when, and what the process had used by then.
#[derive(Debug, Clone, Copy)]
struct Mark {
    at: Instant,
    usage: Usage,
}

impl Mark {
    fn now() -> Mark {
        Mark {
            at: Instant::now(),
            usage: Usage::now(),
        }
    }
}

/// What the process has used so far, where the system says (Linux): its minor page faults
/// ([`minor_faults`]) and its CPU time ([`process_cpu_seconds`]). A stage's use is the
/// difference of two ([`Usage::since`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Usage {
    /// Minor page faults.
    pub faults: Option<u64>,
    /// CPU time of every thread, user and system (s).
    pub cpu_seconds: Option<f64>,
}

impl Usage {
    /// The process's use so far.
    pub fn now() -> Usage {
        Usage {
            faults: minor_faults(),
            cpu_seconds: process_cpu_seconds(),
        }
    }

    /// The use from `before` to `self` (each count where both have it; never negative).
    pub fn since(self, before: Usage) -> Usage {
        Usage {
            faults: (self.faults.zip(before.faults)).map(|(n, b)| n.saturating_sub(b)),
            cpu_seconds: (self.cpu_seconds.zip(before.cpu_seconds)).map(|(n, b)| (n - b).max(0.0)),
        }
    }
}

/// The CPU time the whole process has taken so far, every thread's, user and system
/// (`CLOCK_PROCESS_CPUTIME_ID`, nanoseconds), in seconds: on Linux, `None` elsewhere. The
/// stage trace's `cpu_seconds` are differences of it: against a stage's wall time on N
/// threads it says how busy the threads were (N × the wall time when every thread worked
/// throughout; a waiting thread that spins before it sleeps counts as busy).
pub fn process_cpu_seconds() -> Option<f64> {
    #[cfg(target_os = "linux")]
    {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ProcessCPUTime);
        Some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
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

/// Ends stage `name`: prints its wall time since the previous mark (or [`start`]), and the
/// page faults and CPU time since then.
pub(crate) fn mark(name: &str) {
    if !enabled() {
        return;
    }
    let now = Mark::now();
    LAST.with(|last| {
        if let Some(before) = last.replace(Some(now)) {
            let seconds = (now.at - before.at).as_secs_f64();
            let used = now.usage.since(before.usage);
            let faults = used
                .faults
                .map_or_else(String::new, |n| format!(", {n} page faults"));
            let cpu = used
                .cpu_seconds
                .map_or_else(String::new, |c| format!(", {c:.3} s CPU"));
            tracing::debug!(
                target: "csm::stages",
                stage = name,
                seconds,
                faults = used.faults,
                cpu_seconds = used.cpu_seconds,
                "stage {name} {seconds:.3} s{faults}{cpu}{}",
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The CPU clock counts every thread's work: two threads that each spin for 40 ms add
    /// about 80 ms (at least 60, should a thread be descheduled meanwhile), and a use since
    /// a later point is none.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_cpu_time_sums_the_threads() {
        let spin = |ms: u64| {
            let start = Instant::now();
            let mut x = 0u64;
            while start.elapsed() < std::time::Duration::from_millis(ms) {
                x = std::hint::black_box(x.wrapping_add(1));
            }
            x
        };
        let before = Usage::now();
        let (a, b) = std::thread::scope(|s| {
            let other = s.spawn(|| spin(40));
            (spin(40), other.join().expect("the spinning thread ends"))
        });
        let used = Usage::now().since(before);
        assert!(a > 0 && b > 0);
        let cpu = used.cpu_seconds.expect("Linux has a process CPU clock");
        assert!(
            (0.06..1.0).contains(&cpu),
            "{cpu} s CPU for two 40 ms spins"
        );
        // A use since a later point is none, not negative.
        let later = Usage::now();
        assert_eq!(before.since(later).cpu_seconds, Some(0.0));
        assert_eq!(before.since(later).faults, Some(0));
    }

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
