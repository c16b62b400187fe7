//! The meshing stage: uniform patches, or (by default) adaptive ones.
//!
//! Input: the scene, the settings' patch size `h` (m) and the occluder. Output: the
//! [`PatchMesh`] every later stage uses, and what the summary says about it.
//!
//! Adaptive meshing starts from patches of `COARSE × h`, estimates the direct light on them
//! with the scene's lights, luminaires and profiled emitters (Lambertian emitting surfaces are
//! not in the estimate: their light arrives through the patch field), and splits edges where
//! linear interpolation misses it (see [`patches::adapt`]), down to `h / 2`. Smooth regions
//! keep patches 4× the area of the uniform mesh's; shadow edges and steep gradients get patches
//! a quarter of it. `--uniform-patches` turns it off (the harness measures both).

use crate::direct::{bounds::ProfileBounds, emitters, sources::DirectSource};
use crate::patches::{self, PatchMesh, adapt::Adapt};
use crate::scene::Scene;
use crate::settings::Settings;
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// The adaptive mesh starts from patches this many times the uniform size.
pub const COARSE: f64 = 2.0;

/// Build the patch mesh for patch size `h`.
pub fn mesh(
    scene: &Scene,
    settings: &Settings,
    h: f64,
    occluder: &Occluder,
    bounds: &ProfileBounds,
) -> (PatchMesh, serde_json::Value) {
    if settings.uniform_patches {
        return (patches::build(scene, h, None), serde_json::json!(null));
    }
    let coarse = patches::build(scene, COARSE * h, None);
    let emitted = emitters::patch_exitance(scene, &coarse);
    let sources = DirectSource::all(scene, &coarse, &emitted, bounds);
    if sources.is_empty() {
        // Nothing to adapt to (emitting surfaces only): the uniform mesh.
        return (patches::build(scene, h, None), serde_json::json!(null));
    }
    let probe = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
        q.par_iter()
            .map(|(p, n)| {
                sources
                    .iter()
                    .map(|s| s.illuminance(occluder, *p, *n))
                    .sum()
            })
            .collect()
    };
    let points: Vec<(DVec3, DVec3)> = coarse
        .receivers
        .iter()
        .map(|r| (r.point, r.normal))
        .collect();
    let values = probe(&points);
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    let adapt = Adapt {
        probe: &probe,
        min_edge: h / 2.0,
        levels: 3,
        mean,
    };
    let mesh = patches::build(scene, COARSE * h, Some(&adapt));
    let note = serde_json::json!({
        "coarsePatchSize": COARSE * h,
        "smallestPatchSize": h / 2.0,
        "coarsePatches": coarse.patches.len(),
        "relative": patches::adapt::RELATIVE,
        "absolute": patches::adapt::ABSOLUTE,
    });
    (mesh, note)
}
