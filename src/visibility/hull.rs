//! The convex geometry behind [`super::settle`]: the hull of a few points and a box, tested
//! against BVH boxes and triangles by separating axes, and the plane polygons a cross-section
//! is checked with. All in the BVH's coordinates, with the proofs' [`MARGIN`].

use super::BVH_DIAGONAL;
use glam::{DVec2, DVec3};
use obvhs::{aabb::Aabb, triangle::Triangle};

/// Separation (BVH units, 5·10⁻⁷ of the scene's diagonal) a proof keeps against the rounding of
/// the f32 triangles and ray origins (≤ 10⁻⁷ of the scene) and the ray–triangle test's slack.
pub(super) const MARGIN: f64 = 5e-7 * BVH_DIAGONAL;

fn tri_bounds(t: &[DVec3; 3]) -> (DVec3, DVec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

pub(super) fn tri64(t: &Triangle) -> [DVec3; 3] {
    [t.v0, t.v1, t.v2].map(|a| a.as_dvec3())
}

/// The convex hull of points in the plane, counter-clockwise (monotone chain).
pub(super) fn convex_hull_2d(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let mut hull: Vec<DVec2> = Vec::with_capacity(points.len() * 2);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2 {
                let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                if (b - a).perp_dot(p - a) <= 0.0 {
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Whether `p` lies in the (closed) triangle `t`.
pub(super) fn inside_2d(t: [DVec2; 3], p: DVec2) -> bool {
    let area = (t[1] - t[0]).perp_dot(t[2] - t[0]);
    let s = [0, 1, 2].map(|k| (t[(k + 1) % 3] - t[k]).perp_dot(p - t[k]) * area.signum());
    area != 0.0 && s.iter().all(|x| *x >= 0.0)
}

/// Whether the segment `a`–`b` comes within `reach` of the convex polygon (counter-clockwise).
pub(super) fn segment_meets_polygon(a: DVec2, b: DVec2, polygon: &[DVec2], reach: f64) -> bool {
    let apart = |axis: DVec2| {
        let len = axis.length();
        if len == 0.0 {
            return false;
        }
        let axis = axis / len;
        let (s0, s1) = (axis.dot(a), axis.dot(b));
        let (lo, hi) = polygon
            .iter()
            .map(|p| axis.dot(*p))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(x), h.max(x))
            });
        s0.min(s1) > hi + reach || s0.max(s1) < lo - reach
    };
    if apart((b - a).perp()) {
        return false;
    }
    !(0..polygon.len()).any(|k| apart((polygon[(k + 1) % polygon.len()] - polygon[k]).perp()))
}

/// The convex hull of a few points and the corners of a box (BVH units), as the axes that can
/// separate it from a box or a triangle: its faces' normals and the directions of its edges.
pub(super) struct Hull {
    verts: Vec<DVec3>,
    lo: DVec3,
    hi: DVec3,
    /// Unit face normals with the hull's extent along them.
    faces: Vec<(DVec3, f64, f64)>,
    /// Directions its edges may take (box axes, start to corner, start to start).
    edges: Vec<DVec3>,
}

impl Hull {
    pub(super) fn new(starts: &[DVec3], corners: &[DVec3; 8]) -> Self {
        let mut verts = starts.to_vec();
        verts.extend_from_slice(corners);
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &verts {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let mut hull = Hull {
            verts,
            lo,
            hi,
            faces: Vec::new(),
            edges: vec![DVec3::X, DVec3::Y, DVec3::Z],
        };
        // Candidate faces: through a start and a box edge, two starts and a corner, three starts
        // (the box's own faces are the bounding box's); kept when the plane supports the hull.
        let box_edges = (0..8usize)
            .flat_map(|i| (0..3).map(move |a| (i, i | (1 << a))))
            .filter(|(i, j)| i != j);
        let mut planes: Vec<(DVec3, DVec3)> = Vec::new();
        for (k, &a) in starts.iter().enumerate() {
            for (i, j) in box_edges.clone() {
                planes.push((a, (corners[j] - corners[i]).cross(corners[i] - a)));
            }
            for (l, &b) in starts.iter().enumerate().skip(k + 1) {
                for &c in corners {
                    planes.push((a, (b - a).cross(c - a)));
                }
                for &c in &starts[l + 1..] {
                    planes.push((a, (b - a).cross(c - a)));
                }
                hull.edges.push(b - a);
            }
            for &c in corners {
                hull.edges.push(c - a);
            }
        }
        for (through, n) in planes {
            let n = n.normalize_or_zero();
            if n == DVec3::ZERO {
                continue;
            }
            let (mn, mx) = hull.extent(n);
            let at = n.dot(through);
            let tol = 1e-9 * BVH_DIAGONAL;
            if at >= mx - tol || at <= mn + tol {
                hull.faces.push((n, mn, mx));
            }
        }
        hull
    }

    fn extent(&self, axis: DVec3) -> (f64, f64) {
        self.verts
            .iter()
            .map(|p| axis.dot(*p))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(x), h.max(x))
            })
    }

    /// Whether a BVH node's box may meet the hull (conservative).
    pub(super) fn meets_box(&self, b: &Aabb) -> bool {
        let (bl, bh) = (b.min.as_dvec3(), b.max.as_dvec3());
        if bl.cmpgt(self.hi + MARGIN).any() || bh.cmplt(self.lo - MARGIN).any() {
            return false;
        }
        let (c, h) = ((bl + bh) * 0.5, (bh - bl) * 0.5);
        self.faces.iter().all(|(n, mn, mx)| {
            let (mid, r) = (n.dot(c), n.abs().dot(h));
            mid - r <= mx + MARGIN && mid + r >= mn - MARGIN
        })
    }

    /// Whether a triangle comes within MARGIN of the hull (separating axes: the hull's faces,
    /// the triangle's plane, and the cross products of their edges).
    pub(super) fn meets_triangle(&self, t: &Triangle) -> bool {
        let t = tri64(t);
        let (tl, th) = tri_bounds(&t);
        if tl.cmpgt(self.hi + MARGIN).any() || th.cmplt(self.lo - MARGIN).any() {
            return false;
        }
        let apart = |n: DVec3, mn: f64, mx: f64| {
            let p = t.map(|v| n.dot(v));
            p[0].min(p[1]).min(p[2]) > mx + MARGIN || p[0].max(p[1]).max(p[2]) < mn - MARGIN
        };
        if self.faces.iter().any(|(n, mn, mx)| apart(*n, *mn, *mx)) {
            return false;
        }
        let e = [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
        let normal = e[0].cross(e[1]).normalize_or_zero();
        let mut axes = std::iter::once(normal).chain(e.iter().flat_map(|a| {
            self.edges
                .iter()
                .map(move |b| a.cross(*b).normalize_or_zero())
        }));
        !axes.any(|n| {
            if n == DVec3::ZERO {
                return false;
            }
            let (mn, mx) = self.extent(n);
            apart(n, mn, mx)
        })
    }
}
