//! Contacts: where one surface covers another — a cube's bottom on a floor, a panel mounted on
//! a ceiling, a cabinet's back against a wall, a picture on a wall — found once per bake.
//!
//! Input: the [`Scene`], the largest gap that still counts as contact (m) and the [`Occluder`]
//! (to tell a face resting on a body from two faces back to back). Output: [`Contacts`]: per
//! surface, the [`Cover`]s of its triangles' sides. A side of triangle T is covered where
//! another triangle U, parallel to it within [`PARALLEL`], lies in front of that side no
//! further than the gap, over the part of T that U's outline (projected along U's normal)
//! overlaps. Coplanar U facing the same way (a rug drawn on a floor) covers T when U's surface
//! is the smaller; coplanar U facing the other way covers T only when the space just in front
//! of T there is inside a solid (a cube's bottom on a floor: yes; the two faces of a slab drawn
//! back to back: no).
//!
//! Invariants: covers depend on the scene and the gap only (never on the thread count); a
//! cover's outline half-planes are computed once from U, so every triangle it cuts splits a
//! shared edge at the same point. What a cover does — cut the surface along its outline, drop
//! the covered part from light transport — is [`cut`]'s and `patches`' business.

pub mod cut;
mod grid;

use crate::scene::Scene;
use crate::visibility::Occluder;
use glam::DVec3;
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
    /// The covered triangle's plane: unit normal n (of its front) and offset, n·x = offset.
    pub plane: (DVec3, f64),
    /// How deep the contact is (m): from the covered side at the overlap, along its normal, to
    /// the first surface there (the cover itself across a gap; a body's far side — a framed
    /// picture's face, a cube's top — when the cover is a body's face resting on it). Light
    /// beside the outline changes over about this distance.
    pub depth: f64,
    /// Inward half-planes of the outline: a point x is under the cover when m·x ≥ d for all
    /// three (m unit, perpendicular to the covering triangle's normal).
    pub edges: [(DVec3, f64); 3],
}

impl Cover {
    /// Signed distance of `x` inside edge `k`'s half-plane (m).
    pub fn inside(&self, k: usize, x: DVec3) -> f64 {
        self.edges[k].0.dot(x) - self.edges[k].1
    }
}

/// The covers of every surface, and the tolerances they were found with.
#[derive(Debug, Default)]
pub struct Contacts {
    /// Per scene surface, its covers ordered by triangle.
    pub covers: Vec<Vec<Cover>>,
    /// Largest gap counted as contact (m).
    pub gap: f64,
    /// Distances below this are zero (m): coplanarity and points on outlines.
    pub tolerance: f64,
}

impl Contacts {
    /// No contacts (every surface whole).
    pub fn none() -> Self {
        Contacts::default()
    }

    /// The covers of surface `s`.
    pub fn of(&self, s: usize) -> &[Cover] {
        self.covers.get(s).map_or(&[], |c| c.as_slice())
    }

    /// Total number of covers.
    pub fn count(&self) -> usize {
        self.covers.iter().map(|c| c.len()).sum()
    }
}

/// One scene triangle, in world space.
#[derive(Clone, Copy)]
struct Tri {
    surface: u32,
    index: u32,
    p: [DVec3; 3],
    normal: DVec3,
}

/// Find every cover in `scene` with gaps up to `gap` (m).
pub fn find(scene: &Scene, gap: f64, occ: &Occluder) -> Contacts {
    let tolerance = 1e-6 * occ.diagonal.max(1e-300);
    let tris: Vec<Tri> = scene
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
                    })
                })
        })
        .collect();
    let surface_area: Vec<f64> = scene
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
        .collect();
    let grid = grid::Grid::new(
        &tris.iter().map(|t| t.p).collect::<Vec<_>>(),
        gap + tolerance,
    );
    let context = Context {
        scene,
        surface_area: &surface_area,
        gap,
        tolerance,
        occ,
    };
    let found: Vec<Vec<(u32, Cover)>> = tris
        .par_chunks(1024)
        .map(|chunk| {
            let mut out = Vec::new();
            let mut near = Vec::new();
            for t in chunk {
                grid.near(t.p, &mut near);
                let mut mine = Vec::new();
                for &u in &near {
                    context.covers(t, &tris[u as usize], &mut mine);
                }
                out.extend(mine.into_iter().map(|c| (t.surface, c)));
            }
            out
        })
        .collect();
    // Chunks come in triangle order and triangles in surface order: covers stay sorted.
    let mut covers: Vec<Vec<Cover>> = vec![Vec::new(); scene.surfaces.len()];
    for (s, c) in found.into_iter().flatten() {
        covers[s as usize].push(c);
    }
    Contacts {
        covers,
        gap,
        tolerance,
    }
}

