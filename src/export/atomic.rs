//! Atomic file output: a file either keeps its old content or gets all of the new content.
//!
//! Input: a destination path and the bytes. Output: the file, written to a temporary file in the
//! same directory (`.<name>.luxbake-<pid>-<n>.tmp`), flushed to disk and renamed over the
//! destination. Invariants: on any error no temporary file is left behind and the destination is
//! untouched; every temporary is listed in a process-wide registry from before it is created
//! until it is renamed or removed, so [`install_signal_handler`]'s SIGINT/SIGTERM handler removes
//! them all (it waits for a [`Batch::commit`] in progress to finish: renames are never cut).
//! [`Batch`] stages several files before renaming any of them. [`fault`] is a test-only hook that
//! kills or pauses the process at a chosen staging write, rename or cleanup removal.

use crate::{Error, Result};
use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// Write `bytes` to `path` atomically (temporary file in the same directory, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_all(&[(path, bytes)])
}

/// Write several files: stage every one in a temporary file, then rename them in the given order.
/// If staging fails nothing changes; if a rename fails (rare: same directory, same filesystem),
/// the files renamed so far by this call are removed when they did not exist before.
pub fn write_atomic_all(files: &[(&Path, &[u8])]) -> Result<()> {
    let mut batch = Batch::default();
    for (path, bytes) in files {
        batch.stage(path, bytes)?;
    }
    batch.commit()
}

/// The temporaries of this process not yet renamed or removed.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The registry, even if a thread panicked while holding it (it is only a list of paths).
fn registry() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner())
}

/// On SIGINT or SIGTERM: remove every registered temporary, then exit with 128 + the signal
/// (130, 143). A commit in progress holds the registry, so the handler runs after its last rename.
pub fn install_signal_handler() -> std::io::Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("luxbake-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Held until exit: no temporary can be created or renamed any more.
                let temporaries = registry();
                for tmp in temporaries.iter() {
                    let _ = fs::remove_file(tmp);
                }
                std::process::exit(128 + signal);
            }
        })?;
    Ok(())
}

/// Files staged one by one (so their bytes need not all be held at once) and renamed together
/// by [`Batch::commit`], in staging order; dropped uncommitted (an error on the way), it removes
/// its temporaries.
#[derive(Debug, Default)]
pub struct Batch {
    /// (temporary, destination), in the order they will be renamed.
    staged: Vec<(PathBuf, PathBuf)>,
}

impl Batch {
    /// Write `bytes` to a temporary file beside `path`, to be renamed over it by `commit`.
    pub fn stage(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        let tmp = stage(path, bytes)?;
        self.staged.push((tmp, path.to_path_buf()));
        Ok(())
    }

    /// Rename every staged file over its destination, in staging order. If a rename fails, the
    /// destinations renamed so far that did not exist before are removed again.
    pub(crate) fn commit(mut self) -> Result<()> {
        let staged = std::mem::take(&mut self.staged);
        let existed: Vec<bool> = staged.iter().map(|(_, p)| p.exists()).collect();
        let mut temporaries = registry();
        for i in 0..staged.len() {
            let (tmp, path) = &staged[i];
            fault::step("rename", path);
            let renamed = fs::rename(tmp, path);
            temporaries.retain(|t| t != tmp);
            if let Err(e) = renamed {
                for (tmp, _) in &staged[i..] {
                    let _ = fs::remove_file(tmp);
                    temporaries.retain(|t| t != tmp);
                }
                for (j, (_, done)) in staged[..i].iter().enumerate() {
                    if !existed[j] {
                        let _ = fs::remove_file(done);
                    }
                }
                return Err(Error::output(
                    path,
                    format!("cannot rename temporary file: {e}"),
                ));
            }
        }
        Ok(())
    }
}

impl Drop for Batch {
    fn drop(&mut self) {
        let mut temporaries = registry();
        for (tmp, _) in &self.staged {
            let _ = fs::remove_file(tmp);
            temporaries.retain(|t| t != tmp);
        }
    }
}

