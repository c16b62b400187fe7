//! Replays the committed fuzz corpus (`fuzz/corpus/<target>/`, found by `cargo fuzz` on nightly;
//! see fuzz/README.md) through the same target functions on stable: no input may panic. Each
//! target's corpus must exist and hold both inputs the reader accepts and inputs it rejects, so
//! a lost corpus or a reader that starts rejecting everything fails here.

#[path = "../fuzz/src/targets.rs"]
mod targets;

use std::path::Path;

fn replay(target: &str, run: fn(&[u8]) -> bool) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let (mut accepted, mut rejected) = (0, 0);
    for file in &files {
        let bytes = std::fs::read(file).unwrap();
        let ok = std::panic::catch_unwind(|| run(&bytes))
            .unwrap_or_else(|_| panic!("{target}: {} panicked", file.display()));
        if ok {
            accepted += 1;
        } else {
            rejected += 1;
        }
    }
    eprintln!("{target}: {accepted} accepted, {rejected} rejected");
    assert!(
        accepted > 0,
        "{target}: no input of {} is accepted",
        dir.display()
    );
    assert!(
        rejected > 0,
        "{target}: no input of {} is rejected",
        dir.display()
    );
}

#[test]
fn gltf() {
    replay("gltf", targets::gltf);
}

#[test]
fn glb() {
    replay("glb", targets::glb);
}

#[test]
fn accessors() {
    replay("accessors", targets::accessors);
}

#[test]
fn obj() {
    replay("obj", targets::obj);
}

#[test]
fn ies() {
    replay("ies", targets::ies);
}

#[test]
fn ldt() {
    replay("ldt", targets::ldt);
}

#[test]
fn probes_csv() {
    replay("probes_csv", targets::probes_csv);
}

#[test]
fn targets_json() {
    replay("targets_json", targets::targets_json);
}

#[test]
fn exr() {
    replay("exr", targets::exr);
}

#[test]
fn baked() {
    replay("baked", targets::baked);
}
