//! glTF materials → [`Material`]s: photometry for the bake, display data for the output.
//!
//! Inputs: the validated document, its raw JSON (factors at f64 precision, `LUXBAKE_material`,
//! `extras`) and the loaded images (for the mean of base colour textures). Output: one
//! [`Material`] per glTF material, same indices.
//! Rules: `LUXBAKE_material` sets reflectance and/or emission explicitly. Otherwise reflectance =
//! `baseColorFactor.rgb` × mean linear colour of `baseColorTexture` × (1 − `metallicFactor`)
//! (a warning says when the material is black only because `metallicFactor` defaulted to 1), and
//! emission luminance (cd/m²) = Y(`emissiveFactor`) × `KHR_materials_emissive_strength`, coloured
//! like `emissiveFactor` (zero = no emission; `emissiveTexture` does not change the amount).
//! `LUXBAKE_material.emission.profile` indexes `LUXBAKE_luminaire.profiles` and becomes
//! `Emission::profile` (a scene profile index).
//! Invariants: every reflectance is in [0, 1) (else an error at `/materials/N` saying how to fix
//! it); emission amounts are finite and ≥ 0; an emission profile index that does not exist is an
//! error at `.../LUXBAKE_material/emission/profile`. Texture means are computed once per image.

use super::luxbake_ext;
use super::profiles::Counts;
use super::{
    document::{LUXBAKE_LUMINAIRE, LUXBAKE_MATERIAL},
    raw,
};
use crate::Result;
use crate::import::context::Ctx;
use crate::import::images::mean_linear_rgb;
use crate::import::material_values::{check_reflectance, emission_from_rgb};
use crate::scene::{
    AlphaMode, DisplayMaterial, Emission, Image, Material, ReflectanceSource, TextureRef,
};
use glam::DVec3;
use serde_json::Value;
use std::collections::HashMap;

/// Every glTF material of `doc`, in index order.
pub(super) fn materials(
    ctx: &mut Ctx,
    doc: &::gltf::Document,
    raw: &Value,
    images: &[Image],
    profiles: Counts,
) -> Result<Vec<Material>> {
    let mut means = TextureMeans {
        images,
        cache: HashMap::new(),
    };
    doc.materials()
        .map(|m| material(ctx, &m, raw, profiles, &mut means))
        .collect()
}

/// The mean linear colour of each base colour image, computed once per image.
struct TextureMeans<'a> {
    images: &'a [Image],
    cache: HashMap<usize, DVec3>,
}

impl TextureMeans<'_> {
    /// The mean of image `image`, the base colour texture of the material at `at`.
    fn of(&mut self, ctx: &Ctx, at: &str, image: usize) -> Result<DVec3> {
        Ok(match self.cache.get(&image) {
            Some(&mean) => mean,
            None => {
                let mean = mean_linear_rgb(&self.images[image].bytes).map_err(|msg| {
                    ctx.err(
                        format!("{at}/pbrMetallicRoughness/baseColorTexture"),
                        format!("cannot average /images/{image}: {msg}"),
                    )
                })?;
                *self.cache.entry(image).or_insert(mean)
            }
        })
    }
}

/// The glTF material `m`: its photometry for the bake and its display data.
fn material(
    ctx: &mut Ctx,
    m: &::gltf::Material,
    raw: &Value,
    profiles: Counts,
    means: &mut TextureMeans,
) -> Result<Material> {
    let index = m.index().unwrap_or_default();
    let at = format!("/materials/{index}");
    let ext_at = extension_at(raw, &at);
    let extension = raw::cloned(raw, &ext_at);
    let ext = match &extension {
        Some(v) => Some(luxbake_ext::parse(v).map_err(|msg| ctx.err(&ext_at, msg))?),
        None => None,
    };
    check_factors(ctx, raw, &at)?;
    let display = display(m, raw, &at, extension);
    let emission_profile = match ext.as_ref().and_then(|e| e.emission_profile) {
        None => None,
        Some(p) => Some(profiles.luxbake_profile(p).ok_or_else(|| {
            ctx.err(
                format!("{ext_at}/emission/profile"),
                format!(
                    "refers to /extensions/{LUXBAKE_LUMINAIRE}/profiles/{p}, which does not \
                     exist (the file has {} profiles there)",
                    profiles.luxbake
                ),
            )
        })?),
    };

    let (reflectance, source, hint) = match ext.as_ref().and_then(|e| e.reflectance) {
        Some(rho) => (
            rho,
            ReflectanceSource::Extension,
            format!("set {LUXBAKE_MATERIAL}.reflectance below 1 (typical walls: 0.5–0.8)"),
        ),
        None => (
            base_colour_reflectance(ctx, raw, &at, &display, means)?,
            ReflectanceSource::BaseColor,
            format!(
                "the reflectance is baseColorFactor × mean of baseColorTexture × \
                 (1 − metallicFactor); lower baseColorFactor or give \
                 {LUXBAKE_MATERIAL}.reflectance explicitly (below 1)"
            ),
        ),
    };
    check_reflectance(reflectance, &hint).map_err(|msg| ctx.err(&at, msg))?;

    let emission = match ext.and_then(|e| e.emission) {
        Some(emission) => emission.map(|e| Emission {
            profile: emission_profile,
            ..e
        }),
        None => emissive_factor(ctx, &at, &display)?,
    };
    Ok(Material {
        name: m.name().map(str::to_owned),
        source_path: at.clone(),
        reflectance,
        emission,
        double_sided: m.double_sided(),
        reflectance_source: source,
        display,
        extras: raw::cloned(raw, &format!("{at}/extras")),
    })
}

