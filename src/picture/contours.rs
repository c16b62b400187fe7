//! Isolines by marching squares (stub; filled in next).

use super::scale::ColourScale;
use glam::DVec2;

/// Isolines of `values` (w × h, row-major) at `level`, as joined polylines.
pub fn isolines(_values: &[f64], _w: usize, _h: usize, _level: f64) -> Vec<Vec<DVec2>> {
    Vec::new()
}

/// 1-px contour pixels where a pixel's band differs from its right or lower neighbour.
pub fn band_edges(values: &[f64], _w: u32, _h: u32, _scale: &ColourScale) -> Vec<bool> {
    vec![false; values.len()]
}
