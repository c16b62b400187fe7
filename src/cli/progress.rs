//! Progress on stderr for the command line: a bar per stage when stderr is a terminal, warnings
//! always.

use super::memory::MemoryTrace;
use indicatif::{ProgressBar, ProgressStyle};
use luxbake::progress::Progress;
use std::sync::Mutex;

/// Progress on stderr: a bar per stage when stderr is a terminal; warnings always.
pub struct CliProgress {
    bar: Option<Mutex<ProgressBar>>,
    /// Peak memory per stage, when asked for ([`CliProgress::trace_memory`]).
    memory: Option<MemoryTrace>,
}

impl CliProgress {
    pub fn new(show: bool) -> Self {
        CliProgress {
            bar: show.then(|| Mutex::new(ProgressBar::hidden())),
            memory: None,
        }
    }

    /// Record each stage's peak memory from now on, the time until the first stage as `first`.
    pub fn trace_memory(mut self, first: &str) -> Self {
        self.memory = MemoryTrace::start(first);
        self
    }

    /// A stage the library does not announce begins (memory is recorded per stage).
    pub fn mark(&self, name: &str) {
        if let Some(m) = &self.memory {
            m.next(name);
        }
    }

    /// Every stage's memory so far, ending the current stage.
    pub fn memory(&self) -> Vec<luxbake::summary::StageMemory> {
        self.memory.as_ref().map(|m| m.finish()).unwrap_or_default()
    }

    pub fn done(&self) {
        if let Some(bar) = &self.bar {
            bar.lock().unwrap().finish_and_clear();
        }
    }
}

impl Progress for CliProgress {
    fn stage(&self, name: &str, total: u64) {
        self.mark(name);
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
