//! The report for people: an aligned plain-text table (terminal) or Markdown. Illuminances in
//! whole lx, areas to 0.01 m², reflectance and U₀ to two decimals, luminance to 0.1 cd/m²;
//! a missing value shows as `—`. A surface section's title says what its figures come from
//! (`Surfaces by node (from lightmap texels)`).

use super::rows::source_of;
use super::{PlaneRow, Report, Row, TargetRow};
use crate::table::Section;

pub(super) fn render(report: &Report, markdown: bool) -> String {
    let mut sections = Vec::new();
    if let Some(rows) = &report.by_material {
        sections.push(surfaces("Surfaces by material", "material", rows));
    }
    if let Some(rows) = &report.by_node {
        sections.push(surfaces("Surfaces by node", "node", rows));
    }
    if let Some(p) = &report.working_plane {
        sections.push(plane(p));
    }
    if let Some(t) = &report.targets {
        sections.push(targets(t));
    }
    crate::table::render(&sections, markdown)
}

fn surfaces(title: &'static str, what: &'static str, rows: &[Row]) -> Section {
    let title = match source_of(rows) {
        Some(s) => format!("{title} (from {})", s.describe()),
        None => title.to_string(),
    };
    Section {
        title,
        headers: vec![
            what,
            "area m²",
            "ρ",
            "E avg lx",
            "E min lx",
            "E max lx",
            "direct lx",
            "indirect lx",
            "U₀",
            "L avg cd/m²",
        ],
        cells: rows
            .iter()
            .map(|r| {
                vec![
                    r.name.clone(),
                    format!("{:.2}", r.area),
                    format!("{:.2}", r.reflectance),
                    lux(r.e_avg),
                    lux(r.e_min),
                    lux(r.e_max),
                    lux(r.e_direct_avg),
                    lux(r.e_indirect_avg),
                    format!("{:.2}", r.uniformity),
                    format!("{:.1}", r.l_avg),
                ]
            })
            .collect(),
    }
}

fn plane(p: &PlaneRow) -> Section {
    let metres = |m: Option<f64>| m.map_or("—".into(), |m| format!("{m:.2}"));
    Section {
        title: "Working plane".into(),
        headers: vec![
            "height m",
            "spacing m",
            "points",
            "E avg lx",
            "E min lx",
            "E max lx",
            "direct lx",
            "indirect lx",
            "U₀",
        ],
        cells: vec![vec![
            metres(p.height),
            metres(p.spacing),
            p.points.to_string(),
            lux(p.e_avg),
            lux(p.e_min),
            lux(p.e_max),
            lux(p.e_direct_avg),
            lux(p.e_indirect_avg),
            format!("{:.2}", p.uniformity),
        ]],
    }
}

fn targets(rows: &[TargetRow]) -> Section {
    Section {
        title: "Targets".into(),
        headers: vec!["target", "E target lx", "E avg lx", "ratio"],
        cells: rows
            .iter()
            .map(|t| {
                vec![
                    t.name.clone(),
                    lux(t.target),
                    t.achieved.map_or("—".into(), lux),
                    t.ratio.map_or("—".into(), |r| format!("{r:.2}")),
                ]
            })
            .collect(),
    }
}

/// Whole lx (never "-0").
fn lux(x: f64) -> String {
    if x.abs() < 0.5 {
        "0".into()
    } else {
        format!("{x:.0}")
    }
}
