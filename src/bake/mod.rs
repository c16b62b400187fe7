//! The bake pipeline: a [`Scene`] and validated [`Settings`] in, a [`BakeResult`] out.
//!
//! [`solve`] runs the stages up to the solved scene, [`bake`] adds the probes and the output;
//! each stage is a function of the previous stages' data, in its own module:
//! 1. `meshing` — contacts found (what covers what: `contacts`), surfaces cut along them and
//!    refined into patches (adaptively by default), vertices as receivers, what each patch
//!    emits, the direct sources on that mesh;
//! 2. `direct` — direct light exact at every vertex, and as flux into every patch;
//! 3. `links` — every vertex's gather row over the patch hierarchy;
//! 4. `solve` — the balanced patch operator and GMRES: reflected exitance of every patch;
//! 5. `energy` — emitted = absorbed + escaped, each measured;
//! 6. `probes` — cubic illuminance at every probe, read from the [`Solution`];
//! 7. `output` — vertex values and display colours shaped for the exporter;
//! 8. `lightmap` (with `--lightmaps`) — the surfaces laid out in atlases, every texel lit.
//!
//! Stage times and ray counts go to the run summary ([`RunSummary`]). Invariant: nothing here
//! depends on the thread count (parallel maps over fixed chunks, ordered reductions), so the same
//! input and settings give the same bytes.

pub mod budget;
mod direct;
mod display;
mod energy;
mod groups;
mod links;
mod meshing;
mod openings;
mod output;
pub mod probes;
mod run;
pub mod shard;
mod solve;

use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::result::BakeResult;
use crate::scene::{Scene, Surface};
use crate::settings::{LightmapSettings, Settings};
use crate::solution::{PlaneLight, Solution, solved};
use crate::summary::{Counts, EnergyBalance, RunSummary, SettingsRecord, Units};
use crate::visibility::{Occluder, OccluderOptions};
pub use direct::PatchFlux;
use glam::DVec3;
pub use groups::bake_groups;
pub use meshing::Saved as SavedMesh;
use run::{RayStage, Run, Stage};

/// A solved scene, and the run summary of the stages so far.
pub struct Solved<'a> {
    pub solution: Solution<'a>,
    /// Everything but the exposure (set when the output is shaped) and the timings.
    pub summary: RunSummary,
    run: Run,
}

/// Run the whole bake.
pub fn bake(scene: &Scene, settings: &Settings, progress: &dyn Progress) -> Result<BakeResult> {
    let solved = solve(scene, settings, progress)?;
    Ok(finish(scene, settings, solved, progress))
}

/// The stages after the solve: probes, the output's vertex values, lightmaps.
fn finish(
    scene: &Scene,
    settings: &Settings,
    solved: Solved,
    progress: &dyn Progress,
) -> BakeResult {
    let Solved {
        solution,
        mut summary,
        mut run,
    } = solved;
    let wanted = crate::probes::place::Wanted {
        grid: settings.probe_grid,
        explicit: &settings.extra_probes,
        working_plane: settings.working_plane,
    };
    let probes = run.time(Stage::Probes, || {
        let places = crate::probes::place::all(scene, wanted, solution.occluder(), progress);
        probes::measure(&solution, &places, progress)
    });
    let (scale, exposure) = run.time(Stage::Output, || {
        display::exposure(settings.exposure, &solution)
    });
    summary.exposure = exposure;
    let mut surfaces = run.time(Stage::Output, || output::surfaces(&solution, scale));
    let lightmaps = settings.lightmaps.map(|l| {
        run.time(Stage::Lightmaps, || {
            let options = crate::lightmap::Options {
                texel_size: texel_size(&l, settings.quality, summary.patch_size, &solution),
                max_size: l.max_size,
                tolerance: l.tolerance.unwrap_or(settings.quality.lightmap_tolerance()),
            };
            let color = |e: DVec3, m: DVec3, material: usize| {
                display::color(e, m, &scene.materials[material], scale)
            };
            let (maps, record) =
                crate::lightmap::bake(&solution, &mut surfaces, &options, &color, progress);
            summary.lightmaps = Some(record);
            maps
        })
    });
    if settings.record_timings {
        summary.timings_seconds = Some(run.seconds);
    }
    let openings = run.time(Stage::Output, || openings::meshes(scene, scale));
    BakeResult {
        surfaces,
        probes,
        lightmaps,
        openings,
        summary,
        timings: run.seconds,
    }
}

