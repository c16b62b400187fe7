//! The report document's figures: the working plane's isolux plan (`plan`'s SVG, inlined), the
//! camera nodes' false-colour views (`view` + `picture::legend`, PNG as `data:` URIs), and a
//! plan of the working plane's grid with its border zone and the flow of light (the horizontal
//! part of each probe's illumination vector), drawn here as SVG.
//!
//! Everything is deterministic: same bake and options, same bytes.

use super::inline::data_uri;
use crate::picture::{legend, scale::ColourScale};
use crate::probes::metrics::from_faces;
use crate::readback::{BakedOutput, ProbeNode};
use crate::report::PlaneRow;
use crate::scene::Scene;
use crate::view::{self, Camera, ViewOptions};
use crate::{Error, Result};
use std::fmt::Write;

/// The isolux plan of the working plane as inline SVG (no XML declaration), `size` px wide.
pub(crate) fn plan_svg(input: &BakedOutput, size: u32) -> Result<String> {
    let options = crate::plan::Options {
        size,
        ..Default::default()
    };
    let svg = crate::plan::build(input, &options)?.svg();
    Ok(match svg.split_once("?>\n") {
        Some((_, rest)) if svg.starts_with("<?xml") => rest.to_string(),
        _ => svg,
    })
}

/// One false-colour view: its camera's name and the PNG's `data:` URI.
pub struct ViewFigure {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub uri: String,
}

/// A false-colour luminance view (log scale, 12 bands with their edges drawn) from each camera
/// node, `width` px wide (the camera's aspect ratio), 4 rays a pixel, all on one scale: the
/// automatic range over every view's pixels together, so one colour reads one luminance in
/// every figure of the report.
pub(crate) fn views(input: &BakedOutput, scene: &Scene, width: u32) -> Result<Vec<ViewFigure>> {
    let mut rendered = Vec::new();
    for node in &input.cameras {
        let name = node
            .name
            .clone()
            .unwrap_or_else(|| format!("node {}", node.node));
        let Ok(probe) = Camera::from_node(node, None, None) else {
            continue; // Orthographic cameras are not drawn.
        };
        let height = ((width as f64) * probe.height as f64 / probe.width as f64).round() as u32;
        let camera = Camera::from_node(node, Some((width, height.max(1))), None)?;
        let v = view::render(input, scene, &camera, &ViewOptions::default())?;
        let values: Vec<f64> = v.luminance().iter().map(|&y| y as f64).collect();
        rendered.push((name, camera, values));
    }
    let all: Vec<f64> = (rendered.iter())
        .flat_map(|(_, _, v)| v.iter().copied())
        .collect();
    let scale = ColourScale::auto(&all, true, 12);
    let mut out = Vec::new();
    for (name, camera, values) in rendered {
        let img = legend::false_colour(&values, camera.width, camera.height, &scale, "cd/m²", true);
        let png = crate::export::display::png_rgb8(&img)
            .map_err(|m| Error::output(&input.file, format!("view {name}: {m}")))?;
        out.push(ViewFigure {
            name,
            width: img.width,
            height: img.height,
            uri: data_uri("image/png", &png),
        });
    }
    Ok(out)
}

/// The working plane seen from above (x right, z down, +Y toward the viewer), `size` px wide:
/// its extent, the border zone shaded, each grid point (filled: taken; hollow: in the border),
/// and at every `step`-th point an arrow along the horizontal part of its illumination vector
/// (the flow of light), longest arrow 0.8 of the distance between arrows, clipped to the extent.
pub(crate) fn border_and_flow(input: &BakedOutput, plane: &PlaneRow, size: u32) -> String {
    let [x0, z0, x1, z1] = plane.extent;
    let (w_m, h_m) = ((x1 - x0).max(1e-9), (z1 - z0).max(1e-9));
    let margin = 8.0;
    let top = 22.0;
    let s = (size as f64 - 2.0 * margin) / w_m;
    let page = Page {
        x0,
        z0,
        w_m,
        h_m,
        margin,
        top,
        s,
    };
    let (w, h) = (size as f64, h_m * s + margin + top);
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" class="flow" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" role="img" aria-label="working plane: border zone and flow of light">"#
    );
    let b = plane.border;
    extent_and_border(&mut out, &page, b);
    let points: Vec<_> = input.probes.iter().filter(|p| p.working_plane).collect();
    grid_points(&mut out, &page, plane, &points);
    flow(&mut out, &page, plane.spacing.unwrap_or(0.25), &points);
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}" font-size="10" font-family="sans-serif">{w_m:.2} × {h_m:.2} m, border {b:.2} m</text>"#,
        margin,
        top - 8.0
    );
    out.push_str("</svg>\n");
    out
}

/// Where the working plane's extent (from `x0`, `z0`; `w_m` × `h_m` m) sits on the figure: `s`
/// px per metre, `margin` px in from the left, `top` px down.
struct Page {
    x0: f64,
    z0: f64,
    w_m: f64,
    h_m: f64,
    margin: f64,
    top: f64,
    s: f64,
}

