//! The report as CSV (RFC 4180 quoting, `\n` line ends): one table per section, separated by a blank line, each with a
//! header row and a first column `section` (`byMaterial`, `byNode`, `workingPlane`, `targets`).
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
            "points",
            "eAvg",
            "eMin",
            "eMax",
            "eDirectAvg",
            "eIndirectAvg",
            "uniformity",
        ]);
        out += &line(&[
            "workingPlane".into(),
            opt(p.height),
            opt(p.spacing),
            p.points.to_string(),
            num(p.e_avg),
            num(p.e_min),
            num(p.e_max),
            num(p.e_direct_avg),
            num(p.e_indirect_avg),
            num(p.uniformity),
        ]);
        blocks.push(out);
    }
    if let Some(targets) = &report.targets {
        let mut out = line(&["section", "name", "target", "achieved", "ratio"]);
        for t in targets {
            out += &line(&[
                "targets".into(),
                t.name.clone(),
                num(t.target),
                opt(t.achieved),
                opt(t.ratio),
            ]);
        }
        blocks.push(out);
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
        "lAvg",
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
            num(r.l_avg),
            source(r),
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
