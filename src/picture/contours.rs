//! Isolines by marching squares, and the band-edge pixels of a false-colour image.
//!
//! Input: a grid of values, row-major, w × h samples at integer coordinates (col, row); NaN
//! means no data. Output: [`isolines`]: polylines (x = col, y = row) where the bilinear-free,
//! edge-linear interpolant equals the level — crossing points linear along cell edges, saddle
//! cells split by the average of their four corners; segments joined through shared edges
//! into polylines, closed ones ending on their first point. [`band_edges`]: per sample, whether
//! its band on a scale differs from its right or lower neighbour's. Invariants: a cell with a
//! NaN corner gives no segment; a crossing on an edge two cells share is computed once, so
//! joined polylines meet exactly; output order is fixed (row-major scan of the edges).

use super::scale::ColourScale;
use glam::DVec2;

/// Isolines of `values` (w × h, row-major) at `level`, as joined polylines; closed ones repeat
/// their first point at the end. Corners at or above the level count as above.
pub fn isolines(values: &[f64], w: usize, h: usize, level: f64) -> Vec<Vec<DVec2>> {
    if w < 2 || h < 2 || values.len() < w * h || !level.is_finite() {
        return Vec::new();
    }
    let grid = Grid {
        values,
        w,
        h,
        level,
    };
    // Each crossing edge links to at most two segments (one per cell beside it).
    let mut links: Vec<[usize; 2]> = vec![[NONE; 2]; grid.edge_count()];
    for j in 0..h - 1 {
        for i in 0..w - 1 {
            for (e0, e1) in grid.cell_segments(i, j) {
                link(&mut links, e0, e1);
                link(&mut links, e1, e0);
            }
        }
    }
    let mut used = vec![false; links.len()];
    let mut lines = Vec::new();
    // Open polylines start at an end (one link), in edge order; what is left are loops.
    for open in [true, false] {
        for start in 0..links.len() {
            let degree = links[start].iter().filter(|&&l| l != NONE).count();
            if used[start] || degree == 0 || (open && degree != 1) {
                continue;
            }
            lines.push(grid.walk(start, &links, &mut used));
        }
    }
    lines
}

/// No link.
const NONE: usize = usize::MAX;

fn link(links: &mut [[usize; 2]], from: usize, to: usize) {
    let slot = &mut links[from];
    if slot[0] == NONE {
        slot[0] = to;
    } else if slot[1] == NONE && slot[0] != to {
        slot[1] = to;
    }
}

struct Grid<'v> {
    values: &'v [f64],
    w: usize,
    h: usize,
    level: f64,
}

impl Grid<'_> {
    fn at(&self, i: usize, j: usize) -> f64 {
        self.values[j * self.w + i]
    }

    /// Horizontal edges (i, j)–(i+1, j) first, then vertical ones (i, j)–(i, j+1).
    fn edge_count(&self) -> usize {
        self.h * (self.w - 1) + (self.h - 1) * self.w
    }

    fn h_edge(&self, i: usize, j: usize) -> usize {
        j * (self.w - 1) + i
    }

    fn v_edge(&self, i: usize, j: usize) -> usize {
        self.h * (self.w - 1) + j * self.w + i
    }

    /// The two grid points an edge joins.
    fn ends(&self, e: usize) -> ((usize, usize), (usize, usize)) {
        let nh = self.h * (self.w - 1);
        if e < nh {
            let (j, i) = (e / (self.w - 1), e % (self.w - 1));
            ((i, j), (i + 1, j))
        } else {
            let e = e - nh;
            let (j, i) = (e / self.w, e % self.w);
            ((i, j), (i, j + 1))
        }
    }

    /// Where the level crosses edge `e` (linear between its ends).
    fn crossing(&self, e: usize) -> DVec2 {
        let ((i0, j0), (i1, j1)) = self.ends(e);
        let (a, b) = (self.at(i0, j0), self.at(i1, j1));
        let t = ((self.level - a) / (b - a)).clamp(0.0, 1.0);
        let p0 = DVec2::new(i0 as f64, j0 as f64);
        let p1 = DVec2::new(i1 as f64, j1 as f64);
        p0 + (p1 - p0) * t
    }

    /// The segments (pairs of crossing edges) of cell (i, j): none when a corner is NaN.
    fn cell_segments(&self, i: usize, j: usize) -> Vec<(usize, usize)> {
        let v = [
            self.at(i, j),
            self.at(i + 1, j),
            self.at(i + 1, j + 1),
            self.at(i, j + 1),
        ];
        if v.iter().any(|x| x.is_nan()) {
            return Vec::new();
        }
        let above = v.map(|x| x >= self.level);
        // Edges: top (corners 0–1), right (1–2), bottom (2–3), left (3–0).
        let edges = [
            self.h_edge(i, j),
            self.v_edge(i + 1, j),
            self.h_edge(i, j + 1),
            self.v_edge(i, j),
        ];
        let crossed: Vec<usize> = (0..4).filter(|&k| above[k] != above[(k + 1) % 4]).collect();
        match crossed.len() {
            2 => vec![(edges[crossed[0]], edges[crossed[1]])],
            4 => {
                // Saddle: cut off the two corners on the other side than the centre (the mean
                // of the four); corner k touches edges k − 1 and k.
                let centre = v.iter().sum::<f64>() / 4.0 >= self.level;
                (0..4)
                    .filter(|&k| above[k] != centre)
                    .map(|k| (edges[(k + 3) % 4], edges[k]))
                    .collect()
            }
            _ => Vec::new(),
        }
    }

    /// The polyline from edge `start` along the links, marking edges used; a loop ends on its
    /// first point again.
    fn walk(&self, start: usize, links: &[[usize; 2]], used: &mut [bool]) -> Vec<DVec2> {
        let mut line = vec![self.crossing(start)];
        used[start] = true;
        let (mut prev, mut at) = (NONE, start);
        loop {
            let next = match links[at] {
                [a, _] if a != NONE && a != prev && !(used[a] && a != start) => a,
                [_, b] if b != NONE && b != prev && !(used[b] && b != start) => b,
                _ => break,
            };
            if next == start {
                line.push(line[0]);
                break;
            }
            used[next] = true;
            line.push(self.crossing(next));
            prev = at;
            at = next;
        }
        line
    }
}

