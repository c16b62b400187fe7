//! The output's materials, textures, images and samplers.
//!
//! Input: the [`Scene`]'s materials and texture data, which materials were baked with a back
//! side, and the [`ExportOptions`]. Output: the `materials`, `textures`, `images` and `samplers`
//! JSON arrays (images embedded in the [`Binary`] with their mimeType, whatever the input did).
//! Invariants: every scene material is written, in order, with its name and extras; the input's
//! `LUXBAKE_material` object is kept under `extensions` (with unlit, under
//! `extras.luxbake.original`, because the validator warns about any extension beside unlit), its
//! `emission.profile` set to the output index of the emission's profile. With `unlit` (default) a material gets
//! `KHR_materials_unlit`, the spec's fallback metallic 0 / roughness 1, emissive zeroed and
//! `KHR_materials_emissive_strength` dropped (it is forbidden with unlit), an emitting material's
//! base colour its emission colour scaled to a largest channel of 1 (`Material::display_base`:
//! COLOR_0 then shows its luminance) and its base colour texture dropped; a material baked with a
//! back side is written single-sided (each face has its own primitive). Every changed value is
//! kept in `extras.luxbake.original`; `extras.luxbake` also records the reflectance used.

use super::{ExportOptions, buffer::Binary, extras::with_luxbake, luminaires::Profiles};
use crate::scene::{AlphaMode, Material, Scene, TextureRef};
use serde_json::{Map, Value, json};

pub const UNLIT: &str = "KHR_materials_unlit";
pub const EMISSIVE_STRENGTH: &str = "KHR_materials_emissive_strength";
pub const LUXBAKE_MATERIAL: &str = "LUXBAKE_material";

/// The `materials` array; `back_baked[i]` tells whether material `i` got back-side primitives.
/// `profiles` gives the output index of emission profiles.
pub(crate) fn materials(
    scene: &Scene,
    back_baked: &[bool],
    options: &ExportOptions,
    profiles: &Profiles,
) -> Vec<Value> {
    scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let back_baked = back_baked.get(i).copied().unwrap_or(false);
            material(m, back_baked, options, profiles)
        })
        .collect()
}

/// Material `m` written lit (PBR, as `--keep-lit-materials` writes it), whatever the options.
pub(crate) fn lit(m: &Material, back_baked: bool, profiles: &Profiles) -> Value {
    let options = ExportOptions {
        unlit: false,
        probe_glyphs: None,
    };
    material(m, back_baked, &options, profiles)
}

/// The material's `LUXBAKE_material` object with `emission.profile` pointing into the output.
fn luxbake_extension(m: &Material, profiles: &Profiles) -> Option<Value> {
    let mut ext = m.display.luxbake_extension.clone()?;
    let output_index = m
        .emission
        .and_then(|e| e.profile)
        .and_then(|p| profiles.luxbake_index(p));
    if let (Some(k), Some(emission)) = (
        output_index,
        ext.get_mut("emission").and_then(Value::as_object_mut),
    ) {
        emission.insert("profile".into(), json!(k));
    }
    Some(ext)
}

