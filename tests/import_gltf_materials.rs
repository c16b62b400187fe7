//! Integration tests of glTF materials and KHR_lights_punctual lights through
//! `luxbake::import::load`.

mod common;

use common::*;
use glam::DVec3;
use luxbake::scene::{
    AlphaMode, EmissionAmount, LightKind, Material, ReflectanceSource, Scene, TextureRef,
};
use serde_json::{Value, json};
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_4};
use std::path::Path;

/// One triangle primitive per material, all on one node.
fn material_builder(materials: Vec<Value>) -> Builder {
    let mut b = Builder::new();
    let position = b.vec3s(&TRIANGLE);
    let primitives = (0..materials.len())
        .map(|m| json!({"attributes": {"POSITION": position}, "material": m}))
        .collect();
    let mesh = b.mesh(primitives);
    b.node(json!({"mesh": mesh}));
    b.set("scenes", json!([{"nodes": [0]}]));
    for m in materials {
        b.material(m);
    }
    b
}

fn load_materials(dir: &Path, name: &str, b: &Builder) -> Scene {
    load_ok(&b.write_gltf(dir, name, Bin::DataUri))
}

fn luminance(m: &Material) -> f64 {
    match m.emission.expect("emission").amount {
        EmissionAmount::Luminance(l) => l,
        other => panic!("luminance expected, got {other:?}"),
    }
}

