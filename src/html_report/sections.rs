//! The sections of the report document, each written into the HTML text in order (see the
//! module above): room summary, luminaire schedule, targets, surfaces, working plane, views,
//! cubic illuminance. Illuminances in whole lx, ratios to two decimals, as the text report.

use super::figures;
use super::html::{escape, facts, section};
use crate::Result;
use crate::readback::BakedOutput;
use crate::report::{self, Report, Row};
use crate::scene::Scene;
use crate::summary::RunSummary;
use std::fmt::Write;

pub(super) fn room(out: &mut String, input: &BakedOutput, s: Option<&RunSummary>) {
    out.push_str("<section id=\"room\">\n<h2>Room summary</h2>\n");
    let area = |f: &dyn Fn(&Row) -> bool| -> f64 {
        let rows = report::rows::by_node(input, &report::Filter::All);
        rows.iter()
            .filter(|r| f(r))
            .map(|r| r.area + r.covered_area)
            .sum()
    };
    let mut pairs = vec![
        (
            "File",
            input
                .file
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
        ),
        ("Baked primitives", input.primitives.len().to_string()),
        ("Surface area", format!("{:.2} m²", area(&|_| true))),
    ];
    if let Some(s) = s {
        let st = &s.settings;
        pairs.extend([
            ("Tool", s.tool.clone()),
            (
                "Quality",
                format!(
                    "{:?}, patches {:.3} m{}",
                    st.quality,
                    s.patch_size,
                    if st.uniform_patches {
                        " (uniform)"
                    } else {
                        ", refined where light changes"
                    }
                )
                .to_lowercase(),
            ),
            (
                "Patches",
                format!("{} ({} vertices)", s.counts.patches, s.counts.receivers),
            ),
            (
                "Working plane",
                st.working_plane.map_or("none".into(), |g| {
                    format!("{:.2} m above the floor, grid {:.2} m", g.height, g.spacing)
                }),
            ),
            (
                "Lightmaps",
                s.lightmaps
                    .as_ref()
                    .map_or("none (figures from vertices)".into(), |l| {
                        format!("{} texels of {:.3} m", l.texels, l.texel_size_m)
                    }),
            ),
            (
                "Covered surfaces",
                format!(
                    "{:.2} m² ({} contacts)",
                    s.contacts.covered_area_m2, s.contacts.covers
                ),
            ),
            (
                "Luminous flux emitted",
                format!("{:.0} lm", s.energy.emitted_lm),
            ),
            ("Absorbed", format!("{:.0} lm", s.energy.absorbed_lm)),
            ("Escaped", format!("{:.0} lm", s.energy.escaped_lm)),
            (
                "Energy balance error",
                format!(
                    "{:.1} lm ({:.3} %)",
                    s.energy.balance_error_lm,
                    100.0 * s.energy.balance_error_relative
                ),
            ),
            (
                "Solver",
                format!(
                    "{} iterations, relative residual {:.1e}",
                    s.solver.iterations, s.solver.relative_residual
                ),
            ),
        ]);
    }
    facts(out, "room-facts", &pairs);
    out.push_str("</section>\n");
}

pub(super) fn luminaires(out: &mut String, rows: &[report::ScheduleRow], rep: &Report) {
    out.push_str("<section id=\"luminaires\">\n<h2>Luminaire schedule</h2>\n");
    section(
        out,
        "schedule",
        "Luminaires by type",
        &report::render::schedule(rows),
    );
    out.push_str(
        "<p class=\"note\">Lamp lm: rated lamp flux of one luminaire (its profile); LOR: light \
         output ratio; MF: maintenance factor; dimming: the scene's multiplier; emitted: flux \
         leaving one luminaire and all of them (rated × dimming × LOR × MF); power: from the \
         luminaire node's <code>extras.power_W</code>.</p>\n",
    );
    let flux: f64 = rows.iter().map(|r| r.emitted_total_lm).sum();
    let power: Option<f64> = rows.iter().map(|r| r.power_total_w).sum();
    let mut line = format!(
        "Total: {} sources, {flux:.0} lm",
        rows.iter().map(|r| r.count).sum::<usize>()
    );
    if let Some(p) = power {
        let _ = write!(line, ", {p:.1} W ({:.0} lm/W)", flux / p);
        if let Some(w) = &rep.working_plane {
            let a = (w.extent[2] - w.extent[0]) * (w.extent[3] - w.extent[1]);
            let _ = write!(line, ", {:.2} W/m² over the {a:.1} m² plan", p / a);
        }
    }
    let _ = writeln!(out, "<p>{}.</p>", escape(&line));
    out.push_str("</section>\n");
}

