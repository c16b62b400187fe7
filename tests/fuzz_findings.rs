//! Regression tests for what the fuzzer found (fuzz/README.md, bench/results/fuzz/README.md):
//! each input once panicked; it must now be refused with an input error naming the element.

use luxbake::import::{GltfFile, ImportOptions, load};
use std::path::Path;

/// A glTF whose one primitive's `POSITION` names accessor 3 of none: the `gltf` crate's
/// validation indexed the accessors with it and panicked.
const POSITION_OUT_OF_RANGE: &str = r#"{"asset":{"version":"2.0"},
    "meshes":[{"primitives":[{"attributes":{"POSITION":3}}]}],
    "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}"#;

#[test]
fn position_accessor_out_of_range_is_an_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing-accessor.gltf");
    std::fs::write(&path, POSITION_OUT_OF_RANGE).unwrap();
    let pointer = "/meshes/0/primitives/0/attributes/POSITION";
    let message = load(&path, &ImportOptions::default())
        .err()
        .expect("refused")
        .to_string();
    assert!(message.contains(pointer), "{message}");
    assert!(message.contains("missing-accessor.gltf"), "{message}");
    // The reader of baked outputs (`bake report`, `bake diff`) parses the same way.
    let message = GltfFile::from_bytes(Path::new("bake.gltf"), POSITION_OUT_OF_RANGE.as_bytes())
        .err()
        .expect("refused")
        .to_string();
    assert!(message.contains(pointer), "{message}");
}