/// The folder a file is written to (`.` for a bare name).
pub(crate) fn folder(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Create a new, registered temporary file beside `path`; returns its path and the open file.
fn create(path: &Path) -> Result<(PathBuf, File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| Error::output(path, "not a file name"))?
        .to_string_lossy()
        .into_owned();
    let dir = folder(path);
    let mut temporaries = registry();
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(".{name}.luxbake-{}-{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => {
                temporaries.push(tmp.clone());
                return Ok((tmp, f));
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => {
                return Err(Error::output(
                    path,
                    format!("cannot create a temporary file in {}: {e}", dir.display()),
                ));
            }
        }
    }
}

/// Remove a registered temporary and forget it.
fn discard(tmp: &Path) {
    let mut temporaries = registry();
    let _ = fs::remove_file(tmp);
    temporaries.retain(|t| t != tmp);
}

/// Write `bytes` to a new temporary file beside `path`; returns the temporary file's path.
fn stage(path: &Path, bytes: &[u8]) -> Result<PathBuf> {
    let (tmp, mut file) = create(path)?;
    if let Err(e) = fill(&mut file, bytes, path) {
        drop(file);
        discard(&tmp);
        return Err(Error::output(path, format!("cannot write: {e}")));
    }
    Ok(tmp)
}

fn fill(file: &mut File, bytes: &[u8], path: &Path) -> std::io::Result<()> {
    // In two halves, so the fault hook can stop the process with a half-written temporary.
    let (first, second) = bytes.split_at(bytes.len() / 2);
    file.write_all(first)?;
    fault::step("write", path);
    file.write_all(second)?;
    file.sync_all()
}

/// Check that files can be created in `dir` (create and remove a temporary there).
pub(crate) fn check_writable(dir: &Path) -> std::result::Result<(), String> {
    let (tmp, file) = create(&dir.join("luxbake-check")).map_err(|e| match e {
        Error::Output { message, .. } => message,
        e => e.to_string(),
    })?;
    drop(file);
    discard(&tmp);
    Ok(())
}

/// Remove a file as a cleanup step (counted by the fault hook); a failure is ignored (the file is
/// a leftover the next run removes).
pub(crate) fn remove_leftover(path: &Path) {
    fault::step("remove", path);
    let _ = fs::remove_file(path);
}

/// Remove the temporaries in `dir` that processes no longer running left behind (killed).
pub(crate) fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut stale: Vec<PathBuf> = entries
        .filter_map(|e| e.ok())
        .filter(|e| {
            e.file_name()
                .to_str()
                .and_then(temporary_pid)
                .is_some_and(|pid| !running(pid))
        })
        .map(|e| e.path())
        .collect();
    stale.sort();
    for path in stale {
        remove_leftover(&path);
    }
}

/// The process id in a temporary's name `.<name>.luxbake-<pid>-<n>.tmp`.
fn temporary_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (_, ids) = rest.rsplit_once(".luxbake-")?;
    let (pid, n) = ids.split_once('-')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(pid) && digits(n))
        .then(|| pid.parse().ok())
        .flatten()
}

