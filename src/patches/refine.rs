//! Conforming refinement of one triangle mesh into patches no larger than a target size.
//!
//! Input: positions, optional per-vertex attributes, triangles, target edge length `h`.
//! Output: a refined mesh in which every input edge of length ℓ is split into k = ⌈ℓ/h⌉ equal
//! segments. The points on an edge depend only on the edge (its endpoints, ordered canonically by
//! position), so two triangles sharing an edge share its points: no T-junctions and no cracks,
//! and vertices stay shared within the surface (smooth vertex colours) while creases (input
//! vertices duplicated with different normals) stay sharp.
//!
//! Each triangle is subdivided uniformly with n = max(k) segments per side; the grid points on a
//! side with fewer segments are snapped to that side's edge points, and triangles that collapse are
//! dropped. Snapping moves points only along their edge, so no triangle flips. Zero-area input
//! triangles are skipped. A sliver (thinner than `h`, where the n² grid would make more than
//! [`SLIVER`] times the triangles its edge points need) is instead a strip zipped between its
//! longest edge and the other two: Σk − 2 triangles, not n² (a 10 km needle at 1 cm is 10⁶
//! patches, not 10¹²). [`triangle_patches`] counts either way without meshing (see `bake::budget`).

use glam::DVec3;
use std::collections::HashMap;

/// A refined triangle mesh. Vertex `i` of the output came from `origin[i]`: a barycentric
/// combination of up to three input vertices (used to interpolate attributes).
#[derive(Debug, Default)]
pub struct Refined {
    pub positions: Vec<DVec3>,
    pub origin: Vec<Blend>,
    pub triangles: Vec<[u32; 3]>,
    /// Per output triangle, the input triangle it lies in.
    pub parent: Vec<u32>,
}

/// Barycentric weights over input vertices.
#[derive(Debug, Clone, Copy)]
pub struct Blend {
    pub index: [u32; 3],
    pub weight: [f64; 3],
}

impl Blend {
    fn vertex(v: u32) -> Self {
        Blend {
            index: [v, v, v],
            weight: [1.0, 0.0, 0.0],
        }
    }

    /// Interpolate a per-input-vertex attribute.
    pub(crate) fn apply<T>(&self, data: &[T]) -> T
    where
        T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
    {
        data[self.index[0] as usize] * self.weight[0]
            + data[self.index[1] as usize] * self.weight[1]
            + data[self.index[2] as usize] * self.weight[2]
    }
}

/// A triangle is meshed as a strip (see the module doc) when it is thinner than `h` and the
/// uniform grid would make more than this many times the strip's triangles.
pub const SLIVER: f64 = 64.0;

/// Segments of an edge of length `len` at patch size `h` (f64: an estimate may be huge).
fn segments(len: f64, h: f64) -> f64 {
    // An edge that is a whole number of patch sizes (common in rooms drawn on a grid) must
    // get that number at every scale, not one more where rounding lands above it.
    (len / h * (1.0 - 1e-9)).ceil().max(1.0)
}

/// How [`refine`] meshes triangle `p` at patch size `h`: `Some(side)` (the longest side,
/// 0 = p0→p1, 1 = p1→p2, 2 = p2→p0) for a strip, `None` for the uniform grid; and how many
/// triangles it makes (at most; the grid drops collapsed ones). Zero area: 0.
pub(crate) fn triangle_patches(p: [DVec3; 3], h: f64) -> (Option<usize>, f64) {
    let cross = (p[1] - p[0]).cross(p[2] - p[0]).length();
    if cross.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return (None, 0.0);
    }
    let len = [0, 1, 2].map(|i| (p[(i + 1) % 3] - p[i]).length());
    let k = len.map(|l| segments(l, h));
    let n = k[0].max(k[1]).max(k[2]);
    // A strip triangulates the polygon of its Σk edge points: Σk − 2 triangles.
    let strip = k[0] + k[1] + k[2] - 2.0;
    let longest = (0..3)
        .max_by(|&a, &b| len[a].total_cmp(&len[b]))
        .unwrap_or(0);
    // Height over the longest side: thinner than a patch needs no interior points.
    let height = cross / len[longest];
    if height < h && k[longest] >= 2.0 && n * n > SLIVER * strip {
        (Some(longest), strip)
    } else {
        (None, n * n)
    }
}

