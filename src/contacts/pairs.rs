//! What one triangle does to another: the covers a triangle parallel to it lays on its sides,
//! and the seam along which one crossing its plane meets it; and, per chunk of triangles, the
//! covers and seams the triangles near each make ([`Context::found`]).

use super::{Cover, PARALLEL, Seam, Tri, classify_seamed, cut, inside_solid, sees_nothing};
use crate::scene::Scene;
use crate::visibility::Occluder;
use crate::visibility::boxes::BoxIndex;
use glam::DVec3;

/// The covers found on a chunk of triangles, each with its surface and whether it is cut along
/// (see [`kept`]), and the seams, each with its surface.
pub(super) type Found = (Vec<(u32, Cover, bool)>, Vec<(u32, Seam)>);

/// Whether each cover `c` of triangle `t` is cut along. What a surface covers of this triangle
/// smaller than a quarter patch (a desk leg's foot on a floor) is left uncut: the mesh cannot
/// show it, and cutting it costs patches. A triangle covered whole (the foot's own bottom, on
/// the floor) needs no cut: it is kept, however small, as is any cover of a quarter of its
/// triangle or more (a lintel against a 15 cm door jamb: left uncut, the jamb's patches reach
/// into the seam and their receivers read the far side).
fn kept(t: &Tri, c: &[Cover], min_area: f64) -> Vec<bool> {
    let covered_by = |by: u32, back: bool| -> f64 {
        (c.iter().filter(|x: &&Cover| x.by == by && x.back == back))
            .map(|x| x.area)
            .sum()
    };
    let quarter = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length() / 8.0;
    c.iter()
        .map(|x| {
            let a = covered_by(x.by, x.back);
            a >= min_area || a >= quarter
        })
        .collect()
}

/// What finding contacts shares: the scene, its surfaces' areas, the gap and tolerance (m), and
/// the occluder.
pub(super) struct Context<'a> {
    pub(super) scene: &'a Scene,
    pub(super) surface_area: &'a [f64],
    pub(super) gap: f64,
    pub(super) tolerance: f64,
    pub(super) occ: &'a Occluder,
}

impl Context<'_> {
    /// Where what can cover `t` or cut it along a seam lies: within the gap of its plane, and
    /// within the gap × the tilt that still counts as parallel of its outline: its box grown
    /// by that (a desk top's box grown upward, not sideways), with margin.
    fn reach(&self, t: &Tri) -> (DVec3, DVec3) {
        let (gap, tolerance) = (self.gap, self.tolerance);
        let tilt = 0.05;
        let pad = (t.normal.abs() + DVec3::splat(tilt)).min(DVec3::ONE) * gap
            + DVec3::splat(4.0 * tolerance);
        let (lo, hi) = (
            t.p[0].min(t.p[1]).min(t.p[2]),
            t.p[0].max(t.p[1]).max(t.p[2]),
        );
        (lo - pad, hi + pad)
    }

    /// The covers and seams on the triangles of `chunk` made by the triangles near each
    /// (`index`: the boxes of `tris`).
    pub(super) fn found(&self, chunk: &[Tri], tris: &[Tri], index: &BoxIndex) -> Found {
        // Covers below the patch scale (2 × the gap is h/2) are not cut along (seams: see
        // `Context::seam`).
        let min_area = (2.0 * self.gap).powi(2);
        let (mut covers, mut seams) = (Vec::new(), Vec::new());
        let mut near = Vec::new();
        for t in chunk {
            let (lo, hi) = self.reach(t);
            index.near(lo, hi, &mut near);
            let (mut c, mut m) = (Vec::new(), Vec::new());
            for &u in &near {
                self.covers(t, &tris[u as usize], &mut c);
                self.seam(t, &tris[u as usize], &mut m);
            }
            let keep = kept(t, &c, min_area);
            covers.extend(c.into_iter().zip(keep).map(|(c, k)| (t.surface, c, k)));
            seams.extend(m.into_iter().map(|m| (t.surface, m)));
        }
        (covers, seams)
    }

    /// Surface `s` cut along its covers and seams, the pieces along seams classified; `None`
    /// when it has none, or only creases along its outer edges that part nothing.
    pub(super) fn cut_surface(
        &self,
        s: usize,
        covers: &[Cover],
        seams: &[Seam],
    ) -> Option<cut::CutSurface> {
        let (scene, gap) = (self.scene, self.gap);
        if covers.is_empty() && seams.is_empty() {
            return None;
        }
        let surface = &scene.surfaces[s];
        // Triangles shorter than a patch (8 × the gap: 2h) are covered or not as a whole.
        let mut c = cut::cut(surface, covers, seams, self.tolerance, 8.0 * gap);
        let double = scene.materials[surface.material].double_sided;
        classify_seamed(&mut c, double, self.occ);
        let copies = cut::part_creases(
            &mut c,
            if double {
                cut::FRONT | cut::BACK
            } else {
                cut::FRONT
            },
        );
        // Creases along the surface's outer edges only (a wall's foot where a room is drawn
        // with nothing under its floor): nothing was cut or parted.
        let untouched = covers.is_empty()
            && seams.iter().all(|x| x.crease)
            && copies == 0
            && c.triangles.len() == surface.triangles.len();
        (!untouched).then_some(c)
    }
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
            // Up to half the gap (h/8: a slot a quarter of the finest patch) always; wider
            // only when small beside both faces.
            let gap = self
                .gap
                .min((t.extent.min(u.extent) / 20.0).max(self.gap / 2.0));
            if heights.iter().any(|h| *h < -eps || *h > gap) {
                continue;
            }
            let edges = outline(u);
            let Some((centre, area)) = overlap_centre(t, &edges, eps) else {
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
                    // when the space just in front is inside a solid (the floor under a cube's
                    // bottom). And a face closing a solid whose front, behind `u`, sees nothing
                    // (the cube's bottom itself: below the floor no light comes from anywhere).
                    inside_solid(self.occ, centre, n).is_some()
                        || (inside_solid(self.occ, centre, -n).is_some()
                            && sees_nothing(self.occ, centre, n))
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
                depth,
                edges,
                by: u.surface,
                area,
            });
        }
    }
}

