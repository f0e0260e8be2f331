//! The machine's ceiling for every stage of a search: N copies of the same run, each on a
//! thread of its own with a one-thread rayon pool, against one copy alone.
//!
//! A speed-up table says how much faster N threads made a stage, not how much faster this
//! machine could make it. N copies that share nothing (each reads its own model, none waits
//! for another) are the best any parallel form of the stage can do: every copy does the whole
//! work, so N copies finishing in the time one copy takes alone is a speed-up of N, and a
//! stage whose copies slow each other down (memory bandwidth, a shared cache, the clock of a
//! busy chip, the kernel's page faults) shows it as a ceiling below N. `cargo xtask scaling`
//! runs this beside its sweep and prints the ceiling next to every stage's speed-up.
//!
//! ```text
//! cargo run --release --example copies -- MESH SETUP.json COPIES OUT.json
//! ```
//!
//! One run per process, as `csm search` is one: the mesh is read once and cloned for every
//! copy, a barrier starts the copies' initialise phase together and another their search
//! step, and every copy's stage times are taken from the `csm::stages` trace (the stages of
//! `csm search --profile`). `COPIES` 1 is the copy alone. OUT.json (`csm-copies/1`):
//! `{"format": "csm-copies/1", "copies": N, "runs": [[{"phase": "initialize", "stage":
//! "normal check", "seconds": s}, …], …]}`, a list per copy, the rest of each phase's time as
//! its stage `other` (as `csm search --profile` reports it) and its wall time as its stage
//! `all`. `cargo xtask scaling` alternates runs of one copy and of N and takes the
//! ceiling as the one copy's fastest time times the N copies' best throughput (the sum of
//! 1 / time over the copies).

use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Barrier, Mutex, PoisonError};
use std::thread::ThreadId;
use std::time::Instant;

use csm::io::read_mesh;
use csm::model::ModelPart;
use csm::search::{ContactSearch, SearchSetup};
use serde_json::{Value, json};
use tracing::field::{Field, Visit};
use tracing_subscriber::layer::{Context, Layer, SubscriberExt};

/// Stage times recorded per thread, in the order they ended.
type Marks = Arc<Mutex<HashMap<ThreadId, Vec<(String, f64)>>>>;

/// Keeps every `csm::stages` mark with the thread that made it.
struct MarkLayer {
    marks: Marks,
}

#[derive(Default)]
struct Fields {
    stage: Option<String>,
    seconds: Option<f64>,
}

impl Visit for Fields {
    fn record_f64(&mut self, field: &Field, value: f64) {
        if field.name() == "seconds" {
            self.seconds = Some(value);
        }
    }

    fn record_str(&mut self, field: &Field, value: &str) {
        if field.name() == "stage" {
            self.stage = Some(value.to_owned());
        }
    }

    fn record_debug(&mut self, _field: &Field, _value: &dyn std::fmt::Debug) {}
}

impl<S: tracing::Subscriber> Layer<S> for MarkLayer {
    fn on_event(&self, event: &tracing::Event<'_>, _ctx: Context<'_, S>) {
        if event.metadata().target() != "csm::stages" {
            return;
        }
        let mut fields = Fields::default();
        event.record(&mut fields);
        if let (Some(stage), Some(seconds)) = (fields.stage, fields.seconds) {
            let id = std::thread::current().id();
            let mut marks = self.marks.lock().unwrap_or_else(PoisonError::into_inner);
            marks.entry(id).or_default().push((stage, seconds));
        }
    }
}

/// One copy's times: `(phase, stage) → seconds`, with `(phase, "all")` the phase's wall time.
type Times = Vec<((String, String), f64)>;

/// Runs `copies` copies of initialise + search step on clones of `model` at once, each on a
/// thread with a one-thread pool; returns every copy's times.
fn run(model: &ModelPart, setup: &SearchSetup, copies: usize, marks: &Marks) -> Vec<Times> {
    let barrier = Barrier::new(copies);
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..copies)
            .map(|_| {
                let mut model = model.clone();
                let barrier = &barrier;
                scope.spawn(move || {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(1)
                        .build()
                        .expect("a one-thread pool");
                    pool.install(|| one_copy(&mut model, setup, barrier, marks))
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a copy panicked"))
            .collect()
    })
}

/// One copy: initialise, then the search step, each started at the barrier.
fn one_copy(model: &mut ModelPart, setup: &SearchSetup, barrier: &Barrier, marks: &Marks) -> Times {
    let id = std::thread::current().id();
    // The phase's stages, the rest of its time as its stage `other` (as `csm search
    // --profile` reports it), and its wall time as its stage `all`.
    let take = |phase: &str, wall: f64, times: &mut Times| {
        let mut marks = marks.lock().unwrap_or_else(PoisonError::into_inner);
        let mut staged = 0.0;
        for (stage, s) in marks.remove(&id).unwrap_or_default() {
            staged += s;
            times.push(((phase.to_owned(), stage), s));
        }
        times.push(((phase.to_owned(), "other".into()), (wall - staged).max(0.0)));
        times.push(((phase.to_owned(), "all".into()), wall));
    };
    let mut times = Times::new();
    barrier.wait();
    let start = Instant::now();
    let mut search = ContactSearch::initialize(model, setup).expect("the setup initialises");
    take("initialize", start.elapsed().as_secs_f64(), &mut times);
    barrier.wait();
    let start = Instant::now();
    search.step(model).expect("the search step runs");
    take("search", start.elapsed().as_secs_f64(), &mut times);
    times
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [mesh, setup, copies, out] = args.as_slice() else {
        eprintln!("usage: copies MESH SETUP.json COPIES OUT.json");
        std::process::exit(2);
    };
    let fail = |what: String| -> ! {
        eprintln!("copies: {what}");
        std::process::exit(1)
    };
    let copies = match copies.parse::<usize>() {
        Ok(n) if n >= 1 => n,
        _ => fail(format!("`{copies}`: give the number of copies, 1 or more")),
    };
    let model = read_mesh(Path::new(mesh)).unwrap_or_else(|e| fail(e.to_string()));
    let text = std::fs::read_to_string(setup).unwrap_or_else(|e| fail(format!("{setup}: {e}")));
    let setup = csm::search::parse_setup(&text, setup).unwrap_or_else(|e| fail(e.to_string()));
    let marks = Marks::default();
    let subscriber = tracing_subscriber::registry().with(MarkLayer {
        marks: marks.clone(),
    });
    tracing::subscriber::set_global_default(subscriber).expect("the only subscriber");
    let runs: Vec<Value> = run(&model, &setup, copies, &marks)
        .into_iter()
        .map(|times| {
            let rows: Vec<Value> = times
                .into_iter()
                .map(|((phase, stage), seconds)| {
                    json!({"phase": phase, "stage": stage, "seconds": seconds})
                })
                .collect();
            Value::Array(rows)
        })
        .collect();
    let doc = json!({"format": "csm-copies/1", "copies": copies, "runs": runs});
    let text = serde_json::to_string_pretty(&doc).expect("JSON") + "\n";
    std::fs::write(out, text).unwrap_or_else(|e| fail(format!("{out}: {e}")));
}
