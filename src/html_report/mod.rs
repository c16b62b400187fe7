//! The designer's report document (`bake report --format html`): one self-contained HTML file a
//! designer hands to a client — inline CSS, inline SVG, images as `data:` URIs, no scripts, no
//! network.
//!
//! Input: a [`BakedOutput`], the same output imported as a [`Scene`] (for the views' luminaire
//! openings; `None`: no views), the [`report::Report`] built from it, and [`Options`]. Output:
//! the HTML text. Sections, in order: room summary (file, tool, settings, patches, contacts,
//! energy balance), luminaire schedule, targets, surfaces by node and by material (E avg / min /
//! max, U₀, U_d, direct, inter-reflected, luminance, covered area), working plane (figures, its
//! border zone and the flow of light, the isolux plan), false-colour views of the camera nodes,
//! cubic illuminance. Print CSS: A4 portrait, tables and figures never split across pages.
//! Deterministic: the same inputs give the same bytes (only the output's file name is shown, not
//! its folder).

mod figures;
mod html;
mod inline;
mod sections;
mod style;

use crate::Result;
use crate::readback::BakedOutput;
use crate::report::Report;
use crate::scene::Scene;
use html::escape;
use sections::{cubic, luminaires, room, surfaces, targets, views, working_plane};
use std::fmt::Write;

/// What the document shows beside the report.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Width of the plan and of each view (px).
    pub figure_width: u32,
    /// Render the camera nodes' views.
    pub views: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            figure_width: 640,
            views: true,
        }
    }
}

/// The HTML document.
pub fn document(
    input: &BakedOutput,
    scene: Option<&Scene>,
    rep: &Report,
    options: &Options,
) -> Result<String> {
    let summary = input.run_summary().ok().flatten();
    let file = (input.file.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut out = String::with_capacity(1 << 20);
    let _ = writeln!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>Lighting \
         report: {}</title>\n<style>\n{}</style>\n</head>\n<body>",
        escape(&file),
        style::CSS
    );
    let _ = writeln!(
        out,
        "<header><h1>Lighting report</h1><p class=\"sub\">{} · {} · illuminance in lx, \
         luminance in cd/m², lengths in m, +Y up</p></header>",
        escape(&file),
        escape(summary.as_ref().map_or("luxbake", |s| s.tool.as_str()))
    );
    room(&mut out, input, summary.as_ref());
    if let Some(rows) = &rep.luminaires {
        luminaires(&mut out, rows, rep);
    }
    if let Some(t) = &rep.targets {
        targets(&mut out, t);
    }
    // The heading and its note stay with the first table (`div.keep`).
    out.push_str("<section id=\"surfaces\">\n<div class=\"keep\">\n<h2>Surfaces</h2>\n");
    out.push_str(
        "<p class=\"note\">Averages are area-weighted; U₀ = E<sub>min</sub>/E<sub>avg</sub>, \
         U<sub>d</sub> = E<sub>min</sub>/E<sub>max</sub>. Parts covered by another surface \
         (the ceiling above a surface-mounted luminaire, the wall behind a picture) receive no \
         light; they are left out of every figure and their area is given apart.</p>\n",
    );
    let mut open = true;
    for (rows, id, what) in [
        (&rep.by_node, "by-node", "node"),
        (&rep.by_material, "by-material", "material"),
    ] {
        if let Some(rows) = rows {
            surfaces(&mut out, rows, id, what);
            if std::mem::take(&mut open) {
                out.push_str("</div>\n");
            }
        }
    }
    if open {
        out.push_str("</div>\n");
    }
    out.push_str("</section>\n");
    if let Some(p) = &rep.working_plane {
        working_plane(&mut out, input, p, options.figure_width)?;
    }
    if let Some(scene) = scene.filter(|_| options.views && !input.cameras.is_empty()) {
        views(&mut out, input, scene, options.figure_width)?;
    }
    if let Some(c) = &rep.cubic {
        cubic(&mut out, c);
    }
    out.push_str(
        "<footer><p>Computed by radiosity (luxbake): light from luminaires exact at every \
         point, inter-reflections between the room's surfaces solved to convergence. Values are \
         maintained values where the luminaires carry a maintenance factor.</p></footer>\n\
         </body>\n</html>\n",
    );
    Ok(out)
}
