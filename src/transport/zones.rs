//! Zones: the patches that share the air in front of them (one closed room, rooms joined by an
//! open door, the outside), so that the patch hierarchy never puts patches from both sides of a
//! wall in one node.
//!
//! Input: a [`PatchMesh`]. Output: per patch, its zone (0, 1, … in order of each zone's first
//! patch). Two patches are in one zone when a ray from one's front reaches the other's front
//! ([`RAYS`] cosine-spread rays from every patch's centroid, turned about its normal by an angle
//! of its own; a ray that leaves the scene joins its patch to the outside).
//!
//! Invariants: zones are joined only on a ray's evidence, so two patches an opaque surface
//! separates are never in one zone; rays that missed an opening only split a zone in two, which
//! costs the tree a node and changes no answer (a node's visibility is still traced). The result
//! depends on the mesh alone (fixed directions, unions in patch order), never on the thread count.

use crate::geom::samples;
use crate::patches::PatchMesh;
use crate::visibility::Occluder;
use glam::{DQuat, DVec3};
use rayon::prelude::*;

/// Rays per patch: [`samples::cosine_directions`] on a 2 × 2 grid.
const RAYS: usize = 2;

/// Each patch's zone.
pub(crate) fn of(mesh: &PatchMesh) -> Vec<u32> {
    let n = mesh.patches.len();
    if n == 0 {
        return Vec::new();
    }
    let tris: Vec<[DVec3; 3]> = (mesh.patches.iter())
        .map(|p| p.corners(&mesh.receivers))
        .collect();
    let occ = Occluder::from_triangles(&tris, false);
    let twin = twins(mesh, &tris);
    let outside = n as u32;
    let seen: Vec<[u32; RAYS * RAYS]> = (0..n)
        .into_par_iter()
        .map(|i| {
            let patch = &mesh.patches[i];
            let c = tris[i];
            let origin = (c[0] + c[1] + c[2]) / 3.0 + patch.normal * (4.0 * occ.epsilon);
            let turn = samples::unit_pair(i as u64)[0] * std::f64::consts::TAU;
            let turn = DQuat::from_axis_angle(patch.normal, turn);
            let mut out = [u32::MAX; RAYS * RAYS];
            for (k, d) in samples::cosine_directions(patch.normal, RAYS).enumerate() {
                let d = turn * d;
                // A back is the inside of a solid, or a double-sided patch whose twin (the
                // coincident patch facing the other way) the ray met first: then the twin.
                out[k] = match occ.closest(origin, d) {
                    None => outside,
                    Some(h) if mesh.patches[h.triangle].normal.dot(d) < 0.0 => h.triangle as u32,
                    Some(h) => twin.get(&(h.triangle as u32)).copied().unwrap_or(u32::MAX),
                };
            }
            out
        })
        .collect();
    let mut parent: Vec<u32> = (0..=outside).collect();
    for (i, hits) in seen.iter().enumerate() {
        for &j in hits.iter().filter(|&&j| j != u32::MAX) {
            union(&mut parent, i as u32, j);
        }
    }
    let mut zone: Vec<u32> = (0..n as u32).map(|i| root(&mut parent, i)).collect();
    let blind: Vec<bool> = seen
        .iter()
        .map(|h| h.iter().all(|&j| j == u32::MAX))
        .collect();
    adopt_blind(mesh, &blind, &mut zone);
    relabel(&zone)
}

/// A zone made only of blind patches (all their rays met backs: crevices, faces inside solids)
/// has no evidence of its own: its patches take the lowest zone among the sighted patches they
/// share a vertex with, whose values they are interpolated with anyway; those with no sighted
/// neighbour form one zone together. Without this every crevice would be a zone and a node of
/// the tree for every receiver to visit.
fn adopt_blind(mesh: &PatchMesh, blind: &[bool], zone: &mut [u32]) {
    let n = zone.len();
    let mut sighted = vec![false; n + 1];
    for (i, &z) in zone.iter().enumerate() {
        sighted[z as usize] |= !blind[i];
    }
    let mut at_vertex: Vec<Vec<u32>> = vec![Vec::new(); mesh.receivers.len()];
    for (i, p) in mesh.patches.iter().enumerate() {
        for &v in &p.v {
            at_vertex[v as usize].push(i as u32);
        }
    }
    // Rounds from the previous state (Jacobi), so the result does not depend on patch order
    // beyond the lowest-zone rule; a chain of blind patches is adopted one link per round.
    let mut open: Vec<usize> = (0..n).filter(|&i| !sighted[zone[i] as usize]).collect();
    while !open.is_empty() {
        let adopted: Vec<(usize, u32)> = (open.iter())
            .filter_map(|&i| {
                let near = mesh.patches[i]
                    .v
                    .iter()
                    .flat_map(|&v| &at_vertex[v as usize]);
                let z = near
                    .map(|&j| zone[j as usize])
                    .filter(|&z| sighted[z as usize])
                    .min()?;
                Some((i, z))
            })
            .collect();
        if adopted.is_empty() {
            break;
        }
        for &(i, z) in &adopted {
            zone[i] = z;
        }
        open.retain(|&i| !sighted[zone[i] as usize]);
    }
    // The rest lie inside solids, out of every room's sight: one zone, so that they cost the
    // tree one subtree rather than one per crevice.
    if let Some(&first) = open.first() {
        let sealed = zone[first];
        open.iter().for_each(|&i| zone[i] = sealed);
    }
}

