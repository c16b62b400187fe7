//! Tracing a view: per pixel, the centre ray and, where the image has an edge, rays through
//! fixed antialiasing offsets, each to the first front face (or a nearer luminaire opening),
//! averaged.
//!
//! Input: a [`Camera`], the [`Surfaces`], the [`Openings`] and the sample count. Output: per
//! pixel (row 0 at the top) the mean luminance RGB over its rays (a ray that meets nothing counts
//! as 0; which rays: [`trace`]), the mean illuminance of the surface points its rays hit (NaN when none hit), and, when
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
use crate::scene::luma;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// One pixel's values.
#[derive(Debug, Clone, Copy)]
pub struct Pixel {
    pub luminance: [f32; 3],
    pub illuminance: f32,
    pub display: [u8; 3],
}

/// Relative luminance step between neighbouring centre rays above which a pixel takes its
/// antialiasing rays.
const CONTRAST: f64 = 0.02;

/// What one ray sees.
#[derive(Debug, Clone, Copy)]
struct Sample {
    /// What it hit: a primitive's index, an opening's (with the top bit set), or `u32::MAX`.
    what: u32,
    luminance: DVec3,
    /// Illuminance of the surface hit (NaN for none).
    illuminance: f64,
    /// Display colour, sRGB-encoded (0 when not asked).
    display: DVec3,
}

/// Trace every pixel of `camera`'s image; `display`: also the display colour.
///
/// With one sample a pixel is its centre ray. With more, every pixel's centre ray is traced
/// first; a pixel whose centre sees something else than one of its four neighbours' (another
/// primitive, an opening, nothing) or a luminance differing by more than 2 % takes the fixed
/// offsets' rays and their mean; the others keep their centre ray (within a primitive the
/// values are smooth, and the centre is the mean of a linear variation over the pixel). Both
/// passes depend on the rays alone, so the image does not depend on the thread count.
pub(crate) fn trace(
    camera: &Camera,
    surfaces: &Surfaces,
    openings: &Openings,
    samples: u32,
    display: bool,
    epsilon: f64,
) -> Vec<Pixel> {
    let (w, h) = (camera.width as usize, camera.height as usize);
    let ray = |p: DVec2| sample(camera, surfaces, openings, p, display, epsilon);
    let centres: Vec<Sample> = (0..h)
        .into_par_iter()
        .flat_map_iter(|row| {
            (0..w).map(move |col| ray(DVec2::new(col as f64 + 0.5, row as f64 + 0.5)))
        })
        .collect();
    if samples <= 1 {
        return centres.iter().map(|s| pixel(&[*s])).collect();
    }
    let offsets = sample_offsets(samples);
    let centres = &centres;
    let offsets = &offsets;
    (0..h)
        .into_par_iter()
        .flat_map_iter(|row| {
            (0..w).map(move |col| {
                let c = centres[row * w + col];
                let differs = |r: usize, k: usize| {
                    let n = centres[r * w + k];
                    let (a, b) = (luma(c.luminance), luma(n.luminance));
                    n.what != c.what || (a - b).abs() > CONTRAST * a.max(b)
                };
                let edge = (row > 0 && differs(row - 1, col))
                    || (row + 1 < h && differs(row + 1, col))
                    || (col > 0 && differs(row, col - 1))
                    || (col + 1 < w && differs(row, col + 1));
                if !edge {
                    return pixel(&[c]);
                }
                let centre = DVec2::new(col as f64 + 0.5, row as f64 + 0.5);
                let rays: Vec<Sample> = offsets.iter().map(|&o| ray(centre + o)).collect();
                pixel(&rays)
            })
        })
        .collect()
}

/// The mean of a pixel's rays: luminance over all (a miss counts 0), illuminance over those
/// that hit a surface, encoded display colours over all.
fn pixel(rays: &[Sample]) -> Pixel {
    let n = rays.len() as f64;
    let l = rays.iter().map(|s| s.luminance).sum::<DVec3>() / n;
    let hits: Vec<f64> = (rays.iter())
        .map(|s| s.illuminance)
        .filter(|e| !e.is_nan())
        .collect();
    let shown = rays.iter().map(|s| s.display).sum::<DVec3>() / n;
    Pixel {
        luminance: [l.x as f32, l.y as f32, l.z as f32],
        illuminance: match hits.is_empty() {
            true => f32::NAN,
            false => (hits.iter().sum::<f64>() / hits.len() as f64) as f32,
        },
        display: shown.to_array().map(|c| (c * 255.0).round() as u8),
    }
}

/// What the ray through image point `p` sees.
fn sample(
    camera: &Camera,
    surfaces: &Surfaces,
    openings: &Openings,
    p: DVec2,
    display: bool,
    epsilon: f64,
) -> Sample {
    let dir = camera.direction(p);
    let origin = camera.origin(dir);
    let hit = surfaces.hit(origin, dir);
    let reach = hit.map_or(f64::INFINITY, |h| h.distance + epsilon);
    let lamp = match openings.is_empty() {
        true => None,
        false => openings.seen(origin, dir, reach),
    };
    let (what, luminance) = match (lamp, &hit) {
        (Some((_, lum, k)), _) => (k as u32 | 1 << 31, lum),
        (None, Some(h)) => (h.primitive as u32, surfaces.luminance(h)),
        (None, None) => (u32::MAX, DVec3::ZERO),
    };
    Sample {
        what,
        luminance,
        illuminance: hit.map_or(f64::NAN, |h| surfaces.illuminance(&h)),
        display: match display {
            true => {
                let reach = hit.map_or(f64::INFINITY, |h| h.distance);
                match (surfaces.shown_display(origin, dir, reach), &hit) {
                    (Some(c), _) => c.map(srgb_encode),
                    (None, Some(h)) => surfaces.display(h).map(srgb_encode),
                    (None, None) => DVec3::ZERO,
                }
            }
            false => DVec3::ZERO,
        },
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
pub(crate) fn inside_solid(surfaces: &Surfaces, eye: DVec3) -> bool {
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
