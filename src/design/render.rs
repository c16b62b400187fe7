//! The flux table written out: an aligned plain-text table (terminal), Markdown, or CSV.
//!
//! Table and Markdown round as the seed's Table 1 prints: the inputs (area, reflectance,
//! illuminance) and each row's reflected flux A·R·E as short decimals (`15.75`, `0.7`, `93.75`:
//! they are exact products of the inputs), everything that depends on E_r (direct illuminance,
//! direct flux) and the total reflected flux and E_r in whole lx and lm, computed from the
//! unrounded E_r. Then one `warning:` line per surface designed below E_r. CSV writes numbers in
//! full (shortest round-trip decimal) with the JSON field names as columns.

use super::FluxTable;
use crate::table::Section;

pub(super) fn render(table: &FluxTable, markdown: bool) -> String {
    let t = &table.totals;
    let sections = [
        Section {
            title: "Flux table (Lynes: direct flux each surface needs)".into(),
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
            title: "Totals".into(),
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
    let mut out = crate::table::render(&sections, markdown);
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
    crate::table::csv_record(fields)
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
