//! Contacts: where one surface covers another — a cube's bottom on a floor, a panel mounted on
//! a ceiling, a cabinet's back against a wall, a picture on a wall — found once per bake.
//!
//! Input: the [`Scene`], the largest gap that still counts as contact (m) and the [`Occluder`]
//! (to tell a face resting on a body from two faces back to back). Output: [`Contacts`]: per
//! surface, the [`Cover`]s of its triangles' sides. A side of triangle T is covered where
//! another triangle U, parallel to it within [`PARALLEL`], lies in front of that side no
//! further than the gap (h/4; beyond half of it, only up to a twentieth of the smaller extent of
//! T's and U's planar faces, [`faces`]), over the part of T
//! that U's outline (projected along U's normal) overlaps. Coplanar U facing the same way (a rug drawn on a floor) covers T when U's surface
//! is the smaller; coplanar U facing the other way covers T only when the space just in front
//! of T there is inside a solid (the floor under a cube's bottom: yes; the two faces of a slab
//! drawn back to back: no), or when T closes a solid (just behind it is inside one) and nothing
//! but backs is seen in front of it (the cube's bottom itself, looking below the floor). Covers
//! of less than a quarter patch are dropped unless they cover a quarter of their triangle or more.
//!
//! Where another surface meets T along a line (a [`Seam`]), T is cut along it, only over the
//! meeting segment's length: the pieces on a side whose front is inside a solid are covered (a
//! block's foot); where the surface met has open space on both sides (a zero-thickness partition
//! standing on a slab) the seam is a crease: nothing is covered, but the cut surface's vertices
//! along it are copied per side, so no value is interpolated across the partition's foot.
//!
//! Invariants: covers depend on the scene and the gap only (never on the thread count); a
//! cover's outline half-planes are computed once from U, so every triangle it cuts splits a
//! shared edge at the same point. What a cover does — cut the surface along its outline, drop
//! the covered part from light transport — is [`cut`]'s and `patches`' business.

pub mod cut;
mod faces;
mod pairs;

use crate::scene::Scene;
use crate::visibility::Occluder;
use crate::visibility::boxes::BoxIndex;
use glam::DVec3;
use pairs::{Context, Found};
use rayon::prelude::*;

/// Two triangles are parallel when their unit normals' dot product is at least this (≈ 1.1°).
pub const PARALLEL: f64 = 0.9998;

/// Where a covering triangle's outline lies on a covered triangle.
#[derive(Debug, Clone)]
pub struct Cover {
    /// The covered triangle (index into its surface's triangles).
    pub triangle: u32,
    /// The covered side is the back (of a double-sided surface).
    pub back: bool,
    /// How deep the contact is (m): from the covered side at the overlap, along its normal, to
    /// the first surface there (the cover itself across a gap; a body's far side — a framed
    /// picture's face, a cube's top — when the cover is a body's face resting on it). Light
    /// beside the outline changes over about this distance.
    pub depth: f64,
    /// Inward half-planes of the outline: a point x is under the cover when m·x ≥ d for all
    /// three (m unit, perpendicular to the covering triangle's normal).
    pub edges: [(DVec3, f64); 3],
    /// The covering surface, and the area of the covered triangle under this cover (m²).
    pub by: u32,
    pub area: f64,
}

impl Cover {
    /// Signed distance of `x` inside edge `k`'s half-plane (m).
    pub(crate) fn inside(&self, k: usize, x: DVec3) -> f64 {
        self.edges[k].0.dot(x) - self.edges[k].1
    }
}

/// Where another surface meets a triangle along a line (a block's side standing on a floor, a
/// partition on a floor, a leg through it): the triangle is cut along it, and each piece on
/// either side is covered when the space in front of it is inside a solid.
#[derive(Debug, Clone)]
pub struct Seam {
    /// The triangle met (index into its surface's triangles).
    pub triangle: u32,
    /// The line in the triangle's plane: points x with m·x = d (m unit, in the plane).
    pub line: (DVec3, f64),
    /// The ends of the meeting segment (on the line).
    pub ends: [DVec3; 2],
    /// Open space on both sides (a zero-thickness partition standing on a slab): nothing is
    /// covered, but no vertex is shared across the segment, so no value is interpolated
    /// across the partition's foot.
    pub crease: bool,
}

