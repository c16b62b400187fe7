//! Peak resident memory per stage of a run, for `--summary-json` (Linux only: elsewhere nothing
//! is recorded).
//!
//! The kernel keeps one peak per process (`VmHWM` in `/proc/self/status`); it is never reset
//! here, since `time -v` and other tools read the same peak. A stage during which it rose peaked
//! at it exactly; for a stage during which it did not, the peak is the largest resident size
//! (`VmRSS`) a sampling thread saw every [`EVERY`], which can miss a spike shorter than that.

use luxbake::summary::StageMemory;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

const EVERY: Duration = Duration::from_millis(10);

pub struct MemoryTrace {
    state: Arc<Mutex<State>>,
    stop: Arc<AtomicBool>,
}

struct State {
    /// The stage running now; `None` once the trace has ended.
    current: Option<String>,
    /// The process's peak when it began, and the largest resident size sampled since.
    began_peak: u64,
    sampled: u64,
    stages: Vec<StageMemory>,
}

impl MemoryTrace {
    /// A trace whose first stage (until the first [`MemoryTrace::next`]) is `first`; `None`
    /// where `/proc/self/status` cannot be read.
    pub fn start(first: &str) -> Option<Self> {
        let (resident, peak) = status()?;
        let state = Arc::new(Mutex::new(State {
            current: Some(first.to_string()),
            began_peak: peak,
            sampled: resident,
            stages: Vec::new(),
        }));
        let stop = Arc::new(AtomicBool::new(false));
        let (s, halt) = (state.clone(), stop.clone());
        std::thread::Builder::new()
            .name("memory".into())
            .spawn(move || {
                while !halt.load(Ordering::Relaxed) {
                    if let Some((resident, _)) = status() {
                        let mut s = s.lock().unwrap();
                        s.sampled = s.sampled.max(resident);
                    }
                    std::thread::sleep(EVERY);
                }
            })
            .ok()?;
        Some(MemoryTrace { state, stop })
    }

    /// The current stage ends and `name` begins.
    pub fn next(&self, name: &str) {
        let Some((resident_kib, peak)) = status() else {
            return;
        };
        let mut s = self.state.lock().unwrap();
        let Some(ended) = s.current.take() else {
            return;
        };
        let stage_peak = if peak > s.began_peak {
            peak
        } else {
            s.sampled.max(resident_kib)
        };
        // A stage reported again right after itself (a bake of several groups) is one stage.
        match s.stages.last_mut() {
            Some(last) if last.stage == ended => {
                last.peak_kib = last.peak_kib.max(stage_peak);
                last.resident_kib = resident_kib;
            }
            _ => s.stages.push(StageMemory {
                stage: ended,
                peak_kib: stage_peak,
                resident_kib,
            }),
        }
        s.current = Some(name.to_string());
        s.began_peak = peak;
        s.sampled = resident_kib;
    }

    /// End the current stage and the trace; every stage's record.
    pub fn finish(&self) -> Vec<StageMemory> {
        self.next("");
        self.stop.store(true, Ordering::Relaxed);
        let mut s = self.state.lock().unwrap();
        s.current = None;
        std::mem::take(&mut s.stages)
    }
}

impl Drop for MemoryTrace {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// (VmRSS, VmHWM) in KiB.
fn status() -> Option<(u64, u64)> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key))?
            .trim()
            .strip_suffix("kB")?
            .trim()
            .parse::<u64>()
            .ok()
    };
    Some((field("VmRSS:")?, field("VmHWM:")?))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hold `mib` MiB, every page touched, for 60 ms (six samples), then free them.
    fn hold(mib: usize) {
        let block = vec![1u8; mib << 20];
        std::hint::black_box(&block);
        std::thread::sleep(Duration::from_millis(60));
    }

    #[test]
    fn each_stage_gets_the_peak_it_reached() {
        let Some(trace) = MemoryTrace::start("small") else {
            eprintln!("skipped: /proc/self/status is not available here");
            return;
        };
        hold(1);
        trace.next("large");
        hold(96);
        // The process's peak does not rise here: this stage's peak is sampled.
        trace.next("middle");
        hold(48);
        let stages = trace.finish();
        let names: Vec<&str> = stages.iter().map(|s| s.stage.as_str()).collect();
        assert_eq!(names, ["small", "large", "middle"]);
        let (small, large, middle) = (&stages[0], &stages[1], &stages[2]);
        assert!(large.peak_kib > small.peak_kib + 80 * 1024, "{stages:?}");
        assert!(
            middle.peak_kib > middle.resident_kib + 40 * 1024,
            "{stages:?}"
        );
        assert!(middle.peak_kib + 40 * 1024 < large.peak_kib, "{stages:?}");
        // Freed before each stage ended.
        assert!(
            large.resident_kib + 80 * 1024 < large.peak_kib,
            "{stages:?}"
        );
    }
}
