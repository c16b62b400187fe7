//! The bake pipeline: a [`Scene`] and validated [`Settings`] in, a [`BakeResult`] out.
//!
//! Stages (each a function of the previous stage's data):
//! 1. `patches::build` — surfaces refined into patches, receivers at their vertices;
//! 2. `visibility::Occluder::build` — the BVH, once;
//! 3. patch trees (all patches; emitting patches);
//! 4. direct light — exact at receivers (`receivers::direct_at_receivers`), as flux into patches;
//! 5. `transport::links` — every receiver's view of the patch hierarchy;
//! 6. `solve::gmres` — reflected exitance B of every patch, to a residual tolerance;
//! 7. gather at receivers — E = E_direct + Σ links·B; luminance, display colours, energy report.
//!
//! Invariant: nothing here depends on the thread count (parallel maps over fixed chunks, ordered
//! reductions), so the same input and settings give the same bytes.

mod display;
mod energy;
mod meshing;
mod receivers;
mod solution;

use crate::direct::{
    bounds::ProfileBounds, emitters, enclosed::Solids, groups::Groups, sources::DirectSource,
};
use crate::error::{Error, Result};
use crate::patches::PatchMesh;
use crate::progress::Progress;
use crate::result::{BakeResult, BakedSurface};
use crate::scene::{Scene, luma};
use crate::settings::Settings;
use crate::solve;
use crate::transport::{
    field::NodeField, gather::Gatherer, links::ReceiverLinks, operator::PatchOperator,
    tree::PatchTree,
};
use crate::visibility::{Occluder, OccluderOptions};
use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

pub use energy::EnergyBalance;

/// Everything the solve produced, before it is shaped for output. Later stages (probes,
/// lightmaps) read light from it through its methods (`solution.rs`), which use the same
/// [`Gatherer`] interface as the vertices.
pub struct Solution<'a> {
    pub scene: &'a Scene,
    pub settings: &'a Settings,
    /// Lights, luminaires and profiled emitting surfaces.
    pub sources: Vec<DirectSource<'a>>,
    /// The luminaires among `sources` grouped for shared visibility.
    pub groups: Groups,
    pub mesh: PatchMesh,
    pub occluder: Occluder,
    pub tree: PatchTree,
    pub emitter_tree: PatchTree,
    /// Lambertian emitted exitance per patch (lm/m², RGB): what enters the patch field.
    pub exitance: Vec<DVec3>,
    /// All emitted exitance per patch, profiled emitters included (for the output's luminance).
    pub emitted: Vec<DVec3>,
    /// Reflected exitance per patch (lm/m², RGB).
    pub reflected: Vec<DVec3>,
    /// Illuminance at each receiver: direct and from inter-reflection (lx, RGB).
    pub direct: Vec<DVec3>,
    pub indirect: Vec<DVec3>,
    /// The patch fields summarised on the trees, for gathering at new points: emitted exitance,
    /// and reflected exitance built when first needed (a bake without probes never reads it,
    /// and on the 10⁶-triangle floor its arrays come to about 480 MB, mostly every inner node's
    /// normal distribution).
    pub node_exitance: NodeField,
    pub(crate) node_reflected: std::sync::OnceLock<NodeField>,
    /// Per tree node, when some are: all its patches are black (`Gatherer::dark`).
    pub dark: Option<Vec<bool>>,
    /// Cuttle's first reflected flux (lm, photometric): Σ ρ × direct flux onto each patch.
    pub first_reflected_flux: f64,
    /// Closest-hit index over the patches (front faces) and the patch of each of its triangles,
    /// built when first needed.
    pub(crate) surface_index: std::sync::OnceLock<(Occluder, Vec<usize>)>,
}

/// A solved scene and what the summary says about the solve.
pub struct Solved<'a> {
    pub solution: Solution<'a>,
    /// counts, solver, balancing, energy, sources (merged into the output's summary).
    pub summary: serde_json::Value,
    pub timings: Vec<(String, f64)>,
    pub patch_size: f64,
}

/// Run the whole bake.
pub fn bake(scene: &Scene, settings: &Settings, progress: &dyn Progress) -> Result<BakeResult> {
    let solved = solve(scene, settings, progress)?;
    let mut timings = solved.timings.clone();
    let clock = Instant::now();
    let s = &solved.solution;
    let probe_list = crate::probes::gather::all(scene, settings, s, progress);
    let probes = crate::probes::evaluate::all(s, &probe_list, progress);
    let surfaces = output_surfaces(scene, s, settings);
    let exposure = display::exposure_note(settings, s, scene);
    timings.push(("output".into(), clock.elapsed().as_secs_f64()));
    let mut summary = serde_json::json!({
        "tool": format!("luxbake {}", env!("CARGO_PKG_VERSION")),
        "settings": settings,
        "quality": settings.params(),
        "patchSize": solved.patch_size,
    });
    for (k, v) in solved.summary.as_object().into_iter().flatten() {
        summary[k] = v.clone();
    }
    summary["exposure"] = exposure;
    summary["units"] = serde_json::json!({"illuminance": "lx", "luminance": "cd/m2", "flux": "lm", "length": "m", "up": "+Y"});
    if settings.record_timings {
        summary["timingsSeconds"] = timings_json(&timings);
    }
    Ok(BakeResult {
        surfaces,
        probes,
        summary,
        timings,
    })
}