/// The covers of every surface, and the tolerances they were found with.
#[derive(Debug, Default)]
pub struct Contacts {
    /// Per scene surface, its covers ordered by triangle.
    pub covers: Vec<Vec<Cover>>,
    /// Per scene surface, the covers too small to cut along (a desk leg's foot on a floor),
    /// ordered by triangle: a receiver under one reads from beside it (`patches`).
    pub uncut: Vec<Vec<Cover>>,
    /// Per scene surface, its seams ordered by triangle.
    pub seams: Vec<Vec<Seam>>,
    /// Per scene surface, the surface cut along its covers and seams (`None`: untouched).
    pub cuts: Vec<Option<cut::CutSurface>>,
    /// Largest gap counted as contact (m).
    pub gap: f64,
    /// Distances below this are zero (m): coplanarity and points on outlines.
    pub tolerance: f64,
}

impl Contacts {
    /// No contacts (every surface whole).
    pub(crate) fn none() -> Self {
        Contacts::default()
    }

    /// Surface `s` cut along its contacts, when it has any.
    pub fn cut(&self, s: usize) -> Option<&cut::CutSurface> {
        self.cuts.get(s).and_then(|c| c.as_ref())
    }

    /// Total number of covers and seams.
    pub(crate) fn count(&self) -> usize {
        self.covers.iter().map(|c| c.len()).sum::<usize>()
            + self.seams.iter().map(|c| c.len()).sum::<usize>()
    }
}

/// One scene triangle, in world space.
#[derive(Clone, Copy)]
struct Tri {
    surface: u32,
    index: u32,
    p: [DVec3; 3],
    normal: DVec3,
    /// Extent of its planar face (m): see [`faces`].
    extent: f64,
}

/// Find every cover in `scene` with gaps up to `gap` (m).
pub fn find(scene: &Scene, gap: f64, occ: &Occluder) -> Contacts {
    let tolerance = 1e-6 * occ.diagonal.max(1e-300);
    let tris = triangles(scene);
    let surface_area = surface_areas(scene);
    let index = box_index(&tris, tolerance);
    let context = Context {
        scene,
        surface_area: &surface_area,
        gap,
        tolerance,
        occ,
    };
    let found: Vec<Found> = tris
        .par_chunks(1024)
        .map(|chunk| context.found(chunk, &tris, &index))
        .collect();
    let sorted = by_surface(found, scene.surfaces.len());
    let cuts = (0..scene.surfaces.len())
        .into_par_iter()
        .map(|s| context.cut_surface(s, &sorted.covers[s], &sorted.seams[s]))
        .collect();
    Contacts {
        cuts,
        gap,
        tolerance,
        ..sorted
    }
}

/// Every scene triangle with area, in surface then triangle order, with its planar face's
/// extent.
fn triangles(scene: &Scene) -> Vec<Tri> {
    let mut tris: Vec<Tri> = scene
        .surfaces
        .iter()
        .enumerate()
        .flat_map(|(s, surface)| {
            surface
                .triangles
                .iter()
                .enumerate()
                .filter_map(move |(k, t)| {
                    let p = t.map(|v| surface.positions[v as usize]);
                    let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                    (normal != DVec3::ZERO).then_some(Tri {
                        surface: s as u32,
                        index: k as u32,
                        p,
                        normal,
                        extent: 0.0,
                    })
                })
        })
        .collect();
    // A gap wider than h/8 counts as contact only when small beside both faces (a twentieth of
    // the smaller one's extent): a panel 3 cm under a ceiling, not a shelf 30 cm above a desk,
    // nor a monitor's back 12 cm behind its screen in a mesh drawing a row of monitors.
    let extents = faces::extents(&tris);
    for (t, e) in tris.iter_mut().zip(extents) {
        t.extent = e;
    }
    tris
}

