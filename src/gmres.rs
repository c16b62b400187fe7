//! The linear solver of the solve stage (`bake/solve.rs`): restarted GMRES on (I − ρ·G)·B = b.
//!
//! Input: the operator x ↦ x − ρ·G(x) as a closure over per-patch RGB vectors, the right-hand
//! side b (first reflected exitance, ρ·E_direct), per-patch weights (areas: the inner product is
//! flux-weighted), a relative tolerance. Output: the reflected exitance B and [`SolveStats`].
//!
//! Why GMRES: the error of a bounce-by-bounce (Jacobi) solver shrinks like ρᵏ, so at ρ = 0.99 it
//! needs ~900 sweeps for 10⁻⁴, and stopping early is exactly RADIANCE's −25 % at ρ = 0.95. In a
//! room the slow mode is nearly one vector (uniform exitance); GMRES removes such isolated modes in
//! a few iterations, so its iteration count barely grows as ρ → 1. It stops on the residual
//! ‖b − A·B‖ / ‖b‖ < tol (a flux-weighted 2-norm), never on an iteration count unless the cap is
//! hit, in which case the result says `converged: false`. All reductions run sequentially in index
//! order, so the result does not depend on the thread count.
//!
//! The Krylov basis is stored in single precision (half the solve's memory on a large floor);
//! the vector being orthogonalised, the solution and the residual stay in double. Rounding the
//! basis perturbs a cycle's Arnoldi relation by about 6·10⁻⁸ of its vectors, so a cycle may stop
//! short of the tolerance it estimates; the true residual, recomputed in double at every restart,
//! decides, and the next cycle corrects what the rounding left (iterative refinement).

use glam::{DVec3, Vec3};

#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct SolveStats {
    pub iterations: usize,
    /// Final relative residual ‖b − A·x‖ / ‖b‖ (flux-weighted 2-norm).
    pub relative_residual: f64,
    pub converged: bool,
}

/// A vector the operator is applied to: the iterate (double) or a basis vector (single).
#[derive(Clone, Copy)]
pub enum Input<'a> {
    Double(&'a [DVec3]),
    Single(&'a [Vec3]),
}

impl Input<'_> {
    /// Component `i`, in double.
    pub(crate) fn get(&self, i: usize) -> DVec3 {
        match self {
            Input::Double(x) => x[i],
            Input::Single(x) => x[i].as_dvec3(),
        }
    }
}

/// Solve A·x = b for x, with A given by `apply(x, out)`.
pub(crate) fn gmres(
    apply: impl Fn(Input, &mut [DVec3]),
    b: &[DVec3],
    weights: &[f64],
    tol: f64,
    max_iterations: usize,
    restart: usize,
) -> (Vec<DVec3>, SolveStats) {
    let n = b.len();
    let dot = |x: &[DVec3], y: &[DVec3]| -> f64 {
        x.iter()
            .zip(y)
            .zip(weights)
            .map(|((a, c), w)| w * a.dot(*c))
            .sum()
    };
    let b_norm = dot(b, b).sqrt();
    let mut x = b.to_vec();
    let mut stats = SolveStats {
        iterations: 0,
        relative_residual: 0.0,
        converged: true,
    };
    if b_norm == 0.0 || n == 0 {
        return (vec![DVec3::ZERO; n], stats);
    }
    // Memory: x and the vector being filled (double), the basis (single).
    loop {
        let mut r = vec![DVec3::ZERO; n];
        apply(Input::Double(&x), &mut r);
        for (r, b) in r.iter_mut().zip(b) {
            *r = *b - *r;
        }
        let beta = dot(&r, &r).sqrt();
        stats.relative_residual = beta / b_norm;
        if stats.relative_residual < tol {
            return (x, stats);
        }
        // A residual that is not finite cannot improve: stop at once (the caller reports it).
        if stats.iterations >= max_iterations || !stats.relative_residual.is_finite() {
            stats.converged = false;
            return (x, stats);
        }
        // Arnoldi with modified Gram–Schmidt and Givens rotations.
        let m = restart.min(max_iterations - stats.iterations).max(1);
        let mut v: Vec<Vec<Vec3>> = vec![single(&r, beta)];
        drop(r);
        let mut h = vec![vec![0.0; m]; m + 1];
        let (mut cs, mut sn) = (vec![0.0; m], vec![0.0; m]);
        let mut g = vec![0.0; m + 1];
        g[0] = beta;
        let mut k_used = 0;
        for k in 0..m {
            let mut w = vec![DVec3::ZERO; n];
            apply(Input::Single(&v[k]), &mut w);
            for (j, vj) in v.iter().enumerate() {
                h[j][k] = dot_single(&w, vj, weights);
                for (wi, vi) in w.iter_mut().zip(vj) {
                    *wi -= vi.as_dvec3() * h[j][k];
                }
            }
            // ‖w‖: the subdiagonal entry, the breakdown test and the next basis vector's scale.
            let norm = dot(&w, &w).sqrt();
            h[k + 1][k] = norm;
            for j in 0..k {
                let t = cs[j] * h[j][k] + sn[j] * h[j + 1][k];
                h[j + 1][k] = -sn[j] * h[j][k] + cs[j] * h[j + 1][k];
                h[j][k] = t;
            }
            let denom = h[k][k].hypot(h[k + 1][k]);
            (cs[k], sn[k]) = if denom == 0.0 {
                (1.0, 0.0)
            } else {
                (h[k][k] / denom, h[k + 1][k] / denom)
            };
            h[k][k] = cs[k] * h[k][k] + sn[k] * h[k + 1][k];
            h[k + 1][k] = 0.0;
            g[k + 1] = -sn[k] * g[k];
            g[k] *= cs[k];
            stats.iterations += 1;
            k_used = k + 1;
            let breakdown = norm <= 1e-300;
            if (g[k + 1].abs() / b_norm) < tol * 0.5 || breakdown {
                break;
            }
            v.push(single(&w, norm));
        }
        // Back-substitute y from the triangular system and update x.
        let mut y = vec![0.0; k_used];
        for i in (0..k_used).rev() {
            let mut s = g[i];
            for j in (i + 1)..k_used {
                s -= h[i][j] * y[j];
            }
            y[i] = if h[i][i] != 0.0 { s / h[i][i] } else { 0.0 };
        }
        for (j, yj) in y.iter().enumerate() {
            for (xi, vi) in x.iter_mut().zip(&v[j]) {
                *xi += vi.as_dvec3() * *yj;
            }
        }
    }
}

