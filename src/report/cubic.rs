//! Cubic illuminance in the report: the flow of light at the bake's probes (the seed's subject).
//!
//! Input: the bake's probe nodes (`readback::ProbeNode`: six face illuminances, probe axes, +Y up)
//! and the working plane's points (to tell its probes apart). Output: [`Cubic`]: one
//! [`ProbeRow`] per probe that is not a working-plane point (named probes, `--probe-grid`,
//! CSV), and a summary over the working plane's probes inside its border, all from
//! [`crate::probes::metrics::from_faces`]: illumination vector (magnitude, altitude: its
//! elevation above the horizontal, negative when light flows down; azimuth), scalar
//! illuminance, vector/scalar ratio, cylindrical illuminance.

use crate::probes::metrics::from_faces;
use crate::readback::BakedOutput;

/// Cubic-illuminance figures of one probe (lx, degrees).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ProbeRow {
    pub name: String,
    /// World position (m, +Y up).
    pub position: [f64; 3],
    /// E on the upward face.
    pub horizontal: f64,
    pub scalar: f64,
    pub vector_magnitude: f64,
    pub vector_scalar_ratio: f64,
    pub altitude_deg: f64,
    pub azimuth_deg: f64,
    pub cylindrical: f64,
}

/// Means over a set of probes (lx; the ratio and altitude are means of each probe's).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ProbeSummary {
    pub points: usize,
    pub scalar_avg: f64,
    pub cylindrical_avg: f64,
    pub vector_scalar_ratio_avg: f64,
    pub vector_scalar_ratio_min: f64,
    pub vector_scalar_ratio_max: f64,
    pub altitude_avg_deg: f64,
    /// E_cyl / E_horizontal averaged (the modelling balance of vertical to horizontal light).
    pub cylindrical_to_horizontal: f64,
}

/// The cubic-illuminance section.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Cubic {
    /// Probes other than the working plane's.
    pub probes: Vec<ProbeRow>,
    /// The working plane's probes inside the border; `None` without a working plane.
    pub working_plane: Option<ProbeSummary>,
}

/// The section, or `None` when the bake has no probes. `inside(position)`: whether a
/// working-plane point is inside the border zone.
pub(crate) fn cubic(input: &BakedOutput, inside: impl Fn(glam::DVec3) -> bool) -> Option<Cubic> {
    if input.probes.is_empty() {
        return None;
    }
    let mut probes = Vec::new();
    let mut plane = Vec::new();
    for p in &input.probes {
        let m = from_faces(&p.faces, None);
        let row = ProbeRow {
            name: input.node_name(p.node),
            position: p.position.to_array(),
            horizontal: m.horizontal,
            scalar: m.scalar,
            vector_magnitude: m.vector_magnitude,
            vector_scalar_ratio: m.vector_scalar_ratio,
            altitude_deg: m.altitude_deg,
            azimuth_deg: m.azimuth_deg,
            cylindrical: m.cylindrical,
        };
        if p.working_plane {
            if inside(p.position) {
                plane.push(row);
            }
        } else {
            probes.push(row);
        }
    }
    Some(Cubic {
        probes,
        working_plane: summary(&plane),
    })
}

/// Means over `rows` (`None` for none), summed in order.
fn summary(rows: &[ProbeRow]) -> Option<ProbeSummary> {
    if rows.is_empty() {
        return None;
    }
    let n = rows.len() as f64;
    let mean = |f: fn(&ProbeRow) -> f64| rows.iter().map(f).sum::<f64>() / n;
    let ratios = rows.iter().map(|r| r.vector_scalar_ratio);
    Some(ProbeSummary {
        points: rows.len(),
        scalar_avg: mean(|r| r.scalar),
        cylindrical_avg: mean(|r| r.cylindrical),
        vector_scalar_ratio_avg: mean(|r| r.vector_scalar_ratio),
        vector_scalar_ratio_min: ratios.clone().fold(f64::INFINITY, f64::min),
        vector_scalar_ratio_max: ratios.fold(f64::NEG_INFINITY, f64::max),
        altitude_avg_deg: mean(|r| r.altitude_deg),
        cylindrical_to_horizontal: mean(|r| super::rows::ratio(r.cylindrical, r.horizontal)),
    })
}
