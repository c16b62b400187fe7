//! Light at texels: each texel a receiver, read through the same interfaces as vertices.
//!
//! Input: the solved scene, the re-indexed surfaces (with, per vertex, the mesh vertex it copies),
//! the texels' samples. Output: every sampled texel's values written into its atlas; the number
//! of texels whose inter-reflected light was gathered at the texel.
//!
//! Direct light is exact at every texel ([`crate::solution::DirectLight::at`]: shadow rays per
//! texel, so shadows and cut-off lines are as crisp as the texel). Inter-reflected light is
//! interpolated over the texel's triangle from its vertices' gathers (the solve's own rows);
//! triangles never cross a contact or a chart edge. Where a gather at a triangle's middle texel
//! differs from that interpolation by more than the tolerance, every texel of the triangle is
//! gathered. Before reading, a sample is pushed off any surface within a hundredth of a texel
//! along its plane, and out of a solid when most short rays along the plane meet back faces.

use super::{Display, Options, Sampled};
use crate::progress::Progress;
use crate::result::{Atlas, BakedSurface};
use crate::scene::luma;
use crate::solution::{Planes, Receiver, Receivers, Solution, receivers};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// The texels (a subset of them, by index) as receivers.
struct Points<'a> {
    points: &'a [(DVec3, DVec3)],
    subset: Option<&'a [usize]>,
}

impl Receivers for Points<'_> {
    fn len(&self) -> usize {
        self.subset.map_or(self.points.len(), |s| s.len())
    }

    fn receiver(&self, i: usize) -> Receiver {
        let k = self.subset.map_or(i, |s| s[i]);
        let (point, normal) = self.points[k];
        Receiver {
            point,
            planes: Planes::one(normal),
        }
    }
}

