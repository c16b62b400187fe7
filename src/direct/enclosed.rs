//! Closed solids: surfaces whose backs all face the inside of a solid they close.
//!
//! Input: the scene's surfaces (world space). Output: per surface, the bounding box of the solid
//! when the surface is one — watertight (with vertices welded by position, every edge is run by
//! exactly two triangles, in opposite directions) with its fronts facing out (positive signed
//! volume) — else nothing.
//!
//! Use: light from a source outside a closed solid never reaches the backs of its faces (every
//! path from a back leads into the solid and meets its surface before leaving). So a source
//! wholly outside the solid's box and wholly behind a patch's plane costs that patch nothing:
//! no shadow rays from the backs of a chair's facets into the chair, which would all be blocked.

use crate::scene::{Scene, Surface};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// An axis-aligned box (m, world space): lower and upper corners.
pub type Bounds = (DVec3, DVec3);

/// Per scene surface: the box of the closed solid it is, if it is one.
pub struct Solids(Vec<Option<Bounds>>);

impl Solids {
    pub(crate) fn new(scene: &Scene) -> Self {
        Solids(scene.surfaces.par_iter().map(solid_bounds).collect())
    }

    /// The box of surface `s` when it closes a solid with its fronts facing out.
    pub(crate) fn of(&self, s: usize) -> Option<Bounds> {
        self.0[s]
    }
}

/// The bounding box of `s` when it is watertight and faces out.
fn solid_bounds(s: &Surface) -> Option<Bounds> {
    if s.triangles.len() < 4 {
        return None;
    }
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in &s.positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    // Weld vertices that coincide to 10⁻⁹ of the size, so a mesh with split normals (a box with
    // sharp edges stores each corner once per face) or a pole stored once per segment still
    // closes. A pair that rounds apart only hides a solid: never wrongly finds one.
    let cell = 1e-9 * (hi - lo).length();
    if cell.is_nan() || cell <= 0.0 {
        return None;
    }
    let mut weld: HashMap<[i64; 3], u32> = HashMap::with_capacity(s.positions.len());
    let id: Vec<u32> = s
        .positions
        .iter()
        .map(|p| {
            let next = weld.len() as u32;
            let key = ((*p - lo) / cell).round().as_i64vec3().to_array();
            *weld.entry(key).or_insert(next)
        })
        .collect();
    // Every directed edge once, and its reverse once.
    let mut edges: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * s.triangles.len());
    for t in &s.triangles {
        let v = t.map(|k| id[k as usize]);
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            if a == b {
                return None;
            }
            let n = edges.entry((a, b)).or_insert(0);
            *n += 1;
            if *n > 1 {
                return None;
            }
        }
    }
    if edges.keys().any(|&(a, b)| !edges.contains_key(&(b, a))) {
        return None;
    }
    // Six times the signed volume of each connected part, about the box's centre (for
    // precision far from the origin): every part must face out. (One mesh may hold a solid and
    // a small room facing in, whose backs face the world: its whole volume could still be
    // positive.)
    let mut parent: Vec<u32> = (0..weld.len() as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    for t in &s.triangles {
        let r = t.map(|k| root(&mut parent, id[k as usize]));
        parent[r[1] as usize] = r[0];
        let r2 = root(&mut parent, r[2]);
        parent[r2 as usize] = r[0];
    }
    let o = (lo + hi) / 2.0;
    let mut volume = vec![0.0f64; weld.len()];
    for t in &s.triangles {
        let [a, b, c] = t.map(|k| s.positions[k as usize] - o);
        volume[root(&mut parent, id[t[0] as usize]) as usize] += a.dot(b.cross(c));
    }
    let outward = s
        .triangles
        .iter()
        .all(|t| volume[root(&mut parent, id[t[0] as usize]) as usize] > 0.0);
    outward.then_some((lo, hi))
}

