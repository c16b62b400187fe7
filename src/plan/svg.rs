//! A [`Drawing`] as SVG 1.1 text: vector throughout (cells as rectangles in a crisp-edged group,
//! lines as polylines, text as `<text>`), coordinates with at most two decimals, so the same
//! drawing always gives the same bytes.

use super::layout::{Anchor, Drawing, Item};
use std::fmt::Write;

/// The SVG document.
pub(crate) fn render(d: &Drawing) -> String {
    let mut s = String::with_capacity(64 * (d.field.len() + d.items.len()) + 512);
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans, Arial, Helvetica, sans-serif">"#,
        w = d.width,
        h = d.height
    );
    let _ = writeln!(s, "<title>{}</title>", escape(&d.title));
    let _ = writeln!(
        s,
        r##"<rect x="0" y="0" width="{}" height="{}" fill="#ffffff"/>"##,
        d.width, d.height
    );
    let _ = writeln!(s, r#"<g id="field" shape-rendering="crispEdges">"#);
    for item in &d.field {
        item_svg(&mut s, item);
    }
    let _ = writeln!(s, "</g>");
    for item in &d.items {
        item_svg(&mut s, item);
    }
    s.push_str("</svg>\n");
    s
}

fn item_svg(s: &mut String, item: &Item) {
    match item {
        Item::Rect { x, y, w, h, fill } => {
            let _ = writeln!(
                s,
                r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{}"/>"#,
                n(*x),
                n(*y),
                n(*w),
                n(*h),
                hex(*fill)
            );
        }
        Item::Line {
            points,
            colour,
            width,
        } => {
            let mut p = String::new();
            for (i, q) in points.iter().enumerate() {
                if i > 0 {
                    p.push(' ');
                }
                let _ = write!(p, "{},{}", n(q.x), n(q.y));
            }
            let _ = writeln!(
                s,
                r#"<polyline points="{p}" fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round"/>"#,
                hex(*colour),
                n(*width)
            );
        }
        Item::Text {
            x,
            y,
            size,
            text,
            colour,
            anchor,
        } => {
            let anchor = match anchor {
                Anchor::Start => "start",
                Anchor::Middle => "middle",
                Anchor::End => "end",
            };
            // y is the text box's top; the baseline sits about 0.8 of the size below it.
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" font-size="{size}" text-anchor="{anchor}" fill="{}">{}</text>"#,
                n(*x),
                n(*y + 0.8 * *size as f64),
                hex(*colour),
                escape(text)
            );
        }
    }
}

/// A coordinate with at most two decimals, no trailing zeros.
fn n(v: f64) -> String {
    let s = format!("{:.2}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// Text escaped for XML character data.
fn escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    #[test]
    fn numbers_are_short_and_stable() {
        assert_eq!(super::n(1.0), "1");
        assert_eq!(super::n(1.256), "1.26");
        assert_eq!(super::n(-0.001), "0");
        assert_eq!(super::n(10.5), "10.5");
    }
}