/// Zones renumbered 0, 1, … in order of each zone's first patch.
fn relabel(zone: &[u32]) -> Vec<u32> {
    let mut label = std::collections::HashMap::new();
    (zone.iter())
        .map(|&z| {
            let next = label.len() as u32;
            *label.entry(z).or_insert(next)
        })
        .collect()
}

/// Each double-sided patch's twin: the patch with the same corners facing the other way.
fn twins(mesh: &PatchMesh, tris: &[[DVec3; 3]]) -> std::collections::HashMap<u32, u32> {
    let key = |c: &[DVec3; 3]| {
        let mut k = c.map(|p| p.to_array().map(f64::to_bits));
        k.sort_unstable();
        k
    };
    let mut by_place: std::collections::HashMap<_, Vec<u32>> = Default::default();
    for (i, p) in mesh.patches.iter().enumerate() {
        if p.double_sided {
            by_place.entry(key(&tris[i])).or_default().push(i as u32);
        }
    }
    let mut twin = std::collections::HashMap::new();
    for pair in by_place.values().filter(|v| v.len() == 2) {
        twin.insert(pair[0], pair[1]);
        twin.insert(pair[1], pair[0]);
    }
    twin
}

fn root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        parent[i as usize] = parent[parent[i as usize] as usize];
        i = parent[i as usize];
    }
    i
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (root(parent, a), root(parent, b));
    parent[ra.max(rb) as usize] = ra.min(rb);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::building::{self, Partitions, Slabs};

    /// The zones of a row's patches whose fronts lie inside each room.
    fn zones_by_room(slabs: Slabs, doors: &[bool]) -> Vec<Vec<u32>> {
        let row = building::row(slabs, 3, 0.5, 100.0, doors);
        let occ = Occluder::build(&row.scene, Default::default());
        let contacts = crate::contacts::find(&row.scene, 0.125, &occ);
        let mesh = crate::patches::build_cut(&row.scene, 0.5, None, &contacts);
        let zone = of(&mesh);
        let mut by_room = vec![Vec::new(); 3];
        for (p, z) in mesh.patches.iter().zip(&zone) {
            let c = p.corners(&mesh.receivers);
            let front = (c[0] + c[1] + c[2]) / 3.0 + p.normal * 0.01;
            if let Some(k) = row.room_of(front, 0.0) {
                if std::env::var("ZDEBUG").is_ok() {
                    eprintln!(
                        "room {k} zone {z} at {front:.3?} n {:.2?} area {:.3}",
                        p.normal, p.area
                    );
                }
                by_room[k].push(*z);
            }
        }
        by_room.iter_mut().for_each(|z| {
            z.sort_unstable();
            z.dedup();
        });
        by_room
    }

    #[test]
    fn closed_rooms_on_one_slab_are_zones_of_their_own_and_an_open_door_joins_two() {
        for partitions in [Partitions::Box, Partitions::Thin] {
            let shut = zones_by_room(Slabs::Shared(partitions), &[]);
            assert!(
                shut.iter().all(|z| z.len() == 1),
                "{partitions:?}: {shut:?}"
            );
            assert!(shut[0] != shut[1] && shut[1] != shut[2] && shut[0] != shut[2]);
            let open = zones_by_room(Slabs::Shared(partitions), &[true]);
            assert!(
                open.iter().all(|z| z.len() == 1),
                "{partitions:?}: {open:?}"
            );
            assert_eq!(
                open[0], open[1],
                "{partitions:?}: the open door joins rooms 0 and 1"
            );
            assert!(open[1] != open[2]);
        }
    }

    #[test]
    fn faces_inside_a_solid_take_a_neighbour_zone_or_share_one_not_a_zone_each() {
        // A closed room; a box with its lower part sunk in a second box: the sunk faces' rays
        // all meet the second box's backs (blind); those touching sighted faces take their zone.
        let mut b = crate::fixtures::SceneBuilder::new();
        let m = b.material("grey", 0.5);
        b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, m);
        b.axis_box(
            "plinth",
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(2.0, 0.5, 2.0),
            false,
            m,
        );
        b.axis_box(
            "post",
            DVec3::new(1.2, 0.2, 1.2),
            DVec3::new(1.8, 1.5, 1.8),
            false,
            m,
        );
        let scene = b.build();
        let occ = Occluder::build(&scene, Default::default());
        let contacts = crate::contacts::find(&scene, 0.05, &occ);
        let mesh = crate::patches::build_cut(&scene, 0.2, None, &contacts);
        let zone = of(&mesh);
        let zones = zone.iter().max().map_or(0, |z| z + 1);
        // The room; the pocket inside the plinth (the floor under it sees the post's foot); the
        // plinth's underside. Without adoption: 29, one per blind patch.
        assert!(zones <= 3, "{zones} zones");
        let sunk = (mesh.patches.iter().zip(&zone)).filter(|(p, _)| {
            let c = p.corners(&mesh.receivers);
            let m = (c[0] + c[1] + c[2]) / 3.0;
            m.y < 0.45 && (1.25..1.75).contains(&m.x) && (1.25..1.75).contains(&m.z)
        });
        assert!(sunk.count() > 10, "the post has faces inside the plinth");
    }
}
