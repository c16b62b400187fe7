//! Tracing a view: per pixel, rays through fixed antialiasing offsets, each to the first front
//! face (or a nearer luminaire opening), averaged.
//!
//! Input: a [`Camera`], the [`Surfaces`], the [`Openings`] and the sample count. Output: per
//! pixel (row 0 at the top) the mean luminance RGB over its rays (a ray that meets nothing counts
//! as 0), the mean illuminance of the surface points its rays hit (NaN when none hit), and, when
//! asked, the display colour: each ray's linear colour sRGB-encoded, then averaged (a
//! multisampling viewer resolves its encoded output).
//!
//! A luminaire opening shows instead of the surface when it is no farther than the surface hit
//! plus the BVH's epsilon (an opening flush with a ceiling or a diffuser is seen). Illuminance
//! is always the surface's (an opening has none). Rows run in parallel; every pixel depends on
//! its own rays only, so the image does not depend on the thread count.

use super::camera::{Camera, sample_offsets};
use super::luminaires::Openings;
use super::surfaces::Surfaces;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// One pixel's values.
#[derive(Debug, Clone, Copy)]
pub struct Pixel {
    pub luminance: [f32; 3],
    pub illuminance: f32,
    pub display: [u8; 3],
}

/// Trace every pixel of `camera`'s image with `samples` rays each; `display`: also the display
/// colour.
pub fn trace(
    camera: &Camera,
    surfaces: &Surfaces,
    openings: &Openings,
    samples: u32,
    display: bool,
    epsilon: f64,
) -> Vec<Pixel> {
    let offsets = sample_offsets(samples);
    let (w, h) = (camera.width, camera.height);
    (0..h)
        .into_par_iter()
        .flat_map_iter(|row| {
            let offsets = &offsets;
            (0..w).map(move |col| {
                let centre = DVec2::new(col as f64 + 0.5, row as f64 + 0.5);
                pixel(camera, surfaces, openings, centre, offsets, display, epsilon)
            })
        })
        .collect()
}

fn pixel(
    camera: &Camera,
    surfaces: &Surfaces,
    openings: &Openings,
    centre: DVec2,
    offsets: &[DVec2],
    display: bool,
    epsilon: f64,
) -> Pixel {
    let mut l = DVec3::ZERO;
    let (mut e, mut hits) = (0.0, 0u32);
    let mut shown = DVec3::ZERO;
    for &o in offsets {
        let dir = camera.direction(centre + o);
        let origin = camera.origin(dir);
        let hit = surfaces.hit(origin, dir);
        let reach = hit.map_or(f64::INFINITY, |h| h.distance + epsilon);
        let lamp = match openings.is_empty() {
            true => None,
            false => openings.seen(origin, dir, reach),
        };
        if let Some(h) = &hit {
            e += surfaces.illuminance(h);
            hits += 1;
            if display {
                shown += surfaces.display(h).map(srgb_encode);
            }
        }
        l += match (lamp, &hit) {
            (Some((_, lum)), _) => lum,
            (None, Some(h)) => surfaces.luminance(h),
            (None, None) => DVec3::ZERO,
        };
    }
    let n = offsets.len() as f64;
    let l = l / n;
    Pixel {
        luminance: [l.x as f32, l.y as f32, l.z as f32],
        illuminance: if hits > 0 {
            (e / hits as f64) as f32
        } else {
            f32::NAN
        },
        display: (shown / n).to_array().map(|c| (c * 255.0).round() as u8),
    }
}

/// The sRGB encoding curve (IEC 61966-2-1) of a linear value, clamped to [0, 1].
fn srgb_encode(linear: f64) -> f64 {
    let c = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// True when the eye is inside a solid: every one of 14 fixed directions (the axes and the
/// cube's diagonals) first meets the back of a surface.
pub fn inside_solid(surfaces: &Surfaces, eye: DVec3) -> bool {
    let mut dirs: Vec<DVec3> = Vec::with_capacity(14);
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        dirs.push(axis);
        dirs.push(-axis);
    }
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                dirs.push(DVec3::new(sx, sy, sz).normalize());
            }
        }
    }
    dirs.iter().all(|&d| surfaces.meets_back_face(eye, d))
}
