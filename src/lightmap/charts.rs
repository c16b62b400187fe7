//! Charts: each baked surface's triangles grouped into pieces that unfold flat, in texel units.
//!
//! Input: one [`BakedSurface`] (its first `open` triangles receive light, the rest is its covered
//! part) and the texel edge t (m). Output: [`SurfaceCharts`]: the open triangles in charts, each
//! with per-corner coordinates in texels (origin at the chart's lower corner, unpadded) and its
//! extent; the covered triangles apart (they are laid on one black texel).
//!
//! A surface whose input `TEXCOORD_1` is a usable layout (inside [0, 1], its charts apart by two
//! texels at the resolution its area asks for, no triangle over another) keeps it: one chart, the
//! unit square scaled. Otherwise: coplanar connected pieces (normals within 2°) of at least 16
//! texels are one chart each (a floor, a wall), projected on their plane with world-aligned axes (floors: +X right, +Z
//! down the image; walls: horizontal right, −Y down, glTF +Y up); what is left (curved clutter)
//! grows into charts from the largest triangle while normals stay within 50° of the seed's,
//! projected on the seed's plane (area distortion at most 1/cos 50°). Connectivity is by
//! position (exporters split vertices at creases and seams), never through the covered part.

use crate::result::BakedSurface;
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// A chart: triangles of one surface and their corners in texels.
#[derive(Debug, Clone)]
pub struct Chart {
    /// Indices into the surface's triangles.
    pub triangles: Vec<u32>,
    /// Per triangle, per corner: texel coordinates (x right, y down), min corner at (0, 0).
    pub corners: Vec<[DVec2; 3]>,
    /// Extent in texels.
    pub size: DVec2,
}

/// One surface's charts.
#[derive(Debug, Clone)]
pub struct SurfaceCharts {
    pub charts: Vec<Chart>,
    /// The covered triangles (all laid on one texel).
    pub covered: Vec<u32>,
    /// Whether the charts are the input's `TEXCOORD_1` layout.
    pub kept_input: bool,
}

impl SurfaceCharts {
    /// The same charts at a texel `factor` times larger.
    pub(crate) fn coarser(&self, factor: f64) -> Self {
        let mut out = self.clone();
        for c in &mut out.charts {
            c.size /= factor;
            for t in &mut c.corners {
                for p in t.iter_mut() {
                    *p /= factor;
                }
            }
        }
        out
    }
}

/// Coplanar pieces smaller than this many texels are charted with the clutter.
const MIN_PLANAR_TEXELS: f64 = 16.0;
/// Normals of one clutter chart stay within this of the seed's (cos 50°).
const CLUTTER_COS: f64 = 0.6428;
/// Coplanar: normals within 2° of the seed's (exporters' quads are often a little bent).
const PLANAR_COS: f64 = 0.99939;

/// The charts of `s`, whose first `open` triangles receive light, at texel edge `t` (m).
pub(crate) fn of(s: &BakedSurface, open: usize, t: f64) -> SurfaceCharts {
    let covered = (open as u32..s.triangles.len() as u32).collect();
    let tris = &s.triangles[..open];
    if let Some(chart) = s.uv1.as_ref().and_then(|uv| input_layout(s, uv, tris, t)) {
        return SurfaceCharts {
            charts: vec![chart],
            covered,
            kept_input: true,
        };
    }
    let geo = Geometry::new(s, tris);
    let mut chart_of = vec![usize::MAX; tris.len()];
    let mut charts = Vec::new();
    // Seeds in order of decreasing area (ties by index): large planes first.
    let mut order: Vec<usize> = (0..tris.len()).filter(|&i| geo.area[i] > 0.0).collect();
    order.sort_by(|&a, &b| geo.area[b].total_cmp(&geo.area[a]).then(a.cmp(&b)));
    for &seed in &order {
        if chart_of[seed] != usize::MAX {
            continue;
        }
        let n = geo.normal[seed];
        let planar = geo.grow(seed, &chart_of, |i| geo.normal[i].dot(n) > PLANAR_COS);
        let area: f64 = planar.iter().map(|&i| geo.area[i]).sum();
        let members = if area >= MIN_PLANAR_TEXELS * t * t {
            planar
        } else {
            geo.grow(seed, &chart_of, |i| geo.normal[i].dot(n) > CLUTTER_COS)
        };
        for &i in &members {
            chart_of[i] = charts.len();
        }
        charts.push(project(&geo, members, n, t));
    }
    // Degenerate triangles (no area) join a chart of one of their own.
    for (i, c) in chart_of.iter().enumerate() {
        if *c == usize::MAX {
            charts.push(project(&geo, vec![i], DVec3::Y, t));
        }
    }
    SurfaceCharts {
        charts,
        covered,
        kept_input: false,
    }
}

/// Triangles' corners, normals and areas, and which share an edge (by position).
struct Geometry<'a> {
    positions: &'a [DVec3],
    tris: &'a [[u32; 3]],
    normal: Vec<DVec3>,
    area: Vec<f64>,
    /// Per triangle, per edge: the neighbours across it.
    neighbours: Vec<Vec<u32>>,
}

