//! Metrics from cubic illuminance (Cuttle 1997; docs/ANALYTIC.md §4). Input: the six face
//! illuminances `[+x, −x, +y, −y, +z, −z]` (lx) in the probe's axes, +y up. Output: [`Metrics`].
//!
//! - Illumination vector **E** = (E(−x) − E(+x), E(−y) − E(+y), E(−z) − E(+z)): it points along
//!   the flow of light (away from the sources). Its altitude is its elevation above the
//!   horizontal (negative when light flows downward); its azimuth is measured in the horizontal
//!   plane from +x toward −z (counter-clockwise seen from above).
//! - Symmetric component per axis ~Eᵢ = min(E(+i), E(−i)); ~E = their mean.
//! - Scalar (mean spherical) illuminance E_sr = ~E + |**E**|/4; vector/scalar ratio |**E**|/E_sr.
//! - Cylindrical (vertical axis) E_c = ~E + |**E**|·sin ε/π, ε the angle of **E** from vertical.
//! - Semi-cylindrical facing the horizontal direction α (its curved face turned toward α):
//!   E_sc = ~E + |**E**|·sin ε·(1 + cos(α − α_s))/π, α_s the azimuth the light comes from (of −**E**),
//!   so a semi-cylinder facing the source gets the most.
//! - The six-face estimates are exact for one beam and for a uniform field; for two opposed beams
//!   they give E/3 where the true scalar illuminance is E/2. The exact values from an integration
//!   over the sphere are reported beside them (`exact_*`, filled by the probe evaluation).

use glam::DVec3;
use std::f64::consts::PI;

/// Everything derived from one probe's six numbers (lx, degrees).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Metrics {
    /// Illumination vector (probe axes).
    pub vector: [f64; 3],
    pub vector_magnitude: f64,
    pub altitude_deg: f64,
    pub azimuth_deg: f64,
    /// ~E per axis (x, y, z) and their mean ~E.
    pub symmetric: [f64; 3],
    pub symmetric_mean: f64,
    pub scalar: f64,
    pub vector_scalar_ratio: f64,
    /// Horizontal illuminance: on the upward face, E(+y).
    pub horizontal: f64,
    /// Vertical illuminances on the faces +x, −x, +z, −z.
    pub vertical: [f64; 4],
    pub cylindrical: f64,
    /// Semi-cylindrical illuminance facing +x, −x, +z, −z.
    pub semicylindrical: [f64; 4],
    /// Semi-cylindrical illuminance facing the probe's `toward` direction, when it has one.
    pub semicylindrical_toward: Option<f64>,
    /// Scalar and cylindrical illuminance integrated over the sphere of incoming light.
    pub exact_scalar: Option<f64>,
    pub exact_cylindrical: Option<f64>,
    /// Cuttle's constant estimate of the indirect illuminance, FRF / (A·(1 − R)), for comparison
    /// with the computed indirect part.
    pub cuttle_indirect: Option<f64>,
}

/// The metrics of a probe whose faces read `faces`; `toward` (probe axes) adds one more
/// semi-cylindrical value.
pub(crate) fn from_faces(faces: &[f64; 6], toward: Option<DVec3>) -> Metrics {
    let [px, nx, py, ny, pz, nz] = *faces;
    let v = DVec3::new(nx - px, ny - py, nz - pz);
    let mag = v.length();
    let symmetric = [px.min(nx), py.min(ny), pz.min(nz)];
    let sym = (symmetric[0] + symmetric[1] + symmetric[2]) / 3.0;
    let scalar = sym + mag / 4.0;
    let horizontal_len = (v.x * v.x + v.z * v.z).sqrt();
    // sin ε: the vector's angle from the vertical.
    let sin_eps = if mag > 0.0 { horizontal_len / mag } else { 0.0 };
    let azimuth = |d: DVec3| (-d.z).atan2(d.x);
    // Azimuth the light comes from (of −E).
    let alpha_s = azimuth(-v);
    let semi = |alpha: f64| sym + mag * sin_eps * (1.0 + (alpha - alpha_s).cos()) / PI;
    Metrics {
        vector: v.to_array(),
        vector_magnitude: mag,
        altitude_deg: if mag > 0.0 {
            (v.y / mag).asin().to_degrees()
        } else {
            0.0
        },
        azimuth_deg: if horizontal_len > 0.0 {
            azimuth(v).to_degrees()
        } else {
            0.0
        },
        symmetric,
        symmetric_mean: sym,
        scalar,
        vector_scalar_ratio: if scalar > 0.0 { mag / scalar } else { 0.0 },
        horizontal: py,
        vertical: [px, nx, pz, nz],
        cylindrical: sym + mag * sin_eps / PI,
        semicylindrical: [DVec3::X, DVec3::NEG_X, DVec3::Z, DVec3::NEG_Z].map(|d| semi(azimuth(d))),
        semicylindrical_toward: toward.map(|d| semi(azimuth(d))),
        exact_scalar: None,
        exact_cylindrical: None,
        cuttle_indirect: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_field_has_no_vector() {
        let m = from_faces(&[100.0; 6], None);
        assert_eq!(m.vector_magnitude, 0.0);
        assert_eq!(m.vector_scalar_ratio, 0.0);
        assert!((m.scalar - 100.0).abs() < 1e-12 && (m.cylindrical - 100.0).abs() < 1e-12);
        assert!(m.semicylindrical.iter().all(|s| (s - 100.0).abs() < 1e-12));
    }

    #[test]
    fn single_beam_gives_ratio_four() {
        // A beam of E = 300 lx travelling along −y (from above): only the +y face is lit.
        let m = from_faces(&[0.0, 0.0, 300.0, 0.0, 0.0, 0.0], None);
        assert_eq!(m.vector, [0.0, -300.0, 0.0]);
        assert!((m.scalar - 75.0).abs() < 1e-12, "E/4");
        assert!((m.vector_scalar_ratio - 4.0).abs() < 1e-12);
        assert!((m.altitude_deg + 90.0).abs() < 1e-12, "flows straight down");
        assert_eq!(
            m.cylindrical, 0.0,
            "a vertical beam misses a vertical cylinder's side"
        );
    }

    #[test]
    fn horizontal_beam_and_semicylinders() {
        // Light arriving from +x (travelling along −x): faces +x lit with E.
        let e = 200.0;
        let m = from_faces(&[e, 0.0, 0.0, 0.0, 0.0, 0.0], None);
        assert_eq!(m.vector, [-e, 0.0, 0.0]);
        assert!((m.azimuth_deg.abs() - 180.0).abs() < 1e-9);
        // Cylinder: E/π; semi-cylinder facing the source 2E/π, facing away 0, sideways E/π.
        assert!((m.cylindrical - e / PI).abs() < 1e-9);
        let [to_px, to_nx, to_pz, to_nz] = m.semicylindrical;
        assert!((to_px - 2.0 * e / PI).abs() < 1e-9, "{to_px}");
        assert!(to_nx.abs() < 1e-9);
        assert!((to_pz - e / PI).abs() < 1e-9 && (to_nz - e / PI).abs() < 1e-9);
    }

    #[test]
    fn opposed_beams_show_the_six_face_limit() {
        // Two equal beams from ±x: the six-face scalar estimate is E/3 (exact would be E/2).
        let e = 90.0;
        let m = from_faces(&[e, e, 0.0, 0.0, 0.0, 0.0], None);
        assert!((m.scalar - e / 3.0).abs() < 1e-12);
        assert_eq!(m.vector_magnitude, 0.0);
    }
}