/// Mesh, light and solve the scene (everything but probes and the output).
pub fn solve<'a>(
    scene: &'a Scene,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Solved<'a>> {
    let mut m = mesh(scene, settings, progress)?;
    let direct = light(scene, &mut m, progress);
    let params = settings.params();
    progress.stage("form factors", m.meshed.mesh.receivers.len() as u64);
    let inputs = links::Inputs {
        scene,
        settings,
        tau: params.tau,
        meshed: &m.meshed,
        occluder: &m.occluder,
        vertex_direct: &direct.vertex,
        light_flux: &direct.flux.per_patch,
    };
    let rows = m.run.time(Stage::Links, || links::stage(&inputs));
    m.run.rays(RayStage::Links, &m.occluder);
    complete(scene, settings, m, direct, rows, progress)
}

/// The scene meshed: patches, receivers and light sources on them, the occluder, the run so far.
pub struct Meshing<'a> {
    meshed: meshing::Meshed<'a>,
    occluder: Occluder,
    run: Run,
    h: f64,
}

impl Meshing<'_> {
    pub(crate) fn mesh(&self) -> &crate::patches::PatchMesh {
        &self.meshed.mesh
    }
}

/// Direct light: exact at every vertex (lx, RGB), and as flux into every patch.
pub struct Direct {
    pub vertex: Vec<DVec3>,
    pub flux: direct::PatchFlux,
}

/// Validate the settings, check the budget, mesh the scene (stage 1).
pub(crate) fn mesh<'a>(
    scene: &'a Scene,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Meshing<'a>> {
    let tau_direct = settings.params().tau_direct;
    let m = meshing_by(scene, settings, progress, |occluder, h| {
        meshing::stage(scene, settings, h, occluder, tau_direct)
    })?;
    if m.meshed.lights.is_dark() {
        progress.warn("the scene has no light source (no emitting material, light or luminaire): everything bakes to 0 lx");
    }
    Ok(m)
}

/// [`mesh`]'s result from a mesh it made before for `scene` and `settings` (the caller's to
/// check: `shard` compares fingerprints), counting the `rays` that meshing traced then.
pub(crate) fn restore<'a>(
    scene: &'a Scene,
    settings: &Settings,
    saved: SavedMesh,
    rays: u64,
    progress: &dyn Progress,
) -> Result<Meshing<'a>> {
    let tau_direct = settings.params().tau_direct;
    meshing_by(scene, settings, progress, |occluder, _| {
        occluder.credit_rays(rays);
        meshing::restore(scene, settings, saved, tau_direct)
    })
}

/// Stage 1 with the patch mesh from `make` (given the occluder and the patch size, m).
fn meshing_by<'a>(
    scene: &'a Scene,
    settings: &Settings,
    progress: &dyn Progress,
    make: impl FnOnce(&Occluder, f64) -> meshing::Meshed<'a>,
) -> Result<Meshing<'a>> {
    let h = patch_size_checked(scene, settings, progress)?;
    let mut run = Run::default();
    progress.stage("meshing", 0);
    let occluder = run.time(Stage::Mesh, || occluder(scene, settings));
    let meshed = run.time(Stage::Mesh, || make(&occluder, h));
    run.rays(RayStage::Meshing, &occluder);
    Ok(Meshing {
        meshed,
        occluder,
        run,
        h,
    })
}

/// Validate the settings and check the budget (warning of what it finds): the patch size (m).
fn patch_size_checked(scene: &Scene, settings: &Settings, progress: &dyn Progress) -> Result<f64> {
    settings.validate()?;
    let params = settings.params();
    let areas: Vec<f64> = scene.surfaces.iter().map(Surface::area).collect();
    let budget = budget::check(scene, settings, patch_size(scene, &areas, settings)?)?;
    if let Some(w) = &budget.warning {
        progress.warn(w);
    }
    let h = budget.patch_size;
    if settings.patch_size.is_none()
        && let Some(w) = budget::dominant_surface(scene, &areas, params.target_patches, h)
    {
        progress.warn(&w);
    }
    Ok(h)
}

