//! Normal distributions of clusters: how a cluster of differently oriented patches (a chair seen
//! from across the room) sends light in each direction. Patches facing along an axis (floors,
//! desk tops, walls, box sides: most of a building) are kept exactly in six bins, since
//! max(0, ±eₖ·w) is known; the others go into order-2 real spherical harmonics, below.
//!
//! A cluster of patches j (area Aⱼ, unit normal mⱼ, exitance Bⱼ) has intensity
//! I(w) = Σⱼ Bⱼ·Aⱼ·max(0, mⱼ·w)/π toward the unit direction w. With Sₗₘ = Σⱼ Bⱼ·Aⱼ·Yₗₘ(mⱼ) (the
//! harmonics of the exitance-weighted normal distribution), max(0, m·w) = Σₗ Âₗ Σₘ Yₗₘ(m)·Yₗₘ(w)
//! (Funk–Hecke; Âₗ = π, 2π/3, π/4 for the clamped cosine) gives I(w) ≈ Σ Âₗ·Sₗₘ·Yₗₘ(w)/π, and
//! with Bⱼ = 1 the projected area the cluster shows toward w. Truncated at order 2 the clamped
//! cosine of a single normal is 1.0625 instead of 1 head-on and 0.0625 instead of 0 straight
//! behind (Ramamoorthi & Hanrahan 2001), and a cube (whose anisotropy is of order 4) shows 1.5
//! faces from every direction instead of 1 to √3. The mean over directions is exact (Cauchy: a
//! quarter of the area for closed shapes), so the errors of many clusters seen from many points
//! largely cancel. Only clusters whose normals spread too widely for the exact far-field moments
//! use it, and only far away.

use glam::DVec3;
use std::f64::consts::PI;

/// Coefficients Y₀₀, Y₁₋₁, Y₁₀, Y₁₁, Y₂₋₂, Y₂₋₁, Y₂₀, Y₂₁, Y₂₂.
pub type Coeffs = [f64; 9];

/// Entries of a [`Dist`]: areas (or exitance × areas) facing +x, −x, +y, −y, +z, −z exactly,
/// then the [`Coeffs`] of all other normals.
pub const DIST: usize = 15;
pub type Dist = [f64; DIST];

/// A normal within this of an axis counts as facing along it.
const AXIS: f64 = 1e-6;

/// A weight `a` at the unit normal `m`.
pub(crate) fn dist_point(m: DVec3, a: f64) -> Dist {
    let mut d = [0.0; DIST];
    for k in 0..3 {
        if (m[k].abs() - 1.0).abs() <= AXIS {
            d[2 * k + usize::from(m[k] < 0.0)] = a;
            return d;
        }
    }
    d[6..].copy_from_slice(&point(m, a));
    d
}

/// The weights that turn a [`Dist`] into Σⱼ wⱼ·max(0, mⱼ·w).
pub(crate) fn dist_weights(w: DVec3) -> Dist {
    let mut d = [0.0; DIST];
    for k in 0..3 {
        d[2 * k] = w[k].max(0.0);
        d[2 * k + 1] = (-w[k]).max(0.0);
    }
    d[6..].copy_from_slice(&projection_weights(w));
    d
}

/// Σⱼ Aⱼ·max(0, mⱼ·w) from a [`Dist`] of areas: the area shown toward `w`.
pub(crate) fn dist_projected(d: &Dist, w: DVec3) -> f64 {
    let x = dist_weights(w);
    (0..DIST).map(|k| d[k] * x[k]).sum()
}

/// The nine basis functions at the unit vector `w`.
pub(crate) fn basis(w: DVec3) -> Coeffs {
    let (x, y, z) = (w.x, w.y, w.z);
    [
        0.282_094_791_773_878_1,
        0.488_602_511_902_919_9 * y,
        0.488_602_511_902_919_9 * z,
        0.488_602_511_902_919_9 * x,
        1.092_548_430_592_079_2 * x * y,
        1.092_548_430_592_079_2 * y * z,
        0.315_391_565_252_520_05 * (3.0 * z * z - 1.0),
        1.092_548_430_592_079_2 * x * z,
        0.546_274_215_296_039_6 * (x * x - y * y),
    ]
}

/// Âₗ per coefficient: the clamped cosine's Funk–Hecke factors.
pub const CLAMPED_COSINE: Coeffs = [
    PI,
    2.0 * PI / 3.0,
    2.0 * PI / 3.0,
    2.0 * PI / 3.0,
    PI / 4.0,
    PI / 4.0,
    PI / 4.0,
    PI / 4.0,
    PI / 4.0,
];

/// The weights that turn a normal distribution's coefficients into Σⱼ wⱼ·max(0, mⱼ·w):
/// Âₗ·Yₗₘ(w).
pub(crate) fn projection_weights(w: DVec3) -> Coeffs {
    let y = basis(w);
    std::array::from_fn(|k| y[k] * CLAMPED_COSINE[k])
}

