//! How much of a clutter cluster is hidden by itself: the share of its front-facing area that a
//! far viewer actually sees, along each axis direction.
//!
//! Input: the patch mesh, a node's patches and its bounding box. Output: six factors V(±x),
//! V(±y), V(±z) in [0, 1] (the tree keeps 1 for nodes that are never clusters).
//!
//! A cluster's order-2 model (`geom::sh`) shows the area Σ Aⱼ·max(0, mⱼ·w) toward w: every
//! front face counts, even one the cluster hides from itself (the floor under a seat, a leg
//! behind a leg). Seen along an axis, what is really shown is the cluster's silhouette, the same
//! from both ends. It is measured by rasterising the node's patches onto a [`GRID`]² grid over the
//! node's box in the two other coordinates (pixel centres inside a projected triangle count), and
//! V(±e) = silhouette / Σ Aⱼ·max(0, ±mⱼ·e), at most 1 (1 where that front area is below one
//! pixel: nothing measurable faces that way). Between the axes a direction w is
//! weighted by wₖ² (which sums to 1). Every node is measured on its own patches, in parallel.

use crate::patches::PatchMesh;
use glam::{DVec2, DVec3};

/// Pixels per side of the silhouette grid.
pub const GRID: usize = 16;

/// V along +x, −x, +y, −y, +z, −z for the patches inside the box `lo..hi`.
pub(crate) fn shares(mesh: &PatchMesh, patches: &[u32], lo: DVec3, hi: DVec3) -> [f32; 6] {
    let mut out = [1.0f32; 6];
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (u0, v0) = (lo[u], lo[v]);
        let (du, dv) = (
            (hi[u] - lo[u]).max(1e-300) / GRID as f64,
            (hi[v] - lo[v]).max(1e-300) / GRID as f64,
        );
        let mut covered = [false; GRID * GRID];
        let (mut plus, mut minus) = (0.0, 0.0);
        for &p in patches {
            let patch = &mesh.patches[p as usize];
            let m = patch.normal[axis];
            plus += patch.area * m.max(0.0);
            minus += patch.area * (-m).max(0.0);
            let c = patch.corners(&mesh.receivers);
            let q = c.map(|x| DVec2::new((x[u] - u0) / du, (x[v] - v0) / dv));
            fill(&q, &mut covered);
        }
        let silhouette = covered.iter().filter(|&&c| c).count() as f64 * du * dv;
        // A front area below one pixel cannot be measured on the grid (a tube seen along its
        // axis: its facets are edge-on, their area ~1e-17 m² by rounding): nothing to hide.
        let share = |front: f64| {
            if front > du * dv {
                (silhouette / front).min(1.0) as f32
            } else {
                1.0
            }
        };
        out[2 * axis] = share(plus);
        out[2 * axis + 1] = share(minus);
    }
    out
}

/// Mark the pixels (unit cells of the grid) whose centres lie inside triangle `q`.
fn fill(q: &[DVec2; 3], covered: &mut [bool; GRID * GRID]) {
    let edge = |a: DVec2, b: DVec2, p: DVec2| (b - a).perp_dot(p - a);
    let area = edge(q[0], q[1], q[2]);
    if area == 0.0 {
        return; // seen edge-on: no area in this projection
    }
    let lo = q[0].min(q[1]).min(q[2]);
    let hi = q[0].max(q[1]).max(q[2]);
    // Pixel k has its centre at k + 0.5: the centres within [lo, hi].
    let range = |a: f64, b: f64| {
        let first = (a - 0.5).ceil().max(0.0);
        let last = (b - 0.5).floor().min(GRID as f64 - 1.0);
        if last < first {
            0..0
        } else {
            first as usize..last as usize + 1
        }
    };
    for j in range(lo.y, hi.y) {
        for i in range(lo.x, hi.x) {
            let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
            let inside = [
                edge(q[1], q[2], p),
                edge(q[2], q[0], p),
                edge(q[0], q[1], p),
            ]
            .iter()
            .all(|&x| x * area >= 0.0);
            if inside {
                covered[j * GRID + i] = true;
            }
        }
    }
}

