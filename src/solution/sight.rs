//! What a point of a solved scene sees along a direction: the luminance of the surface it meets
//! first, and the point-like beams of direct light arriving at it. View pixels and the exact
//! integrals over the sphere (`sphere`) read the solution this way.

use super::solved::Solution;
use crate::patches::Side;
use crate::scene::luma;
use crate::visibility::Occluder;
use glam::DVec3;

impl Solution<'_> {
    /// Photometric luminance (cd/m²) of the surface first seen from `p` along the unit `dir`
    /// (interpolated between the patch's vertices; 0 for the back of a single-sided face), and
    /// the distance to it; `None` when the ray leaves the scene. Direct sources are not included
    /// (points have no area; see [`Solution::beams`]).
    pub(crate) fn luminance_toward(&self, p: DVec3, dir: DVec3) -> Option<(f64, f64)> {
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
        let pt = &self.mesh().patches[patch];
        let c = pt.corners(&self.mesh().receivers);
        let w = barycentric(q, &c);
        let material = &self.scene().materials[self.mesh().groups[pt.group as usize].material];
        let emitted = self.emitted(patch);
        let l: f64 = (0..3)
            .map(|k| {
                let e = self.vertex(pt.v[k] as usize).total();
                w[k] * luma(emitted + material.reflectance * e) / std::f64::consts::PI
            })
            .sum();
        Some((l.max(0.0), hit.distance))
    }

    fn front_patches(&self) -> Vec<usize> {
        self.mesh()
            .groups
            .iter()
            .filter(|g| g.side == Side::Front)
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
                .map(|p| self.mesh().patches[*p].corners(&self.mesh().receivers))
                .collect();
            (Occluder::from_triangles(&tris, false), front)
        });
        (index, front)
    }

    /// The back-side patch of a front patch of a double-sided surface (groups are laid out front,
    /// then back, with the same patch order).
    fn back_twin(&self, patch: usize) -> Option<usize> {
        let g = self.mesh().patches[patch].group as usize;
        let back = self.mesh().groups.get(g + 1)?;
        let front = &self.mesh().groups[g];
        (back.side == Side::Back && back.surface == front.surface)
            .then(|| back.patches.start + (patch - front.patches.start))
    }

    /// Point-like beams of direct light arriving at `p`: unit direction toward each (sub-)source
    /// and the illuminance it gives on a plane facing it (lx, photometric), shadows included.
    pub(crate) fn beams(&self, p: DVec3) -> Vec<(DVec3, f64)> {
        self.lights()
            .sources
            .iter()
            .flat_map(|s| s.beams(self.occluder(), p))
            .collect()
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
