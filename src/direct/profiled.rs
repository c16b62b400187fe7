//! Emitting surfaces whose material carries a photometric profile (`LUXBAKE_material.emission.
//! profile`): instead of Lambert's cosine, each patch of such a surface emits the profile's
//! distribution, nadir along the surface normal, C = 0 along the node's local +X projected onto
//! the patch, scaled so the patch emits what a Lambertian patch of that exitance would (M·A).
//!
//! Their light does not go through the diffuse patch field (it is not diffuse); like luminaires
//! they are direct sources: evaluated at receivers and integrated into patches, with each patch
//! split into sub-triangles near the receiver (the same near-field rule as luminaire openings).

use super::bounds::{AngleBounds, ProfileBounds};
use super::flux::{self, Radiator, Spread};
use super::luminaire::NEAR_FIELD_RATIO;
use crate::geom::lambert;
use crate::patches::PatchMesh;
use crate::photometry::Photometry;
use crate::scene::Scene;
use crate::visibility::Occluder;
use glam::{DMat3, DVec3};
use std::sync::Arc;

/// At most this many 4-way splits of a patch per receiver.
const MAX_DEPTH: u32 = 4;

/// One emitting patch with a profile.
struct Patch {
    corners: [DVec3; 3],
    normal: DVec3,
    /// World from photometric frame (photometric −Z = the surface normal).
    frame: DMat3,
    /// Intensity scale: M·A / profile flux.
    scale: f64,
}

/// All patches of the surfaces that use one profiled emitting material side.
pub struct Surface<'a> {
    pub name: Option<String>,
    pub source_path: String,
    pub photometry: &'a Photometry,
    pub color: DVec3,
    patches: Vec<Patch>,
    bounds: Arc<AngleBounds>,
    /// Total flux (lm).
    pub flux: f64,
}

impl<'a> Surface<'a> {
    /// One source per material with a profiled emission; `exitance` is each patch's emitted
    /// exitance (lm/m², RGB) as if it were Lambertian; each profile's bounds from `bounds`.
    pub(crate) fn all(
        scene: &'a Scene,
        mesh: &PatchMesh,
        exitance: &[DVec3],
        bounds: &ProfileBounds,
    ) -> Vec<Surface<'a>> {
        let mut out: Vec<Surface<'a>> = Vec::new();
        for (m, material) in scene.materials.iter().enumerate() {
            let Some(e) = &material.emission else {
                continue;
            };
            let Some(profile) = e.profile else { continue };
            let photometry = &scene.profiles[profile].photometry;
            let profile_flux = photometry.flux();
            if profile_flux <= 0.0 {
                continue;
            }
            let mut patches = Vec::new();
            let mut flux = 0.0;
            for g in mesh.groups.iter().filter(|g| g.material == m) {
                let node = &scene.nodes[scene.surfaces[g.surface].node];
                let local_x = node.world_from_local.transform_vector3(DVec3::X);
                for (k, p) in mesh.patches[g.patches.clone()].iter().enumerate() {
                    let m_e = crate::scene::luma(exitance[g.patches.start + k]);
                    let z = -p.normal;
                    let x = (local_x - z * local_x.dot(z))
                        .try_normalize()
                        .unwrap_or_else(|| z.any_orthonormal_vector());
                    patches.push(Patch {
                        corners: p.corners(&mesh.receivers),
                        normal: p.normal,
                        frame: DMat3::from_cols(x, z.cross(x), z),
                        scale: m_e * p.area / profile_flux,
                    });
                    flux += m_e * p.area;
                }
            }
            out.push(Surface {
                bounds: bounds.get(profile),
                name: material.name.clone(),
                source_path: material.source_path.clone(),
                photometry,
                color: e.color,
                patches,
                flux,
            });
        }
        out
    }

    /// Illuminance (lx, photometric) at `p` with unit normal `n`.
    pub(crate) fn illuminance(&self, occ: &Occluder, p: DVec3, n: DVec3) -> f64 {
        let mut e = 0.0;
        for patch in &self.patches {
            for (q, share) in split(&patch.corners, p) {
                let d = q - p;
                let dist2 = d.length_squared();
                let cos = n.dot(d);
                if cos <= 0.0 || dist2 <= 0.0 || patch.normal.dot(-d) <= 0.0 {
                    continue;
                }
                let dist = dist2.sqrt();
                let i = patch.scale
                    * share
                    * self
                        .photometry
                        .intensity(patch.frame.transpose() * (-d / dist));
                if i > 0.0 && occ.clear(p, n, q, patch.normal) {
                    e += i * (cos / dist) / dist2;
                }
            }
        }
        e
    }

    /// The sub-patches seen from `p` as point sources: position, unit direction from `p`, and
    /// the illuminance each gives on a plane facing it (lx, unshadowed).
    pub(crate) fn point_sources(&self, p: DVec3) -> Vec<(Option<DVec3>, DVec3, f64)> {
        let mut out = Vec::new();
        for patch in &self.patches {
            for (q, share) in split(&patch.corners, p) {
                let d = q - p;
                let dist2 = d.length_squared();
                if dist2 <= 0.0 || patch.normal.dot(-d) <= 0.0 {
                    continue;
                }
                let dir = d / dist2.sqrt();
                let i =
                    patch.scale * share * self.photometry.intensity(patch.frame.transpose() * -dir);
                if i > 0.0 {
                    out.push((Some(q), dir, i / dist2));
                }
            }
        }
        out
    }

    /// `(front, back)` flux (lm) into a triangle patch of the scene.
    pub(crate) fn patch_flux(
        &self,
        occ: &Occluder,
        corners: &[DVec3; 3],
        normal: DVec3,
    ) -> (f64, f64) {
        let c = (corners[0] + corners[1] + corners[2]) / 3.0;
        let budget = 1e-6 * self.flux;
        let mut total = (0.0, 0.0);
        for patch in &self.patches {
            if patch.corners == *corners {
                continue;
            }
            for (q, share) in split(&patch.corners, c) {
                let sub = SubPatch {
                    surface: self,
                    patch,
                    position: q,
                    share,
                };
                let facing = normal.dot(q - corners[0]) > 0.0;
                let (f, b) = flux::patch_flux(&sub, occ, corners, normal, facing, budget * share);
                total.0 += f;
                total.1 += b;
            }
        }
        total
    }
}

