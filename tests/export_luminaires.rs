//! Luminaires and photometric profiles in the exporter's output: the round trip import → export →
//! import keeps every luminaire and the profile bytes; profiles are embedded as bufferViews with
//! their mimeType; node and material references are remapped; neither extension is required; the
//! output passes the Khronos glTF-Validator without errors or warnings and Blender imports the
//! luminaire nodes as empties.
//!
//! Every test here imports a scene with profiles, so all are ignored until the photometry parser
//! lands (`src/photometry` is a stub whose `Photometry::parse` always fails).

mod common;
mod support;

use common::luminaires::{IES, LDT, base, data_uri};
use common::{Bin, Builder, load_ok};
use luxbake::export::{self, ExportOptions};
use luxbake::result::BakeResult;
use luxbake::scene::{Luminaire, Scene};
use serde_json::{Value, json};
use std::path::Path;
use support::{gltf_read, scratch, tools};

/// A result with a dark front side for every surface (the values do not matter here).
fn flat_result(scene: &Scene) -> BakeResult {
    BakeResult::unbaked(scene)
}

/// The base scene made richer: an external IES file, a bufferView EULUMDAT profile, an IES light
/// with a `LUXBAKE_luminaire` beside it (maintenance factor, opening), a material emitting
/// through a profile, and a profile nobody uses.
fn rich(dir: &Path) -> Builder {
    std::fs::write(dir.join("down.ies"), IES).unwrap();
    let mut b = base();
    let view = b.view(LDT.as_bytes());
    b.json["extensions"] = json!({
        "EXT_lights_ies": {"lights": [
            {"uri": data_uri("application/x-ies-lm-63", IES), "name": "unused"},
            {"uri": "down.ies", "name": "down"},
        ]},
        "LUXBAKE_luminaire": {"profiles": [
            {"uri": data_uri("application/x-eulumdat", LDT), "name": "panel"},
            {"bufferView": view, "mimeType": "application/x-eulumdat"},
        ]},
    });
    b.json["nodes"][1]["extensions"] = json!({
        "EXT_lights_ies": {"light": 1, "multiplier": 2, "color": [1, 0.9, 0.7]},
        "LUXBAKE_luminaire": {"maintenanceFactor": 0.8,
            "opening": {"length": 1.2, "width": 0.3, "height": 0}},
    });
    b.json["nodes"][1]["rotation"] = json!([0.0, 0.0, 0.6, 0.8]);
    b.json["nodes"][2]["extensions"]["LUXBAKE_luminaire"] =
        json!({"profile": 1, "multiplier": 3, "extras": {"tag": 1}});
    let m = b.material(json!({"name": "glow", "extensions": {"LUXBAKE_material":
        {"reflectance": 0.5, "emission": {"luminousFlux": 900, "profile": 0}}}}));
    b.json["meshes"][0]["primitives"][0]["material"] = json!(m);
    b
}

fn assert_same_luminaires(a: &[Luminaire], b: &[Luminaire], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.name, y.name, "{what}");
        assert_eq!(x.node, y.node, "{what}");
        assert_eq!(x.profile, y.profile, "{what}");
        assert_eq!(x.source_path, y.source_path, "{what}");
        assert!((x.multiplier - y.multiplier).abs() < 1e-12, "{what}");
        assert_eq!(x.maintenance_factor, y.maintenance_factor, "{what}");
        assert!((x.color - y.color).abs().max_element() < 1e-12, "{what}");
        assert!(
            (x.position - y.position).abs().max_element() < 1e-12,
            "{what}"
        );
        let frame = x.world_from_photometric - y.world_from_photometric;
        assert!(frame.abs_diff_eq(glam::DMat3::ZERO, 1e-12), "{what}");
        assert_eq!(x.opening, y.opening, "{what}");
    }
}

fn assert_same_profiles(a: &Scene, b: &Scene, what: &str) {
    let names = |s: &Scene| -> Vec<(String, Option<String>, Vec<u8>)> {
        s.profiles
            .iter()
            .map(|p| (p.source_path.clone(), p.name.clone(), p.bytes.clone()))
            .collect()
    };
    assert_eq!(names(a), names(b), "{what}");
}

#[test]

