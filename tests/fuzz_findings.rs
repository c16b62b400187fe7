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
        .expect_err("refused")
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

/// An MTL colour line with fewer than three values: `tobj` unwrapped a failed conversion to
/// `[f64; 3]` and panicked.
#[test]
fn short_mtl_colour_line_is_an_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("room.obj");
    std::fs::write(
        &obj,
        "mtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wall\nf 1 2 3\n",
    )
    .unwrap();
    for line in ["Kd 0.5 0.5", "Ka", "Ke 2", "Ks 0.1 0.2"] {
        std::fs::write(
            dir.path().join("room.mtl"),
            format!("newmtl wall\n{line}\n"),
        )
        .unwrap();
        let message = load(&obj, &ImportOptions::default())
            .expect_err("refused")
            .to_string();
        let key = &line[..2];
        assert!(message.contains("room.mtl"), "{message}");
        assert!(
            message.contains(&format!("line 2: {key} needs three values")),
            "{message}"
        );
    }
}

/// An EXR file whose header declares a 40 001 × 40 001 data window: the `exr` crate allocated
/// 6.4 GB of samples from the header before reading any (the fuzzer's limit is 4 GiB).
#[test]
fn exr_header_larger_than_its_file_is_refused_before_allocating() {
    use exr::prelude::*;
    let layer = Layer::new(
        (8, 8),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(vec![AnyChannel::new("Y", FlatSamples::F32(vec![1.0; 64]))].into()),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .unwrap();
    let mut bytes = bytes.into_inner();
    assert!(luxbake::import::exr::decode(&bytes, &["Y"]).is_ok());
    // dataWindow: name, type, size 16, then xMin yMin xMax yMax (i32 LE).
    let key = b"dataWindow\0box2i\0\x10\0\0\0";
    let at = (bytes.windows(key.len()))
        .position(|w| w == key)
        .expect("a dataWindow attribute")
        + key.len();
    bytes[at + 8..at + 12].copy_from_slice(&40_000i32.to_le_bytes());
    bytes[at + 12..at + 16].copy_from_slice(&40_000i32.to_le_bytes());
    // The chunk count the writer stores must agree: one scan line per uncompressed chunk.
    let key = b"chunkCount\0int\0\x04\0\0\0";
    let at = (bytes.windows(key.len()))
        .position(|w| w == key)
        .expect("a chunkCount attribute")
        + key.len();
    bytes[at..at + 4].copy_from_slice(&40_001i32.to_le_bytes());
    let message = luxbake::import::exr::decode(&bytes, &["Y"]).unwrap_err();
    assert!(
        message.contains("declares 40001 × 40001 pixels of 1 channel(s), more than a file"),
        "{message}"
    );
}
