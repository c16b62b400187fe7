//! The files of the distributed bake's three steps (`bake shard plan|gather|merge --dir DIR`,
//! parsed in `cli::bake`; `dask/dask_bake.py` runs them on a Dask cluster): the state and task
//! files in DIR, read and written here.

use anyhow::{Context, Result};
use luxbake::bake::shard::{self, State};
use luxbake::export::atomic::write_atomic;
use luxbake::progress::Progress;
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::Settings;
use luxbake::shardfile;
use std::path::{Path, PathBuf};

fn state_path(dir: &Path) -> PathBuf {
    dir.join("state.bin")
}

fn task_path(dir: &Path, k: usize) -> PathBuf {
    dir.join(format!("task-{k}.bin"))
}

/// Mesh and light the scene; write DIR/state.bin and DIR/plan.json (the task count).
pub fn plan(
    dir: &Path,
    tasks: usize,
    scene: &Scene,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let state = shard::plan(scene, settings, tasks, progress)?;
    write_atomic(&state_path(dir), &shardfile::state_bytes(&state))?;
    let plan = serde_json::json!({
        "version": 1,
        "tasks": state.tasks.len(),
        "receivers": state.mesh.mesh.receivers.len(),
        "patches": state.flux.per_patch.len(),
    });
    write_atomic(&dir.join("plan.json"), format!("{plan:#}\n").as_bytes())?;
    Ok(())
}

/// Gather task `k`; write DIR/task-K.bin.
pub fn gather(
    dir: &Path,
    k: usize,
    scene: &Scene,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<()> {
    let state = read_state(dir)?;
    let result = shard::gather(scene, settings, state, k, progress)?;
    write_atomic(&task_path(dir, k), &shardfile::task_bytes(&result))?;
    Ok(())
}

/// Read the state and every task's result and finish the bake.
pub fn merge(
    dir: &Path,
    scene: &Scene,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<BakeResult> {
    let state = read_state(dir)?;
    let results = (0..state.tasks.len())
        .map(|k| {
            let path = task_path(dir, k);
            let bytes = std::fs::read(&path)
                .with_context(|| format!("{}: cannot read task {k}'s result", path.display()))?;
            shardfile::read_task(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(shard::merge(scene, settings, state, results, progress)?)
}

fn read_state(dir: &Path) -> Result<State> {
    let path = state_path(dir);
    let bytes = std::fs::read(&path).with_context(|| {
        format!(
            "{}: cannot read the plan's state (run bake shard plan first)",
            path.display()
        )
    })?;
    shardfile::read_state(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}
