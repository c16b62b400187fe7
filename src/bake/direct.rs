//! The direct stage: light from the scene's sources, exact at every vertex, and as flux into every
//! patch (what the radiosity solution then reflects).
//!
//! Input: the meshed scene, its [`DirectLight`] and the occluder. Output: direct illuminance at
//! each vertex (lx, RGB), and [`PatchFlux`]. Both are sums over fixed chunks in order:
//! deterministic whatever the thread count. Both go through the light's cut (`direct::cut`):
//! with a fraction f above 0, each vertex's light and each patch's front flux from the
//! luminaires are within f of their full sums.

use crate::direct::enclosed::Solids;
use crate::direct::sources::DirectSource;
use crate::direct::targets::IntoPatch;
use crate::patches::{Patch, PatchMesh};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::solution::{DirectLight, receivers};
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// Direct illuminance (lx, RGB) at every vertex of `mesh`: the vertices are receivers like any
/// other, read before the solve.
pub(crate) fn at_vertices(
    lights: &DirectLight,
    mesh: &PatchMesh,
    occ: &Occluder,
    progress: &dyn Progress,
) -> Vec<DVec3> {
    let vertices = receivers::Vertices(&mesh.receivers);
    receivers::map(&vertices, progress, |_, r| lights.at(mesh, occ, r)[0])
}

/// [`at_vertices`] at the vertices `subset` (indices into the mesh's receivers), in its order:
/// each value is the one `at_vertices` gives that vertex (a vertex's light depends on it alone),
/// so a distributed bake's tasks can each light their own.
pub(crate) fn at_some_vertices(
    lights: &DirectLight,
    mesh: &PatchMesh,
    occ: &Occluder,
    subset: &[u32],
    progress: &dyn Progress,
) -> Vec<DVec3> {
    let vertices = receivers::VertexSubset(&mesh.receivers, subset);
    receivers::map(&vertices, progress, |_, r| lights.at(mesh, occ, r)[0])
}

/// Direct flux of the lights and luminaires: into each patch's front (RGB), onto back faces
/// (RGB), and per source (lm, photometric, front and back, as integrated).
pub struct PatchFlux {
    pub per_patch: Vec<DVec3>,
    pub back: DVec3,
    pub per_source: Vec<f64>,
    /// Per source, the factor its share of `per_patch` and `back` was scaled by so that the
    /// patches receive exactly its flux ([`closure`]); 1 where none was applied.
    pub closure: Vec<f64>,
    /// Per source, the flux its escape rays found leaving the scene (lm; 0 for sources without
    /// an emitted flux of their own: `DirectSource::escaping_flux`). Traced once, here: the
    /// closure and the energy report read it.
    pub escaped: Vec<f64>,
}

/// Per source, the factor that makes the flux its patches received (`received`, lm) its whole
/// emitted flux, where that is what they must receive: a point-like source (light or
/// luminaire) none of whose escape rays leaves the scene (`DirectSource::escaping_flux`
/// exactly 0, every ray of its 8 192 meets a surface), so that every lumen it emits lands on
/// a patch, a back face or a covered part. Else 1 (directional lights, emitting surfaces,
/// sources in open scenes: their escape is an estimate, not a target).
///
/// Why: a patch's flux is integrated to a few per mille, but the errors do not cancel over a
/// room. A luminaire's opening is split into sub-sources as seen from each patch (finer for
/// near ones): the midpoint rule of a near patch is corrected, the far patches' small
/// corrections, which sum to as much with the opposite sign, are not (a 1.5 m linear in an empty
/// 4 × 3 × 5 m box: +2.1·10⁻³); a piece whose corners agree on visibility is taken as seen or
/// hidden whole (chair legs: ±5·10⁻³ per source on the open plan). The factor puts the lost or
/// surplus per mille back in proportion to what each patch received; the summary reports it
/// (`closure`) beside what was integrated (`reachedSurfacesLm`).
pub(crate) fn closure(sources: &[DirectSource], received: &[f64], escaped: &[f64]) -> Vec<f64> {
    (sources.iter().zip(received).zip(escaped))
        .map(
            |((source, &received), &escaped)| match source.emitted_flux() {
                Some(flux)
                    if received > 0.0
                        && !matches!(source, DirectSource::Profiled(_))
                        && escaped == 0.0 =>
                {
                    let f = flux / received;
                    // A factor far from 1 is no integration error: leave that light as it is.
                    if (f - 1.0).abs() <= MAX_CLOSURE {
                        f
                    } else {
                        1.0
                    }
                }
                _ => 1.0,
            },
        )
        .collect()
}

/// Largest correction [`closure`] applies (2 %): the integration errs by a few per mille.
const MAX_CLOSURE: f64 = 0.02;

