//! The two places the light cut ([`super::cut`]) sums light into: a point's planes
//! ([`AtPoint`]: vertices, probes, texels, meshing's estimate) and a patch's front
//! ([`IntoPatch`]: the flux the inter-reflection starts from).
//!
//! Input: the direct sources and the occluder, a point and its planes or a patch. Output: the
//! light summed source by source: exactly for what the cut does not cluster, its estimate for
//! each luminaire of a kept cluster.

use super::cut::Target;
use super::enclosed;
use super::groups::Known;
use super::luminaire::Source;
use super::sources::DirectSource;
use crate::visibility::Occluder;
use glam::DVec3;

/// Direct light at a point on the planes with unit `normals`: photometric (lx) and RGB per plane.
pub struct AtPoint<'a, 's> {
    pub sources: &'s [DirectSource<'a>],
    pub occ: &'s Occluder,
    pub p: DVec3,
    pub normals: &'s [DVec3],
    /// lx, photometric, per plane.
    pub luma: Vec<f64>,
    /// lx, RGB, per plane.
    pub rgb: Vec<DVec3>,
    /// Luminaires' soft shadows integrated (true from [`AtPoint::new`]); off, one ray per
    /// near-field sub-source: what meshing's estimate of the light needs, at a quarter of the rays.
    pub soft_shadows: bool,
}

impl<'a, 's> AtPoint<'a, 's> {
    pub fn new(
        sources: &'s [DirectSource<'a>],
        occ: &'s Occluder,
        p: DVec3,
        normals: &'s [DVec3],
    ) -> Self {
        AtPoint {
            sources,
            occ,
            p,
            normals,
            luma: vec![0.0; normals.len()],
            rgb: vec![DVec3::ZERO; normals.len()],
            soft_shadows: true,
        }
    }

    fn add(&mut self, k: usize, values: &[f64]) {
        let color = self.sources[k].color();
        for ((e, l), x) in self.rgb.iter_mut().zip(self.luma.iter_mut()).zip(values) {
            *e += color * *x;
            *l += x;
        }
    }
}

impl Target for AtPoint<'_, '_> {
    fn planes(&self) -> usize {
        self.normals.len()
    }
    fn cluster_planes(&self) -> usize {
        self.normals.len()
    }
    fn exact(&mut self, k: usize, known: Known, out: &mut [f64]) {
        let how = (known, self.soft_shadows);
        self.sources[k].illuminance_faces(self.occ, self.p, self.normals, out, how);
        self.add(k, out);
    }
    fn sees(&self, n: DVec3, q: DVec3, nq: DVec3) -> bool {
        self.occ.clear(self.p, n, q, nq)
    }
    fn geometry(&self, s: &Source, out: &mut [f64]) {
        s.geometry_faces(self.p, self.normals, out);
    }
    fn cone(&self, lo: DVec3, hi: DVec3) -> Option<(DVec3, f64)> {
        super::cut::cone(lo, hi, self.p, 0.0)
    }
    fn accept(&mut self, k: usize, values: &[f64]) {
        self.add(k, values);
    }
}

/// One patch's flux, source by source, for the cut: only groups in front of the patch are
/// clustered (their flux all lands on the front), the bound kept on the front's flux.
pub struct IntoPatch<'a, 's> {
    pub sources: &'s [DirectSource<'a>],
    pub occ: &'s Occluder,
    pub corners: [DVec3; 3],
    pub normal: DVec3,
    /// Centroid and bounding radius (m).
    pub c: DVec3,
    pub size: f64,
    /// Sources behind the patch and outside this solid light nothing of it (see `into_patches`).
    pub dark_back: Option<Option<enclosed::Bounds>>,
    pub double_sided: bool,
    /// `(front, back)` flux (lm) per source.
    pub row: &'s mut [(f64, f64)],
}

impl Target for IntoPatch<'_, '_> {
    fn planes(&self) -> usize {
        1
    }
    fn cluster_planes(&self) -> usize {
        1
    }
    fn exact(&mut self, k: usize, known: Known, out: &mut [f64]) {
        let s = &self.sources[k];
        if (self.dark_back).is_some_and(|solid| s.behind_and_outside(self.c, self.normal, solid)) {
            return;
        }
        let (front, back) = s.patch_flux(self.occ, &self.corners, self.normal, known);
        // A double-sided patch's back is its twin, which takes that light as front.
        self.row[k] = (front, if self.double_sided { 0.0 } else { back });
        out[0] += front;
    }
    fn sees(&self, n: DVec3, q: DVec3, nq: DVec3) -> bool {
        self.occ.clear(self.c, n, q, nq)
    }
    fn geometry(&self, s: &Source, out: &mut [f64]) {
        out[0] += s.geometry_patch(&self.corners);
    }
    fn cone(&self, lo: DVec3, hi: DVec3) -> Option<(DVec3, f64)> {
        super::cut::cone(lo, hi, self.c, self.size)
    }
    fn accept(&mut self, k: usize, values: &[f64]) {
        self.row[k] = (values[0], 0.0);
    }
}
