//! End to end on the two samples: `samples/office/office.gltf` baked to `.gltf` and
//! `samples/cornell-box/cornell-box.obj` baked to `.glb` (both `--quality draft`) by the `bake`
//! binary. Each output must pass the Khronos glTF-Validator with 0 errors and 0 warnings, and
//! import into Blender (bpy 5.0.1) with every baked value intact: per glTF node name (Blender
//! renames duplicates `top` → `top.001`, so objects are grouped by their name without the suffix)
//! the vertex count, the sorted multisets of `_ILLUMINANCE`, `_ILLUMINANCE_DIRECT` and
//! `_LUMINANCE` (32-bit floats, 1e-6 relative) and Blender's statistics of them, and `COLOR_0`
//! as Blender's 8-bit sRGB "Color" (each channel's sorted values within 1/255 of the sRGB
//! encoding of the glTF's linear value). The scene's `extras.luxbake` must arrive as the scene
//! custom property `luxbake`, energy balance included. The office input itself must validate.

mod support;

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use support::cli::{bake, repo_file};
use support::gltf_read::{self, Gltf};
use support::{scratch, tools};

const SCALARS: [&str; 3] = ["_ILLUMINANCE", "_ILLUMINANCE_DIRECT", "_LUMINANCE"];

/// Bake `input` (draft) to `dir/name`; returns the output path.
fn bake_sample(input: &str, dir: &Path, name: &str) -> PathBuf {
    let output = dir.join(name);
    let input = repo_file(input);
    let args = [input.as_os_str(), "-o".as_ref(), output.as_os_str()];
    let run = bake(
        args.into_iter()
            .chain(["--quality", "draft", "-q"].map(|s| s.as_ref())),
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    output
}

fn assert_valid(path: &Path) {
    let report = tools::validate(path);
    assert_eq!(
        (report.errors, report.warnings),
        (0, 0),
        "{}:\n{}",
        path.display(),
        report.listing()
    );
}

/// The sRGB transfer function (IEC 61966-2-1), as Blender applies it to byte colours.
fn srgb(linear: f64) -> f64 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Per-vertex values of one node name: scalar attributes and the three colour channels.
#[derive(Debug, Default)]
struct Values {
    vertices: usize,
    scalars: BTreeMap<String, Vec<f64>>,
    channels: [Vec<f64>; 3],
}

/// The glTF's values by node name (all nodes of a name, all primitives), colours as sRGB.
fn from_gltf(gltf: &Gltf) -> BTreeMap<String, Values> {
    let mut out: BTreeMap<String, Values> = BTreeMap::new();
    for node in gltf.json["nodes"].as_array().unwrap() {
        let Some(mesh) = node["mesh"].as_u64() else {
            continue;
        };
        // Luminous openings, drawn for viewers: no baked values (checked in tests/viewer.rs).
        if node["extras"]["luxbake"]["displayOnly"] == Value::Bool(true) {
            continue;
        }
        let name = node["name"]
            .as_str()
            .expect("mesh nodes are named")
            .to_string();
        let v = out.entry(name).or_default();
        for p in gltf.json["meshes"][mesh as usize]["primitives"]
            .as_array()
            .unwrap()
        {
            let a = &p["attributes"];
            let acc = |key: &str| a[key].as_u64().unwrap_or_else(|| panic!("no {key}: {a}"));
            let values = |key: &str| gltf.floats(acc(key) as usize);
            v.vertices += gltf.json["accessors"][acc("POSITION") as usize]["count"]
                .as_u64()
                .unwrap() as usize;
            for key in SCALARS {
                let list = v.scalars.entry(key.to_string()).or_default();
                list.extend(values(key).iter().map(|x| f64::from(x[0])));
            }
            for rgb in values("COLOR_0") {
                // VEC3 or VEC4: the first three components.
                for (channel, x) in v.channels.iter_mut().zip(&rgb) {
                    channel.push(srgb(f64::from(*x)));
                }
            }
        }
    }
    out
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// A Blender object name without the `.001` suffix Blender adds to duplicate names.
fn base_name(name: &str) -> &str {
    match name.rsplit_once('.') {
        Some((base, n)) if n.len() == 3 && n.bytes().all(|b| b.is_ascii_digit()) => base,
        _ => name,
    }
}

/// Blender's values by base object name, checking the attributes' domains and types.
/// `skip`: names of display-only nodes (luminous openings), which carry no baked values.
fn from_blender(report: &Value, skip: &[String]) -> BTreeMap<String, Values> {
    let mut out: BTreeMap<String, Values> = BTreeMap::new();
    for mesh in report["meshes"].as_array().unwrap() {
        let name = mesh["name"].as_str().unwrap();
        if skip.iter().any(|s| s == base_name(name)) {
            continue;
        }
        let kind = |attr: &str| {
            let a = mesh["attributes"]
                .as_array()
                .unwrap()
                .iter()
                .find(|a| a["name"] == attr);
            let a = a.unwrap_or_else(|| panic!("{name}: no attribute {attr}"));
            (
                a["domain"].as_str().unwrap(),
                a["data_type"].as_str().unwrap(),
            )
        };
        assert_eq!(kind("Color"), ("CORNER", "BYTE_COLOR"), "{name}");
        let v = out.entry(base_name(name).to_string()).or_default();
        let count = mesh["vertex_count"].as_u64().unwrap() as usize;
        v.vertices += count;
        for key in SCALARS {
            assert_eq!(kind(key), ("POINT", "FLOAT"), "{name}");
            let stats = &mesh["values"][key];
            assert_eq!(stats["count"], count, "{name} {key}");
            let first = numbers(&stats["first"]);
            assert_eq!(first.len(), count, "{name} {key}: values listed partly");
            // Blender's own statistics agree with the values it listed.
            let (min, max) = first
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
            let mean = first.iter().sum::<f64>() / count as f64;
            let close =
                |a: f64, b: &Value| (a - b.as_f64().unwrap()).abs() <= 1e-9 * a.abs().max(1.0);
            assert!(
                close(min, &stats["min"]) && close(max, &stats["max"]),
                "{name} {key}"
            );
            assert!(
                close(mean, &stats["mean"]),
                "{name} {key}: mean {mean} vs {}",
                stats["mean"]
            );
            v.scalars.entry(key.to_string()).or_default().extend(first);
        }
        let colors = mesh["values"]["Color"]["vertex_srgb"].as_array().unwrap();
        assert_eq!(colors.len(), count, "{name} Color");
        for rgb in colors {
            for (channel, x) in v.channels.iter_mut().zip(numbers(rgb)) {
                channel.push(x);
            }
        }
    }
    out
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

/// Import `path` in Blender and compare what it holds with the glTF file's own values; returns
/// Blender's report.
fn check_blender(path: &Path, expected_emitted_lm: f64) -> Value {
    let gltf = gltf_read::read(path);
    let report = tools::blender_import(path);
    let shown: Vec<String> = (gltf.json["nodes"].as_array().unwrap().iter())
        .filter(|n| n["extras"]["luxbake"]["displayOnly"] == Value::Bool(true))
        .map(|n| n["name"].as_str().unwrap().to_string())
        .collect();
    // Each photometric luminaire's opening is drawn: the office's six fittings and spotlight.
    assert_eq!(
        shown.len(),
        gltf.json["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|n| n["extensions"]["LUXBAKE_luminaire"].is_object())
            .count()
    );
    let (want, got) = (from_gltf(&gltf), from_blender(&report, &shown));
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        want.keys().collect::<Vec<_>>(),
        "mesh objects in Blender vs mesh nodes in the glTF"
    );
    for (name, w) in &want {
        let g = &got[name];
        assert_eq!(g.vertices, w.vertices, "{name}: vertex count");
        for key in SCALARS {
            let (a, b) = (
                sorted(g.scalars[key].clone()),
                sorted(w.scalars[key].clone()),
            );
            assert_eq!(a.len(), b.len(), "{name} {key}");
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= 1e-6 * y.abs().max(1.0),
                    "{name} {key}: {x} vs {y}"
                );
            }
        }
        for c in 0..3 {
            let (a, b) = (sorted(g.channels[c].clone()), sorted(w.channels[c].clone()));
            assert_eq!(a.len(), b.len(), "{name} Color");
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= 1.0 / 255.0 + 1e-6,
                    "{name} Color[{c}]: {x} vs {y}"
                );
            }
        }
    }

    let summary = &gltf.json["scenes"][0]["extras"]["luxbake"];
    let property = &report["scene"]["properties"]["luxbake"];
    assert_eq!(property, summary, "scene custom property `luxbake`");
    let e = &property["energy"];
    let lm = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("energy.{k}: {e}"));
    let emitted = lm("emittedLm");
    assert!(
        (emitted - expected_emitted_lm).abs() <= 0.01 * expected_emitted_lm,
        "{e}"
    );
    let error = emitted - lm("absorbedLm") - lm("escapedLm");
    assert!(
        (error - lm("balanceErrorLm")).abs() <= 1e-6 * emitted,
        "{e}"
    );
    assert!(
        (lm("balanceErrorRelative") - error.abs() / emitted).abs() < 1e-9,
        "{e}"
    );
    report
}

