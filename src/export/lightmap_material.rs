//! The material variants of lightmapped primitives: one per (scene material, atlas) pair in use,
//! appended after the scene's materials (which keep their indices, for the other primitives).
//!
//! Input: the [`Scene`], the [`BakeResult`] (which written surfaces have `lightmap: Some(k)`),
//! the material as written lit (PBR, from [`material::lit`]), the atlases' display textures and
//! `LUXBAKE_lightmap` objects. Output: the variants' JSON, and the index of each variant.
//! Every variant carries `MOZ_lightmap` (three.js, Hubs) and `LUXBAKE_lightmap`, keeps its
//! material's name, and records `extras.luxbake.variantOf` (the scene material's index).
//! - With unlit (default) the display reaches every viewer through emission, whatever its
//!   lights: base colour black (alpha kept), metallic 0, roughness 1, no other texture,
//!   `emissiveFactor` = the display base (`Material::display_base`: the base colour, an
//!   emitter's emission colour), `emissiveTexture` = the display on `TEXCOORD_1`; not
//!   `KHR_materials_unlit`, which the validator warns about beside any other extension. What
//!   was changed is kept in `extras.luxbake.original`, and `LUXBAKE_material` states the
//!   photometry explicitly (reflectance, emission) so baking the output anew reads the input's.
//! - Without unlit (`--keep-lit-materials`) the lit material is kept as it is (for engines that
//!   relight with the lightmap).
//!
//! Invariants: variants are ordered by (material, atlas), so equal inputs give equal documents;
//! alpha mode, cutoff and `doubleSided` are those of the material written for the same surfaces.

use super::{
    ExportOptions,
    lightmaps::{Atlases, LUXBAKE_LIGHTMAP, MOZ_LIGHTMAP, TEX_COORD},
    luminaires::Profiles,
    material::{self, EMISSIVE_STRENGTH, LUXBAKE_MATERIAL},
};
use crate::scene::{EmissionAmount, Material, Scene};
use crate::{Error, Result, result::BakeResult};
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

/// Which variants exist and where they are in `materials`.
#[derive(Debug, Default)]
pub struct Variants {
    /// (scene material, atlas) → index in the output's `materials`.
    index: BTreeMap<(usize, usize), usize>,
}

impl Variants {
    /// The variants `result` needs (none unless `readback`); the first gets index `first`.
    pub(crate) fn plan(
        scene: &Scene,
        result: &BakeResult,
        baked: bool,
        first: usize,
    ) -> Result<Self> {
        let mut index = BTreeMap::new();
        if !baked {
            return Ok(Variants { index });
        }
        let atlases = result.lightmaps.as_ref().map_or(0, |l| l.atlases.len());
        for b in &result.surfaces {
            let Some(k) = b.lightmap else { continue };
            let surface = scene.surfaces.get(b.surface).ok_or_else(|| {
                Error::Bake(format!(
                    "a baked surface names missing surface {}",
                    b.surface
                ))
            })?;
            if k >= atlases {
                return Err(Error::Bake(format!(
                    "{}: laid out in lightmap {k}, but the bake has {atlases} atlases",
                    surface.source_path
                )));
            }
            if !b.triangles.is_empty() {
                index.insert((surface.material, k), 0);
            }
        }
        for (i, v) in index.values_mut().enumerate() {
            *v = first + i;
        }
        Ok(Variants { index })
    }

    /// The material index of `material`'s variant for atlas `k`.
    pub(crate) fn get(&self, material: usize, k: usize) -> Option<usize> {
        self.index.get(&(material, k)).copied()
    }

    /// The variants' JSON, in index order; `back_baked` as for [`material::materials`].
    pub(crate) fn materials(
        &self,
        scene: &Scene,
        back_baked: &[bool],
        options: &ExportOptions,
        profiles: &Profiles,
        atlases: &Atlases,
    ) -> Vec<Value> {
        self.index
            .keys()
            .map(|&(i, k)| {
                let m = &scene.materials[i];
                let back = back_baked.get(i).copied().unwrap_or(false);
                let mut out = material::lit(m, back, profiles);
                let texture = atlases.texture[k];
                if options.unlit {
                    emissive(&mut out, m, texture);
                }
                let ext = out
                    .as_object_mut()
                    .expect("material object")
                    .entry("extensions")
                    .or_insert_with(|| json!({}));
                let ext = ext.as_object_mut().expect("extensions object");
                ext.insert(LUXBAKE_LIGHTMAP.into(), atlases.extension[k].clone());
                ext.insert(
                    MOZ_LIGHTMAP.into(),
                    json!({"index": texture, "texCoord": TEX_COORD, "intensity": 1.0}),
                );
                reorder(ext, &[]);
                if let Some(luxbake) = out["extras"]["luxbake"].as_object_mut() {
                    luxbake.insert("variantOf".into(), json!(i));
                }
                reorder(out.as_object_mut().expect("material object"), MATERIAL_KEYS);
                out
            })
            .collect()
    }
}

