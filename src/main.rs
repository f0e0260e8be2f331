//! The `csm` command-line tool. See `csm --help` and `docs/ARCHITECTURE.md`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};
use csm::cli::profile::Recorder;
use csm::cli::{Progress, ReportText as _, RunOptions, logger};

#[derive(Debug, Parser)]
#[command(name = "csm", version, about = "Finite-element contact search")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Build the embedded demo scene (a sphere pressed onto a plate), search it, print a
    /// summary and write RESULT.json and demo.vtu.
    Demo {
        /// About how many contact faces (plate and sphere together).
        #[arg(long, default_value_t = csm::cli::DEFAULT_FACES)]
        faces: usize,
        /// The folder to write RESULT.json and demo.vtu into (created if missing).
        #[arg(
            short = 'o',
            long = "output",
            value_name = "DIR",
            default_value = "csm-demo"
        )]
        output: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Print nothing but errors.
        #[arg(long)]
        quiet: bool,
        /// Also write the full error-vs-run-time report of the scene (report.md,
        /// report.svg, as `csm report`).
        #[arg(long)]
        report: bool,
        /// Write demo.vtu's arrays as text (for diffs) instead of raw binary data.
        #[arg(long)]
        vtk_ascii: bool,
        /// Also write the wall time of every stage as JSON (`csm-profile/1`, as `csm search
        /// --profile`): building the scene is the phase `read`, the sampled ground truth the
        /// phase `truth`.
        #[arg(long, value_name = "PROFILE.json")]
        profile: Option<PathBuf>,
    },
    /// Print which stages will run and which structures will be built or allocated for a
    /// mesh and a setup, and why each other one is left out. Reads the mesh and the setup as
    /// `csm search` does; runs nothing.
    Plan {
        /// The mesh: a Kratos `.mdpa` or a Gmsh `.msh`.
        mesh: PathBuf,
        /// The setup, as for `csm search` (default: the parts `slave` and `master`).
        #[arg(long)]
        setup: Option<PathBuf>,
        /// Print JSON ({"format": "csm-plan/1", "initialize", "variables", "pairs"}).
        #[arg(long)]
        json: bool,
    },
    /// Print the parts of a mesh (full paths) with node/element/condition counts and geometry types.
    Info {
        /// The mesh: a Kratos `.mdpa` or a Gmsh `.msh` (2.2 or 4.1, ASCII or binary).
        mesh: PathBuf,
        /// Print JSON: {"nodes", "elements", "conditions", "parts": {"<path>": {...}}}.
        #[arg(long)]
        json: bool,
        /// Report only this part (full path, `.` or `/` separated).
        #[arg(long)]
        part: Option<String>,
    },
    /// Measure every search strategy against the exact ground truth: missed true pairs,
    /// spurious candidates, wrong ACTIVE flags, gap error and search time, for every
    /// type_search × Simple/Advanced × search_factor (× bounding_box_factor) × kratos/robust;
    /// writes report.md and report.svg (docs/report.md explains the metrics).
    Report {
        /// The mesh: a Kratos `.mdpa` or a Gmsh `.msh`.
        mesh: PathBuf,
        /// The setup, as for `csm search` (default: the parts `slave` and `master`).
        #[arg(long)]
        setup: Option<PathBuf>,
        /// The folder to write report.md and report.svg into (created if missing).
        #[arg(
            short = 'o',
            long = "output",
            value_name = "DIR",
            default_value = "csm-report"
        )]
        output: PathBuf,
        /// Above this many faces per side, the ground truth uses a seeded random sample of
        /// the slave faces (all masters).
        #[arg(long, default_value_t = 20_000)]
        sample_limit: usize,
        /// How many slave faces the sample holds.
        #[arg(long, default_value_t = 2_000)]
        sample_size: usize,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Print nothing but errors.
        #[arg(long)]
        quiet: bool,
    },
    /// Run the contact search (one step, or every step of the setup's `steps`) and write
    /// RESULT.json.
    Search {
        /// The mesh: a Kratos `.mdpa` or a Gmsh `.msh`.
        mesh: PathBuf,
        /// The setup: the Parameters of a Kratos contact process, or a ProjectParameters
        /// file. Without it, the parts named `slave` and `master` are used with the defaults.
        #[arg(long)]
        setup: Option<PathBuf>,
        /// Where to write RESULT.json (default: standard output).
        #[arg(short = 'o', long = "output")]
        output: Option<PathBuf>,
        /// Also write the mesh, the contact flags and the pairs (as lines between the
        /// condition centres) as a VTK file for ParaView.
        #[arg(long, value_name = "OUT.vtu")]
        vtk: Option<PathBuf>,
        /// Write the VTK file's arrays as text (for diffs) instead of raw binary data.
        #[arg(long, requires = "vtk")]
        vtk_ascii: bool,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Also write the wall time of every stage (read, initialize, search, write) as
        /// JSON, with its page faults and CPU time on Linux (`csm-profile/1`; under `mpirun`,
        /// rank 0's stages and every rank's phases).
        #[arg(long, value_name = "PROFILE.json")]
        profile: Option<PathBuf>,
        /// Print nothing but errors.
        #[arg(long)]
        quiet: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let profile = match &cli.command {
        Command::Search {
            profile: Some(_), ..
        }
        | Command::Demo {
            profile: Some(_), ..
        } => Some(Recorder::new()),
        _ => None,
    };
    logger::init_from_env(profile.as_ref());
    match run(cli, profile) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli, recorder: Option<Recorder>) -> Result<(), String> {
    match cli.command {
        Command::Info { mesh, json, part } => {
            let model = csm::io::read_mesh(&mesh).map_err(|e| e.to_string())?;
            let mut info = csm::cli::mesh_info(&model);
            if let Some(path) = part {
                info = info.only_part(&path).ok_or_else(|| {
                    format!(
                        "{}: no sub model part `{path}`; the parts are: {}",
                        mesh.display(),
                        info.parts.keys().cloned().collect::<Vec<_>>().join(", ")
                    )
                })?;
            }
            if json {
                let text = serde_json::to_string_pretty(&info.to_json())
                    .map_err(|e| format!("cannot format JSON: {e}"))?;
                out(&format!("{text}\n"))?;
            } else {
                out(&info.to_text(&mesh.display().to_string()))?;
            }
            Ok(())
        }
        Command::Search {
            mesh,
            setup,
            output,
            vtk,
            vtk_ascii,
            threads,
            profile,
            quiet,
        } => {
            start_threads(threads)?;
            #[cfg(feature = "mpi")]
            if csm::distributed::MpiTransport::launched() {
                let files = (mesh.as_path(), setup.as_deref(), output.as_deref());
                let profile = profile.as_deref().zip(recorder.as_ref());
                return search_on_ranks(files, (vtk.is_some(), profile), quiet);
            }
            let start = Instant::now();
            let phase = |name: &str| {
                if let Some(r) = &recorder {
                    r.phase(name);
                }
            };
            let end_phase = |seconds: f64| {
                if let Some(r) = &recorder {
                    r.end_phase(seconds);
                }
            };
            phase("read");
            let progress = Progress::start("reading", csm::cli::progress_wanted(quiet));
            let model = csm::io::read_mesh(&mesh);
            progress.finish();
            let mut model = model.map_err(|e| e.to_string())?;
            let read = start.elapsed().as_secs_f64();
            end_phase(read);
            tracing::info!(target: "csm",
                "read {}: {read:.3} s; {} nodes, {} elements, {} conditions, {} parts",
                mesh.display(),
                model.nodes().len(),
                model.elements().len(),
                model.conditions().len(),
                model.parts().len()
            );
            let setup = csm::cli::setup_for(setup.as_deref(), &model)?;
            let options = RunOptions {
                progress: csm::cli::progress_wanted(quiet),
                profile: recorder.clone(),
            };
            let (result, timings) = csm::cli::run_search_with(&mut model, &setup, read, options)?;
            let writing = Instant::now();
            phase("write");
            match &output {
                Some(path) => write_result(path, &result, &timings)?,
                None => out(&result_json(&result, &timings)?)?,
            }
            if let Some(r) = &recorder {
                r.record("RESULT.json", writing.elapsed().as_secs_f64());
            }
            if let Some(path) = &vtk {
                let vtu = Instant::now();
                csm::cli::write_search_vtu(&model, &result, path, vtu_format(vtk_ascii))?;
                if let Some(r) = &recorder {
                    r.record("VTU", vtu.elapsed().as_secs_f64());
                }
                tracing::info!(target: "csm", "wrote {}", path.display());
            }
            end_phase(writing.elapsed().as_secs_f64());
            write_profile(profile.as_deref(), recorder.as_ref(), start)?;
            if !quiet {
                let steps = match result.steps.len() {
                    0 => String::new(),
                    n => format!("{n} steps; after the last: "),
                };
                summary(&result, &timings, (&steps, ""));
            }
            // The process ends here and gives its memory back whole: freeing the model's and
            // the result's allocations one by one would take one thread several milliseconds
            // (1e5 faces) for nothing.
            std::mem::forget(model);
            std::mem::forget(result);
            Ok(())
        }
        Command::Plan { mesh, setup, json } => {
            let model = csm::io::read_mesh(&mesh).map_err(|e| e.to_string())?;
            let setup = csm::cli::setup_for(setup.as_deref(), &model)?;
            let plan = csm::cli::search_plan(&model, &setup)?;
            if json {
                let text = serde_json::to_string_pretty(&plan.to_json())
                    .map_err(|e| format!("cannot format JSON: {e}"))?;
                out(&format!("{text}\n"))?;
            } else {
                out(&plan.to_string())?;
            }
            for w in &setup.warnings {
                eprintln!("warning: {w}");
            }
            Ok(())
        }
        Command::Report {
            mesh,
            setup,
            output,
            sample_limit,
            sample_size,
            threads,
            quiet,
        } => {
            start_threads(threads)?;
            let model = csm::io::read_mesh(&mesh).map_err(|e| e.to_string())?;
            let setup = csm::cli::setup_for(setup.as_deref(), &model)?;
            let defaults = csm::cli::ReportOptions::default();
            let options = csm::cli::ReportOptions {
                sample_limit,
                sample: csm::eval::Sample {
                    size: sample_size,
                    ..defaults.sample
                },
                ..defaults
            };
            let name = mesh.file_name().map_or_else(
                || mesh.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            measure_report(&model, &setup, &name, &options, &output, quiet)
        }
        Command::Demo {
            faces,
            output,
            threads,
            quiet,
            report,
            vtk_ascii,
            profile,
        } => {
            start_threads(threads)?;
            let start = Instant::now();
            if let Some(r) = &recorder {
                r.phase("read");
            }
            let progress = Progress::start("building the scene", csm::cli::progress_wanted(quiet));
            let scene = csm::cli::demo_scene(faces);
            progress.finish();
            let mut scene = scene?;
            let read = start.elapsed().as_secs_f64();
            if let Some(r) = &recorder {
                r.end_phase(read);
            }
            tracing::info!(target: "csm",
                "built the demo scene: {read:.3} s; {} nodes, {} elements, {} slave and {} \
                 master faces",
                scene.model.nodes().len(),
                scene.model.elements().len(),
                scene.n_slave_faces,
                scene.n_master_faces
            );
            let setup = csm::cli::default_setup(&scene.model)?;
            let options = RunOptions {
                progress: csm::cli::progress_wanted(quiet),
                profile: recorder.clone(),
            };
            let pristine = scene.model.clone();
            let (result, timings) =
                csm::cli::run_search_with(&mut scene.model, &setup, read, options)?;
            let truth_start = Instant::now();
            if let Some(r) = &recorder {
                r.phase("truth");
            }
            let progress = Progress::start("ground truth", csm::cli::progress_wanted(quiet));
            // The truth searches the pristine scene itself, or a copy where the report needs
            // it after.
            let (scene_before, pristine) = if report {
                (pristine.clone(), Some(pristine))
            } else {
                (pristine, None)
            };
            let truth = csm::cli::demo_truth(scene_before, &setup, &result);
            progress.finish();
            let truth = truth?;
            if let Some(r) = &recorder {
                r.end_phase(truth_start.elapsed().as_secs_f64());
                r.phase("write");
            }
            std::fs::create_dir_all(&output)
                .map_err(|e| format!("{}: cannot create the folder: {e}", output.display()))?;
            let json_path = output.join("RESULT.json");
            let writing = Instant::now();
            write_result(&json_path, &result, &timings)?;
            let json_s = writing.elapsed().as_secs_f64();
            // (Each stage recorded as it ends: its page faults are counted up to then.)
            if let Some(r) = &recorder {
                r.record("RESULT.json", json_s);
            }
            let vtu_path = output.join("demo.vtu");
            let vtu_start = Instant::now();
            csm::cli::write_search_vtu(&scene.model, &result, &vtu_path, vtu_format(vtk_ascii))?;
            let vtu_s = vtu_start.elapsed().as_secs_f64();
            if let Some(r) = &recorder {
                r.record("VTU", vtu_s);
                r.end_phase(writing.elapsed().as_secs_f64());
            }
            write_profile(profile.as_deref(), recorder.as_ref(), start)?;
            if !quiet {
                print!("{}", csm::cli::demo_summary(&scene, &result, &timings));
                print!("{}", truth.line());
                println!(
                    "wrote {} ({json_s:.3} s) and {} ({vtu_s:.3} s; open it in ParaView)",
                    json_path.display(),
                    vtu_path.display()
                );
            }
            if let Some(pristine) = pristine {
                let options = csm::cli::ReportOptions::default();
                measure_report(&pristine, &setup, "demo scene", &options, &output, quiet)?;
            }
            Ok(())
        }
    }
}

/// Writes the profile `recorder` kept into `path` (`--profile`), with the whole run's time
/// counted from `start`.
fn write_profile(
    path: Option<&Path>,
    recorder: Option<&Recorder>,
    start: Instant,
) -> Result<(), String> {
    if let (Some(path), Some(r)) = (path, recorder) {
        let json = r.to_json(rayon::current_num_threads(), start.elapsed().as_secs_f64());
        write_json(path, &json)?;
    }
    Ok(())
}

/// Writes `json` into `path`, pretty-printed, with a final newline.
fn write_json(path: &Path, json: &serde_json::Value) -> Result<(), String> {
    let text =
        serde_json::to_string_pretty(json).map_err(|e| format!("cannot format JSON: {e}"))?;
    std::fs::write(path, text + "\n").map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Runs the error-vs-run-time report (with progress), writes it into `output` and, unless
/// `quiet`, prints its summary.
fn measure_report(
    model: &csm::model::ModelPart,
    setup: &csm::search::SearchSetup,
    name: &str,
    options: &csm::cli::ReportOptions,
    output: &Path,
    quiet: bool,
) -> Result<(), String> {
    let progress = Progress::start("measuring", csm::cli::progress_wanted(quiet));
    let report = csm::cli::run_report(model, setup, name, options);
    progress.finish();
    let report = report?;
    let paths = write_report(&report, output)?;
    if !quiet {
        print!("{}", report.summary());
        println!("wrote {} and {}", paths.0.display(), paths.1.display());
    }
    Ok(())
}

/// Writes `report.md` and `report.svg` into `dir` (created if missing).
fn write_report(report: &csm::cli::Report, dir: &Path) -> Result<(PathBuf, PathBuf), String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
    let md = dir.join("report.md");
    let svg = dir.join("report.svg");
    write(&md, report.to_markdown())?;
    write(&svg, report.to_svg())?;
    Ok((md, svg))
}

/// The VTU form `--vtk-ascii` asks for.
fn vtu_format(ascii: bool) -> csm::io::VtuFormat {
    if ascii {
        csm::io::VtuFormat::Ascii
    } else {
        csm::io::VtuFormat::Binary
    }
}

/// Sizes rayon's global pool (`--threads`); all cores when `None`.
/// `csm search` started by `mpirun`: every rank reads the mesh and the setup, searches its
/// part (`csm::distributed::search_rank_timed`), and rank 0 writes RESULT.json and the
/// summary. Any rank's error stops every rank with the lowest failed rank's message.
#[cfg(feature = "mpi")]
fn search_on_ranks(
    (mesh, setup, output): (&Path, Option<&Path>, Option<&Path>),
    (vtk_asked, profile): (bool, Option<(&Path, &Recorder)>),
    quiet: bool,
) -> Result<(), String> {
    use std::sync::Arc;
    let transport: Arc<dyn csm::model::Transport> =
        Arc::new(csm::distributed::MpiTransport::start()?);
    let start = Instant::now();
    let recorder = profile.map(|(_, r)| r);
    if let Some(r) = recorder {
        r.phase("read");
    }
    let input = if vtk_asked {
        Err("--vtk: a distributed run does not write it yet".to_owned())
    } else {
        csm::io::read_mesh(mesh)
            .map_err(|e| e.to_string())
            .and_then(|model| Ok((model.to_arrays(), csm::cli::setup_for(setup, &model)?)))
    };
    let read = start.elapsed().as_secs_f64();
    if let Some(r) = recorder {
        r.end_phase(read);
        // The distributed search says where its search phase begins.
        r.phase("initialize");
    }
    let outcome = match &input {
        Ok((arrays, setup)) => {
            csm::distributed::search_rank_timed(Arc::clone(&transport), arrays, setup)
        }
        Err(message) => Err(csm::distributed::fail_rank(Arc::clone(&transport), message)),
    };
    if let Err(e) = &outcome {
        // Every rank prints the error, in one write (mpirun forwards the ranks' output
        // together: a line written in pieces would interleave with the others'), then waits
        // for the others to have printed theirs: mpirun stops the whole job at the first
        // non-zero exit, which could cut a rank that had not printed yet.
        let line = format!("error: {e}\n");
        let _ = std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes());
        transport.all_gather(&[]);
        drop(transport);
        std::process::exit(1);
    }
    if let Some(r) = recorder {
        r.end_current_phase();
    }
    // Every rank's phase times, on every rank (every rank that got here takes part, profile
    // or not, so that the ranks stay in step).
    let (result, times) = outcome.map_err(|e| e.to_string())?;
    let mine: Vec<u8> = [read, times.initialize, times.search]
        .iter()
        .flat_map(|t| t.to_le_bytes())
        .collect();
    let every_rank = transport.all_gather(&mine);
    // The last handle: MPI is finalised here, before the process ends.
    drop(transport);
    let Some(result) = result else {
        return Ok(());
    };
    let timings = csm::cli::Timings {
        read,
        initialize: times.initialize,
        search: times.search,
        total: start.elapsed().as_secs_f64(),
    };
    let writing = Instant::now();
    if let Some(r) = recorder {
        r.phase("write");
    }
    match output {
        Some(path) => write_result(path, &result, &timings)?,
        None => out(&result_json(&result, &timings)?)?,
    }
    if let Some((path, r)) = profile {
        r.record("RESULT.json", writing.elapsed().as_secs_f64());
        r.end_phase(writing.elapsed().as_secs_f64());
        let mut json = r.to_json(rayon::current_num_threads(), start.elapsed().as_secs_f64());
        json["ranks"] = rank_times(&every_rank).into();
        write_json(path, &json)?;
    }
    if !quiet {
        summary(&result, &timings, ("", " (rank 0)"));
    }
    Ok(())
}