/// Sub-triangle centroids of `t` as seen from `p`, with their area shares.
fn split(t: &[DVec3; 3], p: DVec3) -> Vec<(DVec3, f64)> {
    let mut out = Vec::new();
    split_into(t, p, 1.0, 0, &mut out);
    out
}

fn split_into(t: &[DVec3; 3], p: DVec3, share: f64, depth: u32, out: &mut Vec<(DVec3, f64)>) {
    let c = (t[0] + t[1] + t[2]) / 3.0;
    let size = (t[0] - t[1])
        .length()
        .max((t[1] - t[2]).length())
        .max((t[2] - t[0]).length());
    if depth >= MAX_DEPTH || size <= NEAR_FIELD_RATIO * (p - c).length() {
        out.push((c, share));
        return;
    }
    let m = [
        (t[0] + t[1]) * 0.5,
        (t[1] + t[2]) * 0.5,
        (t[2] + t[0]) * 0.5,
    ];
    for s in [
        [t[0], m[0], m[2]],
        [m[0], t[1], m[1]],
        [m[2], m[1], t[2]],
        [m[0], m[1], m[2]],
    ] {
        split_into(&s, p, share / 4.0, depth + 1, out);
    }
}

/// A piece of a profiled patch as a point source.
struct SubPatch<'p, 'a> {
    surface: &'p Surface<'a>,
    patch: &'p Patch,
    position: DVec3,
    share: f64,
}

impl Radiator for SubPatch<'_, '_> {
    fn intensity(&self, dir: DVec3) -> f64 {
        if self.patch.normal.dot(dir) <= 0.0 {
            return 0.0;
        }
        self.patch.scale
            * self.share
            * self
                .surface
                .photometry
                .intensity(self.patch.frame.transpose() * dir)
    }

    fn samples_corners(&self) -> bool {
        true
    }

    fn spread(&self, t: &[DVec3; 3], at: Option<&[f64; 3]>) -> Spread {
        let dirs = t.map(|v| (v - self.position).normalize_or_zero());
        if dirs.iter().all(|d| self.patch.normal.dot(*d) <= 0.0) {
            return Spread::Zero;
        }
        flux::sampled_spread(
            &dirs,
            at,
            |d| self.intensity(d),
            |enough| {
                let scale = self.patch.scale * self.share;
                scale
                    * self.surface.bounds.over_triangle(
                        &self.patch.frame,
                        &dirs,
                        enough / scale.max(1e-300),
                    )
            },
        )
    }

    fn measure(&self, t: &[DVec3; 3], _n: DVec3) -> f64 {
        lambert::triangle_solid_angle(self.position, t)
    }

    fn toward(&self, p: DVec3) -> DVec3 {
        (p - self.position).normalize_or_zero()
    }

    fn sees(&self, occ: &Occluder, p: DVec3, n: DVec3) -> bool {
        occ.clear(p, n, self.position, self.patch.normal)
    }
}