/// Where the material at `at` keeps `LUXBAKE_material`: its extensions, or (a luxbake output
/// whose materials were made unlit) its extras; the extensions' place when neither has it.
fn extension_at(raw: &Value, at: &str) -> String {
    [
        format!("{at}/extensions/{LUXBAKE_MATERIAL}"),
        format!("{at}/extras/luxbake/original/{LUXBAKE_MATERIAL}"),
    ]
    .into_iter()
    .find(|p| raw::cloned(raw, p).is_some())
    .unwrap_or_else(|| format!("{at}/extensions/{LUXBAKE_MATERIAL}"))
}

/// The reflectance without the extension: baseColorFactor × mean of baseColorTexture ×
/// (1 − metallicFactor), with a warning when only a defaulted metallicFactor makes it black.
fn base_colour_reflectance(
    ctx: &mut Ctx,
    raw: &Value,
    at: &str,
    display: &DisplayMaterial,
    means: &mut TextureMeans,
) -> Result<DVec3> {
    let [r, g, b, _] = display.base_color_factor;
    let mut color = DVec3::new(r, g, b);
    let source = |t: &TextureRef| raw::number(raw, &format!("/textures/{}/source", t.texture));
    if let Some(image) = display.base_color_texture.as_ref().and_then(source) {
        color *= means.of(ctx, at, image as usize)?;
    }
    let metallic = display.metallic_factor;
    let metallic_given =
        raw::number(raw, &format!("{at}/pbrMetallicRoughness/metallicFactor")).is_some();
    if !metallic_given && color.max_element() > 0.0 {
        ctx.warn(format!(
            "{at}: metallicFactor is not given and defaults to 1 (pure metal), so the \
             diffuse reflectance is 0 and the material is black in the bake; set \
             metallicFactor to 0 or give {LUXBAKE_MATERIAL}.reflectance"
        ));
    }
    Ok(color * (1.0 - metallic))
}

/// The emission without the extension: Y(emissiveFactor) × emissive strength, coloured like
/// the factor (a note once that emissiveTexture does not change it).
fn emissive_factor(ctx: &mut Ctx, at: &str, display: &DisplayMaterial) -> Result<Option<Emission>> {
    let strength = display.emissive_strength.unwrap_or(1.0);
    let emission = emission_from_rgb(DVec3::from_array(display.emissive_factor), strength)
        .map_err(|msg| ctx.err(at, msg))?;
    if emission.is_some() && display.emissive_texture.is_some() {
        ctx.warn_once(
            "emissive texture",
            format!(
                "{at}: emissiveTexture does not change the emitted luminance, which \
                 comes from emissiveFactor × emissiveStrength only"
            ),
        );
    }
    Ok(emission)
}

