//! The baked surfaces as a view sees them: every triangle of every baked primitive in one BVH,
//! the first front face along a ray, and what that point shows.
//!
//! Input: a [`BakedOutput`] and the decoded display textures of its lightmapped materials.
//! Output, at a hit: luminance RGB (cd/m²), illuminance (lx) and the display colour a glTF
//! viewer shows (linear RGB).
//! - Lightmapped primitives: RGB luminance read bilinearly from the lightmap at the hit's
//!   interpolated layout UV (exact: the lightmap holds RGB); illuminance likewise.
//! - Vertex primitives: `_LUMINANCE` (Y) interpolated; the bake writes Y only, so the colour of
//!   each vertex comes from its display colour: COLOR_0 = shoulder(k·E_rgb) per channel is
//!   inverted to k·E_rgb, times the material's RGB reflectance ρ (or, for an emitting vertex —
//!   π·L above ρ·E — the inverted colour itself, which the bake made of the exitance), scaled to
//!   the vertex's Y. Y is exact; the chromaticity is exact up to f32 rounding where COLOR_0 is
//!   below the shoulder (0.8), and degrades where it saturates (clipped at 1: ρ's chromaticity).
//!   Vertex RGB is then interpolated linearly (so interpolated Y is interpolated `_LUMINANCE`).
//! - Display: vertex primitives show baseColorFactor ⊙ interpolated COLOR_0 (unlit); lightmapped
//!   ones emissiveFactor ⊙ the display texture (sRGB texels decoded to linear, then bilinear, as
//!   a GPU's sRGB texture filters). Base colour textures are not drawn.
//!
//! - Display-only primitives (luminous openings): base colour × interpolated COLOR_0, in the
//!   display only, where nearer than every surface.
//!
//! Back faces are culled ([`Occluder::closest_front`]): a double-sided surface is baked as two
//! primitives wound opposite ways, so each side shows its own values.

use crate::readback::{BakedOutput, Lightmap, Primitive};
use crate::scene::luma;
use crate::visibility::Occluder;
use glam::{DVec2, DVec3};

/// A linear-RGB display texture (decoded sRGB texels).
pub struct DisplayTexture {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
}

impl DisplayTexture {
    /// Decode 8-bit sRGB texels to linear.
    pub(crate) fn from_srgb8(width: u32, height: u32, texels: &[[u8; 3]]) -> Self {
        let lut: Vec<f32> = (0..256)
            .map(|i| srgb_to_linear(i as f64 / 255.0) as f32)
            .collect();
        DisplayTexture {
            width,
            height,
            texels: texels.iter().map(|t| t.map(|c| lut[c as usize])).collect(),
        }
    }

    /// Bilinear between texel centres, clamped at the edges (LINEAR, CLAMP_TO_EDGE).
    fn bilinear(&self, uv: DVec2) -> DVec3 {
        let texel = |k: usize| {
            let t = self.texels[k];
            DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
        };
        crate::readback::bilinear(self.width, self.height, texel, uv)
    }
}

/// The sRGB decoding curve (IEC 61966-2-1).
fn srgb_to_linear(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// A ray's first front face.
#[derive(Debug, Clone, Copy)]
pub struct SurfaceHit {
    pub primitive: usize,
    pub triangle: usize,
    /// Barycentric weights of the triangle's vertices at the hit.
    pub weights: [f64; 3],
    pub distance: f64,
}

pub struct Surfaces<'a> {
    baked: &'a BakedOutput,
    /// (primitive, triangle) of each triangle given to the BVH.
    ids: Vec<(u32, u32)>,
    occluder: Occluder,
    /// Per primitive, per vertex: RGB luminance (empty for lightmapped primitives).
    vertex_rgb: Vec<Vec<DVec3>>,
    /// Per texture index of the output: its decoded display texture, where a lightmapped
    /// material shows one.
    textures: Vec<Option<DisplayTexture>>,
    /// The display-only primitives (luminous openings): (primitive, triangle) of each triangle
    /// of their BVH, which the display alone sees.
    shown_ids: Vec<(u32, u32)>,
    shown: Option<Occluder>,
}

