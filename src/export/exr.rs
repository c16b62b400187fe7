//! One lightmap atlas as an OpenEXR file (the only user of the `exr` crate); also a view's
//! luminance image ([`encode_view`]: channels `R`, `G`, `B`, `luminance` in cd/m², the camera in
//! text attributes).
//!
//! Input: an [`Atlas`] and the texts of its header ([`Header`]). Output: the bytes of a
//! single-part, scan-line, uncompressed EXR whose data window is the atlas (W × H), with 32-bit
//! float channels `R`, `G`, `B` (luminance leaving the surface per channel, cd/m², linear
//! Rec. 709), `illuminance` and `illuminanceDirect` (lx) and `footprint` (m² of surface per
//! texel, 0 = padding; not `area`: Blender takes any channel whose name ends in `a` for alpha).
//! Scan line 0 is atlas row 0, the top: texel (col, row) is centred at UV ((col + 0.5)/W,
//! (row + 0.5)/H), v down as glTF's. Header: `whiteLuminance` 1 (RGB (1, 1, 1) is
//! 1 cd/m²) and text attributes `luxbake.*` (atlas, tool, units, settings, texel size, exposure).
//! Invariants: equal inputs give equal bytes (no timestamp; attributes sorted by name, as
//! OpenEXR's own library writes them, because the crate keeps custom ones in a hash map).

use crate::result::Atlas;
use exr::prelude::*;
use std::io::Cursor;

/// The unit of each channel, as written in `luxbake.units` and in `LUXBAKE_lightmap.channels`.
pub const CHANNEL_UNITS: [(&str, &str); 6] = [
    ("R", "cd/m2"),
    ("G", "cd/m2"),
    ("B", "cd/m2"),
    ("illuminance", "lx"),
    ("illuminanceDirect", "lx"),
    ("footprint", "m2"),
];

/// The header's text attributes (values must be ASCII, see [`ascii_json`]).
#[derive(Debug, Clone)]
pub struct Header {
    pub atlas: usize,
    /// `luxbake <version>`.
    pub tool: String,
    /// The bake's settings, JSON.
    pub settings: String,
    /// Texel edge of the layout (m).
    pub texel_size: f64,
    /// The display exposure, JSON.
    pub exposure: String,
}

/// Compression of the written files: none (float lightmaps barely compress losslessly, and
/// uncompressed files are the fastest to write and read).
const COMPRESSION: Compression = Compression::Uncompressed;

/// The EXR bytes of `atlas`; an error message when the atlas is inconsistent.
pub(crate) fn encode(atlas: &Atlas, header: &Header) -> std::result::Result<Vec<u8>, String> {
    encode_with(atlas, header, COMPRESSION)
}

/// [`encode`] with another compression (for measurements).
pub(crate) fn encode_with(
    atlas: &Atlas,
    header: &Header,
    compression: Compression,
) -> std::result::Result<Vec<u8>, String> {
    let (w, h) = (atlas.width as usize, atlas.height as usize);
    let n = w * h;
    let lengths = [
        atlas.luminance.len(),
        atlas.illuminance.len(),
        atlas.illuminance_direct.len(),
        atlas.area.len(),
    ];
    if n == 0 || lengths.iter().any(|&l| l != n) {
        return Err(format!(
            "atlas {} is {w} × {h} texels but has {lengths:?} values per channel",
            header.atlas
        ));
    }
    let rgb = |c: usize| FlatSamples::F32(atlas.luminance.iter().map(|v| v[c]).collect());
    let channels = AnyChannels::sort(SmallVec::from_vec(vec![
        AnyChannel::new("R", rgb(0)),
        AnyChannel::new("G", rgb(1)),
        AnyChannel::new("B", rgb(2)),
        AnyChannel::new("illuminance", FlatSamples::F32(atlas.illuminance.clone())),
        AnyChannel::new(
            "illuminanceDirect",
            FlatSamples::F32(atlas.illuminance_direct.clone()),
        ),
        AnyChannel::new("footprint", FlatSamples::F32(atlas.area.clone())),
    ]));
    let units = serde_json::Value::Object(
        CHANNEL_UNITS
            .iter()
            .map(|(c, u)| (c.to_string(), serde_json::json!(u)))
            .collect(),
    );
    let texts = [
        ("luxbake.atlas", header.atlas.to_string()),
        ("luxbake.tool", header.tool.clone()),
        ("luxbake.units", units.to_string()),
        ("luxbake.settings", header.settings.clone()),
        ("luxbake.texelSize", format!("{} m", header.texel_size)),
        ("luxbake.exposure", header.exposure.clone()),
    ];
    let texts = texts.map(|(name, value)| (name.to_string(), value));
    write_layer(
        (w, h),
        channels,
        &texts,
        compression,
        &format!("atlas {}", header.atlas),
    )
}

