//! Shared test support: running the `bake` binary on a minimal input scene (`cli`), the `bake
//! diff` tests' room and file surgery (`bakes`), a hand-built scene with its bake result
//! (`fixture`), a minimal reader of the written glTF (`gltf_read`) and the external tools
//! (`tools`: Khronos glTF-Validator, Blender's importer). Each test binary uses what it needs.
#![allow(dead_code)]

pub mod bakes;
pub mod cli;
pub mod fixture;
pub mod gltf_read;
pub mod lightmapped;
pub mod tools;

use std::path::{Path, PathBuf};

/// A fresh, empty directory for one test's files, under cargo's temporary directory for
/// integration tests (emptied again by the next run of the same test).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("luxbake-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
