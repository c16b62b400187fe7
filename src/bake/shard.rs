//! A bake split across processes or machines: the stages that grow with the receivers — the
//! direct light at each and its gather over the patch hierarchy, most of a large scene's time —
//! run as independent tasks.
//!
//! 1. [`plan`]: mesh the scene and light its patches; out comes a [`State`]: the mesh and the
//!    direct flux into every patch (what every task's estimates read), fingerprints of the scene
//!    and the mesh, and the task list (contiguous ranges of groups, so no task shares a gather
//!    with another).
//! 2. [`gather`]: one task, anywhere: the same scene file (its fingerprint must match the
//!    state's), the mesh from the state (meshing runs once, in the plan); it lights its
//!    receivers and gathers their rows ([`TaskResult`]).
//! 3. [`merge`]: the mesh and the patches' light from the state, the receivers' light and rows
//!    from every task; it finishes the bake as [`super::bake`] does.
//!
//! Invariant: the merged [`BakeResult`] equals the single-process bake's, whatever the task
//! count, the order the tasks ran in and each process's thread count (rows are numbered
//! as one process numbers them, `transport::sharing::assemble`; ray counts are summed).

use super::run::{RayStage, Stage};
use super::{Direct, PatchFlux, SavedMesh, complete, direct, finish, light_patches, links};
use super::{mesh, restore};
use crate::error::{Error, Result};
use crate::patches::PatchMesh;
use crate::progress::Progress;
use crate::result::BakeResult;
use crate::scene::Scene;
use crate::settings::Settings;
use crate::summary::SettingsRecord;
use crate::transport::sharing::Part;
use glam::DVec3;

/// What [`plan`] hands the tasks and the merge.
pub struct State {
    /// The settings record (JSON): tasks and merge must run with the same settings.
    pub settings: String,
    /// [`scene_fingerprint`] of the scene planned.
    pub scene: u64,
    /// [`fingerprint`] of the mesh.
    pub fingerprint: u64,
    pub mesh: SavedMesh,
    pub flux: PatchFlux,
    /// Rays traced: meshing, the direct light into patches.
    pub rays: [u64; 2],
    /// Per task, its range of groups `[start, end)`.
    pub tasks: Vec<(u32, u32)>,
}

/// One task's rows.
pub struct TaskResult {
    pub task: u32,
    pub fingerprint: u64,
    /// Rays its gathers traced.
    pub rays: u64,
    /// Direct illuminance at its receivers (lx, RGB; `part.receivers`' order), and the rays
    /// that took.
    pub direct: Vec<DVec3>,
    pub direct_rays: u64,
    pub part: Part,
}

/// Mesh the scene and light its patches; the receivers split into `tasks` tasks (at most one
/// per group) of about equal receiver counts.
pub fn plan(
    scene: &Scene,
    settings: &Settings,
    tasks: usize,
    progress: &dyn Progress,
) -> Result<State> {
    let mut m = mesh(scene, settings, progress)?;
    progress.stage("direct light into patches", 0);
    let flux = light_patches(scene, &mut m);
    let rays = [m.run.rays.meshing, m.run.rays.direct_into_patches];
    // The mesh moves into the state: no copy of it.
    let mesh = m.meshed.into_saved();
    Ok(State {
        settings: settings_json(settings),
        scene: scene_fingerprint(scene),
        fingerprint: fingerprint(&mesh.mesh),
        tasks: split(&mesh.mesh, tasks.max(1)),
        mesh,
        flux,
        rays,
    })
}

/// Task `task` of `state`: its receivers' direct light and rows.
pub fn gather(
    scene: &Scene,
    settings: &Settings,
    state: State,
    task: usize,
    progress: &dyn Progress,
) -> Result<TaskResult> {
    let &(start, end) = state.tasks.get(task).ok_or_else(|| {
        Error::Settings(format!(
            "task {task} is not in the plan (it has {} tasks: 0 to {})",
            state.tasks.len(),
            state.tasks.len().saturating_sub(1)
        ))
    })?;
    check_settings(settings, &state)?;
    check_scene(scene, &state)?;
    let m = restore(scene, settings, state.mesh, 0, progress)?;
    let receivers = &m.mesh().receivers;
    let subset: Vec<u32> = (0..receivers.len() as u32)
        .filter(|&r| (start..end).contains(&receivers[r as usize].group))
        .collect();
    progress.stage("direct light", subset.len() as u64);
    let before = m.occluder.rays_traced();
    let (meshed, occ) = (&m.meshed, &m.occluder);
    let direct = direct::at_some_vertices(&meshed.lights, &meshed.mesh, occ, &subset, progress);
    let direct_rays = occ.rays_traced() - before;
    // The gathers' estimates read the direct light of this task's receivers only (nothing is
    // shared across groups): the others' stay zero.
    let mut vertex_direct = vec![DVec3::ZERO; receivers.len()];
    for (&r, &e) in subset.iter().zip(&direct) {
        vertex_direct[r as usize] = e;
    }
    progress.stage("form factors", subset.len() as u64);
    let before = occ.rays_traced();
    let inputs = links::Inputs {
        scene,
        settings,
        tau: settings.params().tau,
        meshed,
        occluder: occ,
        vertex_direct: &vertex_direct,
        light_flux: &state.flux.per_patch,
    };
    let (part, marking) = links::part(&inputs, &subset);
    Ok(TaskResult {
        task: task as u32,
        fingerprint: state.fingerprint,
        rays: occ.rays_traced() - before - marking,
        direct,
        direct_rays,
        part,
    })
}