/// Do boxes `a` and `b` overlap (touching counts)?
pub(crate) fn overlap(a: Bounds, b: Bounds) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;

    fn solids(b: SceneBuilder) -> Vec<Option<Bounds>> {
        Solids::new(&b.build()).0
    }

    #[test]
    fn closed_outward_meshes_are_solids_and_open_or_inward_ones_are_not() {
        let mut b = SceneBuilder::new();
        let m = b.material("grey", 0.5);
        b.ball("ball", DVec3::new(1.0, 2.0, 3.0), 0.5, (6, 8), m);
        let mut inward = SceneBuilder::new();
        let m2 = inward.material("grey", 0.5);
        inward.axis_box("room", DVec3::ZERO, DVec3::ONE, true, m2);
        let ball = solids(b);
        let (lo, hi) = ball[0].expect("a tessellated ball is a closed solid");
        assert!(
            (lo - DVec3::new(0.5, 1.5, 2.5)).abs().max_element() < 0.01,
            "{lo}"
        );
        assert!(
            (hi - DVec3::new(1.5, 2.5, 3.5)).abs().max_element() < 0.01,
            "{hi}"
        );
        // A box of six separate quads is six open surfaces, never a solid.
        assert!(solids(inward).iter().all(|s| s.is_none()));
    }

    #[test]
    fn sources_behind_a_patch_and_outside_a_solid() {
        use crate::direct::{bounds::ProfileBounds, sources::DirectSource};
        use crate::scene::LightKind;
        let mut b = SceneBuilder::new();
        b.point_light("lamp", DVec3::new(0.0, 3.0, 0.0), 100.0);
        // Shining down (+Y up): light arrives from above.
        b.light(
            "sun",
            LightKind::Directional,
            DVec3::ZERO,
            -DVec3::Y,
            1000.0,
        );
        let scene = b.build();
        let bounds = ProfileBounds::new(&scene);
        let sources = DirectSource::all(&scene, &Default::default(), &[], &bounds);
        let (lamp, sun) = (&sources[0], &sources[1]);
        let c = DVec3::ZERO;
        let elsewhere = Some((DVec3::splat(5.0), DVec3::splat(6.0)));
        let around_lamp = Some((DVec3::new(-1.0, 2.0, -1.0), DVec3::new(1.0, 4.0, 1.0)));
        // A patch facing down: both sources lie behind it.
        assert!(lamp.behind_and_outside(c, -DVec3::Y, None));
        assert!(lamp.behind_and_outside(c, -DVec3::Y, elsewhere));
        assert!(
            !lamp.behind_and_outside(c, -DVec3::Y, around_lamp),
            "the lamp is in the box"
        );
        assert!(
            sun.behind_and_outside(c, -DVec3::Y, around_lamp),
            "the sun is in no box"
        );
        // Facing up or sideways: not behind.
        assert!(!lamp.behind_and_outside(c, DVec3::Y, None));
        assert!(!sun.behind_and_outside(c, DVec3::Y, None));
        assert!(!lamp.behind_and_outside(DVec3::new(0.0, 3.0, 0.0), DVec3::X, None));
        assert!(!sun.behind_and_outside(c, DVec3::X, None));
    }

    /// One surface made of the quads of `boxes` (each `box_faces`, counter-clockwise from
    /// inside; turned round for `outward`), four vertices a quad, as exporters write sharp
    /// boxes: whether it is a solid, and its box.
    fn quads(boxes: &[(&[[DVec3; 4]], bool)]) -> Option<Bounds> {
        let mut b = SceneBuilder::new();
        let m = b.material("grey", 0.5);
        let (mut positions, mut triangles) = (Vec::new(), Vec::new());
        for (faces, outward) in boxes {
            for quad in faces.iter() {
                let k = positions.len() as u32;
                positions.extend(match outward {
                    true => [quad[0], quad[3], quad[2], quad[1]],
                    false => *quad,
                });
                triangles.push([k, k + 1, k + 2]);
                triangles.push([k, k + 2, k + 3]);
            }
        }
        let normals = vec![DVec3::Y; positions.len()];
        b.surface("quads", positions, normals, triangles, m);
        solids(b)[0]
    }

    #[test]
    fn a_box_with_split_corners_closes_and_facing_in_does_not() {
        let faces = crate::fixtures::box_faces(DVec3::ZERO, DVec3::new(2.0, 1.0, 3.0));
        let small = crate::fixtures::box_faces(DVec3::splat(10.0), DVec3::splat(11.0));
        assert_eq!(
            quads(&[(&faces, true)]),
            Some((DVec3::ZERO, DVec3::new(2.0, 1.0, 3.0)))
        );
        assert_eq!(
            quads(&[(&faces, false)]),
            None,
            "fronts facing in: the backs face out"
        );
        // A solid and, in the same mesh, a smaller box facing in: not a solid.
        assert_eq!(quads(&[(&faces, true), (&small, false)]), None);
        // One face missing: open.
        assert_eq!(quads(&[(&faces[1..], true)]), None);
    }
}
