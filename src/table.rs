//! Plain-text tables for the terminal, Markdown and CSV, shared by `bake report` and `bake
//! design`: a title, a header row and rows of cells already formatted as text.
//!
//! Invariants: the first column is left-aligned and the others right-aligned (numbers); widths
//! count characters, not bytes (`m²`, `ρ`); no trailing spaces; every record ends in `\n`.

/// One table: a title, column headers (the first column left-aligned, the others right) and
/// rows of cells.
pub struct Section {
    pub title: String,
    pub headers: Vec<&'static str>,
    pub cells: Vec<Vec<String>>,
}

/// The sections as Markdown or aligned tables, separated by blank lines.
pub(crate) fn render(sections: &[Section], markdown: bool) -> String {
    let blocks: Vec<String> = sections
        .iter()
        .map(|s| {
            if markdown {
                self::markdown(&s.title, &s.headers, &s.cells)
            } else {
                aligned(&s.title, &s.headers, &s.cells)
            }
        })
        .collect();
    blocks.join("\n")
}

/// Title, header, a rule of dashes, rows; columns two spaces apart.
pub(crate) fn aligned<S: AsRef<str>>(title: &str, headers: &[S], cells: &[Vec<String>]) -> String {
    let width = |s: &str| s.chars().count();
    let mut widths: Vec<usize> = headers.iter().map(|h| width(h.as_ref())).collect();
    for row in cells {
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
    let headers: Vec<String> = headers.iter().map(|h| h.as_ref().to_string()).collect();
    let rule: Vec<String> = widths.iter().map(|&w| "-".repeat(w)).collect();
    let mut out = format!("{title}\n");
    out += &line(&headers);
    out += &line(&rule);
    for row in cells {
        out += &line(row);
    }
    out
}

/// `### Title`, then a Markdown table (numbers right-aligned, `|` in cells escaped).
pub(crate) fn markdown<S: AsRef<str>>(title: &str, headers: &[S], cells: &[Vec<String>]) -> String {
    let escape = |c: &str| c.replace('|', "\\|");
    let headers: Vec<&str> = headers.iter().map(|h| h.as_ref()).collect();
    let mut out = format!("### {title}\n\n");
    out += &format!("| {} |\n", headers.join(" | "));
    let aligns: Vec<&str> = (0..headers.len())
        .map(|k| if k == 0 { "---" } else { "---:" })
        .collect();
    out += &format!("| {} |\n", aligns.join(" | "));
    for row in cells {
        let cells: Vec<String> = row.iter().map(|c| escape(c)).collect();
        out += &format!("| {} |\n", cells.join(" | "));
    }
    out
}

/// One CSV record, fields quoted when they hold a comma, a quote or a line break.
pub(crate) fn csv_record<S: AsRef<str>>(fields: &[S]) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aligned_markdown_and_csv() {
        let cells = vec![
            vec!["floor".to_string(), "40".into()],
            vec!["wall".into(), "25.6".into()],
        ];
        assert_eq!(
            aligned("T", &["name", "m²"], &cells),
            "T\nname     m²\n-----  ----\nfloor    40\nwall   25.6\n"
        );
        assert_eq!(
            markdown("T", &["a|b", "n"], &[vec!["x|y".to_string(), "1".into()]]),
            "### T\n\n| a|b | n |\n| --- | ---: |\n| x\\|y | 1 |\n"
        );
        assert_eq!(csv_record(&["a,b", "q\"", "c"]), "\"a,b\",\"q\"\"\",c\n");
    }
}

/// How a table is written (`bake design`, `bake fit`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// Aligned columns for the terminal.
    #[default]
    Table,
    Markdown,
    /// One CSV table per section, separated by blank lines, numbers in full.
    Csv,
    Json,
}