fn round_trip_keeps_luminaires_and_profiles() {
    let dir = scratch("luminaires-round-trip");
    let input = rich(&dir).write_gltf(&dir, "in.gltf", Bin::DataUri);
    let scene = load_ok(&input);
    assert_eq!(scene.luminaires.len(), 2);
    assert_eq!(scene.materials[0].emission.unwrap().profile, Some(2));
    let result = flat_result(&scene);
    for (name, unlit) in [("out.gltf", true), ("out.glb", true), ("pbr.gltf", false)] {
        let path = dir.join(name);
        export::write(
            &path,
            &scene,
            &result,
            &ExportOptions {
                unlit,
                ..Default::default()
            },
        )
        .unwrap();
        let again = load_ok(&path);
        assert_same_luminaires(&scene.luminaires, &again.luminaires, name);
        assert_same_profiles(&scene, &again, name);
        for (x, y) in scene.luminaires.iter().zip(&again.luminaires) {
            assert_eq!(x.extensions, y.extensions, "{name}");
        }
        assert_eq!(
            again.materials[0].emission, scene.materials[0].emission,
            "{name}"
        );
    }
}

#[test]

fn profiles_are_embedded_and_nothing_is_required() {
    let dir = scratch("luminaires-json");
    let input = rich(&dir).write_gltf(&dir, "in.gltf", Bin::DataUri);
    let scene = load_ok(&input);
    let path = dir.join("out.gltf");
    export::write(
        &path,
        &scene,
        &flat_result(&scene),
        &ExportOptions::default(),
    )
    .unwrap();
    let out = gltf_read::read(&path);
    let j = &out.json;
    assert!(j.get("extensionsRequired").is_none());
    let used: Vec<&str> = j["extensionsUsed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    // LUXBAKE_material lives in extras under unlit, so it is not "used".
    assert_eq!(
        used,
        ["EXT_lights_ies", "KHR_materials_unlit", "LUXBAKE_luminaire"]
    );

    let bytes_of = |entry: &Value| -> Vec<u8> {
        let view = &j["bufferViews"][entry["bufferView"].as_u64().unwrap() as usize];
        let at = view["byteOffset"].as_u64().unwrap() as usize;
        let len = view["byteLength"].as_u64().unwrap() as usize;
        assert!(view.get("target").is_none());
        out.bin[at..at + len].to_vec()
    };
    let lights = j["extensions"]["EXT_lights_ies"]["lights"]
        .as_array()
        .unwrap();
    assert_eq!(lights.len(), 2);
    for (entry, name) in lights.iter().zip(["unused", "down"]) {
        assert_eq!(entry["mimeType"], "application/x-ies-lm-63");
        assert_eq!(entry["name"], name);
        assert!(entry.get("uri").is_none());
        assert_eq!(bytes_of(entry), IES.as_bytes());
    }
    let profiles = j["extensions"]["LUXBAKE_luminaire"]["profiles"]
        .as_array()
        .unwrap();
    assert_eq!(profiles.len(), 2);
    for entry in profiles {
        assert_eq!(entry["mimeType"], "application/x-eulumdat");
        assert_eq!(bytes_of(entry), LDT.as_bytes());
    }
    assert_eq!(profiles[0]["name"], "panel");
    assert!(profiles[1].get("name").is_none());

    assert_eq!(
        j["nodes"][1]["extensions"],
        json!({
            "EXT_lights_ies": {"light": 1, "multiplier": 2, "color": [1, 0.9, 0.7]},
            "LUXBAKE_luminaire": {"maintenanceFactor": 0.8,
                "opening": {"length": 1.2, "width": 0.3, "height": 0}},
        })
    );
    assert_eq!(
        j["nodes"][2]["extensions"]["LUXBAKE_luminaire"],
        json!({"profile": 1, "multiplier": 3, "extras": {"tag": 1}})
    );
    assert_eq!(
        j["materials"][0]["extras"]["luxbake"]["original"]["LUXBAKE_material"]["emission"],
        json!({"luminousFlux": 900, "profile": 0})
    );
}

/// Luminaires of a scene built (or changed) in code: their extension objects are made from
/// their values, and an EXT_lights_ies profile used by a material moves to LUXBAKE_luminaire
/// (the only list a material can index), with every reference following it.
#[test]

fn references_are_remapped_and_missing_objects_made() {
    let dir = scratch("luminaires-remap");
    let input = rich(&dir).write_gltf(&dir, "in.gltf", Bin::DataUri);
    let mut scene = load_ok(&input);
    for l in &mut scene.luminaires {
        l.extensions.clear();
    }
    // First without moving anything: node 1's objects are made from its values.
    let path = dir.join("made.gltf");
    export::write(
        &path,
        &scene,
        &flat_result(&scene),
        &ExportOptions::default(),
    )
    .unwrap();
    let j = gltf_read::read(&path).json;
    let node1 = &j["nodes"][1]["extensions"];
    assert_eq!(node1["EXT_lights_ies"]["light"], 1);
    let color: Vec<f64> = node1["EXT_lights_ies"]["color"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    for (got, want) in color.iter().zip([1.0, 0.9, 0.7]) {
        assert!((got - want).abs() < 1e-12, "{color:?}");
    }
    assert_eq!(
        node1["LUXBAKE_luminaire"],
        json!({"maintenanceFactor": 0.8, "opening": {"length": 1.2, "width": 0.3, "height": 0.0}})
    );
    let again = load_ok(&path);
    assert_same_luminaires(&scene.luminaires, &again.luminaires, "made");

    // The glowing material now uses EXT_lights_ies light 1 (scene profile 1).
    let mut e = scene.materials[0].emission.unwrap();
    e.profile = Some(1);
    scene.materials[0].emission = Some(e);
    let path = dir.join("out.gltf");
    export::write(
        &path,
        &scene,
        &flat_result(&scene),
        &ExportOptions::default(),
    )
    .unwrap();
    let j = gltf_read::read(&path).json;
    // Output lists: EXT [scene 0], LUXBAKE [scene 1, 2, 3].
    assert_eq!(
        j["extensions"]["EXT_lights_ies"]["lights"][0]["name"],
        "unused"
    );
    let names: Vec<&Value> = (0..3)
        .map(|k| &j["extensions"]["LUXBAKE_luminaire"]["profiles"][k]["name"])
        .collect();
    assert_eq!(names, [&json!("down"), &json!("panel"), &Value::Null]);
    assert_eq!(
        j["materials"][0]["extras"]["luxbake"]["original"]["LUXBAKE_material"]["emission"]["profile"],
        0
    );
    let node1 = &j["nodes"][1]["extensions"];
    assert!(node1.get("EXT_lights_ies").is_none(), "{node1}");
    assert_eq!(node1["LUXBAKE_luminaire"]["profile"], 0);
    assert_eq!(node1["LUXBAKE_luminaire"]["maintenanceFactor"], 0.8);
    assert_eq!(
        j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["profile"],
        2
    );

    let again = load_ok(&path);
    assert_eq!(again.materials[0].emission.unwrap().profile, Some(1));
    assert_eq!(again.luminaires.len(), 2);
    for (x, y) in scene.luminaires.iter().zip(&again.luminaires) {
        assert_eq!(
            scene.profiles[x.profile].bytes,
            again.profiles[y.profile].bytes
        );
        assert!((x.multiplier - y.multiplier).abs() < 1e-12);
        assert!((x.color - y.color).abs().max_element() < 1e-12);
        assert_eq!(
            (x.maintenance_factor, x.opening),
            (y.maintenance_factor, y.opening)
        );
        let frame = x.world_from_photometric - y.world_from_photometric;
        assert!(frame.abs_diff_eq(glam::DMat3::ZERO, 1e-12));
    }
}

#[test]

fn validator_finds_no_errors_or_warnings() {
    if !tools::have_validator() {
        return;
    }
    let dir = scratch("luminaires-validate");
    let input = rich(&dir).write_gltf(&dir, "in.gltf", Bin::DataUri);
    let scene = load_ok(&input);
    let result = flat_result(&scene);
    for (name, unlit) in [("lit.gltf", true), ("lit.glb", true), ("pbr.gltf", false)] {
        let path = dir.join(name);
        export::write(
            &path,
            &scene,
            &result,
            &ExportOptions {
                unlit,
                ..Default::default()
            },
        )
        .unwrap();
        let report = tools::validate(&path);
        assert_eq!(
            (report.errors, report.warnings),
            (0, 0),
            "{name}:\n{}",
            report.listing()
        );
    }
}

#[test]

fn blender_keeps_luminaire_nodes() {
    if !tools::have_blender() {
        return;
    }
    let dir = scratch("luminaires-blender");
    let input = rich(&dir).write_gltf(&dir, "in.gltf", Bin::DataUri);
    let scene = load_ok(&input);
    let result = flat_result(&scene);
    for name in ["room.gltf", "room.glb"] {
        let path = dir.join(name);
        export::write(&path, &scene, &result, &ExportOptions::default()).unwrap();
        let report = tools::blender_import(&path);
        let kinds: Vec<(&str, &str)> = report["objects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| (o["name"].as_str().unwrap(), o["type"].as_str().unwrap()))
            .collect();
        for expected in [("Ies", "EMPTY"), ("Ldt", "EMPTY")] {
            assert!(kinds.contains(&expected), "{name}: {kinds:?}");
        }
    }
}
