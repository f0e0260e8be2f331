//! The `csm` binary's log: `tracing` events written by `tracing-subscriber` to standard error
//! as `  0.012s  INFO message`. `RUST_LOG` picks what is printed, as env_logger reads it:
//! comma-separated directives, each a level (`error`, `warn` — the default —, `info`,
//! `debug`, `trace`, `off`) or `target=level` (`csm=info`, `csm::stages=debug`). The libraries
//! log only the stage trace (target `csm::stages`, `debug`: each stage's wall time and
//! memory); the facade logs the phases of a run at `info` and its settings at `debug`.

use std::io::IsTerminal as _;

use tracing_subscriber::filter::{LevelFilter, Targets};
use tracing_subscriber::fmt::time::Uptime;
use tracing_subscriber::prelude::*;

/// The filter a `RUST_LOG` value asks for: `warn` when unset, empty or not understood.
pub fn filter(rust_log: Option<&str>) -> Targets {
    let warn = || Targets::new().with_default(LevelFilter::WARN);
    match rust_log.map(str::trim) {
        None | Some("") => warn(),
        Some(value) => value.parse().unwrap_or_else(|_| warn()),
    }
}

/// Installs the log for the environment variable `RUST_LOG` (once; later calls do nothing).
pub fn init_from_env() {
    let value = std::env::var("RUST_LOG").ok();
    let layer = tracing_subscriber::fmt::layer()
        .with_writer(std::io::stderr)
        .with_timer(Uptime::default())
        .with_target(false)
        .with_ansi(std::io::stderr().is_terminal());
    let _ = tracing_subscriber::registry()
        .with(layer.with_filter(filter(value.as_deref())))
        .try_init();
}

#[cfg(test)]
mod tests;
