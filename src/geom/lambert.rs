//! Exact unoccluded transfer from a uniform Lambertian polygon to a point: Lambert's contour
//! formula (docs/ANALYTIC.md §2 Lambert).
//!
//! Input: a receiver point `p` with unit normal `n` and a planar polygon (any winding).
//! Output: the point-to-polygon form factor F ∈ [0, 1]: the fraction of the receiver's
//! cosine-weighted hemisphere the polygon covers, so that a polygon of uniform exitance M gives
//! illuminance E = F·M (= F·π·L). The polygon is clipped to the receiver's upper half-space
//! first, so parts behind the receiver contribute nothing. Winding does not matter (coverage is
//! returned as a magnitude). Degenerate edges (the point on a vertex or on an edge line) contribute
//! zero instead of NaN.

use glam::DVec3;
use std::f64::consts::PI;

/// Maximum polygon size handled without allocation (a triangle clipped by one plane has ≤ 4
/// vertices; we accept up to 8-gons).
const MAX_VERTS: usize = 16;

/// Point-to-polygon form factor from `p` (normal `n`) to the polygon `verts`.
pub fn form_factor(p: DVec3, n: DVec3, verts: &[DVec3]) -> f64 {
    if !rises_above(p, n, verts) {
        return 0.0;
    }
    form_factor_rising(p, n, verts)
}

/// [`form_factor`] of a polygon already known to [`rises_above`] the receiver's plane (the test
/// is not repeated).
pub(crate) fn form_factor_rising(p: DVec3, n: DVec3, verts: &[DVec3]) -> f64 {
    let mut clipped = [DVec3::ZERO; MAX_VERTS];
    let count = clip_to_hemisphere(p, n, verts, &mut clipped);
    if count < 3 {
        return 0.0;
    }
    contour_sum(p, n, &clipped[..count]).abs() / (2.0 * PI)
}

/// Does the polygon reach above the plane through `p` with normal `n` (by more than 10⁻¹² of
/// its distance), and does `p` lie off the polygon's own plane (by more than [`IN_PLANE`] of
/// its distance)? When not, its form factor is zero: a polygon lying in the receiver's own
/// plane covers no solid angle above it, and neither does one whose plane passes through the
/// receiver — seen edge-on. The second case is the patch a vertex receiver sits in on a curved,
/// smooth-shaded surface: its shading normal differs from the facet's (by 10⁻⁶ rad for f32
/// normals), the facet pokes above the receiver's plane by a hair, and the contour sum from a
/// point inside the facet would see the whole hemisphere.
pub(crate) fn rises_above(p: DVec3, n: DVec3, verts: &[DVec3]) -> bool {
    let (mut height, mut reach) = (0.0f64, 0.0f64);
    for v in verts {
        height = height.max(n.dot(*v - p));
        reach = reach.max((*v - p).length());
    }
    if height <= 1e-12 * reach {
        return false;
    }
    // Newell's normal of the polygon (twice its vector area).
    let mut area = DVec3::ZERO;
    for (i, a) in verts.iter().enumerate() {
        area += a.cross(verts[(i + 1) % verts.len()]);
    }
    let len = area.length();
    len > 0.0 && (area.dot(p - verts[0]) / len).abs() > IN_PLANE * reach
}

/// A point nearer a polygon's plane than this share of its distance to the polygon's farthest
/// vertex lies in that plane (f64 rounding of coordinates leaves ~10⁻¹⁶; a receiver nudged off
/// a room's corner sits 10⁻⁴ × the patch size off the neighbouring wall).
const IN_PLANE: f64 = 1e-9;

