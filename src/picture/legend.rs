//! A false-colour image of a grid of values with its legend strip on the right.
//!
//! Input: values (w × h, row-major, row 0 at the top; NaN = no data), a [`ColourScale`], the
//! unit's text ("cd/m²" or "lx") and whether to draw contours. Output: an [`Rgb8Image`] of
//! (w + strip) × max(h, the legend's least height): the values in the scale's colours (no
//! data dark grey), with contours the band-edge pixels black on light colours and white on
//! dark ones; right of it on white, the unit (and "log" when logarithmic) at the top, the
//! colour bar (top = hi) with a tick at each level and a label at each the scale labels (every
//! level when linear; 1, 2, 5 × 10^k when logarithmic), "≥ hi" / "≤ lo" where values lie
//! beyond the range (an automatic range leaves the extremes out). Invariants: text size grows
//! with the image (scale ⌊h / 240⌋, 1 … 4); the bar has at least one text line per band, so
//! labels never overlap (the image grows taller than h when it must); deterministic.

use super::Rgb8Image;
use super::contours::band_edges;
use super::font::{draw_text, text_size};
use super::scale::ColourScale;

/// Colour of samples without data.
pub const NO_DATA: [u8; 3] = [64, 64, 64];
const PAPER: [u8; 3] = [255, 255, 255];
const INK: [u8; 3] = [0, 0, 0];

/// The false-colour image of `values` (w × h, row 0 top; NaN = no data, drawn dark grey), with
/// contour lines when asked, and a legend strip on the right: colour bar, level labels, unit
/// ("cd/m²" or "lx"), "log" when logarithmic.
pub fn false_colour(
    values: &[f64],
    w: u32,
    h: u32,
    scale: &ColourScale,
    unit: &str,
    contours: bool,
) -> Rgb8Image {
    let field = coloured(values, w, h, scale, contours);
    let strip = legend(scale, unit, h);
    let mut img = Rgb8Image::new(w + strip.width, h.max(strip.height), PAPER);
    img.paste(&field, 0, 0);
    img.paste(&strip, i64::from(w), 0);
    img
}

/// The values in the scale's colours, with band edges drawn when `contours`.
pub(crate) fn coloured(
    values: &[f64],
    w: u32,
    h: u32,
    scale: &ColourScale,
    contours: bool,
) -> Rgb8Image {
    let mut img = Rgb8Image::new(w, h, NO_DATA);
    for (p, v) in img.pixels.iter_mut().zip(values) {
        if !v.is_nan() {
            *p = scale.colour(*v);
        }
    }
    if contours {
        for (p, edge) in img.pixels.iter_mut().zip(band_edges(values, w, h, scale)) {
            if edge {
                *p = contrasting(*p);
            }
        }
    }
    img
}

/// Black on a light colour, white on a dark one (by Rec. 709 luma of the sRGB bytes).
pub(crate) fn contrasting(c: [u8; 3]) -> [u8; 3] {
    let luma = 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]);
    if luma > 128.0 { INK } else { PAPER }
}

/// The text line height for an image `h` pixels high (a multiple of the font's 9 rows).
pub(crate) fn text_height(h: u32) -> u32 {
    9 * (h / 240).clamp(1, 4)
}

/// The legend strip for an image `h` pixels high: at least `h` high when it fits in it, more
/// when its labels need more room.
pub(crate) fn legend(scale: &ColourScale, unit: &str, h: u32) -> Rgb8Image {
    let lh = text_height(h);
    let s = i64::from(lh / 9);
    let pad = 6 * s;
    let bar_w = 14 * s;
    let tick = 4 * s;
    let levels = scale.levels();
    let labels = scale.legend_labels();
    let title_lines: Vec<&str> = if scale.log {
        vec![unit, "log"]
    } else {
        vec![unit]
    };
    let label_w = labels
        .iter()
        .map(String::as_str)
        .chain(title_lines.iter().copied())
        .map(|t| i64::from(text_size(t, lh).0))
        .max()
        .unwrap_or(0);
    let width = pad + bar_w + tick + 2 * s + label_w.max(bar_w) + pad;
    let lh64 = i64::from(lh);
    let top = pad + title_lines.len() as i64 * (lh64 + s) + pad + lh64 / 2;
    // room for every label one line apart, and at least the image's height
    let least = top + (levels.len() as i64 - 1) * (lh64 + s) + lh64 / 2 + pad;
    let height = least.max(i64::from(h));
    let bottom = height - pad - lh64 / 2;
    let mut img = Rgb8Image::new(width as u32, height as u32, PAPER);
    for (k, t) in title_lines.iter().enumerate() {
        draw_text(&mut img, pad, pad + k as i64 * (lh64 + s), t, lh, INK);
    }
    // the bar, top = hi, one colour per row at the row's middle
    let span = (bottom - top) as f64;
    for y in top..bottom {
        let t = 1.0 - ((y - top) as f64 + 0.5) / span;
        img.fill_rect(pad, y, bar_w as u32, 1, scale.colour(scale.value_at(t)));
    }
    outline(&mut img, pad, top, bar_w, bottom - top);
    // ticks and labels: the bar is at least one line per band high, so labels never touch
    let ys: Vec<i64> = levels
        .iter()
        .map(|&v| top + ((1.0 - scale.position(v)) * span).round() as i64)
        .collect();
    for (k, &y) in ys.iter().enumerate() {
        img.fill_rect(pad + bar_w, y - s / 2, tick as u32, s.max(1) as u32, INK);
        let text_top = y - (7 * s) / 2;
        draw_text(
            &mut img,
            pad + bar_w + tick + 2 * s,
            text_top,
            &labels[k],
            lh,
            INK,
        );
    }
    img
}

/// A 1-pixel black frame round the rectangle.
fn outline(img: &mut Rgb8Image, x: i64, y: i64, w: i64, h: i64) {
    img.fill_rect(x - 1, y - 1, (w + 2) as u32, 1, INK);
    img.fill_rect(x - 1, y + h, (w + 2) as u32, 1, INK);
    img.fill_rect(x - 1, y, 1, h as u32, INK);
    img.fill_rect(x + w, y, 1, h as u32, INK);
}
