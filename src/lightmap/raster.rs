//! Rasterisation in UV space: which surface point each texel reads, and how much surface it
//! stands for.
//!
//! Input: triangles in atlas texel coordinates (x right, y down; texel (col, row) spans
//! [col, col + 1] × [row, row + 1], its centre at + 0.5). Output: per texel touched, the triangle
//! and barycentric point it samples and the area of surface it covers. Conservative: every texel
//! a triangle touches is covered, so thin triangles leave no holes. A texel whose centre lies in
//! a triangle samples there; a texel a chart only touches samples the chart's point nearest its
//! centre (the part of the surface that is really there), pulled a hair inside the triangle so no
//! sample sits on an edge where surfaces meet. Invariant: the areas of a triangle's texels sum to
//! its area.

use glam::DVec2;

/// What one texel reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Index of the triangle (the caller's numbering).
    pub triangle: u32,
    /// Barycentric coordinates of the point it reads.
    pub bary: [f64; 3],
    /// Whether the texel's centre is on the triangle (else: the nearest point of it).
    pub centre: bool,
    /// When the centre is off the triangle: its barycentric coordinates there all the same
    /// (the plane extended), for a texel of the chart's edge to read where its centre is
    /// when surface is really there (a coplanar neighbour).
    pub extended: Option<[f64; 3]>,
    /// Area of the triangle's piece in the texel, in texels² (ranks samples that only touch).
    pub piece: f64,
    /// Distance from the texel's centre to the point read (texels).
    pub distance: f64,
}

/// Barycentric coordinates of `p` in triangle `t`; `None` when it has no area.
pub(crate) fn barycentric(t: &[DVec2; 3], p: DVec2) -> Option<[f64; 3]> {
    let [a, b, c] = *t;
    let d = (b - a).perp_dot(c - a);
    if d.abs() < 1e-300 {
        return None;
    }
    let l1 = (p - a).perp_dot(c - a) / d;
    let l2 = (b - a).perp_dot(p - a) / d;
    Some([1.0 - l1 - l2, l1, l2])
}

/// The point of triangle `t` nearest `p`, as barycentric coordinates.
fn nearest(t: &[DVec2; 3], p: DVec2) -> [f64; 3] {
    if let Some(l) = barycentric(t, p)
        && l.iter().all(|x| *x >= 0.0)
    {
        return l;
    }
    // On an edge: the closest of the three edges' nearest points.
    let mut best = (f64::MAX, [1.0, 0.0, 0.0]);
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let ab = b - a;
        let s = match ab.length_squared() > 0.0 {
            true => ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0),
            false => 0.0,
        };
        let d = (a + ab * s - p).length_squared();
        if d < best.0 {
            let mut l = [0.0; 3];
            l[k] = 1.0 - s;
            l[(k + 1) % 3] = s;
            best = (d, l);
        }
    }
    best.1
}

/// `bary` pulled toward the centroid by a hair, off every edge.
fn inset(bary: [f64; 3]) -> [f64; 3] {
    const H: f64 = 1e-4;
    bary.map(|l| l * (1.0 - H) + H / 3.0)
}

/// The area of triangle `t` inside the square [x0, x0 + 1] × [y0, y0 + 1].
fn clipped_area(t: &[DVec2; 3], x0: f64, y0: f64) -> f64 {
    let mut poly: Vec<DVec2> = t.to_vec();
    for (axis, bound, below) in [
        (0, x0, false),
        (0, x0 + 1.0, true),
        (1, y0, false),
        (1, y0 + 1.0, true),
    ] {
        poly = clip(&poly, axis, bound, below);
        if poly.len() < 3 {
            return 0.0;
        }
    }
    area(&poly)
}

/// The part of convex polygon `poly` on one side of the line `axis = bound` (`below`: the side
/// where the coordinate is at most `bound`).
pub(crate) fn clip(poly: &[DVec2], axis: usize, bound: f64, below: bool) -> Vec<DVec2> {
    let inside = |p: &DVec2| {
        let v = p[axis];
        if below { v <= bound } else { v >= bound }
    };
    let mut out = Vec::with_capacity(poly.len() + 2);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (ia, ib) = (inside(&a), inside(&b));
        if ia {
            out.push(a);
        }
        if ia != ib {
            let s = (bound - a[axis]) / (b[axis] - a[axis]);
            out.push(a + (b - a) * s);
        }
    }
    out
}

/// Area of a simple polygon.
pub(crate) fn area(poly: &[DVec2]) -> f64 {
    if poly.len() < 3 {
        return 0.0;
    }
    let twice: f64 = (0..poly.len())
        .map(|i| poly[i].perp_dot(poly[(i + 1) % poly.len()]))
        .sum();
    twice.abs() / 2.0
}

/// Every texel bilinear filtering reads for a point of triangle `t` (its centre within one
/// texel of it along both axes, so every texel it touches too) in a `width` × `height` grid:
/// (texel index, sample, area in texels² of the triangle inside the texel).
pub(crate) fn texels_of(
    t: &[DVec2; 3],
    triangle: u32,
    width: u32,
    height: u32,
    mut each: impl FnMut(usize, Sample, f64),
) {
    let lo = t[0].min(t[1]).min(t[2]);
    let hi = t[0].max(t[1]).max(t[2]);
    let (x0, x1) = (
        (lo.x - 1.5).ceil().max(0.0) as i64,
        ((hi.x + 0.5).ceil() as i64).min(width as i64),
    );
    let (y0, y1) = (
        (lo.y - 1.5).ceil().max(0.0) as i64,
        ((hi.y + 0.5).ceil() as i64).min(height as i64),
    );
    for row in y0..y1 {
        for col in x0..x1 {
            let centre = DVec2::new(col as f64 + 0.5, row as f64 + 0.5);
            let l = barycentric(t, centre);
            let inside = l.filter(|l| l.iter().all(|x| *x >= 0.0));
            let near = inside.unwrap_or_else(|| nearest(t, centre));
            let d = t[0] * near[0] + t[1] * near[1] + t[2] * near[2] - centre;
            if d.x.abs() >= 1.0 || d.y.abs() >= 1.0 {
                continue;
            }
            let piece = clipped_area(t, col as f64, row as f64);
            let sample = Sample {
                triangle,
                bary: inset(near),
                centre: inside.is_some(),
                extended: if inside.is_some() { None } else { l },
                piece,
                distance: d.length(),
            };
            each(row as usize * width as usize + col as usize, sample, piece);
        }
    }
}