/// The spec's ranges of the material's factors: an out-of-range value is an error naming it.
fn check_factors(ctx: &Ctx, raw: &Value, at: &str) -> Result<()> {
    let unit = |v: f64| (0.0..=1.0).contains(&v);
    type Range<'a> = (String, &'a dyn Fn(f64) -> bool, &'a str);
    let kept = format!("{at}/extras/luxbake/original");
    let ranges: [Range; 12] = [
        (
            format!("{at}/pbrMetallicRoughness/baseColorFactor"),
            &unit,
            "in [0, 1]",
        ),
        (
            format!("{at}/pbrMetallicRoughness/metallicFactor"),
            &unit,
            "in [0, 1]",
        ),
        (
            format!("{at}/pbrMetallicRoughness/roughnessFactor"),
            &unit,
            "in [0, 1]",
        ),
        (
            format!("{at}/emissiveFactor"),
            &unit,
            "in [0, 1] (brighter emission: KHR_materials_emissive_strength or \
             LUXBAKE_material.emission)",
        ),
        (
            format!("{at}/occlusionTexture/strength"),
            &unit,
            "in [0, 1]",
        ),
        (format!("{at}/alphaCutoff"), &|v| v >= 0.0, "≥ 0"),
        (
            format!("{at}/extensions/KHR_materials_emissive_strength/emissiveStrength"),
            &|v| (0.0..=crate::import::MAX_PHOTOMETRIC).contains(&v),
            "≥ 0 and at most 1e12",
        ),
        // What a luxbake output kept of an unlit material, read in its place.
        (format!("{kept}/baseColorFactor"), &unit, "in [0, 1]"),
        (format!("{kept}/metallicFactor"), &unit, "in [0, 1]"),
        (format!("{kept}/roughnessFactor"), &unit, "in [0, 1]"),
        (format!("{kept}/emissiveFactor"), &unit, "in [0, 1]"),
        (
            format!("{kept}/emissiveStrength"),
            &|v| (0.0..=crate::import::MAX_PHOTOMETRIC).contains(&v),
            "≥ 0 and at most 1e12",
        ),
    ];
    for (pointer, ok, range) in ranges {
        let values: Vec<&Value> = match raw.pointer(&pointer) {
            None => continue,
            Some(Value::Array(a)) => a.iter().collect(),
            Some(v) => vec![v],
        };
        for v in values {
            if !v.as_f64().is_some_and(|x| x.is_finite() && ok(x)) {
                return Err(ctx.err(&pointer, format!("{v} is out of range: must be {range}")));
            }
        }
    }
    Ok(())
}

fn display(m: &::gltf::Material, raw: &Value, at: &str, ext: Option<Value>) -> DisplayMaterial {
    let pbr = m.pbr_metallic_roughness();
    let pbr_at = format!("{at}/pbrMetallicRoughness");
    let texture = |info: Option<::gltf::texture::Info>| {
        info.map(|i| TextureRef {
            texture: i.texture().index(),
            tex_coord: i.tex_coord(),
            scale: 1.0,
        })
    };
    // A luxbake output made unlit keeps the material's own values here (see `export::material`).
    let original = format!("{at}/extras/luxbake/original");
    let kept = |path: String, key: &str| match raw::cloned(raw, &format!("{original}/{key}")) {
        Some(_) => format!("{original}/{key}"),
        None => path,
    };
    let base_color_texture = match raw::cloned(raw, &format!("{original}/baseColorTexture")) {
        Some(info) => (info["index"].as_u64())
            .filter(|t| raw::cloned(raw, &format!("/textures/{t}")).is_some())
            .map(|t| TextureRef {
                texture: t as usize,
                tex_coord: info["texCoord"].as_u64().unwrap_or(0) as u32,
                scale: 1.0,
            }),
        None => texture(pbr.base_color_texture()),
    };
    DisplayMaterial {
        base_color_factor: raw::numbers(
            raw,
            &kept(format!("{pbr_at}/baseColorFactor"), "baseColorFactor"),
        )
        .unwrap_or([1.0; 4]),
        base_color_texture,
        metallic_factor: raw::number_or(
            raw,
            &kept(format!("{pbr_at}/metallicFactor"), "metallicFactor"),
            1.0,
        ),
        roughness_factor: raw::number_or(
            raw,
            &kept(format!("{pbr_at}/roughnessFactor"), "roughnessFactor"),
            1.0,
        ),
        metallic_roughness_texture: texture(pbr.metallic_roughness_texture()),
        normal_texture: m.normal_texture().map(|t| TextureRef {
            texture: t.texture().index(),
            tex_coord: t.tex_coord(),
            scale: raw::number_or(raw, &format!("{at}/normalTexture/scale"), 1.0),
        }),
        occlusion_texture: m.occlusion_texture().map(|t| TextureRef {
            texture: t.texture().index(),
            tex_coord: t.tex_coord(),
            scale: raw::number_or(raw, &format!("{at}/occlusionTexture/strength"), 1.0),
        }),
        emissive_texture: texture(m.emissive_texture()),
        emissive_factor: raw::numbers(raw, &kept(format!("{at}/emissiveFactor"), "emissiveFactor"))
            .unwrap_or([0.0; 3]),
        emissive_strength: raw::number(
            raw,
            &kept(
                format!("{at}/extensions/KHR_materials_emissive_strength/emissiveStrength"),
                "emissiveStrength",
            ),
        ),
        alpha_mode: match m.alpha_mode() {
            ::gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            ::gltf::material::AlphaMode::Mask => AlphaMode::Mask,
            ::gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        alpha_cutoff: raw::number(raw, &format!("{at}/alphaCutoff")),
        luxbake_extension: ext,
    }
}
