//! The plain-text rendering of a [`Diff`]: the files, the mode and the tolerance, one line per
//! quantity with values, `_ILLUMINANCE` by node and by material, the worst places, and a verdict
//! on the last line (`OK: …` or `FAIL: … worst: …`). Columns are aligned; numbers have 4
//! significant digits. Deterministic: the same diff gives the same bytes.

use super::{Diff, Group, Mode, Place, Quantity};
use std::fmt::Write;

/// A number with 4 significant digits (exponent form outside [10⁻³, 10⁵)).
pub fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return if x.is_nan() { "nan" } else { "inf" }.into();
    }
    let a = x.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{x:.3e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// A relative difference (3 significant digits, exponent form).
fn rel(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if !x.is_finite() {
        num(x)
    } else {
        format!("{x:.2e}")
    }
}

/// Aligned columns: the first `left` columns flush left, the others flush right.
fn table(out: &mut String, rows: &[Vec<String>], left: usize) {
    let n = rows.iter().map(Vec::len).max().unwrap_or(0);
    let width: Vec<usize> = (0..n)
        .map(|c| {
            rows.iter()
                .filter_map(|r| r.get(c))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    for r in rows {
        let mut line = String::new();
        for (c, cell) in r.iter().enumerate() {
            if c > 0 {
                line.push_str("  ");
            }
            let pad = width[c] - cell.chars().count();
            if c < left {
                line.push_str(cell);
                line.push_str(&" ".repeat(pad));
            } else {
                line.push_str(&" ".repeat(pad));
                line.push_str(cell);
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
}

const STATS_HEADER: [&str; 8] = [
    "values",
    "failed",
    "|Δ| max",
    "|Δ| mean",
    "|Δ| p95",
    "rel max",
    "rel mean",
    "rel p95",
];

fn stats_cells(g: &Group) -> Vec<String> {
    vec![
        g.values.to_string(),
        g.failed.to_string(),
        num(g.abs.max),
        num(g.abs.mean),
        num(g.abs.p95),
        rel(g.rel.max),
        rel(g.rel.mean),
        rel(g.rel.p95),
    ]
}

fn header(first: &[&str]) -> Vec<String> {
    first
        .iter()
        .chain(STATS_HEADER.iter())
        .map(|s| s.to_string())
        .collect()
}

/// Where a place is: `_ILLUMINANCE node floor primitive 0 vertex 17 at (x, y, z) m`,
/// `illuminance node floor primitive 0 atlas 0 texel (12, 40) at …`, `illuminance node floor
/// primitive 0 triangle 3 centroid at …`, `probe probes/grid/p3 face +y at …`,
/// `_ILLUMINANCE mean of node floor (centroid at …)`.
pub(crate) fn place(p: &Place) -> String {
    let q = Quantity::from_key(p.quantity).map_or(p.quantity, |q| {
        let lightmap = matches!(p.kind, "texel" | "sample");
        q.label_in(if lightmap {
            Mode::Texels
        } else {
            Mode::Vertices
        })
    });
    let [x, y, z] = p.position;
    let at = format!("at ({}, {}, {}) m", num(x), num(y), num(z));
    let node = p.node.as_deref().unwrap_or("?");
    match p.kind {
        "vertex" => format!(
            "{q} node {node} primitive {} vertex {} {at}",
            p.primitive.unwrap_or(0),
            p.vertex.unwrap_or(0)
        ),
        "texel" => {
            let [c, r] = p.texel.unwrap_or_default();
            let atlas = p.atlas.unwrap_or(0);
            match p.primitive {
                Some(k) => {
                    format!("{q} node {node} primitive {k} atlas {atlas} texel ({c}, {r}) {at}")
                }
                None => format!("{q} atlas {atlas} texel ({c}, {r}) (on no primitive of B)"),
            }
        }
        "sample" => {
            let k = p.primitive.unwrap_or(0);
            match (p.vertex, p.triangle) {
                (Some(v), _) => format!("{q} node {node} primitive {k} vertex {v} {at}"),
                (_, t) => format!(
                    "{q} node {node} primitive {k} triangle {} centroid {at}",
                    t.unwrap_or(0)
                ),
            }
        }
        "probe" => format!("probe {node} face {} {at}", p.face.unwrap_or("?")),
        "nodeMean" => format!("{q} mean of node {node} (centroid {at})"),
        _ => format!(
            "{q} mean of material {} (centroid {at})",
            p.material.as_deref().unwrap_or("?")
        ),
    }
}

/// The verdict line (without newline).
pub(crate) fn verdict(d: &Diff) -> String {
    match &d.worst_failure {
        None => format!("OK: all {} values within tolerance", d.values),
        Some(p) => {
            let unit = Quantity::from_key(p.quantity).map_or("", Quantity::unit);
            format!(
                "FAIL: {} of {} values outside tolerance; worst: {}: A {} vs B {} {unit} (|Δ| {} > tolerance {})",
                d.failed,
                d.values,
                place(p),
                num(p.a),
                num(p.b),
                num(p.abs),
                num(p.tolerance)
            )
        }
    }
}

/// The whole text (ends with a newline; the verdict is the last line).
pub fn render(d: &Diff) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "A: {}\nB: {} (reference)", d.a, d.b);
    let note = match d.mode {
        Mode::Vertices | Mode::Texels | Mode::Samples => "",
        Mode::Means => " (each value is one node's or one material's mean, not a vertex)",
        Mode::Probes => " (meshes not compared)",
    };
    let _ = writeln!(out, "compared {}{note}", d.mode.describe());
    if let Some(l) = &d.lightmaps {
        let _ = writeln!(out, "lightmaps: {l}");
    }
    let floor_note = if d.floor_is_default {
        " (1 % of B's p99 _ILLUMINANCE)"
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "pass: |a − b| ≤ {} lx + {} · max(|b|, {} lx{floor_note}); {}: both lx terms / π\n",
        num(d.atol),
        num(d.rtol),
        num(d.floor),
        Quantity::Luminance.label_in(d.mode),
    );

    let mut rows = vec![header(&["quantity", "unit"])];
    for q in &d.quantities {
        if q.overall.values == 0 {
            continue;
        }
        let label = Quantity::from_key(q.quantity).map_or(q.quantity, |q| q.label_in(d.mode));
        let mut r = vec![label.to_string(), q.unit.to_string()];
        r.extend(stats_cells(&q.overall));
        rows.push(r);
    }
    table(&mut out, &rows, 2);

    let illuminance = &d.quantities[0];
    for (title, groups, what) in [
        ("by node", &illuminance.by_node, "node"),
        ("by material", &illuminance.by_material, "material"),
    ] {
        if groups.is_empty() {
            continue;
        }
        let means = if d.mode == Mode::Means { " mean" } else { "" };
        let label = Quantity::Illuminance.label_in(d.mode);
        let _ = writeln!(out, "\n{label}{means} {title} (lx)");
        let mut rows = vec![header(&[what])];
        for g in groups {
            let mut r = vec![g.name.clone()];
            r.extend(stats_cells(g));
            rows.push(r);
        }
        table(&mut out, &rows, 1);
    }

    if !d.worst.is_empty() {
        let _ = writeln!(out, "\nworst places");
        let mut rows = vec![
            [
                "quantity", "node", "prim", "where", "x m", "y m", "z m", "A", "B", "|Δ|", "rel",
                "",
            ]
            .map(String::from)
            .to_vec(),
        ];
        for p in &d.worst {
            let label = Quantity::from_key(p.quantity).map_or(p.quantity, |q| q.label_in(d.mode));
            let [x, y, z] = p.position;
            let (node, at) = match p.kind {
                "vertex" => (p.node.clone(), p.vertex.map(|v| v.to_string())),
                "texel" => {
                    let [c, r] = p.texel.unwrap_or_default();
                    let atlas = p.atlas.unwrap_or(0);
                    (p.node.clone(), Some(format!("texel {c},{r} atlas {atlas}")))
                }
                "sample" => match (p.vertex, p.triangle) {
                    (Some(v), _) => (p.node.clone(), Some(format!("vertex {v}"))),
                    (_, t) => (p.node.clone(), Some(format!("triangle {}", t.unwrap_or(0)))),
                },
                "probe" => (p.node.clone(), p.face.map(String::from)),
                "nodeMean" => (p.node.clone(), Some("mean".into())),
                _ => (
                    p.material.as_ref().map(|m| format!("material {m}")),
                    Some("mean".into()),
                ),
            };
            rows.push(vec![
                label.to_string(),
                node.unwrap_or_default(),
                p.primitive.map_or("-".into(), |k| k.to_string()),
                at.unwrap_or_default(),
                num(x),
                num(y),
                num(z),
                num(p.a),
                num(p.b),
                num(p.abs),
                rel(p.rel),
                if p.pass { "" } else { "FAIL" }.to_string(),
            ]);
        }
        table(&mut out, &rows, 2);
    }
    out.push('\n');
    out.push_str(&verdict(d));
    out.push('\n');
    out
}
