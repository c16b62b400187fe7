//! The glTF exporter on a hand-built scene (see `support/fixture.rs`): validity (Khronos
//! glTF-Validator: no errors, no warnings), JSON structure, geometry back in local space,
//! winding, determinism, and the refusal / atomicity rules.

mod support;

use glam::DVec3;
use luxbake::{Error, export, export::ExportOptions};
use serde_json::{Value, json};
use std::path::Path;
use support::{fixture, gltf_read, scratch, tools};

fn write(path: &Path, options: &ExportOptions) {
    let (scene, result) = fixture::scene();
    export::write(path, &scene, &result, options).unwrap();
}

/// Which values of `CI` make a missing external tool fail its tests instead of skipping them.
#[test]
fn ci_is_any_value_but_empty_false_or_0() {
    for v in ["true", "TRUE", "1", "yes", "gitlab"] {
        assert!(tools::ci_value_means_ci(Some(v)), "CI={v}");
    }
    for v in [
        None,
        Some(""),
        Some(" "),
        Some("false"),
        Some("False"),
        Some("0"),
    ] {
        assert!(!tools::ci_value_means_ci(v), "CI={v:?}");
    }
}

#[test]
fn validator_finds_no_errors_or_warnings() {
    if !tools::have_validator() {
        return;
    }
    let dir = scratch("validate");
    for (name, unlit) in [("lit.gltf", true), ("lit.glb", true), ("pbr.gltf", false)] {
        let path = dir.join(name);
        write(
            &path,
            &ExportOptions {
                unlit,
                ..Default::default()
            },
        );
        let report = tools::validate(&path);
        // Unlit materials carry LUXBAKE_material in extras (the validator warns about any other
        // extension beside KHR_materials_unlit), so both modes have no warning at all.
        assert_eq!(
            (report.errors, report.warnings),
            (0, 0),
            "{name}:\n{}",
            report.listing()
        );
        let codes: Vec<&str> = report
            .messages
            .iter()
            .filter_map(|m| m["code"].as_str())
            .collect();
        // LUXBAKE_material is an unknown (info-level) extension only where it stays an extension.
        assert_eq!(
            codes.contains(&"UNSUPPORTED_EXTENSION"),
            !unlit,
            "{codes:?}"
        );
    }
}

