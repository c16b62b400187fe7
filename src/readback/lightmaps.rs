//! The lightmap atlases of an output: each material's `LUXBAKE_lightmap` read and checked, and
//! each atlas's channels, from its EXR file beside the output (through `import`'s confined reads
//! and EXR decoder) or, for a bake still in memory, from the bake's own atlases.
//!
//! Input: the output's [`GltfFile`] and, optionally, the in-memory [`Lightmaps`] its EXR files
//! will be written from. Output: the atlases in order of their `atlas` number, and per material
//! the atlas it names and its `texCoord`. Errors name the file and the material's pointer
//! (`/materials/3/extensions/LUXBAKE_lightmap`, with the field when one is wrong): a field
//! missing or out of range, two materials describing one atlas differently, an EXR file missing,
//! outside the output's folder, unreadable or truncated, a channel missing, a size that is not
//! the material's.

use super::model::Lightmap;
use crate::import::GltfFile;
use crate::import::exr::decode;
use crate::result::Lightmaps;
use crate::{Error, Result};
use serde_json::Value;
use std::collections::BTreeMap;

pub const EXTENSION: &str = "LUXBAKE_lightmap";

/// The channels read from each file, in this order.
pub const CHANNELS: [&str; 6] = [
    "R",
    "G",
    "B",
    "illuminance",
    "illuminanceDirect",
    "footprint",
];

/// Largest atlas edge accepted (texels), so a wrong number cannot ask for terabytes.
const MAX_EDGE: u64 = 1 << 16;

/// The atlases and which one each material names.
pub(super) struct Layouts {
    pub lightmaps: Vec<Lightmap>,
    /// Per material: (index into `lightmaps`, `texCoord`), or `None` without `LUXBAKE_lightmap`.
    pub of_material: Vec<Option<(usize, u32)>>,
}

/// What a material says of its atlas.
struct Described {
    atlas: usize,
    uri: String,
    tex_coord: u32,
    width: u32,
    height: u32,
    texel_size: f64,
    at: String,
}

/// Read every material's `LUXBAKE_lightmap` and the atlases they name; `memory`: the atlases of
/// a bake not yet written (their files are not read).
pub(super) fn read(file: &mut GltfFile, memory: Option<&Lightmaps>) -> Result<Layouts> {
    let count = file.json()["materials"].as_array().map_or(0, Vec::len);
    let mut described: Vec<Option<Described>> = Vec::with_capacity(count);
    for i in 0..count {
        let at = format!("/materials/{i}/extensions/{EXTENSION}");
        described.push(
            match &file.json()["materials"][i]["extensions"][EXTENSION] {
                Value::Null => None,
                v => Some(describe(file, v, at)?),
            },
        );
    }
    // One entry per atlas number, checked against every material naming it.
    let mut atlases: BTreeMap<usize, &Described> = BTreeMap::new();
    for d in described.iter().flatten() {
        let first = *atlases.entry(d.atlas).or_insert(d);
        if (&first.uri, first.width, first.height) != (&d.uri, d.width, d.height) {
            return Err(file.err(
                &d.at,
                format!(
                    "atlas {} is {} ({} × {}) here but {} ({} × {}) at {}",
                    d.atlas,
                    d.uri,
                    d.width,
                    d.height,
                    first.uri,
                    first.width,
                    first.height,
                    first.at
                ),
            ));
        }
    }
    let mut lightmaps = Vec::with_capacity(atlases.len());
    let mut index = BTreeMap::new();
    for (&k, d) in &atlases {
        index.insert(k, lightmaps.len());
        lightmaps.push(match memory {
            Some(m) => from_memory(file, d, m)?,
            None => from_exr(file, d)?,
        });
    }
    let of_material = described
        .iter()
        .map(|d| d.as_ref().map(|d| (index[&d.atlas], d.tex_coord)))
        .collect();
    Ok(Layouts {
        lightmaps,
        of_material,
    })
}

