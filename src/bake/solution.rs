//! Reading light from a solved scene at new points — probe faces now, lightmap texels later —
//! through the same machinery as the vertices: direct light from every source at the point,
//! inter-reflected light gathered over the patch hierarchy with visibility, and the luminance of
//! the surface seen in a direction.

use super::Solution;
use crate::direct::sources::DirectSource;
use crate::scene::luma;
use crate::transport::{
    field::NodeField,
    gather::{Gatherer, SharedRays},
    links,
};
use crate::visibility::Occluder;
use glam::DVec3;

impl Solution<'_> {
    /// Direct illuminance (lx, RGB) at `p` on a plane with unit normal `n`: lights, luminaires,
    /// profiled and Lambertian emitting surfaces, with shadow rays.
    pub fn direct_at(&self, p: DVec3, n: DVec3) -> DVec3 {
        self.direct_at_faces(p, &[n])[0]
    }

    /// [`Solution::direct_at`] on several planes through one point (a probe's six faces).
    pub fn direct_at_faces(&self, p: DVec3, normals: &[DVec3]) -> Vec<DVec3> {
        let emitters = Gatherer {
            mesh: &self.mesh,
            tree: &self.emitter_tree,
            occluder: &self.occluder,
            tau: self.settings.params().tau_direct,
            dark: None,
        };
        super::receivers::direct_at_faces(
            super::receivers::Lights {
                sources: &self.sources,
                groups: &self.groups,
            },
            &self.occluder,
            &emitters,
            &self.node_exitance,
            p,
            normals,
        )
    }

    /// Inter-reflected illuminance (lx, RGB) at `p` on a plane with unit normal `n`, gathered from
    /// the solution with visibility (normalised like a vertex when the point is enclosed).
    pub fn indirect_at(&self, p: DVec3, n: DVec3) -> DVec3 {
        self.indirect_at_faces(p, &[n])[0]
    }

    /// [`Solution::indirect_at`] for several planes through one point (a probe's six faces),
    /// tracing each shadow ray toward a given target once for all of them.
    pub fn indirect_at_faces(&self, p: DVec3, normals: &[DVec3]) -> Vec<DVec3> {
        let gatherer = Gatherer {
            mesh: &self.mesh,
            tree: &self.tree,
            occluder: &self.occluder,
            tau: self.settings.params().tau,
            dark: self.dark.as_deref(),
        };
        // One plane alone has nothing to share.
        let mut shared = (normals.len() > 1).then(SharedRays::default);
        normals
            .iter()
            .map(|n| {
                let row = links::gather_row_shared(&gatherer, p, *n, shared.as_mut());
                self.node_reflected().gather(&row.links)
            })
            .collect()
    }

    /// The reflected exitance summarised on the tree (built on first use, then shared).
    fn node_reflected(&self) -> &NodeField {
        self.node_reflected
            .get_or_init(|| NodeField::new(&self.tree, &self.mesh, &self.reflected))
    }

    /// Photometric luminance (cd/m²) of the surface first seen from `p` along the unit `dir`
    /// (interpolated between the patch's vertices; 0 for the back of a single-sided face), and
    /// the distance to it; `None` when the ray leaves the scene. Direct sources are not included
    /// (points have no area; see [`DirectSource::beams`]).
    pub fn luminance_toward(&self, p: DVec3, dir: DVec3) -> Option<(f64, f64)> {
        let (index, front) = self.surface_index();
        let hit = index.closest(p, dir)?;
        let mut patch = front[hit.triangle];
        if hit.normal.dot(dir) > 0.0 {
            // The back of the face: its twin when double-sided, else black.
            match self.back_twin(patch) {
                Some(twin) => patch = twin,
                None => return Some((0.0, hit.distance)),
            }
        }
        let q = p + dir * hit.distance;
        let pt = &self.mesh.patches[patch];
        let c = pt.corners(&self.mesh.receivers);
        let w = barycentric(q, &c);
        let material = &self.scene.materials[self.mesh.groups[pt.group as usize].material];
        let emitted = self.emitted[patch];
        let l: f64 = (0..3)
            .map(|k| {
                let v = pt.v[k] as usize;
                let e = self.direct[v] + self.indirect[v];
                w[k] * luma(emitted + material.reflectance * e) / std::f64::consts::PI
            })
            .sum();
        Some((l.max(0.0), hit.distance))
    }

    fn front_patches(&self) -> Vec<usize> {
        self.mesh
            .groups
            .iter()
            .filter(|g| g.side == crate::result::Side::Front)
            .flat_map(|g| g.patches.clone())
            .collect()
    }

    /// The closest-hit index over the front patches, and the patch of each of its triangles
    /// (built on first use, then shared).
    fn surface_index(&self) -> (&Occluder, &[usize]) {
        let (index, front) = self.surface_index.get_or_init(|| {
            let front = self.front_patches();
            let tris: Vec<[DVec3; 3]> = front
                .iter()
                .map(|p| self.mesh.patches[*p].corners(&self.mesh.receivers))
                .collect();
            (Occluder::from_triangles(&tris, false), front)
        });
        (index, front)
    }

    /// The back-side patch of a front patch of a double-sided surface (groups are laid out front,
    /// then back, with the same patch order).
    fn back_twin(&self, patch: usize) -> Option<usize> {
        let g = self.mesh.patches[patch].group as usize;
        let back = self.mesh.groups.get(g + 1)?;
        let front = &self.mesh.groups[g];
        (back.side == crate::result::Side::Back && back.surface == front.surface)
            .then(|| back.patches.start + (patch - front.patches.start))
    }

    /// Point-like beams of direct light arriving at `p`: unit direction toward each (sub-)source
    /// and the illuminance it gives on a plane facing it (lx, photometric), shadows included.
    pub fn beams(&self, p: DVec3) -> Vec<(DVec3, f64)> {
        self.sources
            .iter()
            .flat_map(|s| s.beams(&self.occluder, p))
            .collect()
    }

    /// Cuttle's constant estimate of the indirect illuminance, FRF / (A·(1 − R)) (lx): the first
    /// reflected flux spread as in an integrating sphere of the room's area and mean reflectance.
    pub fn cuttle_indirect(&self) -> f64 {
        let (mut area, mut rho) = (0.0, 0.0);
        for p in &self.mesh.patches {
            let m = &self.scene.materials[self.mesh.groups[p.group as usize].material];
            area += p.area;
            rho += p.area * luma(m.reflectance);
        }
        if area <= 0.0 {
            return 0.0;
        }
        let r = rho / area;
        self.first_reflected_flux / (area * (1.0 - r))
    }
}

/// Barycentric weights of `q` (on or near the triangle's plane) in triangle `t`.
fn barycentric(q: DVec3, t: &[DVec3; 3]) -> [f64; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], q - t[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (dq1, dq2) = (d.dot(e1), d.dot(e2));
    let den = d11 * d22 - d12 * d12;
    if den <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let v = ((d22 * dq1 - d12 * dq2) / den).clamp(0.0, 1.0);
    let w = ((d11 * dq2 - d12 * dq1) / den).clamp(0.0, 1.0 - v);
    [1.0 - v - w, v, w]
}

impl DirectSource<'_> {
    /// Point-like beams of this source reaching `p` (see [`Solution::beams`]).
    pub fn beams(&self, occ: &Occluder, p: DVec3) -> Vec<(DVec3, f64)> {
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
}