/// Turn the lit material `out` of `m` into one that shows display texture `texture` through
/// emission.
fn emissive(out: &mut Value, m: &Material, texture: usize) {
    let out = out.as_object_mut().expect("material object");
    let mut original = Map::new();
    let pbr = out["pbrMetallicRoughness"]
        .as_object_mut()
        .expect("pbrMetallicRoughness object");
    let a = m.display.base_color_factor[3];
    let [r, g, b] = m.display_base().to_array();
    for key in [
        "baseColorFactor",
        "baseColorTexture",
        "metallicFactor",
        "roughnessFactor",
        "metallicRoughnessTexture",
    ] {
        if let Some(v) = pbr.remove(key) {
            original.insert(key.into(), v);
        }
    }
    pbr.insert("baseColorFactor".into(), json!([0.0, 0.0, 0.0, a]));
    pbr.insert("metallicFactor".into(), json!(0.0));
    pbr.insert("roughnessFactor".into(), json!(1.0));
    reorder(
        pbr,
        &["baseColorFactor", "metallicFactor", "roughnessFactor"],
    );
    for key in [
        "normalTexture",
        "occlusionTexture",
        "emissiveTexture",
        "emissiveFactor",
    ] {
        if let Some(v) = out.remove(key) {
            original.insert(key.into(), v);
        }
    }
    out.insert(
        "emissiveTexture".into(),
        json!({"index": texture, "texCoord": TEX_COORD}),
    );
    out.insert("emissiveFactor".into(), json!([r, g, b]));

    let ext = out
        .entry("extensions")
        .or_insert_with(|| json!({}))
        .as_object_mut()
        .expect("extensions object");
    if let Some(s) = ext.remove(EMISSIVE_STRENGTH) {
        original.insert("emissiveStrength".into(), s["emissiveStrength"].clone());
    }
    let given = ext.remove(LUXBAKE_MATERIAL);
    if let Some(v) = &given {
        original.insert(LUXBAKE_MATERIAL.into(), v.clone());
    }
    ext.insert(LUXBAKE_MATERIAL.into(), explicit_photometry(m, given));

    if let Some(luxbake) = out["extras"]["luxbake"].as_object_mut() {
        let kept = luxbake
            .entry("original")
            .or_insert_with(|| json!({}))
            .as_object_mut()
            .expect("original object");
        kept.extend(original);
    }
}

/// A material's keys in the order `material.rs` writes them.
const MATERIAL_KEYS: &[&str] = &[
    "name",
    "pbrMetallicRoughness",
    "normalTexture",
    "occlusionTexture",
    "emissiveTexture",
    "emissiveFactor",
    "alphaMode",
    "alphaCutoff",
    "doubleSided",
    "extensions",
    "extras",
];

/// Put `map`'s keys in the order of `keys`, the others after them sorted by name (removing keys
/// from a JSON map may reorder it).
fn reorder(map: &mut Map<String, Value>, keys: &[&str]) {
    let mut old = std::mem::take(map);
    for &k in keys {
        if let Some(v) = old.remove(k) {
            map.insert(k.into(), v);
        }
    }
    let mut rest: Vec<(String, Value)> = old.into_iter().collect();
    rest.sort_by(|a, b| a.0.cmp(&b.0));
    map.extend(rest);
}

/// `LUXBAKE_material` with reflectance and emission stated (a black, emissive variant would
/// otherwise read as a black emitter): the given object's members win.
fn explicit_photometry(m: &Material, given: Option<Value>) -> Value {
    let mut out = match given {
        Some(Value::Object(o)) => o,
        _ => Map::new(),
    };
    if !out.contains_key("reflectance") {
        out.insert("reflectance".into(), json!(m.reflectance.to_array()));
    }
    if !out.contains_key("emission") {
        let emission = match &m.emission {
            None => json!({"luminance": 0.0}),
            Some(e) => {
                let (key, amount) = match e.amount {
                    EmissionAmount::Luminance(l) => ("luminance", l),
                    EmissionAmount::LuminousFlux(f) => ("luminousFlux", f),
                };
                json!({key: amount, "color": e.color.to_array()})
            }
        };
        out.insert("emission".into(), emission);
    }
    reorder(&mut out, &["reflectance", "emission"]);
    Value::Object(out)
}