/// Refine `triangles` over `positions` so no patch edge is longer than about `h`.
pub(crate) fn refine(positions: &[DVec3], triangles: &[[u32; 3]], h: f64) -> Refined {
    let mut out = Refined {
        positions: positions.to_vec(),
        origin: (0..positions.len() as u32).map(Blend::vertex).collect(),
        triangles: Vec::with_capacity(triangles.len()),
        parent: Vec::with_capacity(triangles.len()),
    };
    // Edge (lo, hi) by input index → (segment count, ids of its k+1 points from lo to hi).
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (index, tri) in triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|v| positions[v as usize]);
        if (b - a).cross(c - a).length_squared() <= 0.0 {
            continue;
        }
        let sides = [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])];
        let points: [Vec<u32>; 3] =
            sides.map(|(u, v)| edge_points(&mut out, &mut edges, positions, u, v, h));
        let n = points.iter().map(|p| p.len() - 1).max().unwrap_or(1);
        let before = out.triangles.len();
        match triangle_patches([a, b, c], h).0 {
            Some(longest) => strip(&mut out, &points, longest),
            None => subdivide(&mut out, positions, *tri, &points, n),
        }
        let added = out.triangles.len() - before;
        out.parent.extend(std::iter::repeat_n(index as u32, added));
    }
    out
}

/// The ids of the points on edge u→v (ordered from u to v), creating them on first use.
fn edge_points(
    out: &mut Refined,
    edges: &mut HashMap<(u32, u32), Vec<u32>>,
    positions: &[DVec3],
    u: u32,
    v: u32,
    h: f64,
) -> Vec<u32> {
    let key = (u.min(v), u.max(v));
    let ids = edges.entry(key).or_insert_with(|| {
        let (pu, pv) = (positions[key.0 as usize], positions[key.1 as usize]);
        let k = segments((pv - pu).length(), h) as usize;
        // Interpolate from the lexicographically smaller endpoint so every surface computes the
        // same coordinates for the same geometric edge.
        let flip = lex_less(pv, pu);
        let mut ids = Vec::with_capacity(k + 1);
        ids.push(key.0);
        for i in 1..k {
            let t = i as f64 / k as f64;
            let (from, to, s) = if flip { (pv, pu, 1.0 - t) } else { (pu, pv, t) };
            out.positions.push(from + (to - from) * s);
            out.origin.push(Blend {
                index: [key.0, key.1, key.1],
                weight: [1.0 - t, t, 0.0],
            });
            ids.push(out.positions.len() as u32 - 1);
        }
        ids.push(key.1);
        ids
    });
    if key.0 == u {
        ids.clone()
    } else {
        ids.iter().rev().copied().collect()
    }
}

fn lex_less(a: DVec3, b: DVec3) -> bool {
    (a.x, a.y, a.z) < (b.x, b.y, b.z)
}

