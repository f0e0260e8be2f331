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
    }
}
