//! Settling a group of luminaires at once: what can be proved of every shadow ray from a few
//! points to a box (the group's openings) without tracing them one by one.
//!
//! Input: the occluder's BVH and triangles, the ray starts (already pulled off their surfaces)
//! and the box. Output: `Some(true)` all clear, `Some(false)` all blocked, `None` not proved.
//! Invariant: an answer is only given when [`Occluder::clear`] would give it for every such ray
//! (a margin above f32 rounding and the ray–triangle slack), so grouping cannot change what a
//! luminaire's own rays find; the answer does not depend on the BVH's layout.

use super::hull::{Hull, MARGIN, convex_hull_2d, inside_2d, segment_meets_polygon, tri64};
use super::{BVH_DIAGONAL, Occluder, Tracer, as_vec3a, intersect};
use glam::{DVec2, DVec3, UVec2, Vec3A};
use obvhs::{
    aabb::Aabb,
    cwbvh::node::{CwBvhNode, extract_byte64},
    ray::Ray,
    traverse,
};

impl Tracer {
    /// Visit the triangles (BVH order) whose boxes may meet the region that `meets` accepts
    /// (a conservative box test), until `visit` returns false.
    fn each_near(
        &self,
        towards: Vec3A,
        meets: impl Fn(&Aabb) -> bool,
        mut visit: impl FnMut(usize) -> bool,
    ) {
        let Some(bvh) = &self.bvh else { return };
        let mut state = bvh.new_traversal(towards);
        let mut node: &CwBvhNode;
        'outer: {
            traverse!(
                bvh,
                node,
                state,
                child_hits(node, state.oct_inv4, &meets),
                {
                    if !visit(state.primitive_id as usize) {
                        break 'outer;
                    }
                }
            );
        }
    }
}

/// The hit mask of a wide BVH node's children whose boxes `meets` accepts (as
/// `CwBvhNode::intersect_aabb` builds it).
fn child_hits(node: &CwBvhNode, oct_inv4: u32, meets: &impl Fn(&Aabb) -> bool) -> u32 {
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut mask = 0;
    for child in 0..8 {
        if !node.is_child_empty(child) && meets(&node.child_aabb(child)) {
            mask |= extract_byte64(child_bits8, child) << extract_byte64(bit_index8, child);
        }
    }
    mask
}

impl Occluder {
    /// What can be proved of the segments from the points `starts` (already pulled off their
    /// surfaces) to every point of the box `[lo, hi]` (a group's luminaire openings, m):
    /// `Some(true)` when no triangle meets their convex hull, so [`Occluder::clear`] would find
    /// every one of them clear; `Some(false)` when one plane of triangles, with no edge of its
    /// own inside the hull's cross-section, separates the starts from the box, so every one is
    /// blocked; `None` otherwise. Both proofs keep a margin of 5·10⁻⁷ of the scene's diagonal
    /// against the f32 rounding and the slack of the ray–triangle test; the answer does not
    /// depend on the BVH's layout.
    pub fn settle(&self, starts: &[DVec3], lo: DVec3, hi: DVec3) -> Option<bool> {
        // As in `clear`: the shell cannot block segments between points inside it.
        let inner = starts
            .iter()
            .chain(&box_corners(lo, hi))
            .all(|p| self.inside_shell(*p));
        // Segments that leave the shell are left to the rays (the proofs read one tracer).
        if !inner && self.on_shell.bvh.is_some() {
            return None;
        }
        let tracer = &self.interior;
        let Some(bvh) = tracer.bvh.as_ref() else {
            // Nothing can block.
            return Some(true);
        };
        let m = |p: DVec3| (p - self.center) * self.scale;
        let starts: Vec<DVec3> = starts.iter().map(|p| m(*p)).collect();
        let corners = box_corners(m(lo), m(hi));
        // First one ray to the box's centre, inside the hull: a triangle on it rules out
        // "seen" and names the planes that may prove "hidden"; none rules out "hidden".
        let (from, to) = (starts[0], (corners[0] + corners[7]) * 0.5);
        let ray = segment(from, to)?;
        self.rays.add();
        let mut hits: Vec<(f32, u32, usize)> = Vec::new();
        bvh.ray_traverse_anyhit(ray, |r, id| {
            let t = intersect(&tracer.triangles[id], r);
            if t <= r.tmax {
                hits.push((t, tracer.ids[id], id));
            }
        });
        // Rays to the box's corners: one that disagrees with the centre's means a shadow edge
        // crosses the group and the proof the centre points to must fail; a few rays decide
        // that sooner than the proof does (both proofs cost many triangle tests on big scenes).
        let blocked = !hits.is_empty();
        for (k, c) in corners.iter().enumerate() {
            if corners[..k].contains(c) {
                continue;
            }
            let ray = segment(from, *c)?;
            self.rays.add();
            if tracer.miss(ray) == blocked {
                return None;
            }
        }
        if blocked {
            // Nearest first, ties by input index (layout-free).
            hits.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            return self
                .hidden_behind_a_plane(tracer, &hits, &starts, &corners)
                .then_some(false);
        }
        let hull = Hull::new(&starts, &corners);
        let mut blocked = false;
        tracer.each_near(
            as_vec3a(to - from),
            |b| hull.meets_box(b),
            |id| {
                blocked = hull.meets_triangle(&tracer.triangles[id]);
                !blocked
            },
        );
        (!blocked).then_some(true)
    }

