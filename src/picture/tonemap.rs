//! Tone mapping for the adapted eye (stub; filled in next).

use super::{Rgb8Image, srgb8};

/// A tone-mapped image and the adaptation luminance used.
#[derive(Debug, Clone)]
pub struct ToneMapped {
    pub image: Rgb8Image,
    /// Mean log of the foveal samples (cd/m²).
    pub adaptation_cd_m2: f64,
}

/// Tone map linear RGB luminances (cd/m²), row 0 top.
pub fn histogram_adjustment(rgb: &[[f32; 3]], w: u32, h: u32, _vfov_deg: f64) -> ToneMapped {
    let mut image = Rgb8Image::new(w, h, [0; 3]);
    for (p, c) in image.pixels.iter_mut().zip(rgb) {
        *p = c.map(|v| srgb8(f64::from(v) / 100.0));
    }
    ToneMapped {
        image,
        adaptation_cd_m2: 1.0,
    }
}
