//! A minimal logger for the `csm` binary: `RUST_LOG` picks the level (`error`, `warn` — the
//! default —, `info`, `debug`; `trace` counts as `debug`, `off` silences it), messages go to
//! standard error as `[  0.012 s INFO ] message`.
//!
//! `RUST_LOG` is read as env_logger reads it, simplified: comma-separated directives, each a
//! level or `target=level`; directives for targets other than `csm…` are ignored, the last
//! one that applies wins. The libraries never log; the facade logs the phases of a run.

use std::fmt;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};
use std::time::Instant;

/// How important a message is; a logger at level `L` prints messages of `L` and above.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// Nothing is printed (`RUST_LOG=off`); never used for a message.
    Off = 0,
    /// A failure.
    Error = 1,
    /// Something the user should know (the default level).
    Warn = 2,
    /// The phases of a run with their counts and times.
    Info = 3,
    /// Details: settings in force, sizes of intermediate structures.
    Debug = 4,
}

impl Level {
    fn from_u8(x: u8) -> Level {
        match x {
            0 => Level::Off,
            1 => Level::Error,
            2 => Level::Warn,
            3 => Level::Info,
            _ => Level::Debug,
        }
    }

    fn parse(word: &str) -> Option<Level> {
        match word.trim().to_ascii_lowercase().as_str() {
            "off" => Some(Level::Off),
            "error" => Some(Level::Error),
            "warn" | "warning" => Some(Level::Warn),
            "info" => Some(Level::Info),
            "debug" | "trace" => Some(Level::Debug),
            _ => None,
        }
    }

    fn label(self) -> &'static str {
        match self {
            Level::Off => "OFF  ",
            Level::Error => "ERROR",
            Level::Warn => "WARN ",
            Level::Info => "INFO ",
            Level::Debug => "DEBUG",
        }
    }
}

static LEVEL: AtomicU8 = AtomicU8::new(Level::Warn as u8);
static START: OnceLock<Instant> = OnceLock::new();

/// The level a `RUST_LOG` value asks for (`None`: unset), [`Level::Warn`] when it names none.
pub fn parse_filter(rust_log: Option<&str>) -> Level {
    let mut level = Level::Warn;
    for directive in rust_log.unwrap_or("").split(',') {
        let (target, word) = match directive.split_once('=') {
            Some((t, w)) => (Some(t.trim()), w),
            None => (None, directive),
        };
        if target.is_some_and(|t| !t.starts_with("csm")) {
            continue;
        }
        if let Some(l) = Level::parse(word) {
            level = l;
        }
    }
    level
}

/// Sets the level from the environment variable `RUST_LOG` and starts the clock.
pub fn init_from_env() {
    let value = std::env::var("RUST_LOG").ok();
    set_level(parse_filter(value.as_deref()));
}

/// Sets the level (and starts the clock of the time stamps if not yet started).
pub fn set_level(level: Level) {
    START.get_or_init(Instant::now);
    LEVEL.store(level as u8, Ordering::Relaxed);
}

/// Whether a message of `level` would be printed.
pub fn enabled(level: Level) -> bool {
    level != Level::Off && level <= Level::from_u8(LEVEL.load(Ordering::Relaxed))
}

/// Prints `args` at `level` if enabled; use it as `log(Level::Info, format_args!(…))`.
pub fn log(level: Level, args: fmt::Arguments<'_>) {
    if enabled(level) {
        let t = START.get_or_init(Instant::now).elapsed().as_secs_f64();
        eprintln!("[{t:8.3} s {}] {args}", level.label());
    }
}

/// `log(Level::Info, args)`.
pub fn info(args: fmt::Arguments<'_>) {
    log(Level::Info, args);
}

/// `log(Level::Debug, args)`.
pub fn debug(args: fmt::Arguments<'_>) {
    log(Level::Debug, args);
}

#[cfg(test)]
mod tests;
