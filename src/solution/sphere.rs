//! Integration of incoming light over the whole sphere at a point: the exact definitions of
//! scalar illuminance E_sr = ¼∫L dΩ and cylindrical illuminance E_c = (1/π)∫L·sin ε dΩ
//! (ε from the vertical), and planar illuminance ∫L·cos θ dΩ on given planes — the brute-force
//! reference the six-face estimates are checked against.
//!
//! Input: the solved scene, a point, its vertical axis, plane normals, a resolution. Output:
//! [`SphereResult`]. Surfaces are sampled along `rings × 2·rings` directions of equal solid
//! angle (stratified in cos θ and φ about the vertical), each taking the luminance of the surface
//! it meets; point-like sources (lights, luminaire sub-sources) are added exactly as beams.

use super::solved::Solution;
use glam::DVec3;
use std::f64::consts::PI;

#[derive(Debug, Clone, PartialEq)]
pub struct SphereResult {
    /// Scalar (mean spherical) illuminance (lx).
    pub scalar: f64,
    /// Cylindrical illuminance about the vertical (lx).
    pub cylindrical: f64,
    /// Illuminance on each requested plane (lx).
    pub planes: Vec<f64>,
}

pub fn integrate(
    solution: &Solution,
    p: DVec3,
    up: DVec3,
    normals: &[DVec3],
    rings: usize,
) -> SphereResult {
    let up = up.normalize();
    let (t, b) = up.any_orthonormal_pair();
    let (nu, nv) = (rings.max(2), 2 * rings.max(2));
    let cell = 4.0 * PI / (nu * nv) as f64;
    let mut out = SphereResult {
        scalar: 0.0,
        cylindrical: 0.0,
        planes: vec![0.0; normals.len()],
    };
    let mut add = |dir: DVec3, e: f64| {
        // `e`: illuminance this direction brings onto a plane facing it.
        let sin_eps = (1.0 - dir.dot(up).powi(2)).max(0.0).sqrt();
        out.scalar += e / 4.0;
        out.cylindrical += e * sin_eps / PI;
        for (acc, n) in out.planes.iter_mut().zip(normals) {
            *acc += e * n.dot(dir).max(0.0);
        }
    };
    for iu in 0..nu {
        let cos = 1.0 - 2.0 * (iu as f64 + 0.5) / nu as f64;
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        for iv in 0..nv {
            let phi = 2.0 * PI * (iv as f64 + 0.5) / nv as f64;
            let dir = up * cos + t * (sin * phi.cos()) + b * (sin * phi.sin());
            if let Some((l, _)) = solution.luminance_toward(p, dir) {
                add(dir, l * cell);
            }
        }
    }
    for (dir, e) in solution.beams(p) {
        add(dir, e);
    }
    out
}
