//! Every direct source of a scene behind one interface: `KHR_lights_punctual` lights,
//! photometric luminaires and emitting surfaces with a photometric profile. Lambertian emitting
//! surfaces are not here: their light travels through the patch field (see `direct::emitters`).

use super::bounds::ProfileBounds;
use super::groups::{Groups, Known};
use super::{enclosed, luminaire, profiled, punctual};
use crate::patches::PatchMesh;
use crate::scene::{Light, LightKind, Scene};
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::PI;

pub enum DirectSource<'a> {
    Punctual(&'a Light),
    Luminaire(luminaire::Source<'a>),
    /// Emitting surfaces whose material has a photometric profile.
    Profiled(profiled::Surface<'a>),
}

impl<'a> DirectSource<'a> {
    /// The scene's lights, its luminaires, then its profiled emitting surfaces (`exitance`: what
    /// each patch emits, as if Lambertian).
    pub(crate) fn all(
        scene: &'a Scene,
        mesh: &PatchMesh,
        exitance: &[DVec3],
        bounds: &ProfileBounds,
    ) -> Vec<DirectSource<'a>> {
        let lights = scene.lights.iter().map(DirectSource::Punctual);
        let luminaires = luminaire::Source::all(scene, bounds)
            .into_iter()
            .map(DirectSource::Luminaire);
        let surfaces = profiled::Surface::all(scene, mesh, exitance, bounds)
            .into_iter()
            .map(DirectSource::Profiled);
        lights.chain(luminaires).chain(surfaces).collect()
    }

    /// The luminaires among `sources` grouped in space for shared visibility (other sources are
    /// always traced).
    pub fn groups(sources: &[DirectSource]) -> Groups {
        Groups::from_places(sources.iter().map(|s| match s {
            DirectSource::Luminaire(l) => {
                let c = l.opening_corners();
                let lo = c.iter().fold(c[0], |a, b| a.min(*b));
                let hi = c.iter().fold(c[0], |a, b| a.max(*b));
                Some((l.position, lo, hi))
            }
            _ => None,
        }))
    }

    /// Point-like beams of this source reaching `p` (shadows included; see `Solution::beams`).
    pub(crate) fn beams(&self, occ: &Occluder, p: DVec3) -> Vec<(DVec3, f64)> {
        self.point_sources(p)
            .into_iter()
            .filter_map(|(q, dir_from_p, e_normal)| {
                let visible = match q {
                    Some(q) => occ.clear(p, DVec3::ZERO, q, DVec3::ZERO),
                    None => occ.escapes(p, DVec3::ZERO, dir_from_p),
                };
                (visible && e_normal > 0.0).then_some((dir_from_p, e_normal))
            })
            .collect()
    }

    /// The point-like pieces of this source as seen from `p`: position (None for a directional
    /// light), unit direction from `p` toward it, and the illuminance it gives on a plane facing
    /// it (lx, photometric, unshadowed).
    pub(crate) fn point_sources(&self, p: DVec3) -> Vec<(Option<DVec3>, DVec3, f64)> {
        let toward = |q: DVec3, i: f64| {
            let d = q - p;
            let dist2 = d.length_squared();
            (dist2 > 0.0).then(|| (Some(q), d / dist2.sqrt(), i / dist2))
        };
        match self {
            DirectSource::Punctual(l) if l.kind == LightKind::Directional => {
                vec![(None, -l.direction, l.intensity)]
            }
            DirectSource::Punctual(l) => {
                let d = (p - l.position).normalize_or_zero();
                toward(l.position, punctual::intensity(l, d))
                    .into_iter()
                    .collect()
            }
            DirectSource::Luminaire(s) => s
                .split(p)
                .into_iter()
                .filter_map(|(q, share)| {
                    toward(q, share * s.intensity((p - q).normalize_or_zero()))
                })
                .collect(),
            DirectSource::Profiled(s) => s.point_sources(p),
        }
    }

    /// Relative RGB colour (luminance 1).
    pub(crate) fn color(&self) -> DVec3 {
        match self {
            DirectSource::Punctual(l) => l.color,
            DirectSource::Luminaire(s) => s.color,
            DirectSource::Profiled(s) => s.color,
        }
    }

    /// Illuminance (lx, photometric) at point `p` with unit normal `n`.
    pub(crate) fn illuminance(&self, occ: &Occluder, p: DVec3, n: DVec3) -> f64 {
        match self {
            DirectSource::Punctual(l) => punctual::illuminance(l, occ, p, n),
            DirectSource::Luminaire(s) => s.illuminance(occ, p, n),
            DirectSource::Profiled(s) => s.illuminance(occ, p, n),
        }
    }

    /// Illuminance (lx, photometric) at `p` on planes with the unit `normals`, added to `out`
    /// (luminaires share their sub-sources' intensities and shadow rays between the planes).
    /// `known`: what a group's query proved of a luminaire's visibility ([`super::groups`]);
    /// `soft`: integrate luminaires' soft shadows (else one ray per sub-source: an estimate).
    pub fn illuminance_faces(
        &self,
        occ: &Occluder,
        p: DVec3,
        normals: &[DVec3],
        out: &mut [f64],
        (known, soft): (Known, bool),
    ) {
        match self {
            DirectSource::Luminaire(s) => s.illuminance_faces(occ, p, normals, out, (known, soft)),
            _ => {
                for (e, n) in out.iter_mut().zip(normals) {
                    *e += self.illuminance(occ, p, *n);
                }
            }
        }
    }

    /// `(front, back)` flux (lm, photometric) into a triangle patch (`known`: as for
    /// [`DirectSource::illuminance_faces`]).
    pub(crate) fn patch_flux(
        &self,
        occ: &Occluder,
        corners: &[DVec3; 3],
        normal: DVec3,
        known: Known,
    ) -> (f64, f64) {
        match self {
            DirectSource::Punctual(l) => {
                let budget = punctual::refinement_budget(l, occ.diagonal);
                punctual::patch_flux(l, occ, corners, normal, budget)
            }
            DirectSource::Luminaire(s) => s.patch_flux(occ, corners, normal, s.budget(), known),
            DirectSource::Profiled(s) => s.patch_flux(occ, corners, normal),
        }
    }

    /// Does the source lie wholly behind the plane through `c` with unit normal `n` — so that
    /// there it can light only a patch's back — and, when `solid` is given, wholly outside that
    /// box? Conservative: profiled emitting surfaces always answer no.
    pub(crate) fn behind_and_outside(
        &self,
        c: DVec3,
        n: DVec3,
        solid: Option<enclosed::Bounds>,
    ) -> bool {
        // Runs for every patch and source: no allocation.
        let corners: [DVec3; 4] = match self {
            // At infinity: outside every box.
            DirectSource::Punctual(l) if l.kind == LightKind::Directional => {
                return n.dot(l.direction) > 0.0;
            }
            DirectSource::Punctual(l) => [l.position; 4],
            DirectSource::Luminaire(s) => s.opening_corners(),
            DirectSource::Profiled(_) => return false,
        };
        let behind = corners.iter().all(|q| n.dot(*q - c) < 0.0);
        let bounds = corners
            .iter()
            .fold((corners[0], corners[0]), |(lo, hi), q| {
                (lo.min(*q), hi.max(*q))
            });
        behind && solid.is_none_or(|s| !enclosed::overlap(s, bounds))
    }

    /// Emitted flux (lm); `None` for a directional light (it emits what the scene intercepts).
    pub(crate) fn emitted_flux(&self) -> Option<f64> {
        match self {
            DirectSource::Punctual(l) => punctual::emitted_flux(l),
            DirectSource::Luminaire(s) => Some(s.flux),
            DirectSource::Profiled(s) => Some(s.flux),
        }
    }

    /// Flux that leaves the scene without touching a surface: a 64 × 128 grid of equal
    /// solid-angle cells (uniform in cos θ and φ), each weighted by the intensity at its centre.
    pub(crate) fn escaping_flux(&self, occ: &Occluder) -> f64 {
        let (position, intensity): (DVec3, Box<dyn Fn(DVec3) -> f64 + Sync + '_>) = match self {
            DirectSource::Punctual(l) if l.kind == LightKind::Directional => return 0.0,
            DirectSource::Punctual(l) => (l.position, Box::new(move |d| punctual::intensity(l, d))),
            DirectSource::Luminaire(s) => (s.position, Box::new(move |d| s.intensity(d))),
            // Surfaces: their escape is counted with the other surfaces' (rays from patches).
            DirectSource::Profiled(_) => return 0.0,
        };
        let (nu, nv) = (64usize, 128usize);
        let cell = 4.0 * PI / (nu * nv) as f64;
        (0..nu)
            .into_par_iter()
            .map(|iu| {
                let cos = 1.0 - 2.0 * (iu as f64 + 0.5) / nu as f64;
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                (0..nv)
                    .map(|iv| {
                        let phi = 2.0 * PI * (iv as f64 + 0.5) / nv as f64;
                        let d = DVec3::new(sin * phi.cos(), cos, sin * phi.sin());
                        let i = intensity(d);
                        if i > 0.0 && occ.escapes(position, DVec3::ZERO, d) {
                            i * cell
                        } else {
                            0.0
                        }
                    })
                    .sum::<f64>()
            })
            .collect::<Vec<_>>()
            .iter()
            .sum()
    }
}