/// Whether `a` should replace `b` as a texel's sample: a centre on the triangle first, then the
/// larger piece, then the nearer point, then the lower triangle index (a fixed order whatever
/// the traversal).
pub(crate) fn better(a: &Sample, b: &Sample) -> bool {
    let key = |s: &Sample| {
        (
            s.centre,
            s.piece,
            -s.distance,
            std::cmp::Reverse(s.triangle),
        )
    };
    key(a).partial_cmp(&key(b)).is_some_and(|o| o.is_gt())
}

/// Whether a `[0, 1]²` layout is usable at `res` texels a side: UV charts (triangles joined by
/// shared UV corners) at least two texels apart, no triangle over another.
pub(crate) fn layout_is_clean(uv: &[DVec2], tris: &[[u32; 3]], res: u32) -> bool {
    if (res as u64).pow(2) > 64 << 20 {
        return false;
    }
    // UV charts by union-find over corners with the same UV.
    let mut parent: Vec<usize> = (0..tris.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let mut first: std::collections::HashMap<[u64; 2], usize> = Default::default();
    for (i, t) in tris.iter().enumerate() {
        for &v in t {
            let key = uv[v as usize].to_array().map(f64::to_bits);
            let j = *first.entry(key).or_insert(i);
            let (a, b) = (find(&mut parent, i), find(&mut parent, j));
            parent[a.max(b)] = a.min(b);
        }
    }
    let n = res as usize;
    let mut owner = vec![u32::MAX; n * n];
    let mut centres = vec![0u8; n * n];
    for (i, t) in tris.iter().enumerate() {
        let chart = find(&mut parent, i) as u32;
        let p = t.map(|v| uv[v as usize] * res as f64);
        let mut clash = false;
        texels_of(&p, i as u32, res, res, |k, s, piece| {
            if piece <= 0.0 && !s.centre {
                return;
            }
            if s.centre && s.bary.iter().all(|l| *l > 1e-3) {
                centres[k] = centres[k].saturating_add(1);
                clash |= centres[k] > 1;
            }
            let o = &mut owner[k];
            clash |= *o != u32::MAX && *o != chart;
            *o = chart;
        });
        if clash {
            return false;
        }
    }
    // Two texels of different charts closer than three texels (centre to centre): their
    // dilated padding would meet.
    for row in 0..n {
        for col in 0..n {
            let o = owner[row * n + col];
            if o == u32::MAX {
                continue;
            }
            for r in row.saturating_sub(2)..(row + 3).min(n) {
                for c in col.saturating_sub(2)..(col + 3).min(n) {
                    let q = owner[r * n + c];
                    if q != u32::MAX && q != o {
                        return false;
                    }
                }
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_sum_to_the_triangle_area_and_centres_sample_inside() {
        let t = [
            DVec2::new(0.3, 0.2),
            DVec2::new(7.7, 1.4),
            DVec2::new(2.2, 5.9),
        ];
        let area = (t[1] - t[0]).perp_dot(t[2] - t[0]).abs() / 2.0;
        let mut sum = 0.0;
        let mut touched = 0;
        texels_of(&t, 0, 16, 16, |k, s, piece| {
            sum += piece;
            touched += 1;
            let (col, row) = ((k % 16) as f64 + 0.5, (k / 16) as f64 + 0.5);
            let p = t[0] * s.bary[0] + t[1] * s.bary[1] + t[2] * s.bary[2];
            if s.centre {
                assert!((p - DVec2::new(col, row)).length() < 1e-3);
            }
            assert!(s.bary.iter().all(|l| *l > 0.0), "inside, off the edges");
        });
        assert!((sum - area).abs() < 1e-9 * area, "{sum} vs {area}");
        assert!(touched >= 20);
    }

    #[test]
    fn a_sliver_still_covers_every_texel_it_crosses_and_the_ones_filtering_reads() {
        // 10 texels long, a hundredth of a texel wide, centred on no texel centre.
        let t = [
            DVec2::new(1.1, 3.01),
            DVec2::new(11.1, 3.02),
            DVec2::new(1.1, 3.03),
        ];
        let mut touched = Vec::new();
        let mut read = Vec::new();
        texels_of(&t, 0, 16, 16, |k, _, piece| {
            read.push((k / 16, k % 16));
            if piece > 0.0 {
                touched.push(k % 16);
            }
        });
        assert_eq!(touched, (1..12).collect::<Vec<_>>());
        // Rows 2 and 3 (centres 2.5 and 3.5 are within a texel of y = 3.02), columns 0 to 11.
        let want: Vec<(usize, usize)> = (2..4).flat_map(|r| (0..12).map(move |c| (r, c))).collect();
        assert_eq!(read, want);
    }

    #[test]
    fn nearest_points_lie_on_the_triangle() {
        let t = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 4.0)];
        let l = nearest(&t, DVec2::new(5.0, 5.0));
        let p = t[0] * l[0] + t[1] * l[1] + t[2] * l[2];
        assert!((p - DVec2::new(2.0, 2.0)).length() < 1e-12);
    }
}