    /// Whether the plane of one of the triangles `hits` (on the segment from the first start to
    /// the box's centre, nearest first; BVH units) provably hides the whole box from every start.
    fn hidden_behind_a_plane(
        &self,
        tracer: &Tracer,
        hits: &[(f32, u32, usize)],
        starts: &[DVec3],
        corners: &[DVec3; 8],
    ) -> bool {
        let mut tried: Vec<(DVec3, f64)> = Vec::new();
        for &(_, _, id) in hits {
            let t = tri64(&tracer.triangles[id]);
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
            let d = n.dot(t[0]);
            let same = |(m, e): &(DVec3, f64)| {
                m.dot(n).abs() > 1.0 - 1e-12 && (e - d * m.dot(n).signum()).abs() <= COPLANAR
            };
            if n == DVec3::ZERO || tried.iter().any(same) {
                continue;
            }
            if tried.len() == HIDDEN_PLANES {
                break;
            }
            tried.push((n, d));
            if self.plane_hides(tracer, n, d, starts, corners) {
                return true;
            }
        }
        false
    }

    /// Whether the triangles on the plane n·x = d (BVH units) hide every point of the box from
    /// every start: the plane separates them, and the triangles lying on it cover the hull's
    /// cross-section with no edge of their own inside it (so a segment through it crosses them).
    fn plane_hides(
        &self,
        tracer: &Tracer,
        n: DVec3,
        d: f64,
        starts: &[DVec3],
        corners: &[DVec3; 8],
    ) -> bool {
        let flip = if n.dot(starts[0]) - d >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let (n, d) = (n * flip, d * flip);
        let side = |p: DVec3| n.dot(p) - d;
        let eps = self.epsilon * self.scale;
        let far = corners
            .iter()
            .map(|c| side(*c))
            .fold(f64::NEG_INFINITY, f64::max);
        for &a in starts {
            // A shadow ray stops ε short of its luminaire: its end must lie beyond the plane too.
            let near = box_distance(a, corners[0], corners[7]);
            if side(a) < MARGIN
                || near <= eps
                || side(a) * eps / near + far * (1.0 - eps / near) > -MARGIN
            {
                return false;
            }
        }
        // The cross-section: where the segments from the starts to the corners meet the plane.
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let mut section = Vec::with_capacity(starts.len() * 8);
        let mut steepest_cot = 0.0f64;
        for &a in starts {
            for &c in corners {
                let (sa, sc) = (side(a), side(c));
                let x = a + (c - a) * (sa / (sa - sc));
                section.push(x);
                let sin = (sa - sc) / (c - a).length();
                steepest_cot = steepest_cot.max((1.0 - sin * sin).max(0.0).sqrt() / sin);
            }
        }
        // Triangles within COPLANAR of the plane count as on it; a ray may then cross one of
        // them up to COPLANAR·cot θ away from where it meets the plane.
        let reach = MARGIN + COPLANAR * steepest_cot;
        if !reach.is_finite() {
            return false;
        }
        let flat = |p: DVec3| DVec2::new(u.dot(p), v.dot(p));
        let polygon = convex_hull_2d(section.iter().map(|p| flat(*p)).collect());
        if polygon.len() < 3 {
            return false;
        }
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &section {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let grow = DVec3::splat(reach + COPLANAR);
        let query = Aabb::new(as_vec3a(lo - grow), as_vec3a(hi + grow));
        let mut on: Vec<[DVec3; 3]> = Vec::new();
        let mut too_many = false;
        // Only boxes that reach the plane can hold a triangle lying on it (a floor finely
        // tessellated next to a wall would otherwise be visited triangle by triangle).
        let reaches_plane = |b: &Aabb| {
            let (bl, bh) = (b.min.as_dvec3(), b.max.as_dvec3());
            let (c, h) = ((bl + bh) * 0.5, (bh - bl) * 0.5);
            (side(c)).abs() <= n.abs().dot(h) + COPLANAR
        };
        tracer.each_near(
            as_vec3a(-n),
            |b| b.intersect_aabb(&query) && reaches_plane(b),
            |id| {
                let t = tri64(&tracer.triangles[id]);
                if t.iter().all(|p| side(*p).abs() <= COPLANAR) {
                    on.push(t);
                    too_many = on.len() > MAX_COVER;
                }
                !too_many
            },
        );
        if too_many || on.is_empty() {
            return false;
        }
        union_covers(&on, (u, v), &polygon, reach)
    }
}

/// Whether the union of the triangles `on` (lying on the plane spanned by `u`, `v`) covers the
/// convex `polygon`: one point of it is covered and no edge of the union (an edge not shared
/// with a triangle on its other side) comes within `reach` of it.
fn union_covers(on: &[[DVec3; 3]], (u, v): (DVec3, DVec3), polygon: &[DVec2], reach: f64) -> bool {
    let flat = |p: DVec3| DVec2::new(u.dot(p), v.dot(p));
    let centre = polygon.iter().copied().sum::<DVec2>() / polygon.len() as f64;
    if !on.iter().any(|t| inside_2d(t.map(flat), centre)) {
        return false;
    }
    let key = |p: DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut edges: Vec<([[u64; 3]; 2], f64, DVec2, DVec2)> = Vec::with_capacity(on.len() * 3);
    for t in on {
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let (a, b) = if key(a) <= key(b) { (a, b) } else { (b, a) };
            let (fa, fb) = (flat(a), flat(b));
            let turn = (fb - fa).perp_dot(flat(c) - fa).signum();
            edges.push(([key(a), key(b)], turn, fa, fb));
        }
    }
    edges.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            j += 1;
        }
        let shared = j - i == 2 && edges[i].1 * edges[i + 1].1 < 0.0;
        if !shared
            && edges[i..j]
                .iter()
                .any(|e| segment_meets_polygon(e.2, e.3, polygon, reach))
        {
            return false;
        }
        i = j;
    }
    true
}

