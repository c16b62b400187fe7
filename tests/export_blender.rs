//! Blender's glTF importer (PyPI `bpy` 5.0.1) on the exporter's output: the baked attributes
//! arrive with their values, and node and scene extras become custom properties.
//!
//! Blender keeps `COLOR_0` as the 8-bit corner attribute "Color", stored sRGB-encoded (Blender
//! converts the linear glTF value to sRGB, then quantises to a byte), so the check is
//! |srgb(expected) − stored sRGB| ≤ 1/255. `_ILLUMINANCE` / `_LUMINANCE` are 32-bit floats in the
//! point domain, compared to 1e-6 relative.

mod support;

use luxbake::{export, export::ExportOptions, result::BakeResult, scene::Scene};
use serde_json::Value;
use support::{fixture, scratch, tools};

/// The sRGB transfer function (IEC 61966-2-1), as Blender applies it to byte colours.
fn srgb(linear: f32) -> f64 {
    let c = f64::from(linear);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Check one Blender mesh object against the baked sides of its node, in primitive order.
fn check_mesh(report: &Value, scene: &Scene, result: &BakeResult, node: usize, baked: &[usize]) {
    let name = scene.nodes[node].name.as_deref().unwrap();
    let mesh = report["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == name)
        .unwrap_or_else(|| panic!("no mesh object {name} in {report:#}"));
    assert_eq!(
        mesh["mesh"].as_str(),
        scene.nodes[node].mesh_name.as_deref()
    );
    let sides: Vec<_> = baked.iter().map(|&b| &result.surfaces[b]).collect();
    let n: usize = sides.iter().map(|b| b.positions.len()).sum();
    assert_eq!(mesh["vertex_count"], n, "{name}");

    let attr = |a: &str| {
        let found = mesh["attributes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["name"] == a);
        let found = found.unwrap_or_else(|| panic!("{name}: no attribute {a}: {mesh:#}"));
        (
            found["domain"].as_str().unwrap(),
            found["data_type"].as_str().unwrap(),
        )
    };
    assert_eq!(attr("_ILLUMINANCE"), ("POINT", "FLOAT"));
    assert_eq!(attr("_LUMINANCE"), ("POINT", "FLOAT"));
    assert_eq!(attr("Color"), ("CORNER", "BYTE_COLOR"));

    for (key, expected) in [
        (
            "_ILLUMINANCE",
            sides
                .iter()
                .flat_map(|b| b.illuminance.clone())
                .collect::<Vec<_>>(),
        ),
        (
            "_LUMINANCE",
            sides.iter().flat_map(|b| b.luminance.clone()).collect(),
        ),
    ] {
        let got = floats(&mesh["values"][key]["first"]);
        assert_eq!(got.len(), expected.len(), "{name} {key}");
        for (g, e) in got.iter().zip(&expected) {
            let e = f64::from(*e);
            assert!(
                (g - e).abs() <= 1e-6 * e.abs().max(1.0),
                "{name} {key}: {got:?} vs {expected:?}"
            );
        }
    }
    let colors = mesh["values"]["Color"]["vertex_srgb"].as_array().unwrap();
    let expected: Vec<[f32; 3]> = sides.iter().flat_map(|b| b.color.clone()).collect();
    assert_eq!(colors.len(), expected.len(), "{name} Color");
    for (i, (got, want)) in colors.iter().zip(&expected).enumerate() {
        let got = floats(got);
        for c in 0..3 {
            let diff = (got[c] - srgb(want[c])).abs();
            assert!(
                diff <= 1.0 / 255.0 + 1e-6,
                "{name} vertex {i} channel {c}: {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn blender_imports_baked_attributes_and_properties() {
    if !tools::have_blender() {
        return;
    }
    let (scene, result) = fixture::scene();
    let dir = scratch("blender");
    for name in ["room.gltf", "room.glb"] {
        let path = dir.join(name);
        export::write(&path, &scene, &result, &ExportOptions::default()).unwrap();
        let report = tools::blender_import(&path);

        check_mesh(&report, &scene, &result, 1, &[0]);
        check_mesh(&report, &scene, &result, 2, &[1, 2]);

        let panel = report["meshes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == "Panel")
            .unwrap();
        assert_eq!(
            &panel["properties"],
            scene.nodes[1].extras.as_ref().unwrap(),
            "{name}"
        );
        let props = &report["scene"]["properties"];
        let summary = serde_json::to_value(&result.summary).unwrap();
        assert_eq!(props["luxbake"], summary, "{name}");
        assert_eq!(props["project"], "test room", "{name}");

        let kinds: Vec<(&str, &str)> = report["objects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| (o["name"].as_str().unwrap(), o["type"].as_str().unwrap()))
            .collect();
        for expected in [("Room", "EMPTY"), ("Spot", "LIGHT"), ("Camera", "CAMERA")] {
            assert!(kinds.contains(&expected), "{name}: {kinds:?}");
        }
    }
}
