//! A [`Drawing`] rasterised into an sRGB image with `picture`'s primitives: rectangles with
//! edges rounded to whole pixels (so adjacent cells tile without gaps or overlaps), 1-pixel lines
//! (a 2-pixel line drawn twice, one pixel apart across it), text in the built-in bitmap font
//! (characters it lacks written as their nearest ASCII: U₀ as U0, arrows as -> and v).

use super::layout::{Anchor, Drawing, Item, WHITE};
use crate::picture::Rgb8Image;
use crate::picture::font::{draw_text, text_size};
use glam::DVec2;

/// The image.
pub(crate) fn render(d: &Drawing) -> Rgb8Image {
    let mut img = Rgb8Image::new(d.width, d.height, WHITE);
    for item in d.field.iter().chain(&d.items) {
        match item {
            Item::Rect { x, y, w, h, fill } => {
                // Edges nudged by 10⁻⁶ px: a cell's right edge and its neighbour's left edge,
                // computed apart, round to the same pixel.
                let snap = |v: f64| (v + 1e-6).round();
                let (x0, y0) = (snap(*x), snap(*y));
                let (x1, y1) = (snap(x + w), snap(y + h));
                if x1 > x0 && y1 > y0 {
                    let (cw, ch) = ((x1 - x0) as u32, (y1 - y0) as u32);
                    img.fill_rect(x0 as i64, y0 as i64, cw, ch, *fill);
                }
            }
            Item::Line {
                points,
                colour,
                width,
            } => {
                for w in points.windows(2) {
                    img.line(w[0], w[1], *colour);
                    if *width >= 1.5 {
                        // The second pixel: one pixel across the segment's main direction.
                        let d = w[1] - w[0];
                        let off = if d.x.abs() >= d.y.abs() {
                            DVec2::Y
                        } else {
                            DVec2::X
                        };
                        img.line(w[0] + off, w[1] + off, *colour);
                    }
                }
            }
            Item::Text {
                x,
                y,
                size,
                text,
                colour,
                anchor,
            } => {
                let t = plain(text);
                let (tw, _) = text_size(&t, *size);
                let x = match anchor {
                    Anchor::Start => *x,
                    Anchor::Middle => x - tw as f64 / 2.0,
                    Anchor::End => x - tw as f64,
                };
                draw_text(
                    &mut img,
                    x.round() as i64,
                    y.round() as i64,
                    &t,
                    *size,
                    *colour,
                );
            }
        }
    }
    img
}

/// Text with the characters the bitmap font lacks replaced.
pub(crate) fn plain(t: &str) -> String {
    t.replace('\u{2080}', "0")
        .replace('\u{2192}', "->")
        .replace('\u{2193}', "v")
}