/// Σ βᵢ (n·ĝᵢ) over the edges, signed by the polygon's orientation as seen from `p`.
fn contour_sum(p: DVec3, n: DVec3, verts: &[DVec3]) -> f64 {
    let mut sum = 0.0;
    let k = verts.len();
    for i in 0..k {
        let a = verts[i] - p;
        let b = verts[(i + 1) % k] - p;
        let cross = a.cross(b);
        let sin_len = cross.length();
        let la = a.length();
        let lb = b.length();
        if sin_len <= 1e-14 * la * lb || la == 0.0 || lb == 0.0 {
            // Collinear with the point: either a zero-length edge seen end-on (β = 0) or the
            // point lies on the edge, where the polygon is seen edge-on and covers nothing.
            continue;
        }
        let beta = super::atan::atan2(sin_len, a.dot(b));
        sum += beta * n.dot(cross) / sin_len;
    }
    sum
}

/// Sutherland–Hodgman clip of `verts` to the half-space n·(x − p) ≥ 0. Returns the vertex count
/// written into `out`.
fn clip_to_hemisphere(p: DVec3, n: DVec3, verts: &[DVec3], out: &mut [DVec3; MAX_VERTS]) -> usize {
    let k = verts.len().min(MAX_VERTS / 2);
    let mut count = 0;
    for i in 0..k {
        let a = verts[i];
        let b = verts[(i + 1) % k];
        let da = n.dot(a - p);
        let db = n.dot(b - p);
        if da >= 0.0 {
            out[count] = a;
            count += 1;
        }
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            out[count] = a + (b - a) * t;
            count += 1;
        }
    }
    count
}