/// Mesh, light and solve the scene (everything but shaping the output).
pub fn solve<'a>(
    scene: &'a Scene,
    settings: &'a Settings,
    progress: &dyn Progress,
) -> Result<Solved<'a>> {
    settings.validate()?;
    let mut timings = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |name: &str, timings: &mut Vec<(String, f64)>| {
        timings.push((name.to_string(), clock.elapsed().as_secs_f64()));
        clock = Instant::now();
    };
    let params = settings.params();
    let total_area: f64 = scene
        .surfaces
        .iter()
        .flat_map(|s| {
            s.triangles.iter().map(|t| {
                let [a, b, c] = t.map(|v| s.positions[v as usize]);
                (b - a).cross(c - a).length() / 2.0
            })
        })
        .sum();
    if total_area.is_nan() || total_area <= 0.0 {
        return Err(Error::input(
            &scene.source_file,
            "",
            "the scene has no surface with area (nothing to bake)",
        ));
    }
    // Patch size = longest patch edge. Uniform subdivision of a triangle whose longest edge is
    // split into segments of h gives patches of area ≈ h²/4, hence the factor 2.
    let h = settings
        .patch_size
        .unwrap_or(2.0 * (total_area / params.target_patches).sqrt());

    progress.stage("meshing", 0);
    let occluder = Occluder::build(
        scene,
        OccluderOptions {
            always_trace: settings.always_trace,
        },
    );
    // Each profile's intensity bounds, built once for meshing and the direct stage.
    let bounds = ProfileBounds::new(scene);
    let (mesh, adaptive) = meshing::mesh(scene, settings, h, &occluder, &bounds);
    // What every patch emits (for the output's luminance), and the part that is Lambertian and
    // travels through the patch field (profiled emitters are direct sources instead).
    let emitted = emitters::patch_exitance(scene, &mesh);
    let exitance = emitters::diffuse_part(scene, &mesh, &emitted);
    let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
    let emitting: Vec<u32> = (0..mesh.patches.len() as u32)
        .filter(|&p| exitance[p as usize] != DVec3::ZERO)
        .collect();
    let emitter_tree = PatchTree::build(&mesh, emitting);
    let sources = DirectSource::all(scene, &mesh, &emitted, &bounds);
    if sources.is_empty() && emitter_tree.is_empty() {
        progress.warn("the scene has no light source (no emitting material, light or luminaire): everything bakes to 0 lx");
    }
    lap("mesh", &mut timings);
    // Shadow rays traced by each stage (the counter runs across stages; read between them).
    let mut rays_by_stage = serde_json::Map::new();
    let mut rays_before = 0;
    let mut count_rays = |stage: &str, occluder: &Occluder| {
        let now = occluder.rays_traced();
        rays_by_stage.insert(stage.into(), serde_json::json!(now - rays_before));
        rays_before = now;
    };
    count_rays("meshing", &occluder);

    progress.stage("direct light", mesh.receivers.len() as u64);
    let groups = DirectSource::groups(&sources);
    let direct = receivers::direct_at_receivers(
        receivers::Lights {
            sources: &sources,
            groups: &groups,
        },
        &mesh,
        &occluder,
        &emitter_tree,
        &exitance,
        params.tau_direct,
        progress,
    );
    count_rays("directAtReceivers", &occluder);
    let solids = Solids::new(scene);
    let mut lights = light_patch_flux(&sources, &groups, &mesh, &occluder, &solids);
    count_rays("directIntoPatches", &occluder);
    lap("direct", &mut timings);

    progress.stage("form factors", mesh.receivers.len() as u64);
    let rho: Vec<DVec3> = mesh
        .patches
        .iter()
        .map(|p| scene.materials[mesh.groups[p.group as usize].material].reflectance)
        .collect();
    // Black patches reflect nothing and emit nothing into the patch field, so their exitance
    // stays zero and nobody gathers from nodes of them alone (only what they cover counts).
    let black = |p: usize| rho[p] == DVec3::ZERO && exitance[p] == DVec3::ZERO;
    let dark = match settings.gather_black {
        true => None,
        false => tree.nodes_where(black),
    };
    let gatherer = Gatherer {
        mesh: &mesh,
        tree: &tree,
        occluder: &occluder,
        tau: params.tau,
        dark: dark.as_deref(),
    };
    let mut links = match dark.as_ref().is_some_and(|d| d[0]) {
        // Black throughout: nothing is reflected, so there is nothing to gather.
        true => ReceiverLinks::none(mesh.receivers.len(), tree.nodes.len()),
        false => ReceiverLinks::build(&gatherer, &mesh.receivers),
    };
    lap("links", &mut timings);
    count_rays("links", &occluder);

    progress.stage("solving", 0);
    let areas: Vec<f64> = mesh.patches.iter().map(|p| p.area).collect();
    let mut operator = PatchOperator::new(&mesh, &tree, &links);
    let balance_stats = operator.balance(40, 1e-6, &|p| dark.is_some() && black(p));
    // Direct irradiance of each patch: punctual lights exactly (solid angle), emitting surfaces
    // through the balanced operator (so a closed room receives exactly what they emit).
    let from_emitters = if emitter_tree.is_empty() {
        vec![DVec3::ZERO; mesh.patches.len()]
    } else {
        operator.apply(&exitance)
    };
    let direct_patch: Vec<DVec3> = (0..mesh.patches.len())
        .map(|i| lights.per_patch[i] / areas[i] + from_emitters[i])
        .collect();
    // Not needed past here: two patch-sized vectors fewer while the solver runs.
    drop(from_emitters);
    lights.per_patch = Vec::new();
    let b: Vec<DVec3> = (0..mesh.patches.len())
        .map(|i| rho[i] * direct_patch[i])
        .collect();
    let apply = |x: &[DVec3], out: &mut [DVec3]| {
        operator.apply_into(x, out);
        out.par_iter_mut()
            .enumerate()
            .for_each(|(i, o)| *o = x[i] - rho[i] * *o);
    };
    let (reflected, stats) = solve::gmres(apply, &b, &areas, params.tolerance, 2_000, 40);
    let indirect_patch = operator.apply(&reflected);
    let indirect = operator.gather_receivers(&reflected);
    lap("solve", &mut timings);
    drop(operator);
    // The rows are done with (the largest thing a bake holds): keep what the report needs.
    let link_counts = serde_json::json!({
        "links": links.link_count(),
        "clusterLinks": links.far_links().filter(|l| l.is_cluster()).count(),
        "closedReceivers": links.closed.iter().filter(|c| **c).count(),
    });
    let (back, closed) = (
        std::mem::take(&mut links.back),
        std::mem::take(&mut links.closed),
    );
    drop(links);

    let node_exitance = NodeField::new(&emitter_tree, &mesh, &exitance);
    let first_reflected_flux: f64 = (0..mesh.patches.len())
        .map(|i| luma(rho[i] * direct_patch[i]) * areas[i])
        .sum();
    let solution = Solution {
        scene,
        settings,
        sources,
        groups,
        mesh,
        occluder,
        tree,
        emitter_tree,
        exitance,
        emitted,
        reflected,
        direct,
        indirect,
        node_exitance,
        node_reflected: Default::default(),
        dark,
        first_reflected_flux,
        surface_index: Default::default(),
    };
    let balance = energy::balance(energy::Inputs {
        solution: &solution,
        back: &back,
        closed: &closed,
        direct_patch: &direct_patch,
        light_back: lights.back,
        sources: &solution.sources,
        source_received: &lights.per_source,
        indirect_patch: &indirect_patch,
        rho: &rho,
    });
    count_rays("energy", &solution.occluder); // escape rays of the energy report
    let summary = serde_json::json!({
        "counts": {
            "surfaces": scene.surfaces.len(),
            "patches": solution.mesh.patches.len(),
            "receivers": solution.mesh.receivers.len(),
            "links": link_counts["links"],
            "clusterLinks": link_counts["clusterLinks"],
            "closedReceivers": link_counts["closedReceivers"],
            "rays": solution.occluder.rays_traced(),
            "raysByStage": rays_by_stage,
            "convexEmptyScene": solution.occluder.convex_empty,
        },
        "adaptiveMeshing": adaptive,
        "solver": stats,
        "balancing": balance_stats,
        "energy": balance,
        "sources": solution.sources
            .iter()
            .zip(&lights.per_source)
            .map(|(s, received)| s.report(scene, *received))
            .collect::<Vec<_>>(),
    });
    if !stats.converged {
        progress.warn(&format!(
            "the solver stopped at {} iterations with relative residual {:.2e} (tolerance {:.0e})",
            stats.iterations, stats.relative_residual, params.tolerance
        ));
    }
    Ok(Solved {
        solution,
        summary,
        timings,
        patch_size: h,
    })
}

