//! Where the probes are: glTF nodes whose `extras.probe` is true (what Blender writes for a custom
//! property `probe` on an Empty), a grid over the floor (`--probe-grid`), probes given explicitly
//! (`--probes FILE.csv`), and the report's working plane (`--working-plane`).
//!
//! Input: the scene, what to measure ([`Wanted`]), and the scene's occluder (to find the floor
//! and to skip grid points inside objects). Output: the list of [`Probe`]s, in that order, and
//! warnings.
//!
//! A node probe takes the node's world position and its world rotation (scale removed) unless its
//! `extras.probe` is an object with `"aligned": true`, which keeps the cube aligned with the world
//! axes; `extras.toward` ([x, y, z], probe axes) adds a semi-cylindrical illuminance toward that
//! direction. Grid points: every `spacing` over the scene's horizontal extent (+Y up), centred in
//! it and at least half a spacing from its edges (a 5 m room at 1 m: 0.5, 1.5, … 4.5), `height`
//! above the first upward surface below it (found with a ray from underneath the scene); points
//! with no floor below, or inside an object (a back face is the nearest surface in some axis
//! direction), are skipped and counted in a warning. Explicit probes are kept wherever they are,
//! with a warning for each one inside an object.

use super::{Probe, ProbeGrid, ProbeOrigin};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::visibility::Occluder;
use glam::{DMat3, DVec3};

/// What a bake measures besides the scene's own probe nodes.
#[derive(Debug, Clone, Copy, Default)]
pub struct Wanted<'a> {
    /// `--probe-grid`.
    pub grid: Option<ProbeGrid>,
    /// Probes given explicitly (`--probes FILE.csv`).
    pub explicit: &'a [Probe],
    /// The report's working plane.
    pub working_plane: Option<ProbeGrid>,
}

/// All probes of a bake, in order: nodes, grid, explicit, working plane.
pub fn all(scene: &Scene, wanted: Wanted, occ: &Occluder, progress: &dyn Progress) -> Vec<Probe> {
    let mut out = node_probes(scene);
    if let Some(g) = wanted.grid {
        out.extend(grid(
            scene,
            occ,
            &g,
            "grid",
            ProbeOrigin::Grid {
                layer: "grid".into(),
            },
            progress,
        ));
    }
    for p in wanted.explicit {
        if is_inside(occ, p.position) {
            progress.warn(&format!(
                "probe '{}' ({}) is inside an object or behind a one-sided surface: its faces may read 0 lx",
                p.name,
                match p.origin {
                    ProbeOrigin::File { line } => format!("line {line} of the probes file"),
                    _ => "given explicitly".into(),
                }
            ));
        }
    }
    out.extend(wanted.explicit.iter().cloned());
    if let Some(g) = wanted.working_plane {
        out.extend(grid(
            scene,
            occ,
            &g,
            "working_plane",
            ProbeOrigin::WorkingPlane,
            progress,
        ));
    }
    out
}

/// Nodes whose `extras.probe` is `true` (or an object).
pub fn node_probes(scene: &Scene) -> Vec<Probe> {
    let mut out = Vec::new();
    for (i, node) in scene.nodes.iter().enumerate() {
        let Some(extras) = &node.extras else { continue };
        let marked = &extras["probe"];
        let on = marked.as_bool().unwrap_or(false) || marked.is_object();
        if !on {
            continue;
        }
        let aligned = marked["aligned"].as_bool().unwrap_or(false);
        let m = node.world_from_local;
        let rotation = if aligned {
            DMat3::IDENTITY
        } else {
            orthonormal(DMat3::from_mat4(m))
        };
        let toward = extras["toward"]
            .as_array()
            .filter(|a| a.len() == 3)
            .and_then(|a| {
                let v: Vec<f64> = a.iter().filter_map(|x| x.as_f64()).collect();
                (v.len() == 3).then(|| DVec3::new(v[0], v[1], v[2]))
            })
            .and_then(|v| v.try_normalize());
        out.push(Probe {
            name: node.name.clone().unwrap_or_else(|| format!("node {i}")),
            position: m.w_axis.truncate(),
            world_from_probe: rotation,
            origin: ProbeOrigin::Node { node: i },
            toward,
        });
    }
    out
}

/// Rotation part of a transform with scale (and mirroring) removed: Gram–Schmidt on X then Y.
fn orthonormal(m: DMat3) -> DMat3 {
    let x = m.x_axis.try_normalize().unwrap_or(DVec3::X);
    let y = (m.y_axis - x * m.y_axis.dot(x))
        .try_normalize()
        .unwrap_or_else(|| x.any_orthonormal_vector());
    DMat3::from_cols(x, y, x.cross(y))
}

/// Grid points along x and z (+Y up) over the box `lo`..`hi`: floor(extent / spacing) per axis,
/// at least one; centred in the extent, so at least half a spacing from its edges and no point
/// lies in a bounding wall. In f64: `bake::budget` counts before anything is allocated.
pub fn grid_counts(lo: DVec3, hi: DVec3, spacing: f64) -> [f64; 2] {
    [hi.x - lo.x, hi.z - lo.z].map(|extent| (extent / spacing).floor().max(1.0))
}

/// A horizontal grid of world-aligned probes `height` above the floor.
pub fn grid(
    scene: &Scene,
    occ: &Occluder,
    g: &ProbeGrid,
    name: &str,
    origin: ProbeOrigin,
    progress: &dyn Progress,
) -> Vec<Probe> {
    let Some((lo, hi)) = scene.bounds() else {
        return Vec::new();
    };
    let [nx, nz] = grid_counts(lo, hi, g.spacing).map(|n| n as usize);
    let (x0, z0) = (
        lo.x + (hi.x - lo.x - (nx - 1) as f64 * g.spacing) / 2.0,
        lo.z + (hi.z - lo.z - (nz - 1) as f64 * g.spacing) / 2.0,
    );
    let below = lo.y - 1e-3 * (hi - lo).length() - 1.0;
    let (mut out, mut inside, mut no_floor) = (Vec::new(), 0, 0);
    for i in 0..nx {
        for k in 0..nz {
            let (x, z) = (x0 + i as f64 * g.spacing, z0 + k as f64 * g.spacing);
            // The floor: the first surface a ray from underneath the scene meets.
            let Some(hit) = occ.closest(DVec3::new(x, below, z), DVec3::Y) else {
                no_floor += 1;
                continue;
            };
            let p = DVec3::new(x, below + hit.distance + g.height, z);
            if is_inside(occ, p) {
                inside += 1;
                continue;
            }
            out.push(Probe {
                name: format!("{name}_{i}_{k}"),
                position: p,
                world_from_probe: DMat3::IDENTITY,
                origin: origin.clone(),
                toward: None,
            });
        }
    }
    if inside + no_floor > 0 {
        progress.warn(&format!(
            "{name}: {inside} grid point(s) inside objects and {no_floor} with no floor below were skipped ({} kept)",
            out.len()
        ));
    }
    out
}

/// True when, along some axis direction, the nearest surface shows `p` its back: `p` is inside a
/// closed object (or behind a single-sided face).
fn is_inside(occ: &Occluder, p: DVec3) -> bool {
    super::FACES
        .into_iter()
        .any(|d| occ.closest(p, d).is_some_and(|h| h.normal.dot(d) > 0.0))
}
