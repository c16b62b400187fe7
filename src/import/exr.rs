//! Decoding an OpenEXR file's channels (the only reader of the `exr` crate; `export/exr.rs` is
//! its only writer): what `crate::readback` needs of a lightmap atlas written beside a bake.
//!
//! Input: the file's bytes (read through the confined paths of [`super::GltfFile::resource`])
//! and the channel names wanted. Output: the data window's size and each wanted channel's
//! samples as `f32`, row-major from the first scan line (`f16` samples widened; `u32` ones are
//! an error). Invariants: pedantic decoding (a truncated or inconsistent file is an error, never
//! zeros); a missing channel or a subsampled one is an error naming it; messages are plain text
//! the caller attaches to the file and element.

use exr::prelude::*;
use std::io::Cursor;

/// The wanted channels of an EXR file's first layer.
#[derive(Debug, Clone, PartialEq)]
pub struct ExrChannels {
    pub width: usize,
    pub height: usize,
    /// One vector of `width × height` samples per wanted channel, in the order asked for.
    pub channels: Vec<Vec<f32>>,
}

/// Largest ratio of decoded to stored pixel bytes accepted: deflate's bound (1032:1), beyond
/// what any uncompressed, RLE or ZIP file reaches. The `exr` crate allocates every layer's
/// samples from its header before reading them: a forged data window asked for any amount.
const MAX_EXPANSION: u128 = 1032;

/// Decode `bytes` and take the channels named `wanted`.
pub fn decode(bytes: &[u8], wanted: &[&str]) -> std::result::Result<ExrChannels, String> {
    check_sizes(bytes)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .pedantic()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| format!("not a readable OpenEXR file ({e})"))?;
    let layer = image.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let n = width * height;
    let list = &layer.channel_data.list;
    let mut channels = Vec::with_capacity(wanted.len());
    for &name in wanted {
        let c = list.iter().find(|c| c.name == *name).ok_or_else(|| {
            let present: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
            format!("no channel '{name}' (it has {})", present.join(", "))
        })?;
        let values: Vec<f32> = match &c.sample_data {
            FlatSamples::F32(v) => v.clone(),
            FlatSamples::F16(v) => v.iter().map(|x| x.to_f32()).collect(),
            FlatSamples::U32(_) => {
                return Err(format!("channel '{name}' holds integers, not floats"));
            }
        };
        if values.len() != n {
            return Err(format!(
                "channel '{name}' has {} samples for {width} × {height} pixels (subsampled?)",
                values.len()
            ));
        }
        channels.push(values);
    }
    Ok(ExrChannels {
        width,
        height,
        channels,
    })
}

/// Every layer's pixels (and its offset table) fit in what a file of this length can hold.
fn check_sizes(bytes: &[u8]) -> std::result::Result<(), String> {
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), true)
        .map_err(|e| format!("not a readable OpenEXR file ({e})"))?;
    let stored = bytes.len() as u128;
    for h in meta.headers.iter() {
        let (w, ht) = (h.layer_size.0, h.layer_size.1);
        let per_pixel: u128 = (h.channels.list.iter())
            .map(|c| c.sample_type.bytes_per_sample() as u128)
            .sum();
        let decoded = w as u128 * ht as u128 * per_pixel;
        if decoded > stored * MAX_EXPANSION || h.chunk_count as u128 * 8 > stored {
            return Err(format!(
                "its header declares {w} × {ht} pixels of {} channel(s), more than a file of \
                 {stored} bytes can hold",
                h.channels.list.len()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(channels: &[(&str, Vec<f32>)], w: usize, h: usize) -> Vec<u8> {
        let list = channels
            .iter()
            .map(|(n, v)| AnyChannel::new(*n, FlatSamples::F32(v.clone())))
            .collect();
        let layer = Layer::new(
            (w, h),
            LayerAttributes::default(),
            Encoding::UNCOMPRESSED,
            AnyChannels::sort(list),
        );
        let mut out = Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .non_parallel()
            .to_buffered(&mut out)
            .unwrap();
        out.into_inner()
    }

    #[test]
    fn channels_come_back_in_the_order_asked() {
        let bytes = file(&[("b", vec![1., 2., 3.]), ("a", vec![4., 5., 6.])], 3, 1);
        let c = decode(&bytes, &["b", "a"]).unwrap();
        assert_eq!((c.width, c.height), (3, 1));
        assert_eq!(c.channels, vec![vec![1., 2., 3.], vec![4., 5., 6.]]);
        let e = decode(&bytes, &["a", "footprint"]).unwrap_err();
        assert!(e.contains("no channel 'footprint' (it has a, b)"), "{e}");
    }

    #[test]
    fn truncated_or_garbage_bytes_are_errors() {
        let bytes = file(&[("a", vec![1.0; 64])], 8, 8);
        for cut in [bytes.len() - 1, bytes.len() / 2, 20, 0] {
            let e = decode(&bytes[..cut], &["a"]).unwrap_err();
            assert!(e.starts_with("not a readable OpenEXR file"), "{cut}: {e}");
        }
        assert!(decode(b"not an exr at all", &["a"]).is_err());
    }
}
