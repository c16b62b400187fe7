//! Every way a glTF input can be refused, through `luxbake::import::load`: each error must name
//! the file and the exact JSON pointer of the offending element, and never panic.

mod common;

use common::*;
use luxbake::import::{ImportOptions, load};
use serde_json::json;
use std::path::Path;

/// Assert the error is at `pointer` and that its message says so and contains `needle`.
fn assert_error(path: &Path, pointer: &str, needle: &str) {
    let (at, message) = load_err(path);
    assert_eq!(at, pointer, "{message}");
    if !pointer.is_empty() {
        assert!(message.contains(&format!("{pointer}: ")), "{message}");
    }
    assert!(
        message.contains(needle),
        "expected '{needle}' in: {message}"
    );
    assert!(message.contains(&path.display().to_string()), "{message}");
}

#[test]
fn missing_buffer_file() {
    let dir = tempfile::tempdir().unwrap();
    let b = triangle_builder();
    let path = b.write_gltf(dir.path(), "m.gltf", Bin::External("gone.bin"));
    std::fs::remove_file(dir.path().join("gone.bin")).unwrap();
    assert_error(&path, "/buffers/0", "gone.bin");
}

#[test]
fn buffer_shorter_than_byte_length() {
    let dir = tempfile::tempdir().unwrap();
    let b = triangle_builder();
    let path = b.write_gltf(dir.path(), "short.gltf", Bin::External("short.bin"));
    std::fs::write(dir.path().join("short.bin"), &b.bin[..10]).unwrap();
    assert_error(&path, "/buffers/0", "byteLength");
}

#[test]
fn truncated_glb() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = triangle_builder().glb_bytes();
    for cut in [4, 12, 30, bytes.len() / 2, bytes.len() - 1] {
        let path = dir.path().join(format!("cut{cut}.glb"));
        std::fs::write(&path, &bytes[..cut]).unwrap();
        assert_error(&path, "", "truncated");
    }
}

#[test]
fn glb_bin_chunk_shorter_than_buffer() {
    let dir = tempfile::tempdir().unwrap();
    let b = triangle_builder();
    // The JSON declares the buffer's 36 bytes, the BIN chunk holds only 24.
    let bytes = glb_from(&b.finished_json(None), &b.bin[..24]);
    let path = dir.path().join("short.glb");
    std::fs::write(&path, bytes).unwrap();
    assert_error(&path, "/buffers/0", "byteLength is 36");
}

#[test]
fn nan_position() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let mesh = b.simple_mesh(
        &[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]],
        None,
        None,
        None,
    );
    b.node(json!({"mesh": mesh}));
    let path = b.write_gltf(dir.path(), "nan.gltf", Bin::DataUri);
    assert_error(
        &path,
        "/meshes/0/primitives/0/attributes/POSITION",
        "accessor /accessors/0 holds a non-finite position",
    );
}

#[test]
fn reflectance_at_or_above_one() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    for _ in 0..3 {
        b.material(json!({"pbrMetallicRoughness": {"metallicFactor": 0,
            "baseColorFactor": [0.5, 0.5, 0.5, 1]}}));
    }
    b.material(json!({"extensions": {"LUXBAKE_material": {"reflectance": 1.2}}}));
    let path = b.write_gltf(dir.path(), "bright.gltf", Bin::DataUri);
    assert_error(&path, "/materials/3", "reflectance 1.2 ≥ 1");
    assert!(
        load_err(&path)
            .1
            .contains("LUXBAKE_material.reflectance below 1")
    );

    // baseColor 1 with metallic 0 reflects everything: refused with a hint.
    b.json["materials"][3] = json!({"pbrMetallicRoughness": {"metallicFactor": 0}});
    let path = b.write_gltf(dir.path(), "white.gltf", Bin::DataUri);
    assert_error(&path, "/materials/3", "lower baseColorFactor");

    b.json["materials"][3] =
        json!({"extensions": {"LUXBAKE_material": {"reflectance": [0.5, -0.1, 0.5]}}});
    let path = b.write_gltf(dir.path(), "negative.gltf", Bin::DataUri);
    assert_error(&path, "/materials/3", "channel G");
}