#[test]
fn luxbake_extension_reflectance_and_emission() {
    let dir = tempfile::tempdir().unwrap();
    let ext = |v: Value| json!({"extensions": {"LUXBAKE_material": v}});
    let mut b = material_builder(vec![
        ext(json!({"reflectance": 0.7})),
        ext(json!({"reflectance": [0.1, 0.2, 0.3]})),
        json!({"extensions": {"LUXBAKE_material": {"emission": {"luminance": 250}}},
               "emissiveFactor": [1, 1, 1],
               "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}),
        ext(json!({"reflectance": 0.2,
                   "emission": {"luminousFlux": 1000, "color": [1, 0.5, 0.25]}})),
        ext(json!({"reflectance": 0.2, "emission": {"luminance": 0}})),
    ]);
    b.set("extensionsUsed", json!(["LUXBAKE_material"]));
    b.set("extensionsRequired", json!(["LUXBAKE_material"]));
    let scene = load_materials(dir.path(), "ext.gltf", &b);
    let m = &scene.materials;
    assert_eq!(m.len(), 5, "no default material needed");

    assert_close(m[0].reflectance, DVec3::splat(0.7), "scalar reflectance");
    assert_eq!(m[0].reflectance_source, ReflectanceSource::Extension);
    assert_eq!(
        m[0].display.luxbake_extension,
        Some(json!({"reflectance": 0.7}))
    );
    assert!(m[0].emission.is_none());
    assert_close(
        m[1].reflectance,
        DVec3::new(0.1, 0.2, 0.3),
        "RGB reflectance",
    );

    // The extension's emission wins over emissiveFactor; reflectance falls back to baseColor.
    assert_near(luminance(&m[2]), 250.0, "luminance");
    assert_close(m[2].emission.unwrap().color, DVec3::ONE, "default white");
    assert_close(m[2].reflectance, DVec3::splat(0.5), "baseColor reflectance");
    assert_eq!(m[2].reflectance_source, ReflectanceSource::BaseColor);

    let e = m[3].emission.unwrap();
    assert_eq!(e.amount, EmissionAmount::LuminousFlux(1000.0));
    let y = 0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25;
    assert_close(
        e.color,
        DVec3::new(1.0, 0.5, 0.25) / y,
        "colour normalised to Y = 1",
    );
    assert!(m[4].emission.is_none(), "zero luminance emits nothing");
}

#[test]
fn base_color_times_texture_mean_times_one_minus_metallic() {
    let dir = tempfile::tempdir().unwrap();
    // Half pure red, half pure blue: mean linear colour (0.5, 0, 0.5).
    let png = png(4, 2, |x, _| if x < 2 { [255, 0, 0] } else { [0, 0, 255] });
    std::fs::write(dir.path().join("tex.png"), &png).unwrap();
    let material = json!({"name": "painted", "doubleSided": true, "alphaMode": "MASK",
        "alphaCutoff": 0.3, "extras": {"note": "kept"},
        "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1],
            "baseColorTexture": {"index": 0, "texCoord": 1}, "metallicFactor": 0.25,
            "roughnessFactor": 0.9},
        "normalTexture": {"index": 0, "scale": 0.5}});
    let mut b = material_builder(vec![material]);
    b.set("textures", json!([{"source": 0, "sampler": 0}]));
    b.set("samplers", json!([{"magFilter": 9729, "wrapS": 33648}]));
    b.set("images", json!([{"uri": "tex.png"}]));
    let expected = DVec3::new(0.8 * 0.5 * 0.75, 0.0, 0.4 * 0.5 * 0.75);

    let scene = load_materials(dir.path(), "tex.gltf", &b);
    let m = &scene.materials[0];
    assert_close(m.reflectance, expected, "reflectance from a texture file");
    assert_eq!(m.reflectance_source, ReflectanceSource::BaseColor);
    assert!(m.double_sided);
    assert_eq!(m.name.as_deref(), Some("painted"));
    assert_eq!(m.extras, Some(json!({"note": "kept"})));
    let d = &m.display;
    assert_eq!(d.alpha_mode, AlphaMode::Mask);
    assert_eq!(d.alpha_cutoff, Some(0.3));
    assert_eq!(d.base_color_factor, [0.8, 0.6, 0.4, 1.0]);
    assert_eq!((d.metallic_factor, d.roughness_factor), (0.25, 0.9));
    let tex = |tex_coord, scale| {
        Some(TextureRef {
            texture: 0,
            tex_coord,
            scale,
        })
    };
    assert_eq!(d.base_color_texture, tex(1, 1.0));
    assert_eq!(d.normal_texture, tex(0, 0.5));
    assert_eq!(scene.images[0].mime_type, "image/png");
    assert_eq!(scene.images[0].bytes, png);
    assert_eq!(scene.textures[0].image, 0);
    assert_eq!(scene.textures[0].sampler, Some(0));
    let s = scene.samplers[0];
    assert_eq!((s.mag_filter, s.min_filter), (Some(9729), None));
    assert_eq!((s.wrap_s, s.wrap_t), (Some(33648), None));
    let png_path = dir.path().join("tex.png").canonicalize().unwrap();
    assert!(scene.input_files.contains(&png_path));

    // The same image embedded through a bufferView of a .glb.
    let view = b.view(&png);
    b.set(
        "images",
        json!([{"bufferView": view, "mimeType": "image/png"}]),
    );
    let scene = load_ok(&b.write_glb(dir.path(), "tex.glb"));
    assert_close(
        scene.materials[0].reflectance,
        expected,
        "reflectance from a bufferView",
    );
    assert_eq!(scene.images[0].bytes, png);
}

#[test]
fn default_metallic_makes_black_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let b = material_builder(vec![
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}}),
    ]);
    let scene = load_materials(dir.path(), "metal.gltf", &b);
    assert_close(scene.materials[0].reflectance, DVec3::ZERO, "black");
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("/materials/0") && w.contains("metallicFactor")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn emissive_factor_and_strength_give_luminance() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = material_builder(vec![
        json!({"emissiveFactor": [1, 0.5, 0.25],
               "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 100}},
               "pbrMetallicRoughness": {"metallicFactor": 0, "baseColorFactor": [0.2, 0.2, 0.2, 1]}}),
        json!({"emissiveFactor": [0.2, 0.2, 0.2], "pbrMetallicRoughness": {"metallicFactor": 1}}),
        json!({"pbrMetallicRoughness": {"metallicFactor": 1}}),
    ]);
    b.set("extensionsUsed", json!(["KHR_materials_emissive_strength"]));
    let scene = load_materials(dir.path(), "emissive.gltf", &b);
    let m = &scene.materials;
    let y = 0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25;
    assert_near(luminance(&m[0]), 100.0 * y, "Y(emissiveFactor) × strength");
    assert_close(
        m[0].emission.unwrap().color,
        DVec3::new(1.0, 0.5, 0.25) / y,
        "colour",
    );
    assert_eq!(m[0].display.emissive_strength, Some(100.0));
    assert_eq!(m[0].display.emissive_factor, [1.0, 0.5, 0.25]);
    assert_near(luminance(&m[1]), 0.2, "no strength: factor alone, cd/m²");
    assert!(m[2].emission.is_none(), "zero emissive");
}

