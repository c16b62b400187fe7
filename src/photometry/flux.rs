//! Luminous flux of the interpolated distribution: Φ = ∫∫ I(φ, θ) sin θ dθ dφ.
//!
//! Input: a [`Grid`]. Output: lm. Gauss–Legendre quadrature on every interpolation cell (6 nodes
//! in θ, 4 in φ per segment), so each piece of the piecewise cubic is integrated smoothly; a
//! single plane (axial symmetry) is integrated over θ and multiplied by 2π. The quadrature error
//! is far below the interpolation error (< 10⁻⁶ relative for the test distributions).

use super::grid::Grid;

/// Gauss–Legendre nodes on [−1, 1] and weights.
const GL6: [(f64, f64); 6] = [
    (-0.932_469_514_203_152, 0.171_324_492_379_170_3),
    (-0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (-0.238_619_186_083_196_9, 0.467_913_934_572_691),
    (0.238_619_186_083_196_9, 0.467_913_934_572_691),
    (0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (0.932_469_514_203_152, 0.171_324_492_379_170_3),
];
const GL4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// Quadrature points (angle in degrees, weight in radians) over consecutive segments of `nodes`.
fn points(nodes: impl Iterator<Item = (f64, f64)>, rule: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (a, b) in nodes {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        out.extend(
            rule.iter()
                .map(|&(x, w)| (mid + half * x, w * half.to_radians())),
        );
    }
    out
}

/// Total flux (lm) of the grid's interpolant.
pub(super) fn integrate(grid: &Grid) -> f64 {
    let t = &grid.thetas;
    let thetas: Vec<(f64, f64)> = points(t.windows(2).map(|w| (w[0], w[1])), &GL6)
        .into_iter()
        .map(|(th, w)| (th, w * th.to_radians().sin()))
        .collect();
    let p = &grid.planes;
    let phis = if p.len() == 1 {
        vec![(p[0], std::f64::consts::TAU)]
    } else {
        let segs = p.iter().zip(&grid.gaps).map(|(&a, &g)| (a, a + g));
        points(segs, &GL4)
    };
    let mut total = 0.0;
    for &(phi, wp) in &phis {
        let ring: f64 = thetas.iter().map(|&(th, w)| w * grid.eval(phi, th)).sum();
        total += wp * ring;
    }
    total
}
