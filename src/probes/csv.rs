//! Reading probes from a CSV file (`--probes FILE.csv`).
//!
//! Input: the file's text. Output: one [`Probe`] per data row, in file order, or the first error
//! as `(line, message)` (1-based line; the caller adds the file name).
//!
//! Format: rows `x,y,z[,name]` — world coordinates in metres (glTF axes, +Y up). Fields are
//! trimmed; a name may be wrapped in double quotes. Blank lines are skipped and `#` starts a
//! comment that runs to the end of the line. The first row may be a header: it is recognised
//! when none of its fields is a number (so a mistyped first data row is still an error). A row without a name is named
//! `probe_<line>`. Probes are aligned with the world axes ([`ProbeOrigin::File`] with the row's
//! line). Errors: a row with fewer than three or more than four fields, a coordinate that is not a
//! finite number within ±[`MAX_COORDINATE`] m, an empty quoted name, two probes with the same name, a file with no probe row.

use super::{Probe, ProbeOrigin};
use crate::scene::MAX_COORDINATE;
use glam::{DMat3, DVec3};
use std::collections::HashMap;

/// Parse a probe CSV file's text.
pub fn parse(text: &str) -> Result<Vec<Probe>, (usize, String)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut probes: Vec<Probe> = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    let mut first_row = true;
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        let is_first = std::mem::replace(&mut first_row, false);
        if is_first && is_header(&fields) {
            continue;
        }
        if fields.len() < 3 || fields.len() > 4 {
            return Err((
                line,
                format!(
                    "expected x,y,z[,name] (3 or 4 fields), found {} field(s)",
                    fields.len()
                ),
            ));
        }
        let mut xyz = [0.0; 3];
        for (k, (axis, field)) in ["x", "y", "z"].iter().zip(&fields).enumerate() {
            xyz[k] = number(field)
                .filter(|v| v.abs() <= MAX_COORDINATE)
                .ok_or_else(|| {
                    (
                        line,
                        format!(
                            "{axis} must be a finite number of metres within ±{MAX_COORDINATE:e}, \
                             got '{field}'"
                        ),
                    )
                })?;
        }
        let name = match fields.get(3).map(|f| unquote(f)) {
            Some(n) if !n.is_empty() => n.to_string(),
            Some(_) if fields[3].starts_with('"') => {
                return Err((line, "the probe name is empty".into()));
            }
            _ => format!("probe_{line}"),
        };
        if let Some(first) = names.insert(name.clone(), line) {
            return Err((
                line,
                format!("probe name '{name}' is already used on line {first}"),
            ));
        }
        probes.push(Probe {
            name,
            position: DVec3::from_array(xyz),
            world_from_probe: DMat3::IDENTITY,
            origin: ProbeOrigin::File { line },
            toward: None,
        });
    }
    if probes.is_empty() {
        return Err((
            last_line.max(1),
            "no probe rows (expected rows x,y,z[,name] in metres)".into(),
        ));
    }
    Ok(probes)
}

/// A finite number, or `None`.
fn number(field: &str) -> Option<f64> {
    field.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// A header row: none of its (at least three) fields is a number.
fn is_header(fields: &[&str]) -> bool {
    fields.len() >= 3 && fields.iter().all(|f| f.parse::<f64>().is_err())
}

fn unquote(field: &str) -> &str {
    field
        .strip_prefix('"')
        .and_then(|f| f.strip_suffix('"'))
        .unwrap_or(field)
        .trim()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_names_and_lines() {
        let p = parse("x,y,z,name\n# desks\n1, 1.2, 2, desk A  # left\n\n3,0.8,4\n").unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].name, "desk A");
        assert_eq!(p[0].position, DVec3::new(1.0, 1.2, 2.0));
        assert_eq!(p[0].origin, ProbeOrigin::File { line: 3 });
        assert_eq!(p[1].name, "probe_5");
    }

    #[test]
    fn a_header_only_counts_on_the_first_row() {
        assert_eq!(parse("1,2,3\nx,y,z\n").unwrap_err().0, 2);
        assert_eq!(parse("1,2,oops\n").unwrap_err().0, 1);
    }
}