/// Light every sampled texel; returns how many were gathered rather than interpolated.
#[allow(clippy::too_many_arguments)]
pub fn light(
    s: &Solution,
    surfaces: &[BakedSurface],
    origins: &[Vec<u32>],
    samples: &[Sampled],
    atlases: &mut [Atlas],
    o: &Options,
    display: &Display,
    progress: &dyn Progress,
) -> usize {
    let mesh = s.mesh();
    let lit: Vec<usize> = (0..samples.len())
        .filter(|&i| samples[i].sample.is_some())
        .collect();
    progress.stage("lightmaps", lit.len() as u64);
    // Where each texel reads, and the barycentric coordinates it interpolates with.
    let placed: Vec<(DVec3, DVec3, [f64; 3])> = samples
        .par_iter()
        .map(|t| match &t.sample {
            Some(x) => {
                let b = &surfaces[t.surface as usize];
                let tri = b.triangles[x.triangle as usize];
                let at = |l: &[f64; 3]| -> (DVec3, DVec3) {
                    let (mut p, mut n) = (DVec3::ZERO, DVec3::ZERO);
                    for j in 0..3 {
                        p += b.positions[tri[j] as usize] * l[j];
                        n += b.normals[tri[j] as usize] * l[j];
                    }
                    (p, n.normalize_or(b.normals[tri[0] as usize]))
                };
                let (near, n) = at(&x.bary);
                if let Some(l) = &x.extended {
                    let (far, _) = at(l);
                    if really_there(s, near, far, n, o.texel_size) {
                        return (far, n, *l);
                    }
                }
                (unocclude(s, near, n, o.texel_size), n, x.bary)
            }
            None => (DVec3::ZERO, DVec3::Y, [1.0, 0.0, 0.0]),
        })
        .collect();
    let points: Vec<(DVec3, DVec3)> = placed.iter().map(|(p, n, _)| (*p, *n)).collect();
    let direct_set = Points {
        points: &points,
        subset: Some(&lit),
    };
    let direct: Vec<DVec3> = receivers::map(&direct_set, progress, |_, r| {
        s.lights().at(mesh, s.occluder(), r)[0]
    });
    // Interpolated inter-reflected light from the vertices' gathers.
    let vertex_indirect = |surface: usize, v: u32| -> DVec3 {
        let g = &mesh.groups[surface];
        let o = origins[surface][v as usize] as usize;
        match o < g.receivers.len() {
            true => s.vertex(g.receivers.start + o).indirect,
            false => DVec3::ZERO,
        }
    };
    let mut indirect: Vec<DVec3> = lit
        .iter()
        .map(|&i| {
            let t = &samples[i];
            let x = t.sample.expect("lit");
            let tri = surfaces[t.surface as usize].triangles[x.triangle as usize];
            let l = placed[i].2;
            (0..3)
                .map(|j| vertex_indirect(t.surface as usize, tri[j]) * l[j])
                .sum()
        })
        .collect();
    // Vertices on a contact's outline read light off it (see `patches`): the triangles they
    // belong to are gathered texel by texel rather than interpolated.
    let outline = |surface: u32, triangle: u32| -> bool {
        let g = &mesh.groups[surface as usize];
        let tri = surfaces[surface as usize].triangles[triangle as usize];
        tri.iter().any(|&v| {
            let k = origins[surface as usize][v as usize] as usize;
            k < g.receivers.len() && {
                let r = &mesh.receivers[g.receivers.start + k];
                (r.point - r.position).length() > 0.01 * o.texel_size
            }
        })
    };
    let gathered = check_and_gather(
        s,
        samples,
        &lit,
        &points,
        &direct,
        &mut indirect,
        o,
        &outline,
        progress,
    );
    for (k, &i) in lit.iter().enumerate() {
        let t = &samples[i];
        let g = &mesh.groups[t.surface as usize];
        let material = &s.scene().materials[g.material];
        let emitted = match g.patches.is_empty() {
            true => DVec3::ZERO,
            false => s.emitted(g.patches.start),
        };
        let e = direct[k] + indirect[k];
        let exitance = emitted + material.reflectance * e;
        let a = &mut atlases[t.atlas as usize];
        let texel = t.texel as usize;
        a.illuminance[texel] = luma(e) as f32;
        a.illuminance_direct[texel] = luma(direct[k]) as f32;
        a.luminance[texel] = (exitance / std::f64::consts::PI)
            .to_array()
            .map(|x| x as f32);
        a.display[texel] = display(e, exitance, g.material);
    }
    for t in samples.iter().filter(|t| t.sample.is_none()) {
        let g = &mesh.groups[t.surface as usize];
        atlases[t.atlas as usize].display[t.texel as usize] =
            display(DVec3::ZERO, DVec3::ZERO, g.material);
    }
    gathered
}

/// Triangles with fewer texels are interpolated unchecked (their vertices are that close).
const MIN_CHECKED: usize = 8;

