//! Lightmaps: every baked surface laid out in atlases, every texel a receiver.
//!
//! Input: the solved scene and the baked surfaces of the output stage (one per patch group, in
//! the mesh's group order; each group's patches first, its covered part after). Output: the
//! surfaces re-indexed on their atlas layout (`uv1` = `TEXCOORD_1`, vertices split on chart
//! edges, `lightmap` = atlas) and the [`Lightmaps`]: per texel the luminance leaving the surface
//! (cd/m², RGB), illuminance and its direct part (lx), the area it stands for (m²) and the
//! display colour.
//!
//! Stages: `charts` (flat pieces in texels, or the input's own layout), `pack` (charts of one
//! surface into one atlas, more atlases when one is full; a surface too large for one is laid
//! out coarser), `raster` (which point each texel reads, conservatively), `texels` (direct light
//! exact at every texel; inter-reflected light interpolated from the vertices' gathers where a
//! gather at the triangle's middle texel agrees, gathered at every texel where it does not),
//! `fill` (padding dilated so bilinear filtering never reads an empty texel). Invariants: a
//! chart's texels never share a texel or its padding with another chart; a texel's areas sum to
//! the surface's area; nothing depends on the thread count.

pub mod charts;
mod fill;
pub mod pack;
pub mod raster;
mod reflected;
mod texels;

use crate::progress::Progress;
use crate::result::{Atlas, BakedSurface, Lightmaps};
use crate::solution::Solution;
use crate::summary::{CoarserSurface, LightmapRecord};
use charts::SurfaceCharts;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// How to bake the lightmaps.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Texel edge (m).
    pub texel_size: f64,
    /// Largest atlas edge (texels).
    pub max_size: u32,
    /// Inter-reflected light is interpolated from the vertices over a triangle where a gather at
    /// its middle texel differs from the interpolation by at most this fraction of the texel's
    /// total illuminance; 0 gathers at every texel.
    pub tolerance: f64,
}

/// The display colour of a texel from its illuminance and exitance (RGB) and its material.
pub type Display<'a> = dyn Fn(DVec3, DVec3, usize) -> [f32; 3] + Sync + 'a;

/// Texels of padding around each chart (its dilated ring stays inside its rectangle).
const PAD: u32 = 1;

/// Lay out and bake the lightmaps of `surfaces` (re-indexed in place).
pub(crate) fn bake(
    s: &Solution,
    surfaces: &mut [BakedSurface],
    o: &Options,
    display: &Display,
    progress: &dyn Progress,
) -> (Lightmaps, LightmapRecord) {
    let open: Vec<usize> = s.mesh().groups.iter().map(|g| g.patches.len()).collect();
    assert_eq!(
        open.len(),
        surfaces.len(),
        "one baked surface per patch group"
    );
    let mut charts: Vec<SurfaceCharts> = (surfaces.par_iter().zip(&open))
        .map(|(b, &k)| charts::of(b, k, o.texel_size))
        .collect();
    let mut factor = vec![1.0; surfaces.len()];
    let packing = loop {
        let groups: Vec<Vec<pack::Rect>> = charts.iter().map(rects).collect();
        match pack::pack(&groups, o.max_size) {
            Ok(p) => break p,
            Err(pack::TooBig { group }) => {
                factor[group] *= 2.0;
                charts[group] = charts[group].coarser(2.0);
            }
        }
    };
    let mut origins = Vec::with_capacity(surfaces.len());
    for (i, b) in surfaces.iter_mut().enumerate() {
        origins.push(relayout(
            b,
            &charts[i],
            &packing.places[i],
            &packing.atlases,
        ));
    }
    let mut atlases: Vec<Atlas> = (packing.atlases.iter())
        .map(|&(w, h)| Atlas::new(w, h))
        .collect();
    let samples = rasterise(surfaces, &open, &charts, &packing, &mut atlases);
    let reading = reflected::Reading {
        s,
        surfaces,
        origins: &origins,
        o,
        progress,
    };
    let gathered = texels::light(&reading, &samples, &mut atlases, display);
    let mut filled: Vec<Vec<bool>> = (atlases.iter())
        .map(|a| vec![false; a.width as usize * a.height as usize])
        .collect();
    for t in &samples {
        filled[t.atlas as usize][t.texel as usize] = true;
    }
    for (a, f) in atlases.iter_mut().zip(filled) {
        fill::dilate(a, f);
    }
    let record = LightmapRecord {
        texel_size_m: o.texel_size,
        max_size: o.max_size,
        atlases: atlases.iter().map(|a| [a.width, a.height]).collect(),
        texels: (atlases.iter())
            .map(|a| a.area.iter().filter(|x| **x > 0.0).count())
            .sum(),
        charts: charts.iter().map(|c| c.charts.len()).sum(),
        kept_input_layouts: charts.iter().filter(|c| c.kept_input).count(),
        coarser: (factor.iter().enumerate())
            .filter(|(_, f)| **f > 1.0)
            .map(|(i, f)| CoarserSurface {
                surface: surfaces[i].surface,
                texel_size_m: o.texel_size * f,
            })
            .collect(),
        gathered_texels: gathered,
    };
    let lightmaps = Lightmaps {
        texel_size: o.texel_size,
        atlases,
    };
    (lightmaps, record)
}

/// A surface's rectangles: its charts padded, then (when it has a covered part) one texel.
fn rects(c: &SurfaceCharts) -> Vec<pack::Rect> {
    let mut out: Vec<pack::Rect> = (c.charts.iter())
        .map(|c| pack::Rect {
            w: c.size.x.ceil() as u32 + 2 * PAD,
            h: c.size.y.ceil() as u32 + 2 * PAD,
        })
        .collect();
    if !c.covered.is_empty() {
        out.push(pack::Rect {
            w: 1 + 2 * PAD,
            h: 1 + 2 * PAD,
        });
    }
    out
}