/// Every rank's phase times (`read`, `initialize`, `search`: three little-endian `f64`
/// each, in rank order) as the profile's `ranks` list.
#[cfg(feature = "mpi")]
fn rank_times(every_rank: &[Vec<u8>]) -> Vec<serde_json::Value> {
    every_rank
        .iter()
        .map(|bytes| {
            let at = |k: usize| {
                (bytes.get(8 * k..8 * k + 8))
                    .and_then(|b| <[u8; 8]>::try_from(b).ok())
                    .map_or(f64::NAN, f64::from_le_bytes)
            };
            serde_json::json!({"read": at(0), "initialize": at(1), "search": at(2)})
        })
        .collect()
}

/// `csm search`'s summary on standard error: the counts, the times (`before` and `after`
/// them), the warnings.
fn summary(
    result: &csm::search::SearchResult,
    timings: &csm::cli::Timings,
    (before, after): (&str, &str),
) {
    eprintln!(
        "{before}{} slave conditions, {} pairs, {} paired conditions; read {:.3} s, initialize \
         {:.3} s, search {:.3} s{after}",
        result.pairs.values().map(|m| m.len()).sum::<usize>(),
        result.n_pairs(),
        result.paired_conditions,
        timings.read,
        timings.initialize,
        timings.search
    );
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
}