/// The fields of one `LUXBAKE_lightmap` object.
fn describe(file: &GltfFile, v: &Value, at: String) -> Result<Described> {
    if !v.is_object() {
        return Err(file.err(&at, "not an object"));
    }
    let int = |key: &str, lo: u64, hi: u64| {
        v[key]
            .as_u64()
            .filter(|x| (lo..=hi).contains(x))
            .ok_or_else(|| {
                file.err(
                    format!("{at}/{key}"),
                    format!("an integer from {lo} to {hi} expected, found {}", v[key]),
                )
            })
    };
    let uri = v["uri"].as_str().filter(|u| !u.is_empty()).ok_or_else(|| {
        file.err(
            format!("{at}/uri"),
            "the EXR file's URI (a string) expected",
        )
    })?;
    let texel_size = v["texelSize"]
        .as_f64()
        .filter(|t| *t > 0.0 && t.is_finite())
        .ok_or_else(|| {
            file.err(
                format!("{at}/texelSize"),
                format!("a texel edge in m (> 0) expected, found {}", v["texelSize"]),
            )
        })?;
    Ok(Described {
        atlas: int("atlas", 0, u32::MAX.into())? as usize,
        uri: uri.to_owned(),
        tex_coord: int("texCoord", 0, 15)? as u32,
        width: int("width", 1, MAX_EDGE)? as u32,
        height: int("height", 1, MAX_EDGE)? as u32,
        texel_size,
        at,
    })
}

/// An atlas of `d` with these channels (luminance RGB, illuminance, direct, footprint).
fn lightmap(d: &Described, channels: (Vec<[f32; 3]>, Vec<f32>, Vec<f32>, Vec<f32>)) -> Lightmap {
    Lightmap {
        atlas: d.atlas,
        uri: d.uri.clone(),
        width: d.width,
        height: d.height,
        texel_size: d.texel_size,
        at: d.at.clone(),
        luminance: channels.0,
        illuminance: channels.1,
        illuminance_direct: channels.2,
        footprint: channels.3,
    }
}

/// The atlas's EXR file, decoded and checked against the material's size.
fn from_exr(file: &mut GltfFile, d: &Described) -> Result<Lightmap> {
    let bytes = file.resource(&d.uri, &d.at, "lightmap")?;
    let exr = decode(&bytes, &CHANNELS)
        .map_err(|m| file.err(&d.at, format!("lightmap {}: {m}", d.uri)))?;
    if (exr.width, exr.height) != (d.width as usize, d.height as usize) {
        return Err(file.err(
            &d.at,
            format!(
                "lightmap {} is {} × {} texels but the material says {} × {}",
                d.uri, exr.width, exr.height, d.width, d.height
            ),
        ));
    }
    let [r, g, b, e, direct, footprint]: [Vec<f32>; 6] =
        exr.channels.try_into().expect("six channels asked for");
    let rgb = (r.iter().zip(&g).zip(&b))
        .map(|((r, g), b)| [*r, *g, *b])
        .collect();
    Ok(lightmap(d, (rgb, e, direct, footprint)))
}

/// The atlas as the bake holds it in memory (what its EXR file will hold).
fn from_memory(file: &GltfFile, d: &Described, m: &Lightmaps) -> Result<Lightmap> {
    let a = m.atlases.get(d.atlas).ok_or_else(|| {
        Error::Bake(format!(
            "{}: atlas {} named but the bake has {}",
            d.at,
            d.atlas,
            m.atlases.len()
        ))
    })?;
    if (a.width, a.height) != (d.width, d.height) {
        return Err(file.err(&d.at, "the atlas in memory has another size"));
    }
    let channels = (
        a.luminance.clone(),
        a.illuminance.clone(),
        a.illuminance_direct.clone(),
        a.area.clone(),
    );
    Ok(lightmap(d, channels))
}