impl<'a> Geometry<'a> {
    fn new(s: &'a BakedSurface, tris: &'a [[u32; 3]]) -> Self {
        let positions = &s.positions;
        let (lo, hi) = positions.iter().fold(
            (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let scale = (hi - lo).length().max(1e-9);
        // Welded on a grid of 10⁻⁷ of the surface's size: refinement computes a shared edge's
        // points from each triangle's own corners, a few ulps apart.
        let grid = 1e-7 * scale;
        let mut ids: HashMap<[i64; 3], u32> = HashMap::new();
        let weld: Vec<u32> = positions
            .iter()
            .map(|p| {
                let key = ((*p - lo) / grid).round().to_array().map(|x| x as i64);
                let next = ids.len() as u32;
                *ids.entry(key).or_insert(next)
            })
            .collect();
        let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
        let (mut normal, mut area) = (
            Vec::with_capacity(tris.len()),
            Vec::with_capacity(tris.len()),
        );
        for (i, t) in tris.iter().enumerate() {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            let cross = (b - a).cross(c - a);
            area.push(cross.length() / 2.0);
            normal.push(cross.normalize_or_zero());
            for k in 0..3 {
                let (u, v) = (weld[t[k] as usize], weld[t[(k + 1) % 3] as usize]);
                if u != v {
                    edges
                        .entry((u.min(v), u.max(v)))
                        .or_default()
                        .push(i as u32);
                }
            }
        }
        let mut neighbours = vec![Vec::new(); tris.len()];
        let mut keys: Vec<_> = edges.into_iter().collect();
        keys.sort_unstable_by_key(|(k, _)| *k);
        for (_, ts) in keys {
            for &a in &ts {
                for &b in &ts {
                    if a != b {
                        neighbours[a as usize].push(b);
                    }
                }
            }
        }
        Geometry {
            positions,
            tris,
            normal,
            area,
            neighbours,
        }
    }

    fn corners(&self, i: usize) -> [DVec3; 3] {
        self.tris[i].map(|v| self.positions[v as usize])
    }

    /// Triangles reachable from `seed` across shared edges through triangles not yet charted
    /// that `accept`; breadth first, so the order is fixed.
    fn grow(&self, seed: usize, chart_of: &[usize], accept: impl Fn(usize) -> bool) -> Vec<usize> {
        let mut taken = std::collections::HashSet::new();
        let mut out = vec![seed];
        taken.insert(seed);
        let mut k = 0;
        while k < out.len() {
            let i = out[k];
            k += 1;
            for &j in &self.neighbours[i] {
                let j = j as usize;
                if chart_of[j] == usize::MAX
                    && self.area[j] > 0.0
                    && !taken.contains(&j)
                    && accept(j)
                {
                    taken.insert(j);
                    out.push(j);
                }
            }
        }
        out.sort_unstable();
        out
    }
}

/// World-aligned axes of a plane with normal `n` (glTF +Y up): floors map +X right and +Z down
/// the image (seen from above), walls horizontal right and −Y down (upright).
pub(crate) fn axes(n: DVec3) -> (DVec3, DVec3) {
    let u = match n.y.abs() > 0.7 {
        true => (DVec3::X - n * n.x).normalize(),
        false => DVec3::Y.cross(n).normalize(),
    };
    (u, u.cross(n))
}

fn project(geo: &Geometry, members: Vec<usize>, n: DVec3, t: f64) -> Chart {
    let (u, v) = axes(n);
    let mut corners: Vec<[DVec2; 3]> = members
        .iter()
        .map(|&i| geo.corners(i).map(|p| DVec2::new(p.dot(u), p.dot(v)) / t))
        .collect();
    let lo = corners
        .iter()
        .flatten()
        .fold(DVec2::splat(f64::MAX), |a, p| a.min(*p));
    let hi = corners
        .iter()
        .flatten()
        .fold(DVec2::splat(f64::MIN), |a, p| a.max(*p));
    for c in &mut corners {
        for p in c.iter_mut() {
            *p -= lo;
        }
    }
    Chart {
        triangles: members.into_iter().map(|i| i as u32).collect(),
        corners,
        size: hi - lo,
    }
}

/// The input's `TEXCOORD_1` as one chart when it is a usable layout at texel `t`.
fn input_layout(s: &BakedSurface, uv: &[DVec2], tris: &[[u32; 3]], t: f64) -> Option<Chart> {
    if tris.is_empty() {
        return None;
    }
    let inside = |p: &DVec2| p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0 && p.is_finite();
    if !tris.iter().flatten().all(|&v| inside(&uv[v as usize])) {
        return None;
    }
    let (mut world, mut uv_area) = (0.0, 0.0);
    for tri in tris {
        let [a, b, c] = tri.map(|v| s.positions[v as usize]);
        world += (b - a).cross(c - a).length() / 2.0;
        let [p, q, r] = tri.map(|v| uv[v as usize]);
        uv_area += ((q - p).perp_dot(r - p) / 2.0).abs();
    }
    if uv_area <= 0.0 || world <= 0.0 {
        return None;
    }
    // Texels per UV unit so that a texel stands for about t² of surface.
    let res = ((world / uv_area).sqrt() / t).ceil().clamp(4.0, 16384.0);
    if !super::raster::layout_is_clean(uv, tris, res as u32) {
        return None;
    }
    Some(Chart {
        triangles: (0..tris.len() as u32).collect(),
        corners: tris
            .iter()
            .map(|tri| tri.map(|v| uv[v as usize] * res))
            .collect(),
        size: DVec2::splat(res),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::result::Side;

    fn surface(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> BakedSurface {
        let n = positions.len();
        BakedSurface {
            surface: 0,
            side: Side::Front,
            normals: vec![DVec3::Y; n],
            positions,
            uv0: None,
            uv1: None,
            triangles,
            illuminance: vec![0.0; n],
            illuminance_direct: vec![0.0; n],
            luminance: vec![0.0; n],
            color: vec![[0.0; 3]; n],
            lightmap: None,
            covered_from: None,
        }
    }

    /// A 2 m × 1 m floor (+Y up) and a 1 m wall on its far edge, vertices split at the crease.
    fn floor_and_wall() -> BakedSurface {
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        surface(
            vec![
                p(0., 0., 0.),
                p(0., 0., 1.),
                p(2., 0., 1.),
                p(2., 0., 0.),
                p(0., 0., 0.),
                p(2., 0., 0.),
                p(2., 1., 0.),
                p(0., 1., 0.),
            ],
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
        )
    }

    #[test]
    fn a_floor_and_a_wall_are_two_flat_charts_in_texels() {
        let c = of(&floor_and_wall(), 4, 0.1);
        assert_eq!(c.charts.len(), 2);
        let floor = c.charts.iter().find(|c| c.triangles == [0, 1]).unwrap();
        assert!((floor.size - DVec2::new(20.0, 10.0)).length() < 1e-9);
        let wall = c.charts.iter().find(|c| c.triangles == [2, 3]).unwrap();
        assert!((wall.size - DVec2::new(20.0, 10.0)).length() < 1e-9);
        // Projections keep lengths: the floor's diagonal is √5 m = 22.36 texels.
        let [a, _, c2] = floor.corners[0];
        assert!(((a - c2).length() - 5f64.sqrt() * 10.0).abs() < 1e-9);
    }

    #[test]
    fn axes_are_right_handed_and_walls_read_upright() {
        for n in [
            DVec3::Y,
            -DVec3::Y,
            DVec3::X,
            -DVec3::Z,
            DVec3::new(1.0, 0.2, 0.3).normalize(),
        ] {
            let (u, v) = axes(n);
            assert!(u.dot(n).abs() < 1e-12 && v.dot(n).abs() < 1e-12 && u.dot(v).abs() < 1e-12);
            assert!((u.length() - 1.0).abs() < 1e-12 && (v.length() - 1.0).abs() < 1e-12);
        }
        // A wall's image rows run down: v points down (−Y).
        assert!(axes(DVec3::Z).1.y < -0.99);
    }

    #[test]
    fn a_usable_input_layout_is_kept_and_an_overlapping_one_is_not() {
        let mut s = floor_and_wall();
        s.uv1 = Some(vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(0.0, 0.4),
            DVec2::new(0.9, 0.4),
            DVec2::new(0.9, 0.0),
            DVec2::new(0.0, 0.6),
            DVec2::new(0.9, 0.6),
            DVec2::new(0.9, 1.0),
            DVec2::new(0.0, 1.0),
        ]);
        let kept = of(&s, 4, 0.1);
        assert!(kept.kept_input);
        assert_eq!(kept.charts.len(), 1);
        // The wall laid over the floor: not a layout.
        let uv = s.uv1.as_mut().unwrap();
        for k in 4..8 {
            uv[k] = uv[k - 4];
        }
        assert!(!of(&s, 4, 0.1).kept_input);
    }

    #[test]
    fn a_cylinder_is_few_charts_within_the_cone() {
        // 24 facets of a vertical cylinder, radius 0.2 m, height 0.5 m.
        let (mut pos, mut tris) = (Vec::new(), Vec::new());
        for k in 0..24 {
            let a = k as f64 * std::f64::consts::TAU / 24.0;
            pos.push(DVec3::new(0.2 * a.cos(), 0.0, 0.2 * a.sin()));
            pos.push(DVec3::new(0.2 * a.cos(), 0.5, 0.2 * a.sin()));
        }
        for k in 0..24u32 {
            let (a, b) = (2 * k, 2 * ((k + 1) % 24));
            tris.push([a, a + 1, b + 1]);
            tris.push([a, b + 1, b]);
        }
        let c = of(&surface(pos, tris), 48, 0.05);
        let sizes: usize = c.charts.iter().map(|c| c.triangles.len()).sum();
        assert_eq!(sizes, 48);
        assert!(c.charts.len() <= 4, "{} charts", c.charts.len());
    }
}
