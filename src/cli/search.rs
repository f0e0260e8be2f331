//! `csm search`: read a mesh and a setup, run the search (one step, or every step of the
//! setup's `steps`), report RESULT.json; and
//! `csm plan`, which reads them the same way and says what the search would run.

use std::path::Path;
use std::time::Instant;

use csm_model::ModelPart;
use csm_search::{ContactSearch, Plan, SearchResult, SearchSetup, StepResult, parse_setup};

use crate::cli::profile::Recorder;
use crate::cli::progress::Progress;

/// Wall times of the phases of a run, in seconds (RESULT.json `timings_s`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timings {
    /// Parsing the mesh.
    pub read: f64,
    /// Everything before the search step (contact parts, NODAL_H, …).
    pub initialize: f64,
    /// The search step (Kratos' ExecuteInitializeSolutionStep); with `steps`, the sum over
    /// the steps (each step's own time is in its RESULT.json entry).
    pub search: f64,
    /// From the start of reading to the end of the (last) search, the motion and the
    /// finalization between steps included.
    pub total: f64,
}

impl Timings {
    /// As `(key, seconds)` pairs in the contract's order.
    pub fn entries(&self) -> [(&'static str, f64); 4] {
        [
            ("read", self.read),
            ("initialize", self.initialize),
            ("search", self.search),
            ("total", self.total),
        ]
    }
}

/// The setup used without `--setup`: the parts named `slave` and `master` (any case), the
/// default parameters.
pub fn default_setup(model: &ModelPart) -> Result<SearchSetup, String> {
    let find = |name: &str| {
        let found: Vec<&str> = model
            .part_paths()
            .into_iter()
            .filter(|p| p.eq_ignore_ascii_case(name))
            .collect();
        match found.as_slice() {
            [one] => Ok((*one).to_owned()),
            [] => Err(format!(
                "no part named `{name}` (any case); the parts are: {} — give a setup with \
                 --setup",
                model.part_paths().join(", ")
            )),
            _ => Err(format!(
                "several parts are named `{name}` (any case): {}",
                found.join(", ")
            )),
        }
    };
    let (slave, master) = (find("slave")?, find("master")?);
    let text = serde_json::json!({
        "contact_model_part": {"0": [slave, master]},
        "assume_master_slave": {"0": [slave]},
    })
    .to_string();
    parse_setup(&text, "<default setup>").map_err(|e| e.to_string())
}

/// Parses setup text (`file` names it in errors).
pub fn load_setup(text: &str, file: &str) -> Result<SearchSetup, String> {
    parse_setup(text, file).map_err(|e| e.to_string())
}

/// The setup of `csm search` and `csm plan`: the file at `path` (`--setup`), else
/// [`default_setup`].
pub fn setup_for(path: Option<&Path>, model: &ModelPart) -> Result<SearchSetup, String> {
    match path {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            load_setup(&text, &path.display().to_string())
        }
        None => default_setup(model),
    }
}

/// `csm plan`: what a search of `model` with `setup` will run and build, and why the rest is
/// left out ([`Plan::new`]; the same plan [`ContactSearch::initialize`] follows).
pub fn search_plan(model: &ModelPart, setup: &SearchSetup) -> Result<Plan, String> {
    Plan::new(model, setup).map_err(|e| e.to_string())
}

/// How [`run_search_with`] reports while it runs.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Draw a progress line on standard error for phases longer than [`Progress::DELAY`]
    /// (see [`progress_wanted`](crate::cli::progress_wanted)).
    pub progress: bool,
    /// Record the phases `initialize` and `search` and their stages (`--profile`).
    pub profile: Option<Recorder>,
}

/// Runs initialize + one search step on `model` (or, when the setup has `steps`, every step:
/// motion, search, and ExecuteFinalizeSolutionStep before the next one); `read` is the time the
/// mesh took to read. With steps the result is that of the last step, with every step's in
/// [`SearchResult::steps`].
pub fn run_search(
    model: &mut ModelPart,
    setup: &SearchSetup,
    read: f64,
) -> Result<(SearchResult, Timings), String> {
    run_search_with(model, setup, read, RunOptions::default())
}

/// [`run_search`] with a progress line and the phases logged at `info` (`RUST_LOG`).
pub fn run_search_with(
    model: &mut ModelPart,
    setup: &SearchSetup,
    read: f64,
    options: RunOptions,
) -> Result<(SearchResult, Timings), String> {
    tracing::debug!(target: "csm",
        "setup: pairs {:?}, compatibility {:?}, {} rayon threads",
        setup.pairs.keys().collect::<Vec<_>>(),
        setup.compatibility,
        rayon::current_num_threads()
    );
    let profile = options.profile.as_ref();
    let start = Instant::now();
    if let Some(p) = profile {
        p.phase("initialize");
    }
    let progress = Progress::start("initializing", options.progress);
    let search = ContactSearch::initialize(model, setup);
    progress.finish();
    let mut search = search.map_err(|e| e.to_string())?;
    let initialize = start.elapsed().as_secs_f64();
    if let Some(p) = profile {
        p.end_phase(initialize);
    }
    tracing::info!(target: "csm",
        "initialize: {initialize:.3} s ({} nodes, {} conditions after the interface generation)",
        model.nodes().len(),
        model.conditions().len()
    );
    let start = Instant::now();
    if let Some(p) = profile {
        p.phase("search");
    }
    let mut search_time = 0.0;
    let result = if setup.steps.is_empty() {
        let progress = Progress::start("searching", options.progress);
        let result = search.step(model);
        progress.finish();
        search_time = start.elapsed().as_secs_f64();
        let result = result.map_err(|e| e.to_string())?;
        log_step(None, search_time, &result);
        result
    } else {
        let n = setup.steps.len();
        let mut steps: Vec<StepResult> = Vec::with_capacity(n);
        for (k, step_setup) in setup.steps.iter().enumerate() {
            let step = k as u32 + 1;
            if k > 0 {
                search.finalize_step(model).map_err(|e| e.to_string())?;
            }
            search
                .advance(model, step_setup)
                .map_err(|e| e.to_string())?;
            let step_start = Instant::now();
            let progress =
                Progress::start(&format!("searching, step {step}/{n}"), options.progress);
            let result = search.step(model);
            progress.finish();
            let search_s = step_start.elapsed().as_secs_f64();
            let result = result.map_err(|e| e.to_string())?;
            log_step(Some(step), search_s, &result);
            search_time += search_s;
            steps.push(StepResult {
                step,
                result,
                search_s,
            });
        }
        let mut last = steps.last().map(|s| s.result.clone()).unwrap_or_default();
        last.steps = steps;
        last
    };
    let searching = start.elapsed().as_secs_f64();
    if let Some(p) = profile {
        p.end_phase(searching);
    }
    let timings = Timings {
        read,
        initialize,
        search: search_time,
        total: read + initialize + searching,
    };
    Ok((result, timings))
}

fn log_step(step: Option<u32>, seconds: f64, result: &SearchResult) {
    let label = step.map_or(String::new(), |k| format!(" (step {k})"));
    tracing::info!(target: "csm",
        "search{label}: {seconds:.3} s; {} slave conditions, {} pairs, {} paired conditions, {} \
         active nodes, {} warnings",
        result.pairs.values().map(|m| m.len()).sum::<usize>(),
        result.n_pairs(),
        result.paired_conditions,
        result.nodes.values().filter(|n| n.active).count(),
        result.warnings.len()
    );
}