/// A sliver as a strip: its longest side's points (a→b) zipped with the other two sides' (a→c→b),
/// advancing along whichever chain's next point lies nearer `a` along a→b. Only edge points are
/// used, so neighbours conform; the triangle is convex, so no zipped triangle flips. The first
/// and last triangles are fixed so that no triangle has three points on one side.
fn strip(out: &mut Refined, points: &[Vec<u32>; 3], longest: usize) {
    let lower = &points[longest];
    let upper: Vec<u32> = (points[(longest + 2) % 3].iter().rev())
        .chain(points[(longest + 1) % 3].iter().rev().skip(1))
        .copied()
        .collect();
    let (a, b) = (
        out.positions[lower[0] as usize],
        out.positions[lower[lower.len() - 1] as usize],
    );
    let along = |id: u32| (out.positions[id as usize] - a).dot(b - a);
    let (last_l, last_u) = (lower.len() - 2, upper.len() - 2);
    let mut tris = vec![[lower[0], lower[1], upper[1]]];
    let (mut i, mut j) = (1, 1);
    while i < last_l || j < last_u {
        let advance_lower =
            j == last_u || (i < last_l && along(lower[i + 1]) <= along(upper[j + 1]));
        if advance_lower {
            tris.push([lower[i], lower[i + 1], upper[j]]);
            i += 1;
        } else {
            tris.push([lower[i], upper[j + 1], upper[j]]);
            j += 1;
        }
    }
    tris.push([lower[i], lower[i + 1], upper[j]]);
    out.triangles.extend(tris);
}

