//! Progress on stderr for the command line: a bar per stage when stderr is a terminal, warnings
//! always.

use indicatif::{ProgressBar, ProgressStyle};
use luxbake::progress::Progress;
use std::sync::Mutex;

/// Progress on stderr: a bar per stage when stderr is a terminal; warnings always.
pub struct CliProgress {
    bar: Option<Mutex<ProgressBar>>,
}

impl CliProgress {
    pub fn new(show: bool) -> Self {
        CliProgress {
            bar: show.then(|| Mutex::new(ProgressBar::hidden())),
        }
    }

    pub fn done(&self) {
        if let Some(bar) = &self.bar {
            bar.lock().unwrap().finish_and_clear();
        }
    }
}

impl Progress for CliProgress {
    fn stage(&self, name: &str, total: u64) {
        if let Some(bar) = &self.bar {
            let mut bar = bar.lock().unwrap();
            bar.finish_and_clear();
            *bar = if total > 0 {
                ProgressBar::new(total)
            } else {
                ProgressBar::new_spinner()
            };
            bar.set_style(
                ProgressStyle::with_template("{msg:>14} [{bar:30}] {pos}/{len} {elapsed}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            bar.set_message(name.to_string());
        }
    }

    fn advance(&self, n: u64) {
        if let Some(bar) = &self.bar {
            bar.lock().unwrap().inc(n);
        }
    }

    fn warn(&self, message: &str) {
        match &self.bar {
            Some(bar) => bar.lock().unwrap().println(format!("warning: {message}")),
            None => eprintln!("warning: {message}"),
        }
    }
}
