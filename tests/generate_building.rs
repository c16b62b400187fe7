//! `bake generate building`: the building floor of closed rooms (src/fixtures/building_floor.rs),
//! written as an input glTF.
//! - two runs give byte-identical files (.gltf + .bin, and .glb);
//! - the file loads back as the scene built in code: its triangles, materials (the thin
//!   partitions and the thin door leaf double-sided), its 14 luminaires and its extras (rooms,
//!   doors, working planes);
//! - the Khronos glTF-Validator finds no error or warning (skipped when absent, except under
//!   CI: see `support/tools.rs`);
//! - `samples/building/` holds exactly what the command writes.

mod support;

use luxbake::fixtures::building_floor::building_floor;
use luxbake::import::load;
use std::path::Path;
use support::cli::{bake, listing};
use support::{scratch, tools};

/// Run `bake generate building -q -o out`; panics unless it succeeds silently.
fn generate(out: &Path) {
    let all = ["generate", "building", "-q", "-o", out.to_str().unwrap()];
    let run = bake(all);
    assert!(run.ok(), "bake {all:?}: {run:?}");
    assert!(run.stderr.is_empty(), "-q prints nothing: {}", run.stderr);
}

#[test]
fn two_runs_write_the_same_bytes() {
    let dir = scratch("generate-building-determinism");
    let read = |p: &Path| std::fs::read(p).unwrap();
    let mut runs = Vec::new();
    for sub in ["a", "b"] {
        let d = dir.join(sub);
        std::fs::create_dir(&d).unwrap();
        generate(&d.join("building.gltf"));
        generate(&d.join("building.glb"));
        assert_eq!(
            listing(&d),
            ["building.#.bin", "building.glb", "building.gltf"]
        );
        runs.push([
            read(&d.join("building.gltf")),
            read(&support::hashed(&d, "building.#.bin")),
            read(&d.join("building.glb")),
        ]);
    }
    for (k, name) in ["building.gltf", "building.bin", "building.glb"]
        .iter()
        .enumerate()
    {
        assert!(runs[0][k] == runs[1][k], "{name} differs between two runs");
    }
}

#[test]
fn the_file_loads_back_as_the_scene_built_in_code() {
    let dir = scratch("generate-building-load");
    let path = dir.join("building.glb");
    generate(&path);
    let loaded = load(&path, &Default::default()).unwrap();
    let built = building_floor();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let triangles =
        |s: &luxbake::scene::Scene| -> usize { s.surfaces.iter().map(|x| x.triangles.len()).sum() };
    assert_eq!(triangles(&loaded), triangles(&built));
    assert_eq!(loaded.extras, built.extras);
    assert_eq!(loaded.luminaires.len(), 14);
    let double: Vec<&str> = loaded
        .materials
        .iter()
        .filter(|m| m.double_sided)
        .map(|m| m.name.as_deref().unwrap())
        .collect();
    assert_eq!(double, ["partition_thin", "door_thin"]);
    let emitters = loaded.materials.iter().filter(|m| m.emission.is_some());
    assert_eq!(emitters.count(), 1);
}

#[test]
fn validator_finds_no_errors_or_warnings() {
    if !tools::have_validator() {
        return;
    }
    let dir = scratch("generate-building-validate");
    for name in ["building.gltf", "building.glb"] {
        let path = dir.join(name);
        generate(&path);
        let report = tools::validate(&path);
        assert_eq!(
            (report.errors, report.warnings),
            (0, 0),
            "{}:\n{}",
            path.display(),
            report.listing()
        );
    }
}

#[test]
fn the_committed_sample_is_what_the_generator_writes() {
    let dir = scratch("generate-building-sample");
    generate(&dir.join("building.gltf"));
    let sample = support::cli::repo_file("samples/building");
    for name in ["building.gltf", "building.#.bin"] {
        let read = |d: &Path| std::fs::read(support::hashed(d, name)).unwrap();
        assert!(
            read(&dir) == read(&sample),
            "samples/building/{name} is stale: rewrite it with \
             `bake generate building -o samples/building/building.gltf`"
        );
    }
}
