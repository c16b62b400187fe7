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
//! triangles are skipped.

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
    pub fn apply<T>(&self, data: &[T]) -> T
    where
        T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
    {
        data[self.index[0] as usize] * self.weight[0]
            + data[self.index[1] as usize] * self.weight[1]
            + data[self.index[2] as usize] * self.weight[2]
    }
}

/// Refine `triangles` over `positions` so no patch edge is longer than about `h`.
pub fn refine(positions: &[DVec3], triangles: &[[u32; 3]], h: f64) -> Refined {
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
        subdivide(&mut out, positions, *tri, &points, n);
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
        // An edge that is a whole number of patch sizes (common in rooms drawn on a grid) must
        // get that number at every scale, not one more where rounding lands above it.
        let k = ((pv - pu).length() / h * (1.0 - 1e-9)).ceil().max(1.0) as usize;
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
    fn zero_area_triangles_are_dropped() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let r = refine(&p, &[[0, 1, 2]], 0.1);
        assert!(r.triangles.is_empty());
    }
}
