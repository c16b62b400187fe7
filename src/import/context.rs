//! The state one import carries around: which file is being read, the folder every referenced
//! resource must stay inside, the files read so far and the warnings collected.
//!
//! Inputs: the path of the input file. Outputs: [`Error`]s naming that file, and (at the end) the
//! `warnings` and `input_files` that go into [`crate::scene::Scene`].
//! Invariants: `dir` is canonical; `input_files` holds canonical paths, each once; a warning
//! *kind* given to [`Ctx::warn_once`] is reported only the first time.

use crate::{Error, Result};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

pub(crate) struct Ctx {
    /// The input file as the caller named it (used in messages).
    pub file: PathBuf,
    /// Canonical folder of the input file; resources must resolve inside it. `None` for a
    /// document read from memory, which may reference no file at all.
    pub dir: Option<PathBuf>,
    pub input_files: Vec<PathBuf>,
    pub warnings: Vec<String>,
    warned: HashSet<String>,
}

impl Ctx {
    /// Start importing `path`: check that it exists and record it as read.
    pub(crate) fn new(path: &Path) -> Result<Self> {
        let canonical = path
            .canonicalize()
            .map_err(|e| Error::input(path, "", format!("cannot open the file: {e}")))?;
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let dir = parent
            .canonicalize()
            .map_err(|e| Error::input(path, "", format!("cannot resolve its folder: {e}")))?;
        let mut ctx = Ctx {
            file: path.to_path_buf(),
            dir: Some(dir),
            input_files: Vec::new(),
            warnings: Vec::new(),
            warned: HashSet::new(),
        };
        ctx.record(canonical);
        Ok(ctx)
    }

    /// A document held in memory, named `name` in messages: it may reference no file.
    pub(crate) fn in_memory(name: &Path) -> Self {
        Ctx {
            file: name.to_path_buf(),
            dir: None,
            input_files: Vec::new(),
            warnings: Vec::new(),
            warned: HashSet::new(),
        }
    }

    /// The folder resources must resolve inside, or an error at `at` for a document in memory.
    pub(crate) fn folder(&self, at: &str, what: &str) -> Result<&Path> {
        self.dir.as_deref().ok_or_else(|| {
            self.err(
                at,
                format!("{what}: a document read from memory cannot reference files"),
            )
        })
    }

    /// An input error at `at` (a JSON pointer or other locator) in the current file.
    pub(crate) fn err(&self, at: impl Into<String>, message: impl Into<String>) -> Error {
        Error::input(&self.file, at, message)
    }

    /// Read the whole input file.
    pub(crate) fn read_input(&self) -> Result<Vec<u8>> {
        super::files::read(&self.file)
            .map_err(|e| self.err("", format!("cannot read the file: {e}")))
    }

    /// Note that a (canonical) file was read.
    pub(crate) fn record(&mut self, canonical: PathBuf) {
        if !self.input_files.contains(&canonical) {
            self.input_files.push(canonical);
        }
    }

    pub(crate) fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }

    /// Warn once per `kind` (later warnings of the same kind are dropped).
    pub(crate) fn warn_once(&mut self, kind: &str, message: impl Into<String>) {
        if self.warned.insert(kind.to_owned()) {
            self.warnings.push(message.into());
        }
    }
}
