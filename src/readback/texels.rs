//! Texels and primitives: which texels of its atlas a primitive stands on, where a texel is on
//! the surface, and a lightmap read between texel centres.
//!
//! A primitive stands on the texels its UV triangles cover with some area (the texels the
//! baker's clipping, `crate::lightmap::raster`, gave a footprint); a triangle without UV area
//! (a covered part's, laid on one texel) on the texel holding it. Charts never share texels, so
//! each texel with a footprint belongs to one primitive; within it, to the triangle with the
//! most area there (the lowest index on a tie). Texel (col, row) spans [col, col + 1] ×
//! [row, row + 1] in texel coordinates (UV × size, row 0 at the top). Rasterised row by row:
//! the texels a triangle covers whole across a row are taken without clipping, only those on
//! its edges are clipped, so the work is the texel count plus the edges' length.

use super::model::{Lightmap, Primitive, Texel};
use crate::lightmap::raster::{area, barycentric, clip};
use glam::{DVec2, DVec3};

/// Per texel of an atlas, the best triangle so far: (area in it, triangle); reused between the
/// primitives of one atlas (only the texels touched are reset).
pub(super) struct Scratch {
    best: Vec<(f64, u32)>,
    touched: Vec<u32>,
}

impl Scratch {
    pub(crate) fn new(w: u32, h: u32) -> Self {
        Scratch {
            best: vec![(0.0, u32::MAX); w as usize * h as usize],
            touched: Vec::new(),
        }
    }

    /// Offer `piece` texels² of `triangle` to texel `k`.
    fn offer(&mut self, k: u32, piece: f64, triangle: u32) {
        let slot = &mut self.best[k as usize];
        if slot.1 == u32::MAX {
            self.touched.push(k);
            *slot = (piece, triangle);
        } else if piece > slot.0 {
            *slot = (piece, triangle);
        }
    }
}

/// The texels the triangles stand on in a `w` × `h` atlas, in texel order.
pub(super) fn rasterise(
    uv: &[DVec2],
    triangles: &[[u32; 3]],
    (w, h): (u32, u32),
    scratch: &mut Scratch,
) -> Vec<Texel> {
    let scale = DVec2::new(w as f64, h as f64);
    for (t, tri) in triangles.iter().enumerate() {
        let q = tri.map(|v| uv[v as usize] * scale);
        if !q.iter().all(|p| p.is_finite()) {
            continue;
        }
        if (q[1] - q[0]).perp_dot(q[2] - q[0]) == 0.0 {
            let c = (q[0] + q[1] + q[2]) / 3.0;
            let col = (c.x.floor().max(0.0) as u32).min(w - 1);
            let row = (c.y.floor().max(0.0) as u32).min(h - 1);
            scratch.offer(row * w + col, 0.0, t as u32);
            continue;
        }
        triangle(&q, (w, h), |k, piece| scratch.offer(k, piece, t as u32));
    }
    let Scratch { best, touched } = scratch;
    touched.sort_unstable();
    let out = touched
        .iter()
        .map(|&k| Texel {
            index: k,
            triangle: best[k as usize].1,
        })
        .collect();
    for &k in touched.iter() {
        best[k as usize] = (0.0, u32::MAX);
    }
    touched.clear();
    out
}

/// Every texel of a `w` × `h` grid triangle `q` covers with area: (index, area in texels²).
fn triangle(q: &[DVec2; 3], (w, h): (u32, u32), mut each: impl FnMut(u32, f64)) {
    let lo = q[0].min(q[1]).min(q[2]);
    let hi = q[0].max(q[1]).max(q[2]);
    let rows = (lo.y.floor().max(0.0) as u32)..(hi.y.ceil().min(h as f64) as u32);
    for row in rows {
        let (y0, y1) = (row as f64, row as f64 + 1.0);
        let strip = clip(&clip(q, 1, y0, false), 1, y1, true);
        if strip.len() < 3 {
            continue;
        }
        let (x0, x1) = strip
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.x), b.max(p.x)));
        // Columns covered whole: inside the triangle's span at both edges of the row.
        let full = match (span(q, y0), span(q, y1)) {
            (Some(a), Some(b)) => (a.0.max(b.0).ceil(), a.1.min(b.1).floor()),
            _ => (0.0, 0.0),
        };
        let cols = (x0.floor().max(0.0) as u32)..(x1.ceil().min(w as f64) as u32);
        for col in cols {
            let c = col as f64;
            let piece = if c >= full.0 && c + 1.0 <= full.1 {
                1.0
            } else {
                area(&clip(&clip(&strip, 0, c, false), 0, c + 1.0, true))
            };
            if piece > 0.0 {
                each(row * w + col, piece);
            }
        }
    }
}

/// Where the horizontal line at `y` crosses triangle `q`: (left, right), or `None` when it
/// misses it.
fn span(q: &[DVec2; 3], y: f64) -> Option<(f64, f64)> {
    let mut out: Option<(f64, f64)> = None;
    for k in 0..3 {
        let (a, b) = (q[k], q[(k + 1) % 3]);
        if (a.y - y) * (b.y - y) > 0.0 || a.y == b.y {
            continue;
        }
        let x = a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
        out = Some(out.map_or((x, x), |(l, r)| (l.min(x), r.max(x))));
    }
    out
}

