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
//! A texel a chart only touches reads its centre where the surface really goes on beyond the
//! chart's edge; else the edge point nearest it, except beside a contact's outline, where it
//! reads half a texel inside (toward its triangle's centroid): at the outline's foot whatever
//! stands there shades a quarter of the sphere, and filtering would smear that over the wall.

use super::reflected::{At, Points, Reading};
use super::{Display, Sampled};
use crate::result::{Atlas, BakedSurface};
use crate::scene::luma;
use crate::solution::{Solution, receivers};
use glam::DVec3;
use rayon::prelude::*;

/// Light every sampled texel; returns how many were gathered rather than interpolated.
pub(crate) fn light(
    r: &Reading,
    samples: &[Sampled],
    atlases: &mut [Atlas],
    display: &Display,
) -> usize {
    let Reading { s, progress, .. } = *r;
    let mesh = s.mesh();
    let lit: Vec<usize> = (0..samples.len())
        .filter(|&i| samples[i].sample.is_some())
        .collect();
    progress.stage("lightmaps", lit.len() as u64);
    // Where each texel reads, and the barycentric coordinates it interpolates with.
    let placed: Vec<(DVec3, DVec3, [f64; 3])> = samples.par_iter().map(|t| place(r, t)).collect();
    let points: Vec<(DVec3, DVec3)> = lit.iter().map(|&i| (placed[i].0, placed[i].1)).collect();
    let direct: Vec<DVec3> = receivers::map(&Points(&points), progress, |_, r| {
        s.lights().at(mesh, s.occluder(), r)[0]
    });
    let at: Vec<At> = (lit.iter())
        .map(|&i| {
            let t = &samples[i];
            At {
                surface: t.surface,
                triangle: t.sample.expect("lit").triangle,
                bary: placed[i].2,
                point: placed[i].0,
                normal: placed[i].1,
            }
        })
        .collect();
    let (indirect, gathered) = super::reflected::at_texels(r, &at, &direct);
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

/// Where texel sample `t` reads (point and normal), and the barycentric coordinates it
/// interpolates with: its centre where the surface really goes on beyond its chart's edge,
/// else the edge point nearest it or, beside a contact's outline, half a texel inside.
fn place(r: &Reading, t: &Sampled) -> (DVec3, DVec3, [f64; 3]) {
    let (s, surfaces, origins, o) = (r.s, r.surfaces, r.origins, r.o);
    match &t.sample {
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
            let mut bary = x.bary;
            if let Some(l) = &x.extended {
                let (far, _) = at(l);
                if really_there(s, near, far, n, o.texel_size) {
                    return (far, n, *l);
                }
                // No surface under its centre, and the edge a contact's outline: the texel
                // reads half a texel inside its triangle, toward the triangle's centroid,
                // so bilinear filtering carries the light of the surface beside the edge,
                // not that of the edge itself (in the shadow of what stands on it, within
                // the contact's gap). At other edges (a room's corner) it reads the edge.
                let surface = t.surface as usize;
                let outline = on_outline(
                    s,
                    surfaces,
                    surface,
                    &origins[surface],
                    tri,
                    &x.bary,
                    o.texel_size,
                );
                if !outline {
                    return (unocclude(s, near, n, o.texel_size), n, x.bary);
                }
                let (centroid, _) = at(&[1.0 / 3.0; 3]);
                let d = centroid.distance(near);
                let toward = match d > 0.0 {
                    true => (0.5 * o.texel_size / d).min(1.0),
                    false => 0.0,
                };
                bary = std::array::from_fn(|k| x.bary[k] + toward * (1.0 / 3.0 - x.bary[k]));
            }
            let (point, _) = at(&bary);
            (unocclude(s, point, n, o.texel_size), n, bary)
        }
        None => (DVec3::ZERO, DVec3::Y, [1.0, 0.0, 0.0]),
    }
}

/// Whether the point `bary` of triangle `tri` of surface `surface` lies on an edge whose two
/// ends are on a contact's outline, or within half a texel of a vertex there. Outline vertices
/// are those the solve read off the surface by more than a hundredth of a texel (`origins`:
/// each vertex's mesh receiver in its group).
fn on_outline(
    s: &Solution,
    surfaces: &[BakedSurface],
    surface: usize,
    origins: &[u32],
    tri: [u32; 3],
    bary: &[f64; 3],
    texel: f64,
) -> bool {
    let nudged = |v: u32| super::reflected::outline_step(s, surface, origins, v, texel).is_some();
    let on_edge =
        (0..3).any(|k| bary[k] < 1e-3 && nudged(tri[(k + 1) % 3]) && nudged(tri[(k + 2) % 3]));
    // Or beside an outline vertex (on an edge leaving the outline), within half a texel.
    let b = &surfaces[surface];
    let p: DVec3 = (0..3).map(|k| b.positions[tri[k] as usize] * bary[k]).sum();
    on_edge || (tri.iter()).any(|&v| nudged(v) && b.positions[v as usize].distance(p) < 0.5 * texel)
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
    if !under.is_some_and(|h| h.distance < 2.0 * lift && h.normal.dot(n) > 0.9994) {
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
