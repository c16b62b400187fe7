//! The classic polar intensity diagram as standalone SVG.
//!
//! Input: a [`Photometry`]. Output: an SVG document (UTF-8 text, 480 × 540 user units): the
//! C0–C180 curve (solid red) and the C90–C270 curve (dashed blue) of absolute intensity in cd,
//! C0 / C90 to the right and C180 / C270 to the left, nadir (γ = 0°) down, zenith up; concentric
//! rings at round intensities labelled in cd; spokes every 30° labelled with γ; a title and a
//! legend.
//! Invariants: well-formed XML (text is escaped), deterministic output.

use std::fmt::Write;

use glam::DVec3;

use super::Photometry;

const CX: f64 = 240.0;
const CY: f64 = 270.0;
const R: f64 = 190.0;

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// A round ring spacing (1, 2 or 5 × 10ⁿ) giving 3–6 rings up to `max`.
fn ring_step(max: f64) -> f64 {
    let raw = max / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag)
}

/// Type-C-frame direction of signed angle `s` from the nadir in the plane of `c` (s < 0: c + 180°).
fn plane_dir(c: f64, s: f64) -> DVec3 {
    let (c, g) = if s >= 0.0 { (c, s) } else { (c + 180.0, -s) };
    let (sg, cg) = g.to_radians().sin_cos();
    let (sc, cc) = c.to_radians().sin_cos();
    DVec3::new(sg * cc, sg * sc, -cg)
}

pub(super) fn svg(p: &Photometry) -> String {
    let peak = p.max_intensity().0.max(1e-12);
    let step = ring_step(peak);
    let rings = (peak / step).ceil().max(1.0) as usize;
    let scale = R / (rings as f64 * step);
    let mut s = String::new();
    let title = p
        .info()
        .luminaire
        .clone()
        .or_else(|| p.info().catalog_number.clone())
        .unwrap_or_else(|| "Luminaire".into());
    let _ = writeln!(
        s,
        r##"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="480" height="540" viewBox="0 0 480 540" font-family="sans-serif" font-size="11">
<rect width="480" height="540" fill="white"/>
<text x="240" y="24" text-anchor="middle" font-size="{}">{}</text>
<text x="240" y="42" text-anchor="middle">Luminous intensity (cd), nadir down</text>
<text x="16" y="66" fill="#555">C180 / C270</text>
<text x="464" y="66" text-anchor="end" fill="#555">C0 / C90</text>"##,
        // Long names shrink to fit the 480 px width (about 0.55 em per character).
        (15.0f64)
            .min(460.0 / (0.55 * title.chars().count().max(1) as f64))
            .max(7.0)
            .round(),
        escape(&title.replace('\n', " "))
    );
    for k in 1..=rings {
        let r = k as f64 * step * scale;
        let _ = writeln!(
            s,
            r##"<circle cx="{CX}" cy="{CY}" r="{r:.2}" fill="none" stroke="#bbb" stroke-width="0.6"/>
<text x="{:.2}" y="{:.2}" fill="#555">{}</text>"##,
            CX + 3.0,
            CY - r - 2.0,
            format_cd(k as f64 * step)
        );
    }
    for a in (0..360).step_by(30) {
        let (sn, cs) = (a as f64).to_radians().sin_cos();
        let (x, y) = (CX + R * sn, CY + R * cs);
        let gamma = if a <= 180 { a } else { 360 - a };
        let (lx, ly) = (CX + (R + 14.0) * sn, CY + (R + 14.0) * cs + 4.0);
        let _ = writeln!(
            s,
            r##"<line x1="{CX}" y1="{CY}" x2="{x:.2}" y2="{y:.2}" stroke="#ddd" stroke-width="0.6"/>
<text x="{lx:.2}" y="{ly:.2}" text-anchor="middle" fill="#555">{gamma}°</text>"##
        );
    }
    for (c, colour, dash) in [
        (0.0, "#c0392b", ""),
        (90.0, "#2463b4", r#" stroke-dasharray="6 4""#),
    ] {
        let mut d = String::new();
        for k in -360..=360 {
            let sgn = f64::from(k) * 0.5;
            let r = p.intensity(plane_dir(c, sgn)) * scale;
            let (sn, cs) = sgn.to_radians().sin_cos();
            let cmd = if k == -360 { 'M' } else { 'L' };
            let _ = write!(d, "{cmd}{:.2},{:.2} ", CX + r * sn, CY + r * cs);
        }
        let _ = writeln!(
            s,
            r#"<path d="{}" fill="none" stroke="{colour}" stroke-width="1.8"{dash}/>"#,
            d.trim_end()
        );
    }
    let _ = writeln!(
        s,
        r##"<line x1="40" y1="510" x2="70" y2="510" stroke="#c0392b" stroke-width="1.8"/>
<text x="76" y="514">C0–C180</text>
<line x1="170" y1="510" x2="200" y2="510" stroke="#2463b4" stroke-width="1.8" stroke-dasharray="6 4"/>
<text x="206" y="514">C90–C270</text>
<text x="440" y="514" text-anchor="end" fill="#555">max {} cd</text>
</svg>"##,
        format_cd(p.max_intensity().0)
    );
    s
}

fn format_cd(v: f64) -> String {
    if v >= 100.0 || v == v.round() {
        format!("{v:.0}")
    } else if v >= 1.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.3}")
    }
}
