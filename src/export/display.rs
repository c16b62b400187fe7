//! A lightmap atlas's display colours as the PNG a glTF viewer shows, and any
//! [`Rgb8Image`] (views, false colour, plans) as a PNG: the crate's only use of the `png` crate.
//!
//! Input: an [`Atlas`]'s `display` (linear, each component in [0, 1]). Output: the bytes of an
//! 8-bit RGB PNG of W × H pixels, first row = atlas row 0 (glTF's v = 0, the top), each component
//! sRGB-encoded (IEC 61966-2-1, as glTF's colour textures are) and rounded to the nearest byte.
//! [`png_rgb8`]: an [`Rgb8Image`] (already sRGB bytes, row 0 at the top) as an 8-bit RGB PNG
//! with an `sRGB` chunk (perceptual intent; the `gAMA`/`cHRM` fallbacks the PNG spec gives).
//! Invariants: equal atlases (images) give equal bytes; NaN shows as 0, values outside [0, 1] are
//! clamped.

use crate::picture::Rgb8Image;
use crate::result::Atlas;

/// The PNG bytes of `img` (8-bit RGB, `sRGB` chunk); an error message when the image is
/// empty or its pixel count does not match its size.
pub fn png_rgb8(img: &Rgb8Image) -> Result<Vec<u8>, String> {
    let n = img.width as usize * img.height as usize;
    if n == 0 || img.pixels.len() != n {
        return Err(format!(
            "a {} × {} image has {} pixels",
            img.width,
            img.height,
            img.pixels.len()
        ));
    }
    let bytes: Vec<u8> = img.pixels.iter().flatten().copied().collect();
    let mut out = Vec::new();
    let mut encoder = ::png::Encoder::new(&mut out, img.width, img.height);
    encoder.set_color(::png::ColorType::Rgb);
    encoder.set_depth(::png::BitDepth::Eight);
    encoder.set_source_srgb(::png::SrgbRenderingIntent::Perceptual);
    let fail = |e: ::png::EncodingError| format!("cannot encode the PNG: {e}");
    let mut writer = encoder.write_header().map_err(fail)?;
    writer.write_image_data(&bytes).map_err(fail)?;
    writer.finish().map_err(fail)?;
    Ok(out)
}

/// The PNG bytes of `atlas.display`; an error message when the atlas is inconsistent.
pub(crate) fn png(atlas: &Atlas) -> Result<Vec<u8>, String> {
    let n = atlas.width as usize * atlas.height as usize;
    if n == 0 || atlas.display.len() != n {
        return Err(format!(
            "a {} × {} atlas has {} display colours",
            atlas.width,
            atlas.height,
            atlas.display.len()
        ));
    }
    let pixels: Vec<u8> = atlas.display.iter().flatten().map(|&c| srgb8(c)).collect();
    let mut out = Vec::new();
    let mut encoder = ::png::Encoder::new(&mut out, atlas.width, atlas.height);
    encoder.set_color(::png::ColorType::Rgb);
    encoder.set_depth(::png::BitDepth::Eight);
    let fail = |e: ::png::EncodingError| format!("cannot encode the display PNG: {e}");
    let mut writer = encoder.write_header().map_err(fail)?;
    writer.write_image_data(&pixels).map_err(fail)?;
    writer.finish().map_err(fail)?;
    Ok(out)
}

/// A linear component as an 8-bit sRGB-encoded byte (`picture::srgb8`).
pub(crate) fn srgb8(linear: f32) -> u8 {
    crate::picture::srgb8(f64::from(linear))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_and_layout() {
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(f32::NAN), 0);
        assert_eq!(srgb8(2.0), 255);
        // 0.5 linear is 0.7354 encoded: 187.5 → 188.
        assert_eq!(srgb8(0.5), 188);
        assert_eq!(srgb8(0.002), 7); // the linear segment: 0.02584 × 255 = 6.59

        let mut atlas = Atlas::new(2, 1);
        atlas.display = vec![[1.0, 0.0, 0.0], [0.0, 0.0, 0.5]];
        let bytes = png(&atlas).unwrap();
        let decoder = ::png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (2, 1));
        assert_eq!(&buf[..6], &[255, 0, 0, 0, 0, 188]);
    }

    #[test]
    fn rgb8_png_has_srgb_chunk_and_pixels() {
        let mut img = Rgb8Image::new(3, 2, [10, 20, 30]);
        img.put(2, 1, [255, 0, 7]);
        let bytes = png_rgb8(&img).unwrap();
        assert_eq!(bytes, png_rgb8(&img).unwrap());
        assert!(bytes.windows(4).any(|w| w == b"sRGB"), "an sRGB chunk");
        let decoder = ::png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        assert!(reader.info().srgb.is_some());
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(&buf[..3], &[10, 20, 30]);
        assert_eq!(&buf[15..18], &[255, 0, 7]);
        assert!(png_rgb8(&Rgb8Image::new(0, 2, [0; 3])).is_err());
    }
}
