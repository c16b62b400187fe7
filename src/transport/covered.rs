//! What covered parts cover of a receiver's hemisphere: the slots and gaps where one surface
//! rests on another are light traps, not more of what the receiver sees elsewhere.
//!
//! Input: a [`PatchMesh`] whose groups carry [`crate::patches::CoveredPart`]s. Output:
//! [`CoveredField`], those triangles as a mesh and tree of their own, every node black, which a
//! [`Gatherer`] reads for coverage only ([`Gatherer::covered`]).
//!
//! Why: covered parts are neither patches nor receivers but still block rays, so a receiver
//! beside a contact (the floor in the 3 cm slot between a screen and a desk frame) sees part of
//! its hemisphere as nothing at all. Normalising its row to coverage 1 then spreads that part over
//! what it does see, as if the slot's walls were as bright as the ceiling (twice the light at
//! coverage 0.5). Measured, that part counts as absorbed where the receiver is inside a slot
//! ([`super::gather::absorbed_share`]), like a back face: rows, the operator's balancing
//! targets and the energy report then agree that light sent into a slot stays there.
//! Invariant: the mesh depends only on the patch mesh (the same for a bake, its tasks and its
//! merge), and a double-sided surface's covered triangles are never seen from behind (what faces
//! that way is the other side's, a patch or covered in turn).

use super::gather::Gatherer;
use super::tree::PatchTree;
use crate::patches::{Group, Patch, PatchMesh, Side, Vertex};
use crate::visibility::Occluder;

/// Far-field acceptance of the covered parts' gather, relative to the receivers'.
const TAU_FACTOR: f64 = 2.0;

/// The covered triangles of a patch mesh as a mesh of their own, with its tree.
pub struct CoveredField {
    pub mesh: PatchMesh,
    pub tree: PatchTree,
    /// Every node black: what these triangles cover is counted, nothing is linked to them.
    black: Vec<bool>,
}

impl CoveredField {
    /// The covered triangles of `mesh`, or `None` when nothing is covered.
    pub(crate) fn of(mesh: &PatchMesh) -> Option<CoveredField> {
        let two_sided = double_sided_surfaces(mesh);
        let mut out = PatchMesh {
            patch_size: mesh.patch_size,
            ..Default::default()
        };
        for g in &mesh.groups {
            let Some(c) = &g.covered else { continue };
            let group = out.groups.len() as u32;
            let (first_vertex, first_patch) = (out.receivers.len(), out.patches.len());
            out.receivers
                .extend(c.positions.iter().zip(&c.normals).map(|(&p, &n)| Vertex {
                    position: p,
                    normal: n,
                    point: p,
                    group,
                }));
            for t in &c.triangles {
                let [a, b, d] = t.map(|v| c.positions[v as usize]);
                let cross = (b - a).cross(d - a);
                let area = cross.length() / 2.0;
                if area.is_nan() || area <= 0.0 {
                    continue;
                }
                out.patches.push(Patch {
                    v: t.map(|v| v + first_vertex as u32),
                    group,
                    area,
                    normal: cross / (2.0 * area),
                    double_sided: two_sided[g.surface],
                });
            }
            let area = out.patches[first_patch..].iter().map(|p| p.area).sum();
            out.groups.push(Group {
                surface: g.surface,
                side: g.side,
                material: g.material,
                receivers: first_vertex..out.receivers.len(),
                patches: first_patch..out.patches.len(),
                uv0: None,
                uv1: None,
                area,
                covered: None,
            });
        }
        if out.patches.is_empty() {
            return None;
        }
        let tree = PatchTree::build(&out, (0..out.patches.len() as u32).collect());
        let black = vec![true; tree.nodes.len()];
        Some(CoveredField {
            mesh: out,
            tree,
            black,
        })
    }

    /// A gatherer of what these triangles cover, seen past `occluder`'s geometry, for receivers
    /// gathering at far-field acceptance `tau`: at [`TAU_FACTOR`] times it, since only the sum
    /// counts (on the 10⁴ floor that halves its rays and moves the energy balance by < 10⁻⁵).
    pub(crate) fn gatherer<'a>(&'a self, occluder: &'a Occluder, tau: f64) -> Gatherer<'a> {
        Gatherer {
            mesh: &self.mesh,
            tree: &self.tree,
            occluder,
            tau: tau * TAU_FACTOR,
            split_leaves: false,
            fronts_only: false,
            dark: Some(&self.black),
            covered: None,
        }
    }
}

