//! A uniform grid over triangles' bounding boxes: which triangles lie near a triangle.

use glam::DVec3;
use std::collections::HashMap;

/// Triangles spanning more cells than this are kept in a list every query returns.
const MAX_CELLS: usize = 4096;

pub struct Grid {
    cell: f64,
    pad: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
    big: Vec<u32>,
}

impl Grid {
    /// Index `tris`; queries return triangles whose boxes come within `pad` (m) of a box.
    pub fn new(tris: &[[DVec3; 3]], pad: f64) -> Self {
        // Cells about the size of a typical (median) triangle.
        let mut sizes: Vec<f64> = tris.iter().map(|t| extent(t).max_element()).collect();
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in tris.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let diagonal = (hi - lo).length().max(1e-300);
        sizes.sort_by(f64::total_cmp);
        let median = sizes.get(sizes.len() / 2).copied().unwrap_or(1.0);
        let cell = median.max(pad).max(diagonal * 1e-4);
        let mut grid = Grid {
            cell,
            pad,
            cells: HashMap::new(),
            big: Vec::new(),
        };
        for (i, t) in tris.iter().enumerate() {
            let (a, b) = grid.range(t);
            let count = (0..3)
                .map(|k| (b[k] - a[k] + 1) as usize)
                .product::<usize>();
            if count > MAX_CELLS {
                grid.big.push(i as u32);
                continue;
            }
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        grid.cells.entry([x, y, z]).or_default().push(i as u32);
                    }
                }
            }
        }
        grid
    }

    /// The cells a triangle's box, padded, overlaps.
    fn range(&self, t: &[DVec3; 3]) -> ([i64; 3], [i64; 3]) {
        let lo = t[0].min(t[1]).min(t[2]) - DVec3::splat(self.pad);
        let hi = t[0].max(t[1]).max(t[2]) + DVec3::splat(self.pad);
        let c = |v: f64| (v / self.cell).floor() as i64;
        ([c(lo.x), c(lo.y), c(lo.z)], [c(hi.x), c(hi.y), c(hi.z)])
    }

    /// The triangles near `t` (sorted, each once) into `out`.
    pub fn near(&self, t: [DVec3; 3], out: &mut Vec<u32>) {
        out.clear();
        out.extend_from_slice(&self.big);
        let (a, b) = self.range(&t);
        let count = (0..3)
            .map(|k| (b[k] - a[k] + 1) as usize)
            .product::<usize>();
        if count > MAX_CELLS * 16 {
            // A huge triangle: walk the occupied cells instead of the box's.
            for (key, ids) in &self.cells {
                if (0..3).all(|k| key[k] >= a[k] && key[k] <= b[k]) {
                    out.extend_from_slice(ids);
                }
            }
        } else {
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        if let Some(ids) = self.cells.get(&[x, y, z]) {
                            out.extend_from_slice(ids);
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

fn extent(t: &[DVec3; 3]) -> DVec3 {
    t[0].max(t[1]).max(t[2]) - t[0].min(t[1]).min(t[2])
}
