//! The report as CSV (RFC 4180 quoting, `\n` line ends): one table per section, separated by a blank line, each with a
//! header row and a first column `section` (`byMaterial`, `byNode`, `workingPlane`, `targets`,
//! `luminaires`, `cubicWorkingPlane`, `cubicProbes`).
//! Column names are the JSON report's field names; numbers are written in full (shortest
//! round-trip decimal); a missing value is an empty field; a surface row's last column is its
//! `source` (`texels`, `vertices`, `texelsAndVertices`).

use super::{Report, Row};

pub(super) fn render(report: &Report) -> String {
    let mut blocks = Vec::new();
    for (section, rows) in [
        ("byMaterial", &report.by_material),
        ("byNode", &report.by_node),
    ] {
        if let Some(rows) = rows {
            blocks.push(surfaces(section, rows));
        }
    }
    if let Some(p) = &report.working_plane {
        let mut out = line(&[
            "section",
            "height",
            "spacing",
            "border",
            "points",
            "pointsTotal",
            "eAvg",
            "eMin",
            "eMax",
            "eDirectAvg",
            "eIndirectAvg",
            "uniformity",
            "uniformityD",
        ]);
        out += &line(&[
            "workingPlane".into(),
            opt(p.height),
            opt(p.spacing),
            num(p.border),
            p.points.to_string(),
            p.points_total.to_string(),
            num(p.e_avg),
            num(p.e_min),
            num(p.e_max),
            num(p.e_direct_avg),
            num(p.e_indirect_avg),
            num(p.uniformity),
            num(p.uniformity_d),
        ]);
        blocks.push(out);
    }
    if let Some(targets) = &report.targets {
        let mut out = line(&["section", "name", "target", "achieved", "ratio", "pass"]);
        for t in targets {
            out += &line(&[
                "targets".into(),
                t.name.clone(),
                num(t.target),
                opt(t.achieved),
                opt(t.ratio),
                t.pass.map(|p| p.to_string()).unwrap_or_default(),
            ]);
        }
        blocks.push(out);
    }
    if let Some(rows) = &report.luminaires {
        blocks.push(luminaires(rows));
    }
    if let Some(c) = &report.cubic {
        if let Some(w) = &c.working_plane {
            let mut out = line(&[
                "section",
                "points",
                "scalarAvg",
                "cylindricalAvg",
                "cylindricalToHorizontal",
                "vectorScalarRatioAvg",
                "vectorScalarRatioMin",
                "vectorScalarRatioMax",
                "altitudeAvgDeg",
            ]);
            out += &line(&[
                "cubicWorkingPlane".into(),
                w.points.to_string(),
                num(w.scalar_avg),
                num(w.cylindrical_avg),
                num(w.cylindrical_to_horizontal),
                num(w.vector_scalar_ratio_avg),
                num(w.vector_scalar_ratio_min),
                num(w.vector_scalar_ratio_max),
                num(w.altitude_avg_deg),
            ]);
            blocks.push(out);
        }
        if !c.probes.is_empty() {
            let mut out = line(&[
                "section",
                "name",
                "x",
                "y",
                "z",
                "horizontal",
                "scalar",
                "vectorMagnitude",
                "vectorScalarRatio",
                "altitudeDeg",
                "azimuthDeg",
                "cylindrical",
            ]);
            for p in &c.probes {
                out += &line(&[
                    "cubicProbes".into(),
                    p.name.clone(),
                    num(p.position[0]),
                    num(p.position[1]),
                    num(p.position[2]),
                    num(p.horizontal),
                    num(p.scalar),
                    num(p.vector_magnitude),
                    num(p.vector_scalar_ratio),
                    num(p.altitude_deg),
                    num(p.azimuth_deg),
                    num(p.cylindrical),
                ]);
            }
            blocks.push(out);
        }
    }
    blocks.join("\n")
}

fn surfaces(section: &str, rows: &[Row]) -> String {
    let mut out = line(&[
        "section",
        "name",
        "area",
        "reflectance",
        "eAvg",
        "eMin",
        "eMax",
        "eDirectAvg",
        "eIndirectAvg",
        "uniformity",
        "uniformityD",
        "lAvg",
        "coveredArea",
        "source",
    ]);
    for r in rows {
        out += &line(&[
            section.to_string(),
            r.name.clone(),
            num(r.area),
            num(r.reflectance),
            num(r.e_avg),
            num(r.e_min),
            num(r.e_max),
            num(r.e_direct_avg),
            num(r.e_indirect_avg),
            num(r.uniformity),
            num(r.uniformity_d),
            num(r.l_avg),
            num(r.covered_area),
            source(r),
        ]);
    }
    out
}

fn luminaires(rows: &[super::ScheduleRow]) -> String {
    let mut out = line(&[
        "section",
        "kind",
        "profile",
        "count",
        "ratedLampLm",
        "lightOutputRatio",
        "maintenanceFactor",
        "multiplier",
        "emittedLm",
        "emittedTotalLm",
        "powerW",
        "powerTotalW",
        "names",
    ]);
    for r in rows {
        let kind = serde_json::to_value(r.kind)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default();
        out += &line(&[
            "luminaires".into(),
            kind,
            r.profile.clone().unwrap_or_default(),
            r.count.to_string(),
            opt(r.rated_lamp_lm),
            opt(r.light_output_ratio),
            num(r.maintenance_factor),
            num(r.multiplier),
            num(r.emitted_lm),
            num(r.emitted_total_lm),
            opt(r.power_w),
            opt(r.power_total_w),
            r.names.join(" "),
        ]);
    }
    out
}

/// The row's source as in JSON (`texels`, `vertices`, `texelsAndVertices`).
fn source(r: &Row) -> String {
    serde_json::to_value(r.source)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned))
        .unwrap_or_default()
}

fn num(x: f64) -> String {
    format!("{x}")
}

fn opt(x: Option<f64>) -> String {
    x.map(num).unwrap_or_default()
}

/// One record, fields quoted when they hold a comma, a quote or a line break.
fn line<S: AsRef<str>>(fields: &[S]) -> String {
    crate::table::csv_record(fields)
}