/// The bake, from `state` and every task's result (any order).
pub fn merge(
    scene: &Scene,
    settings: &Settings,
    state: State,
    mut results: Vec<TaskResult>,
    progress: &dyn Progress,
) -> Result<BakeResult> {
    check_settings(settings, &state)?;
    check_scene(scene, &state)?;
    results.sort_by_key(|r| r.task);
    let ids: Vec<u32> = results.iter().map(|r| r.task).collect();
    if ids != (0..state.tasks.len() as u32).collect::<Vec<_>>() {
        return Err(Error::Settings(format!(
            "the merge needs the results of tasks 0 to {} once each, got tasks {ids:?}",
            state.tasks.len().saturating_sub(1)
        )));
    }
    if let Some(r) = results.iter().find(|r| r.fingerprint != state.fingerprint) {
        return Err(Error::Settings(format!(
            "task {}'s result is from another plan (mesh fingerprint {:016x}, the state's {:016x})",
            r.task, r.fingerprint, state.fingerprint
        )));
    }
    // Meshing and the patches' direct light ran in the plan, the receivers' in the tasks:
    // their mesh, light and rays.
    let mut m = restore(scene, settings, state.mesh, state.rays[0], progress)?;
    let vertex = receivers_light(m.mesh().receivers.len(), &results)?;
    m.occluder
        .credit_rays(results.iter().map(|r| r.direct_rays).sum());
    m.run.rays(RayStage::DirectAtReceivers, &m.occluder);
    m.occluder.credit_rays(state.rays[1]);
    m.run.rays(RayStage::DirectIntoPatches, &m.occluder);
    let direct = Direct {
        vertex,
        flux: state.flux,
    };
    m.occluder.credit_rays(results.iter().map(|r| r.rays).sum());
    let parts = results.into_iter().map(|r| r.part).collect();
    let rows = m.run.time(Stage::Links, || {
        links::assembled(scene, settings, &m.meshed, &m.occluder, parts)
    });
    m.run.rays(RayStage::Links, &m.occluder);
    let solved = complete(scene, settings, m, direct, rows, progress)?;
    Ok(finish(scene, settings, solved, progress))
}

/// The direct light at each of `n` receivers, from the tasks that lit them (each exactly once).
fn receivers_light(n: usize, results: &[TaskResult]) -> Result<Vec<DVec3>> {
    let mut out = vec![DVec3::ZERO; n];
    let mut lit = vec![false; n];
    for t in results {
        let rs = &t.part.receivers;
        let fits = rs.len() == t.direct.len()
            && rs
                .iter()
                .all(|&r| (r as usize) < n && !std::mem::replace(&mut lit[r as usize], true));
        if !fits {
            return Err(Error::Settings(format!(
                "task {}'s result does not fit the plan: its receivers and their light do not \
                 match the mesh's",
                t.task
            )));
        }
        for (&r, &e) in rs.iter().zip(&t.direct) {
            out[r as usize] = e;
        }
    }
    match lit.iter().all(|l| *l) {
        true => Ok(out),
        false => Err(Error::Settings(
            "the tasks' results leave some receivers unlit: they are not this plan's".into(),
        )),
    }
}

/// The settings as recorded in the output (threads aside: they do not change the result).
fn settings_json(settings: &Settings) -> String {
    serde_json::to_string(&SettingsRecord::from(settings)).expect("settings serialise")
}

fn check_settings(settings: &Settings, state: &State) -> Result<()> {
    match settings_json(settings) == state.settings {
        true => Ok(()),
        false => Err(Error::Settings(format!(
            "the settings differ from the plan's: run every task and the merge with the plan's \
             options (the plan's: {}, these: {})",
            state.settings,
            settings_json(settings)
        ))),
    }
}

fn check_scene(scene: &Scene, state: &State) -> Result<()> {
    let here = scene_fingerprint(scene);
    // Every group names a surface of this scene and that surface's material.
    let fits = |g: &crate::patches::Group| {
        (scene.surfaces.get(g.surface)).is_some_and(|s| s.material == g.material)
    };
    match here == state.scene && state.mesh.mesh.groups.iter().all(fits) {
        true => Ok(()),
        false => Err(Error::Settings(format!(
            "{} is not the scene the plan meshed (its surfaces' fingerprint {here:016x}, the \
             plan's {:016x})",
            scene.source_file.display(),
            state.scene
        ))),
    }
}

