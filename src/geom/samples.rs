//! Deterministic sample patterns: points on a triangle (for visibility), stratified
//! directions over a hemisphere (for escape tests), and scattered directions over the sphere (for
//! checks and benchmarks). Fixed patterns keep bakes noise-free in the
//! sense that matters to CI: the same input gives the same numbers.

use glam::DVec3;
use std::sync::OnceLock;

/// Barycentric sample points on a triangle: the centroids of the 4^level sub-triangles of its
/// uniform subdivision (level 0: the centroid). Each point stands for an equal area.
pub(crate) fn triangle_points(level: u32) -> &'static [[f64; 3]] {
    static LEVELS: OnceLock<[Vec<[f64; 3]>; 3]> = OnceLock::new();
    let levels = LEVELS.get_or_init(|| [grid_centroids(1), grid_centroids(2), grid_centroids(4)]);
    &levels[level.min(2) as usize]
}

fn grid_centroids(n: usize) -> Vec<[f64; 3]> {
    let nf = n as f64;
    let mut out = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..(n - j) {
            let (b, c) = ((i as f64 + 1.0 / 3.0) / nf, (j as f64 + 1.0 / 3.0) / nf);
            out.push([1.0 - b - c, b, c]);
            if i + j + 1 < n {
                let (b, c) = ((i as f64 + 2.0 / 3.0) / nf, (j as f64 + 2.0 / 3.0) / nf);
                out.push([1.0 - b - c, b, c]);
            }
        }
    }
    out
}

/// `k × k` cosine-weighted directions over the hemisphere around `n`, one per cell of a stratified
/// grid in (u, v) (each stands for an equal share of projected solid angle).
pub(crate) fn cosine_directions(n: DVec3, k: usize) -> impl Iterator<Item = DVec3> {
    shifted_cosine_directions(n, k, [0.5, 0.5])
}

/// [`cosine_directions`] with the point in each cell at `shift` (in [0, 1)², the cell's middle
/// at [0.5, 0.5]). A shift drawn per use ([`unit_pair`]) makes the pattern's estimates unbiased
/// when summed over many uses, where a fixed pattern repeats its error at every one.
pub(crate) fn shifted_cosine_directions(
    n: DVec3,
    k: usize,
    shift: [f64; 2],
) -> impl Iterator<Item = DVec3> {
    let (t, b) = n.any_orthonormal_pair();
    (0..k * k).map(move |c| {
        let u = ((c / k) as f64 + shift[0]) / k as f64;
        let v = ((c % k) as f64 + shift[1]) / k as f64;
        let r = u.sqrt();
        let phi = 2.0 * std::f64::consts::PI * v;
        t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u).sqrt()
    })
}

/// Two numbers in [0, 1) hashed from `seed` (SplitMix64's finaliser): a fixed, well-spread value
/// per patch or ray pattern, so that results do not depend on the order of work.
pub(crate) fn unit_pair(seed: u64) -> [f64; 2] {
    let mix = |x: u64| {
        let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let a = mix(seed);
    let b = mix(a);
    [a, b].map(|z| (z >> 11) as f64 / (1u64 << 53) as f64)
}

/// `n` unit directions scattered over the whole sphere, uniform in area: a pseudo-random sequence
/// (a 64-bit linear congruential generator) with a fixed seed, so always the same directions.
pub fn scattered_directions(n: usize) -> Vec<DVec3> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let z = 2.0 * next() - 1.0;
            let phi = std::f64::consts::TAU * next();
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_points_are_inside_and_balanced() {
        for level in 0..3 {
            let pts = triangle_points(level);
            assert_eq!(pts.len(), 4usize.pow(level));
            let mut mean = [0.0; 3];
            for p in pts {
                assert!(p.iter().all(|&w| w > 0.0 && w < 1.0));
                assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
                for k in 0..3 {
                    mean[k] += p[k] / pts.len() as f64;
                }
            }
            for m in mean {
                assert!((m - 1.0 / 3.0).abs() < 1e-12, "sample mean is the centroid");
            }
        }
    }

    #[test]
    fn cosine_directions_are_unit_and_in_hemisphere() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        let dirs: Vec<_> = cosine_directions(n, 8).collect();
        assert_eq!(dirs.len(), 64);
        // Mean of cos θ under the cosine distribution is 2/3.
        let mean_cos: f64 = dirs.iter().map(|d| d.dot(n)).sum::<f64>() / 64.0;
        assert!((mean_cos - 2.0 / 3.0).abs() < 0.01, "{mean_cos}");
        assert!(
            dirs.iter()
                .all(|d| (d.length() - 1.0).abs() < 1e-12 && d.dot(n) > 0.0)
        );
    }
}
