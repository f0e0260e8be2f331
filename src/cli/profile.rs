//! `csm search --profile PROFILE.json`: the wall time of every stage of a run, for the scaling
//! sweep (`cargo xtask scaling`) and for a user who wants to know where the time goes.
//!
//! The libraries mark their stages with `tracing` events of target `csm::stages` (fields
//! `stage` and `seconds`; `csm_search`'s stage trace). [`Recorder::layer`] is a subscriber layer
//! that keeps them; the binary adds its own phases (reading the mesh, writing the outputs) with
//! [`Recorder::record`]. Each stage belongs to the phase that was current when it ended
//! ([`Recorder::phase`]); the time of a phase not covered by its stages is reported as its
//! stage `other`, so the stages of a phase always add up to the phase.
//!
//! A library run whose phases the binary does not see begin and end (a distributed search:
//! initialise and search inside one call) says where the next phase begins with a
//! `csm::stages` event carrying the field `phase` ([`Recorder::next_phase`]).
//!
//! Where the system counts them (Linux), every stage also has its minor page faults (field
//! `faults` of the libraries' events; the binary's own stages and `other` count them here):
//! those of the whole process while the stage ran, each a page of fresh memory touched for
//! the first time; and its CPU time (field `cpu_seconds`): every thread's of the process
//! while the stage ran, user and system. A stage that ran beside another on another thread
//! counts the other's too. On N threads, CPU time near N × the wall time says the threads
//! were busy throughout (a waiting thread that spins before it sleeps counts as busy); less
//! says they waited (a serial stretch, the end of a parallel pass).
//!
//! The file (`csm-profile/1`):
//! `{"format": "csm-profile/1", "threads": N, "phases": {"read": s, …, "total": s},
//!   "stages": [{"phase": "initialize", "stage": "normal check", "seconds": s, "faults": n,
//!   "cpu": s}, …]}` (`faults` and `cpu` where counted); under
//! `mpirun` also `"ranks": [{"read": s, "initialize": s, "search": s}, …]`, every rank's
//! phases in rank order (the file's phases and stages are rank 0's).

use std::sync::{Arc, Mutex, PoisonError};

use serde_json::{Value, json};
use tracing::field::{Field, Visit};
use tracing_subscriber::layer::{Context, Layer};

use crate::search::Usage;

/// One stage of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct StageTime {
    /// The phase it belongs to (`read`, `initialize`, `search`, `write`).
    pub phase: String,
    /// The stage's name (`normal check`, `mapping`, …; `other` for the rest of a phase).
    pub stage: String,
    /// Its wall time (s).
    pub seconds: f64,
    /// The process's minor page faults while it ran, where the system counts them.
    pub faults: Option<u64>,
    /// The process's CPU time while it ran (every thread's, s), where the system counts it.
    pub cpu_seconds: Option<f64>,
}

#[derive(Debug, Default)]
struct State {
    phase: String,
    /// When the current phase began ([`Recorder::phase`]).
    began: Option<std::time::Instant>,
    stages: Vec<StageTime>,
    phases: Vec<(String, f64)>,
    /// What the process had used (page faults, CPU time) when the current phase began.
    phase_usage: Usage,
    /// … when the binary's last stage of the phase ended ([`Recorder::record`]), or the
    /// phase began.
    record_usage: Usage,
}

impl State {
    /// Adds stage `stage` of the current phase.
    fn push(&mut self, stage: &str, seconds: f64, used: Usage) {
        self.stages.push(StageTime {
            phase: self.phase.clone(),
            stage: stage.to_owned(),
            seconds,
            faults: used.faults,
            cpu_seconds: used.cpu_seconds,
        });
    }
}

/// Keeps the stage times of a run (cloning shares the record).
#[derive(Debug, Clone, Default)]
pub struct Recorder {
    state: Arc<Mutex<State>>,
}

impl Recorder {
    /// An empty record.
    pub fn new() -> Recorder {
        Recorder::default()
    }

    fn with<T>(&self, f: impl FnOnce(&mut State) -> T) -> T {
        f(&mut self.state.lock().unwrap_or_else(PoisonError::into_inner))
    }

    /// Starts phase `name`: the stages that end from now on belong to it.
    pub fn phase(&self, name: &str) {
        let usage = Usage::now();
        self.with(|s| {
            s.phase = name.to_owned();
            s.began = Some(std::time::Instant::now());
            s.phase_usage = usage;
            s.record_usage = usage;
        });
    }

    /// Ends the current phase with the time since it began ([`Recorder::end_phase`]) and
    /// starts phase `name`: for a library that says where its phases meet (a `csm::stages`
    /// event with the field `phase`, [`Recorder::layer`]).
    pub fn next_phase(&self, name: &str) {
        self.end_current_phase();
        self.phase(name);
    }

    /// Ends the current phase with the time since it began.
    pub fn end_current_phase(&self) {
        let seconds = self.with(|s| s.began.map_or(0.0, |b| b.elapsed().as_secs_f64()));
        self.end_phase(seconds);
    }