/// Stage timings as a JSON object.
pub fn timings_json(timings: &[(String, f64)]) -> serde_json::Value {
    serde_json::Value::Object(
        timings
            .iter()
            .map(|(k, v)| (k.clone(), serde_json::json!(v)))
            .collect(),
    )
}

/// Direct flux of the lights and luminaires: into each patch's front (RGB), onto back faces
/// (RGB), and per source (lm, photometric, front and back).
struct LightFlux {
    per_patch: Vec<DVec3>,
    back: DVec3,
    per_source: Vec<f64>,
}

fn light_patch_flux(
    sources: &[DirectSource],
    groups: &Groups,
    mesh: &PatchMesh,
    occ: &Occluder,
    solids: &Solids,
) -> LightFlux {
    // Fixed chunks of patches, each summed into its own totals, the chunks' totals added in
    // order: deterministic whatever the thread count. (A row of every source for every patch,
    // kept until the end, was patches × sources × 16 bytes: 10 GB on the 10⁶-triangle floor,
    // the bake's peak memory.)
    let parts: Vec<LightFlux> = mesh
        .patches
        .par_chunks(FLUX_CHUNK)
        .map(|chunk| {
            let mut part = LightFlux {
                per_patch: Vec::with_capacity(chunk.len()),
                back: DVec3::ZERO,
                per_source: vec![0.0; sources.len()],
            };
            let mut row = vec![(0.0, 0.0); sources.len()];
            for p in chunk {
                let corners = p.corners(&mesh.receivers);
                // A group's rays leave from the centroid, pulled off the side that faces it (the
                // back of a single-sided patch absorbs what reaches it).
                let c = (corners[0] + corners[1] + corners[2]) / 3.0;
                let clear = |q: DVec3, n: DVec3| occ.clear(c, n, q, DVec3::ZERO);
                row.fill((0.0, 0.0));
                // Sources that can light only this patch's back, when that back is lit by its
                // twin instead (double-sided) or faces the inside of a closed solid they lie
                // outside of, send it nothing: no rays for them.
                let dark_back = match p.double_sided {
                    true => Some(None),
                    false => solids.of(mesh.groups[p.group as usize].surface).map(Some),
                };
                groups.visit(c, &[p.normal, -p.normal], clear, |k, known| {
                    if dark_back
                        .is_some_and(|solid| sources[k].behind_and_outside(c, p.normal, solid))
                    {
                        return;
                    }
                    let (front, back) = sources[k].patch_flux(occ, &corners, p.normal, known);
                    // A double-sided patch's back is its twin, which takes that light as front.
                    row[k] = (front, if p.double_sided { 0.0 } else { back });
                });
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
    let mut out = LightFlux {
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
    out
}

/// Patches per chunk of [`light_patch_flux`].
const FLUX_CHUNK: usize = 256;

/// Shape the solution for the exporter: one baked surface per patch group.
fn output_surfaces(scene: &Scene, s: &Solution, settings: &Settings) -> Vec<BakedSurface> {
    let scale = display::exposure_scale(settings, s, scene);
    s.mesh
        .groups
        .iter()
        .map(|g| {
            let material = &scene.materials[g.material];
            // Every patch of a group emits alike.
            let emitted = s
                .emitted
                .get(g.patches.start)
                .copied()
                .filter(|_| !g.patches.is_empty())
                .unwrap_or(DVec3::ZERO);
            let range = g.receivers.clone();
            let r0 = range.start as u32;
            let mut illuminance = Vec::with_capacity(range.len());
            let mut illuminance_direct = Vec::with_capacity(range.len());
            let mut luminance = Vec::with_capacity(range.len());
            let mut color = Vec::with_capacity(range.len());
            for r in range.clone() {
                let e = s.direct[r] + s.indirect[r];
                let exitance = emitted + material.reflectance * e;
                illuminance.push(luma(e) as f32);
                illuminance_direct.push(luma(s.direct[r]) as f32);
                luminance.push((luma(exitance) / std::f64::consts::PI) as f32);
                color.push(display::color(e, exitance, material, scale));
            }
            BakedSurface {
                surface: g.surface,
                side: g.side,
                positions: s.mesh.receivers[range.clone()]
                    .iter()
                    .map(|r| r.position)
                    .collect(),
                normals: s.mesh.receivers[range.clone()]
                    .iter()
                    .map(|r| r.normal)
                    .collect(),
                uv0: g.uv0.clone(),
                uv1: g.uv1.clone(),
                triangles: s.mesh.patches[g.patches.clone()]
                    .iter()
                    .map(|p| p.v.map(|v| v - r0))
                    .collect(),
                illuminance,
                illuminance_direct,
                luminance,
                color,
            }
        })
        .collect()
}