pub(super) fn targets(out: &mut String, rows: &[report::TargetRow]) {
    out.push_str(
        "<section id=\"targets\">\n<h2>Targets</h2>\n<p class=\"note\">A target passes when the \
         average achieved is at least the target (EN 12464-1's maintained illuminance is a \
         floor the average must not fall below); the ratio shows by how much it is over.</p>\n",
    );
    section(
        out,
        "targets-table",
        "Average illuminance against the design",
        &report::render::targets(rows),
    );
    out.push_str("</section>\n");
}

pub(super) fn surfaces(out: &mut String, rows: &[Row], id: &str, what: &'static str) {
    let title = match what {
        "material" => "Surfaces by material",
        _ => "Surfaces by node",
    };
    let table = report::render::surfaces(title, what, rows);
    section(out, id, &table.title, &table);
}

pub(super) fn working_plane(
    out: &mut String,
    input: &BakedOutput,
    p: &report::PlaneRow,
    width: u32,
) -> Result<()> {
    out.push_str("<section id=\"working-plane\">\n<div class=\"keep\">\n<h2>Working plane</h2>\n");
    section(
        out,
        "plane",
        &format!(
            "Illuminance on the working plane, points at least {:.2} m from its edges",
            p.border
        ),
        &report::render::plane(p),
    );
    let _ = writeln!(
        out,
        "<p class=\"note\">The plane's extent is its grid points' extent grown by half the \
         spacing (for a rectangular room, the room's inside): x {:.2}–{:.2} m, z {:.2}–{:.2} m. \
         The border zone (EN 12464-1 calculation grids) leaves out the points closer than {:.2} m \
         to its edges.</p>",
        p.extent[0], p.extent[2], p.extent[1], p.extent[3], p.border
    );
    out.push_str("</div>\n<div class=\"row\">\n");
    let flow = figures::border_and_flow(input, p, width * 3 / 8);
    let _ = writeln!(out, "<figure id=\"flow\"{}>", figure_width(&flow));
    out.push_str(&flow);
    out.push_str(
        "<figcaption>The working plane from above (x to the right, z down): points taken \
         (filled) and in the border zone (hollow, shaded band); arrows: the flow of light, the \
         horizontal part of the illumination vector at every few points.</figcaption>\n</figure>\n",
    );
    let plan = figures::plan_svg(input, width * 2 / 3)?;
    let _ = writeln!(out, "<figure id=\"plan\"{}>", figure_width(&plan));
    out.push_str(&plan);
    out.push_str(
        "<figcaption>Isolux plan of the working plane (all points, border zone included).\
         </figcaption>\n</figure>\n</div>\n</section>\n",
    );
    Ok(())
}

pub(super) fn views(
    out: &mut String,
    input: &BakedOutput,
    scene: &Scene,
    width: u32,
) -> Result<()> {
    let figures = figures::views(input, scene, width)?;
    if figures.is_empty() {
        return Ok(());
    }
    out.push_str("<section id=\"views\">\n<h2>False-colour views</h2>\n");
    for f in figures {
        let _ = writeln!(
            out,
            "<figure class=\"view\"><img src=\"{}\" width=\"{}\" height=\"{}\" alt=\"{}\">\
             <figcaption>{}: luminance (cd/m², log scale)</figcaption></figure>",
            f.uri,
            f.width,
            f.height,
            escape(&format!("false-colour luminance from {}", f.name)),
            escape(&f.name)
        );
    }
    out.push_str("</section>\n");
    Ok(())
}

pub(super) fn cubic(out: &mut String, c: &report::Cubic) {
    out.push_str("<section id=\"cubic\">\n<h2>Cubic illuminance: the flow of light</h2>\n");
    out.push_str(
        "<p class=\"note\">From the six faces of a small cube at each point (Cuttle): the \
         illumination vector points along the flow of light; the vector/scalar ratio is its \
         strength against the light from all around (0: fully diffuse; 4: a single beam; about \
         1.2–1.8 is the range commonly recommended for modelling faces); altitude is the vector's elevation (−90°: straight down); \
         E<sub>cyl</sub> is cylindrical illuminance.</p>\n",
    );
    let tables = report::render::cubic(c);
    let mut tables = tables.iter();
    if c.working_plane.is_some()
        && let Some(t) = tables.next()
    {
        section(
            out,
            "cubic-plane",
            "At the working plane's points inside the border (means)",
            t,
        );
    }
    if let Some(t) = tables.next() {
        section(out, "cubic-probes", "At the probes", t);
    }
    out.push_str("</section>\n");
}

/// ` style="width: Wpx"` for a figure holding `svg` (its root's `width`), so the caption wraps
/// to the drawing's width; empty when the SVG does not say.
fn figure_width(svg: &str) -> String {
    let root = svg.split_once('>').map_or("", |(head, _)| head);
    let width = root
        .split_once(" width=\"")
        .and_then(|(_, rest)| rest.split_once('"'))
        .and_then(|(w, _)| w.parse::<f64>().ok());
    width.map_or(String::new(), |w| format!(" style=\"width: {w}px\""))
}