#[test]
fn json_structure() {
    let dir = scratch("structure");
    let path = dir.join("room.gltf");
    write(&path, &ExportOptions::default());
    let j = gltf_read::read(&path).json;

    assert_eq!(j["asset"]["version"], "2.0");
    assert_eq!(
        j["asset"]["generator"],
        format!("luxbake {}", env!("CARGO_PKG_VERSION"))
    );
    assert_eq!(
        j["extensionsUsed"],
        json!(["KHR_lights_punctual", "KHR_materials_unlit"])
    );
    assert!(j.get("extensionsRequired").is_none());
    // `room.<16 hex digits of the bytes' FNV-1a>.bin`.
    let bin = std::fs::read(support::hashed(&dir, "room.#.bin")).unwrap();
    let hash = luxbake::export::content_hash(&bin);
    assert_eq!(j["buffers"][0]["uri"], format!("room.{hash:016x}.bin"));

    let scene = &j["scenes"][j["scene"].as_u64().unwrap() as usize];
    assert_eq!(scene["name"], "Lit room");
    assert_eq!(scene["nodes"], json!([0]));
    assert_eq!(scene["extras"]["project"], "test room");
    assert_eq!(scene["extras"]["luxbake"]["counts"]["patches"], 12);

    let m0 = &j["materials"][0];
    assert_eq!(m0["name"], "Textured");
    assert_eq!(m0["extensions"]["KHR_materials_unlit"], json!({}));
    assert!(
        m0["extensions"]
            .get("KHR_materials_emissive_strength")
            .is_none()
    );
    assert!(m0["extensions"].get("LUXBAKE_material").is_none());
    assert_eq!(
        m0["extras"]["luxbake"]["original"]["LUXBAKE_material"]["reflectance"],
        json!([0.4, 0.4, 0.4])
    );
    let pbr = &m0["pbrMetallicRoughness"];
    assert_eq!(
        (
            pbr["metallicFactor"].as_f64(),
            pbr["roughnessFactor"].as_f64()
        ),
        (Some(0.0), Some(1.0))
    );
    assert_eq!(pbr["baseColorTexture"], json!({"index": 0, "texCoord": 0}));
    assert_eq!(m0["emissiveFactor"], json!([0.0, 0.0, 0.0]));
    assert_eq!(m0["extras"]["author"], "fixture");
    let original = &m0["extras"]["luxbake"]["original"];
    assert_eq!(original["metallicFactor"], 0.2);
    assert_eq!(original["roughnessFactor"], 0.6);
    assert_eq!(original["emissiveFactor"], json!([0.1, 0.0, 0.0]));
    assert_eq!(original["emissiveStrength"], 2.0);
    assert_eq!(original["baseColorFactor"], json!([0.8, 0.7, 0.6, 1.0]));
    assert_eq!(m0["extras"]["luxbake"]["reflectanceSource"], "extension");
    let m1 = &j["materials"][1];
    assert_eq!(m1["doubleSided"], false);
    assert_eq!(m1["extras"]["luxbake"]["original"]["doubleSided"], true);

    assert_eq!(j["images"][0]["mimeType"], "image/png");
    assert!(j["images"][0]["bufferView"].is_u64());
    assert_eq!(
        j["samplers"][0],
        json!({"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33648})
    );

    let nodes = j["nodes"].as_array().unwrap();
    assert_eq!(nodes[0]["children"], json!([1, 2, 3, 4]));
    assert_eq!(nodes[1]["extras"]["nested"]["k"], 1);
    assert_eq!(nodes[1]["scale"], json!([-1.5, 1.0, 2.0]));
    assert_eq!(nodes[2]["matrix"].as_array().unwrap().len(), 16);
    assert_eq!(nodes[3]["extensions"]["KHR_lights_punctual"]["light"], 0);
    assert_eq!(nodes[4]["camera"], 0);
    assert_eq!(j["cameras"][0]["name"], "Eye");
    let light = &j["extensions"]["KHR_lights_punctual"]["lights"][0];
    assert_eq!(
        (light["type"].as_str(), light["intensity"].as_f64()),
        (Some("spot"), Some(990.0))
    );
    assert_eq!(
        light["spot"],
        json!({"innerConeAngle": 0.2, "outerConeAngle": 0.4})
    );
    let c: Vec<f64> = light["color"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        (c[0] - 1.0).abs() < 1e-12 && (c[1] - 0.9).abs() < 1e-12 && (c[2] - 0.8).abs() < 1e-12,
        "{c:?}"
    );

    // One mesh per node with surfaces; the double-sided divider has a front and a back primitive.
    assert_eq!(
        (nodes[1]["mesh"].as_u64(), nodes[2]["mesh"].as_u64()),
        (Some(0), Some(1))
    );
    assert_eq!(j["meshes"][0]["name"], "PanelMesh");
    assert_eq!(j["meshes"][1]["primitives"].as_array().unwrap().len(), 2);
    let prim = &j["meshes"][0]["primitives"][0];
    assert_eq!(
        (prim["mode"].as_u64(), prim["material"].as_u64()),
        (Some(4), Some(0))
    );
    let types = [
        ("POSITION", "VEC3"),
        ("NORMAL", "VEC3"),
        ("TEXCOORD_0", "VEC2"),
        ("COLOR_0", "VEC3"),
        ("_ILLUMINANCE", "SCALAR"),
        ("_ILLUMINANCE_DIRECT", "SCALAR"),
        ("_LUMINANCE", "SCALAR"),
    ];
    let attributes = prim["attributes"].as_object().unwrap();
    assert_eq!(attributes.len(), types.len());
    for (name, kind) in types {
        let acc = &j["accessors"][attributes[name].as_u64().unwrap() as usize];
        assert_eq!(
            (acc["type"].as_str(), acc["componentType"].as_u64()),
            (Some(kind), Some(5126)),
            "{name}"
        );
    }
    assert!(j["accessors"][attributes["POSITION"].as_u64().unwrap() as usize]["min"].is_array());
    assert_eq!(
        j["accessors"][prim["indices"].as_u64().unwrap() as usize]["componentType"],
        5123
    );
    for view in j["bufferViews"].as_array().unwrap() {
        assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
        assert!(view.get("byteStride").is_none());
    }
}

#[test]
fn geometry_returns_to_local_space_with_mirrored_winding() {
    let (scene, result) = fixture::scene();
    let dir = scratch("geometry");
    let path = dir.join("room.glb");
    export::write(&path, &scene, &result, &ExportOptions::default()).unwrap();
    let g = gltf_read::read(&path);
    // Panel (mesh 0, det < 0) and the divider's two sides (mesh 1, det > 0).
    let cases = [(1, 0, 0, 0), (2, 1, 0, 1), (2, 1, 1, 2)];
    for (node, mesh, prim, baked) in cases {
        let m = scene.nodes[node].world_from_local;
        let mirrored = m.determinant() < 0.0;
        let b = &result.surfaces[baked];
        let p = &g.json["meshes"][mesh]["primitives"][prim];
        let attr = |name: &str| p["attributes"][name].as_u64().unwrap() as usize;
        let positions = g.floats(attr("POSITION"));
        let normals = g.floats(attr("NORMAL"));
        for (i, local) in positions.iter().enumerate() {
            let world = m.transform_point3(DVec3::new(
                local[0].into(),
                local[1].into(),
                local[2].into(),
            ));
            assert!(
                (world - b.positions[i]).length() < 1e-5,
                "node {node} vertex {i}"
            );
            let n = DVec3::new(
                normals[i][0].into(),
                normals[i][1].into(),
                normals[i][2].into(),
            );
            let n_world = m.inverse().transpose().transform_vector3(n).normalize();
            assert!(
                (n_world - b.normals[i]).length() < 1e-5,
                "node {node} normal {i}"
            );
        }
        let indices = g.indices(p["indices"].as_u64().unwrap() as usize);
        let expected: Vec<u32> = b
            .triangles
            .iter()
            .flat_map(|&[a, c, d]| if mirrored { [a, d, c] } else { [a, c, d] })
            .collect();
        assert_eq!(
            indices, expected,
            "node {node} winding (mirrored: {mirrored})"
        );
        let e: Vec<f32> = g.floats(attr("_ILLUMINANCE")).concat();
        assert_eq!(e, b.illuminance);
        assert_eq!(g.floats(attr("_LUMINANCE")).concat(), b.luminance);
        assert_eq!(
            g.floats(attr("COLOR_0")),
            b.color.iter().map(|c| c.to_vec()).collect::<Vec<_>>()
        );
    }
}

#[test]
fn output_is_byte_identical_on_a_second_write() {
    let dir = scratch("determinism");
    for name in ["a.gltf", "a.glb"] {
        let path = dir.join(name);
        write(&path, &ExportOptions::default());
        let first = std::fs::read(&path).unwrap();
        let bin = support::hashed(&dir, "a.#.bin");
        let first_bin = std::fs::read(&bin).unwrap();
        write(&path, &ExportOptions::default());
        assert_eq!(first, std::fs::read(&path).unwrap(), "{name}");
        assert_eq!(first_bin, std::fs::read(&bin).unwrap());
    }
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 3, "temporary files left behind: {names:?}");
}

#[test]
fn lit_materials_are_kept_when_unlit_is_off() {
    let dir = scratch("lit");
    let path = dir.join("room.gltf");
    write(
        &path,
        &ExportOptions {
            unlit: false,
            ..Default::default()
        },
    );
    let j = gltf_read::read(&path).json;
    let m0 = &j["materials"][0];
    assert!(m0["extensions"].get("KHR_materials_unlit").is_none());
    assert_eq!(
        m0["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"],
        2.0
    );
    assert_eq!(m0["pbrMetallicRoughness"]["metallicFactor"], 0.2);
    assert_eq!(m0["emissiveFactor"], json!([0.1, 0.0, 0.0]));
    assert!(m0["extras"]["luxbake"].get("original").is_none());
    assert_eq!(
        j["materials"][1]["extras"]["luxbake"]["original"],
        json!({"doubleSided": true})
    );
    let used: Vec<Value> = j["extensionsUsed"].as_array().unwrap().clone();
    assert_eq!(
        used,
        vec![
            json!("KHR_lights_punctual"),
            json!("KHR_materials_emissive_strength"),
            json!("LUXBAKE_material")
        ]
    );
}

fn assert_output_error(r: luxbake::Result<()>) {
    match r {
        Err(Error::Output { .. }) => {}
        other => panic!("expected an output error, got {other:?}"),
    }
}

#[test]
fn refuses_to_overwrite_an_input_file() {
    let dir = scratch("refuse");
    let (mut scene, result) = fixture::scene();
    let input = dir.join("in.gltf");
    std::fs::write(&input, b"input").unwrap();
    scene.source_file = input.clone();
    let opts = ExportOptions::default();
    // The same file through another spelling of its path.
    let sub = dir.join("sub");
    std::fs::create_dir(&sub).unwrap();
    assert_output_error(export::write(
        &sub.join("../in.gltf"),
        &scene,
        &result,
        &opts,
    ));
    assert_eq!(std::fs::read(&input).unwrap(), b"input");
    // An input buffer named like a side file of `out.gltf` (which a bake writes and removes):
    // nothing is written.
    let buffer = dir.join("out.0123456789abcdef.bin");
    std::fs::write(&buffer, b"buffer").unwrap();
    scene.input_files = vec![buffer.canonicalize().unwrap()];
    assert_output_error(export::write(&dir.join("out.gltf"), &scene, &result, &opts));
    assert_eq!(std::fs::read(&buffer).unwrap(), b"buffer");
    assert!(!dir.join("out.gltf").exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 3);
}

#[test]
fn failed_writes_leave_nothing_behind() {
    let dir = scratch("atomic");
    let (scene, result) = fixture::scene();
    let opts = ExportOptions::default();
    assert_output_error(export::write(
        &dir.join("missing/room.glb"),
        &scene,
        &result,
        &opts,
    ));
    assert_output_error(export::write(&dir.join("room.obj"), &scene, &result, &opts));
    // The .gltf cannot replace a directory: refused before anything is staged.
    std::fs::create_dir(dir.join("room.gltf")).unwrap();
    assert_output_error(export::write(
        &dir.join("room.gltf"),
        &scene,
        &result,
        &opts,
    ));
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["room.gltf"], "left behind: {names:?}");
}

