//! The intensity table over the sphere and its interpolation.
//!
//! Input: plane angles φ, polar angles θ (degrees, strictly increasing) and absolute candela per
//! plane and θ, already expanded by symmetry (type C planes cover [0°, 360°) and are periodic;
//! types A/B cover their measured φ range only). Output: `eval(φ, θ)`, cd.
//!
//! Interpolation: cubic Hermite in θ within each plane (coefficients precomputed), then cubic
//! Hermite across the four nearest planes in φ (periodic for type C). Node slopes are the
//! three-point (quadratic-exact) estimates for uneven spacing, limited where the data are
//! monotone so the curve cannot overshoot there (Hyman's filter: |m| ≤ 3·min|Δ|), zero next to a
//! flat run (a beam edge dropping to 0 stays at 0), kept as they are at a strict extremum (a
//! peak stays smooth). At a type C pole (γ = 0° or 180°) the slope uses the opposite plane
//! (φ + 180°) as the point beyond the pole, so a nadir peak is smooth. Invariants: exact at every
//! node; C¹ in θ and φ; never negative (clamped at 0); 0 outside the measured θ range and,
//! for types A/B, outside the measured φ range.

use super::frame::Frame;

/// Angles closer than this (degrees) are the same angle.
pub(super) const EPS_DEG: f64 = 1e-9;

#[derive(Debug, Clone)]
pub(super) struct Grid {
    pub(super) frame: Frame,
    /// φ of each plane; periodic: in [0°, 360°).
    pub(super) planes: Vec<f64>,
    /// Spacing after each plane: `planes.len()` entries when periodic (the last wraps), else one fewer.
    pub(super) gaps: Vec<f64>,
    pub(super) thetas: Vec<f64>,
    /// cd, plane-major: `values[j * thetas.len() + i]`.
    pub(super) values: Vec<f64>,
    /// Hermite coefficients per plane and θ segment, in the segment's local t ∈ [0, 1].
    coefs: Vec<[f64; 4]>,
    plane_nodes: Axis,
    theta_nodes: Axis,
}

/// Sorted nodes with an O(1) lookup when evenly spaced.
#[derive(Debug, Clone)]
struct Axis {
    x: Vec<f64>,
    step: Option<f64>,
}

impl Axis {
    fn new(x: Vec<f64>) -> Axis {
        let n = x.len();
        let step = (n >= 2).then(|| (x[n - 1] - x[0]) / (n - 1) as f64);
        let even = step.filter(|s| {
            x.windows(2)
                .all(|w| ((w[1] - w[0]) - s).abs() <= 1e-9 * s.abs())
        });
        Axis { x, step: even }
    }

    /// Segment k (nodes k, k + 1) holding `v` (clamped into range) and the local t.
    #[inline]
    fn locate(&self, v: f64) -> (usize, f64) {
        let x = &self.x;
        let n = x.len();
        let mut k = match self.step {
            Some(s) => ((v - x[0]) / s).max(0.0) as usize,
            None => x.partition_point(|&a| a <= v).saturating_sub(1),
        };
        k = k.min(n - 2);
        (k, (v - x[k]) / (x[k + 1] - x[k]))
    }
}

/// Slope at an interior node from its neighbours (spacings h0, h1; values y0, y1, y2).
#[inline]
fn slope(h0: f64, h1: f64, y0: f64, y1: f64, y2: f64) -> f64 {
    let d0 = (y1 - y0) / h0;
    let d1 = (y2 - y1) / h1;
    let m = (h1 * d0 + h0 * d1) / (h0 + h1);
    if d0 == 0.0 || d1 == 0.0 {
        0.0
    } else if (d0 > 0.0) != (d1 > 0.0) {
        m
    } else if (m > 0.0) != (d0 > 0.0) {
        0.0
    } else {
        m.signum() * m.abs().min(3.0 * d0.abs().min(d1.abs()))
    }
}

