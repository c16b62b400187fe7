//! The report as CSV (RFC 4180 quoting, `\n` line ends): one table per section, separated by a blank line, each with a
//! header row and a first column `section` (`byMaterial`, `byNode`, `workingPlane`, `targets`,
//! `luminaires`, `cubicWorkingPlane`, `cubicProbes`).
//! Column names are the JSON report's field names; numbers are written in full (shortest
//! round-trip decimal); a missing value is an empty field; a surface row's last column is its
//! `source` (`texels`, `vertices`, `texelsAndVertices`).

use super::{PlaneRow, ProbeRow, ProbeSummary, Report, Row, TargetRow};

/// The report as CSV: the sections present, in a fixed order, a blank line between tables.
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
        blocks.push(working_plane(p));
    }
    if let Some(targets) = &report.targets {
        blocks.push(targets_table(targets));
    }
    if let Some(rows) = &report.luminaires {
        blocks.push(luminaires(rows));
    }
    if let Some(c) = &report.cubic {
        if let Some(w) = &c.working_plane {
            blocks.push(cubic_working_plane(w));
        }
        if !c.probes.is_empty() {
            blocks.push(cubic_probes(&c.probes));
        }
    }
    blocks.join("\n")
}

/// The working plane's one row.
fn working_plane(p: &PlaneRow) -> String {
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
    out
}

/// One row per target.
fn targets_table(targets: &[TargetRow]) -> String {
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
    out
}

/// The cubic illumination summary over the working plane: one row.
fn cubic_working_plane(w: &ProbeSummary) -> String {
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
    out
}

/// The cubic illumination at each probe: one row per probe.
fn cubic_probes(probes: &[ProbeRow]) -> String {
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
    for p in probes {
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
    out
}

/// One row per surface group of `section` (`byMaterial` or `byNode`).
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

/// The luminaire schedule: one row per schedule line.
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
