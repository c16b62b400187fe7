//! Encoded images (PNG, JPEG): recognising their type and computing their mean linear colour.
//!
//! Inputs: encoded bytes. Outputs: the media type (`image/png`, `image/jpeg`), the mean over
//! all texels of the sRGB-decoded (linear) RGB values, alpha ignored, and the 8-bit texels
//! themselves (`decode_rgb8`, for the views' display mode).
//! Invariant: the type comes from the bytes' signature, never from a file name or a declared
//! media type (those can be wrong); decoding errors become messages, never panics.

use glam::DVec3;

/// The media type of PNG or JPEG bytes; `None` for anything else.
pub(crate) fn sniff_mime(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else {
        None
    }
}

/// The sRGB electro-optical transfer function (IEC 61966-2-1): encoded [0, 1] → linear.
pub(crate) fn srgb_to_linear(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Mean linear RGB of an encoded PNG/JPEG image (texel values are sRGB-encoded, as glTF
/// requires for base colour textures).
pub(crate) fn mean_linear_rgb(bytes: &[u8]) -> Result<DVec3, String> {
    let format = match sniff_mime(bytes) {
        Some("image/png") => image::ImageFormat::Png,
        Some(_) => image::ImageFormat::Jpeg,
        None => return Err("not a PNG or JPEG image".into()),
    };
    let decoded = image::load_from_memory_with_format(bytes, format)
        .map_err(|e| format!("cannot decode the image: {e}"))?;
    let eight_bit = matches!(
        decoded.color(),
        image::ColorType::L8
            | image::ColorType::La8
            | image::ColorType::Rgb8
            | image::ColorType::Rgba8
    );
    let mut sum = DVec3::ZERO;
    let texels;
    if eight_bit {
        let lut: Vec<f64> = (0..256).map(|i| srgb_to_linear(i as f64 / 255.0)).collect();
        let rgb = decoded.to_rgb8();
        texels = rgb.pixels().len();
        for p in rgb.pixels() {
            sum += DVec3::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]);
        }
    } else {
        let rgb = decoded.to_rgb32f();
        texels = rgb.pixels().len();
        for p in rgb.pixels() {
            sum += DVec3::new(
                srgb_to_linear(p[0].clamp(0.0, 1.0) as f64),
                srgb_to_linear(p[1].clamp(0.0, 1.0) as f64),
                srgb_to_linear(p[2].clamp(0.0, 1.0) as f64),
            );
        }
    }
    if texels == 0 {
        return Err("the image has no texels".into());
    }
    Ok(sum / texels as f64)
}

/// An encoded PNG/JPEG image decoded to 8-bit RGB (alpha dropped): (width, height, texels
/// row-major from the top), the bytes as stored (sRGB-encoded for colour textures).
pub fn decode_rgb8(bytes: &[u8]) -> Result<(u32, u32, Vec<[u8; 3]>), String> {
    let format = match sniff_mime(bytes) {
        Some("image/png") => image::ImageFormat::Png,
        Some(_) => image::ImageFormat::Jpeg,
        None => return Err("not a PNG or JPEG image".into()),
    };
    let rgb = image::load_from_memory_with_format(bytes, format)
        .map_err(|e| format!("cannot decode the image: {e}"))?
        .to_rgb8();
    let texels = rgb.pixels().map(|p| p.0).collect();
    Ok((rgb.width(), rgb.height(), texels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-12);
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-6);
    }

    #[test]
    fn mean_of_png() {
        let img = image::RgbImage::from_fn(2, 1, |x, _| {
            if x == 0 {
                image::Rgb([255, 0, 0])
            } else {
                image::Rgb([0, 0, 255])
            }
        });
        let mut bytes = Vec::new();
        img.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
        assert_eq!(sniff_mime(&bytes), Some("image/png"));
        let mean = mean_linear_rgb(&bytes).unwrap();
        assert!((mean - DVec3::new(0.5, 0.0, 0.5)).abs().max_element() < 1e-12);
    }
}
