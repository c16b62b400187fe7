//! One mesh lit by several groups of sources, one group at a time: the responses `bake fit`
//! combines.
//!
//! Input: the scene whose light sets the mesh (`mesh_scene`), and one scene per group with the
//! same surfaces and materials, in which only that group's sources emit. Output: one
//! [`BakeResult`] per group. Meshing (contacts, adaptive refinement), the vertices' gather rows
//! and the balanced transport operator are made once, from `mesh_scene`; each group costs its
//! direct light and one solve on that operator (one right-hand side each). Invariant: light is
//! linear in the sources, and every group shares the mesh and the operator, so a bake on this
//! mesh of the scene whose group `g` is scaled by `x_g` gives Σ x_g × (group g's values), to the
//! solver's tolerance.

use super::run::{RayStage, Run, Stage};
use super::{Solved, budget, direct, energy, finish, links, meshing, patch_size, solution_of};
use super::{Stages, solve, summary_of};
use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::result::BakeResult;
use crate::scene::{Scene, Surface};
use crate::settings::Settings;
use crate::visibility::{Occluder, OccluderOptions};
use glam::DVec3;

/// Bake `groups` (each a scene lit by one group of sources) on the mesh of `mesh_scene`.
pub fn bake_groups(
    mesh_scene: &Scene,
    groups: &[Scene],
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Vec<BakeResult>> {
    settings.validate()?;
    if let Some(g) = groups.iter().find(|g| !same_surfaces(mesh_scene, g)) {
        return Err(Error::Bake(format!(
            "{}: a group's scene must have the surfaces of the scene that sets the mesh",
            g.source_file.display()
        )));
    }
    let params = settings.params();
    let areas: Vec<f64> = mesh_scene.surfaces.iter().map(Surface::area).collect();
    let h = budget::check(
        mesh_scene,
        settings,
        patch_size(mesh_scene, &areas, settings)?,
    )?
    .patch_size;
    let options = OccluderOptions {
        always_trace: settings.always_trace,
    };
    let mut run = Run::default();
    progress.stage("meshing", 0);
    let occluder = run.time(Stage::Mesh, || Occluder::build(mesh_scene, options));
    let base = run.time(Stage::Mesh, || {
        meshing::stage(mesh_scene, settings, h, &occluder, params.tau_direct)
    });
    let n = base.mesh.receivers.len() as u64;
    let mut lit = Vec::with_capacity(groups.len());
    for scene in groups {
        progress.stage("direct light", n);
        let meshed = meshing::relight(
            &base,
            scene,
            params.tau_direct,
            meshing::cut_settings(settings),
        );
        let vertex_direct = run.time(Stage::Direct, || {
            direct::at_vertices(&meshed.lights, &meshed.mesh, &occluder, progress)
        });
        let mut flux = run.time(Stage::Direct, || {
            direct::into_patches(scene, &meshed.lights, &meshed.mesh, &occluder)
        });
        let light_flux = std::mem::take(&mut flux.per_patch);
        lit.push((meshed, vertex_direct, flux, light_flux));
    }
    run.rays(RayStage::DirectAtReceivers, &occluder);
    // Light is linear in the sources: the groups' direct light summed is the whole scene's, what
    // the shared gathers' estimate reads (the same rows as a plain bake of the scene).
    progress.stage("form factors", n);
    let rows = run.time(Stage::Links, || {
        let direct = sum(lit.iter().map(|l| &l.1[..]), n as usize);
        let flux = sum(lit.iter().map(|l| &l.3[..]), base.mesh.patches.len());
        links::stage(&links::Inputs {
            scene: mesh_scene,
            settings,
            tau: params.tau,
            meshed: &base,
            occluder: &occluder,
            vertex_direct: &direct,
            light_flux: &flux,
        })
    });
    // The open patches' escape, for the balancing, with every group's light (as the rows).
    let open = run.time(Stage::Links, || {
        let flux = sum(lit.iter().map(|l| &l.3[..]), base.mesh.patches.len());
        solve::open_fractions(&base, &occluder, &rows, &flux)
    });
    run.rays(RayStage::Links, &occluder);

    progress.stage("solving", 0);
    let rhs = (lit.iter_mut())
        .map(|(m, _, _, f)| (&*m, std::mem::take(f)))
        .collect();
    let solved = run.time(Stage::Solve, || {
        solve::stage_many(&base, rows, rhs, &open, params.tolerance)
    });
    drop(base);

    let mut out = Vec::with_capacity(groups.len());
    for ((scene, (meshed, vertex_direct, flux, _)), radiosity) in groups.iter().zip(lit).zip(solved)
    {
        if let Some(w) = solve::warning(&radiosity.stats, params.tolerance) {
            progress.warn(&w);
        }
        let energy = energy::balance(&meshed, &occluder, &flux, &radiosity);
        let stages = Stages {
            meshed: &meshed,
            occluder: &occluder,
            flux: &flux,
            radiosity: &radiosity,
            run: &run,
        };
        let summary = summary_of(scene, settings, h, stages, energy);
        // Each solution owns its occluder: the same BVH, built again.
        let own = Occluder::build(mesh_scene, options);
        let solution = solution_of(scene, meshed, own, vertex_direct, radiosity, params.tau);
        let solved = Solved {
            solution,
            summary,
            run: run.clone(),
        };
        out.push(finish(scene, settings, solved, progress));
    }
    Ok(out)
}

/// The element-wise sum of `parts`, each of length `len` (zeros when there are none).
fn sum<'a>(parts: impl Iterator<Item = &'a [DVec3]>, len: usize) -> Vec<DVec3> {
    let mut total = vec![DVec3::ZERO; len];
    for part in parts {
        total.iter_mut().zip(part).for_each(|(t, x)| *t += *x);
    }
    total
}

/// `a` and `b` have the same surfaces (positions, triangles, materials).
fn same_surfaces(a: &Scene, b: &Scene) -> bool {
    a.surfaces.len() == b.surfaces.len()
        && (a.surfaces.iter().zip(&b.surfaces)).all(|(s, t)| {
            s.material == t.material && s.positions == t.positions && s.triangles == t.triangles
        })
}
