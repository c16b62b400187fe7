//! Direct light from emitting surfaces (materials with Lambertian emission).
//!
//! - [`patch_exitance`]: the exitance M_e (lm/m², RGB) every patch emits. A material given by
//!   luminance L emits M_e = π·L; one given by luminous flux Φ shares Φ over the area of every face
//!   using it (both faces of a double-sided one).
//! - At receivers, direct light from emitters is gathered like any other patch field, through
//!   `transport::gather` on a tree of the emitting patches only (exact Lambert near, far-field
//!   expansion far).
//! - Into patches, emitted exitance travels through the same balanced transport operator as
//!   reflected exitance (`transport::operator`), so a closed room receives exactly the flux its
//!   surfaces emit.

use crate::patches::PatchMesh;
use crate::scene::{EmissionAmount, Scene};
use glam::DVec3;
use std::f64::consts::PI;

/// Emitted exitance per patch (lm/m², linear RGB scaled so luminance Y is photometric).
pub(crate) fn patch_exitance(scene: &Scene, mesh: &PatchMesh) -> Vec<DVec3> {
    let mut material_area = vec![0.0; scene.materials.len()];
    for g in &mesh.groups {
        material_area[g.material] += g.area;
    }
    let group_exitance: Vec<DVec3> = mesh
        .groups
        .iter()
        .map(|g| {
            let Some(e) = &scene.materials[g.material].emission else {
                return DVec3::ZERO;
            };
            let m = match e.amount {
                EmissionAmount::Luminance(l) => PI * l,
                EmissionAmount::LuminousFlux(phi) if material_area[g.material] > 0.0 => {
                    phi / material_area[g.material]
                }
                EmissionAmount::LuminousFlux(_) => 0.0,
            };
            e.color * m
        })
        .collect();
    mesh.patches
        .iter()
        .map(|p| group_exitance[p.group as usize])
        .collect()
}

/// The Lambertian part of `emitted`: zero for patches whose material emits through a profile
/// (those are direct sources, `direct::profiled`).
pub(crate) fn diffuse_part(scene: &Scene, mesh: &PatchMesh, emitted: &[DVec3]) -> Vec<DVec3> {
    mesh.patches
        .iter()
        .zip(emitted)
        .map(|(p, e)| {
            let m = &scene.materials[mesh.groups[p.group as usize].material];
            match &m.emission {
                Some(em) if em.profile.is_some() => DVec3::ZERO,
                _ => *e,
            }
        })
        .collect()
}