/// Distance (BVH units) within which a triangle's corners count as lying on a plane.
const COPLANAR: f64 = 1e-7 * BVH_DIAGONAL;

/// Planes tried to prove a group hidden.
const HIDDEN_PLANES: usize = 4;

/// Most triangles on a plane examined to prove that they cover a cross-section.
const MAX_COVER: usize = 256;

/// The corners of the box `[lo, hi]` (bit k of the index picks `hi` along axis k).
fn box_corners(lo: DVec3, hi: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The ray along the segment from `a` to `b` (BVH units); `None` when they coincide.
fn segment(a: DVec3, b: DVec3) -> Option<Ray> {
    let len = (b - a).length();
    (len > 0.0).then(|| Ray::new(as_vec3a(a), as_vec3a((b - a) / len), 0.0, len as f32))
}

/// Distance from `p` to the box `[lo, hi]`.
fn box_distance(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length()
}

#[cfg(test)]
mod tests {
    use super::super::OccluderOptions;
    use super::super::tests::{quad_surface, scene_with};
    use super::*;

    /// A floor 20 m square at y = 0 (glTF +Y up), a far post that keeps the scene non-convex,
    /// and `blockers` (quads, each two triangles).
    fn settle_scene(blockers: &[[DVec3; 4]]) -> Occluder {
        let mut surfaces = vec![
            quad_surface([
                DVec3::new(-10.0, 0.0, 10.0),
                DVec3::new(10.0, 0.0, 10.0),
                DVec3::new(10.0, 0.0, -10.0),
                DVec3::new(-10.0, 0.0, -10.0),
            ]),
            quad_surface([
                DVec3::new(9.0, 0.0, 9.0),
                DVec3::new(9.0, 0.0, 8.0),
                DVec3::new(9.0, 2.0, 8.0),
                DVec3::new(9.0, 2.0, 9.0),
            ]),
        ];
        surfaces.extend(blockers.iter().map(|q| quad_surface(*q)));
        Occluder::build(&scene_with(surfaces), OccluderOptions::default())
    }

    /// A horizontal quad at height `y` over x ∈ [x0, x1], z ∈ [z0, z1].
    fn flat(y: f64, x0: f64, x1: f64, z0: f64, z1: f64) -> [DVec3; 4] {
        [
            DVec3::new(x0, y, z0),
            DVec3::new(x1, y, z0),
            DVec3::new(x1, y, z1),
            DVec3::new(x0, y, z1),
        ]
    }

    /// A group's box 3 m above the origin, 2 m wide, seen from the floor's origin.
    fn settle_group(occ: &Occluder) -> Option<bool> {
        let start = DVec3::Y * occ.epsilon;
        occ.settle(
            &[start],
            DVec3::new(-1.0, 3.0, -1.0),
            DVec3::new(1.0, 3.0, 1.0),
        )
    }

    #[test]
    fn a_group_is_seen_only_when_nothing_meets_its_hull() {
        // A blocker beside the hull (which spans |x|, |z| ≤ y/3 at height y): seen.
        let occ = settle_scene(&[flat(1.5, 0.6, 2.0, -2.0, 2.0)]);
        assert_eq!(settle_group(&occ), Some(true));
        // The same blocker reaching 5 cm into it: not seen, not hidden.
        let occ = settle_scene(&[flat(1.5, 0.45, 2.0, -2.0, 2.0)]);
        assert_eq!(settle_group(&occ), None);
        // Nothing in the scene but the shell: seen without tracing.
        let occ = settle_scene(&[]);
        assert_eq!(settle_group(&occ), Some(true));
    }

    #[test]
    fn a_group_is_hidden_only_behind_an_unbroken_plane() {
        // One quad across the whole cross-section (|x|, |z| ≤ 0.5 at y = 1.5): hidden.
        let occ = settle_scene(&[flat(1.5, -2.0, 2.0, -2.0, 2.0)]);
        assert_eq!(settle_group(&occ), Some(false));
        // Two quads sharing an edge across it: hidden.
        let occ = settle_scene(&[
            flat(1.5, -2.0, 0.1, -2.0, 2.0),
            flat(1.5, 0.1, 2.0, -2.0, 2.0),
        ]);
        assert_eq!(settle_group(&occ), Some(false));
        // The same with a 1 mm slit between them: light passes, so neither.
        let occ = settle_scene(&[
            flat(1.5, -2.0, 0.1, -2.0, 2.0),
            flat(1.5, 0.101, 2.0, -2.0, 2.0),
        ]);
        assert_eq!(settle_group(&occ), None);
        // Quads meeting in a T-junction (edges not shared): not proved, so neither.
        let occ = settle_scene(&[
            flat(1.5, -2.0, 0.1, -2.0, 2.0),
            flat(1.5, 0.1, 2.0, -2.0, 0.2),
            flat(1.5, 0.1, 2.0, 0.2, 2.0),
        ]);
        assert_eq!(settle_group(&occ), None);
        // A quad covering all but a corner of it: neither.
        let occ = settle_scene(&[flat(1.5, -2.0, 0.45, -2.0, 2.0)]);
        assert_eq!(settle_group(&occ), None);
    }
}
