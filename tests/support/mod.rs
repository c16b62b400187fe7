//! Shared test support: a hand-built scene with its bake result (`fixture`), a minimal reader of
//! the written glTF (`gltf_read`) and the external tools (`tools`: Khronos glTF-Validator,
//! Blender's importer). Each test binary uses what it needs.
#![allow(dead_code)]

pub mod fixture;
pub mod gltf_read;
pub mod tools;

use std::path::PathBuf;

/// A fresh, empty directory for one test's files (under the system temp directory).
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("luxbake-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