/// Uniform n-subdivision of `tri` with boundary points snapped to the shared edge points.
/// `points[0]` runs a→b, `points[1]` b→c, `points[2]` c→a.
fn subdivide(
    out: &mut Refined,
    positions: &[DVec3],
    tri: [u32; 3],
    points: &[Vec<u32>; 3],
    n: usize,
) {
    let [a, b, c] = tri;
    let (pa, pb, pc) = (
        positions[a as usize],
        positions[b as usize],
        positions[c as usize],
    );
    // Grid point (i, j): barycentric (1 − (i+j)/n, i/n, j/n) over (a, b, c).
    let snap = |edge: &Vec<u32>, t: f64| -> u32 {
        let k = edge.len() - 1;
        edge[(t * k as f64).round() as usize]
    };
    let row = |j: usize| -> usize { j * (n + 1) - j * (j.saturating_sub(1)) / 2 };
    let mut ids = vec![0u32; (n + 1) * (n + 2) / 2];
    for j in 0..=n {
        for i in 0..=(n - j) {
            let id = if j == 0 {
                snap(&points[0], i as f64 / n as f64)
            } else if i + j == n {
                snap(&points[1], j as f64 / n as f64)
            } else if i == 0 {
                snap(&points[2], 1.0 - j as f64 / n as f64)
            } else {
                let (wb, wc) = (i as f64 / n as f64, j as f64 / n as f64);
                let wa = 1.0 - wb - wc;
                out.positions.push(pa * wa + pb * wb + pc * wc);
                out.origin.push(Blend {
                    index: [a, b, c],
                    weight: [wa, wb, wc],
                });
                out.positions.len() as u32 - 1
            };
            ids[row(j) + i] = id;
        }
    }
    let at = |i: usize, j: usize| ids[row(j) + i];
    let mut emit = |t: [u32; 3]| {
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            out.triangles.push(t);
        }
    };
    for j in 0..n {
        for i in 0..(n - j) {
            emit([at(i, j), at(i + 1, j), at(i, j + 1)]);
            if i + j + 1 < n {
                emit([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(r: &Refined, t: &[u32; 3]) -> f64 {
        let p = t.map(|v| r.positions[v as usize]);
        (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0
    }

    #[test]
    fn quad_refines_conformingly_and_keeps_area_and_orientation() {
        // A 3 × 1 quad as two triangles, with an anisotropic target size.
        let p = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, -1.0),
            DVec3::new(0.0, 0.0, -1.0),
        ];
        let tris = [[0, 1, 2], [0, 2, 3]];
        let r = refine(&p, &tris, 0.4);
        let total: f64 = r.triangles.iter().map(|t| area(&r, t)).sum();
        assert!((total - 3.0).abs() < 1e-12, "{total}");
        for t in &r.triangles {
            let q = t.map(|v| r.positions[v as usize]);
            let n = (q[1] - q[0]).cross(q[2] - q[0]);
            assert!(n.y > 0.0, "orientation kept (normal +Y)");
            for e in 0..3 {
                assert!((q[e] - q[(e + 1) % 3]).length() < 0.4 * 1.5 + 1e-9);
            }
        }
        // Conforming: every edge used by exactly one triangle lies on the outer boundary.
        let mut count: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &r.triangles {
            for e in 0..3 {
                let (u, v) = (t[e], t[(e + 1) % 3]);
                *count.entry((u.min(v), u.max(v))).or_default() += 1;
            }
        }
        for ((u, v), c) in count {
            if c == 1 {
                let (a, b) = (r.positions[u as usize], r.positions[v as usize]);
                let on_boundary = |q: DVec3| {
                    q.x.abs() < 1e-12
                        || (q.x - 3.0).abs() < 1e-12
                        || q.z.abs() < 1e-12
                        || (q.z + 1.0).abs() < 1e-12
                };
                let mid = (a + b) / 2.0;
                assert!(
                    on_boundary(mid),
                    "interior edge used once: T-junction at {mid}"
                );
            } else {
                assert_eq!(c, 2);
            }
        }
    }

    #[test]
    fn sliver_triangle_is_refined_without_flips() {
        let p = vec![
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, -0.001),
        ];
        let r = refine(&p, &[[0, 1, 2]], 0.5);
        let total: f64 = r.triangles.iter().map(|t| area(&r, t)).sum();
        assert!((total - 0.005).abs() < 1e-12);
        for t in &r.triangles {
            let q = t.map(|v| r.positions[v as usize]);
            assert!((q[1] - q[0]).cross(q[2] - q[0]).y > 0.0);
        }
    }

    #[test]
    fn a_long_sliver_is_a_strip_of_about_l_over_h_patches_conforming_with_its_neighbour() {
        // A 1 km needle 1 cm wide (y = 0, facing +Y) sharing its long edge with a fat
        // triangle; h = 5 m: the grid would be 200² triangles, the strip 398 (its 400 edge
        // points less two).
        let p = vec![
            DVec3::ZERO,
            DVec3::new(1000.0, 0.0, 0.0),
            DVec3::new(400.0, 0.0, -0.01),
            DVec3::new(500.0, 0.0, 2.0),
        ];
        let tris = [[0, 1, 2], [1, 0, 3]];
        let h = 5.0;
        let (how, count) = triangle_patches(tris[0].map(|v| p[v as usize]), h);
        assert_eq!((how, count), (Some(0), 200.0 + 120.0 + 80.0 - 2.0));
        let r = refine(&p, &tris[..1], h);
        assert_eq!(r.triangles.len(), 398);
        let total: f64 = r.triangles.iter().map(|t| area(&r, t)).sum();
        assert!((total - 5.0).abs() < 1e-9, "{total}");
        for t in &r.triangles {
            let q = t.map(|v| r.positions[v as usize]);
            assert!((q[1] - q[0]).cross(q[2] - q[0]).y > 0.0, "flipped: {q:?}");
            for e in 0..3 {
                assert!((q[e] - q[(e + 1) % 3]).length() < h + 0.011);
            }
        }
        // With the neighbour: every edge is used twice except the outer boundary's.
        let r = refine(&p, &tris, h);
        let mut count: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &r.triangles {
            for e in 0..3 {
                let (u, v) = (t[e], t[(e + 1) % 3]);
                *count.entry((u.min(v), u.max(v))).or_default() += 1;
            }
        }
        let on_long_edge = |q: DVec3| q.z == 0.0 && q.x > 0.0 && q.x < 1000.0;
        for ((u, v), c) in count {
            let mid = (r.positions[u as usize] + r.positions[v as usize]) / 2.0;
            if on_long_edge(mid) {
                assert_eq!(c, 2, "T-junction on the shared edge at {mid}");
            }
        }
    }

    #[test]
    fn zero_area_triangles_are_dropped() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let r = refine(&p, &[[0, 1, 2]], 0.1);
        assert!(r.triangles.is_empty());
    }
}
