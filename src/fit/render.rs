//! A fit written out: the groups' factors and, per designed surface, design, achieved and ratio;
//! as aligned text, Markdown, CSV (two tables, numbers in full) or JSON.

use super::Fit;
use crate::table::{Format, Section, csv_record};

pub(super) fn render(fit: &Fit, format: Format) -> String {
    match format {
        Format::Table => sections(fit, false),
        Format::Markdown => sections(fit, true),
        Format::Csv => csv(fit),
        Format::Json => {
            let mut s = serde_json::to_string_pretty(fit).expect("the fit serialises");
            s.push('\n');
            s
        }
    }
}

fn sections(fit: &Fit, markdown: bool) -> String {
    let mut groups: Vec<Vec<String>> = (fit.groups.iter())
        .map(|g| {
            let bound = match (g.at_maximum, g.off) {
                (true, _) => " (max)",
                (_, true) => " (off)",
                _ => "",
            };
            vec![
                g.name.clone(),
                format!("{:.4}{bound}", g.factor),
                g.sources.len().to_string(),
                list(&g.sources),
            ]
        })
        .collect();
    if !fit.fixed_sources.is_empty() {
        groups.push(vec![
            "(not fitted)".into(),
            "1".into(),
            fit.fixed_sources.len().to_string(),
            list(&fit.fixed_sources),
        ]);
    }
    let surfaces = (fit.surfaces.iter())
        .map(|s| {
            let name = match s.name == s.key {
                true => s.name.clone(),
                false => format!("{} ({})", s.name, s.key),
            };
            vec![
                name,
                format!("{:.1}", s.design),
                format!("{:.1}", s.achieved),
                format!("{:.3}", s.ratio),
            ]
        })
        .collect();
    let sections = [
        Section {
            title: format!(
                "Dimming factors (0 … {}; fitted on {} mesh{})",
                fit.max_factor,
                fit.passes,
                if fit.passes == 1 { "" } else { "es" }
            ),
            headers: vec!["group", "factor", "sources", "which"],
            cells: groups,
        },
        Section {
            title: format!(
                "Design and achieved average illuminance (RMS relative error {:.2} %)",
                100.0 * fit.rms_relative_error
            ),
            headers: vec!["surface", "design lx", "achieved lx", "ratio"],
            cells: surfaces,
        },
    ];
    let mut out = crate::table::render(&sections, markdown);
    if fit.groups.iter().any(|g| g.at_maximum) {
        out += &format!(
            "\nnote: a group at (max) wants more light than a factor of {} gives: raise \
             --max-factor or add luminaires\n",
            fit.max_factor
        );
    }
    out
}

fn csv(fit: &Fit) -> String {
    let mut out = csv_record(&["section", "group", "factor", "sources"]);
    for g in &fit.groups {
        out += &csv_record(&[
            "groups".into(),
            g.name.clone(),
            format!("{}", g.factor),
            g.sources.join(" "),
        ]);
    }
    out += "\n";
    out += &csv_record(&["section", "name", "key", "design", "achieved", "ratio"]);
    for s in &fit.surfaces {
        out += &csv_record(&[
            "surfaces".into(),
            s.name.clone(),
            s.key.clone(),
            format!("{}", s.design),
            format!("{}", s.achieved),
            format!("{}", s.ratio),
        ]);
    }
    out
}

/// Up to three names, then how many more.
fn list(names: &[String]) -> String {
    match names.len() {
        0..=3 => names.join(", "),
        n => format!("{}, {} … ({} more)", names[0], names[1], n - 2),
    }
}
