//! A uniform grid over triangles' bounding boxes: which triangles' boxes meet a query box.

use crate::geom::hash::IntMap;
use glam::DVec3;

/// Triangles spanning more cells than this are kept in a list every query tests.
const MAX_CELLS: usize = 4096;

pub struct Grid {
    cell: f64,
    cells: IntMap<[i64; 3], Vec<u32>>,
    big: Vec<u32>,
    /// Each triangle's bounding box, grown by the index's padding.
    boxes: Vec<(DVec3, DVec3)>,
    /// Each triangle's lowest cell (where a query that starts below it takes it).
    first: Vec<[i64; 3]>,
}

impl Grid {
    /// Index `tris`, their boxes grown by `pad` (m) on every side.
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
        let boxes = tris
            .iter()
            .map(|t| {
                let p = DVec3::splat(pad);
                (t[0].min(t[1]).min(t[2]) - p, t[0].max(t[1]).max(t[2]) + p)
            })
            .collect();
        let mut grid = Grid {
            cell,
            cells: IntMap::default(),
            big: Vec::new(),
            boxes,
            first: Vec::with_capacity(tris.len()),
        };
        for i in 0..tris.len() {
            let (a, b) = grid.range(grid.boxes[i]);
            grid.first.push(a);
            if cells_in(a, b) > MAX_CELLS {
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

    /// The cells a box overlaps.
    fn range(&self, (lo, hi): (DVec3, DVec3)) -> ([i64; 3], [i64; 3]) {
        let c = |v: f64| (v / self.cell).floor() as i64;
        ([c(lo.x), c(lo.y), c(lo.z)], [c(hi.x), c(hi.y), c(hi.z)])
    }

    /// The triangles whose (padded) boxes meet the box `lo..hi`, sorted, each once, into `out`.
    pub fn near(&self, lo: DVec3, hi: DVec3, out: &mut Vec<u32>) {
        out.clear();
        let meets = |i: u32| {
            let (l, h) = self.boxes[i as usize];
            l.cmple(hi).all() && h.cmpge(lo).all()
        };
        let (a, b) = self.range((lo, hi));
        if cells_in(a, b) > self.boxes.len() {
            // A box wider than the index has triangles: test them all.
            out.extend((0..self.boxes.len() as u32).filter(|&i| meets(i)));
            return;
        }
        out.extend(self.big.iter().copied().filter(|&i| meets(i)));
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    let Some(ids) = self.cells.get(&[x, y, z]) else {
                        continue;
                    };
                    // A triangle is taken in one cell only: the first its box shares with the
                    // query's (the component-wise larger of the two lowest cells).
                    for &i in ids {
                        let first = self.first[i as usize];
                        if first[0].max(a[0]) == x
                            && first[1].max(a[1]) == y
                            && first[2].max(a[2]) == z
                            && meets(i)
                        {
                            out.push(i);
                        }
                    }
                }
            }
        }
        out.sort_unstable();
    }
}

/// Number of cells from `a` to `b` inclusive (saturating).
fn cells_in(a: [i64; 3], b: [i64; 3]) -> usize {
    (0..3)
        .map(|k| (b[k] - a[k] + 1).max(0) as usize)
        .fold(1usize, |n, k| n.saturating_mul(k))
}

fn extent(t: &[DVec3; 3]) -> DVec3 {
    t[0].max(t[1]).max(t[2]) - t[0].min(t[1]).min(t[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic scatter of small, medium and huge triangles (glTF +Y up).
    fn scatter() -> Vec<[DVec3; 3]> {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..3000)
            .map(|i| {
                let size = match i % 100 {
                    0 => 30.0,
                    1..=9 => 2.0,
                    _ => 0.05,
                };
                let o = DVec3::new(next() * 20.0, next() * 3.0, next() * 15.0);
                let mut d = || DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * size;
                [o, o + d(), o + d()]
            })
            .collect()
    }

    #[test]
    fn near_names_every_box_that_meets_the_query_once_in_order() {
        let tris = scatter();
        let pad = 1e-3;
        let grid = Grid::new(&tris, pad);
        assert!(
            !grid.big.is_empty(),
            "the scatter has triangles listed apart"
        );
        let mut out = Vec::new();
        let queries = [
            (DVec3::new(5.0, 1.0, 5.0), DVec3::new(5.3, 1.2, 5.1)),
            (DVec3::new(-1.0, -1.0, -1.0), DVec3::new(25.0, 4.0, 20.0)),
            (DVec3::new(10.0, 0.0, 0.0), DVec3::new(10.0, 3.0, 15.0)),
            (
                DVec3::new(100.0, 100.0, 100.0),
                DVec3::new(101.0, 101.0, 101.0),
            ),
        ];
        let mut total = 0;
        for (lo, hi) in queries.into_iter().chain(tris.iter().map(|t| {
            let p = DVec3::new(0.0, 0.02, 0.0);
            (t[0].min(t[1]).min(t[2]) - p, t[0].max(t[1]).max(t[2]) + p)
        })) {
            grid.near(lo, hi, &mut out);
            let expected: Vec<u32> = (0..tris.len() as u32)
                .filter(|&i| {
                    let t = &tris[i as usize];
                    let (l, h) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
                    (l - DVec3::splat(pad)).cmple(hi).all()
                        && (h + DVec3::splat(pad)).cmpge(lo).all()
                })
                .collect();
            assert_eq!(out, expected, "query {lo} .. {hi}");
            total += out.len();
        }
        assert!(
            total > tris.len(),
            "queries found neighbours, not only themselves"
        );
    }
}