/// V(w) for the unit direction `w` from the six axis shares.
pub(crate) fn share_toward(shares: &[f32; 6], w: DVec3) -> f64 {
    (0..3)
        .map(|k| {
            let s = shares[2 * k + usize::from(w[k] < 0.0)] as f64;
            w[k] * w[k] * s
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;

    fn mesh_of(build: impl FnOnce(&mut SceneBuilder, usize)) -> PatchMesh {
        let mut b = SceneBuilder::new();
        let m = b.material("grey", 0.5);
        build(&mut b, m);
        crate::patches::build(&b.build(), 0.25, None)
    }

    fn all(mesh: &PatchMesh) -> (Vec<u32>, DVec3, DVec3) {
        let patches: Vec<u32> = (0..mesh.patches.len() as u32).collect();
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for r in &mesh.receivers {
            lo = lo.min(r.position);
            hi = hi.max(r.position);
        }
        (patches, lo, hi)
    }

    #[test]
    fn a_box_on_a_floor_hides_the_floor_under_it() {
        // A 3 × 3 m floor (+y) with a closed 1 m cube standing on it.
        let mesh = mesh_of(|b, m| {
            b.floor("floor", 1.5, 0.0, m);
            b.axis_box(
                "cube",
                DVec3::new(-0.5, 0.0, -0.5),
                DVec3::new(0.5, 1.0, 0.5),
                false,
                m,
            );
        });
        let (patches, lo, hi) = all(&mesh);
        let v = shares(&mesh, &patches, lo, hi);
        // From above: 9 m² of floor + 1 m² of cube top face up, 9 m² are seen.
        assert!((v[2] - 0.9).abs() < 1e-6, "{v:?}");
        // From below only the cube's bottom faces down; the floor's back covers more than it.
        assert_eq!(v[3], 1.0);
        // From the sides only the cube's faces face x or z, and they hide nothing.
        for k in [0, 1, 4, 5] {
            assert!((v[k] - 1.0).abs() < 1e-6, "{v:?}");
        }
        let up = share_toward(&v, DVec3::Y);
        assert!((up - 0.9).abs() < 1e-6);
        let slant = share_toward(&v, DVec3::new(1.0, 1.0, 0.0).normalize());
        assert!((slant - 0.95).abs() < 1e-6, "{slant}");
    }

    #[test]
    fn stacked_plates_show_one() {
        // Two 1 m squares facing up, one 0.5 m above the other.
        let mesh = mesh_of(|b, m| {
            b.floor("low", 0.5, 0.0, m);
            b.floor("high", 0.5, 0.5, m);
        });
        let (patches, lo, hi) = all(&mesh);
        let v = shares(&mesh, &patches, lo, hi);
        assert!((v[2] - 0.5).abs() < 1e-6, "{v:?}");
    }

    #[test]
    fn a_tube_seen_along_its_axis_hides_nothing() {
        // An open vertical tube (r 0.25 m, 2 m, 32 sides, radial normals): every facet is edge-on
        // from above and below, where its front area is rounding (~1e-17 m²) and its silhouette
        // empty. Was V(±y) = 0, so a viewer 40° above the horizon saw 59 % of it (a cylinder in
        // a room sent its far receivers 17 % too little through its cluster links).
        let mesh = mesh_of(|b, m| {
            let (mut pos, mut nrm, mut tri) = (Vec::new(), Vec::new(), Vec::new());
            for i in 0..32u32 {
                let t = std::f64::consts::TAU * f64::from(i) / 32.0;
                let r = DVec3::new(t.cos(), 0.0, t.sin());
                pos.extend([r * 0.25, r * 0.25 + DVec3::Y * 2.0]);
                nrm.extend([r, r]);
                let j = (i + 1) % 32;
                tri.extend([[2 * i, 2 * j + 1, 2 * j], [2 * i, 2 * i + 1, 2 * j + 1]]);
            }
            b.surface("tube", pos, nrm, tri, m);
        });
        let (patches, lo, hi) = all(&mesh);
        let v = shares(&mesh, &patches, lo, hi);
        assert_eq!((v[2], v[3]), (1.0, 1.0), "{v:?}");
        // From the sides the near half faces the viewer and nothing hides it (the grid's edge
        // pixels aside).
        for k in [0, 1, 4, 5] {
            assert!(v[k] > 0.97, "{v:?}");
        }
        let w = DVec3::new(1.0, 0.84, 0.0).normalize();
        assert!(share_toward(&v, w) > 0.97, "{}", share_toward(&v, w));
    }
}
