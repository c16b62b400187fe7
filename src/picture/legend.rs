//! False-colour images with a legend (stub; filled in next).

use super::Rgb8Image;
use super::scale::ColourScale;

/// The false-colour image of `values` with a legend strip on the right.
pub fn false_colour(
    values: &[f64],
    w: u32,
    h: u32,
    scale: &ColourScale,
    _unit: &str,
    _contours: bool,
) -> Rgb8Image {
    let mut img = Rgb8Image::new(w, h, [64; 3]);
    for (p, v) in img.pixels.iter_mut().zip(values) {
        if v.is_finite() {
            *p = scale.colour(*v);
        }
    }
    img
}