/// An emitting material is written unlit over its emission colour (white), so viewers show the
/// source bright; baking the output anew still reads the input's reflectance, emission and
/// base colour from `extras.luxbake.original` (here a core-glTF emitter: `emissiveFactor` ×
/// `KHR_materials_emissive_strength`, reflectance from `baseColorFactor`).
#[test]
fn an_emitter_shows_its_emission_colour_and_reads_back_as_its_input() {
    let dir = support::scratch("emitter-display-base");
    let mut mini = support::cli::Mini::new();
    mini.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    mini.json["materials"][1] = json!({"name": "core emitter",
        "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.2, 0.1, 1.0], "metallicFactor": 0.0},
        "emissiveFactor": [1.0, 0.5, 0.25],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 400.0}}});
    let input = mini.write_gltf(&dir, "in.gltf", None);
    let output = dir.join("lit.gltf");
    let run = support::cli::bake_draft(&input, &output, &[] as &[&str]);
    assert!(run.ok(), "{run:?}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&output).unwrap()).unwrap();
    let m = &doc["materials"][1];
    assert_eq!(
        m["pbrMetallicRoughness"]["baseColorFactor"],
        json!([1.0, 0.5, 0.25, 1.0])
    );
    assert_eq!(
        m["extras"]["luxbake"]["original"]["baseColorFactor"],
        json!([0.3, 0.2, 0.1, 1.0])
    );
    let (a, b) = (
        luxbake::import::load(&input, &Default::default()).unwrap(),
        luxbake::import::load(&output, &Default::default()).unwrap(),
    );
    let (a, b) = (&a.materials[1], &b.materials[1]);
    assert_eq!(a.reflectance, b.reflectance);
    assert_eq!(a.emission, b.emission);
    assert!(b.emission.is_some());
    assert_eq!(a.display.base_color_factor, b.display.base_color_factor);
}

/// A luxbake output's kept display values (`extras.luxbake.original`, read in place of an unlit
/// material's) are checked as the material's own: out of range is an error naming the pointer.
#[test]
fn kept_original_display_values_are_range_checked() {
    for (key, value) in [
        ("emissiveFactor", serde_json::json!([2.0, 0.0, 0.0])),
        ("baseColorFactor", serde_json::json!([0.5, -1.0, 0.5, 1.0])),
        ("emissiveStrength", serde_json::json!(-3.0)),
    ] {
        let dir = support::scratch(&format!("kept-{key}"));
        let mut mini = support::cli::Mini::new();
        mini.json["materials"][0]["extras"] =
            serde_json::json!({"luxbake": {"original": {key: value}}});
        let path = mini.write_gltf(&dir, "in.gltf", None);
        let e = luxbake::import::load(&path, &Default::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("/materials/0/extras/luxbake/original/{key}"))
                && e.contains("out of range"),
            "{key}: {e}"
        );
    }
}
