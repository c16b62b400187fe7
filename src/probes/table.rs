//! The probes as a CSV table (`--probes-out FILE.csv`): a header row naming each column with its
//! unit as a suffix (`_m`, `_lx`, `_deg`; the ratio has none), then one row per probe in bake
//! order.
//!
//! Columns: `name`, `origin` (`node`, `grid`, `file`, `workingPlane`), the position `x_m y_m z_m`
//! (world), the six face illuminances total `E+x_lx … E-z_lx`, direct `direct+x_lx …` and
//! indirect `indirect+x_lx …` (faces in the probe's axes), the illumination vector
//! `vector_x_lx vector_y_lx vector_z_lx`, `vector_magnitude_lx`, `altitude_deg`, `azimuth_deg`,
//! `symmetric_mean_lx`, `scalar_lx`, `vector_scalar_ratio`, `horizontal_lx`, `cylindrical_lx`, the
//! semi-cylindrical illuminance facing `+x -x +z -z`, `exact_scalar_lx`, `exact_cylindrical_lx` and
//! `cuttle_indirect_lx` (empty when not computed). Numbers are written in Rust's shortest
//! round-trip form, so they equal the JSON values exactly; names are quoted (RFC 4180) when they
//! contain a comma, a quote or a line break.

use super::{FACE_NAMES, ProbeOrigin, ProbeResult};

/// The header row's column names, in order.
pub(crate) fn header() -> Vec<String> {
    let mut h: Vec<String> = ["name", "origin", "x_m", "y_m", "z_m"]
        .map(String::from)
        .to_vec();
    for prefix in ["E", "direct", "indirect"] {
        h.extend(FACE_NAMES.iter().map(|f| format!("{prefix}{f}_lx")));
    }
    h.extend(
        [
            "vector_x_lx",
            "vector_y_lx",
            "vector_z_lx",
            "vector_magnitude_lx",
            "altitude_deg",
            "azimuth_deg",
            "symmetric_mean_lx",
            "scalar_lx",
            "vector_scalar_ratio",
            "horizontal_lx",
            "cylindrical_lx",
        ]
        .map(String::from),
    );
    h.extend(["+x", "-x", "+z", "-z"].map(|f| format!("semicylindrical{f}_lx")));
    h.extend(
        [
            "exact_scalar_lx",
            "exact_cylindrical_lx",
            "cuttle_indirect_lx",
        ]
        .map(String::from),
    );
    h
}

/// The origin's kind as written in the `origin` column (as in the JSON's `origin.kind`).
pub fn origin_kind(o: &ProbeOrigin) -> &'static str {
    match o {
        ProbeOrigin::Node { .. } => "node",
        ProbeOrigin::Grid { .. } => "grid",
        ProbeOrigin::File { .. } => "file",
        ProbeOrigin::WorkingPlane => "workingPlane",
    }
}

/// One probe's fields, in header order.
pub(crate) fn row(r: &ProbeResult) -> Vec<String> {
    let num = |v: f64| format!("{v}");
    let opt = |v: Option<f64>| v.map(num).unwrap_or_default();
    let m = &r.metrics;
    let mut out = vec![
        quote(&r.probe.name),
        origin_kind(&r.probe.origin).to_string(),
    ];
    out.extend(r.probe.position.to_array().map(num));
    for faces in [&r.cubic.total, &r.cubic.direct, &r.cubic.indirect] {
        out.extend(faces.map(num));
    }
    out.extend(m.vector.map(num));
    out.extend(
        [
            m.vector_magnitude,
            m.altitude_deg,
            m.azimuth_deg,
            m.symmetric_mean,
            m.scalar,
            m.vector_scalar_ratio,
            m.horizontal,
            m.cylindrical,
        ]
        .map(num),
    );
    out.extend(m.semicylindrical.map(num));
    out.extend([m.exact_scalar, m.exact_cylindrical, m.cuttle_indirect].map(opt));
    out
}

/// The whole table, header first, `\n` line ends.
pub(crate) fn csv(results: &[ProbeResult]) -> String {
    let mut out = header().join(",");
    out.push('\n');
    for r in results {
        out.push_str(&row(r).join(","));
        out.push('\n');
    }
    out
}

fn quote(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_has_every_column_once() {
        let h = header();
        assert_eq!(h.len(), 5 + 18 + 11 + 4 + 3);
        let mut unique = h.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), h.len());
        assert_eq!(quote("a,\"b\""), "\"a,\"\"b\"\"\"");
    }
}