fn object_types(report: &Value) -> Vec<(String, String)> {
    let objects = report["objects"].as_array().unwrap().iter();
    objects
        .map(|o| (o["name"].to_string(), o["type"].to_string()))
        .collect()
}

#[test]
fn office_input_is_valid() {
    if tools::have_validator() {
        assert_valid(&repo_file("samples/office/office.gltf"));
    }
}

#[test]
fn office_bakes_to_a_valid_gltf_that_blender_imports() {
    let dir = scratch("samples-office");
    let output = bake_sample("samples/office/office.gltf", &dir, "office-lit.gltf");
    if tools::have_validator() {
        assert_valid(&output);
    }
    if tools::have_blender() {
        // Six fluorescents of 3380 lm and the 792 lm spotlight (from their profiles).
        let types = object_types(&check_blender(&output, 6.0 * 3380.0 + 792.0));
        for (name, kind) in [
            ("spotlight", "EMPTY"),
            ("luminaire_1_light", "EMPTY"),
            ("desk_dark", "EMPTY"),
        ] {
            let pair = (format!("\"{name}\""), format!("\"{kind}\""));
            assert!(types.contains(&pair), "{name} {kind}: {types:?}");
        }
    }
}

#[test]
fn cornell_box_bakes_to_a_valid_glb_that_blender_imports() {
    let dir = scratch("samples-cornell");
    let output = bake_sample(
        "samples/cornell-box/cornell-box.obj",
        &dir,
        "cornell-lit.glb",
    );
    if tools::have_validator() {
        assert_valid(&output);
    }
    if tools::have_blender() {
        // π · 9999.98 cd/m² · 0.01365 m² (samples/cornell-box/README.md).
        check_blender(&output, std::f64::consts::PI * 9999.98 * 0.01365);
    }
}