struct Context<'a> {
    scene: &'a Scene,
    surface_area: &'a [f64],
    gap: f64,
    tolerance: f64,
    occ: &'a Occluder,
}

impl Context<'_> {
    /// Push the covers `u` makes on the sides of `t`.
    fn covers(&self, t: &Tri, u: &Tri, out: &mut Vec<Cover>) {
        if (t.surface, t.index) == (u.surface, u.index) || t.normal.dot(u.normal).abs() < PARALLEL {
            return;
        }
        let double =
            self.scene.materials[self.scene.surfaces[t.surface as usize].material].double_sided;
        let eps = self.tolerance;
        for back in [false, true] {
            if back && !double {
                continue;
            }
            let n = if back { -t.normal } else { t.normal };
            let heights = u.p.map(|q| n.dot(q - t.p[0]));
            if heights.iter().any(|h| *h < -eps || *h > self.gap) {
                continue;
            }
            let edges = outline(u);
            let Some(centre) = overlap_centre(t, &edges, eps) else {
                continue;
            };
            let start = centre + n * (4.0 * self.occ.epsilon);
            let hit = self.occ.closest(start, n);
            if heights.iter().all(|h| h.abs() <= eps) {
                let covers = if u.normal.dot(n) > 0.0 {
                    // Drawn on top of each other: the smaller surface is the one on top.
                    let (a, b) = (
                        self.surface_area[u.surface as usize],
                        self.surface_area[t.surface as usize],
                    );
                    a < b || (a == b && (u.surface, u.index) > (t.surface, t.index))
                } else {
                    // Face to face, or back to back (a slab drawn as two faces)? Face to face
                    // when the space just in front is inside a solid: the first surface a ray
                    // from there meets shows it its back.
                    hit.is_some_and(|hit| hit.normal.dot(n) > 0.0)
                };
                if !covers {
                    continue;
                }
            }
            let top = heights.iter().fold(0.0, |a: f64, h| a.max(*h));
            let depth = hit.map_or(top, |hit| hit.distance + 4.0 * self.occ.epsilon);
            out.push(Cover {
                triangle: t.index,
                back,
                plane: (t.normal, t.normal.dot(t.p[0])),
                depth,
                edges,
            });
        }
    }
}

/// The inward half-planes of `u`'s outline along its normal.
fn outline(u: &Tri) -> [(DVec3, f64); 3] {
    std::array::from_fn(|k| {
        let (a, b) = (u.p[k], u.p[(k + 1) % 3]);
        let m = u.normal.cross(b - a).normalize_or_zero();
        (m, m.dot(a))
    })
}

/// The centroid of the part of `t` inside the half-planes, when that part has area (more than
/// a sliver `eps` wide).
fn overlap_centre(t: &Tri, edges: &[(DVec3, f64); 3], eps: f64) -> Option<DVec3> {
    let mut poly: Vec<DVec3> = t.p.to_vec();
    for (m, d) in edges {
        poly = cut::clip(&poly, |x| m.dot(x) - d, eps).0;
        if poly.len() < 3 {
            return None;
        }
    }
    let (area, centre) = cut::area_centroid(&poly, t.normal);
    let longest = (0..poly.len())
        .map(|k| (poly[k] - poly[(k + 1) % poly.len()]).length())
        .fold(0.0, f64::max);
    (area > eps * longest.max(eps)).then_some(centre)
}