#[test]
fn malformed_luxbake_extension() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    for (i, ext) in [
        json!({"emission": {"luminance": -5}}),
        json!({"emission": {"luminance": 5, "luminousFlux": 5}}),
        json!({"reflectance": 0.5, "gloss": 1}),
    ]
    .into_iter()
    .enumerate()
    {
        b.json["materials"] = json!([{"extensions": {"LUXBAKE_material": ext}}]);
        let path = b.write_gltf(dir.path(), &format!("ext{i}.gltf"), Bin::DataUri);
        assert_error(&path, "/materials/0/extensions/LUXBAKE_material", "");
    }
}

#[test]
fn uri_climbing_out_of_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("a/b");
    std::fs::create_dir_all(&inner).unwrap();
    let b = triangle_builder();
    // The target exists, so only confinement can refuse it.
    let path = b.write_gltf(&inner, "up.gltf", Bin::External("../../x.bin"));
    assert!(dir.path().join("x.bin").exists());
    assert_error(&path, "/buffers/0", "outside the folder");
    // Climbing out and back in is fine.
    let ok = b.write_gltf(&inner, "back.gltf", Bin::External("../b/y.bin"));
    assert_eq!(load_ok(&ok).surfaces.len(), 1);
}

#[test]
fn absolute_path_and_foreign_scheme_uris() {
    let dir = tempfile::tempdir().unwrap();
    let b = triangle_builder();
    let path = b.write_gltf(dir.path(), "abs.gltf", Bin::External("abs.bin"));
    // Even an absolute path to a file inside the folder is refused.
    let absolute = dir.path().join("abs.bin").canonicalize().unwrap();
    for (uri, needle) in [
        (absolute.display().to_string(), "absolute path"),
        ("file:///etc/hosts".to_owned(), "scheme 'file:'"),
        ("https://example.com/x.bin".to_owned(), "scheme 'https:'"),
    ] {
        let mut json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        json["buffers"][0]["uri"] = json!(uri);
        std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
        assert_error(&path, "/buffers/0", needle);
    }
}

#[cfg(unix)]
#[test]
fn symlink_escaping_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("inner");
    std::fs::create_dir(&inner).unwrap();
    let b = triangle_builder();
    std::fs::write(dir.path().join("outside.bin"), &b.bin).unwrap();
    std::os::unix::fs::symlink(dir.path().join("outside.bin"), inner.join("link.bin")).unwrap();
    let path = b.write_gltf(&inner, "link.gltf", Bin::External("tmp.bin"));
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("tmp.bin", "link.bin");
    std::fs::write(&path, text).unwrap();
    assert_error(&path, "/buffers/0", "symbolic link");
}

#[test]
fn unsupported_required_extensions() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    b.set(
        "extensionsUsed",
        json!(["LUXBAKE_material", "KHR_draco_mesh_compression"]),
    );
    b.set(
        "extensionsRequired",
        json!(["LUXBAKE_material", "KHR_draco_mesh_compression"]),
    );
    let path = b.write_gltf(dir.path(), "draco.gltf", Bin::DataUri);
    assert_error(
        &path,
        "/extensionsRequired/1",
        "'KHR_draco_mesh_compression'",
    );
    b.set("extensionsRequired", json!(["EXT_meshopt_compression"]));
    let path = b.write_gltf(dir.path(), "meshopt.gltf", Bin::DataUri);
    assert_error(&path, "/extensionsRequired/0", "meshopt");
}

#[test]
fn accessor_and_view_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    b.json["accessors"][0]["count"] = json!(4);
    let path = b.write_gltf(dir.path(), "acc.gltf", Bin::DataUri);
    assert_error(
        &path,
        "/meshes/0/primitives/0/attributes/POSITION",
        "do not fit in /bufferViews/0",
    );

    let mut b = triangle_builder();
    b.json["bufferViews"][0]["byteOffset"] = json!(8);
    let path = b.write_gltf(dir.path(), "view.gltf", Bin::DataUri);
    assert_error(
        &path,
        "/meshes/0/primitives/0/attributes/POSITION",
        "/bufferViews/0 (byteOffset 8, byteLength 36) does not fit in /buffers/0",
    );
}

