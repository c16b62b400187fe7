//! Bounded-variable least squares: minimise ‖M x − y‖² subject to 0 ≤ x ≤ upper, by the active
//! set method (Lawson & Hanson's NNLS with upper bounds, Stark & Parker 1995).
//!
//! Input: M as rows (each row one equation), y, the upper bound. Output: x. Invariants: x lies
//! in the box; at return the Karush–Kuhn–Tucker conditions hold to `1e-12` of the scale of
//! Mᵀy, or the iteration cap (a few times the number of unknowns) was reached; deterministic
//! (no randomness, fixed order). Sized for `bake fit`: tens of unknowns, tens of equations.

/// Where an unknown stands.
#[derive(Debug, Clone, Copy, PartialEq)]
enum State {
    Lower,
    Upper,
    Free,
}

/// Solve min ‖M x − y‖², 0 ≤ x ≤ upper (`upper` may be infinite).
pub(crate) fn solve(m: &[Vec<f64>], y: &[f64], upper: f64) -> Vec<f64> {
    let n = m.first().map_or(0, Vec::len);
    let mut x = vec![0.0; n];
    let mut state = vec![State::Lower; n];
    let scale = (0..n)
        .map(|j| {
            (m.iter().zip(y))
                .map(|(r, yi)| (r[j] * yi).abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    for _ in 0..(3 * n + 10) {
        // −gradient of ½‖Mx − y‖²: Mᵀ(y − Mx).
        let w = gradient(m, y, &x);
        let wants = |j: usize| match state[j] {
            State::Lower => w[j],
            State::Upper => -w[j],
            State::Free => 0.0,
        };
        let Some(j) = (0..n)
            .filter(|&j| wants(j) > 1e-12 * scale)
            .max_by(|&a, &b| wants(a).total_cmp(&wants(b)))
        else {
            break;
        };
        state[j] = State::Free;
        loop {
            let free: Vec<usize> = (0..n).filter(|&j| state[j] == State::Free).collect();
            let z = free_solution(m, y, &x, &free);
            let inside = |k: usize| z[k] > 0.0 && z[k] < upper;
            if (0..free.len()).all(inside) {
                for (k, &j) in free.iter().enumerate() {
                    x[j] = z[k];
                }
                break;
            }
            // Step from x toward z until the first free unknown reaches a bound.
            let mut alpha = 1.0_f64;
            for (k, &j) in free.iter().enumerate() {
                let d = z[k] - x[j];
                if z[k] <= 0.0 && d < 0.0 {
                    alpha = alpha.min(-x[j] / d);
                } else if z[k] >= upper && d > 0.0 {
                    alpha = alpha.min((upper - x[j]) / d);
                }
            }
            for (k, &j) in free.iter().enumerate() {
                x[j] += alpha * (z[k] - x[j]);
                if x[j] <= 1e-15 * upper.min(1.0) || (z[k] <= 0.0 && x[j] <= 0.0) {
                    x[j] = 0.0;
                    state[j] = State::Lower;
                } else if x[j] >= upper * (1.0 - 1e-15) {
                    x[j] = upper;
                    state[j] = State::Upper;
                }
            }
            if free.iter().all(|&j| state[j] != State::Free) {
                break;
            }
        }
    }
    x
}

fn gradient(m: &[Vec<f64>], y: &[f64], x: &[f64]) -> Vec<f64> {
    let mut w = vec![0.0; x.len()];
    for (row, yi) in m.iter().zip(y) {
        let r = yi - row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        for (wj, a) in w.iter_mut().zip(row) {
            *wj += a * r;
        }
    }
    w
}

/// The least-squares values of the `free` unknowns with the others held at `x`: normal
/// equations with a ridge of 10⁻¹² of the largest diagonal (two groups lighting the same
/// surfaces in the same proportions share the light instead of failing), by Cholesky.
fn free_solution(m: &[Vec<f64>], y: &[f64], x: &[f64], free: &[usize]) -> Vec<f64> {
    let k = free.len();
    let mut a = vec![vec![0.0; k]; k];
    let mut b = vec![0.0; k];
    for (row, yi) in m.iter().zip(y) {
        // What the bound unknowns already give.
        let fixed: f64 = (0..x.len())
            .filter(|j| !free.contains(j))
            .map(|j| row[j] * x[j])
            .sum();
        for (p, &i) in free.iter().enumerate() {
            b[p] += row[i] * (yi - fixed);
            for (q, &j) in free.iter().enumerate() {
                a[p][q] += row[i] * row[j];
            }
        }
    }
    let ridge = 1e-12 * (0..k).map(|i| a[i][i]).fold(0.0, f64::max);
    for (i, r) in a.iter_mut().enumerate() {
        r[i] += ridge.max(f64::MIN_POSITIVE);
    }
    cholesky_solve(a, b)
}

fn cholesky_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let k = b.len();
    for j in 0..k {
        let d = a[j][j] - (0..j).map(|p| a[j][p] * a[j][p]).sum::<f64>();
        a[j][j] = d.max(f64::MIN_POSITIVE).sqrt();
        for i in j + 1..k {
            let s = a[i][j] - (0..j).map(|p| a[i][p] * a[j][p]).sum::<f64>();
            a[i][j] = s / a[j][j];
        }
    }
    for i in 0..k {
        b[i] = (b[i] - (0..i).map(|p| a[i][p] * b[p]).sum::<f64>()) / a[i][i];
    }
    for i in (0..k).rev() {
        b[i] = (b[i] - (i + 1..k).map(|p| a[p][i] * b[p]).sum::<f64>()) / a[i][i];
    }
    b
}

#[cfg(test)]
mod tests {
    use super::solve;

    fn close(a: &[f64], b: &[f64]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn an_exact_interior_solution_is_found() {
        let m = vec![vec![2.0, 1.0], vec![1.0, 3.0], vec![1.0, 1.0]];
        let x = [0.7, 1.3];
        let y: Vec<f64> = m.iter().map(|r| r[0] * x[0] + r[1] * x[1]).collect();
        assert!(close(&solve(&m, &y, 10.0), &x));
    }

    #[test]
    fn bounds_hold_and_the_rest_is_optimal() {
        // Unconstrained optimum (−1, 2): x0 sits at 0, x1 is then the 1-D optimum.
        let m = vec![vec![1.0, 0.0], vec![0.0, 1.0]];
        assert!(close(&solve(&m, &[-1.0, 2.0], 10.0), &[0.0, 2.0]));
        // Upper bound 1.5 binds x1.
        assert!(close(&solve(&m, &[-1.0, 2.0], 1.5), &[0.0, 1.5]));
        // Coupled: min (x0 + x1 − 4)² + (x0 − x1)² with x ≤ 1.5: both at the bound.
        let m = vec![vec![1.0, 1.0], vec![1.0, -1.0]];
        assert!(close(&solve(&m, &[4.0, 0.0], 1.5), &[1.5, 1.5]));
        // With x0 ≤ 1 binding only through coupling: min (x0 + x1 − 3)² + (x0 − 2)², upper 1.
        let m = vec![vec![1.0, 1.0], vec![1.0, 0.0]];
        assert!(close(&solve(&m, &[3.0, 2.0], 1.0), &[1.0, 1.0]));
    }

    #[test]
    fn kkt_holds_on_a_random_looking_problem() {
        // Deterministic pseudo-random 8×5 problem; check the KKT conditions.
        let mut s = 12345u64;
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 33) as f64) / (1u64 << 31) as f64
        };
        let m: Vec<Vec<f64>> = (0..8).map(|_| (0..5).map(|_| r()).collect()).collect();
        let y: Vec<f64> = (0..8).map(|_| 3.0 * r() - 0.5).collect();
        let upper = 0.8;
        let x = solve(&m, &y, upper);
        let w = super::gradient(&m, &y, &x);
        for (xj, wj) in x.iter().zip(&w) {
            assert!((0.0..=upper).contains(xj));
            if *xj == 0.0 {
                assert!(*wj <= 1e-9, "{x:?} {w:?}");
            } else if *xj == upper {
                assert!(*wj >= -1e-9, "{x:?} {w:?}");
            } else {
                assert!(wj.abs() < 1e-9, "{x:?} {w:?}");
            }
        }
    }
}