fn material(m: &Material, back_baked: bool, options: &ExportOptions, profiles: &Profiles) -> Value {
    let d = &m.display;
    let luxbake_ext = luxbake_extension(m, profiles);
    let (metallic, roughness, emissive, strength) = if options.unlit {
        (0.0, 1.0, [0.0; 3], None)
    } else {
        (
            d.metallic_factor,
            d.roughness_factor,
            d.emissive_factor,
            d.emissive_strength,
        )
    };
    let double_sided = m.double_sided && !back_baked;

    let mut out = Map::new();
    if let Some(name) = &m.name {
        out.insert("name".into(), json!(name));
    }
    // Unlit, an emitting material shows COLOR_0 over its emission colour (white for white
    // light), not over its reflectance: a source must not look darker than what it lights.
    let shows_emission = options.unlit && m.emission.is_some();
    let base_color = match shows_emission {
        true => {
            let [r, g, b] = m.display_base().to_array();
            [r, g, b, d.base_color_factor[3]]
        }
        false => d.base_color_factor,
    };
    let mut pbr = Map::new();
    pbr.insert("baseColorFactor".into(), json!(base_color));
    if let Some(t) = d.base_color_texture.as_ref().filter(|_| !shows_emission) {
        pbr.insert("baseColorTexture".into(), texture_info(t, None));
    }
    pbr.insert("metallicFactor".into(), json!(metallic));
    pbr.insert("roughnessFactor".into(), json!(roughness));
    if let Some(t) = &d.metallic_roughness_texture {
        pbr.insert("metallicRoughnessTexture".into(), texture_info(t, None));
    }
    out.insert("pbrMetallicRoughness".into(), Value::Object(pbr));
    if let Some(t) = &d.normal_texture {
        out.insert("normalTexture".into(), texture_info(t, Some("scale")));
    }
    if let Some(t) = &d.occlusion_texture {
        out.insert("occlusionTexture".into(), texture_info(t, Some("strength")));
    }
    if let Some(t) = &d.emissive_texture {
        out.insert("emissiveTexture".into(), texture_info(t, None));
    }
    out.insert("emissiveFactor".into(), json!(emissive));
    match d.alpha_mode {
        AlphaMode::Opaque => {}
        AlphaMode::Mask => {
            out.insert("alphaMode".into(), json!("MASK"));
            if let Some(c) = d.alpha_cutoff {
                out.insert("alphaCutoff".into(), json!(c));
            }
        }
        AlphaMode::Blend => {
            out.insert("alphaMode".into(), json!("BLEND"));
        }
    }
    out.insert("doubleSided".into(), json!(double_sided));

    // Extension names are inserted in sorted order.
    let mut extensions = Map::new();
    if let Some(s) = strength {
        extensions.insert(EMISSIVE_STRENGTH.into(), json!({ "emissiveStrength": s }));
    }
    if options.unlit {
        extensions.insert(UNLIT.into(), json!({}));
    }
    // The validator warns when KHR_materials_unlit shares a material with any other extension,
    // so with unlit the LUXBAKE_material object moves to extras.luxbake.original (where the
    // importer finds it again when the output is baked anew).
    if let Some(ext) = luxbake_ext.as_ref().filter(|_| !options.unlit) {
        extensions.insert(LUXBAKE_MATERIAL.into(), ext.clone());
    }
    if !extensions.is_empty() {
        out.insert("extensions".into(), Value::Object(extensions));
    }

    let mut luxbake = Map::new();
    luxbake.insert("reflectance".into(), json!(m.reflectance.to_array()));
    luxbake.insert("reflectanceSource".into(), json!(m.reflectance_source));
    let mut original = Map::new();
    if options.unlit {
        original.insert("baseColorFactor".into(), json!(d.base_color_factor));
        if let Some(t) = d.base_color_texture.as_ref().filter(|_| shows_emission) {
            original.insert("baseColorTexture".into(), texture_info(t, None));
        }
        original.insert("metallicFactor".into(), json!(d.metallic_factor));
        original.insert("roughnessFactor".into(), json!(d.roughness_factor));
        original.insert("emissiveFactor".into(), json!(d.emissive_factor));
        if let Some(s) = d.emissive_strength {
            original.insert("emissiveStrength".into(), json!(s));
        }
        if let Some(ext) = &luxbake_ext {
            original.insert(LUXBAKE_MATERIAL.into(), ext.clone());
        }
    }
    if options.unlit || double_sided != m.double_sided {
        original.insert("doubleSided".into(), json!(m.double_sided));
    }
    if !original.is_empty() {
        luxbake.insert("original".into(), Value::Object(original));
    }
    out.insert(
        "extras".into(),
        with_luxbake(m.extras.as_ref(), Value::Object(luxbake)),
    );
    Value::Object(out)
}

/// A textureInfo object; `scale_key` is `"scale"` (normal) or `"strength"` (occlusion).
fn texture_info(t: &TextureRef, scale_key: Option<&str>) -> Value {
    let mut info = Map::new();
    info.insert("index".into(), json!(t.texture));
    info.insert("texCoord".into(), json!(t.tex_coord));
    if let Some(key) = scale_key {
        info.insert(key.into(), json!(t.scale));
    }
    Value::Object(info)
}

/// The `textures`, `images` (embedded into `binary`) and `samplers` arrays, in scene order.
pub(crate) fn textures(scene: &Scene, binary: &mut Binary) -> (Vec<Value>, Vec<Value>, Vec<Value>) {
    let textures = scene
        .textures
        .iter()
        .map(|t| {
            let mut out = Map::new();
            if let Some(name) = &t.name {
                out.insert("name".into(), json!(name));
            }
            if let Some(s) = t.sampler {
                out.insert("sampler".into(), json!(s));
            }
            out.insert("source".into(), json!(t.image));
            Value::Object(out)
        })
        .collect();
    let images = scene
        .images
        .iter()
        .map(|img| {
            let mut out = Map::new();
            if let Some(name) = &img.name {
                out.insert("name".into(), json!(name));
            }
            out.insert("mimeType".into(), json!(img.mime_type));
            out.insert("bufferView".into(), json!(binary.image(&img.bytes)));
            Value::Object(out)
        })
        .collect();
    let samplers = scene
        .samplers
        .iter()
        .map(|s| {
            let mut out = Map::new();
            let fields = [
                ("magFilter", s.mag_filter),
                ("minFilter", s.min_filter),
                ("wrapS", s.wrap_s),
                ("wrapT", s.wrap_t),
            ];
            for (key, value) in fields {
                if let Some(v) = value {
                    out.insert(key.into(), json!(v));
                }
            }
            Value::Object(out)
        })
        .collect();
    (textures, images, samplers)
}
