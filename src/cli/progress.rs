//! A one-line progress indicator on standard error for a phase that takes a while.
//!
//! The libraries do not print, so the facade shows progress from outside: [`Progress::start`]
//! spawns a helper thread that, once the phase has run for [`Progress::DELAY`], redraws
//! `searching… 3.2 s` with a spinner a few times a second until [`Progress::finish`] (or
//! drop) stops it and clears the line. It is off with `--quiet` and when standard error is
//! not a terminal (see [`progress_wanted`]).

use std::io::{IsTerminal, Write as _};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Whether a progress line should be drawn: not `quiet` and standard error is a terminal.
pub fn progress_wanted(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

/// A running progress line; stops when finished or dropped.
#[derive(Debug)]
pub struct Progress {
    stop: Option<Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl Progress {
    /// How long a phase runs before the line appears.
    pub const DELAY: Duration = Duration::from_millis(500);
    const TICK: Duration = Duration::from_millis(100);

    /// Starts the indicator for a phase called `label` (e.g. `searching`); does nothing when
    /// `enabled` is false.
    pub fn start(label: &str, enabled: bool) -> Progress {
        if !enabled {
            return Progress {
                stop: None,
                thread: None,
            };
        }
        let (tx, rx) = mpsc::channel::<()>();
        let label = label.to_owned();
        let start = Instant::now();
        let thread = std::thread::spawn(move || {
            const SPINNER: [char; 4] = ['|', '/', '-', '\\'];
            let mut wait = Progress::DELAY;
            let mut drawn = false;
            let mut k = 0usize;
            // Until finished (a message) or dropped (the channel disconnects).
            while let Err(RecvTimeoutError::Timeout) = rx.recv_timeout(wait) {
                wait = Progress::TICK;
                let line = format!(
                    "\r{} {label}… {:.1} s",
                    SPINNER[k % SPINNER.len()],
                    start.elapsed().as_secs_f64()
                );
                k += 1;
                let mut err = std::io::stderr().lock();
                let _ = err.write_all(line.as_bytes());
                let _ = err.flush();
                drawn = true;
            }
            if drawn {
                // Clear the line so that what follows starts on a clean one.
                let mut err = std::io::stderr().lock();
                let _ = err.write_all(b"\r\x1b[2K");
                let _ = err.flush();
            }
        });
        Progress {
            stop: Some(tx),
            thread: Some(thread),
        }
    }

    /// Stops the indicator and clears its line (waits for the helper thread).
    pub fn finish(mut self) {
        self.stop_and_join();
    }

    fn stop_and_join(&mut self) {
        if let Some(tx) = self.stop.take() {
            let _ = tx.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.stop_and_join();
    }
}