#[test]
fn index_out_of_range_and_bad_references() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let mesh = b.simple_mesh(&TRIANGLE, Some(&[0, 1, 5]), None, None);
    b.node(json!({"mesh": mesh}));
    let path = b.write_gltf(dir.path(), "idx.gltf", Bin::DataUri);
    assert_error(&path, "/meshes/0/primitives/0/indices", "index 5");

    let mut b = triangle_builder();
    b.json["meshes"][0]["primitives"][0]["material"] = json!(7);
    let path = b.write_gltf(dir.path(), "ref.gltf", Bin::DataUri);
    assert_error(&path, "/meshes/0/primitives/0/material", "does not exist");
}

#[test]
fn node_with_two_parents() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    b.node(json!({"children": [0]}));
    b.node(json!({"children": [0]}));
    b.set("scenes", json!([{"nodes": [1, 2]}]));
    let path = b.write_gltf(dir.path(), "dag.gltf", Bin::DataUri);
    assert_error(&path, "/nodes/0", "two parents");
}

#[test]
fn not_gltf_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("garbage.gltf");
    std::fs::write(&path, b"{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [").unwrap();
    assert_error(&path, "", "not valid JSON");
    std::fs::write(&path, b"{\"asset\": {\"version\": \"1.0\"}}").unwrap();
    assert_error(&path, "/asset/version", "only 2.x");

    let txt = dir.path().join("scene.txt");
    std::fs::write(&txt, b"hello").unwrap();
    let e = load(&txt, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains(".gltf, .glb and .obj"), "{e}");
    let missing = load(&dir.path().join("nope.glb"), &ImportOptions::default());
    assert!(missing.unwrap_err().to_string().contains("nope.glb"));
}

#[test]
fn hostile_numbers_never_panic() {
    // Every size/offset/count of a valid file replaced by awkward values: load must return
    // (Ok or a typed error), never panic or read out of bounds.
    let dir = tempfile::tempdir().unwrap();
    let mut base = Builder::new();
    let position = base.vec3s(&TRIANGLE);
    let idx = base.indices(&[0, 1, 2]);
    let iv = base.view(&0u16.to_le_bytes());
    let vv = base.view(&[0u8; 12]);
    base.json["accessors"][position]["sparse"] = json!({"count": 1,
        "indices": {"bufferView": iv, "componentType": UNSIGNED_SHORT},
        "values": {"bufferView": vv}});
    let mesh = base.mesh(vec![
        json!({"attributes": {"POSITION": position}, "indices": idx}),
    ]);
    base.node(json!({"mesh": mesh}));
    let fields = [
        "/accessors/0/count",
        "/accessors/0/byteOffset",
        "/accessors/1/count",
        "/accessors/0/sparse/count",
        "/accessors/0/sparse/indices/byteOffset",
        "/bufferViews/0/byteOffset",
        "/bufferViews/0/byteLength",
        "/bufferViews/0/byteStride",
        "/bufferViews/1/byteLength",
        "/bufferViews/2/byteLength",
    ];
    for (f, field) in fields.iter().enumerate() {
        for (v, value) in [0u64, 1, 3, 4, 1 << 31, u32::MAX as u64, u64::MAX / 2]
            .iter()
            .enumerate()
        {
            let mut b = Builder {
                bin: base.bin.clone(),
                json: base.json.clone(),
            };
            let (parent, key) = field.rsplit_once('/').unwrap();
            b.json.pointer_mut(parent).unwrap()[key] = json!(value);
            let path = b.write_gltf(dir.path(), &format!("h{f}_{v}.gltf"), Bin::DataUri);
            let result = std::panic::catch_unwind(|| load(&path, &ImportOptions::default()));
            assert!(result.is_ok(), "{field} = {value} panicked");
        }
    }
}
