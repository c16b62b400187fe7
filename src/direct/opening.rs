//! A photometric luminaire's luminous opening as a surface: where a line enters it, its area
//! seen from a direction, and the luminance it shows there.
//!
//! Input: the [`Scene`]'s luminaires with their [`Source`]s. Output: one [`Opening`] per
//! luminaire whose opening has area (`LUXBAKE_luminaire.opening`, else the profile's luminous
//! dimensions), in luminaire order.
//!
//! The rule: the opening sits in the photometric frame centred on the photometric centre:
//! length along photometric X (C0), width along Y (C90), height along Z. Height 0: a rectangle,
//! or an ellipse for a round opening, in the XY plane. Height > 0: a box, or an elliptic
//! cylinder, spanning ±height/2. Seen along unit direction d, it shows the luminance
//! L = I(−d) / A⊥(d) × colour, with I the profile's intensity toward the eye (the luminaire's
//! multiplier and maintenance factor included, as the bake uses it) and A⊥ its area projected on
//! a plane normal to d: for a box L·W|d_z| + W·H|d_x| + L·H|d_y|, for a cylinder
//! (π/4)·L·W|d_z| + 2H·√((L/2)²d_y² + (W/2)²d_x²). So the flux through the opening toward any
//! direction is the profile's.

use super::bounds::ProfileBounds;
use super::luminaire::Source;
use crate::photometry::OpeningShape;
use crate::scene::Scene;
use glam::DVec3;

/// One luminaire's opening.
pub struct Opening<'a> {
    /// Which luminaire (index into `Scene::luminaires`).
    pub luminaire: usize,
    pub source: Source<'a>,
    /// Half length (photometric X), half width (Y), half height (Z), m.
    pub half: DVec3,
    pub round: bool,
}

/// The openings with area of `scene`'s luminaires, in luminaire order.
pub(crate) fn all<'a>(scene: &'a Scene, bounds: &ProfileBounds) -> Vec<Opening<'a>> {
    (scene.luminaires.iter().enumerate())
        .zip(Source::all(scene, bounds))
        .filter_map(|((luminaire, l), source)| {
            let o = l
                .opening
                .unwrap_or_else(|| scene.profiles[l.profile].photometry.opening());
            let half = DVec3::new(o.length, o.width, o.height).max(DVec3::ZERO) / 2.0;
            (half.x > 0.0 && half.y > 0.0).then(|| Opening {
                luminaire,
                source,
                half,
                round: o.shape == OpeningShape::Round,
            })
        })
        .collect()
}

impl Opening<'_> {
    /// The luminance RGB (cd/m²) the opening shows to an eye looking along the unit world
    /// direction `dir` (from the eye toward the opening); zero where it has no projected area.
    pub(crate) fn luminance(&self, dir: DVec3) -> DVec3 {
        let d = self.source.world_from_photometric.transpose() * dir;
        let area = self.projected_area(d);
        match area > 0.0 {
            true => self.source.color * (self.source.intensity(-dir) / area),
            false => DVec3::ZERO,
        }
    }

    /// Where the ray p + t·d (photometric frame) first enters the opening, t ≥ 0.
    pub(crate) fn entry(&self, p: DVec3, d: DVec3) -> Option<f64> {
        let h = self.half;
        let inside_xy = |q: DVec3| {
            if self.round {
                (q.x / h.x).powi(2) + (q.y / h.y).powi(2) <= 1.0
            } else {
                q.x.abs() <= h.x && q.y.abs() <= h.y
            }
        };
        if h.z == 0.0 {
            if d.z == 0.0 {
                return None;
            }
            let t = -p.z / d.z;
            return (t >= 0.0 && inside_xy(p + d * t)).then_some(t);
        }
        // The caps (z = ±h.z), then the sides; the smallest t ≥ 0 that lands on the solid.
        let mut best = f64::INFINITY;
        if d.z != 0.0 {
            for z in [-h.z, h.z] {
                let t = (z - p.z) / d.z;
                if t >= 0.0 && t < best && inside_xy(p + d * t) {
                    best = t;
                }
            }
        }
        let within_z = |t: f64| (p.z + d.z * t).abs() <= h.z;
        if self.round {
            // (x/a)² + (y/b)² = 1.
            let (a, b) = (h.x, h.y);
            let qa = (d.x / a).powi(2) + (d.y / b).powi(2);
            let qb = 2.0 * (p.x * d.x / (a * a) + p.y * d.y / (b * b));
            let qc = (p.x / a).powi(2) + (p.y / b).powi(2) - 1.0;
            let disc = qb * qb - 4.0 * qa * qc;
            if qa > 0.0 && disc >= 0.0 {
                let t = (-qb - disc.sqrt()) / (2.0 * qa);
                if t >= 0.0 && t < best && within_z(t) {
                    best = t;
                }
            }
        } else {
            for (axis, half) in [(0, h.x), (1, h.y)] {
                let (pa, da) = (p[axis], d[axis]);
                if da == 0.0 {
                    continue;
                }
                for s in [-half, half] {
                    let t = (s - pa) / da;
                    let q = p + d * t;
                    let other = 1 - axis;
                    if t >= 0.0 && t < best && q[other].abs() <= h[other] && within_z(t) {
                        best = t;
                    }
                }
            }
        }
        best.is_finite().then_some(best)
    }

    /// The opening's area projected on a plane normal to the unit `d` (photometric frame), m².
    pub(crate) fn projected_area(&self, d: DVec3) -> f64 {
        let (l, w, h) = (2.0 * self.half.x, 2.0 * self.half.y, 2.0 * self.half.z);
        if self.round {
            let (a, b) = (self.half.x, self.half.y);
            std::f64::consts::PI * a * b * d.z.abs()
                + 2.0 * h * ((a * d.y).powi(2) + (b * d.x).powi(2)).sqrt()
        } else {
            l * w * d.z.abs() + w * h * d.x.abs() + l * h * d.y.abs()
        }
    }
}
