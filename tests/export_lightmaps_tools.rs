//! The lightmapped output (`support/lightmapped.rs`) in external tools: the Khronos
//! glTF-Validator finds no error and no warning (`.gltf`, `.glb`, lit materials kept), and
//! Blender (PyPI `bpy` 5.0.1) imports the display texture read through the second UV map into
//! the emission of each lightmapped material, and loads the EXR files with their values.
//! Skipped locally when a tool is missing, never under CI (see `support/tools.rs`).

mod support;

use luxbake::{export, export::ExportOptions};
use serde_json::{Value, json};
use support::{lightmapped, scratch, tools};

#[test]
fn validator_finds_no_errors_or_warnings() {
    if !tools::have_validator() {
        return;
    }
    let dir = scratch("lm-validate");
    let (scene, result) = lightmapped::scene();
    for (name, unlit) in [("lit.gltf", true), ("lit.glb", true), ("pbr.gltf", false)] {
        let path = dir.join(name);
        let options = ExportOptions {
            unlit,
            ..Default::default()
        };
        export::write(&path, &scene, &result, &options).unwrap();
        let report = tools::validate(&path);
        assert_eq!(
            (report.errors, report.warnings),
            (0, 0),
            "{name}:\n{}",
            report.listing()
        );
        // Our extensions and MOZ_lightmap are unknown to the validator: an info each.
        let unsupported: Vec<&str> = report
            .messages
            .iter()
            .filter(|m| m["code"] == "UNSUPPORTED_EXTENSION")
            .filter_map(|m| m["message"].as_str())
            .collect();
        for ext in ["LUXBAKE_lightmap", "MOZ_lightmap"] {
            assert!(
                unsupported.iter().any(|m| m.contains(ext)),
                "{unsupported:?}"
            );
        }
    }
}

fn find<'a>(list: &'a Value, name: &str) -> &'a Value {
    list.as_array()
        .unwrap()
        .iter()
        .find(|v| v["name"] == name)
        .unwrap_or_else(|| panic!("no {name} in {list:#}"))
}

#[test]
fn blender_shows_the_display_texture_on_the_second_uv_map() {
    if !tools::have_blender() {
        return;
    }
    let dir = scratch("lm-blender");
    let (scene, result) = lightmapped::scene();
    for name in ["lit.gltf", "lit.glb"] {
        let path = dir.join(name);
        export::write(&path, &scene, &result, &ExportOptions::default()).unwrap();
        let report = tools::blender_import(&path);
        // (object, atlas): the Panel in atlas 0, the Divider's back in atlas 1.
        for (object, k) in [("Panel", 0), ("Divider", 1)] {
            let mesh = find(&report["meshes"], object);
            // TEXCOORD_1 becomes the second UV map, "UVMap.001".
            assert_eq!(mesh["uv_layers"], json!(["UVMap", "UVMap.001"]), "{name}");
            let lightmapped: Vec<&Value> = mesh["materials"]
                .as_array()
                .unwrap()
                .iter()
                .map(|m| find(&report["materials"], m.as_str().unwrap()))
                .filter(|m| !m["textures"].as_array().unwrap().is_empty())
                .collect();
            assert_eq!(lightmapped.len(), 1, "{name} {object}: {mesh:#}");
            assert_eq!(
                lightmapped[0]["textures"],
                json!([{
                    "image": format!("lightmap {k}"),
                    "uv_map": "UVMap.001",
                    "interpolation": "Linear",
                    "extension": "EXTEND",
                    "feeds": [["BSDF_PRINCIPLED", "Emission Color"]],
                }]),
                "{name} {object}"
            );
        }
    }
}

#[test]
fn blender_loads_the_exr_values() {
    if !tools::have_blender() {
        return;
    }
    let dir = scratch("lm-blender-exr");
    let (scene, result) = lightmapped::scene();
    export::write(
        &dir.join("lit.glb"),
        &scene,
        &result,
        &ExportOptions::default(),
    )
    .unwrap();
    for k in 0..2 {
        let image = tools::blender_image(&support::hashed(&dir, &format!("lit.lightmap{k}.#.exr")));
        let (w, h) = lightmapped::SIZES[k];
        assert_eq!(image["size"], json!([w, h]));
        assert_eq!(
            (&image["is_float"], &image["file_format"]),
            (&json!(true), &json!("OPEN_EXR"))
        );
        let atlas = lightmapped::atlas(k);
        // Blender's rows run from the bottom: atlas row 0 (the top) is its last.
        let rows: Vec<&Value> = image["rows"].as_array().unwrap().iter().rev().collect();
        assert_eq!(rows.len(), h as usize);
        for (row, pixels) in rows.iter().enumerate() {
            for (col, px) in pixels.as_array().unwrap().iter().enumerate() {
                let want = atlas.luminance[row * w as usize + col];
                let got: Vec<f32> = (0..4).map(|c| px[c].as_f64().unwrap() as f32).collect();
                assert_eq!(got[..3], want, "atlas {k} texel ({col}, {row})");
                // No channel is taken for alpha (Blender would for one named `area`).
                assert_eq!(got[3], 1.0, "atlas {k} texel ({col}, {row}) alpha");
            }
        }
    }
}