/// `x / norm` rounded to single precision (a basis vector).
fn single(x: &[DVec3], norm: f64) -> Vec<Vec3> {
    x.iter().map(|c| (*c / norm).as_vec3()).collect()
}

/// The weighted inner product of a double vector with a single-precision basis vector.
fn dot_single(x: &[DVec3], v: &[Vec3], weights: &[f64]) -> f64 {
    x.iter()
        .zip(v)
        .zip(weights)
        .map(|((a, c), w)| w * a.dot(c.as_dvec3()))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense "room": uniform form factors F_ij = 1/(n−1) (a closed enclosure where every patch
    /// sees every other equally), reflectance ρ. The exact solution of B = ρ(e + F·B) is known.
    #[test]
    fn converges_at_high_reflectance_to_the_exact_answer() {
        let n = 50;
        for &rho in &[0.3, 0.9, 0.99, 0.999] {
            let e: Vec<DVec3> = (0..n)
                .map(|i| DVec3::splat(if i == 0 { 100.0 } else { 0.0 }))
                .collect();
            let b: Vec<DVec3> = e.iter().map(|x| *x * rho).collect();
            let apply = |x: Input, out: &mut [DVec3]| {
                let total: DVec3 = (0..n).map(|i| x.get(i)).sum();
                for (i, o) in out.iter_mut().enumerate() {
                    let gathered = (total - x.get(i)) / (n - 1) as f64;
                    *o = x.get(i) - gathered * rho;
                }
            };
            let w = vec![1.0; n];
            let (x, stats) = gmres(apply, &b, &w, 1e-10, 500, 30);
            assert!(stats.converged, "{rho}: {stats:?}");
            assert!(
                stats.iterations < 20,
                "GMRES needs few iterations here: {stats:?}"
            );
            // Energy: total reflected exitance Σ B = ρ(Σe + Σ B) → Σ B = ρ Σe / (1 − ρ).
            let sum: f64 = x.iter().map(|v| v.x).sum();
            let want = rho * 100.0 / (1.0 - rho);
            assert!((sum - want).abs() < 1e-7 * want, "{rho}: {sum} vs {want}");
        }
    }

    #[test]
    fn a_non_finite_right_hand_side_stops_at_once() {
        let b = vec![DVec3::splat(f64::INFINITY), DVec3::ONE];
        let apply = |x: Input, out: &mut [DVec3]| {
            for (i, o) in out.iter_mut().enumerate() {
                *o = x.get(i);
            }
        };
        let (_, stats) = gmres(apply, &b, &[1.0, 1.0], 1e-10, 2000, 30);
        assert!(!stats.converged && stats.iterations == 0, "{stats:?}");
        assert!(!stats.relative_residual.is_finite());
    }
}