/// A 64-bit FNV-1a hash of the scene's surfaces: their positions, triangles and materials.
pub(crate) fn scene_fingerprint(scene: &Scene) -> u64 {
    let mut h = Fnv::default();
    h.eat(scene.surfaces.len() as u64);
    h.eat(scene.materials.len() as u64);
    for s in &scene.surfaces {
        h.eat(s.material as u64);
        h.eat(s.positions.len() as u64);
        for p in &s.positions {
            p.to_array().iter().for_each(|c| h.eat(c.to_bits()));
        }
        h.eat(s.triangles.len() as u64);
        s.triangles.iter().flatten().for_each(|&i| h.eat(i as u64));
    }
    h.0
}

struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn eat(&mut self, x: u64) {
        for b in x.to_le_bytes() {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// A 64-bit FNV-1a hash of the mesh: every receiver's point, normal and group, every patch's
/// vertices, group and area.
pub(crate) fn fingerprint(mesh: &PatchMesh) -> u64 {
    let mut h = Fnv::default();
    h.eat(mesh.receivers.len() as u64);
    for v in &mesh.receivers {
        for x in [v.point, v.normal] {
            x.to_array().iter().for_each(|c| h.eat(c.to_bits()));
        }
        h.eat(v.group as u64);
    }
    h.eat(mesh.patches.len() as u64);
    for p in &mesh.patches {
        p.v.iter().for_each(|&i| h.eat(i as u64));
        h.eat(p.group as u64);
        h.eat(p.area.to_bits());
    }
    h.0
}

/// Contiguous ranges of groups, about equal in receivers, at most `tasks` (at least one).
fn split(mesh: &PatchMesh, tasks: usize) -> Vec<(u32, u32)> {
    let groups = mesh.groups.len();
    let mut count = vec![0usize; groups];
    for v in &mesh.receivers {
        count[v.group as usize] += 1;
    }
    let total: usize = count.iter().sum();
    let mut out = Vec::new();
    let (mut start, mut sum) = (0usize, 0usize);
    for (g, c) in count.iter().enumerate() {
        sum += c;
        // Close a task when the running total passes its share of the receivers.
        if sum * tasks >= total * (out.len() + 1) && out.len() + 1 < tasks {
            out.push((start as u32, g as u32 + 1));
            start = g + 1;
        }
    }
    out.push((start as u32, groups as u32));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tasks_split_the_groups_once_each_in_order() {
        let scene =
            crate::fixtures::closed_box_with_balls(DVec3::new(4.0, 3.0, 5.0), 0.5, 0.5, 100.0);
        let settings = Settings::default();
        let m = mesh(&scene, &settings, &crate::progress::Silent).unwrap();
        let groups = m.mesh().groups.len() as u32;
        for tasks in [1, 2, 3, 7, 1000] {
            let t = split(m.mesh(), tasks);
            assert!(!t.is_empty() && t.len() <= tasks.max(1));
            assert_eq!(t[0].0, 0);
            assert_eq!(t.last().unwrap().1, groups);
            assert!(t.windows(2).all(|w| w[0].1 == w[1].0 && w[0].0 < w[0].1));
        }
    }

    /// Each task lights its own receivers with the single bake's values; the merge takes each
    /// receiver's light from the one task that lit it, and refuses results that do not cover
    /// the receivers once each.
    #[test]
    fn tasks_light_their_receivers_as_the_single_bake_does() {
        let scene =
            crate::fixtures::closed_box_with_balls(DVec3::new(4.0, 3.0, 5.0), 0.5, 0.5, 100.0);
        let settings = Settings::default();
        let silent = &crate::progress::Silent;
        let mut m = mesh(&scene, &settings, silent).unwrap();
        let single = crate::bake::light(&scene, &mut m, silent).vertex;
        let state = || plan(&scene, &settings, 3, silent).unwrap();
        let tasks = state().tasks.len();
        let results: Vec<TaskResult> = (0..tasks)
            .map(|k| gather(&scene, &settings, state(), k, silent).unwrap())
            .collect();
        let n = single.len();
        assert_eq!(receivers_light(n, &results).unwrap(), single);
        // A receiver lit twice (another task's first receiver claimed again), or one not lit.
        let mut twice: Vec<TaskResult> = results;
        let first = twice[0].part.receivers[0];
        twice[1].part.receivers[0] = first;
        assert!(receivers_light(n, &twice).is_err());
        twice.truncate(1);
        assert!(receivers_light(n, &twice).is_err());
    }
}
