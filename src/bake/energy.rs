//! The energy bookkeeping of a bake: emitted = absorbed + escaped, checked, not assumed.
//!
//! Each term is measured on its own: emitted flux from the lights' definitions and the emitting
//! areas; absorbed flux from the solution, (1 − ρ)·E·A summed over patches, plus what lands on the
//! back faces of single-sided surfaces; escaped flux from a fixed pattern of rays that leave the
//! scene (stratified over the sphere for point and spot lights, cosine-weighted over the
//! hemisphere for light leaving surfaces that are not enclosed). Their difference is the balance error: it
//! collects the solver's residual, the balancing tolerance and the error of the escape estimates
//! (in a closed room the transport operator is balanced to conserve flux, see
//! `transport::operator`).

use super::Solution;
use crate::direct::sources::DirectSource;
use crate::geom::samples;
use crate::scene::luma;
use glam::DVec3;
use rayon::prelude::*;

pub struct Inputs<'a> {
    pub solution: &'a Solution<'a>,
    /// Per receiver: the fraction of its hemisphere covered by back faces, and whether it is
    /// enclosed (`ReceiverLinks::back`, `ReceiverLinks::closed`).
    pub back: &'a [f32],
    pub closed: &'a [bool],
    /// Direct irradiance of each patch's front (lx, RGB).
    pub direct_patch: &'a [DVec3],
    /// Flux of punctual lights onto back faces of single-sided patches (lm, RGB).
    pub light_back: DVec3,
    /// The lights and luminaires, and the flux each sends onto surfaces, front and back (lm).
    pub sources: &'a [DirectSource<'a>],
    pub source_received: &'a [f64],
    /// Illuminance from inter-reflection averaged over each patch (lx, RGB).
    pub indirect_patch: &'a [DVec3],
    pub rho: &'a [DVec3],
}

/// Photometric fluxes in lm.
#[derive(Debug, Clone, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct EnergyBalance {
    pub emitted_lm: f64,
    pub emitted_by_lights_lm: f64,
    pub emitted_by_surfaces_lm: f64,
    pub direct_received_lm: f64,
    pub reflected_lm: f64,
    pub absorbed_lm: f64,
    pub escaped_lm: f64,
    /// Of which: straight from punctual lights, and from surfaces (emitted or reflected).
    pub escaped_from_lights_lm: f64,
    pub escaped_from_surfaces_lm: f64,
    /// emitted − absorbed − escaped.
    pub balance_error_lm: f64,
    /// |balance error| / emitted.
    pub balance_error_relative: f64,
}

pub fn balance(i: Inputs) -> EnergyBalance {
    let s = i.solution;
    let mesh = &s.mesh;
    let mut lights = 0.0;
    let mut lights_escaped = 0.0;
    for (source, received) in i.sources.iter().zip(i.source_received) {
        match source.emitted_flux() {
            // A directional light emits what the scene intercepts.
            None => lights += received,
            Some(flux) => {
                lights += flux;
                lights_escaped += source.escaping_flux(&s.occluder);
            }
        }
    }
    let surfaces: f64 = mesh
        .patches
        .iter()
        .zip(&s.exitance)
        .map(|(p, m)| p.area * luma(*m))
        .sum();
    let mut direct_received = luma(i.light_back);
    let mut reflected = 0.0;
    let mut to_back = 0.0;
    let mut surfaces_escaped = 0.0;
    let mut absorbed_front = 0.0;
    let open = open_fractions(i.solution, i.closed);
    for (k, p) in mesh.patches.iter().enumerate() {
        let back = p.v.iter().map(|&v| i.back[v as usize] as f64).sum::<f64>() / 3.0;
        let open = open[k];
        let emitted_here = p.area * luma(s.exitance[k]);
        let out = emitted_here + p.area * luma(s.reflected[k]);
        reflected += p.area * luma(s.reflected[k]);
        to_back += out * back;
        surfaces_escaped += out * open;
        direct_received += p.area * luma(i.direct_patch[k]) + emitted_here * back;
        let e = i.direct_patch[k] + i.indirect_patch[k];
        absorbed_front += p.area * luma((DVec3::ONE - i.rho[k]) * e);
    }
    let emitted = lights + surfaces;
    let absorbed = absorbed_front + luma(i.light_back) + to_back;
    let escaped = lights_escaped + surfaces_escaped;
    let error = emitted - absorbed - escaped;
    EnergyBalance {
        emitted_lm: emitted,
        emitted_by_lights_lm: lights,
        emitted_by_surfaces_lm: surfaces,
        direct_received_lm: direct_received,
        reflected_lm: reflected,
        absorbed_lm: absorbed,
        escaped_lm: escaped,
        escaped_from_lights_lm: lights_escaped,
        escaped_from_surfaces_lm: surfaces_escaped,
        balance_error_lm: error,
        balance_error_relative: if emitted > 0.0 {
            error.abs() / emitted
        } else {
            0.0
        },
    }
}

/// Fraction of each patch's outgoing (cosine-distributed) flux that leaves the scene: 0 for
/// patches whose receivers are all enclosed, else measured with 16 × 16 stratified
/// cosine-weighted rays from the patch centroid. Not measured (0) for patches that send nothing
/// out: the fraction is only ever multiplied by what they send.
fn open_fractions(s: &Solution, closed: &[bool]) -> Vec<f64> {
    let mesh = &s.mesh;
    mesh.patches
        .par_iter()
        .enumerate()
        .map(|(k, p)| {
            let dark = s.exitance[k] == DVec3::ZERO && s.reflected[k] == DVec3::ZERO;
            if dark || p.v.iter().all(|&v| closed[v as usize]) {
                return 0.0;
            }
            let c = p.corners(&mesh.receivers);
            let centroid = (c[0] + c[1] + c[2]) / 3.0;
            let open = samples::cosine_directions(p.normal, 16)
                .filter(|d| s.occluder.escapes(centroid, p.normal, *d))
                .count();
            open as f64 / 256.0
        })
        .collect()
}