impl<'a> Surfaces<'a> {
    /// `textures[t]`: texture `t` decoded, for those the materials' `emissiveTexture` name.
    pub fn new(baked: &'a BakedOutput, textures: Vec<Option<DisplayTexture>>) -> Self {
        let mut ids = Vec::new();
        let mut tris = Vec::new();
        for (p, prim) in baked.primitives.iter().enumerate() {
            for (t, tri) in prim.triangles.iter().enumerate() {
                ids.push((p as u32, t as u32));
                tris.push(tri.map(|v| prim.positions[v as usize]));
            }
        }
        let vertex_rgb = baked
            .primitives
            .iter()
            .map(|p| match p.lightmap {
                Some(_) => Vec::new(),
                None => vertex_luminance(p, baked.materials[p.material].reflectance_rgb),
            })
            .collect();
        let mut shown_ids = Vec::new();
        let mut shown_tris = Vec::new();
        for (p, prim) in baked.shown.iter().enumerate() {
            for (t, tri) in prim.triangles.iter().enumerate() {
                shown_ids.push((p as u32, t as u32));
                shown_tris.push(tri.map(|v| prim.positions[v as usize]));
            }
        }
        Surfaces {
            baked,
            ids,
            occluder: Occluder::from_triangles(&tris, false),
            vertex_rgb,
            textures,
            shown_ids,
            shown: (!shown_tris.is_empty()).then(|| Occluder::from_triangles(&shown_tris, false)),
        }
    }

    /// What a viewer shows of the nearest display-only primitive's front face along the unit
    /// `dir` from `origin` no farther than `reach`: base colour × interpolated COLOR_0.
    pub(crate) fn shown_display(&self, origin: DVec3, dir: DVec3, reach: f64) -> Option<DVec3> {
        let h = self.shown.as_ref()?.closest_front(origin, dir)?;
        if h.distance > reach {
            return None;
        }
        let (p, t) = self.shown_ids[h.triangle];
        let prim = &self.baked.shown[p as usize];
        let tri = prim.triangles[t as usize];
        let w = weights(
            &tri.map(|v| prim.positions[v as usize]),
            origin + dir * h.distance,
        );
        let color: DVec3 = (0..3)
            .map(|k| DVec3::from_array(prim.color[tri[k] as usize].map(f64::from)) * w[k])
            .sum();
        Some(DVec3::from_array(prim.base) * color)
    }

    /// The BVH's distance tolerance (m): 10⁻⁵ of the scene's diagonal.
    pub(crate) fn epsilon(&self) -> f64 {
        self.occluder.epsilon
    }

    /// The first front face along the unit `dir` from `origin`.
    pub fn hit(&self, origin: DVec3, dir: DVec3) -> Option<SurfaceHit> {
        let h = self.occluder.closest_front(origin, dir)?;
        let (p, t) = self.ids[h.triangle];
        let prim = &self.baked.primitives[p as usize];
        let tri = prim.triangles[t as usize].map(|v| prim.positions[v as usize]);
        Some(SurfaceHit {
            primitive: p as usize,
            triangle: t as usize,
            weights: weights(&tri, origin + dir * h.distance),
            distance: h.distance,
        })
    }

    /// Does a ray from `origin` along `dir` meet the back of a triangle no farther than the
    /// first front face (a tie counts: a box standing on a floor)?
    pub(crate) fn meets_back_face(&self, origin: DVec3, dir: DVec3) -> bool {
        let Some(back) = self.occluder.closest_back(origin, dir) else {
            return false;
        };
        self.occluder
            .closest_front(origin, dir)
            .is_none_or(|f| back.distance <= f.distance + self.occluder.epsilon)
    }

    fn interpolate<T>(&self, h: &SurfaceHit, values: &[T], f: impl Fn(&T) -> DVec3) -> DVec3 {
        let prim = &self.baked.primitives[h.primitive];
        let tri = prim.triangles[h.triangle];
        (0..3)
            .map(|k| f(&values[tri[k] as usize]) * h.weights[k])
            .sum()
    }

    fn uv(&self, h: &SurfaceHit, uv: &[DVec2]) -> DVec2 {
        let tri = self.baked.primitives[h.primitive].triangles[h.triangle];
        (0..3).map(|k| uv[tri[k] as usize] * h.weights[k]).sum()
    }

    /// Luminance leaving the surface at the hit, linear RGB (cd/m²).
    pub(crate) fn luminance(&self, h: &SurfaceHit) -> DVec3 {
        let prim = &self.baked.primitives[h.primitive];
        match &prim.lightmap {
            Some(l) => {
                let map = &self.baked.lightmaps[l.lightmap];
                let uv = self.uv(h, &l.uv);
                DVec3::from_array(
                    [0, 1, 2].map(|c| map.bilinear(|k| map.luminance[k][c] as f64, uv)),
                )
            }
            None => self.interpolate(h, &self.vertex_rgb[h.primitive], |v| *v),
        }
    }

    /// Illuminance on the surface at the hit (lx).
    pub fn illuminance(&self, h: &SurfaceHit) -> f64 {
        self.scalar(h, |m| &m.illuminance, |p| &p.illuminance)
    }

    /// The direct part of the illuminance at the hit (lx).
    pub fn direct_illuminance(&self, h: &SurfaceHit) -> f64 {
        self.scalar(h, |m| &m.illuminance_direct, |p| &p.illuminance_direct)
    }

