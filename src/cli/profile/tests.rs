//! The stage recorder: events of `csm::stages` only, phases and their `other`.

use tracing_subscriber::prelude::*;

use super::Recorder;

#[test]
fn records_stage_events_into_the_current_phase() {
    let recorder = Recorder::new();
    let subscriber = tracing_subscriber::registry().with(recorder.layer());
    tracing::subscriber::with_default(subscriber, || {
        recorder.phase("initialize");
        tracing::debug!(target: "csm::stages", stage = "normal check", seconds = 0.25, "m");
        // Not a stage: another target, or a stage event without its fields.
        tracing::debug!(target: "csm", stage = "x", seconds = 1.0, "m");
        tracing::debug!(target: "csm::stages", "stage without fields");
        recorder.end_phase(1.0);
        recorder.phase("read");
        recorder.end_phase(0.5);
        recorder.phase("search");
        tracing::debug!(target: "csm::stages", stage = "mapping", seconds = 0.75, "m");
        recorder.end_phase(0.75);
    });
    let stages: Vec<(String, String, f64)> = recorder
        .stages()
        .into_iter()
        .map(|t| (t.phase, t.stage, t.seconds))
        .collect();
    let s = |p: &str, n: &str, t: f64| (p.to_owned(), n.to_owned(), t);
    assert_eq!(
        stages,
        [
            s("initialize", "normal check", 0.25),
            s("initialize", "other", 0.75),
            s("read", "read", 0.5),
            s("search", "mapping", 0.75),
        ]
    );
    let json = recorder.to_json(3, 2.5);
    assert_eq!(json["format"], "csm-profile/1");
    assert_eq!(json["threads"], 3);
    assert_eq!(json["phases"]["initialize"], 1.0);
    assert_eq!(json["phases"]["total"], 2.5);
    assert_eq!(json["stages"].as_array().unwrap().len(), 4);
}

/// A library's `phase` event ends the current phase with the time it has run and starts the
/// next: the stages after it belong to the new phase, and the phases add up.
#[test]
fn a_phase_event_starts_the_next_phase() {
    let recorder = Recorder::new();
    let subscriber = tracing_subscriber::registry().with(recorder.layer());
    tracing::subscriber::with_default(subscriber, || {
        recorder.phase("initialize");
        tracing::debug!(target: "csm::stages", stage = "normal check", seconds = 0.001, "m");
        std::thread::sleep(std::time::Duration::from_millis(20));
        tracing::debug!(target: "csm::stages", phase = "search");
        tracing::debug!(target: "csm::stages", stage = "mapping", seconds = 0.001, "m");
        std::thread::sleep(std::time::Duration::from_millis(20));
        recorder.end_current_phase();
    });
    let stages: Vec<(String, String)> = (recorder.stages().into_iter())
        .map(|t| (t.phase, t.stage))
        .collect();
    let s = |p: &str, n: &str| (p.to_owned(), n.to_owned());
    assert_eq!(
        stages,
        [
            s("initialize", "normal check"),
            s("initialize", "other"),
            s("search", "mapping"),
            s("search", "other"),
        ]
    );
    let json = recorder.to_json(1, 0.04);
    for phase in ["initialize", "search"] {
        let seconds = json["phases"][phase].as_f64().unwrap();
        assert!((0.02..1.0).contains(&seconds), "{phase}: {seconds}");
    }
}

/// Writes one byte in each of `pages` fresh pages (a large allocation: mapped, not reused).
#[cfg(target_os = "linux")]
fn touch_fresh_pages(pages: usize) -> usize {
    let mut fresh = vec![0u8; pages * 4096];
    for page in fresh.chunks_mut(4096) {
        page[0] = 1;
    }
    fresh.iter().map(|&b| usize::from(b)).sum()
}

/// The libraries' stages keep the faults and CPU time they report; the binary's own stages
/// and `other` count theirs here (process-wide: other tests running beside add to them, never
/// take away).
#[cfg(target_os = "linux")]
#[test]
fn stages_count_their_page_faults_and_cpu_time() {
    const PAGES: usize = 4096;
    // At least one fault per 2 MiB, should the pages be huge.
    let least = (PAGES * 4096 / (2 << 20)) as u64;
    let recorder = Recorder::new();
    let subscriber = tracing_subscriber::registry().with(recorder.layer());
    tracing::subscriber::with_default(subscriber, || {
        recorder.phase("search");
        tracing::debug!(target: "csm::stages", stage = "mapping", seconds = 0.5, faults = 7u64,
            cpu_seconds = 0.75, "m");
        assert_eq!(touch_fresh_pages(PAGES), PAGES);
        recorder.end_phase(1.0);
        recorder.phase("write");
        assert_eq!(touch_fresh_pages(PAGES), PAGES);
        assert!(spin(30) > 0);
        recorder.record("RESULT.json", 0.25);
        recorder.end_phase(0.5);
    });
    let faults = |stage: &str| {
        let found = recorder.stages().into_iter().find(|t| t.stage == stage);
        found.and_then(|t| t.faults).unwrap()
    };
    assert_eq!(faults("mapping"), 7);
    assert!(faults("other") >= least, "{}", faults("other"));
    assert!(faults("RESULT.json") >= least, "{}", faults("RESULT.json"));
    // The CPU time likewise: the library's as reported; `other` the phase's less that (0.75 s
    // more than the phase took: none); the binary's stage its 30 ms spin (at least a third
    // of it, should the thread be descheduled meanwhile).
    let cpu = |stage: &str| {
        let found = recorder.stages().into_iter().find(|t| t.stage == stage);
        found.and_then(|t| t.cpu_seconds).unwrap()
    };
    assert_eq!(cpu("mapping"), 0.75);
    assert_eq!(cpu("other"), 0.0);
    assert!(
        (0.01..5.0).contains(&cpu("RESULT.json")),
        "{}",
        cpu("RESULT.json")
    );
    let json = recorder.to_json(1, 1.5);
    let stages = json["stages"].as_array().unwrap();
    assert!(stages.iter().all(|s| s["faults"].is_u64()), "{json}");
    assert!(stages.iter().all(|s| s["cpu"].is_f64()), "{json}");
    assert_eq!(stages[0]["faults"], 7);
    assert_eq!(stages[0]["cpu"], 0.75);
}

/// Spins the calling thread for `ms` milliseconds of wall time.
fn spin(ms: u64) -> u64 {
    let start = std::time::Instant::now();
    let mut x = 0u64;
    while start.elapsed() < std::time::Duration::from_millis(ms) {
        x = std::hint::black_box(x.wrapping_add(1));
    }
    x
}
