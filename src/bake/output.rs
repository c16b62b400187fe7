//! The output stage: the solution shaped for the exporter, one [`BakedSurface`] per patch group
//! (a side of a surface): world-space vertices, triangles, and at every vertex the illuminance
//! (total and direct), the luminance leaving it and its display colour.

use super::display;
use crate::result::BakedSurface;
use crate::scene::luma;
use crate::solution::Solution;
use glam::DVec3;

/// Shape the solution for the exporter: one baked surface per patch group.
pub(crate) fn surfaces(s: &Solution, scale: f64) -> Vec<BakedSurface> {
    let (scene, mesh) = (s.scene(), s.mesh());
    mesh.groups
        .iter()
        .map(|g| {
            let material = &scene.materials[g.material];
            // Every patch of a group emits alike.
            let emitted = match g.patches.is_empty() {
                true => DVec3::ZERO,
                false => s.emitted(g.patches.start),
            };
            let range = g.receivers.clone();
            let r0 = range.start as u32;
            let mut illuminance = Vec::with_capacity(range.len());
            let mut illuminance_direct = Vec::with_capacity(range.len());
            let mut luminance = Vec::with_capacity(range.len());
            let mut color = Vec::with_capacity(range.len());
            for r in range.clone() {
                let light = s.vertex(r);
                let e = light.total();
                let exitance = emitted + material.reflectance * e;
                illuminance.push(luma(e) as f32);
                illuminance_direct.push(luma(light.direct) as f32);
                luminance.push((luma(exitance) / std::f64::consts::PI) as f32);
                color.push(display::color(e, exitance, material, scale));
            }
            let mut out = BakedSurface {
                surface: g.surface,
                side: g.side,
                positions: mesh.receivers[range.clone()]
                    .iter()
                    .map(|r| r.position)
                    .collect(),
                normals: mesh.receivers[range.clone()]
                    .iter()
                    .map(|r| r.normal)
                    .collect(),
                uv0: g.uv0.clone(),
                uv1: g.uv1.clone(),
                triangles: mesh.patches[g.patches.clone()]
                    .iter()
                    .map(|p| p.v.map(|v| v - r0))
                    .collect(),
                illuminance,
                illuminance_direct,
                luminance,
                color,
                lightmap: None,
                covered_from: None,
            };
            if let Some(c) = &g.covered {
                append_covered(
                    &mut out,
                    c,
                    display::color(DVec3::ZERO, DVec3::ZERO, material, scale),
                );
            }
            out
        })
        .collect()
}

/// A side's covered part, appended with vertices of its own: no light reaches it, and it sends
/// none (what covers it hides it).
fn append_covered(out: &mut BakedSurface, c: &crate::patches::CoveredPart, black: [f32; 3]) {
    let n = out.positions.len() as u32;
    out.covered_from = Some(out.triangles.len() as u32);
    out.positions.extend_from_slice(&c.positions);
    out.normals.extend_from_slice(&c.normals);
    for (uv, extra) in [(&mut out.uv0, &c.uv0), (&mut out.uv1, &c.uv1)] {
        if let (Some(uv), Some(extra)) = (uv.as_mut(), extra) {
            uv.extend_from_slice(extra);
        }
    }
    out.triangles
        .extend(c.triangles.iter().map(|t| t.map(|v| v + n)));
    let k = c.positions.len();
    out.illuminance.extend(std::iter::repeat_n(0.0, k));
    out.illuminance_direct.extend(std::iter::repeat_n(0.0, k));
    out.luminance.extend(std::iter::repeat_n(0.0, k));
    out.color.extend(std::iter::repeat_n(black, k));
}