impl Context<'_> {
    /// Push the seam along which `u` (not parallel to `t`) meets `t`'s plane inside `t`: `u`
    /// touches or crosses that plane and the segment where it does has length inside `t`.
    fn seam(&self, t: &Tri, u: &Tri, out: &mut Vec<Seam>) {
        if t.surface == u.surface && t.index == u.index || t.normal.dot(u.normal).abs() >= PARALLEL
        {
            return;
        }
        let eps = self.tolerance;
        let h = u.p.map(|q| t.normal.dot(q - t.p[0]));
        if h.iter().all(|x| *x > eps) || h.iter().all(|x| *x < -eps) {
            return;
        }
        // The segment of u in t's plane: u's corners on it, and its edges crossing it.
        let mut points = Vec::with_capacity(3);
        for k in 0..3 {
            let (a, b) = (k, (k + 1) % 3);
            if h[a].abs() <= eps {
                points.push(u.p[a]);
            } else if h[b].abs() > eps && (h[a] > 0.0) != (h[b] > 0.0) {
                points.push(u.p[a] + (u.p[b] - u.p[a]) * (h[a] / (h[a] - h[b])));
            }
        }
        if points.len() < 2 {
            return;
        }
        let dir = (points[1] - points[0]).normalize_or_zero();
        if dir == DVec3::ZERO {
            return;
        }
        // The line in t's plane, and the part of the segment inside t.
        let m = t.normal.cross(dir).normalize_or_zero();
        let project = |q: DVec3| q - t.normal * t.normal.dot(q - t.p[0]);
        let (a, b) = (project(points[0]), project(points[points.len() - 1]));
        let mut seg = vec![a, b];
        for (edge_m, edge_d) in outline(t) {
            if seg.len() < 2 {
                return;
            }
            seg = clip_segment(&seg, |x| edge_m.dot(x) - edge_d, eps);
        }
        if seg.len() < 2 || seg[0].distance(seg[1]) <= eps {
            return;
        }
        // A seam matters where it bounds the inside of a solid (a block's foot): one side of it
        // just in front of t is inside, the other not. A partition standing on t with open space
        // on both sides (drawn with no thickness) is a crease: cut along, nothing covered. Along
        // t's own edges nothing is cut, but a crease there still parts the vertices.
        let line = (m, m.dot(a));
        let on_edge = t.p.iter().all(|&c| m.dot(c) - line.1 >= -eps)
            || t.p.iter().all(|&c| m.dot(c) - line.1 <= eps);
        // Only what stands in front of a side that receives light can part it.
        let double =
            self.scene.materials[self.scene.surfaces[t.surface as usize].material].double_sided;
        let in_front = h.iter().any(|x| *x > eps) || double && h.iter().any(|x| *x < -eps);
        // Below the patch scale (2 × the gap is h/2) a meeting line is not cut along; judged by
        // the whole line u meets t's plane along, not its part in t, so a partition's foot is
        // cut along through every triangle it crosses, however little of it lies in one.
        if on_edge && !in_front || a.distance(b) < 2.0 * self.gap {
            return;
        }
        let mid = (seg[0] + seg[1]) * 0.5;
        let step = (seg[0].distance(seg[1]) * 0.01).max(16.0 * self.occ.epsilon);
        let inside =
            |side: f64| inside_solid(self.occ, mid + m * (side * step), t.normal).is_some();
        let crease = match (inside(1.0), inside(-1.0)) {
            (true, true) => return,
            (false, false) if in_front => true,
            (false, false) => return,
            _ if on_edge => return,
            _ => false,
        };
        out.push(Seam {
            triangle: t.index,
            line,
            ends: [seg[0], seg[1]],
            crease,
        });
    }
}

/// The part of segment `seg` (two points) where `dist ≥ 0` (within `eps`).
fn clip_segment(seg: &[DVec3], dist: impl Fn(DVec3) -> f64, eps: f64) -> Vec<DVec3> {
    let (a, b) = (seg[0], seg[1]);
    let (da, db) = (dist(a), dist(b));
    match (da >= -eps, db >= -eps) {
        (true, true) => vec![a, b],
        (false, false) => Vec::new(),
        (true, false) => vec![a, a + (b - a) * (da / (da - db))],
        (false, true) => vec![a + (b - a) * (da / (da - db)), b],
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
fn overlap_centre(t: &Tri, edges: &[(DVec3, f64); 3], eps: f64) -> Option<(DVec3, f64)> {
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
    (area > eps * longest.max(eps)).then_some((centre, area))
}
