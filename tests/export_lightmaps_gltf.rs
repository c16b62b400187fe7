//! The glTF side of a lightmapped output (`support/lightmapped.rs`): material variants (emissive
//! display by default, lit materials kept with `--keep-lit-materials`), the attributes of
//! lightmapped primitives, the display PNG and its sampler, and `LUXBAKE_lightmap` against
//! `schemas/LUXBAKE_lightmap.schema.json`.

mod support;

use luxbake::{export, export::ExportOptions};
use serde_json::{Value, json};
use std::path::Path;
use support::{gltf_read, lightmapped, scratch};

fn write(path: &Path, options: &ExportOptions) {
    let (scene, result) = lightmapped::scene();
    export::write(path, &scene, &result, options).unwrap();
}

fn index(v: &Value) -> usize {
    v.as_u64().unwrap() as usize
}

#[test]
fn materials_attributes_and_display_texture() {
    let dir = scratch("lm-json");
    write(&dir.join("lit.gltf"), &ExportOptions::default());
    let g = gltf_read::read(&dir.join("lit.gltf"));
    let j = &g.json;
    let used = j["extensionsUsed"].as_array().unwrap();
    for e in ["LUXBAKE_lightmap", "MOZ_lightmap", "LUXBAKE_material"] {
        assert!(used.contains(&json!(e)), "{used:?}");
    }
    assert!(j.get("extensionsRequired").is_none());
    // Originals keep their places; variants follow by (material, atlas).
    let materials = j["materials"].as_array().unwrap();
    assert_eq!(materials.len(), 4);
    assert_eq!(materials[2]["name"], "Textured");
    assert_eq!(materials[3]["name"], "TwoSided");
    let panel = &j["meshes"][0]["primitives"][0];
    let front = &j["meshes"][1]["primitives"][0];
    let back = &j["meshes"][1]["primitives"][1];
    assert_eq!(
        [&panel["material"], &front["material"], &back["material"]],
        [2, 1, 3]
    );
    assert!(front["attributes"].get("COLOR_0").is_some());
    for p in [panel, back] {
        let a = p["attributes"].as_object().unwrap();
        assert!(a.get("COLOR_0").is_none(), "{a:?}");
        for key in [
            "_ILLUMINANCE",
            "_ILLUMINANCE_DIRECT",
            "_LUMINANCE",
            "TEXCOORD_1",
        ] {
            assert!(a.contains_key(key), "{key}");
        }
    }
    let uv1 = g.floats(index(&panel["attributes"]["TEXCOORD_1"]));
    assert_eq!(uv1, [[0.0, 1.0], [0.5, 1.0], [0.5, 0.0], [0.0, 0.0]]);
    // No uv0 on the back: TEXCOORD_0 is the layout too (sets start at 0).
    assert_eq!(
        back["attributes"]["TEXCOORD_0"],
        back["attributes"]["TEXCOORD_1"]
    );

    let m = &materials[2];
    let pbr = &m["pbrMetallicRoughness"];
    assert_eq!(
        pbr,
        &json!({"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0})
    );
    assert_eq!(m["emissiveFactor"], json!([0.8, 0.7, 0.6]));
    let texture = index(&m["emissiveTexture"]["index"]);
    assert_eq!(m["emissiveTexture"]["texCoord"], 1);
    assert_eq!(
        m["extensions"]["MOZ_lightmap"],
        json!({"index": texture, "texCoord": 1, "intensity": 1.0})
    );
    let keys: Vec<&String> = m["extensions"].as_object().unwrap().keys().collect();
    assert_eq!(
        keys,
        ["LUXBAKE_lightmap", "LUXBAKE_material", "MOZ_lightmap"]
    );
    assert_eq!(
        m["extensions"]["LUXBAKE_material"],
        json!({"reflectance": [0.4, 0.4, 0.4], "emission": {"luminance": 0.0}})
    );
    let original = &m["extras"]["luxbake"]["original"];
    assert_eq!(
        original["baseColorTexture"],
        json!({"index": 0, "texCoord": 0})
    );
    assert_eq!(original["baseColorFactor"], json!([0.8, 0.7, 0.6, 1.0]));
    assert_eq!(original["emissiveStrength"], 2.0);
    assert_eq!(m["extras"]["luxbake"]["variantOf"], 0);
    assert_eq!(m["extras"]["author"], "fixture");
    // The two-sided material, baked on both sides, is single-sided as its original.
    assert_eq!(materials[3]["doubleSided"], false);

    let ext = &m["extensions"]["LUXBAKE_lightmap"];
    let exr = support::hashed(&dir, "lit.lightmap0.#.exr");
    let uri = exr.file_name().unwrap().to_str().unwrap();
    assert_eq!(
        ext,
        &json!({"atlas": 0, "uri": uri, "texCoord": 1, "width": 8, "height": 4,
                "texelSize": 0.25, "display": texture,
                "exposure": {"whiteIlluminanceLx": 400.0,
                             "rule": "COLOR_0 = shoulder(E_rgb / whiteIlluminanceLx)"},
                "channels": {"R": "cd/m2", "G": "cd/m2", "B": "cd/m2", "illuminance": "lx",
                             "illuminanceDirect": "lx", "footprint": "m2"}})
    );
    check_schema(ext);

    let tex = &j["textures"][texture];
    assert_eq!(
        j["samplers"][index(&tex["sampler"])],
        json!({"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071})
    );
    let image = &j["images"][index(&tex["source"])];
    assert_eq!(image["mimeType"], "image/png");
    let view = &j["bufferViews"][index(&image["bufferView"])];
    let at = index(&view["byteOffset"]);
    let png = &g.bin[at..at + index(&view["byteLength"])];
    let mut reader = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!(
        (info.width, info.height, info.color_type),
        (8, 4, png::ColorType::Rgb)
    );
    // Row 0 first; sRGB-encoded: col/7 red, row/3 green, 0.5 blue → 188.
    let srgb = |x: f64| (255.0 * (1.055 * x.powf(1.0 / 2.4) - 0.055)).round() as u8;
    let at = |col: usize, row: usize| &pixels[3 * (row * 8 + col)..3 * (row * 8 + col) + 3];
    assert_eq!(at(0, 0), [0, 0, 188]);
    assert_eq!(at(7, 3), [255, 255, 188]);
    assert_eq!(at(3, 1), [srgb(3.0 / 7.0), srgb(1.0 / 3.0), 188]);
}

/// Every member written is in the schema, every required one is written.
fn check_schema(ext: &Value) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("schemas/LUXBAKE_lightmap.schema.json");
    let schema: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let properties = schema["properties"].as_object().unwrap();
    for (key, value) in ext.as_object().unwrap() {
        let p = properties
            .get(key)
            .unwrap_or_else(|| panic!("{key} not in the schema"));
        let kind = match value {
            Value::String(_) => "string",
            Value::Number(n) if n.is_u64() => "integer",
            Value::Number(_) => "number",
            Value::Object(_) => "object",
            other => panic!("{key}: unexpected {other}"),
        };
        let allowed = p["type"].as_str().unwrap();
        assert!(
            allowed == kind || (allowed == "number" && kind == "integer"),
            "{key}"
        );
    }
    for key in schema["required"].as_array().unwrap() {
        assert!(ext.get(key.as_str().unwrap()).is_some(), "{key} missing");
    }
    assert_eq!(schema["additionalProperties"], false);
}

#[test]
fn lit_materials_keep_their_textures() {
    let dir = scratch("lm-lit");
    let options = ExportOptions {
        unlit: false,
        ..Default::default()
    };
    write(&dir.join("lit.gltf"), &options);
    let j = gltf_read::read(&dir.join("lit.gltf")).json;
    let (original, variant) = (&j["materials"][0], &j["materials"][2]);
    assert_eq!(
        variant["pbrMetallicRoughness"],
        original["pbrMetallicRoughness"]
    );
    assert_eq!(variant["emissiveFactor"], original["emissiveFactor"]);
    let mut ext = variant["extensions"].as_object().unwrap().clone();
    assert!(ext.remove("MOZ_lightmap").is_some() && ext.remove("LUXBAKE_lightmap").is_some());
    assert_eq!(Value::Object(ext), original["extensions"]);
}

/// Baking the output anew reads the photometry of the input, not the black emissive display.
#[test]
fn variants_read_back_as_their_input_materials() {
    let dir = scratch("lm-reimport");
    let path = dir.join("lit.glb");
    write(&path, &ExportOptions::default());
    let scene = luxbake::import::load(&path, &Default::default()).unwrap();
    let (input, _) = lightmapped::scene();
    for (variant, original) in [(2, 0), (3, 1)] {
        let (v, o) = (&scene.materials[variant], &input.materials[original]);
        assert_eq!(v.reflectance, o.reflectance, "material {variant}");
        assert!(v.emission.is_none(), "material {variant}");
    }
}
