//! The flux table written out: an aligned plain-text table (terminal), Markdown, or CSV.
//!
//! Table and Markdown round as the seed's Table 1 prints: the inputs (area, reflectance,
//! illuminance) and each row's reflected flux A·R·E as short decimals (`15.75`, `0.7`, `93.75`:
//! they are exact products of the inputs), everything that depends on E_r (direct illuminance,
//! direct flux) and the total reflected flux and E_r in whole lx and lm, computed from the
//! unrounded E_r. Then one `warning:` line per surface designed below E_r. CSV writes numbers in
//! full (shortest round-trip decimal) with the JSON field names as columns.

use super::FluxTable;

/// Title, column headers (first column left-aligned, the others right), rows of cells.
struct Section {
    title: &'static str,
    headers: Vec<&'static str>,
    cells: Vec<Vec<String>>,
}

pub(super) fn render(table: &FluxTable, markdown: bool) -> String {
    let t = &table.totals;
    let sections = [
        Section {
            title: "Flux table (Lynes: direct flux each surface needs)",
            headers: vec![
                "surface",
                "area m²",
                "ρ",
                "E lx",
                "A·ρ·E lm",
                "direct lx",
                "direct lm",
            ],
            cells: table
                .rows
                .iter()
                .map(|r| {
                    vec![
                        r.name.clone(),
                        short(r.area, 2),
                        short(r.reflectance, 3),
                        short(r.illuminance, 1),
                        short(r.reflected_flux, 2),
                        whole(r.direct_illuminance),
                        whole(r.direct_flux),
                    ]
                })
                .collect(),
        },
        Section {
            title: "Totals",
            headers: vec!["total", "value"],
            cells: vec![
                vec!["area m²".into(), short(t.area, 2)],
                vec!["reflected flux lm".into(), whole(t.reflected_flux)],
                vec![
                    "indirect illuminance E_r = ΣA·ρ·E / ΣA lx".into(),
                    whole(t.indirect_illuminance),
                ],
                vec!["direct flux lm".into(), whole(t.direct_flux)],
            ],
        },
    ];
    let blocks: Vec<String> = sections
        .iter()
        .map(|s| {
            if markdown {
                to_markdown(s)
            } else {
                to_table(s)
            }
        })
        .collect();
    let mut out = blocks.join("\n");
    if !table.warnings.is_empty() {
        out.push('\n');
        for w in &table.warnings {
            out += &format!("warning: {w}\n");
        }
    }
    out
}

/// Two CSV tables separated by a blank line: `section,name,area,reflectance,illuminance,
/// reflectedFlux,directIlluminance,directFlux` rows (`surfaces`), then
/// `section,area,reflectedFlux,indirectIlluminance,directFlux` (`totals`).
pub(super) fn csv(table: &FluxTable) -> String {
    let mut out = line(&[
        "section",
        "name",
        "area",
        "reflectance",
        "illuminance",
        "reflectedFlux",
        "directIlluminance",
        "directFlux",
    ]);
    for r in &table.rows {
        out += &line(&[
            "surfaces".into(),
            r.name.clone(),
            num(r.area),
            num(r.reflectance),
            num(r.illuminance),
            num(r.reflected_flux),
            num(r.direct_illuminance),
            num(r.direct_flux),
        ]);
    }
    let t = &table.totals;
    out += "\n";
    out += &line(&[
        "section",
        "area",
        "reflectedFlux",
        "indirectIlluminance",
        "directFlux",
    ]);
    out += &line(&[
        "totals".into(),
        num(t.area),
        num(t.reflected_flux),
        num(t.indirect_illuminance),
        num(t.direct_flux),
    ]);
    out
}

/// `x` to at most `decimals` decimals, trailing zeros dropped (`40`, `15.75`, `0.7`; never `-0`).
pub(super) fn short(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".into() } else { s }
}

/// A whole number (never `-0`).
fn whole(x: f64) -> String {
    short(x, 0)
}

fn num(x: f64) -> String {
    format!("{x}")
}

/// One CSV record, fields quoted when they hold a comma, a quote or a line break.
fn line<S: AsRef<str>>(fields: &[S]) -> String {
    let quoted: Vec<String> = fields
        .iter()
        .map(|f| {
            let f = f.as_ref();
            if f.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", f.replace('"', "\"\""))
            } else {
                f.to_string()
            }
        })
        .collect();
    quoted.join(",") + "\n"
}

fn width(s: &str) -> usize {
    s.chars().count()
}

/// Title, header, a rule of dashes, rows; columns two spaces apart (as `bake report`).
fn to_table(s: &Section) -> String {
    let mut widths: Vec<usize> = s.headers.iter().map(|h| width(h)).collect();
    for row in &s.cells {
        for (w, c) in widths.iter_mut().zip(row) {
            *w = (*w).max(width(c));
        }
    }
    let line = |cells: &[String]| {
        let padded: Vec<String> = cells
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(k, (c, &w))| {
                let pad = " ".repeat(w - width(c));
                if k == 0 {
                    format!("{c}{pad}")
                } else {
                    format!("{pad}{c}")
                }
            })
            .collect();
        padded.join("  ").trim_end().to_string() + "\n"
    };
    let headers: Vec<String> = s.headers.iter().map(|h| h.to_string()).collect();
    let rule: Vec<String> = widths.iter().map(|&w| "-".repeat(w)).collect();
    let mut out = format!("{}\n", s.title);
    out += &line(&headers);
    out += &line(&rule);
    for row in &s.cells {
        out += &line(row);
    }
    out
}

/// `### Title`, then a Markdown table (numbers right-aligned).
fn to_markdown(s: &Section) -> String {
    let escape = |c: &str| c.replace('|', "\\|");
    let mut out = format!("### {}\n\n", s.title);
    out += &format!("| {} |\n", s.headers.join(" | "));
    let aligns: Vec<&str> = (0..s.headers.len())
        .map(|k| if k == 0 { "---" } else { "---:" })
        .collect();
    out += &format!("| {} |\n", aligns.join(" | "));
    for row in &s.cells {
        let cells: Vec<String> = row.iter().map(|c| escape(c)).collect();
        out += &format!("| {} |\n", cells.join(" | "));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn short_decimals() {
        assert_eq!(short(40.0, 2), "40");
        assert_eq!(short(15.75, 2), "15.75");
        assert_eq!(short(163.2, 2), "163.2");
        assert_eq!(short(93.209, 0), "93");
        assert_eq!(short(-0.2, 0), "0");
        assert_eq!(short(-6.79, 0), "-7");
    }
}