    /// A scalar channel at the hit: the lightmap's (bilinear) or the vertices' (interpolated).
    fn scalar(
        &self,
        h: &SurfaceHit,
        texels: fn(&Lightmap) -> &[f32],
        vertices: fn(&Primitive) -> &[f32],
    ) -> f64 {
        let prim = &self.baked.primitives[h.primitive];
        match &prim.lightmap {
            Some(l) => {
                let map = &self.baked.lightmaps[l.lightmap];
                let values = texels(map);
                map.bilinear(|k| values[k] as f64, self.uv(h, &l.uv))
            }
            None => (self.interpolate(h, vertices(prim), |&e| DVec3::splat(e as f64))).x,
        }
    }

    /// The colour a glTF viewer shows at the hit with the output's materials (linear RGB).
    pub(crate) fn display(&self, h: &SurfaceHit) -> DVec3 {
        let prim = &self.baked.primitives[h.primitive];
        let look = &self.baked.materials[prim.material].look;
        let base = DVec3::new(look.base_color[0], look.base_color[1], look.base_color[2]);
        let mut out = match &prim.color {
            Some(c) => base * self.interpolate(h, c, |c| c.map(f64::from).into()),
            None if look.unlit => base,
            None => DVec3::ZERO,
        };
        let emissive = DVec3::from_array(look.emissive);
        let texture = look
            .emissive_texture
            .and_then(|(t, _)| self.textures.get(t)?.as_ref());
        match (texture, &prim.lightmap) {
            (Some(tex), Some(l)) => out += emissive * tex.bilinear(self.uv(h, &l.uv)),
            (None, _) => out += emissive,
            (Some(_), None) => {}
        }
        out
    }
}

/// Barycentric weights of `p` (on or near the plane of `t`), clamped onto the triangle.
fn weights(t: &[DVec3; 3], p: DVec3) -> [f64; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if det <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let v = ((d22 * d1 - d12 * d2) / det).max(0.0);
    let w = ((d11 * d2 - d12 * d1) / det).max(0.0);
    let u = (1.0 - v - w).max(0.0);
    let s = u + v + w;
    [u / s, v / s, w / s]
}

/// The inverse of the display shoulder (`bake::display`): x for c ≤ 0.8, else
/// 0.8 − 0.2·ln(1 − (c − 0.8)/0.2); `None` where c has saturated.
fn unshoulder(c: f64) -> Option<f64> {
    if c <= 0.8 {
        return Some(c.max(0.0));
    }
    let f = 1.0 - (c - 0.8) / 0.2;
    (f > 1e-6).then(|| 0.8 - 0.2 * f.ln())
}

/// Per vertex of a vertex-valued primitive: RGB luminance with Y = `_LUMINANCE`, colour from
/// COLOR_0 and the reflectance `rho` (see the module's rule).
fn vertex_luminance(p: &Primitive, rho: DVec3) -> Vec<DVec3> {
    (0..p.luminance.len())
        .map(|v| {
            let y = p.luminance[v] as f64;
            let e = p.illuminance[v] as f64;
            let shown = p.color.as_ref().and_then(|c| {
                let k = c[v].map(|x| unshoulder(x as f64));
                Some(DVec3::new(k[0]?, k[1]?, k[2]?))
            });
            let colour = match shown {
                Some(c) if luma(c) > 0.0 => {
                    // The illuminance it shows, scaled to the baked Y: a vertex leaving more
                    // than ρ·E reflects is an emitter, whose COLOR_0 shows its exitance.
                    let e_rgb = c * (e / luma(c));
                    let reflected = luma(rho * e_rgb);
                    let emits = std::f64::consts::PI * y > reflected * (1.0 + 1e-3) + 1e-12;
                    if emits { c } else { rho * c }
                }
                _ => rho,
            };
            let cy = luma(colour);
            if cy > 0.0 {
                colour * (y / cy)
            } else {
                DVec3::splat(y)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unshoulder_inverts_the_display_rule() {
        let shoulder = |x: f64| {
            if x <= 0.8 {
                x
            } else {
                0.8 + 0.2 * (1.0 - (-(x - 0.8) / 0.2).exp())
            }
        };
        for x in [0.0, 0.3, 0.8, 0.9, 1.2, 2.0] {
            assert!((unshoulder(shoulder(x)).unwrap() - x).abs() < 1e-9, "{x}");
        }
        assert_eq!(unshoulder(1.0), None);
    }

    #[test]
    fn weights_interpolate_the_corners() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let w = weights(&t, DVec3::new(0.25, 0.5, 0.0));
        assert!((w[0] - 0.25).abs() < 1e-12 && (w[1] - 0.25).abs() < 1e-12);
        assert!((w[2] - 0.5).abs() < 1e-12);
    }
}
