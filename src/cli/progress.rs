//! A tiny progress bar on stderr. It is drawn only when stderr is a terminal and the work
//! has run for more than a second, so that programs reading stderr still see, on exit 2 or 3,
//! exactly one `error:` line (contract.md); [`Bar::clear`] erases it before such a line.

use crate::Progress;
use std::io::{IsTerminal, Write};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub struct Bar {
    start: Instant,
    last: Option<Instant>,
    terminal: bool,
}

impl Bar {
    pub fn new() -> Self {
        Bar {
            start: Instant::now(),
            last: None,
            terminal: std::io::stderr().is_terminal(),
        }
    }

    /// Show `what [#####     ] done/total` (at most ten times a second).
    pub fn update(&mut self, what: &str, done: f64, total: f64) {
        let now = Instant::now();
        if !self.terminal || now - self.start < Duration::from_secs(1) {
            return;
        }
        if self
            .last
            .is_some_and(|t| now - t < Duration::from_millis(100))
            && done < total
        {
            return;
        }
        self.last = Some(now);
        const WIDTH: usize = 30;
        let filled = if total > 0.0 {
            ((done / total * WIDTH as f64) as usize).min(WIDTH)
        } else {
            WIDTH
        };
        let bar: String = "#".repeat(filled) + &" ".repeat(WIDTH - filled);
        let secs = (now - self.start).as_secs();
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r\x1b[2K{what} [{bar}] {}/{} {secs} s",
            short(done),
            short(total)
        );
        let _ = err.flush();
    }

    /// Erase the bar if it was drawn.
    pub fn clear(&mut self) {
        if self.last.take().is_some() {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r\x1b[2K");
            let _ = err.flush();
        }
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.clear();
    }
}

/// A count as it is, a time to three decimals.
fn short(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x}")
    } else {
        format!("{x:.3}")
    }
}

/// A [`Bar`] the library's long computations draw through a [`Progress`].
pub struct SharedBar(Arc<Mutex<Bar>>);

impl SharedBar {
    pub fn new() -> Self {
        SharedBar(Arc::new(Mutex::new(Bar::new())))
    }

    /// A progress that updates this bar.
    pub fn progress(&self) -> Progress {
        let bar = self.0.clone();
        Progress::new(move |what, done, total| {
            if let Ok(mut b) = bar.lock() {
                b.update(what, done, total)
            }
        })
    }

    /// Erase the bar if it was drawn.
    pub fn clear(&self) {
        if let Ok(mut b) = self.0.lock() {
            b.clear()
        }
    }
}
