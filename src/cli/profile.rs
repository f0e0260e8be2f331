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
//! The file (`csm-profile/1`):
//! `{"format": "csm-profile/1", "threads": N, "phases": {"read": s, …, "total": s},
//!   "stages": [{"phase": "initialize", "stage": "normal check", "seconds": s}, …]}`; under
//! `mpirun` also `"ranks": [{"read": s, "initialize": s, "search": s}, …]`, every rank's
//! phases in rank order (the file's phases and stages are rank 0's).

use std::sync::{Arc, Mutex, PoisonError};

use serde_json::{Value, json};
use tracing::field::{Field, Visit};
use tracing_subscriber::layer::{Context, Layer};

/// One stage of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct StageTime {
    /// The phase it belongs to (`read`, `initialize`, `search`, `write`).
    pub phase: String,
    /// The stage's name (`normal check`, `mapping`, …; `other` for the rest of a phase).
    pub stage: String,
    /// Its wall time (s).
    pub seconds: f64,
}

#[derive(Debug, Default)]
struct State {
    phase: String,
    /// When the current phase began ([`Recorder::phase`]).
    began: Option<std::time::Instant>,
    stages: Vec<StageTime>,
    phases: Vec<(String, f64)>,
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
        self.with(|s| {
            s.phase = name.to_owned();
            s.began = Some(std::time::Instant::now());
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
        self.with(|s| {
            let covered: f64 = s
                .stages
                .iter()
                .filter(|t| t.phase == s.phase)
                .map(|t| t.seconds)
                .sum();
            let phase = s.phase.clone();
            if covered == 0.0 {
                s.stages.push(StageTime {
                    phase: phase.clone(),
                    stage: phase.clone(),
                    seconds,
                });
            } else if seconds > covered {
                s.stages.push(StageTime {
                    phase: phase.clone(),
                    stage: "other".to_owned(),
                    seconds: seconds - covered,
                });
            }
            s.phases.push((phase, seconds));
        });
    }

    /// Records stage `stage` of the current phase.
    pub fn record(&self, stage: &str, seconds: f64) {
        self.with(|s| {
            let phase = s.phase.clone();
            s.stages.push(StageTime {
                phase,
                stage: stage.to_owned(),
                seconds,
            });
        });
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
                "stages": s.stages.iter().map(|t| json!({
                    "phase": t.phase, "stage": t.stage, "seconds": t.seconds
                })).collect::<Vec<_>>(),
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

/// The `stage` and `seconds` fields of an event, or its `phase` (the next phase begins).
#[derive(Default)]
struct StageFields {
    stage: Option<String>,
    seconds: Option<f64>,
    phase: Option<String>,
}

impl Visit for StageFields {
    fn record_f64(&mut self, field: &Field, value: f64) {
        if field.name() == "seconds" {
            self.seconds = Some(value);
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
            self.recorder.record(&stage, seconds);
        } else if let Some(phase) = fields.phase {
            self.recorder.next_phase(&phase);
        }
    }
}

#[cfg(test)]
mod tests;