/// Whether process `pid` exists (when unsure, it does: its files are kept).
fn running(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    // SAFETY: signal 0 only checks that the process exists; nothing is sent.
    let alive = unsafe { libc::kill(pid, 0) } == 0;
    alive || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

/// Test-only fault injection (documented in ARCHITECTURE.md; built only with the
/// `fault-injection` feature, which `cargo test` turns on): with `LUXBAKE_FAULT_AT=N` the
/// process kills itself (SIGKILL) at its N-th step, counting every staging write (after half the
/// bytes), rename and cleanup removal from 1; with `LUXBAKE_FAULT_AT=N:pause` it prints
/// `luxbake-fault: pause at step N (<kind> <path>)` on stderr and sleeps 20 s there instead (a
/// test sends a signal meanwhile). Every step is printed as `luxbake-fault: step N …` when the
/// variable is set.
pub mod fault {
    use std::path::Path;
    #[cfg(feature = "fault-injection")]
    use std::sync::OnceLock;
    #[cfg(feature = "fault-injection")]
    use std::sync::atomic::{AtomicU64, Ordering};

    /// (N, pause) from `LUXBAKE_FAULT_AT`, read once.
    #[cfg(feature = "fault-injection")]
    fn setting() -> Option<(u64, bool)> {
        static SETTING: OnceLock<Option<(u64, bool)>> = OnceLock::new();
        *SETTING.get_or_init(|| {
            let value = std::env::var("LUXBAKE_FAULT_AT").ok()?;
            let (n, pause) = match value.strip_suffix(":pause") {
                Some(n) => (n, true),
                None => (value.as_str(), false),
            };
            Some((n.trim().parse().ok()?, pause))
        })
    }

    /// One step: `kind` is `write`, `rename` or `remove`, `path` the file concerned. Without
    /// the `fault-injection` feature (every build but `cargo test`'s) it does nothing.
    #[cfg(not(feature = "fault-injection"))]
    pub(crate) fn step(_kind: &str, _path: &Path) {}

    /// One step: `kind` is `write`, `rename` or `remove`, `path` the file concerned.
    #[cfg(feature = "fault-injection")]
    pub(crate) fn step(kind: &str, path: &Path) {
        static STEPS: AtomicU64 = AtomicU64::new(0);
        let Some((at, pause)) = setting() else {
            return;
        };
        let n = STEPS.fetch_add(1, Ordering::SeqCst) + 1;
        eprintln!("luxbake-fault: step {n} ({kind} {})", path.display());
        if n != at {
            return;
        }
        if pause {
            eprintln!(
                "luxbake-fault: pause at step {n} ({kind} {})",
                path.display()
            );
            std::thread::sleep(std::time::Duration::from_secs(20));
        } else {
            // SAFETY: sends SIGKILL to this process, as `kill -9` would.
            unsafe { libc::kill(libc::getpid(), libc::SIGKILL) };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("luxbake-atomic-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn replaces_content_and_leaves_no_temporary() {
        let dir = scratch("replace");
        let path = dir.join("out.txt");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"second");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn failure_changes_nothing() {
        let dir = scratch("fail");
        let good = dir.join("a.bin");
        let bad = dir.join("missing-dir").join("b.gltf");
        let err = write_atomic_all(&[(&good, b"x"), (&bad, b"y")]).unwrap_err();
        assert!(matches!(err, Error::Output { .. }), "{err}");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn dropped_batch_removes_its_temporaries() {
        let dir = scratch("drop");
        let mut batch = Batch::default();
        batch.stage(&dir.join("a.exr"), b"a").unwrap();
        batch.stage(&dir.join("b.exr"), b"b").unwrap();
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 2);
        assert!(registry().iter().any(|t| t.starts_with(&dir)));
        drop(batch);
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
        assert!(!registry().iter().any(|t| t.starts_with(&dir)));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn stale_temporaries_of_dead_processes_only() {
        assert_eq!(temporary_pid(".lit.gltf.luxbake-123-4.tmp"), Some(123));
        assert_eq!(temporary_pid(".a.luxbake-b.luxbake-7-0.tmp"), Some(7));
        for name in [
            "lit.gltf",
            ".lit.luxbake-1.tmp",
            ".x.luxbake-a-1.tmp",
            ".x.luxbake-1-.tmp",
        ] {
            assert_eq!(temporary_pid(name), None, "{name}");
        }
        let dir = scratch("stale");
        // A pid above Linux's largest (2^22) cannot be running; ours is.
        let dead = dir.join(".lit.bin.luxbake-4194305-0.tmp");
        let ours = dir.join(format!(".lit.bin.luxbake-{}-0.tmp", std::process::id()));
        for f in [&dead, &ours] {
            fs::write(f, b"x").unwrap();
        }
        remove_stale_temporaries(&dir);
        assert!(!dead.exists() && ours.exists());
        fs::remove_dir_all(&dir).unwrap();
    }
}
