//! The values a plan draws: a regular grid of cells in the plane's 2-D frame (NaN: no data),
//! and the working plane's grid made from the bake's working-plane probes.
//!
//! The working-plane probes stand on a regular x-by-z grid (+Y up; spacing from the run
//! summary's settings, else the smallest step between probes). Each probe is the centre of a
//! square cell of that spacing; the plan's cells subdivide those `f` times (about 200 cells
//! along the longer side, or a cell per 4 px of a larger plan; at most 16 a step) and read the
//! probes bilinearly between their centres (clamped at the
//! outer half cells, NaN next to a probe that was skipped inside an object). Figures (average,
//! minimum, maximum) are the probes' own, as the report computes them.

use super::frame::Frame;
use super::outline;
use crate::readback::{BakedOutput, PlanePoint};
use crate::{Error, Result};
use glam::{DVec2, DVec3};

/// Values on `w` × `h` square cells of edge `cell` (m), row-major from the top row; cell
/// (c, r) spans `origin + [c, c + 1] × [r, r + 1] · cell` in the frame (right, down).
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub values: Vec<f64>,
    pub w: usize,
    pub h: usize,
    pub origin: DVec2,
    pub cell: f64,
}

impl Field {
    /// The frame point (m) of a grid coordinate (col, row) counted between cell centres (what
    /// `picture::isolines` returns).
    pub fn at(&self, grid: DVec2) -> DVec2 {
        self.origin + (grid + DVec2::splat(0.5)) * self.cell
    }

    /// The field's extent in the frame (m): width, height.
    pub fn extent(&self) -> DVec2 {
        DVec2::new(self.w as f64, self.h as f64) * self.cell
    }
}

/// What a source gives a plan: its name, frame, field, outline and [avg, min, max].
pub type Sampled = (String, Frame, Field, Vec<[DVec2; 2]>, [f64; 3]);

/// At least about this many cells along the longer side.
pub const CELLS: f64 = 200.0;

/// Cells along the longer side for a plan `size` px across: [`CELLS`], or one cell per 4 px on
/// larger plans, so the colour field stays as fine as the contours drawn over it.
pub(crate) fn cells(size: u32) -> f64 {
    (f64::from(size) / 4.0).max(CELLS)
}

/// The working plane's plan, about `cells` cells along its longer side (at most 16 a probe step).
pub(crate) fn working_plane(input: &BakedOutput, cells: f64) -> Result<Sampled> {
    let Some(plane) = input
        .working_plane
        .as_ref()
        .filter(|p| !p.points.is_empty())
    else {
        return Err(Error::input(
            &input.file,
            "",
            "the bake has no working plane: bake it with --working-plane HEIGHT (e.g. \
             --working-plane 0.8), or draw a node with --surface NODE",
        ));
    };
    let points = &plane.points;
    let grid = input.run_summary()?.and_then(|s| s.settings.working_plane);
    let spacing = grid
        .map(|g| g.spacing)
        .unwrap_or_else(|| inferred_spacing(points));
    let lo = points
        .iter()
        .fold(DVec3::INFINITY, |m, p| m.min(p.position));
    let index = |p: &PlanePoint| {
        let i = ((p.position.x - lo.x) / spacing).round() as usize;
        let k = ((p.position.z - lo.z) / spacing).round() as usize;
        (i, k)
    };
    let nx = points.iter().map(|p| index(p).0).max().unwrap_or(0) + 1;
    let nz = points.iter().map(|p| index(p).1).max().unwrap_or(0) + 1;
    if nx.saturating_mul(nz) > 4 * points.len() + 16 {
        return Err(Error::input(
            &input.file,
            "/nodes",
            format!(
                "the working-plane probes do not stand on a grid of spacing {spacing} m \
                 ({} probes span {nx} × {nz} steps)",
                points.len()
            ),
        ));
    }
    let mut probes = vec![f64::NAN; nx * nz];
    for p in points {
        let (i, k) = index(p);
        probes[k * nx + i] = p.total as f64;
    }
    let f = (cells / nx.max(nz) as f64).round().clamp(1.0, 16.0) as usize;
    let (w, h) = (nx * f, nz * f);
    let mut values = Vec::with_capacity(w * h);
    for r in 0..h {
        for c in 0..w {
            let gx = ((c as f64 + 0.5) / f as f64 - 0.5).clamp(0.0, (nx - 1) as f64);
            let gz = ((r as f64 + 0.5) / f as f64 - 0.5).clamp(0.0, (nz - 1) as f64);
            values.push(bilinear(&probes, nx, nz, gx, gz));
        }
    }
    let field = Field {
        values,
        w,
        h,
        origin: DVec2::new(lo.x, lo.z) - DVec2::splat(spacing / 2.0),
        cell: spacing / f as f64,
    };
    let mut heights: Vec<f64> = points.iter().map(|p| p.position.y).collect();
    heights.sort_by(f64::total_cmp);
    let y = heights[heights.len() / 2];
    let name = match grid {
        Some(g) => format!("working plane, {} m above the floor", g.height),
        None => format!("working plane at y = {y:.2} m"),
    };
    let total: Vec<f64> = points.iter().map(|p| p.total as f64).collect();
    let avg = total.iter().sum::<f64>() / total.len() as f64;
    let min = total.iter().copied().fold(f64::INFINITY, f64::min);
    let max = total.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let frame = Frame::of_normal(DVec3::Y);
    let outline = outline::slice(input, y, &frame);
    Ok((name, frame, field, outline, [avg, min, max]))
}

/// The smallest nonzero step between probes along x or z (1 m for a single probe).
fn inferred_spacing(points: &[PlanePoint]) -> f64 {
    let mut step = f64::INFINITY;
    for axis in [0, 2] {
        let mut c: Vec<f64> = points.iter().map(|p| p.position[axis]).collect();
        c.sort_by(f64::total_cmp);
        for pair in c.windows(2) {
            let d = pair[1] - pair[0];
            if d > 1e-6 {
                step = step.min(d);
            }
        }
    }
    if step.is_finite() { step } else { 1.0 }
}

/// `v` read bilinearly at grid point (x, y) (0 ≤ x ≤ w − 1); a corner with no weight is not
/// read, so a NaN spreads only as far as it weighs.
fn bilinear(v: &[f64], w: usize, h: usize, x: f64, y: f64) -> f64 {
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (fx, fy) = (x - x0 as f64, y - y0 as f64);
    let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
    let lerp = |a: f64, b: f64, t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            a + (b - a) * t
        }
    };
    let top = lerp(v[y0 * w + x0], v[y0 * w + x1], fx);
    if fy == 0.0 {
        return top;
    }
    let bottom = lerp(v[y1 * w + x0], v[y1 * w + x1], fx);
    lerp(top, bottom, fy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_reads_corners_and_keeps_nan_local() {
        let v = [0.0, 10.0, 20.0, f64::NAN];
        assert_eq!(bilinear(&v, 2, 2, 0.5, 0.0), 5.0);
        assert_eq!(bilinear(&v, 2, 2, 0.0, 0.5), 10.0);
        assert!(bilinear(&v, 2, 2, 0.5, 0.5).is_nan());
        assert_eq!(bilinear(&v, 2, 2, 1.0, 0.0), 10.0);
    }
}
