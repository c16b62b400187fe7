//! How probe results are written: the JSON object of one probe (the output node's
//! `extras.luxbake`, and each element of a `--probes-out FILE.json`), and the `--probes-out` file.
//!
//! Input: [`ProbeResult`]s. Output: JSON values or file bytes. The object (JSON Schema:
//! `schemas/probe.schema.json`) is
//! `{"probe": {name, position, worldFromProbe, origin, toward?}, "faces": {"+x": lx, …},
//! "facesDirect": {…}, "facesIndirect": {…}, "metrics": {…}}`: camelCase keys, face names
//! literal (`+x -x +y -y +z -z`, probe axes), lengths in m, illuminances in lx, angles in degrees;
//! `worldFromProbe` is the rotation's three columns (the probe's x, y, z axes in world
//! coordinates). Absent optional values are left out (never `null`: Blender cannot store it).
//! The `--probes-out` format follows the extension: `.json` (an array of these objects) or
//! `.csv` (one row per probe, see [`super::table`]).

use super::{FACE_NAMES, ProbeResult, table};
use serde_json::{Map, Value, json};
use std::path::Path;

/// The formats of `--probes-out`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Csv,
    Json,
}

impl Format {
    /// The format for `path`'s extension (case-insensitive), or a message saying what is allowed.
    pub fn for_path(path: &Path) -> Result<Format, String> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("csv") => Ok(Format::Csv),
            Some("json") => Ok(Format::Json),
            _ => Err("unsupported extension for --probes-out: use .csv or .json".into()),
        }
    }
}

/// The file's bytes in `format`.
pub fn bytes(format: Format, results: &[ProbeResult]) -> Vec<u8> {
    match format {
        Format::Csv => table::csv(results).into_bytes(),
        Format::Json => {
            let all: Vec<Value> = results.iter().map(record).collect();
            let mut out =
                serde_json::to_vec_pretty(&Value::Array(all)).expect("JSON values serialise");
            out.push(b'\n');
            out
        }
    }
}

/// The six values keyed by face name.
pub(crate) fn faces(values: &[f64; 6]) -> Value {
    Value::Object(
        FACE_NAMES
            .iter()
            .zip(values)
            .map(|(k, v)| (k.to_string(), json!(v)))
            .collect::<Map<_, _>>(),
    )
}

/// One probe's JSON object.
pub(crate) fn record(r: &ProbeResult) -> Value {
    let mut v = json!({
        "probe": r.probe,
        "faces": faces(&r.cubic.total),
        "facesDirect": faces(&r.cubic.direct),
        "facesIndirect": faces(&r.cubic.indirect),
        "metrics": r.metrics,
    });
    strip_nulls(&mut v);
    v
}

/// Remove every `null` member of every object.
fn strip_nulls(v: &mut Value) {
    match v {
        Value::Object(m) => {
            m.retain(|_, x| !x.is_null());
            m.values_mut().for_each(strip_nulls);
        }
        Value::Array(a) => a.iter_mut().for_each(strip_nulls),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::probes::{CubicIlluminance, Probe, ProbeOrigin, metrics};
    use glam::{DMat3, DVec3};

    #[test]
    fn record_layout() {
        let total = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let r = ProbeResult {
            probe: Probe {
                name: "p".into(),
                position: DVec3::new(1.0, 1.2, 3.0),
                world_from_probe: DMat3::IDENTITY,
                origin: ProbeOrigin::Grid {
                    layer: "grid".into(),
                },
                toward: None,
            },
            cubic: CubicIlluminance {
                total,
                direct: total,
                indirect: [0.0; 6],
            },
            metrics: metrics::from_faces(&total, None),
        };
        let v = record(&r);
        assert_eq!(v["faces"]["-y"], 4.0);
        assert_eq!(
            v["probe"]["origin"],
            json!({"kind": "grid", "layer": "grid"})
        );
        assert_eq!(v["probe"]["worldFromProbe"][1], json!([0.0, 1.0, 0.0]));
        assert!(v["probe"].get("toward").is_none());
        assert!(v["metrics"].get("exactScalar").is_none());
        assert_eq!(v["metrics"]["horizontal"], 3.0);
        assert_eq!(Format::for_path(Path::new("a.JSON")), Ok(Format::Json));
        assert!(Format::for_path(Path::new("a.txt")).is_err());
    }
}