/// Slope at the first node of a non-periodic run: one-sided three-point, limited
/// (Fritsch–Carlson's end condition). `y2` is `None` for a run of two nodes.
#[inline]
fn end_slope(h0: f64, h1: f64, y0: f64, y1: f64, y2: Option<f64>) -> f64 {
    let d0 = (y1 - y0) / h0;
    let Some(y2) = y2 else { return d0 };
    let d1 = (y2 - y1) / h1;
    let m = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
    if (m > 0.0) != (d0 > 0.0) || d0 == 0.0 {
        0.0
    } else if (d0 > 0.0) != (d1 > 0.0) && m.abs() > 3.0 * d0.abs() {
        3.0 * d0
    } else {
        m
    }
}

/// Cubic Hermite on [0, 1] with end values y0, y1 and end slopes (per unit t) s0, s1.
#[inline]
fn hermite(y0: f64, y1: f64, s0: f64, s1: f64, t: f64) -> f64 {
    let c = hermite_coefs(y0, y1, s0, s1);
    c[0] + t * (c[1] + t * (c[2] + t * c[3]))
}

#[inline]
fn hermite_coefs(y0: f64, y1: f64, s0: f64, s1: f64) -> [f64; 4] {
    [
        y0,
        s0,
        3.0 * (y1 - y0) - 2.0 * s0 - s1,
        2.0 * (y0 - y1) + s0 + s1,
    ]
}

impl Grid {
    /// The table; `planes` and `thetas` strictly increasing, at least two θ, `values` plane-major.
    pub(super) fn new(frame: Frame, planes: Vec<f64>, thetas: Vec<f64>, values: Vec<f64>) -> Grid {
        debug_assert_eq!(values.len(), planes.len() * thetas.len());
        let n = planes.len();
        let mut gaps: Vec<f64> = planes.windows(2).map(|w| w[1] - w[0]).collect();
        let mut ext = planes.clone();
        if frame.periodic {
            gaps.push(planes[0] + 360.0 - planes[n - 1]);
            ext.push(planes[0] + 360.0);
        }
        let mut grid = Grid {
            frame,
            plane_nodes: Axis::new(ext),
            theta_nodes: Axis::new(thetas.clone()),
            planes,
            gaps,
            thetas,
            values,
            coefs: Vec::new(),
        };
        grid.coefs = (0..n).flat_map(|j| grid.plane_coefs(j)).collect();
        grid
    }

    /// Hermite coefficients of plane j's θ segments.
    fn plane_coefs(&self, j: usize) -> Vec<[f64; 4]> {
        let t = &self.thetas;
        let m = t.len();
        let y = &self.values[j * m..(j + 1) * m];
        let row = |i: usize| move |k: usize| self.values[k * m + i];
        let opposite = (self.planes[j] + 180.0).rem_euclid(360.0);
        let pole = |at: f64| self.frame.periodic && (t[0] - at).abs() < EPS_DEG;
        let mut s = vec![0.0; m];
        for (i, si) in s.iter_mut().enumerate() {
            *si = if i > 0 && i + 1 < m {
                slope(t[i] - t[i - 1], t[i + 1] - t[i], y[i - 1], y[i], y[i + 1])
            } else if i == 0 && pole(0.0) {
                let ghost = self.interp_phi(opposite, row(1)).max(0.0);
                slope(t[1] - t[0], t[1] - t[0], ghost, y[0], y[1])
            } else if i == 0 {
                end_slope(
                    t[1] - t[0],
                    t.get(2).map_or(0.0, |x| x - t[1]),
                    y[0],
                    y[1],
                    y.get(2).copied(),
                )
            } else if self.frame.periodic && (t[m - 1] - 180.0).abs() < EPS_DEG {
                let ghost = self.interp_phi(opposite, row(m - 2)).max(0.0);
                let h = t[m - 1] - t[m - 2];
                slope(h, h, y[m - 2], y[m - 1], ghost)
            } else {
                let h1 = if m >= 3 { t[m - 2] - t[m - 3] } else { 0.0 };
                let y2 = (m >= 3).then(|| y[m - 3]);
                -end_slope(t[m - 1] - t[m - 2], h1, y[m - 1], y[m - 2], y2)
            };
        }
        (0..m - 1)
            .map(|i| {
                let h = t[i + 1] - t[i];
                hermite_coefs(y[i], y[i + 1], s[i] * h, s[i + 1] * h)
            })
            .collect()
    }