    /// Ends the current phase, which took `seconds` in all: what its stages do not cover
    /// becomes its stage `other` (a phase without stages becomes one stage of its name).
    pub fn end_phase(&self, seconds: f64) {
        let now = Usage::now();
        self.with(|s| {
            let of_phase = || s.stages.iter().filter(|t| t.phase == s.phase);
            let covered: f64 = of_phase().map(|t| t.seconds).sum();
            // The phase's page faults and CPU time that none of its stages counted.
            let phase_used = now.since(s.phase_usage);
            let used = Usage {
                faults: phase_used.faults.map(|n| {
                    let counted: u64 = of_phase().filter_map(|t| t.faults).sum();
                    n.saturating_sub(counted)
                }),
                cpu_seconds: phase_used.cpu_seconds.map(|c| {
                    let counted: f64 = of_phase().filter_map(|t| t.cpu_seconds).sum();
                    (c - counted).max(0.0)
                }),
            };
            let phase = s.phase.clone();
            if covered == 0.0 {
                s.push(&phase, seconds, used);
            } else if seconds > covered {
                s.push("other", seconds - covered, used);
            }
            s.phases.push((phase, seconds));
        });
    }

    /// Records stage `stage` of the current phase, which ends now: its page faults and CPU
    /// time are those since the previous stage recorded here ended, or the phase began.
    pub fn record(&self, stage: &str, seconds: f64) {
        let now = Usage::now();
        self.with(|s| {
            let used = now.since(s.record_usage);
            s.record_usage = now;
            s.push(stage, seconds, used);
        });
    }

    /// Records stage `stage` of the current phase as a library reported it (its page faults
    /// and CPU time counted there).
    fn record_reported(&self, stage: &str, seconds: f64, used: Usage) {
        self.with(|s| s.push(stage, seconds, used));
    }

    /// The stages recorded so far, in the order they ended.
    pub fn stages(&self) -> Vec<StageTime> {
        self.with(|s| s.stages.clone())
    }

    /// The profile as `csm-profile/1` JSON (module docs); `total` is the whole run's time.
    pub fn to_json(&self, threads: usize, total: f64) -> Value {
        self.with(|s| {
            let mut phases = serde_json::Map::new();
            for (name, seconds) in &s.phases {
                let before = phases.get(name).and_then(Value::as_f64).unwrap_or(0.0);
                phases.insert(name.clone(), json!(before + seconds));
            }
            phases.insert("total".to_owned(), json!(total));
            json!({
                "format": "csm-profile/1",
                "threads": threads,
                "phases": phases,
                "stages": s.stages.iter().map(|t| {
                    let mut stage = json!({
                        "phase": t.phase, "stage": t.stage, "seconds": t.seconds
                    });
                    if let Some(faults) = t.faults {
                        stage["faults"] = json!(faults);
                    }
                    if let Some(cpu) = t.cpu_seconds {
                        stage["cpu"] = json!(cpu);
                    }
                    stage
                }).collect::<Vec<_>>(),
            })
        })
    }

    /// A subscriber layer recording the `csm::stages` events (give it a filter that lets
    /// them through: they are at level `debug`).
    pub fn layer(&self) -> StageLayer {
        StageLayer {
            recorder: self.clone(),
        }
    }
}

/// The layer of [`Recorder::layer`].
#[derive(Debug)]
pub struct StageLayer {
    recorder: Recorder,
}

/// The `stage`, `seconds`, `faults` and `cpu_seconds` fields of an event, or its `phase` (the
/// next phase begins).
#[derive(Default)]
struct StageFields {
    stage: Option<String>,
    seconds: Option<f64>,
    used: Usage,
    phase: Option<String>,
}

impl Visit for StageFields {
    fn record_u64(&mut self, field: &Field, value: u64) {
        if field.name() == "faults" {
            self.used.faults = Some(value);
        }
    }

    fn record_f64(&mut self, field: &Field, value: f64) {
        match field.name() {
            "seconds" => self.seconds = Some(value),
            "cpu_seconds" => self.used.cpu_seconds = Some(value),
            _ => {}
        }
    }

    fn record_str(&mut self, field: &Field, value: &str) {
        match field.name() {
            "stage" => self.stage = Some(value.to_owned()),
            "phase" => self.phase = Some(value.to_owned()),
            _ => {}
        }
    }

    fn record_debug(&mut self, _field: &Field, _value: &dyn std::fmt::Debug) {}
}

impl<S: tracing::Subscriber> Layer<S> for StageLayer {
    fn on_event(&self, event: &tracing::Event<'_>, _ctx: Context<'_, S>) {
        if event.metadata().target() != "csm::stages" {
            return;
        }
        let mut fields = StageFields::default();
        event.record(&mut fields);
        if let (Some(stage), Some(seconds)) = (fields.stage, fields.seconds) {
            (self.recorder).record_reported(&stage, seconds, fields.used);
        } else if let Some(phase) = fields.phase {
            self.recorder.next_phase(&phase);
        }
    }
}

#[cfg(test)]
mod tests;
