//! Pictures made of numbers, knowing nothing of scenes: 8-bit sRGB images ([`Rgb8Image`]), the
//! false-colour scale ([`scale`]: linear or logarithmic, round automatic ranges, bands),
//! isolines ([`contours`]: marching squares), a built-in bitmap font for legends and labels
//! ([`font`]), false-colour images with their legend ([`legend`]), and tone mapping of luminance
//! images for the adapted eye ([`tonemap`]: Ward Larson, Rushmeier & Piatko 1997 histogram
//! adjustment).
//!
//! Input: numbers (linear values, cd/m² or lx) and pixel coordinates (x right, y down, row 0 at
//! the top). Output: [`Rgb8Image`]s, sRGB-encoded; `export::display::png_rgb8` writes them.
//! Invariants: everything is deterministic (no threads, no hashing order); drawing outside an
//! image is clipped, never a panic. Imports nothing of the crate (row 16 of ARCHITECTURE.md).

pub mod contours;
pub mod font;
pub mod legend;
pub mod scale;
pub mod tonemap;

use glam::DVec2;

/// An 8-bit sRGB image: `pixels[y * width + x]`, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rgb8Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[u8; 3]>,
}

impl Rgb8Image {
    /// A `width` × `height` image of one colour.
    pub fn new(width: u32, height: u32, fill: [u8; 3]) -> Self {
        Rgb8Image {
            width,
            height,
            pixels: vec![fill; width as usize * height as usize],
        }
    }

    /// The pixel at (x, y); panics outside the image.
    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        assert!(x < self.width && y < self.height, "({x}, {y}) outside");
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Set the pixel at (x, y); pixels outside the image are ignored.
    pub(crate) fn put(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height) {
            self.pixels[y as usize * self.width as usize + x as usize] = c;
        }
    }

    /// A 1-pixel line from `a` to `b` (pixel coordinates: pixel (x, y) covers [x, x+1) × [y, y+1)),
    /// one pixel per step along the major axis (DDA), both ends included; clipped to the image.
    pub fn line(&mut self, a: DVec2, b: DVec2, c: [u8; 3]) {
        if !(a.is_finite() && b.is_finite()) {
            return;
        }
        let d = b - a;
        let n = d.x.abs().max(d.y.abs()).ceil();
        // Far outside lines are clipped by bounding the step count (no huge loops).
        let limit = 4.0 * f64::from(self.width.max(self.height)) + 4.0;
        if n > limit {
            let (a, b) = match clip(a, b, self.width, self.height) {
                Some(ab) => ab,
                None => return,
            };
            return self.line(a, b, c);
        }
        let steps = n as i64;
        for i in 0..=steps {
            let t = if steps == 0 {
                0.0
            } else {
                i as f64 / steps as f64
            };
            let p = a + d * t;
            self.put(p.x.floor() as i64, p.y.floor() as i64, c);
        }
    }

    /// Fill the rectangle [x, x + w) × [y, y + h), clipped.
    pub(crate) fn fill_rect(&mut self, x: i64, y: i64, w: u32, h: u32, c: [u8; 3]) {
        let x0 = x.max(0);
        let y0 = y.max(0);
        let x1 = (x + i64::from(w)).min(i64::from(self.width));
        let y1 = (y + i64::from(h)).min(i64::from(self.height));
        for yy in y0..y1 {
            for xx in x0..x1 {
                self.pixels[yy as usize * self.width as usize + xx as usize] = c;
            }
        }
    }

    /// Copy `other` with its top-left pixel at (x, y), clipped.
    pub(crate) fn paste(&mut self, other: &Rgb8Image, x: i64, y: i64) {
        for oy in 0..other.height {
            for ox in 0..other.width {
                self.put(x + i64::from(ox), y + i64::from(oy), other.get(ox, oy));
            }
        }
    }
}

/// The part of segment `a`–`b` inside the image's box grown by one pixel (Liang–Barsky).
fn clip(a: DVec2, b: DVec2, width: u32, height: u32) -> Option<(DVec2, DVec2)> {
    let lo = DVec2::splat(-1.0);
    let hi = DVec2::new(f64::from(width) + 1.0, f64::from(height) + 1.0);
    let d = b - a;
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| (a + d * t0, a + d * t1))
}

/// IEC 61966-2-1 (sRGB) encoding of a linear value, clamped to [0, 1] (NaN → 0), rounded to the
/// nearest byte.
pub fn srgb8(linear: f64) -> u8 {
    let c = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_transfer() {
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(f64::NAN), 0);
        assert_eq!(srgb8(-1.0), 0);
        assert_eq!(srgb8(0.5), 188); // 0.7354 × 255 = 187.5
        assert_eq!(srgb8(0.002), 7); // linear segment: 0.02584 × 255 = 6.59
    }

    #[test]
    fn drawing_clips() {
        let mut img = Rgb8Image::new(4, 3, [0; 3]);
        img.put(-1, 0, [9; 3]);
        img.put(4, 0, [9; 3]);
        img.fill_rect(-2, -2, 3, 3, [1; 3]);
        assert_eq!(img.get(0, 0), [1; 3]);
        assert_eq!(img.get(1, 0), [0; 3]);
        img.line(DVec2::new(0.5, 2.5), DVec2::new(3.5, 2.5), [2; 3]);
        assert!((0..4).all(|x| img.get(x, 2) == [2; 3]));
        img.line(DVec2::new(-1e9, 1.5), DVec2::new(1e9, 1.5), [3; 3]);
        assert!((0..4).all(|x| img.get(x, 1) == [3; 3]));
        let mut big = Rgb8Image::new(5, 5, [0; 3]);
        big.paste(&img, 3, 3);
        assert_eq!(big.get(3, 4), [3; 3]);
        assert_eq!(big.get(4, 3), [0; 3]);
    }
}
