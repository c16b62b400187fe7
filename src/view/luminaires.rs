//! Luminaires seen directly: the luminous opening of each photometric luminaire (EXT_lights_ies,
//! LUXBAKE_luminaire) as a surface of its own in the view.
//!
//! Input: the output imported as a [`Scene`] (it round-trips its luminaires and profiles).
//! Output: along a ray, the nearest opening it crosses and the luminance shown there, by the
//! rule of [`crate::direct::opening`]. An opening without area (a point) is not seen, nor are
//! KHR punctual lights, which have no area.

use crate::direct::bounds::ProfileBounds;
use crate::direct::opening::{self, Opening};
use crate::scene::Scene;
use glam::DVec3;

pub struct Openings<'a> {
    openings: Vec<Opening<'a>>,
}

impl<'a> Openings<'a> {
    pub(crate) fn new(scene: &'a Scene) -> Self {
        // Each profile's intensity bounds are built once (they are a 721 × 360 sampling).
        let bounds = ProfileBounds::new(scene);
        Openings {
            openings: opening::all(scene, &bounds),
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.openings.is_empty()
    }

    /// The nearest opening along the unit `dir` from `origin` within `tmax`: (distance,
    /// luminance RGB in cd/m², which opening).
    pub(crate) fn seen(&self, origin: DVec3, dir: DVec3, tmax: f64) -> Option<(f64, DVec3, usize)> {
        let mut best: Option<(f64, DVec3, usize)> = None;
        for (k, o) in self.openings.iter().enumerate() {
            let to_local = o.source.world_from_photometric.transpose();
            let p = to_local * (origin - o.source.position);
            let d = to_local * dir;
            let Some(t) = o.entry(p, d) else { continue };
            if t > tmax || best.is_some_and(|b| b.0 <= t) {
                continue;
            }
            if o.projected_area(d) <= 0.0 {
                continue;
            }
            best = Some((t, o.luminance(dir), k));
        }
        best
    }
}