#[test]
fn punctual_lights_in_world_space() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    let h = FRAC_1_SQRT_2;
    b.set("extensionsUsed", json!(["KHR_lights_punctual"]));
    b.set(
        "extensions",
        json!({"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": 50, "color": [1, 0, 0], "range": 10, "name": "bulb"},
            {"type": "spot", "intensity": 200, "spot": {}},
            {"type": "directional", "intensity": 1000}
        ]}}),
    );
    let light = |l: usize| json!({"KHR_lights_punctual": {"light": l}});
    // Point: scaled ×10 (must not change intensity). Spot: turned to point down.
    b.node(json!({"translation": [1, 2, 3], "scale": [10, 10, 10], "extensions": light(0)}));
    b.node(json!({"translation": [0, 3, 0], "rotation": [-h, 0, 0, h], "extensions": light(1)}));
    // Directional: a parent turns 90° about +Y, the child −90° about X; −Z ends up at −Y.
    b.node(json!({"rotation": [0, h, 0, h], "scale": [3, 3, 3], "children": [4]}));
    b.node(json!({"rotation": [-h, 0, 0, h], "extensions": light(2)}));
    b.json["scenes"][0]["nodes"] = json!([0, 1, 2, 3]);
    let scene = load_ok(&b.write_gltf(dir.path(), "lights.gltf", Bin::DataUri));
    assert_eq!(scene.lights.len(), 3);

    let point = &scene.lights[0];
    assert_eq!(point.kind, LightKind::Point);
    assert_eq!(point.name.as_deref(), Some("bulb"));
    assert_eq!(
        point.source_path,
        "/extensions/KHR_lights_punctual/lights/0"
    );
    assert_near(point.intensity, 50.0, "node scale does not scale intensity");
    assert_close(
        point.color,
        DVec3::new(1.0 / 0.2126, 0.0, 0.0),
        "colour Y = 1",
    );
    assert_close(point.position, DVec3::new(1.0, 2.0, 3.0), "point position");
    assert_eq!(point.range, Some(10.0));
    assert_eq!((point.node, scene.nodes[1].light), (1, Some(0)));

    let spot = &scene.lights[1];
    let LightKind::Spot {
        inner_cone_angle,
        outer_cone_angle,
    } = spot.kind
    else {
        panic!("spot expected");
    };
    assert_eq!((inner_cone_angle, outer_cone_angle), (0.0, FRAC_PI_4));
    assert_close(spot.direction, DVec3::NEG_Y, "spot points down");
    assert_close(spot.position, DVec3::new(0.0, 3.0, 0.0), "spot position");
    assert_close(spot.color, DVec3::ONE, "default white");

    let sun = &scene.lights[2];
    assert_eq!(sun.kind, LightKind::Directional);
    assert_near(sun.intensity, 1000.0, "lx");
    assert_close(
        sun.direction,
        DVec3::NEG_Y,
        "directional through a rotated parent",
    );
    assert_near(
        sun.direction.length(),
        1.0,
        "unit direction despite parent scale",
    );
    assert_eq!(scene.nodes[4].light, Some(2));
}

#[test]
fn invalid_lights_are_errors_naming_the_light() {
    let dir = tempfile::tempdir().unwrap();
    for (i, light) in [
        json!({"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.5}}),
        json!({"type": "spot", "spot": {"outerConeAngle": 1.6}}),
        json!({"type": "point", "color": [0, 0, 0]}),
        json!({"type": "point", "intensity": -1}),
        json!({"type": "spot"}),
        json!({"type": "area"}),
    ]
    .into_iter()
    .enumerate()
    {
        let mut b = triangle_builder();
        b.set("extensionsUsed", json!(["KHR_lights_punctual"]));
        b.set(
            "extensions",
            json!({"KHR_lights_punctual": {"lights": [{"type": "point"}, light]}}),
        );
        b.node(json!({"extensions": {"KHR_lights_punctual": {"light": 1}}}));
        b.json["scenes"][0]["nodes"] = json!([0, 1]);
        let (at, message) =
            load_err(&b.write_gltf(dir.path(), &format!("l{i}.gltf"), Bin::DataUri));
        // A missing `spot` object or an unknown type is caught by glTF validation, one level
        // deeper (`.../lights/1/spot`, `.../lights/1/type`).
        assert!(
            at.starts_with("/extensions/KHR_lights_punctual/lights/1"),
            "{message}"
        );
        assert!(message.contains(&format!("{at}: ")), "{message}");
        eprintln!("{message}");
    }
}
