//! Atomic file output: a file either keeps its old content or gets all of the new content.
//!
//! Input: a destination path and the bytes. Output: the file, written to a temporary file in the
//! same directory (`.<name>.luxbake-<pid>-<n>.tmp`), flushed to disk and renamed over the
//! destination. Invariant: on any error no temporary file is left behind and the destination is
//! untouched. [`write_atomic_all`] and [`Batch`] stage several files before renaming any of them,
//! so the common failures (no permission, disk full) leave none of them changed.

use crate::{Error, Result};
use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

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

/// Files staged one by one (so their bytes need not all be held at once) and renamed together
/// by [`Batch::commit`]; dropped uncommitted (an error on the way), it removes its temporaries.
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
    pub fn commit(mut self) -> Result<()> {
        let staged = std::mem::take(&mut self.staged);
        let existed: Vec<bool> = staged.iter().map(|(_, p)| p.exists()).collect();
        for i in 0..staged.len() {
            let (tmp, path) = &staged[i];
            if let Err(e) = fs::rename(tmp, path) {
                for (tmp, _) in &staged[i..] {
                    let _ = fs::remove_file(tmp);
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
        for (tmp, _) in &self.staged {
            let _ = fs::remove_file(tmp);
        }
    }
}

/// Write `bytes` to a new temporary file beside `path`; returns the temporary file's path.
fn stage(path: &Path, bytes: &[u8]) -> Result<PathBuf> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| Error::output(path, "not a file name"))?
        .to_string_lossy()
        .into_owned();
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let (tmp, mut file) = loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(".{name}.luxbake-{}-{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => break (tmp, f),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => {
                return Err(Error::output(
                    path,
                    format!("cannot create temporary file in {}: {e}", dir.display()),
                ));
            }
        }
    };
    if let Err(e) = fill(&mut file, bytes) {
        drop(file);
        let _ = fs::remove_file(&tmp);
        return Err(Error::output(path, format!("cannot write: {e}")));
    }
    Ok(tmp)
}

fn fill(file: &mut File, bytes: &[u8]) -> std::io::Result<()> {
    file.write_all(bytes)?;
    file.sync_all()
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
        drop(batch);
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
        fs::remove_dir_all(&dir).unwrap();
    }
}
