//! Display colours for `COLOR_0`: what a glTF viewer shows with unlit materials is
//! baseColor × COLOR_0, so COLOR_0 carries the illumination, tone-mapped into [0, 1]:
//! COLOR_0 = shoulder(k·E_rgb), with k the exposure scale (k = 1/E_white). The shoulder is linear
//! up to 0.8 and then eases to 1 (continuous slope), so bright areas keep some gradation.
//! Emitting surfaces show their own luminance: the output gives them a display base of their
//! emission colour (largest channel 1, `Material::display_base`) instead of their reflectance,
//! and their colour uses the illuminance that would make a surface of that base as bright,
//! k·π·L/Y(base). So a source brighter than the exposure's white shows white (or its colour).
//!
//! Auto exposure: the area-weighted 95th percentile of illuminance over non-emitting receivers
//! maps to 0.8.

use crate::scene::{Material, luma};
use crate::settings::Exposure;
use crate::solution::Solution;
use crate::summary::{ExposureMode, ExposureRecord};
use glam::DVec3;

/// k such that COLOR_0 = shoulder(k·E), and what the summary records of it.
pub(crate) fn exposure(exposure: Exposure, s: &Solution) -> (f64, ExposureRecord) {
    let (k, mode) = match exposure {
        Exposure::White { lux } => (1.0 / lux, ExposureMode::Fixed),
        Exposure::Auto => {
            let p95 = percentile_illuminance(s, 0.95);
            (if p95 > 0.0 { 0.8 / p95 } else { 1.0 }, ExposureMode::Auto)
        }
    };
    let record = ExposureRecord {
        mode,
        white_illuminance_lx: 1.0 / k,
        rule: "COLOR_0 = shoulder(E_rgb / whiteIlluminanceLx); shoulder(x) = x for x <= 0.8, else 0.8 + 0.2*(1 - exp(-(x - 0.8)/0.2))".into(),
    };
    (k, record)
}

fn percentile_illuminance(s: &Solution, q: f64) -> f64 {
    let mesh = s.mesh();
    let mut weighted: Vec<(f64, f64)> = Vec::new();
    let mut weight = vec![0.0; mesh.receivers.len()];
    for p in &mesh.patches {
        for &v in &p.v {
            weight[v as usize] += p.area / 3.0;
        }
    }
    for (i, r) in mesh.receivers.iter().enumerate() {
        let g = &mesh.groups[r.group as usize];
        if s.scene().materials[g.material].emission.is_some() || weight[i] <= 0.0 {
            continue;
        }
        weighted.push((luma(s.vertex(i).total()), weight[i]));
    }
    if weighted.is_empty() {
        return 0.0;
    }
    weighted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = weighted.iter().map(|w| w.1).sum();
    let mut acc = 0.0;
    for (e, w) in &weighted {
        acc += w;
        if acc >= q * total {
            return *e;
        }
    }
    weighted.last().map(|w| w.0).unwrap_or(0.0)
}

/// The display colour at a receiver with illuminance `e` and exitance `m` (both RGB).
pub(crate) fn color(e: DVec3, m: DVec3, material: &Material, k: f64) -> [f32; 3] {
    let value = if material.emission.is_some() {
        m / luma(material.display_base()).max(0.05)
    } else {
        e
    };
    (value * k).to_array().map(|x| shoulder(x) as f32)
}

/// The display colour of a surface showing luminance `l` (RGB, cd/m²) over a white base: the
/// colour a surface of reflectance 1 under illuminance π·L shows, shoulder(k·π·L).
pub(crate) fn luminance_color(l: DVec3, k: f64) -> [f32; 3] {
    (l * std::f64::consts::PI * k)
        .to_array()
        .map(|x| shoulder(x) as f32)
}

fn shoulder(x: f64) -> f64 {
    if x.is_nan() || x <= 0.0 {
        0.0
    } else if x <= 0.8 {
        x
    } else {
        0.8 + 0.2 * (1.0 - (-(x - 0.8) / 0.2).exp())
    }
}

#[cfg(test)]
mod tests {
    use super::shoulder;

    #[test]
    fn shoulder_is_monotone_continuous_and_bounded() {
        let mut last = 0.0;
        for i in 0..10_000 {
            let x = i as f64 * 0.001;
            let y = shoulder(x);
            assert!(y >= last && y <= 1.0);
            last = y;
        }
        assert!((shoulder(0.8 + 1e-9) - 0.8).abs() < 1e-8);
        assert_eq!(shoulder(f64::NAN), 0.0);
    }
}