fn occluder(scene: &Scene, settings: &Settings) -> Occluder {
    let options = OccluderOptions {
        always_trace: settings.always_trace,
    };
    Occluder::build(scene, options)
}

/// Direct light at the vertices and into the patches (stage 2).
pub(crate) fn light(scene: &Scene, m: &mut Meshing, progress: &dyn Progress) -> Direct {
    let n = m.meshed.mesh.receivers.len() as u64;
    progress.stage("direct light", n);
    let (meshed, occluder) = (&m.meshed, &m.occluder);
    let vertex = m.run.time(Stage::Direct, || {
        direct::at_vertices(&meshed.lights, &meshed.mesh, occluder, progress)
    });
    m.run.rays(RayStage::DirectAtReceivers, occluder);
    let flux = light_patches(scene, m);
    Direct { vertex, flux }
}

/// The direct light into the patches alone (stage 2 of a distributed bake's plan: its tasks
/// light their own vertices).
pub(crate) fn light_patches(scene: &Scene, m: &mut Meshing) -> direct::PatchFlux {
    let (meshed, occluder) = (&m.meshed, &m.occluder);
    let flux = m.run.time(Stage::Direct, || {
        direct::into_patches(scene, &meshed.lights, &meshed.mesh, occluder)
    });
    m.run.rays(RayStage::DirectIntoPatches, occluder);
    flux
}

/// The stages after the links: solve, energy balance, summary (stages 4 and 5).
fn complete<'a>(
    scene: &'a Scene,
    settings: &Settings,
    m: Meshing<'a>,
    direct: Direct,
    rows: links::Rows,
    progress: &dyn Progress,
) -> Result<Solved<'a>> {
    let params = settings.params();
    let Meshing {
        meshed,
        occluder,
        mut run,
        h,
    } = m;
    let Direct {
        vertex: vertex_direct,
        mut flux,
    } = direct;
    progress.stage("solving", 0);
    let light_flux = std::mem::take(&mut flux.per_patch);
    let open = run.time(Stage::Links, || {
        solve::open_fractions(&meshed, &occluder, &rows, &light_flux)
    });
    run.rays(RayStage::Links, &occluder);
    let radiosity = run.time(Stage::Solve, || {
        solve::stage(&meshed, rows, light_flux, &open, params.tolerance)
    });
    if !radiosity.stats.relative_residual.is_finite() {
        return Err(crate::Error::Bake(format!(
            "the solve produced non-finite values (residual {}): an emitted amount or a \
             reflectance overflowed",
            radiosity.stats.relative_residual
        )));
    }
    if let Some(w) = solve::warning(&radiosity.stats, params.tolerance) {
        progress.warn(&w);
    }
    let energy = run.time(Stage::Energy, || {
        energy::balance(&meshed, &occluder, &flux, &radiosity)
    });
    run.rays(RayStage::Energy, &occluder);
    if let Some(w) = energy::warning(&energy) {
        progress.warn(&w);
    }

    let stages = Stages {
        meshed: &meshed,
        occluder: &occluder,
        flux: &flux,
        radiosity: &radiosity,
        run: &run,
    };
    let summary = summary_of(scene, settings, h, stages, energy);
    let solution = solution_of(
        scene,
        meshed,
        occluder,
        vertex_direct,
        radiosity,
        params.tau,
    );
    Ok(Solved {
        solution,
        summary,
        run,
    })
}

/// What the stages up to the energy report made, as the run summary reads it.
struct Stages<'a> {
    meshed: &'a meshing::Meshed<'a>,
    occluder: &'a Occluder,
    flux: &'a direct::PatchFlux,
    radiosity: &'a solve::Radiosity,
    run: &'a Run,
}

