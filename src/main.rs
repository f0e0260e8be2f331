//! The `csm` command-line tool. See `csm --help` and `docs/ARCHITECTURE.md`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Debug, Parser)]
#[command(name = "csm", version, about = "Finite-element contact search")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
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
    /// Run the contact search (one step) and write RESULT.json.
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
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Print nothing but errors.
        #[arg(long)]
        quiet: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
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
                println!("{text}");
            } else {
                print!("{}", info.to_text(&mesh.display().to_string()));
            }
            Ok(())
        }
        Command::Search { mesh, setup, output, threads, quiet } => {
            if let Some(n) = threads {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n.max(1))
                    .build_global()
                    .map_err(|e| format!("cannot start {n} threads: {e}"))?;
            }
            let start = std::time::Instant::now();
            let mut model = csm::io::read_mesh(&mesh).map_err(|e| e.to_string())?;
            let read = start.elapsed().as_secs_f64();
            let setup = match &setup {
                Some(path) => {
                    let text = std::fs::read_to_string(path)
                        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
                    csm::cli::load_setup(&text, &path.display().to_string())?
                }
                None => csm::cli::default_setup(&model)?,
            };
            let (result, timings) = csm::cli::run_search(&mut model, &setup, read)?;
            let json = serde_json::to_string_pretty(&result.to_json(&timings.entries()))
                .map_err(|e| format!("cannot format JSON: {e}"))?;
            match &output {
                Some(path) => std::fs::write(path, json + "\n")
                    .map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
                None => println!("{json}"),
            }
            if !quiet {
                eprintln!(
                    "{} slave conditions, {} pairs, {} paired conditions; read {:.3} s, \
                     initialize {:.3} s, search {:.3} s",
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
            Ok(())
        }
    }
}