/// Re-index `b` on its layout: a vertex per (chart, vertex), `uv1` its atlas coordinates.
/// Returns, per new vertex, the vertex it copies.
fn relayout(
    b: &mut BakedSurface,
    c: &SurfaceCharts,
    places: &[pack::Place],
    sizes: &[(u32, u32)],
) -> Vec<u32> {
    let atlas = places.first().map_or(0, |p| p.atlas);
    let (w, h) = sizes[atlas];
    let scale = DVec2::new(w as f64, h as f64);
    let mut origin: Vec<u32> = Vec::new();
    let mut uv: Vec<DVec2> = Vec::new();
    let mut triangles = b.triangles.clone();
    let mut ids = std::collections::HashMap::new();
    let mut add = |key: (usize, u32), at: DVec2| -> u32 {
        *ids.entry(key).or_insert_with(|| {
            origin.push(key.1);
            uv.push(at / scale);
            origin.len() as u32 - 1
        })
    };
    for (k, chart) in c.charts.iter().enumerate() {
        let corner = DVec2::new((places[k].x + PAD) as f64, (places[k].y + PAD) as f64);
        for (t, q) in chart.triangles.iter().zip(&chart.corners) {
            let tri = b.triangles[*t as usize];
            for j in 0..3 {
                triangles[*t as usize][j] = add((k, tri[j]), corner + q[j]);
            }
        }
    }
    if let Some(p) = places.get(c.charts.len()) {
        let centre = DVec2::new((p.x + PAD) as f64 + 0.5, (p.y + PAD) as f64 + 0.5);
        for &t in &c.covered {
            let tri = b.triangles[t as usize];
            for j in 0..3 {
                triangles[t as usize][j] = add((usize::MAX, tri[j]), centre);
            }
        }
    }
    let pick = |v: &[f32]| origin.iter().map(|&o| v[o as usize]).collect::<Vec<f32>>();
    b.illuminance = pick(&b.illuminance);
    b.illuminance_direct = pick(&b.illuminance_direct);
    b.luminance = pick(&b.luminance);
    b.color = origin.iter().map(|&o| b.color[o as usize]).collect();
    b.positions = origin.iter().map(|&o| b.positions[o as usize]).collect();
    b.normals = origin.iter().map(|&o| b.normals[o as usize]).collect();
    b.uv0 = (b.uv0.as_ref()).map(|u| origin.iter().map(|&o| u[o as usize]).collect());
    b.uv1 = Some(uv);
    b.triangles = triangles;
    b.lightmap = Some(atlas);
    origin
}

/// One texel that stands for some surface.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sampled {
    pub atlas: u32,
    /// Index of the texel in its atlas.
    pub texel: u32,
    pub surface: u32,
    /// `None`: the texel of a covered part (no light).
    pub sample: Option<raster::Sample>,
}

/// Every texel a surface touches, in atlas and texel order, with its area added to the atlas.
fn rasterise(
    surfaces: &[BakedSurface],
    open: &[usize],
    charts: &[SurfaceCharts],
    packing: &pack::Packing,
    atlases: &mut [Atlas],
) -> Vec<Sampled> {
    let mut best: Vec<Vec<Option<(u32, raster::Sample)>>> = (atlases.iter())
        .map(|a| vec![None; a.width as usize * a.height as usize])
        .collect();
    let mut covered: Vec<Vec<(u32, usize)>> = vec![Vec::new(); atlases.len()];
    for (i, b) in surfaces.iter().enumerate() {
        let Some(a) = b.lightmap else { continue };
        let atlas = &mut atlases[a];
        let scale = DVec2::new(atlas.width as f64, atlas.height as f64);
        let uv = b.uv1.as_ref().expect("laid out");
        for (t, tri) in b.triangles[..open[i]].iter().enumerate() {
            let q = tri.map(|v| uv[v as usize] * scale);
            let [p0, p1, p2] = tri.map(|v| b.positions[v as usize]);
            let world = (p1 - p0).cross(p2 - p0).length() / 2.0;
            let texels = (q[1] - q[0]).perp_dot(q[2] - q[0]).abs() / 2.0;
            let per = if texels > 0.0 { world / texels } else { 0.0 };
            let slot = &mut best[a];
            raster::texels_of(&q, t as u32, atlas.width, atlas.height, |k, s, piece| {
                atlas.area[k] += (piece * per) as f32;
                if slot[k].is_none_or(|(_, old)| raster::better(&s, &old)) {
                    slot[k] = Some((i as u32, s));
                }
            });
        }
        if !charts[i].covered.is_empty() {
            let p = packing.places[i][charts[i].charts.len()];
            let k = (p.y + PAD) as usize * atlas.width as usize + (p.x + PAD) as usize;
            let area: f64 = (charts[i].covered.iter())
                .map(|&t| {
                    let [p0, p1, p2] = b.triangles[t as usize].map(|v| b.positions[v as usize]);
                    (p1 - p0).cross(p2 - p0).length() / 2.0
                })
                .sum();
            atlas.area[k] += area as f32;
            covered[a].push((i as u32, k));
        }
    }
    let mut out = Vec::new();
    for (a, slots) in best.iter().enumerate() {
        for (k, s) in slots.iter().enumerate() {
            if let Some((surface, sample)) = s {
                out.push(Sampled {
                    atlas: a as u32,
                    texel: k as u32,
                    surface: *surface,
                    sample: Some(*sample),
                });
            }
        }
        for &(surface, k) in &covered[a] {
            out.push(Sampled {
                atlas: a as u32,
                texel: k as u32,
                surface,
                sample: None,
            });
        }
    }
    out
}