/// Per scene surface (indexed by `Group::surface`): does it have a back side of its own?
fn double_sided_surfaces(mesh: &PatchMesh) -> Vec<bool> {
    let n = mesh.groups.iter().map(|g| g.surface + 1).max().unwrap_or(0);
    let mut out = vec![false; n];
    for g in &mesh.groups {
        if g.side == Side::Back {
            out[g.surface] = true;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::geom::lambert;
    use crate::transport::links::gather_row;
    use crate::visibility::OccluderOptions;
    use glam::DVec3;

    /// `scene` meshed at h = 0.5 m with its contacts cut (h/4), its tree, and its covered parts
    /// (`what`: the ones expected).
    fn with_covers(
        scene: &crate::scene::Scene,
        what: &str,
    ) -> (Occluder, PatchMesh, PatchTree, CoveredField) {
        let occluder = Occluder::build(scene, OccluderOptions::default());
        let h = 0.5;
        let contacts = crate::contacts::find(scene, h / 4.0, &occluder);
        let mesh = crate::patches::build_cut(scene, h, None, &contacts);
        let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        let field = CoveredField::of(&mesh).expect(what);
        (occluder, mesh, tree, field)
    }

    #[test]
    fn a_slot_between_two_blocks_counts_as_absorbed_not_as_more_of_the_room() {
        // A closed 4 × 3 × 4 m room; two 0.2 m blocks on its floor, 4 cm apart: at h = 0.5 m the
        // faces across the slot are contacts (within h/8), so covered parts. A point on the
        // floor in the slot sees those faces over almost all its hemisphere.
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, grey);
        let (lo, hi) = (1.98, 2.02);
        b.axis_box(
            "a",
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(lo, 0.2, 3.0),
            false,
            grey,
        );
        b.axis_box(
            "b",
            DVec3::new(hi, 0.0, 1.0),
            DVec3::new(3.0, 0.2, 3.0),
            false,
            grey,
        );
        let scene = b.build();
        let (occluder, mesh, tree, field) =
            with_covers(&scene, "the slot's faces and the blocks' feet");
        let wall = |x: f64| {
            [(0.0, 1.0), (0.0, 3.0), (0.2, 3.0), (0.2, 1.0)].map(|(y, z)| DVec3::new(x, y, z))
        };
        let (p, n) = (DVec3::new(2.0, 1e-3, 2.0), DVec3::Y);
        let slot_walls =
            lambert::form_factor(p, n, &wall(lo)) + lambert::form_factor(p, n, &wall(hi));
        assert!(slot_walls > 0.8, "{slot_walls}");
        let covered = field.gatherer(&occluder, 0.3);
        // The patches' gatherer: the covered one's settings over the patches' mesh and tree.
        let mut gatherer = Gatherer {
            mesh: &mesh,
            tree: &tree,
            tau: 0.3,
            dark: None,
            covered: Some(&covered),
            ..covered
        };
        let row = gather_row(&gatherer, p, n);
        let linked: f64 = row.links.iter().map(|l| l.coeff as f64).sum();
        // Coverage is short of 1 by what two rays per far node miss through the 4 cm opening.
        assert!(row.closed && row.coverage > 0.95, "{}", row.coverage);
        let absorbed = row.back * row.coverage; // before normalisation
        assert!(
            (absorbed - slot_walls).abs() < 0.01 * slot_walls,
            "absorbed {absorbed} against the slot walls' form factor {slot_walls}"
        );
        assert!(
            (linked + row.back - 1.0).abs() < 1e-6,
            "{linked} + {}",
            row.back
        );
        // Without them the little the point sees of the room stands for its whole hemisphere.
        gatherer.covered = None;
        let row = gather_row(&gatherer, p, n);
        let linked: f64 = row.links.iter().map(|l| l.coeff as f64).sum();
        assert!(row.back < 1e-3 && (linked - 1.0).abs() < 1e-6, "{linked}");
    }

    #[test]
    fn a_receiver_beside_a_cracks_mouth_reads_the_room_not_the_crack() {
        // A 1 m cube standing 1 mm over the floor of a closed room: its underside and the floor
        // under it are covered. A floor point 2 mm outside its edge sees the underside over a
        // few per cent of its hemisphere (Lambert's formula): the millimetres next to the mouth
        // are lit like the room, so none of it counts as absorbed (below a tenth).
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, grey);
        let (lo, hi) = (DVec3::new(1.5, 1e-3, 1.5), DVec3::new(2.5, 1.0, 2.5));
        b.axis_box("cube", lo, hi, false, grey);
        let scene = b.build();
        let (occluder, mesh, tree, field) =
            with_covers(&scene, "the cube's underside and its footprint");
        let (p, n) = (DVec3::new(2.502, 1e-4, 2.0), DVec3::Y);
        let underside = [(lo.x, lo.z), (hi.x, lo.z), (hi.x, hi.z), (lo.x, hi.z)]
            .map(|(x, z)| DVec3::new(x, lo.y, z));
        let share = lambert::form_factor(p, n, &underside).abs();
        assert!(share > 0.02 && share < 0.1, "{share}");
        let covered = field.gatherer(&occluder, 0.3);
        let gatherer = Gatherer {
            mesh: &mesh,
            tree: &tree,
            tau: 0.3,
            dark: None,
            covered: Some(&covered),
            ..covered
        };
        let row = gather_row(&gatherer, p, n);
        let linked: f64 = row.links.iter().map(|l| l.coeff as f64).sum();
        assert!(row.back < 1e-3, "absorbed {} at the mouth", row.back);
        assert!((linked + row.back - 1.0).abs() < 1e-6, "{linked}");
    }
}