/// Solid angle (sr) subtended at `p` by the triangle `t` (Van Oosterom & Strackee), in [0, 2π].
pub(crate) fn triangle_solid_angle(p: DVec3, t: &[DVec3; 3]) -> f64 {
    let a = t[0] - p;
    let b = t[1] - p;
    let c = t[2] - p;
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * super::atan::atan2(num, den)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, x1: f64, z0: f64, z1: f64, y: f64) -> [DVec3; 4] {
        [
            DVec3::new(x0, y, z0),
            DVec3::new(x1, y, z0),
            DVec3::new(x1, y, z1),
            DVec3::new(x0, y, z1),
        ]
    }

    /// docs/ANALYTIC.md §2: element below one corner of a parallel a × b rectangle at height c.
    fn corner_rect(a: f64, b: f64, c: f64) -> f64 {
        let x = a / c;
        let y = b / c;
        let sx = (1.0 + x * x).sqrt();
        let sy = (1.0 + y * y).sqrt();
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
    }

    #[test]
    fn a_polygon_through_the_receiver_is_seen_edge_on() {
        // The receiver inside a triangle (on its edge, at its vertex) whose plane is turned by
        // 10⁻⁶ rad from the receiver's: part of it lies above the receiver's plane, yet from a
        // point in its own plane it covers no solid angle. Off the plane by 10⁻⁴ of its size
        // (a receiver nudged off a room's corner) it counts again.
        let tilt = 1e-6f64;
        let n = DVec3::new(0.0, tilt.cos(), tilt.sin());
        let tri = [
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        for p in [DVec3::ZERO, DVec3::new(0.0, 0.0, -1.0), tri[2]] {
            assert_eq!(form_factor(p, n, &tri), 0.0, "from {p}");
        }
        let wall = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        let f = form_factor(DVec3::new(1e-4, 1e-4, 0.5), DVec3::Y, &wall);
        assert!((f - 0.5).abs() < 0.01, "{f}");
    }

    #[test]
    fn parallel_rectangle_corner_matches_closed_form() {
        for &(a, b, c) in &[
            (1.0, 1.0, 1.0),
            (2.0, 0.5, 3.0),
            (0.1, 5.0, 0.2),
            (4.0, 4.0, 0.01),
        ] {
            let f = form_factor(DVec3::ZERO, DVec3::Y, &rect(0.0, a, 0.0, b, c));
            let want = corner_rect(a, b, c);
            assert!(
                (f - want).abs() < 1e-12 * want.max(1e-3),
                "{a} {b} {c}: {f} vs {want}"
            );
        }
    }

    #[test]
    fn disk_on_axis_matches_closed_form() {
        let (r, h) = (0.7, 1.3);
        let n = 2000;
        let verts: Vec<DVec3> = (0..n)
            .map(|i| {
                let t = 2.0 * PI * i as f64 / n as f64;
                DVec3::new(r * t.cos(), h, r * t.sin())
            })
            .collect();
        // Use a fan of triangles (MAX_VERTS limits a single polygon).
        let mut f = 0.0;
        for i in 0..n {
            let tri = [DVec3::new(0.0, h, 0.0), verts[i], verts[(i + 1) % n]];
            f += form_factor(DVec3::ZERO, DVec3::Y, &tri);
        }
        let want = r * r / (h * h + r * r);
        // The polygon is inscribed in the disk: area ratio sin(2π/n)/(2π/n).
        let inscribed = (2.0 * PI / n as f64).sin() / (2.0 * PI / n as f64);
        assert!((f - want * inscribed).abs() < 1e-5 * want, "{f} vs {want}");
    }

    #[test]
    fn winding_and_clipping() {
        let mut r = rect(-1.0, 1.0, -1.0, 1.0, 1.0);
        let f1 = form_factor(DVec3::ZERO, DVec3::Y, &r);
        r.reverse();
        let f2 = form_factor(DVec3::ZERO, DVec3::Y, &r);
        assert!((f1 - f2).abs() < 1e-15);
        // A vertical wall straddling the receiver plane: only the upper half counts.
        let wall = [
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(1.0, -1.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(-1.0, 1.0, 1.0),
        ];
        let upper = [
            DVec3::new(-1.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(-1.0, 1.0, 1.0),
        ];
        let a = form_factor(DVec3::ZERO, DVec3::Y, &wall);
        let b = form_factor(DVec3::ZERO, DVec3::Y, &upper);
        assert!(a > 0.01 && (a - b).abs() < 1e-15);
        // Entirely behind: nothing.
        assert_eq!(
            form_factor(DVec3::ZERO, DVec3::Y, &rect(-1.0, 1.0, -1.0, 1.0, -1.0)),
            0.0
        );
    }

    #[test]
    fn closed_cube_sums_to_one_from_inside() {
        // Six faces of a cube around an interior point: the hemisphere is covered exactly once.
        let p = DVec3::new(0.2, -0.3, 0.1);
        let n = DVec3::new(0.3, 0.8, -0.2).normalize();
        let faces = crate::fixtures::box_faces(DVec3::splat(-1.0), DVec3::splat(1.0));
        let sum: f64 = faces.iter().map(|f| form_factor(p, n, f)).sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    }

    #[test]
    fn coplanar_polygon_covers_nothing() {
        let floor = rect(-1.0, 1.0, -1.0, 1.0, 0.0);
        for p in [
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(5.0, 0.0, 0.0),
        ] {
            assert_eq!(form_factor(p, DVec3::Y, &floor), 0.0, "{p}");
        }
    }

    #[test]
    fn point_on_polygon_edge_is_finite() {
        // Receiver on the floor exactly at the foot of a wall: the wall is seen edge-on.
        let wall = [
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
        ];
        let f = form_factor(DVec3::ZERO, DVec3::Y, &wall);
        assert!(f.is_finite());
        // Just in front of it the wall covers half the hemisphere's projected area.
        let f = form_factor(DVec3::new(0.0, 0.0, 1e-7), DVec3::Y, &wall);
        assert!((f - 0.5).abs() < 1e-5, "{f}");
    }

    #[test]
    fn solid_angles_of_cube_faces_sum_to_4pi() {
        let p = DVec3::new(0.3, 0.1, -0.4);
        let quads = crate::fixtures::box_faces(DVec3::splat(-1.0), DVec3::splat(1.0));
        let sum: f64 = quads
            .iter()
            .map(|q| {
                triangle_solid_angle(p, &[q[0], q[1], q[2]])
                    + triangle_solid_angle(p, &[q[0], q[2], q[3]])
            })
            .sum();
        assert!((sum - 4.0 * PI).abs() < 1e-12, "{sum}");
    }
}