/// Each scene surface's area (m²): which of two coplanar surfaces is on top.
fn surface_areas(scene: &Scene) -> Vec<f64> {
    scene
        .surfaces
        .iter()
        .map(|s| {
            s.triangles
                .iter()
                .map(|t| {
                    let p = t.map(|v| s.positions[v as usize]);
                    (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0
                })
                .sum()
        })
        .collect()
}

/// An index of the triangles' boxes, each grown by `tolerance`.
fn box_index(tris: &[Tri], tolerance: f64) -> BoxIndex {
    BoxIndex::new(
        (tris.iter())
            .map(|t| {
                let pad = DVec3::splat(tolerance);
                let (lo, hi) = (
                    t.p[0].min(t.p[1]).min(t.p[2]),
                    t.p[0].max(t.p[1]).max(t.p[2]),
                );
                (lo - pad, hi + pad)
            })
            .collect(),
    )
}

/// The found covers and seams sorted per surface (covers cut along, covers left uncut, seams;
/// no cuts yet). Chunks come in triangle order and triangles in surface order: each list stays
/// sorted by triangle.
fn by_surface(found: Vec<Found>, surfaces: usize) -> Contacts {
    let mut covers: Vec<Vec<Cover>> = vec![Vec::new(); surfaces];
    let mut uncut: Vec<Vec<Cover>> = vec![Vec::new(); surfaces];
    let mut seams: Vec<Vec<Seam>> = vec![Vec::new(); surfaces];
    for (c, m) in found {
        for (s, c, kept) in c {
            match kept {
                true => covers[s as usize].push(c),
                false => uncut[s as usize].push(c),
            }
        }
        for (s, m) in m {
            seams[s as usize].push(m);
        }
    }
    Contacts {
        covers,
        uncut,
        seams,
        ..Contacts::none()
    }
}

/// Whether the space just in front of `p` (on a surface with unit normal `n`) is inside a solid,
/// and if so how far the solid reaches along `n` (m). Five rays — along `n` and four at 45° to
/// it — each ask whether the first surface met shows its back; three backs make it inside, and
/// so do two opposite tilted rays both meeting backs: the slot inside a thick wall drawn as two
/// faces without end caps, which abuts another wall (a partition's end against a façade), is
/// closed by the other walls' fronts. One ray is not enough: where two faces coincide (a leg's
/// top against a desk top's underside) the first hit may be either.
fn inside_solid(occ: &Occluder, p: DVec3, n: DVec3) -> Option<f64> {
    let start = p + n * (4.0 * occ.epsilon);
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let dirs = [n, n + u, n - u, n + v, n - v].map(|d| d.normalize());
    let mut back = [false; 5];
    let mut depth = f64::INFINITY;
    for (k, d) in dirs.into_iter().enumerate() {
        if let Some(hit) = first_back(occ, start, d) {
            back[k] = true;
            depth = depth.min(hit * d.dot(n) + 4.0 * occ.epsilon);
        }
    }
    let backs = back.iter().filter(|b| **b).count();
    (backs >= 3 || (back[1] && back[2]) || (back[3] && back[4])).then_some(depth)
}

/// Distance (m) to the first surface a ray from `start` along unit `d` meets when that surface
/// shows its back. A back and a front in one plane (two solids abutting: a wall box's end
/// against another's side, a wall's top under a ceiling slab) count as the back: the ray passes
/// from one solid into the next and is still inside.
fn first_back(occ: &Occluder, start: DVec3, d: DVec3) -> Option<f64> {
    let back = occ.closest_back(start, d)?.distance;
    match occ.closest_front(start, d) {
        Some(front) if front.distance + 2.0 * occ.epsilon < back => None,
        _ => Some(back),
    }
}

/// Whether nothing but backs of surfaces is seen from just in front of `p` (unit normal `n`):
/// the five rays of [`inside_solid`] each escape or meet a back face.
fn sees_nothing(occ: &Occluder, p: DVec3, n: DVec3) -> bool {
    let start = p + n * (4.0 * occ.epsilon);
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    [n, n + u, n - u, n + v, n - v]
        .map(|d| d.normalize())
        .iter()
        .all(|&d| occ.closest(start, d).is_none_or(|h| h.normal.dot(d) > 0.0))
}

/// Pieces cut along seams are covered on a side when the space just in front of it is inside a
/// solid (a block's inside); the contact's depth is how far the solid reaches.
fn classify_seamed(c: &mut cut::CutSurface, double: bool, occ: &Occluder) {
    for i in 0..c.triangles.len() {
        if !c.seamed[i] {
            continue;
        }
        let p = c.triangles[i].map(|v| c.positions[v as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let centre = (p[0] + p[1] + p[2]) / 3.0;
        for (bit, n) in [(cut::FRONT, normal), (cut::BACK, -normal)] {
            if (bit == cut::BACK && !double) || c.covered[i] & bit != 0 {
                continue;
            }
            if let Some(depth) = inside_solid(occ, centre, n) {
                c.covered[i] |= bit;
                c.gap[i] = c.gap[i].max(depth);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::visibility::OccluderOptions;

    /// Area of a cut surface's triangles, all and covered on the front.
    fn areas(c: &cut::CutSurface) -> (f64, f64) {
        let (mut all, mut covered) = (0.0, 0.0);
        for (t, m) in c.triangles.iter().zip(&c.covered) {
            let p = t.map(|v| c.positions[v as usize]);
            let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
            all += a;
            if m & cut::FRONT != 0 {
                covered += a;
            }
        }
        (all, covered)
    }

    /// A 4 × 4 m floor (two triangles sharing no vertex index, +Y up) under a closed room, and
    /// what `extra` adds.
    fn floor_room(extra: impl FnOnce(&mut SceneBuilder, usize)) -> (Scene, Contacts) {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        let c = |x: f64, z: f64| DVec3::new(x, 0.0, z);
        let (p, q, r, s) = (c(0.0, 0.0), c(0.0, 4.0), c(4.0, 4.0), c(4.0, 0.0));
        b.surface(
            "floor",
            vec![p, q, r, p, r, s],
            vec![DVec3::Y; 6],
            vec![[0, 1, 2], [3, 4, 5]],
            grey,
        );
        let faces = crate::fixtures::box_faces(DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0));
        for (k, f) in faces.iter().enumerate().skip(1) {
            b.quad(&format!("room_{k}"), *f, grey);
        }
        extra(&mut b, grey);
        let scene = b.build();
        let occ = Occluder::build(&scene, OccluderOptions::default());
        let contacts = find(&scene, 0.05, &occ);
        (scene, contacts)
    }

    /// Every vertex of `c` lying inside an edge of one of its triangles (a T-junction).
    fn t_junctions(c: &cut::CutSurface) -> usize {
        let mut n = 0;
        for t in &c.triangles {
            for k in 0..3 {
                let (a, b) = (
                    c.positions[t[k] as usize],
                    c.positions[t[(k + 1) % 3] as usize],
                );
                let d = b - a;
                for p in c
                    .triangles
                    .iter()
                    .flatten()
                    .map(|&v| c.positions[v as usize])
                {
                    let s = (p - a).dot(d) / d.length_squared();
                    if s > 1e-9 && s < 1.0 - 1e-9 && (a + d * s).distance(p) < 1e-9 {
                        n += 1;
                    }
                }
            }
        }
        n
    }

    #[test]
    fn a_turned_block_on_a_floor_covers_its_footprint_exactly_without_t_junctions() {
        // A 0.6 m cube turned 30° about +Y, standing on the floor (its bottom face on it), and
        // a 0.5 × 0.8 m block without a bottom face (a seam): both footprints are covered.
        let (_, contacts) = floor_room(|b, grey| {
            let turn = glam::DQuat::from_rotation_y(30f64.to_radians());
            let at = |p: DVec3| turn * (p - DVec3::splat(0.3)) + DVec3::new(1.2, 0.3, 1.3);
            for (k, f) in crate::fixtures::box_faces(DVec3::ZERO, DVec3::splat(0.6))
                .iter()
                .enumerate()
            {
                b.quad(&format!("cube_{k}"), [f[0], f[3], f[2], f[1]].map(at), grey);
            }
            let faces =
                crate::fixtures::box_faces(DVec3::new(2.5, 0.0, 2.5), DVec3::new(3.0, 1.0, 3.3));
            for (k, f) in faces.iter().enumerate().skip(1) {
                b.quad(&format!("block_{k}"), [f[0], f[3], f[2], f[1]], grey);
            }
        });
        let floor = contacts.cut(0).expect("the floor is cut");
        let (all, covered) = areas(floor);
        assert!((all - 16.0).abs() < 1e-9, "the cut floor's area {all}");
        let want = 0.36 + 0.5 * 0.8;
        assert!(
            (covered - want).abs() < 1e-9,
            "covered {covered} m², footprints {want}"
        );
        assert_eq!(t_junctions(floor), 0);
        assert!(!contacts.seams[0].is_empty() && !contacts.covers[0].is_empty());
        // The cube's bottom face is covered by the floor too: below the floor nothing is seen.
        // Surfaces: the floor, five room faces, then the cube's bottom (box_faces' first).
        let bottom = contacts.cut(6).expect("the cube's bottom is cut");
        let (all, covered) = areas(bottom);
        assert!(
            (covered - all).abs() < 1e-9 && (all - 0.36).abs() < 1e-9,
            "{all} {covered}"
        );
    }

    #[test]
    fn a_gap_above_an_eighth_patch_is_a_contact_only_beside_small_faces() {
        // One mesh of three 0.3 m plates facing down over the floor (h = 0.2 m: contact gaps up
        // to h/4 = 0.05 m, and beyond h/8 only within a twentieth of the smaller flat face): at
        // 0.02 m (below h/8: covers), at 0.04 m (0.3 m plate: 0.021 m, no contact, though the
        // mesh spans 3 m), and a 1.2 m plate at 0.04 m (its face's twentieth is 0.085 m: covers).
        let (_, contacts) = floor_room(|b, grey| {
            let plate = |x: f64, y: f64, s: f64| {
                let c = |dx: f64, dz: f64| DVec3::new(x + dx, y, 0.5 + dz);
                [c(0.0, 0.0), c(s, 0.0), c(s, s), c(0.0, s)]
            };
            let quads = [
                plate(0.3, 0.02, 0.3),
                plate(3.3, 0.04, 0.3),
                plate(1.2, 0.04, 1.2),
            ];
            let positions: Vec<DVec3> = quads.iter().flatten().copied().collect();
            let triangles = (0..3u32)
                .flat_map(|k| [[4 * k, 4 * k + 1, 4 * k + 2], [4 * k, 4 * k + 2, 4 * k + 3]])
                .collect();
            let n = positions.len();
            b.surface("plates", positions, vec![-DVec3::Y; n], triangles, grey);
        });
        let floor = contacts.cut(0).expect("the floor is cut");
        let (_, covered) = areas(floor);
        let want = 0.3 * 0.3 + 1.2 * 1.2;
        assert!(
            (covered - want).abs() < 1e-9,
            "covered {covered} m², want {want}"
        );
    }

    #[test]
    fn a_hollow_partition_between_two_walls_covers_the_strips_inside_it() {
        // A 0.1 m partition across the room, drawn as its two big faces only (no end caps, no
        // top or bottom: the walls, floor and ceiling close it). The space between the faces is
        // inside it: where it meets the floor, the ceiling and both end walls, a strip is cut and
        // covered; the seam test's three-backs rule alone sees two backs there.
        let (_, contacts) = floor_room(|b, grey| {
            let faces =
                crate::fixtures::box_faces(DVec3::new(0.0, 0.0, 2.0), DVec3::new(4.0, 3.0, 2.1));
            for (k, f) in faces.iter().enumerate().skip(4) {
                b.quad(&format!("partition_{k}"), [f[0], f[3], f[2], f[1]], grey);
            }
        });
        // Surfaces: the floor, then the room's ceiling, walls at x = 0 and x = 4, z = 0, z = 4.
        for (s, want) in [(0, 0.4), (1, 0.4), (2, 0.3), (3, 0.3)] {
            let cut = contacts.cut(s).expect("cut along the partition");
            let (_, covered) = areas(cut);
            assert!(
                (covered - want).abs() < 1e-9,
                "surface {s}: covered {covered} m², want {want}"
            );
            assert_eq!(t_junctions(cut), 0);
        }
        for s in [4, 5] {
            assert!(contacts.cut(s).is_none(), "surface {s} is not touched");
        }
    }

    #[test]
    fn the_floor_under_two_wall_boxes_meeting_at_a_corner_is_covered_to_the_corner() {
        // Two 0.12 m wall boxes in an L (the second's end against the first's side) up to the
        // ceiling, as CAD exports outer walls: in the corner square every ray from the floor
        // meets a back and a front in one plane (box against box, box top against ceiling).
        // Both feet are covered, the corner square included (it was left lit: the building's
        // balance 1.7·10⁻⁴ at ρ 0.9).
        let (_, contacts) = floor_room(|b, grey| {
            b.axis_box(
                "south",
                DVec3::ZERO,
                DVec3::new(4.0, 3.0, 0.12),
                false,
                grey,
            );
            b.axis_box(
                "west",
                DVec3::new(0.0, 0.0, 0.12),
                DVec3::new(0.12, 3.0, 4.0),
                false,
                grey,
            );
        });
        let floor = contacts.cut(0).expect("the floor is cut");
        let (all, covered) = areas(floor);
        let want = 4.0 * 0.12 + 0.12 * 3.88;
        assert!((all - 16.0).abs() < 1e-9, "the cut floor's area {all}");
        assert!(
            (covered - want).abs() < 1e-9,
            "covered {covered} m², the feet {want}"
        );
    }

    #[test]
    fn a_slab_drawn_as_two_faces_back_to_back_covers_nothing() {
        // A mezzanine: its top (facing +Y) and underside (facing −Y) drawn at one height, and a
        // rug lying on its top (coplanar, facing the same way, smaller: on top).
        let (scene, contacts) = floor_room(|b, grey| {
            let c = |x: f64, z: f64| DVec3::new(x, 1.5, z);
            let (p, q, r, s) = (c(1.0, 1.0), c(1.0, 3.0), c(3.0, 3.0), c(3.0, 1.0));
            b.quad("slab_top", [p, q, r, s], grey);
            b.quad("slab_underside", [p, s, r, q], grey);
            let c = |x: f64, z: f64| DVec3::new(x, 1.5, z);
            b.quad(
                "rug",
                [c(1.5, 1.5), c(1.5, 2.5), c(2.5, 2.5), c(2.5, 1.5)],
                grey,
            );
        });
        let named = |n: &str| {
            scene
                .nodes
                .iter()
                .position(|x| x.name.as_deref() == Some(n))
                .unwrap()
        };
        let surface = |n: &str| scene.nodes[named(n)].surfaces[0];
        assert!(contacts.covers[surface("slab_underside")].is_empty());
        assert!(contacts.covers[surface("rug")].is_empty());
        let top = contacts
            .cut(surface("slab_top"))
            .expect("the rug covers the slab's top");
        assert!((areas(top).1 - 1.0).abs() < 1e-9, "{:?}", areas(top));
    }
}