/// `value` (of a row-major texel index of a `width` × `height` image, row 0 at the top) read
/// bilinearly between texel centres at `uv`, clamped at the edges (a viewer's CLAMP_TO_EDGE,
/// LINEAR sampler): lightmap channels, display textures.
pub fn bilinear<T>(width: u32, height: u32, value: impl Fn(usize) -> T, uv: DVec2) -> T
where
    T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
{
    let (w, h) = (width as f64, height as f64);
    let x = (uv.x * w - 0.5).clamp(0.0, w - 1.0);
    let y = (uv.y * h - 0.5).clamp(0.0, h - 1.0);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |c: f64, r: f64| {
        let (c, r) = (c.min(w - 1.0) as usize, r.min(h - 1.0) as usize);
        value(r * width as usize + c)
    };
    let top = at(x0, y0) * (1.0 - fx) + at(x0 + 1.0, y0) * fx;
    let bottom = at(x0, y0 + 1.0) * (1.0 - fx) + at(x0 + 1.0, y0 + 1.0) * fx;
    top * (1.0 - fy) + bottom * fy
}

impl Lightmap {
    /// `value` (of a texel index) read bilinearly between texel centres at `uv`, clamped at the
    /// atlas's edges (as a viewer's CLAMP_TO_EDGE, LINEAR sampler reads it).
    pub fn bilinear(&self, value: impl Fn(usize) -> f64, uv: DVec2) -> f64 {
        bilinear(self.width, self.height, value, uv)
    }

    /// Column and row of texel `index`.
    pub fn col_row(&self, index: u32) -> [u32; 2] {
        [index % self.width, index / self.width]
    }
}

impl Primitive {
    /// The world point (m) of `texel`'s centre on its triangle: the centre's barycentric
    /// coordinates clamped onto the triangle; a triangle without UV area gives its centroid.
    pub(crate) fn texel_point(&self, lightmap: &Lightmap, texel: Texel) -> DVec3 {
        let tri = self.triangles[texel.triangle as usize].map(|v| v as usize);
        let world = tri.map(|v| self.positions[v]);
        let centroid = (world[0] + world[1] + world[2]) / 3.0;
        let Some(layout) = &self.lightmap else {
            return centroid;
        };
        let scale = DVec2::new(lightmap.width as f64, lightmap.height as f64);
        let q = tri.map(|v| layout.uv[v] * scale);
        let [col, row] = lightmap.col_row(texel.index);
        let centre = DVec2::new(col as f64 + 0.5, row as f64 + 0.5);
        match barycentric(&q, centre) {
            Some(l) => {
                let l = l.map(|x| x.max(0.0));
                let sum: f64 = l.iter().sum();
                (0..3).map(|j| world[j] * (l[j] / sum)).sum()
            }
            None => centroid,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_of_two_triangles_stands_on_the_texels_it_covers() {
        // The square [1, 3] × [1, 2] (texels) of a 4 × 4 atlas: texels (1, 1) and (2, 1).
        let uv = [(1., 1.), (3., 1.), (3., 2.), (1., 2.)].map(|(x, y)| DVec2::new(x, y) / 4.0);
        let texels = rasterise(
            &uv,
            &[[0, 1, 2], [0, 2, 3]],
            (4, 4),
            &mut Scratch::new(4, 4),
        );
        let got: Vec<(u32, u32)> = texels.iter().map(|t| (t.index, t.triangle)).collect();
        // Texel (1, 1) holds 3/4 texel² of triangle 1, texel (2, 1) 3/4 of triangle 0.
        assert_eq!(got, [(5, 1), (6, 0)]);
    }

    #[test]
    fn a_triangle_without_uv_area_stands_on_the_texel_holding_it() {
        let uv = [DVec2::new(2.5, 0.5) / 4.0; 3];
        let texels = rasterise(&uv, &[[0, 1, 2]], (4, 2), &mut Scratch::new(4, 2));
        assert_eq!(
            texels,
            [Texel {
                index: 2,
                triangle: 0
            }]
        );
    }

    #[test]
    fn areas_add_up_and_agree_with_the_bakers_clipping() {
        // A slanted triangle over a 16 × 16 grid: the same texels and areas as the baker's.
        let q = [
            DVec2::new(0.3, 1.7),
            DVec2::new(13.2, 4.1),
            DVec2::new(5.5, 14.9),
        ];
        let mut ours = Vec::new();
        triangle(&q, (16, 16), |k, a| ours.push((k as usize, a)));
        let mut bakers = Vec::new();
        crate::lightmap::raster::texels_of(&q, 0, 16, 16, |k, _, a| {
            if a > 0.0 {
                bakers.push((k, a));
            }
        });
        bakers.sort_by_key(|b| b.0);
        ours.sort_by_key(|b| b.0);
        assert_eq!(ours.len(), bakers.len());
        for (o, b) in ours.iter().zip(&bakers) {
            assert_eq!(o.0, b.0);
            assert!((o.1 - b.1).abs() < 1e-9, "{o:?} vs {b:?}");
        }
        let total: f64 = ours.iter().map(|o| o.1).sum();
        let want = (q[1] - q[0]).perp_dot(q[2] - q[0]).abs() / 2.0;
        assert!((total - want).abs() < 1e-9, "{total} vs {want}");
    }

    #[test]
    fn bilinear_is_exact_at_centres_and_linear_between() {
        let lm = Lightmap {
            atlas: 0,
            uri: String::new(),
            width: 2,
            height: 1,
            texel_size: 1.0,
            at: String::new(),
            luminance: vec![[0.0; 3]; 2],
            illuminance: vec![10.0, 20.0],
            illuminance_direct: vec![0.0; 2],
            footprint: vec![1.0; 2],
        };
        let e = |k: usize| f64::from(lm.illuminance[k]);
        assert_eq!(lm.bilinear(e, DVec2::new(0.25, 0.5)), 10.0);
        assert_eq!(lm.bilinear(e, DVec2::new(0.5, 0.5)), 15.0);
        assert_eq!(lm.bilinear(e, DVec2::new(1.0, 0.0)), 20.0);
    }
}