/// Gather at each triangle's middle texel; where the interpolation misses it by more than the
/// tolerance, gather at every texel of that triangle. Returns the texels gathered.
#[allow(clippy::too_many_arguments)]
fn check_and_gather(
    s: &Solution,
    samples: &[Sampled],
    lit: &[usize],
    points: &[(DVec3, DVec3)],
    direct: &[DVec3],
    indirect: &mut [DVec3],
    o: &Options,
    outline: &dyn Fn(u32, u32) -> bool,
    progress: &dyn Progress,
) -> usize {
    // Texels (positions in `lit`) of each (surface, triangle), in texel order.
    let mut of: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (k, &i) in lit.iter().enumerate() {
        let t = &samples[i];
        of.entry((t.surface, t.sample.expect("lit").triangle))
            .or_default()
            .push(k);
    }
    let gather_at = |ks: &[usize]| -> Vec<DVec3> {
        let set: Vec<usize> = ks.iter().map(|&k| lit[k]).collect();
        let pts = Points {
            points,
            subset: Some(&set),
        };
        receivers::map(&pts, progress, |_, r| {
            s.indirect_at(r.point, r.planes.as_slice()[0])
        })
    };
    let mut full: Vec<usize> = Vec::new();
    if o.tolerance <= 0.0 {
        full = (0..lit.len()).collect();
    } else {
        // The middle texel of each triangle with more than one: nearest the centroid.
        let mut middles_of = Vec::new();
        for ((surface, t), ks) in &of {
            if outline(*surface, *t) {
                full.extend(ks);
            } else if ks.len() >= MIN_CHECKED {
                middles_of.push(ks);
            }
        }
        let middles: Vec<(usize, &Vec<usize>)> = middles_of
            .into_iter()
            .map(|ks| {
                let mid = *ks
                    .iter()
                    .min_by(|&&a, &&b| {
                        let d = |k: usize| {
                            let l = samples[lit[k]].sample.expect("lit").bary;
                            l.iter().map(|x| (x - 1.0 / 3.0).powi(2)).sum::<f64>()
                        };
                        d(a).total_cmp(&d(b))
                    })
                    .expect("non-empty");
                (mid, ks)
            })
            .collect();
        let probe: Vec<usize> = middles.iter().map(|(m, _)| *m).collect();
        let values = gather_at(&probe);
        for ((mid, ks), g) in middles.iter().zip(values) {
            let total = luma(direct[*mid] + g).max(1e-300);
            let miss = (luma(g) - luma(indirect[*mid])).abs();
            indirect[*mid] = g;
            if miss > o.tolerance * total {
                full.extend(ks.iter().filter(|k| *k != mid));
            }
        }
        full.sort_unstable();
        let checked = probe.len();
        let values = gather_at(&full);
        for (k, g) in full.iter().zip(values) {
            indirect[*k] = g;
        }
        return checked + full.len();
    }
    let values = gather_at(&full);
    for (k, g) in full.iter().zip(values) {
        indirect[*k] = g;
    }
    full.len()
}

/// Whether the surface really goes on from `near` (on a chart's edge, normal `n`) to `far` (a
/// texel's centre beyond it, on the plane extended): a coplanar face facing the same way lies
/// under `far`, nothing stands between them along the plane, and nothing covers `far` within a
/// texel. Then the texel reads at its centre and bilinear filtering is continuous across the
/// edge (two meshes meeting, a chart edge on a floor); otherwise it reads at `near`.
fn really_there(s: &Solution, near: DVec3, far: DVec3, n: DVec3, texel: f64) -> bool {
    let occ = s.occluder();
    let lift = (0.01 * texel).max(10.0 * occ.epsilon);
    let under = occ.closest(far + n * lift, -n);
    if !under.is_some_and(|h| h.distance < 2.0 * lift && h.normal.dot(n) > 0.9999) {
        return false;
    }
    let along = far - near;
    let length = along.length();
    if length > 0.0
        && occ
            .closest(near + n * lift, along / length)
            .is_some_and(|h| h.distance < length + lift)
    {
        return false;
    }
    occ.closest(far + n * lift, n)
        .is_none_or(|h| h.distance > texel)
}

/// `p` (on a surface with normal `n`) moved off surfaces it nearly touches along its plane, and
/// out of a solid when most short rays along the plane meet back faces first.
fn unocclude(s: &Solution, p: DVec3, n: DVec3, texel: f64) -> DVec3 {
    let occ = s.occluder();
    let lift = n * occ.epsilon;
    let (u, v) = super::charts::axes(n);
    let reach = 0.75 * texel;
    let margin = (0.01 * texel).max(10.0 * occ.epsilon);
    let mut p = p;
    let mut inside: Option<(f64, DVec3)> = None;
    let mut backs = 0;
    for dir in [u, -u, v, -v] {
        let Some(hit) = occ.closest(p + lift, dir) else {
            continue;
        };
        if hit.distance > reach {
            continue;
        }
        if hit.normal.dot(dir) > 0.0 {
            backs += 1;
            if inside.is_none_or(|(d, _)| hit.distance < d) {
                inside = Some((hit.distance, dir));
            }
        } else if hit.distance < margin {
            p -= dir * (margin - hit.distance);
        }
    }
    if backs >= 2
        && let Some((d, dir)) = inside
    {
        p += dir * (d + margin);
    }
    p
}