/// One scan-line layer of `channels` written to bytes (`whiteLuminance` 1, the texts as
/// attributes sorted by name, so the bytes do not depend on attribute order).
fn write_layer(
    size: (usize, usize),
    channels: AnyChannels<FlatSamples>,
    texts: &[(String, String)],
    compression: Compression,
    what: &str,
) -> std::result::Result<Vec<u8>, String> {
    let mut attributes = LayerAttributes {
        white_luminance: Some(1.0),
        ..LayerAttributes::default()
    };
    for (name, value) in texts {
        let text = Text::new_or_none(value)
            .filter(|_| value.is_ascii())
            .ok_or_else(|| format!("header attribute {name} is not ASCII: {value}"))?;
        attributes
            .other
            .insert(Text::from(name.as_str()), AttributeValue::Text(text));
    }
    let encoding = Encoding {
        compression,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let image = Image::from_layer(Layer::new(size, attributes, encoding, channels));
    let mut bytes = Cursor::new(Vec::new());
    image
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(|e| format!("cannot encode {what}: {e}"))?;
    let mut bytes = bytes.into_inner();
    sort_attributes(&mut bytes)?;
    Ok(bytes)
}

/// A luminance image of `bake view` (row 0 at the top).
#[derive(Debug, Clone)]
pub struct ViewImage<'a> {
    pub width: u32,
    pub height: u32,
    /// Linear Rec. 709 luminance per channel (cd/m²).
    pub rgb: &'a [[f32; 3]],
    /// Photometric luminance Y (cd/m²).
    pub luminance: &'a [f32],
    /// Text attributes (`luxbake.camera`, …), ASCII values.
    pub texts: Vec<(String, String)>,
    /// ZIP compression (lossless; about 4× smaller on a grey room, slower to write).
    pub zip: bool,
}

/// The EXR bytes of a view: channels `R`, `G`, `B` and `luminance` (f32, cd/m²), scan line 0 =
/// image row 0 (the top), `whiteLuminance` 1, the texts as attributes sorted by name.
pub fn encode_view(v: &ViewImage) -> std::result::Result<Vec<u8>, String> {
    let (w, h) = (v.width as usize, v.height as usize);
    let n = w * h;
    if n == 0 || v.rgb.len() != n || v.luminance.len() != n {
        return Err(format!(
            "a {w} × {h} view with {} colours and {} luminances",
            v.rgb.len(),
            v.luminance.len()
        ));
    }
    let rgb = |c: usize| FlatSamples::F32(v.rgb.iter().map(|p| p[c]).collect());
    let channels = AnyChannels::sort(SmallVec::from_vec(vec![
        AnyChannel::new("R", rgb(0)),
        AnyChannel::new("G", rgb(1)),
        AnyChannel::new("B", rgb(2)),
        AnyChannel::new("luminance", FlatSamples::F32(v.luminance.to_vec())),
    ]));
    let compression = if v.zip {
        Compression::ZIP16
    } else {
        COMPRESSION
    };
    write_layer((w, h), channels, &v.texts, compression, "the view")
}

/// `value` as JSON with every non-ASCII character escaped (`\uXXXX`), so it fits an EXR text.
pub fn ascii_json(value: &serde_json::Value) -> String {
    let mut out = String::new();
    for c in value.to_string().chars() {
        if c.is_ascii() {
            out.push(c);
        } else {
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                out.push_str(&format!("\\u{u:04x}"));
            }
        }
    }
    out
}

/// Put the header attributes of a single-part EXR in name order, in place. The header keeps its
/// length, so the offsets that follow it stay valid.
fn sort_attributes(bytes: &mut [u8]) -> std::result::Result<(), String> {
    let bad = || "malformed EXR header".to_string();
    const MULTIPART: u8 = 0x10; // bit 12 of the version field, in its second byte
    if bytes.len() < 9 || bytes[5] & MULTIPART != 0 {
        return Err(bad());
    }
    let zero_after = |at: usize| -> Option<usize> {
        bytes
            .get(at..)?
            .iter()
            .position(|&b| b == 0)
            .map(|i| at + i)
    };
    let start = 8;
    let mut at = start;
    let mut records: Vec<(&[u8], std::ops::Range<usize>)> = Vec::new();
    while *bytes.get(at).ok_or_else(bad)? != 0 {
        let name_end = zero_after(at).ok_or_else(bad)?;
        let type_end = zero_after(name_end + 1).ok_or_else(bad)?;
        let size = bytes.get(type_end + 1..type_end + 5).ok_or_else(bad)?;
        let size = i32::from_le_bytes(size.try_into().expect("4 bytes"));
        let end = type_end + 5 + usize::try_from(size).map_err(|_| bad())?;
        if end > bytes.len() {
            return Err(bad());
        }
        records.push((&bytes[at..name_end], at..end));
        at = end;
    }
    records.sort_by(|a, b| a.0.cmp(b.0));
    let sorted: Vec<u8> = records
        .iter()
        .flat_map(|(_, r)| bytes[r.clone()].to_vec())
        .collect();
    bytes[start..at].copy_from_slice(&sorted);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Header {
        Header {
            atlas: 0,
            tool: "luxbake test".into(),
            settings: ascii_json(&serde_json::json!({"rule": "x ≤ 0.8"})),
            texel_size: 0.05,
            exposure: "{}".into(),
        }
    }

    #[test]
    fn bytes_repeat_and_attributes_are_sorted() {
        let mut atlas = Atlas::new(3, 2);
        atlas.illuminance = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let a = encode(&atlas, &header()).unwrap();
        // A fresh hash map per call: the order the crate writes in may differ between calls.
        for _ in 0..4 {
            assert_eq!(encode(&atlas, &header()).unwrap(), a);
        }
        let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(&a), false).unwrap();
        let other = &meta.headers[0].own_attributes.other;
        assert_eq!(
            other.get(&Text::from("luxbake.settings")),
            Some(&AttributeValue::Text(Text::from(
                "{\"rule\":\"x \\u2264 0.8\"}"
            )))
        );
    }

    #[test]
    fn inconsistent_atlas_is_an_error() {
        let mut atlas = Atlas::new(2, 2);
        atlas.area.pop();
        assert!(encode(&atlas, &header()).is_err());
        assert!(encode(&Atlas::new(0, 0), &header()).is_err());
    }
}