fn start_threads(threads: Option<usize>) -> Result<(), String> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build_global()
            .map_err(|e| format!("cannot start {n} threads: {e}"))?;
    }
    Ok(())
}

/// RESULT.json text, with a final newline.
fn result_json(
    result: &csm::search::SearchResult,
    timings: &csm::cli::Timings,
) -> Result<String, String> {
    let mut text = Vec::new();
    result
        .write_json(&timings.entries(), &mut text)
        .map_err(|e| format!("cannot format JSON: {e}"))?;
    String::from_utf8(text).map_err(|e| format!("cannot format JSON: {e}"))
}

/// Streams RESULT.json to `path` (no copy of the whole text in memory; written a megabyte at
/// a time).
fn write_result(
    path: &Path,
    result: &csm::search::SearchResult,
    timings: &csm::cli::Timings,
) -> Result<(), String> {
    use std::io::Write;
    let file = std::fs::File::create(path)
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    let mut writer = std::io::BufWriter::with_capacity(1 << 20, file);
    result
        .write_json(&timings.entries(), &mut writer)
        .and_then(|()| writer.flush())
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Writes `text` to standard output; a closed pipe (`csm plan … | head`) ends the output
/// quietly instead of panicking as `print!` does.
fn out(text: &str) -> Result<(), String> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write to standard output: {e}"))
        }
        _ => Ok(()),
    }
}

fn write(path: &Path, text: String) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}
