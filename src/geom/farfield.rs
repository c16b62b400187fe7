//! Far-field form factor of a cluster of nearly coplanar patches, to second order.
//!
//! The point-to-area form factor density is f(x) = (n_p·u)(−n_s·u) / (π|u|⁴), u = x − p. For a
//! cluster small against its distance, ∫f dA is expanded about the area centroid c:
//! ∫f dA ≈ A·f(c) + ½ H_f(c) : C, where C = ∫(x − c)(x − c)ᵀ dA is the area's second central
//! moment (the first-order term vanishes about the centroid). The source normal n_s is the
//! cluster's area-weighted mean normal, so the expansion is accurate for clusters with a narrow
//! normal cone; callers only use it there. The error is O((r/d)⁴) relative, r the cluster radius and
//! d its distance (a disk on axis: r⁶/d⁶).
//!
//! [`AreaMoments`] are built per triangle and combined bottom-up in the patch hierarchy.

use glam::{DMat3, DVec3};
use std::f64::consts::PI;

/// Area, centroid, normal sum and second central moment of a set of triangles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaMoments {
    pub area: f64,
    pub centroid: DVec3,
    /// Σ Aₖ·nₖ (its length / area is the cosine spread of the normals; 1 for coplanar).
    pub normal_sum: DVec3,
    /// ∫ (x − c)(x − c)ᵀ dA.
    pub second: DMat3,
}

impl AreaMoments {
    pub const ZERO: AreaMoments = AreaMoments {
        area: 0.0,
        centroid: DVec3::ZERO,
        normal_sum: DVec3::ZERO,
        second: DMat3::ZERO,
    };

    /// Moments of one triangle with unit normal `normal` (the covariance of a uniform triangle is
    /// (1/12)·Σ (vᵢ − m)(vᵢ − m)ᵀ).
    pub(crate) fn triangle(v: &[DVec3; 3], area: f64, normal: DVec3) -> Self {
        let m = (v[0] + v[1] + v[2]) / 3.0;
        let mut second = DMat3::ZERO;
        for &vi in v {
            second += outer(vi - m, vi - m);
        }
        AreaMoments {
            area,
            centroid: m,
            normal_sum: normal * area,
            second: second * (area / 12.0),
        }
    }

    /// Moments of the union of two disjoint sets.
    pub(crate) fn combine(&self, other: &AreaMoments) -> Self {
        let area = self.area + other.area;
        if area <= 0.0 {
            return AreaMoments::ZERO;
        }
        let c = (self.centroid * self.area + other.centroid * other.area) / area;
        let da = self.centroid - c;
        let db = other.centroid - c;
        AreaMoments {
            area,
            centroid: c,
            normal_sum: self.normal_sum + other.normal_sum,
            second: self.second
                + other.second
                + outer(da, da) * self.area
                + outer(db, db) * other.area,
        }
    }

    /// Second-order estimate of the form factor from `p` (unit normal `n`) to this area, signed:
    /// positive when the area faces `p` and lies above its tangent plane.
    pub(crate) fn form_factor(&self, p: DVec3, n: DVec3) -> f64 {
        if self.area <= 0.0 {
            return 0.0;
        }
        let a = n;
        let b = self.normal_sum / self.area;
        let u = self.centroid - p;
        let q = u.length_squared();
        if q <= 0.0 {
            return 0.0;
        }
        let au = a.dot(u);
        let bu = b.dot(u);
        let g = -au * bu;
        let zeroth = self.area * g / (q * q);
        // S = −(abᵀ + baᵀ)/2; g = uᵀSu.
        let c = &self.second;
        let s_c = -a.dot(*c * b);
        let su = -(a * bu + b * au) * 0.5;
        let cu = *c * u;
        let tr = c.x_axis.x + c.y_axis.y + c.z_axis.z;
        let q2 = q * q;
        let q3 = q2 * q;
        let second =
            s_c / q2 - 8.0 * su.dot(cu) / q3 - 2.0 * g * tr / q3 + 12.0 * g * u.dot(cu) / (q3 * q);
        (zeroth + second) / PI
    }

