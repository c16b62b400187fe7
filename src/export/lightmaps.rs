//! The lightmap atlases in the glTF document: a display texture per atlas and the
//! `LUXBAKE_lightmap` object that points at its EXR file.
//!
//! Input: the bake's [`Lightmaps`] and [`RunSummary`], each atlas's EXR URI (relative to the
//! output), and the document's arrays being filled. Output: per atlas, its display PNG embedded in
//! the [`Binary`] (an image `image/png`, a texture, after the scene's own) and its
//! `LUXBAKE_lightmap` object; one sampler shared by every display texture, LINEAR/LINEAR (no
//! mipmaps, so no mip level mixes charts) and CLAMP_TO_EDGE. Also the EXR header each atlas's
//! file gets. Invariants: atlas k is texture `first + k`; the objects follow
//! `schemas/LUXBAKE_lightmap.schema.json`; nothing here depends on time or thread count.

use super::{buffer::Binary, display, exr};
use crate::result::Lightmaps;
use crate::summary::RunSummary;
use crate::{Error, Result};
use serde_json::{Map, Value, json};

pub const MOZ_LIGHTMAP: &str = "MOZ_lightmap";
pub const LUXBAKE_LIGHTMAP: &str = "LUXBAKE_lightmap";
/// The texture coordinate set of every lightmap layout (`TEXCOORD_1`).
pub const TEX_COORD: u32 = 1;
const LINEAR: u32 = 9729;
const CLAMP_TO_EDGE: u32 = 33071;

/// What the document holds of each atlas.
#[derive(Debug, Default)]
pub struct Atlases {
    /// The display texture of each atlas (index into `textures`).
    pub texture: Vec<usize>,
    /// The `LUXBAKE_lightmap` object of each atlas.
    pub extension: Vec<Value>,
}

/// The arrays of the document that receive the display textures.
pub struct Arrays<'a> {
    pub textures: &'a mut Vec<Value>,
    pub images: &'a mut Vec<Value>,
    pub samplers: &'a mut Vec<Value>,
}

/// Add every atlas's display texture; `uris[k]` is atlas k's EXR file, relative to the output.
pub(crate) fn add(
    lightmaps: Option<&Lightmaps>,
    summary: &RunSummary,
    uris: &[String],
    binary: &mut Binary,
    out: Arrays,
) -> Result<Atlases> {
    let mut atlases = Atlases::default();
    let Some(lightmaps) = lightmaps.filter(|l| !l.atlases.is_empty()) else {
        return Ok(atlases);
    };
    let sampler = out.samplers.len();
    out.samplers.push(json!({
        "magFilter": LINEAR,
        "minFilter": LINEAR,
        "wrapS": CLAMP_TO_EDGE,
        "wrapT": CLAMP_TO_EDGE,
    }));
    for (k, atlas) in lightmaps.atlases.iter().enumerate() {
        let png = display::png(atlas).map_err(|m| Error::Bake(format!("lightmap {k}: {m}")))?;
        let image = out.images.len();
        out.images.push(json!({
            "name": format!("lightmap {k}"),
            "mimeType": "image/png",
            "bufferView": binary.image(&png),
        }));
        let texture = out.textures.len();
        out.textures.push(json!({
            "name": format!("lightmap {k}"),
            "sampler": sampler,
            "source": image,
        }));
        let uri = uris.get(k).ok_or_else(|| {
            Error::Bake(format!(
                "lightmap {k} has no file name ({} given)",
                uris.len()
            ))
        })?;
        let channels: Map<String, Value> = exr::CHANNEL_UNITS
            .iter()
            .map(|(c, u)| (c.to_string(), json!(u)))
            .collect();
        atlases.texture.push(texture);
        atlases.extension.push(json!({
            "atlas": k,
            "uri": uri,
            "texCoord": TEX_COORD,
            "width": atlas.width,
            "height": atlas.height,
            "texelSize": lightmaps.texel_size,
            "display": texture,
            "exposure": {
                "whiteIlluminanceLx": summary.exposure.white_illuminance_lx,
                "rule": summary.exposure.rule,
            },
            "channels": channels,
        }));
    }
    Ok(atlases)
}

/// The header texts of atlas `k`'s EXR file.
pub(crate) fn exr_header(k: usize, lightmaps: &Lightmaps, summary: &RunSummary) -> exr::Header {
    let json = |v: serde_json::Result<Value>| exr::ascii_json(&v.expect("summary serialises"));
    exr::Header {
        atlas: k,
        tool: concat!("luxbake ", env!("CARGO_PKG_VERSION")).into(),
        settings: json(serde_json::to_value(&summary.settings)),
        texel_size: lightmaps.texel_size,
        exposure: json(serde_json::to_value(&summary.exposure)),
    }
}
