//! Planar faces: a surface's triangles joined across shared edges while they face the same way
//! (normals within [`PARALLEL`](super::PARALLEL)), and each face's extent.
//!
//! Input: the scene's triangles as [`Tri`]s (any order). Output: per triangle, the diagonal of
//! the box around its face (m). A contact's gap is judged against these, not against the whole
//! mesh: a generator or exporter may draw a row of monitors as one primitive, yet the back of
//! one monitor 12 cm behind its screen is no contact. Edges are shared when their end positions
//! are bit-identical (vertices split for flat shading still join); depends on the scene only.

use super::{PARALLEL, Tri};
use std::collections::HashMap;

/// Per triangle of `tris`, the extent of the planar face it belongs to (m).
pub(super) fn extents(tris: &[Tri]) -> Vec<f64> {
    let mut parent: Vec<u32> = (0..tris.len() as u32).collect();
    // + 0.0 makes -0.0 and 0.0 one key.
    let key = |p: glam::DVec3| (p + glam::DVec3::ZERO).to_array().map(f64::to_bits);
    let mut edges: HashMap<(u32, [u64; 3], [u64; 3]), u32> = HashMap::new();
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (key(t.p[k]), key(t.p[(k + 1) % 3]));
            let e = (t.surface, a.min(b), a.max(b));
            match edges.get(&e) {
                Some(&j) if tris[j as usize].normal.dot(t.normal) >= PARALLEL => {
                    union(&mut parent, i as u32, j)
                }
                Some(_) => {}
                None => {
                    edges.insert(e, i as u32);
                }
            }
        }
    }
    let mut boxes: HashMap<u32, (glam::DVec3, glam::DVec3)> = HashMap::new();
    for (i, t) in tris.iter().enumerate() {
        let r = find(&mut parent, i as u32);
        let b = boxes
            .entry(r)
            .or_insert((glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY));
        for p in t.p {
            b.0 = b.0.min(p);
            b.1 = b.1.max(p);
        }
    }
    (0..tris.len() as u32)
        .map(|i| {
            let b = boxes[&find(&mut parent, i)];
            (b.1 - b.0).length()
        })
        .collect()
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    // The smaller index is the root: the partition does not depend on the order of unions.
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn tri(surface: u32, p: [[f64; 3]; 3]) -> Tri {
        let p = p.map(DVec3::from_array);
        Tri {
            surface,
            index: 0,
            p,
            normal: (p[1] - p[0]).cross(p[2] - p[0]).normalize(),
            extent: 0.0,
        }
    }

    #[test]
    fn a_box_drawn_as_one_mesh_has_a_face_per_side() {
        // Two squares of one mesh: a 4 m floor strip and, 0.12 m above it, a 0.5 m plate,
        // plus a triangle folded up from the strip's edge (not parallel: its own face).
        let tris = [
            tri(0, [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [4.0, 0.0, 0.0]]),
            tri(0, [[4.0, 0.0, 0.0], [0.0, 0.0, 1.0], [4.0, 0.0, 1.0]]),
            tri(0, [[0.0, 0.12, 0.0], [0.0, 0.12, 0.5], [0.5, 0.12, 0.0]]),
            tri(0, [[4.0, 0.0, 0.0], [4.0, 0.0, 1.0], [4.0, 1.0, 0.0]]),
            // Same edge as the first two share, but another surface: not joined.
            tri(1, [[4.0, 0.0, 0.0], [0.0, 0.0, 1.0], [4.0, 0.0, 1.0]]),
        ];
        let e = extents(&tris);
        let strip = 17f64.sqrt();
        assert!(
            (e[0] - strip).abs() < 1e-12 && (e[1] - strip).abs() < 1e-12,
            "{e:?}"
        );
        assert!((e[2] - 0.5f64.hypot(0.5)).abs() < 1e-12, "{e:?}");
        assert!((e[3] - 2f64.sqrt()).abs() < 1e-12, "{e:?}");
        assert!((e[4] - strip).abs() < 1e-12, "{e:?}");
    }
}