/// Σⱼ Aⱼ·max(0, mⱼ·w) from the coefficients of Σⱼ Aⱼ·δ(mⱼ): the area shown toward `w`.
pub fn projected(coeffs: &Coeffs, w: DVec3) -> f64 {
    let p = projection_weights(w);
    (0..9).map(|k| coeffs[k] * p[k]).sum()
}

/// Coefficients of a weight `a` at the unit normal `m`.
pub(crate) fn point(m: DVec3, a: f64) -> Coeffs {
    basis(m).map(|y| y * a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's face normals.
    const CUBE: [DVec3; 6] = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];

    /// The sum of several distributions.
    fn total<const N: usize>(parts: impl Iterator<Item = [f64; N]>) -> [f64; N] {
        parts.fold([0.0; N], |acc, p| std::array::from_fn(|k| acc[k] + p[k]))
    }

    fn directions() -> impl Iterator<Item = DVec3> {
        (0..200).map(|k| {
            // A spiral over the sphere.
            let z = 1.0 - (k as f64 + 0.5) / 100.0;
            let phi = k as f64 * 2.399_963_229_728_653;
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
    }

    #[test]
    fn basis_is_orthonormal() {
        // Quadrature over a fine latitude-longitude grid.
        let (nt, np) = (200, 400);
        let mut gram = [[0.0; 9]; 9];
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * PI;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
                let w = DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let y = basis(w);
                let da = theta.sin() * (PI / nt as f64) * (2.0 * PI / np as f64);
                for (row, ya) in gram.iter_mut().zip(y) {
                    for (g, yb) in row.iter_mut().zip(y) {
                        *g += ya * yb * da;
                    }
                }
            }
        }
        for (a, row) in gram.iter().enumerate() {
            for (b, g) in row.iter().enumerate() {
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((g - want).abs() < 1e-3, "{a} {b} {g}");
            }
        }
    }

    #[test]
    fn single_normal_matches_the_truncated_clamped_cosine() {
        // Order 2 of max(0, cos θ) in Legendre polynomials: 1/4 + cos/2 + (5/16)(3cos² − 1)/2.
        let m = DVec3::new(0.2, -0.5, 0.7).normalize();
        let c = point(m, 2.0);
        for w in directions() {
            let x = m.dot(w);
            let want = 2.0 * (0.25 + 0.5 * x + 5.0 / 16.0 * (3.0 * x * x - 1.0) / 2.0);
            assert!((projected(&c, w) - want).abs() < 1e-12);
        }
        assert!((projected(&c, m) - 2.0 * 1.0625).abs() < 1e-12);
        assert!((projected(&c, -m) - 2.0 * 0.0625).abs() < 1e-12);
    }

    #[test]
    fn axis_faces_are_exact_and_others_go_to_harmonics() {
        // A unit cube: exact |wx| + |wy| + |wz| from the bins.
        for m in CUBE {
            assert_eq!(dist_point(m, 1.0)[6..], [0.0; 9]);
        }
        let d = total(CUBE.into_iter().map(|m| dist_point(m, 1.0)));
        for w in directions() {
            let exact = w.x.abs() + w.y.abs() + w.z.abs();
            assert!((dist_projected(&d, w) - exact).abs() < 1e-12);
        }
        // A slanted normal has no bin.
        let m = DVec3::new(1.0, 1.0, 0.0).normalize();
        let p = dist_point(m, 2.0);
        assert_eq!(p[..6], [0.0; 6]);
        assert!((dist_projected(&p, m) - 2.0 * 1.0625).abs() < 1e-12);
    }

    #[test]
    fn closed_shapes_show_a_quarter_of_their_area_on_average() {
        // A unit cube shows |wx| + |wy| + |wz| toward w.
        let c = total(CUBE.into_iter().map(|m| point(m, 1.0)));
        // Order 2 keeps only the mean of its projected area |wx| + |wy| + |wz|: 1.5 everywhere.
        for w in directions() {
            assert!((projected(&c, w) - 1.5).abs() < 1e-12);
        }
        let mean: f64 = directions()
            .map(|w| w.x.abs() + w.y.abs() + w.z.abs())
            .sum::<f64>()
            / 200.0;
        assert!((mean - 1.5).abs() < 0.01, "{mean}");
        // A sphere's normals (uniform): projected area = total / 4 exactly (only l = 0 remains).
        let s = total(directions().map(|m| point(m, 1.0 / 200.0)));
        for w in directions() {
            assert!(
                (projected(&s, w) - 0.25).abs() < 0.01,
                "{}",
                projected(&s, w)
            );
        }
    }
}
