//! A built-in bitmap font (stub; filled in next).

use super::Rgb8Image;

/// Draw `text` with its top-left corner at (x, y).
pub fn draw_text(img: &mut Rgb8Image, x: i64, y: i64, text: &str, height_px: u32, c: [u8; 3]) {
    let (w, h) = text_size(text, height_px);
    img.fill_rect(x, y, w, h, c);
}

/// The size (width, height) in pixels of `text` drawn at `height_px`.
pub fn text_size(text: &str, height_px: u32) -> (u32, u32) {
    (text.chars().count() as u32 * height_px * 2 / 3, height_px)
}
