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
pub(crate) fn all(
    scene: &Scene,
    wanted: Wanted,
    occ: &Occluder,
    progress: &dyn Progress,
) -> Vec<Probe> {
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
    let two_sided = two_sided_triangles(scene);
    for p in wanted.explicit {
        if is_inside(occ, &two_sided, p.position) {
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
pub(crate) fn node_probes(scene: &Scene) -> Vec<Probe> {
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
pub(crate) fn grid_counts(lo: DVec3, hi: DVec3, spacing: f64) -> [f64; 2] {
    [hi.x - lo.x, hi.z - lo.z].map(|extent| (extent / spacing).floor().max(1.0))
}

/// A horizontal grid of world-aligned probes `height` above the floor.
pub(crate) fn grid(
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
    let two_sided = two_sided_triangles(scene);
    let (mut out, mut inside, mut no_floor) = (Vec::new(), 0, 0);
    for i in 0..nx {
        for k in 0..nz {
            let (x, z) = (x0 + i as f64 * g.spacing, z0 + k as f64 * g.spacing);
            // The floor: the first surface a ray from underneath the scene meets, or when that
            // is the underside of a slab (single-sided, facing down), the slab's top: the first
            // face turned up.
            let from = DVec3::new(x, below, z);
            let floor = occ.closest(from, DVec3::Y).and_then(|h| {
                match h.normal.y < 0.0 && !two_sided[h.triangle] {
                    true => occ.closest_back(from, DVec3::Y),
                    false => Some(h),
                }
            });
            let Some(hit) = floor else {
                no_floor += 1;
                continue;
            };
            let p = DVec3::new(x, below + hit.distance + g.height, z);
            if is_inside(occ, &two_sided, p) {
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

/// True when, along some axis direction, the nearest surface shows `p` the back of a
/// single-sided face: `p` is inside a closed object (or behind a single-sided face). Both sides of
/// a double-sided face are fronts (a zero-thickness partition has a room on each).
fn is_inside(occ: &Occluder, two_sided: &[bool], p: DVec3) -> bool {
    super::FACES.into_iter().any(|d| {
        (occ.closest(p, d)).is_some_and(|h| h.normal.dot(d) > 0.0 && !two_sided[h.triangle])
    })
}

/// Per triangle of the scene (in the occluder's order: surfaces in turn), whether its material
/// is double-sided.
fn two_sided_triangles(scene: &Scene) -> Vec<bool> {
    (scene.surfaces.iter())
        .flat_map(|s| {
            std::iter::repeat_n(scene.materials[s.material].double_sided, s.triangles.len())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::building_floor::{building_floor, rooms};

    #[test]
    fn a_working_plane_stands_on_the_slab_top_in_every_room_of_a_building() {
        // A 0.2 m slab under every room; rooms beside zero-thickness double-sided partitions.
        // Before: every point 0.2 m low (on the slab's underside) and 849 of 2 714 points
        // skipped as "inside objects", rooms behind a thin partition's far side among them.
        let scene = building_floor();
        let occ = Occluder::build(&scene, Default::default());
        let g = ProbeGrid {
            spacing: 0.4,
            height: 0.8,
        };
        let origin = ProbeOrigin::WorkingPlane;
        let silent = crate::progress::Silent;
        let probes = grid(&scene, &occ, &g, "wp", origin, &silent);
        let off: Vec<_> = probes
            .iter()
            .filter(|p| (p.position.y - 0.8).abs() > 1e-6)
            .map(|p| p.position)
            .collect();
        assert!(
            off.is_empty(),
            "{} off: {:?}",
            off.len(),
            &off[..off.len().min(8)]
        );
        for room in rooms() {
            // Points strictly inside the room's air, a spacing from its walls.
            let inner = |p: &Probe| {
                let q = p.position;
                (room.lo.x + 0.4..room.hi.x - 0.4).contains(&q.x)
                    && (room.lo.z + 0.4..room.hi.z - 0.4).contains(&q.z)
            };
            let cells = ((room.hi.x - room.lo.x - 0.8) / 0.4).floor()
                * ((room.hi.z - room.lo.z - 0.8) / 0.4).floor();
            let kept = probes.iter().filter(|p| inner(p)).count() as f64;
            // Only a desk may stand in the way.
            assert!(
                kept >= 0.7 * cells,
                "{}: {kept} of about {cells}",
                room.name
            );
        }
    }
}
