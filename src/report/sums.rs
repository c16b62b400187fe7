//! The sums behind a surface row: area, area-weighted reflectance, E, E direct and L, and E's
//! extremes, over one primitive at a time, from its texels or from its vertices.
//!
//! Texels: each texel the primitive stands on (`crate::readback::LightmapUse::texels`) with a
//! footprint weighs its footprint (m²); its E, E direct and L (Y of the RGB channels) are the
//! EXR's; the extremes are over those texels. A face filter takes the texels whose triangle
//! (the one with the most area in the texel) passes. Vertices: each triangle with area weighs
//! its area, a third at each vertex (the area integral of the piecewise-linear values); the
//! extremes are over the vertices of the triangles taken.
//!
//! Covered triangles (`Primitive::covered_from`: the floor under a desk leg, without light) and
//! texels whose triangle is covered are left out of all of it; their area is summed apart
//! (`covered`).

use crate::readback::{BakedOutput, Primitive};
use glam::DVec3;

/// Which triangles a row takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    All,
    /// Only faces whose normal is within ~8° of this direction (e.g. +Y: upward faces).
    Facing(DVec3),
}

/// What a row's figures were taken from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum Source {
    /// The lightmap texels of every primitive.
    Texels,
    /// The vertex values of every primitive.
    Vertices,
    /// Texels of the lightmapped primitives, vertices of the others.
    TexelsAndVertices,
}

impl Source {
    /// In words, for titles (`lightmap texels`).
    pub(crate) fn describe(self) -> &'static str {
        match self {
            Source::Texels => "lightmap texels",
            Source::Vertices => "vertices",
            Source::TexelsAndVertices => "lightmap texels and vertices",
        }
    }
}

/// Running sums of a row.
#[derive(Debug, Default)]
pub(super) struct Sums {
    pub area: f64,
    pub rho: f64,
    pub e: f64,
    pub ed: f64,
    pub l: f64,
    pub lo: Option<f64>,
    pub hi: Option<f64>,
    /// Area of covered triangles passing the filter (m²), left out of everything else.
    pub covered: f64,
    texels: bool,
    vertices: bool,
}

impl Sums {
    /// Add primitive `p`, from its texels when it has some and `texels`.
    pub(crate) fn add(
        &mut self,
        input: &BakedOutput,
        p: &Primitive,
        filter: &Filter,
        texels: bool,
    ) {
        let rho = input
            .materials
            .get(p.material)
            .map_or(0.0, |m| m.reflectance);
        if let Some(k) = p.covered_from {
            self.covered += (k as usize..p.triangles.len())
                .filter(|&j| passes(p, j, filter))
                .map(|j| area(p, j))
                .sum::<f64>();
        }
        match p.lightmap.as_ref().filter(|_| texels) {
            Some(layout) => {
                let lm = &input.lightmaps[layout.lightmap];
                for t in &layout.texels {
                    let k = t.index as usize;
                    let w = f64::from(lm.footprint[k]);
                    let j = t.triangle as usize;
                    if w > 0.0 && !p.is_covered(j) && passes(p, j, filter) {
                        self.area(w, rho);
                        let e = f64::from(lm.illuminance[k]);
                        let ed = f64::from(lm.illuminance_direct[k]);
                        self.values(w, [e, ed, lm.luminance_y(k)]);
                        self.texels = true;
                    }
                }
            }
            None => {
                for (j, t) in p.triangles.iter().enumerate() {
                    let w = area(p, j);
                    if w <= 0.0 || p.is_covered(j) || !passes(p, j, filter) {
                        continue;
                    }
                    self.area(w, rho);
                    for &v in t {
                        let v = v as usize;
                        let values = [
                            p.illuminance[v] as f64,
                            p.illuminance_direct[v] as f64,
                            p.luminance[v] as f64,
                        ];
                        self.values(w / 3.0, values);
                    }
                    self.vertices = true;
                }
            }
        }
    }

    /// What the sums were taken from.
    pub(crate) fn source(&self) -> Source {
        match (self.texels, self.vertices) {
            (true, false) => Source::Texels,
            (true, true) => Source::TexelsAndVertices,
            (false, _) => Source::Vertices,
        }
    }

    fn area(&mut self, w: f64, rho: f64) {
        self.area += w;
        self.rho += w * rho;
    }

    /// E, E direct and L weighing `w` m²; E counts for the extremes.
    fn values(&mut self, w: f64, [e, ed, l]: [f64; 3]) {
        self.e += w * e;
        self.ed += w * ed;
        self.l += w * l;
        self.lo = Some(self.lo.map_or(e, |x| x.min(e)));
        self.hi = Some(self.hi.map_or(e, |x| x.max(e)));
    }
}

/// Area of triangle `j` of `p` (m²).
fn area(p: &Primitive, j: usize) -> f64 {
    let [a, b, c] = p.triangles[j].map(|v| p.positions[v as usize]);
    (b - a).cross(c - a).length() / 2.0
}

/// Whether triangle `j` of `p` passes the filter (a face filter: its normal within ~8° of the
/// direction).
fn passes(p: &Primitive, j: usize, filter: &Filter) -> bool {
    match filter {
        Filter::All => true,
        Filter::Facing(d) => crate::readback::keys::faces(p, j, *d),
    }
}
