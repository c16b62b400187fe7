//! The direct stage: light from the scene's sources, exact at every vertex, and as flux into every
//! patch (what the radiosity solution then reflects).
//!
//! Input: the meshed scene, its [`DirectLight`] and the occluder. Output: direct illuminance at
//! each vertex (lx, RGB), and [`PatchFlux`]. Both are sums over fixed chunks in order:
//! deterministic whatever the thread count. Both go through the light's cut (`direct::cut`):
//! with a fraction f above 0, each vertex's light and each patch's front flux from the
//! luminaires are within f of their full sums.

use crate::direct::enclosed::Solids;
use crate::direct::targets::IntoPatch;
use crate::patches::PatchMesh;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::solution::{DirectLight, receivers};
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// Direct illuminance (lx, RGB) at every vertex of `mesh`: the vertices are receivers like any
/// other, read before the solve.
pub fn at_vertices(
    lights: &DirectLight,
    mesh: &PatchMesh,
    occ: &Occluder,
    progress: &dyn Progress,
) -> Vec<DVec3> {
    let vertices = receivers::Vertices(&mesh.receivers);
    receivers::map(&vertices, progress, |_, r| lights.at(mesh, occ, r)[0])
}

/// Direct flux of the lights and luminaires: into each patch's front (RGB), onto back faces
/// (RGB), and per source (lm, photometric, front and back).
pub struct PatchFlux {
    pub per_patch: Vec<DVec3>,
    pub back: DVec3,
    pub per_source: Vec<f64>,
}

pub fn into_patches(
    scene: &Scene,
    lights: &DirectLight,
    mesh: &PatchMesh,
    occ: &Occluder,
) -> PatchFlux {
    let (sources, groups) = (&lights.sources, &lights.groups);
    let solids = Solids::new(scene);
    // Fixed chunks of patches, each summed into its own totals, the chunks' totals added in
    // order: deterministic whatever the thread count. (Not a row of every source for every
    // patch kept until the end: patches × sources × 16 bytes, too much on large scenes.)
    let parts: Vec<PatchFlux> = mesh
        .patches
        .par_chunks(FLUX_CHUNK)
        .map(|chunk| {
            let mut part = PatchFlux {
                per_patch: Vec::with_capacity(chunk.len()),
                back: DVec3::ZERO,
                per_source: vec![0.0; sources.len()],
            };
            let mut row = vec![(0.0, 0.0); sources.len()];
            for p in chunk {
                let corners = p.corners(&mesh.receivers);
                // A group's query starts from the corners the patch-flux integration traces
                // from (pulled a hair inside the patch, `direct::flux`), pulled off the side
                // that faces it (the back of a single-sided patch absorbs what reaches it); its
                // hull holds the centroid and every point the integration refines to.
                let c = (corners[0] + corners[1] + corners[2]) / 3.0;
                let inset = corners.map(|v| v + (c - v) * 1e-4);
                let settle = |lo: DVec3, hi: DVec3, n: DVec3| {
                    occ.settle(&inset.map(|v| v + n * occ.epsilon), lo, hi)
                };
                row.fill((0.0, 0.0));
                // Sources that can light only this patch's back, when that back is lit by its
                // twin instead (double-sided) or faces the inside of a closed solid they lie
                // outside of, send it nothing: no rays for them.
                let dark_back = match p.double_sided {
                    true => Some(None),
                    false => solids.of(mesh.groups[p.group as usize].surface).map(Some),
                };
                let mut into = IntoPatch {
                    sources,
                    occ,
                    corners,
                    normal: p.normal,
                    c,
                    size: corners
                        .iter()
                        .map(|v| (*v - c).length())
                        .fold(0.0, f64::max),
                    dark_back,
                    double_sided: p.double_sided,
                    row: &mut row,
                };
                let normals = [p.normal, -p.normal];
                lights
                    .cut
                    .run(sources, groups, c, &normals, settle, &mut into);
                let mut front = DVec3::ZERO;
                for (k, &(f, b)) in row.iter().enumerate() {
                    let color = sources[k].color();
                    front += color * f;
                    part.back += color * b;
                    part.per_source[k] += f + b;
                }
                part.per_patch.push(front);
            }
            part
        })
        .collect();
    let mut out = PatchFlux {
        per_patch: Vec::with_capacity(mesh.patches.len()),
        back: DVec3::ZERO,
        per_source: vec![0.0; sources.len()],
    };
    for part in parts {
        out.per_patch.extend(part.per_patch);
        out.back += part.back;
        for (total, x) in out.per_source.iter_mut().zip(part.per_source) {
            *total += x;
        }
    }
    // What reaches covered parts (through a gap a few millimetres wide, under a cover) is
    // absorbed there: counted with the backs, so the energy report sees it.
    let covered: Vec<[DVec3; 3]> = (mesh.groups.iter())
        .filter_map(|g| g.covered.as_ref())
        .flat_map(|c| {
            c.triangles
                .iter()
                .map(|t| t.map(|v| c.positions[v as usize]))
        })
        .collect();
    let into_covered: Vec<(DVec3, Vec<f64>)> = covered
        .par_chunks(FLUX_CHUNK)
        .map(|chunk| {
            let mut total = (DVec3::ZERO, vec![0.0; sources.len()]);
            for corners in chunk {
                let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
                let Some(normal) = normal.try_normalize() else {
                    continue;
                };
                // Its corners lie on the outline, where a ray may slip out through the gap:
                // the triangle shrunk a hundredth toward its centroid is traced, and its flux
                // scaled back to the whole area.
                let c = (corners[0] + corners[1] + corners[2]) / 3.0;
                let inset = corners.map(|v| v + (c - v) * 0.01);
                let settle = |lo: DVec3, hi: DVec3, n: DVec3| {
                    occ.settle(&inset.map(|v| v + n * occ.epsilon), lo, hi)
                };
                groups.visit(c, &[normal], settle, |k, known| {
                    let (front, _) = sources[k].patch_flux(occ, &inset, normal, known);
                    let front = front / (0.99 * 0.99);
                    total.0 += sources[k].color() * front;
                    total.1[k] += front;
                });
            }
            total
        })
        .collect();
    for (back, per_source) in into_covered {
        out.back += back;
        for (total, x) in out.per_source.iter_mut().zip(per_source) {
            *total += x;
        }
    }
    out
}

/// Patches per chunk of [`into_patches`].
const FLUX_CHUNK: usize = 256;