/// The run summary of the stages up to the energy report (the exposure and the timings are
/// added when the output is shaped).
fn summary_of(
    scene: &Scene,
    settings: &Settings,
    h: f64,
    stages: Stages,
    energy: EnergyBalance,
) -> RunSummary {
    let Stages {
        meshed,
        occluder,
        flux,
        radiosity,
        run,
    } = stages;
    RunSummary {
        tool: format!("luxbake {}", env!("CARGO_PKG_VERSION")),
        settings: SettingsRecord::from(settings),
        quality: settings.params(),
        patch_size: h,
        counts: Counts {
            surfaces: scene.surfaces.len(),
            patches: meshed.mesh.patches.len(),
            receivers: meshed.mesh.receivers.len(),
            links: radiosity.counts.links,
            cluster_links: radiosity.counts.cluster_links,
            closed_receivers: radiosity.counts.closed_receivers,
            gathered_receivers: radiosity.counts.gathered_receivers,
            rays: occluder.rays_traced(),
            rays_by_stage: run.rays,
            convex_empty_scene: occluder.convex_empty,
        },
        adaptive_meshing: meshed.adaptive.clone(),
        contacts: meshed.contacts,
        solver: radiosity.stats,
        balancing: radiosity.balance,
        energy,
        sources: (meshed.lights.sources.iter())
            .zip(flux.per_source.iter().zip(&flux.closure))
            .map(|(s, (received, f))| energy::source_record(s, scene, *received, *f))
            .collect(),
        exposure: Default::default(),
        units: Units::default(),
        lightmaps: None,
        timings_seconds: None,
    }
}

/// The solved scene, from what the stages made.
fn solution_of<'a>(
    scene: &'a Scene,
    meshed: meshing::Meshed<'a>,
    occluder: Occluder,
    vertex_direct: Vec<DVec3>,
    radiosity: solve::Radiosity,
    tau: f64,
) -> Solution<'a> {
    let first_reflected_flux = radiosity.first_reflected_flux(&meshed);
    let vertices = (vertex_direct.into_iter())
        .zip(radiosity.indirect_vertex)
        .map(|(direct, indirect)| PlaneLight { direct, indirect })
        .collect();
    Solution::new(solved::Parts {
        scene,
        mesh: meshed.mesh,
        occluder,
        lights: meshed.lights,
        reflected: solved::Reflected {
            tree: radiosity.tree,
            exitance: radiosity.reflected,
            dark: radiosity.dark,
            tau,
        },
        emitted: meshed.emitted,
        vertices,
        first_reflected_flux,
    })
}

/// The lightmap texel edge (m): asked for, or a quarter of the patch size (so the quality sets
/// it: about four texels per patch edge), at most the quality's edge and at least what keeps
/// the texel count under the quality's cap.
fn texel_size(l: &LightmapSettings, q: crate::settings::Quality, h: f64, s: &Solution) -> f64 {
    if let Some(t) = l.texel_size {
        return t;
    }
    let (t, cap) = q.lightmap_texel();
    let mesh = s.mesh();
    let area: f64 = (mesh.groups.iter()).map(|g| g.area).sum::<f64>();
    (h / 4.0).min(t).max((area / cap).sqrt())
}

/// The patch size: the settings' or, from the quality's patch count, the longest edge of the
/// uniform mesh (m).
fn patch_size(scene: &Scene, areas: &[f64], settings: &Settings) -> Result<f64> {
    let total_area: f64 = areas.iter().sum();
    if total_area.is_nan() || total_area <= 0.0 {
        return Err(Error::input(
            &scene.source_file,
            "",
            "the scene has no surface with area (nothing to bake)",
        ));
    }
    Ok(settings
        .patch_size
        .unwrap_or_else(|| default_patch_size(total_area, settings.params().target_patches)))
}

/// The patch size (m) that meshes `area` m² into about `target_patches` patches: uniform
/// subdivision of a triangle whose longest edge is split into segments of h gives patches of area
/// ≈ h²/4, hence the factor 2.
fn default_patch_size(area: f64, target_patches: f64) -> f64 {
    2.0 * (area / target_patches).sqrt()
}
