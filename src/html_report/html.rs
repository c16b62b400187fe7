//! HTML text helpers for the report document: escaping, and tables written from a header and
//! rows of cells (numbers right-aligned by class), so every table of the document looks alike.

use crate::table::Section;
use std::fmt::Write;

/// `s` with `& < > "` escaped (text and attribute values).
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// One cell: its text and whether it is a number (right-aligned), with an optional class.
pub struct Cell {
    pub text: String,
    pub number: bool,
    pub class: Option<&'static str>,
}

/// A text cell.
pub(crate) fn text(s: impl Into<String>) -> Cell {
    Cell {
        text: s.into(),
        number: false,
        class: None,
    }
}

/// A number cell (already formatted).
pub(crate) fn num(s: impl Into<String>) -> Cell {
    Cell {
        text: s.into(),
        number: true,
        class: None,
    }
}

/// A table with an id, a caption, headers and rows.
pub(crate) fn table(
    out: &mut String,
    id: &str,
    caption: &str,
    headers: &[&str],
    rows: &[Vec<Cell>],
) {
    let _ = writeln!(out, r#"<table id="{}">"#, escape(id));
    let _ = writeln!(out, "<caption>{}</caption>", escape(caption));
    out.push_str("<thead><tr>");
    for h in headers {
        let _ = write!(out, "<th>{}</th>", escape(h));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for row in rows {
        out.push_str("<tr>");
        for c in row {
            let mut classes = Vec::new();
            if c.number {
                classes.push("n");
            }
            classes.extend(c.class);
            match classes.is_empty() {
                true => out.push_str("<td>"),
                false => {
                    let _ = write!(out, r#"<td class="{}">"#, classes.join(" "));
                }
            }
            out.push_str(&escape(&c.text));
            out.push_str("</td>");
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody>\n</table>\n");
}

/// A report [`Section`] as a table with an id and a caption: numbers right-aligned, the rest as
/// text; `pass` and `FAIL` cells get their classes.
pub(crate) fn section(out: &mut String, id: &str, caption: &str, s: &Section) {
    let rows: Vec<Vec<Cell>> = (s.cells.iter())
        .map(|row| {
            (row.iter())
                .map(|c| {
                    let mut cell = match numeric(c) {
                        true => num(c.clone()),
                        false => text(c.clone()),
                    };
                    cell.class = match c.as_str() {
                        "pass" => Some("pass"),
                        "FAIL" => Some("fail"),
                        _ => None,
                    };
                    cell
                })
                .collect()
        })
        .collect();
    table(out, id, caption, &s.headers, &rows);
}

/// A number as the report writes them (`412`, `-3`, `0.55`, `448 of 640`), or `—`.
fn numeric(c: &str) -> bool {
    let c = c.strip_prefix('-').unwrap_or(c);
    c == "—" || c.chars().next().is_some_and(|d| d.is_ascii_digit())
}

/// A definition list of (term, value) pairs.
pub(crate) fn facts(out: &mut String, id: &str, pairs: &[(&str, String)]) {
    let _ = writeln!(out, r#"<dl id="{}" class="facts">"#, escape(id));
    for (k, v) in pairs {
        let _ = writeln!(out, "<dt>{}</dt><dd>{}</dd>", escape(k), escape(v));
    }
    out.push_str("</dl>\n");
}
