//! Reading a design table from CSV text.
//!
//! Input: the file's name (for messages only) and its text. Output: one [`DesignRow`] per data
//! row in file order, or the first error as [`Error::Input`] naming the file and `line N`
//! (1-based).
//!
//! Format: a header row naming the columns [`COLUMNS`] (any order, case-insensitive), then one
//! row per surface. Fields are trimmed and may be wrapped in double quotes (`""` inside is a
//! quote), so a name may hold a comma. Blank lines and lines starting with `#` are skipped.
//! Errors: no header, an unknown, repeated or missing column, a row with too few or too many
//! fields, an empty name, a name used twice, a number that is not finite, an area not > 0 m²,
//! a reflectance outside [0, 1), a negative illuminance, no data row.

use super::DesignRow;
use crate::{Error, Result};
use std::collections::HashMap;
use std::path::Path;

/// The header's column names, in the order the seed's table has them.
pub const COLUMNS: [&str; 4] = ["name", "area_m2", "reflectance", "illuminance_lx"];
/// Largest area a row may give (m²): a face within the scenes' ±10⁷ m coordinates.
const MAX_AREA: f64 = 4e14;
/// Largest illuminance a row may ask (lx): the photometric limit of every input (10¹²). With
/// these, every product and sum of the table stays finite.
const MAX_ILLUMINANCE: f64 = 1e12;

/// Columns a header may add: `surface`, what the row names in a bake (`bake design --scene`,
/// `bake fit`): a node path, `material:NAME`, either with a face (`desk_dark/top[+y]`), or
/// `working_plane`.
pub const OPTIONAL: [&str; 1] = ["surface"];

/// Parse a design table's text (`file` names it in errors).
pub fn parse(file: &Path, text: &str) -> Result<Vec<DesignRow>> {
    let err = |line: usize, message: String| Error::input(file, format!("line {line}"), message);
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Column k of the file holds COLUMNS[order[k]].
    let mut order: Option<Vec<usize>> = None;
    let mut rows: Vec<DesignRow> = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let fields = split(content).map_err(|m| err(line, m))?;
        let Some(order) = &order else {
            order = Some(header(&fields).map_err(|m| err(line, m))?);
            continue;
        };
        if fields.len() > order.len() {
            return Err(err(
                line,
                format!(
                    "{} fields, the header has {} ({})",
                    fields.len(),
                    order.len(),
                    COLUMNS.join(",")
                ),
            ));
        }
        let mut value: [&str; 5] = [""; 5];
        for (k, &column) in order.iter().enumerate() {
            match fields.get(k) {
                Some(f) => value[column] = f,
                None => {
                    return Err(err(
                        line,
                        format!("missing column '{}'", column_name(column)),
                    ));
                }
            }
        }
        let name = value[0].to_string();
        if name.is_empty() {
            return Err(err(line, "the surface name is empty".into()));
        }
        // An empty area is taken from a bake (`--scene`).
        let area = match value[1] {
            "" => None,
            a => Some(number(a).filter(|a| *a > 0.0 && *a <= MAX_AREA).ok_or_else(|| {
                err(
                    line,
                    format!(
                        "area_m2 must be a number of m² in (0, {MAX_AREA:e}] (or empty: from --scene), got '{a}'"
                    ),
                )
            })?),
        };
        let reflectance = number(value[2])
            .filter(|r| (0.0..1.0).contains(r))
            .ok_or_else(|| {
                err(
                    line,
                    format!("reflectance must be a number in [0, 1), got '{}'", value[2]),
                )
            })?;
        let illuminance = (number(value[3]))
            .filter(|e| (0.0..=MAX_ILLUMINANCE).contains(e))
            .ok_or_else(|| {
                err(
                    line,
                    format!(
                        "illuminance_lx must be a number of lx in [0, {MAX_ILLUMINANCE:e}], got '{}'",
                        value[3]
                    ),
                )
            })?;
        if let Some(first) = names.insert(name.clone(), line) {
            return Err(err(
                line,
                format!("surface '{name}' is already on line {first}"),
            ));
        }
        let surface = (!value[4].is_empty()).then(|| value[4].to_string());
        rows.push(DesignRow {
            name,
            area,
            reflectance,
            illuminance,
            surface,
            line,
        });
    }
    if order.is_none() {
        return Err(Error::input(
            file,
            "",
            format!("no header row (expected {})", COLUMNS.join(",")),
        ));
    }
    if rows.is_empty() {
        return Err(Error::input(file, "", "no surface rows after the header"));
    }
    Ok(rows)
}

/// The header's columns as indices into [`COLUMNS`] then [`OPTIONAL`].
fn header(fields: &[String]) -> Result<Vec<usize>, String> {
    let expected = || COLUMNS.join(",");
    if fields.iter().any(|f| number(f).is_some()) {
        return Err(format!(
            "expected the header row {}, found data",
            expected()
        ));
    }
    let mut order = Vec::new();
    for f in fields {
        let Some(k) =
            (0..COLUMNS.len() + OPTIONAL.len()).find(|&k| column_name(k).eq_ignore_ascii_case(f))
        else {
            return Err(format!(
                "unknown column '{f}' (expected {}, optionally {})",
                expected(),
                OPTIONAL.join(",")
            ));
        };
        if order.contains(&k) {
            return Err(format!("column '{}' twice", column_name(k)));
        }
        order.push(k);
    }
    if let Some(missing) = (0..COLUMNS.len()).find(|k| !order.contains(k)) {
        return Err(format!(
            "missing column '{}' in the header (expected {})",
            COLUMNS[missing],
            expected()
        ));
    }
    Ok(order)
}

/// Column `k` of [`COLUMNS`] then [`OPTIONAL`].
fn column_name(k: usize) -> &'static str {
    COLUMNS
        .get(k)
        .copied()
        .unwrap_or_else(|| OPTIONAL[k - COLUMNS.len()])
}

/// A finite number, or `None`.
fn number(field: &str) -> Option<f64> {
    field.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// One CSV record's fields, trimmed, quotes removed (`""` in a quoted field is a quote).
fn split(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| *c == ' ' || *c == '\t') {
            chars.next();
        }
        let mut field = String::new();
        if chars.peek() == Some(&'"') {
            chars.next();
            loop {
                match chars.next() {
                    Some('"') if chars.peek() == Some(&'"') => {
                        chars.next();
                        field.push('"');
                    }
                    Some('"') => break,
                    Some(c) => field.push(c),
                    None => return Err("a quoted field is not closed".into()),
                }
            }
            while chars.peek().is_some_and(|c| *c == ' ' || *c == '\t') {
                chars.next();
            }
            if chars.peek().is_some_and(|c| *c != ',') {
                return Err(format!("text after the quoted field \"{field}\""));
            }
            fields.push(field);
        } else {
            while let Some(&c) = chars.peek() {
                if c == ',' {
                    break;
                }
                field.push(c);
                chars.next();
            }
            fields.push(field.trim().to_string());
        }
        if chars.next().is_none() {
            return Ok(fields);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::split;

    #[test]
    fn fields_split_with_quotes() {
        assert_eq!(split("a, 1 ,2").unwrap(), ["a", "1", "2"]);
        assert_eq!(split("\"x, \"\"y\"\"\" ,3").unwrap(), ["x, \"y\"", "3"]);
        assert_eq!(split("a,").unwrap(), ["a", ""]);
        assert!(split("\"open,1").is_err());
        assert!(split("\"a\"b,1").is_err());
    }
}