/// Per sample (row-major, w × h): whether its band on `scale` differs from its right or lower
/// neighbour's; samples or neighbours that are NaN never mark an edge.
pub(crate) fn band_edges(values: &[f64], w: u32, h: u32, scale: &ColourScale) -> Vec<bool> {
    let (w, h) = (w as usize, h as usize);
    let n = (w * h).min(values.len());
    let band = |k: usize| (!values[k].is_nan()).then(|| scale.band(values[k]));
    let mut out = vec![false; w * h];
    for (k, edge) in out.iter_mut().enumerate().take(n) {
        let Some(b) = band(k) else { continue };
        let (x, y) = (k % w, k / w);
        let right = x + 1 < w && k + 1 < n && band(k + 1).is_some_and(|r| r != b);
        let below = y + 1 < h && k + w < n && band(k + w).is_some_and(|r| r != b);
        *edge = right || below;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(w: usize, h: usize, f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        (0..w * h)
            .map(|k| f((k % w) as f64, (k / w) as f64))
            .collect()
    }

    #[test]
    fn circle_of_a_radial_field() {
        // Distance from (30.4, 29.7): along a grid edge the chord of a convex function of
        // second derivative ≤ 1/r lies within 1/(8r) = 0.006 of it, under 1 % of the spacing.
        let (w, h, r) = (61, 61, 20.3);
        let c = DVec2::new(30.4, 29.7);
        let v = grid(w, h, |x, y| DVec2::new(x, y).distance(c));
        let lines = isolines(&v, w, h, r);
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert_eq!(line.first(), line.last(), "closed");
        assert!(line.len() > 100);
        for p in line {
            assert!((p.distance(c) - r).abs() < 0.01, "{p}: {}", p.distance(c));
        }
        // it goes once round: the signed area is π r² within 0.1 %
        let area: f64 = line.windows(2).map(|s| s[0].perp_dot(s[1])).sum::<f64>() / 2.0;
        let exact = std::f64::consts::PI * r * r;
        assert!(
            (area.abs() - exact).abs() < 1e-3 * exact,
            "{area} vs {exact}"
        );
    }

    #[test]
    fn ramp_gives_straight_line() {
        let (w, h) = (9, 7);
        let v = grid(w, h, |x, _| x);
        let lines = isolines(&v, w, h, 3.25);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].len(), h);
        assert!(lines[0].iter().all(|p| p.x == 3.25));
        let mut ys: Vec<f64> = lines[0].iter().map(|p| p.y).collect();
        ys.sort_by(f64::total_cmp);
        assert_eq!(ys, (0..h).map(|y| y as f64).collect::<Vec<_>>());
        // a diagonal ramp: every point on x + 2y = 7.5 exactly
        let v = grid(w, h, |x, y| x + 2.0 * y);
        let lines = isolines(&v, w, h, 7.5);
        assert_eq!(lines.len(), 1);
        assert!(
            lines[0]
                .iter()
                .all(|p| (p.x + 2.0 * p.y - 7.5).abs() < 1e-12)
        );
    }

    #[test]
    fn nan_cells_cut_the_line() {
        let (w, h) = (5, 7);
        let mut v = grid(w, h, |x, _| x);
        v[3 * w + 2] = f64::NAN; // the 4 cells around (2, 3) have no data
        let lines = isolines(&v, w, h, 1.5);
        assert_eq!(lines.len(), 2);
        assert!(
            lines
                .iter()
                .all(|l| l.iter().all(|p| p.x == 1.5 && p.y != 3.0))
        );
    }

    #[test]
    fn saddle_split_by_the_mean() {
        let v = [1.0, 0.0, 0.0, 1.0];
        // mean 0.5 ≥ 0.5: the centre is above, the two low corners are cut off
        let mut lines = isolines(&v, 2, 2, 0.5);
        lines.sort_by(|a, b| a[0].y.total_cmp(&b[0].y).then(a[0].x.total_cmp(&b[0].x)));
        let mut ends: Vec<[f64; 4]> = lines
            .iter()
            .map(|l| {
                let (a, b) = (l[0], l[1]);
                let (a, b) = if (a.x, a.y) < (b.x, b.y) {
                    (a, b)
                } else {
                    (b, a)
                };
                [a.x, a.y, b.x, b.y]
            })
            .collect();
        ends.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(ends, vec![[0.0, 0.5, 0.5, 1.0], [0.5, 0.0, 1.0, 0.5]]);
        // above the mean the two high corners are cut off
        let lines = isolines(&v, 2, 2, 0.6);
        assert_eq!(lines.len(), 2);
        let cuts: Vec<f64> = lines.iter().map(|l| l[0].distance(l[1])).collect();
        assert!(cuts.iter().all(|d| (d - 0.4 * 2f64.sqrt()).abs() < 1e-12));
    }

    #[test]
    fn band_edges_mark_changes() {
        let s = ColourScale::fixed(0.0, 10.0, false, 2).unwrap(); // bands [0, 5), [5, 10]
        let v = [1.0, 2.0, 6.0, f64::NAN, 1.0, 1.0, 7.0, 9.0];
        let e = band_edges(&v, 4, 2, &s);
        assert_eq!(
            e,
            vec![false, true, false, false, false, true, false, false]
        );
    }
}