    /// Gradient, with respect to the source point, of the form-factor density at the centroid.
    /// For exitance B varying over the area, ∫B·f dA ≈ B̄·F + ∇f(c)·∫(B − B̄)(x − c) dA: the
    /// first-order correction that removes the O((r/d)²) bias of using the mean alone.
    pub(crate) fn density_gradient(&self, p: DVec3, n: DVec3) -> DVec3 {
        if self.area <= 0.0 {
            return DVec3::ZERO;
        }
        let b = self.normal_sum / self.area;
        let u = self.centroid - p;
        let q = u.length_squared();
        if q <= 0.0 {
            return DVec3::ZERO;
        }
        let (au, bu) = (n.dot(u), b.dot(u));
        let g = -au * bu;
        let su = -(n * bu + b * au) * 0.5;
        (su * (2.0 / (q * q)) - u * (4.0 * g / (q * q * q))) / PI
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::lambert;

    /// A grid of coplanar triangles (the shape of a wall's patches).
    fn grid(origin: DVec3, e1: DVec3, e2: DVec3, k: usize) -> (AreaMoments, Vec<[DVec3; 3]>) {
        let normal = e1.cross(e2).normalize();
        let mut m = AreaMoments::ZERO;
        let mut tris = Vec::new();
        for i in 0..k {
            for j in 0..k {
                let p = |a: usize, b: usize| {
                    origin + e1 * (a as f64 / k as f64) + e2 * (b as f64 / k as f64)
                };
                for t in [
                    [p(i, j), p(i + 1, j), p(i + 1, j + 1)],
                    [p(i, j), p(i + 1, j + 1), p(i, j + 1)],
                ] {
                    let area = (t[1] - t[0]).cross(t[2] - t[0]).length() / 2.0;
                    m = m.combine(&AreaMoments::triangle(&t, area, normal));
                    tris.push(t);
                }
            }
        }
        (m, tris)
    }

    #[test]
    fn combined_moments_match_direct_integration() {
        let (m, _) = grid(DVec3::ZERO, DVec3::X * 2.0, DVec3::Z * 1.0, 8);
        assert!((m.area - 2.0).abs() < 1e-12);
        assert!((m.centroid - DVec3::new(1.0, 0.0, 0.5)).length() < 1e-12);
        // Rectangle a × b: ∫x² dA about the centre = b·a³/12.
        assert!((m.second.x_axis.x - 1.0 * 8.0 / 12.0).abs() < 1e-12);
        assert!((m.second.z_axis.z - 2.0 * 1.0 / 12.0).abs() < 1e-12);
        assert!(m.second.y_axis.y.abs() < 1e-15);
    }

    #[test]
    fn second_order_error_is_small_at_moderate_distance() {
        // A 1 m square ceiling patch cluster, seen from points at several distances and angles.
        let (m, tris) = grid(
            DVec3::new(-0.5, 0.0, 0.5),
            DVec3::Z * -1.0,
            DVec3::X * 1.0,
            6,
        );
        // Grid normal is e1 × e2 = (−Z) × X = −Y: facing down.
        assert!(m.normal_sum.y < 0.0);
        for &(p, n, tol) in &[
            (DVec3::new(0.0, -4.0, 0.0), DVec3::Y, 1e-3),
            (DVec3::new(3.0, -2.0, 1.0), DVec3::Y, 3e-4),
            (
                DVec3::new(2.5, -1.5, 0.0),
                DVec3::new(-1.0, 1.0, 0.0).normalize(),
                2e-3,
            ),
            (DVec3::new(0.0, -8.0, 0.0), DVec3::Y, 6e-5),
        ] {
            let exact: f64 = tris.iter().map(|t| lambert::form_factor(p, n, t)).sum();
            let approx = m.form_factor(p, n);
            let zeroth =
                m.area * n.dot(m.centroid - p) * (-(m.normal_sum / m.area).dot(m.centroid - p))
                    / (PI * (m.centroid - p).length_squared().powi(2));
            let rel = (approx - exact).abs() / exact;
            let rel0 = (zeroth - exact).abs() / exact;
            assert!(rel < tol, "p={p}: approx {approx} exact {exact} rel {rel}");
            assert!(
                rel < rel0 / 20.0,
                "second order must improve on zeroth: {rel} vs {rel0}"
            );
        }
    }
}
