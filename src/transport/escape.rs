//! Escape: the share of a patch's cosine-weighted hemisphere through which light leaves the
//! scene, measured with rays.
//!
//! Input: the patch mesh, the occluder, a weight per patch (0: not measured) and a salt that
//! keeps one use's ray pattern apart from another's. Output: per patch, the fraction in [0, 1]
//! (0 where not measured).
//!
//! Each measured patch traces k × k stratified cosine-weighted rays, the pattern shifted within
//! its cells by a value of the patch's own and the rays leaving from points spread over the
//! patch, so the estimates summed over patches are unbiased (a fixed pattern from the centroids
//! repeats one error at every patch facing the same way). Rays go where the weight is: 256 a
//! patch on average, shared in proportion to the weights, between 64 and 2¹⁶ a patch.
//! Deterministic: the pattern depends on the patch index and the salt only.

use crate::geom::samples;
use crate::patches::PatchMesh;
use crate::visibility::Occluder;
use rayon::prelude::*;

/// Rays a measured patch gets on average.
const MEAN_RAYS: f64 = 256.0;

pub(crate) fn open_fractions(
    mesh: &PatchMesh,
    occ: &Occluder,
    weight: &[f64],
    salt: u64,
) -> Vec<f64> {
    let measured = weight.iter().filter(|&&w| w > 0.0).count();
    let total: f64 = weight.iter().filter(|&&w| w > 0.0).sum();
    let budget = MEAN_RAYS * measured as f64;
    (weight.par_iter().enumerate())
        .map(|(k, &w)| {
            if !(w > 0.0) {
                return 0.0;
            }
            let rays = (budget * w / total).clamp(64.0, 65536.0);
            let side = rays.sqrt().ceil() as usize;
            let p = &mesh.patches[k];
            let c = p.corners(&mesh.receivers);
            let points = samples::triangle_points(2);
            let at = |m: usize| {
                let b = points[(m * 7 + m / side * 5) % points.len()];
                c[0] * b[0] + c[1] * b[1] + c[2] * b[2]
            };
            let shift = samples::unit_pair(k as u64 ^ salt);
            let open = samples::shifted_cosine_directions(p.normal, side, shift)
                .enumerate()
                .filter(|(m, d)| occ.escapes(at(*m), p.normal, *d))
                .count();
            open as f64 / (side * side) as f64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use glam::DVec3;

    #[test]
    fn a_floor_under_an_open_box_loses_what_its_opening_subtends() {
        // A 2 × 2 m floor under a 2 × 2 m roof 1 m up, the sides open: from the floor's middle
        // the roof's view factor is known (parallel squares, ANALYTIC.md): F = 0.4152 for a
        // 2 × 2 pair 1 m apart seen from the whole floor. Escape = 1 − F.
        let mut b = SceneBuilder::new();
        let m = b.material("grey", 0.5);
        b.quad(
            "floor",
            [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(0.0, 0.0, 2.0),
                DVec3::new(2.0, 0.0, 2.0),
                DVec3::new(2.0, 0.0, 0.0),
            ],
            m,
        );
        b.quad(
            "roof",
            [
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(2.0, 1.0, 0.0),
                DVec3::new(2.0, 1.0, 2.0),
                DVec3::new(0.0, 1.0, 2.0),
            ],
            m,
        );
        let scene = b.build();
        let occ = Occluder::build(&scene, Default::default());
        let mesh = crate::patches::build(&scene, 0.1, None);
        let floor: Vec<f64> = (mesh.patches.iter())
            .map(|p| if p.normal.y > 0.5 { p.area } else { 0.0 })
            .collect();
        let open = open_fractions(&mesh, &occ, &floor, 1);
        let lost: f64 = open.iter().zip(&floor).map(|(o, a)| o * a).sum::<f64>() / 4.0;
        let exact = 1.0 - parallel_squares(2.0, 1.0);
        // 256 rays a patch: σ = √(f(1 − f)/rays) over the floor; within 4σ.
        let rays = 256.0 * floor.iter().filter(|&&a| a > 0.0).count() as f64;
        let sigma = (exact * (1.0 - exact) / rays).sqrt();
        assert!(
            (lost - exact).abs() < 4.0 * sigma,
            "{lost} vs {exact} (σ {sigma})"
        );
    }

    /// View factor between two directly opposed parallel a × a squares a distance c apart.
    fn parallel_squares(a: f64, c: f64) -> f64 {
        let (x, y) = (a / c, a / c);
        let (x2, y2) = (x * x, y * y);
        let pi = std::f64::consts::PI;
        2.0 / (pi * x * y)
            * (((1.0 + x2) * (1.0 + y2) / (1.0 + x2 + y2)).sqrt().ln()
                + x * (1.0 + y2).sqrt() * (x / (1.0 + y2).sqrt()).atan()
                + y * (1.0 + x2).sqrt() * (y / (1.0 + x2).sqrt()).atan()
                - x * x.atan()
                - y * y.atan())
    }
}