/// Direct flux into every patch of `mesh` from the scene's lights and luminaires, onto back
/// faces and covered parts, and per source (see [`PatchFlux`]).
pub(crate) fn into_patches(
    scene: &Scene,
    lights: &DirectLight,
    mesh: &PatchMesh,
    occ: &Occluder,
) -> PatchFlux {
    let sources = &lights.sources;
    let flux = Flux {
        lights,
        mesh,
        occ,
        solids: Solids::new(scene),
    };
    // Fixed chunks of patches, each summed into its own totals, the chunks' totals added in
    // order: deterministic whatever the thread count. Each patch keeps only its nonzero fronts
    // per source (8 bytes each, not patches × sources), summed once the closure is known.
    let parts: Vec<Chunk> = mesh
        .patches
        .par_chunks(FLUX_CHUNK)
        .map(|chunk| flux.chunk(chunk))
        .collect();
    let mut per_source = vec![0.0; sources.len()];
    let mut back = vec![0.0; sources.len()];
    for part in &parts {
        for k in 0..sources.len() {
            per_source[k] += part.per_source[k];
            back[k] += part.back[k];
        }
    }
    // What reaches covered parts (through a gap a few millimetres wide, under a cover) is
    // absorbed there: counted with the backs, so the energy report sees it.
    let covered = covered_triangles(mesh);
    let into_covered: Vec<Vec<f64>> = covered
        .par_chunks(FLUX_CHUNK)
        .map(|chunk| flux.onto_covered(chunk))
        .collect();
    for part in into_covered {
        for k in 0..sources.len() {
            per_source[k] += part[k];
            back[k] += part[k];
        }
    }
    let escaped: Vec<f64> = (sources.iter())
        .map(|s| match s.emitted_flux() {
            Some(_) => s.escaping_flux(occ),
            None => 0.0,
        })
        .collect();
    let closure = closure(sources, &per_source, &escaped);
    let weight: Vec<DVec3> = (sources.iter().zip(&closure))
        .map(|(s, f)| s.color() * *f)
        .collect();
    PatchFlux {
        per_patch: fronts(parts, &weight, mesh.patches.len()),
        back: (back.iter().zip(&weight)).fold(DVec3::ZERO, |sum, (b, w)| sum + *w * *b),
        per_source,
        closure,
        escaped,
    }
}

/// What [`into_patches`] reads: the lights, the mesh, the occluder and the scene's closed
/// solids.
struct Flux<'a> {
    lights: &'a DirectLight<'a>,
    mesh: &'a PatchMesh,
    occ: &'a Occluder,
    solids: Solids,
}

impl Flux<'_> {
    /// The flux into a chunk of patches: each patch's nonzero fronts, and per source what
    /// landed on backs and in all.
    fn chunk(&self, chunk: &[Patch]) -> Chunk {
        let sources = &self.lights.sources;
        let mut part = Chunk {
            entries: Vec::new(),
            ends: Vec::with_capacity(chunk.len()),
            back: vec![0.0; sources.len()],
            per_source: vec![0.0; sources.len()],
        };
        let mut row = vec![(0.0, 0.0); sources.len()];
        for p in chunk {
            self.patch(p, &mut row);
            for (k, &(f, b)) in row.iter().enumerate() {
                if f != 0.0 {
                    part.entries.push((k as u32, f as f32));
                }
                part.back[k] += b;
                part.per_source[k] += f + b;
            }
            part.ends.push(part.entries.len() as u32);
        }
        part
    }

    /// The `(front, back)` flux (lm) per source into patch `p`, written to `row`: the light's
    /// cut run over the groups from the patch's centroid.
    fn patch(&self, p: &Patch, row: &mut [(f64, f64)]) {
        let (mesh, occ) = (self.mesh, self.occ);
        let (sources, groups) = (&self.lights.sources, &self.lights.groups);
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
            false => (self.solids)
                .of(mesh.groups[p.group as usize].surface)
                .map(Some),
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
            row,
        };
        let normals = [p.normal, -p.normal];
        self.lights
            .cut
            .run(sources, groups, c, &normals, settle, &mut into);
    }

    /// The flux (lm) per source onto a chunk of covered triangles (given by their corners).
    fn onto_covered(&self, chunk: &[[DVec3; 3]]) -> Vec<f64> {
        let occ = self.occ;
        let (sources, groups) = (&self.lights.sources, &self.lights.groups);
        let mut total = vec![0.0; sources.len()];
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
                total[k] += front / (0.99 * 0.99);
            });
        }
        total
    }
}

/// The corners of every covered triangle of the mesh, group by group.
fn covered_triangles(mesh: &PatchMesh) -> Vec<[DVec3; 3]> {
    (mesh.groups.iter())
        .filter_map(|g| g.covered.as_ref())
        .flat_map(|c| {
            c.triangles
                .iter()
                .map(|t| t.map(|v| c.positions[v as usize]))
        })
        .collect()
}

/// Each patch's front flux (RGB): its nonzero fronts per source weighted by the sources'
/// colours and closures, the chunks in order.
fn fronts(parts: Vec<Chunk>, weight: &[DVec3], patches: usize) -> Vec<DVec3> {
    let mut per_patch = Vec::with_capacity(patches);
    for part in parts {
        let mut start = 0;
        for end in part.ends {
            let entries = &part.entries[start..end as usize];
            per_patch.push(entries.iter().fold(DVec3::ZERO, |front, &(k, f)| {
                front + weight[k as usize] * f as f64
            }));
            start = end as usize;
        }
    }
    per_patch
}

/// A chunk of [`into_patches`]: each patch's nonzero fronts per source (`entries`, f32 to halve
/// the memory, the patch's ending at `ends[i]`), and per source what landed on backs and in all.
struct Chunk {
    entries: Vec<(u32, f32)>,
    ends: Vec<u32>,
    back: Vec<f64>,
    per_source: Vec<f64>,
}

/// Patches per chunk of [`into_patches`].
const FLUX_CHUNK: usize = 256;
