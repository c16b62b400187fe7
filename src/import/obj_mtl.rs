//! MTL materials (as parsed by `tobj`) → [`Material`]s, and their `map_Kd` textures.
//!
//! Inputs: one parsed MTL material and where its MTL file lies. Output: a [`Material`], plus any
//! texture/image it uses added to [`ObjTextures`].
//! Rules (documented for users in the OBJ importer's docs too):
//! - reflectance = `Kd` × mean linear colour of `map_Kd` (when the texture loads); `Kd` missing:
//!   1 with a `map_Kd`, else luxbake's default 0.5 (with a warning). Checked to lie in [0, 1).
//! - `Ke` is Lambertian emission: luminance = Y(`Ke`) = 0.2126 R + 0.7152 G + 0.0722 B, in cd/m²,
//!   colour = `Ke` normalised to luminance 1. OBJ has no photometric units; this is luxbake's
//!   convention.
//! - Materials are single-sided. Display: `baseColorFactor` = `Kd`, metallic 0, roughness 1;
//!   `emissiveFactor` = `Ke` scaled into [0, 1] with `emissive_strength` carrying the rest, so the
//!   output stays valid glTF; `map_Kd` becomes the base colour texture (TEXCOORD_0).
//! - `map_Kd` paths are relative to the MTL file and confined to the OBJ's folder (escaping is an
//!   error); a missing or undecodable texture is a warning. Images are shared by path.
//!
//! Errors name the MTL file and `material 'name'`.

use super::context::Ctx;
use super::images::{mean_linear_rgb, sniff_mime};
use super::material_values::{check_reflectance, emission_from_rgb};
use super::resources::{confine, lexically_inside};
use crate::scene::{DisplayMaterial, Image, Material, ReflectanceSource, Texture, TextureRef};
use crate::{Error, Result};
use glam::DVec3;
use std::collections::HashMap;
use std::path::PathBuf;

/// An MTL file that was read: its canonical path, its folder relative to the OBJ's folder, and
/// how many materials it defined (tobj concatenates them in `mtllib` order).
pub(super) struct MtlSource {
    pub path: PathBuf,
    pub folder: PathBuf,
    pub count: usize,
}

/// Images and textures referenced by MTL files (one texture per image).
#[derive(Default)]
pub(super) struct ObjTextures {
    images: Vec<Image>,
    means: Vec<Option<DVec3>>,
    by_path: HashMap<PathBuf, usize>,
}

impl ObjTextures {
    pub(crate) fn into_parts(self) -> (Vec<Image>, Vec<Texture>) {
        let textures = (0..self.images.len())
            .map(|i| Texture {
                name: self.images[i].name.clone(),
                image: i,
                sampler: None,
            })
            .collect();
        (self.images, textures)
    }
}

pub(super) fn material(
    ctx: &mut Ctx,
    m: &tobj::Material,
    source: &MtlSource,
    textures: &mut ObjTextures,
) -> Result<Material> {
    let at = format!("material '{}'", m.name);
    let err = |message: String| Error::input(&source.path, &at, message);
    let texture = match &m.diffuse_texture {
        Some(reference) => load_texture(ctx, reference, source, &at, textures)?,
        None => None,
    };
    let kd = match m.diffuse {
        Some(kd) => DVec3::from_array(kd),
        None if texture.is_some() => DVec3::ONE,
        None => {
            ctx.warn(format!(
                "{}: {at}: no Kd; using luxbake's default reflectance 0.5",
                source.path.display()
            ));
            DVec3::splat(0.5)
        }
    };
    let mean = texture
        .and_then(|t| textures.means[t])
        .unwrap_or(DVec3::ONE);
    let reflectance = kd * mean;
    check_reflectance(
        reflectance,
        "lower Kd (or use a darker map_Kd) in the MTL file so every channel is below 1",
    )
    .map_err(err)?;
    let ke = DVec3::from_array(m.emissive.unwrap_or([0.0; 3]));
    let emission = emission_from_rgb(ke, 1.0).map_err(|msg| err(format!("Ke: {msg}")))?;
    let peak = ke.max_element();
    let (emissive_factor, emissive_strength) = if peak > 1.0 {
        ((ke / peak).to_array(), Some(peak))
    } else {
        (ke.to_array(), None)
    };
    Ok(Material {
        name: Some(m.name.clone()),
        source_path: format!(
            "{}: {at}",
            source
                .path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
        ),
        reflectance,
        emission,
        double_sided: false,
        reflectance_source: ReflectanceSource::MtlKd,
        display: DisplayMaterial {
            base_color_factor: [kd.x, kd.y, kd.z, 1.0],
            base_color_texture: texture.map(|t| TextureRef {
                texture: t,
                tex_coord: 0,
                scale: 1.0,
            }),
            metallic_factor: 0.0,
            roughness_factor: 1.0,
            emissive_factor,
            emissive_strength,
            ..DisplayMaterial::default()
        },
        extras: None,
    })
}

/// The file name in a `map_Kd` statement: options such as `-s 1 1 1` come first, so a value
/// starting with `-` is taken to end with the file name.
fn texture_file(reference: &str) -> &str {
    let reference = reference.trim();
    if reference.starts_with('-') {
        reference.split_whitespace().last().unwrap_or(reference)
    } else {
        reference
    }
}

/// Load (or reuse) the image of a `map_Kd`; `None` (with a warning) if missing or unusable.
fn load_texture(
    ctx: &mut Ctx,
    reference: &str,
    source: &MtlSource,
    at: &str,
    textures: &mut ObjTextures,
) -> Result<Option<usize>> {
    let relative = source.folder.join(texture_file(reference));
    let where_ = format!("{}: {at}", source.path.display());
    if (ctx.dir.as_deref())
        .is_some_and(|d| lexically_inside(d, &relative) && !d.join(&relative).exists())
    {
        ctx.warn(format!(
            "{where_}: map_Kd '{reference}' is missing; the material has no texture"
        ));
        return Ok(None);
    }
    let path = confine(ctx, &relative, at, "map_Kd texture").map_err(|e| match e {
        Error::Input { message, .. } => Error::input(&source.path, at, message),
        other => other,
    })?;
    if let Some(&i) = textures.by_path.get(&path) {
        return Ok(Some(i));
    }
    let bytes = super::files::read(&path).map_err(|e| {
        Error::input(
            &source.path,
            at,
            format!("cannot read {}: {e}", path.display()),
        )
    })?;
    ctx.record(path.clone());
    let Some(mime) = sniff_mime(&bytes) else {
        ctx.warn(format!(
            "{where_}: map_Kd {} is neither PNG nor JPEG; the material has no texture",
            path.display()
        ));
        return Ok(None);
    };
    let mean = match mean_linear_rgb(&bytes) {
        Ok(mean) => Some(mean),
        Err(msg) => {
            ctx.warn(format!(
                "{where_}: map_Kd {}: {msg}; its colour is not used for the reflectance",
                path.display()
            ));
            None
        }
    };
    let index = textures.images.len();
    textures.images.push(Image {
        name: path.file_stem().map(|s| s.to_string_lossy().into_owned()),
        mime_type: mime.to_owned(),
        bytes,
    });
    textures.means.push(mean);
    textures.by_path.insert(path, index);
    Ok(Some(index))
}
