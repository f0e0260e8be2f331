//! The `csm` binary's log: `tracing` events written by `tracing-subscriber` to standard error
//! as `  0.012s  INFO message`. `RUST_LOG` picks what is printed, as env_logger reads it:
//! comma-separated directives, each a level (`error`, `warn` — the default —, `info`,
//! `debug`, `trace`, `off`) or `target=level` (`csm=info`, `csm::stages=debug`). The libraries
//! log only the stage trace (target `csm::stages`, `debug`: each stage's wall time and
//! memory); the facade logs the phases of a run at `info` and its settings at `debug`. Only
//! the messages are printed: the stage trace's fields (`stage`, `seconds`) are for
//! `--profile` ([`crate::cli::profile`]).

use std::io::IsTerminal as _;

use tracing_subscriber::filter::{LevelFilter, Targets};
use tracing_subscriber::fmt::format::debug_fn;
use tracing_subscriber::fmt::time::Uptime;
use tracing_subscriber::prelude::*;

use crate::cli::profile::Recorder;

/// The filter a `RUST_LOG` value asks for: `warn` when unset, empty or not understood.
pub fn filter(rust_log: Option<&str>) -> Targets {
    let warn = || Targets::new().with_default(LevelFilter::WARN);
    match rust_log.map(str::trim) {
        None | Some("") => warn(),
        Some(value) => value.parse().unwrap_or_else(|_| warn()),
    }
}

/// Installs the log for the environment variable `RUST_LOG` (once; later calls do nothing),
/// and with `profile` the recording of the stage trace into it, whatever `RUST_LOG` says.
pub fn init_from_env(profile: Option<&Recorder>) {
    let value = std::env::var("RUST_LOG").ok();
    let layer = tracing_subscriber::fmt::layer()
        .with_writer(std::io::stderr)
        .with_timer(Uptime::default())
        .with_target(false)
        .fmt_fields(debug_fn(|writer, field, value| {
            if field.name() == "message" {
                write!(writer, "{value:?}")
            } else {
                Ok(())
            }
        }))
        .with_ansi(std::io::stderr().is_terminal());
    let stages = Targets::new().with_target("csm::stages", LevelFilter::DEBUG);
    let _ = tracing_subscriber::registry()
        .with(layer.with_filter(filter(value.as_deref())))
        .with(profile.map(|r| r.layer().with_filter(stages)))
        .try_init();
}

#[cfg(test)]
mod tests;