    /// Hermite interpolation across planes at `phi` of the per-plane values `f(j)` (≥ 0).
    /// `phi` must be inside the plane range (any angle when periodic).
    #[inline]
    fn interp_phi(&self, phi: f64, f: impl Fn(usize) -> f64) -> f64 {
        let n = self.planes.len();
        if n == 1 {
            return f(0);
        }
        let g = &self.gaps;
        if self.frame.periodic {
            let base = self.planes[0];
            let phi = base + (phi - base).rem_euclid(360.0);
            let (j, u) = self.plane_nodes.locate(phi);
            let (jm, j1, j2) = ((j + n - 1) % n, (j + 1) % n, (j + 2) % n);
            let (ym, y0, y1, y2) = (f(jm), f(j), f(j1), f(j2));
            let m0 = slope(g[jm], g[j], ym, y0, y1);
            let m1 = slope(g[j], g[j1], y0, y1, y2);
            return hermite(y0, y1, m0 * g[j], m1 * g[j], u);
        }
        let (j, u) = self.plane_nodes.locate(phi);
        let (y0, y1) = (f(j), f(j + 1));
        let m0 = if j == 0 {
            end_slope(
                g[0],
                g.get(1).copied().unwrap_or(0.0),
                y0,
                y1,
                (n > 2).then(|| f(2)),
            )
        } else {
            slope(g[j - 1], g[j], f(j - 1), y0, y1)
        };
        let m1 = if j + 2 == n {
            let h1 = if n > 2 { g[n - 3] } else { 0.0 };
            -end_slope(g[n - 2], h1, y1, y0, (n > 2).then(|| f(n - 3)))
        } else {
            slope(g[j], g[j + 1], y0, y1, f(j + 2))
        };
        hermite(y0, y1, m0 * g[j], m1 * g[j], u)
    }

    /// Intensity (cd) at plane angle `phi` and polar angle `theta`, degrees.
    #[inline]
    pub(super) fn eval(&self, phi: f64, theta: f64) -> f64 {
        let t = &self.thetas;
        let m = t.len();
        if theta < t[0] - EPS_DEG || theta > t[m - 1] + EPS_DEG {
            return 0.0;
        }
        let (k, u) = self.theta_nodes.locate(theta.clamp(t[0], t[m - 1]));
        let plane = |j: usize| {
            let c = &self.coefs[j * (m - 1) + k];
            (c[0] + u * (c[1] + u * (c[2] + u * c[3]))).max(0.0)
        };
        let phi = if self.frame.periodic {
            phi
        } else {
            let (lo, hi) = (self.planes[0], self.planes[self.planes.len() - 1]);
            if phi < lo - EPS_DEG || phi > hi + EPS_DEG {
                return 0.0;
            }
            phi.clamp(lo, hi)
        };
        self.interp_phi(phi, plane).max(0.0)
    }

    /// The largest tabulated intensity and its (φ, θ); the first such node in storage order.
    pub(super) fn peak(&self) -> (f64, f64, f64) {
        let m = self.thetas.len();
        let (mut best, mut at) = (f64::NEG_INFINITY, 0);
        for (i, &v) in self.values.iter().enumerate() {
            if v > best {
                (best, at) = (v, i);
            }
        }
        (best, self.planes[at / m], self.thetas[at % m])
    }
}