impl Page {
    /// The figure's x (px) of the plane's `x` (m).
    fn px(&self, x: f64) -> f64 {
        self.margin + (x - self.x0) * self.s
    }

    /// The figure's y (px) of the plane's `z` (m).
    fn pz(&self, z: f64) -> f64 {
        self.top + (z - self.z0) * self.s
    }
}

/// The extent in grey with the inner area, `b` m in from each edge, white and dashed (the border
/// zone left grey); all white when the border leaves no inner area.
fn extent_and_border(out: &mut String, page: &Page, b: f64) {
    let Page {
        x0,
        z0,
        w_m,
        h_m,
        s,
        ..
    } = *page;
    let (px, pz) = (|x| page.px(x), |z| page.pz(z));
    let _ = writeln!(
        out,
        r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="#e8e8e8" stroke="#000"/>"##,
        px(x0),
        pz(z0),
        w_m * s,
        h_m * s
    );
    if b > 0.0 && 2.0 * b < w_m && 2.0 * b < h_m {
        let _ = writeln!(
            out,
            r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="#fff" stroke="#000" stroke-dasharray="4 3"/>"##,
            px(x0 + b),
            pz(z0 + b),
            (w_m - 2.0 * b) * s,
            (h_m - 2.0 * b) * s
        );
    } else {
        let _ = writeln!(
            out,
            r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="#fff"/>"##,
            px(x0),
            pz(z0),
            w_m * s,
            h_m * s
        );
    }
}

/// Each grid point: filled when taken, hollow when in the border zone.
fn grid_points(out: &mut String, page: &Page, plane: &PlaneRow, points: &[&ProbeNode]) {
    out.push_str(r##"<g fill="#333">"##);
    for p in points {
        let (x, z) = (page.px(p.position.x), page.pz(p.position.z));
        let r = 1.6;
        match crate::report::rows::inside_border(plane.extent, plane.border, p.position) {
            true => {
                let _ = write!(out, r#"<circle cx="{x:.1}" cy="{z:.1}" r="{r}"/>"#);
            }
            false => {
                let _ = write!(
                    out,
                    r##"<circle cx="{x:.1}" cy="{z:.1}" r="{r}" fill="none" stroke="#777" stroke-width="0.6"/>"##
                );
            }
        }
    }
    out.push_str("</g>\n");
}

/// The flow of light: at about a dozen grid points along the longer side (`spacing` m apart),
/// an arrow along the horizontal part of the illumination vector, clipped to the extent
/// (nothing when no point has a horizontal part).
fn flow(out: &mut String, page: &Page, spacing: f64, points: &[&ProbeNode]) {
    let Page {
        x0,
        z0,
        w_m,
        h_m,
        s,
        ..
    } = *page;
    let (px, pz) = (|x| page.px(x), |z| page.pz(z));
    let step = ((w_m.max(h_m) / spacing / 12.0).round() as usize).max(1);
    let longest = points
        .iter()
        .map(|p| {
            let v = from_faces(&p.faces, None).vector;
            (v[0] * v[0] + v[2] * v[2]).sqrt()
        })
        .fold(0.0, f64::max);
    if longest <= 0.0 {
        return;
    }
    // Arrows stay inside the plane's extent (a local clip path: nothing outside the file).
    let _ = write!(
        out,
        r##"<clipPath id="flow-clip"><rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}"/></clipPath><g clip-path="url(#flow-clip)" stroke="#c0392b" stroke-width="1.4" fill="#c0392b">"##,
        px(x0),
        pz(z0),
        w_m * s,
        h_m * s
    );
    let grid = |v: f64, lo: f64| ((v - lo) / spacing).floor() as i64;
    for p in points {
        let (x, z) = (p.position.x, p.position.z);
        if grid(x, x0) % step as i64 != (step / 2) as i64
            || grid(z, z0) % step as i64 != (step / 2) as i64
        {
            continue;
        }
        let v = from_faces(&p.faces, None).vector;
        let len = 0.8 * spacing * step as f64 / longest;
        let (ex, ez) = (x + v[0] * len, z + v[2] * len);
        let (ax, az, bx, bz) = (px(x), pz(z), px(ex), pz(ez));
        let _ = write!(
            out,
            r#"<line x1="{ax:.1}" y1="{az:.1}" x2="{bx:.1}" y2="{bz:.1}"/>"#
        );
        // Arrow head: a small triangle at the end.
        let (dx, dz) = (bx - ax, bz - az);
        let l = (dx * dx + dz * dz).sqrt();
        if l > 3.0 {
            let (ux, uz) = (dx / l, dz / l);
            let _ = write!(
                out,
                r#"<polygon points="{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}"/>"#,
                bx,
                bz,
                bx - 5.0 * ux + 2.5 * uz,
                bz - 5.0 * uz - 2.5 * ux,
                bx - 5.0 * ux - 2.5 * uz,
                bz - 5.0 * uz + 2.5 * ux
            );
        }
    }
    out.push_str("</g>\n");
}
