//! The report for people: its sections as tables of text ([`Section`]s), written as an aligned
//! plain-text table (terminal) or Markdown here, and as HTML tables by `html_report`. Illuminances in
//! whole lx, areas to 0.01 m², reflectance and U₀ to two decimals, luminance to 0.1 cd/m²;
//! a missing value (and a covered area of none) shows as `—`. A surface section's title says what its figures come from
//! (`Surfaces by node (from lightmap texels)`).

use super::rows::source_of;
use super::schedule::kind_name;
use super::{Cubic, PlaneRow, Report, Row, ScheduleRow, TargetRow};
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
    if let Some(l) = &report.luminaires {
        sections.push(schedule(l));
    }
    if let Some(c) = &report.cubic {
        sections.extend(cubic(c));
    }
    crate::table::render(&sections, markdown)
}

/// A surface section: one row per material or node (`what`).
pub(crate) fn surfaces(title: &'static str, what: &'static str, rows: &[Row]) -> Section {
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
            "U_d",
            "L avg cd/m²",
            "covered m²",
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
                    format!("{:.2}", r.uniformity_d),
                    format!("{:.1}", r.l_avg),
                    match r.covered_area > 0.0 {
                        true => format!("{:.2}", r.covered_area),
                        false => "—".into(),
                    },
                ]
            })
            .collect(),
    }
}

/// The working plane's figures.
pub(crate) fn plane(p: &PlaneRow) -> Section {
    let metres = |m: Option<f64>| m.map_or("—".into(), |m| format!("{m:.2}"));
    Section {
        title: "Working plane".into(),
        headers: vec![
            "height m",
            "spacing m",
            "border m",
            "points",
            "E avg lx",
            "E min lx",
            "E max lx",
            "direct lx",
            "indirect lx",
            "U₀",
            "U_d",
        ],
        cells: vec![vec![
            metres(p.height),
            metres(p.spacing),
            format!("{:.2}", p.border),
            format!("{} of {}", p.points, p.points_total),
            lux(p.e_avg),
            lux(p.e_min),
            lux(p.e_max),
            lux(p.e_direct_avg),
            lux(p.e_indirect_avg),
            format!("{:.2}", p.uniformity),
            format!("{:.2}", p.uniformity_d),
        ]],
    }
}

/// Each target beside what was achieved, pass or fail.
pub(crate) fn targets(rows: &[TargetRow]) -> Section {
    Section {
        title: "Targets".into(),
        headers: vec!["target", "E target lx", "E avg lx", "ratio", "pass"],
        cells: rows
            .iter()
            .map(|t| {
                vec![
                    t.name.clone(),
                    lux(t.target),
                    t.achieved.map_or("—".into(), lux),
                    t.ratio.map_or("—".into(), |r| format!("{r:.2}")),
                    pass(t.pass),
                ]
            })
            .collect(),
    }
}

/// `pass`, `FAIL` or `—`.
pub(crate) fn pass(p: Option<bool>) -> String {
    match p {
        Some(true) => "pass".into(),
        Some(false) => "FAIL".into(),
        None => "—".into(),
    }
}

/// The luminaire schedule, one row per type.
pub(crate) fn schedule(rows: &[ScheduleRow]) -> Section {
    let opt = |x: Option<f64>, digits: usize| x.map_or("—".into(), |x| format!("{x:.digits$}"));
    Section {
        title: "Luminaire schedule".into(),
        headers: vec![
            "count",
            "kind",
            "profile",
            "lamp lm",
            "LOR",
            "MF",
            "dimming",
            "emitted lm",
            "total lm",
            "power W",
            "total W",
        ],
        cells: rows
            .iter()
            .map(|r| {
                vec![
                    r.count.to_string(),
                    kind_name(r.kind).into(),
                    r.profile.clone().unwrap_or_else(|| "—".into()),
                    opt(r.rated_lamp_lm, 0),
                    opt(r.light_output_ratio, 2),
                    format!("{:.2}", r.maintenance_factor),
                    format!("{:.2}", r.multiplier),
                    format!("{:.0}", r.emitted_lm),
                    format!("{:.0}", r.emitted_total_lm),
                    opt(r.power_w, 1),
                    opt(r.power_total_w, 1),
                ]
            })
            .collect(),
    }
}

/// Cubic illuminance: the working plane's means, then every probe.
pub(crate) fn cubic(c: &Cubic) -> Vec<Section> {
    let mut out = Vec::new();
    if let Some(w) = &c.working_plane {
        out.push(Section {
            title: "Cubic illuminance on the working plane (inside the border)".into(),
            headers: vec![
                "points",
                "E scalar lx",
                "E cyl lx",
                "E cyl / E h",
                "vector/scalar",
                "min",
                "max",
                "altitude °",
            ],
            cells: vec![vec![
                w.points.to_string(),
                lux(w.scalar_avg),
                lux(w.cylindrical_avg),
                format!("{:.2}", w.cylindrical_to_horizontal),
                format!("{:.2}", w.vector_scalar_ratio_avg),
                format!("{:.2}", w.vector_scalar_ratio_min),
                format!("{:.2}", w.vector_scalar_ratio_max),
                format!("{:.0}", w.altitude_avg_deg),
            ]],
        });
    }
    if !c.probes.is_empty() {
        out.push(Section {
            title: "Cubic illuminance at the probes".into(),
            headers: vec![
                "probe",
                "x m",
                "y m",
                "z m",
                "E h lx",
                "E scalar lx",
                "|E| lx",
                "vector/scalar",
                "altitude °",
                "azimuth °",
                "E cyl lx",
            ],
            cells: c
                .probes
                .iter()
                .map(|p| {
                    vec![
                        p.name.clone(),
                        format!("{:.2}", p.position[0]),
                        format!("{:.2}", p.position[1]),
                        format!("{:.2}", p.position[2]),
                        lux(p.horizontal),
                        lux(p.scalar),
                        lux(p.vector_magnitude),
                        format!("{:.2}", p.vector_scalar_ratio),
                        format!("{:.0}", p.altitude_deg),
                        format!("{:.0}", p.azimuth_deg),
                        lux(p.cylindrical),
                    ]
                })
                .collect(),
        });
    }
    out
}

/// Whole lx (never "-0").
pub(crate) fn lux(x: f64) -> String {
    if x.abs() < 0.5 {
        "0".into()
    } else {
        format!("{x:.0}")
    }
}
