//! Direct light from `KHR_lights_punctual` lights.
//!
//! - At a receiver point: E = I(ω)·cos ξ / d² with one shadow ray (exact; docs/ANALYTIC.md §1);
//!   directional lights give E⊥·cos ξ when a ray towards the light escapes the scene.
//! - Into a patch (the flux the radiosity solution reflects): ∫ I(ω) dω over the solid angle the
//!   patch subtends, times its visible fraction. For a point light this is I·Ω, exact (Van
//!   Oosterom–Strackee); for a spot the cone's falloff is integrated by adaptive subdivision of the
//!   patch. Summed over a closed room the patch fluxes give back the light's flux exactly.
//!
//! Spot falloff is the KHR_lights_punctual reference: a = clamp((cos θ − cos θₒ)·s)², with
//! s = 1/max(0.001, cos θᵢ − cos θₒ); its flux is 2π·I·[(1 − cₒ − w) + w/3], w = 1/s.

use super::flux::{self, Radiator, Spread};
use crate::geom::lambert;
use crate::scene::{Light, LightKind};
use crate::visibility::Occluder;
use glam::DVec3;
use std::f64::consts::PI;

/// Intensity (cd) of a point or spot light in unit direction `dir` (pointing away from it).
pub(crate) fn intensity(light: &Light, dir: DVec3) -> f64 {
    match light.kind {
        LightKind::Point => light.intensity,
        LightKind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let (scale, offset) = spot_ramp(inner_cone_angle, outer_cone_angle);
            let a = (light.direction.dot(dir) * scale + offset).clamp(0.0, 1.0);
            light.intensity * a * a
        }
        LightKind::Directional => 0.0,
    }
}

fn spot_ramp(inner: f64, outer: f64) -> (f64, f64) {
    let scale = 1.0 / (inner.cos() - outer.cos()).max(0.001);
    (scale, -outer.cos() * scale)
}

/// Luminous flux (lm, photometric) a point or spot light emits; `None` for directional lights,
/// whose flux is whatever the scene intercepts.
pub(crate) fn emitted_flux(light: &Light) -> Option<f64> {
    match light.kind {
        LightKind::Point => Some(4.0 * PI * light.intensity),
        LightKind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let (scale, _) = spot_ramp(inner_cone_angle, outer_cone_angle);
            let w = 1.0 / scale;
            let co = outer_cone_angle.cos();
            Some(2.0 * PI * light.intensity * ((1.0 - co - w).max(0.0) + w / 3.0))
        }
        LightKind::Directional => None,
    }
}

/// Illuminance (lx, photometric) at point `p` with unit normal `n`.
pub(crate) fn illuminance(light: &Light, occ: &Occluder, p: DVec3, n: DVec3) -> f64 {
    match light.kind {
        LightKind::Directional => {
            let to_light = -light.direction;
            let cos = n.dot(to_light);
            if cos > 0.0 && occ.escapes(p, n, to_light) {
                light.intensity * cos
            } else {
                0.0
            }
        }
        _ => {
            let d = light.position - p;
            let dist2 = d.length_squared();
            let cos = n.dot(d);
            if cos <= 0.0 || dist2 <= 0.0 {
                return 0.0;
            }
            let dist = dist2.sqrt();
            let i = intensity(light, -d / dist);
            if i <= 0.0 || !occ.clear(p, n, light.position, DVec3::ZERO) {
                return 0.0;
            }
            i * (cos / dist) / dist2
        }
    }
}

/// Flux (lm, photometric) the light sends onto the front of a triangle patch, and onto its back
/// (absorbed when the patch is single-sided): `(front, back)`; see [`flux::patch_flux`].
pub(crate) fn patch_flux(
    light: &Light,
    occ: &Occluder,
    corners: &[DVec3; 3],
    normal: DVec3,
    budget: f64,
) -> (f64, f64) {
    let facing = match light.kind {
        LightKind::Directional => normal.dot(-light.direction) > 0.0,
        _ => normal.dot(light.position - corners[0]) > 0.0,
    };
    flux::patch_flux(&Punctual(light), occ, corners, normal, facing, budget)
}

/// The flux below which [`patch_flux`] stops refining: a millionth of what the light sends into
/// a scene of this diagonal (m).
pub(crate) fn refinement_budget(light: &Light, diagonal: f64) -> f64 {
    1e-6 * emitted_flux(light).unwrap_or(light.intensity * diagonal * diagonal)
}

/// A KHR light as the flux integrator sees it.
struct Punctual<'a>(&'a Light);

impl Radiator for Punctual<'_> {
    fn intensity(&self, dir: DVec3) -> f64 {
        match self.0.kind {
            LightKind::Directional => self.0.intensity,
            _ => intensity(self.0, dir),
        }
    }

    fn spread(&self, t: &[DVec3; 3], _at: Option<&[f64; 3]>) -> Spread {
        let light = self.0;
        match light.kind {
            LightKind::Point | LightKind::Directional => Spread::Uniform(light.intensity),
            LightKind::Spot {
                outer_cone_angle, ..
            } => {
                let dirs = t.map(|v| (v - light.position).normalize_or_zero());
                if outside_cone(light.direction, outer_cone_angle, &dirs) {
                    Spread::Zero
                } else if dirs.iter().all(|&d| intensity(light, d) >= light.intensity) {
                    Spread::Uniform(light.intensity)
                } else {
                    let centre = (dirs[0] + dirs[1] + dirs[2]).normalize_or_zero();
                    let values = dirs.map(|d| intensity(light, d));
                    let lo = values.iter().fold(light.intensity, |a, b| a.min(*b));
                    Spread::Varies {
                        mean: intensity(light, centre),
                        error: light.intensity - lo,
                        hi: light.intensity,
                    }
                }
            }
        }
    }

    fn measure(&self, t: &[DVec3; 3], n: DVec3) -> f64 {
        match self.0.kind {
            LightKind::Directional => {
                let area = (t[1] - t[0]).cross(t[2] - t[0]).length() / 2.0;
                area * n.dot(-self.0.direction).abs()
            }
            _ => lambert::triangle_solid_angle(self.0.position, t),
        }
    }

    fn toward(&self, p: DVec3) -> DVec3 {
        (p - self.0.position).normalize_or_zero()
    }

    fn sees(&self, occ: &Occluder, p: DVec3, n: DVec3) -> bool {
        match self.0.kind {
            LightKind::Directional => occ.escapes(p, n, -self.0.direction),
            _ => occ.clear(p, n, self.0.position, DVec3::ZERO),
        }
    }
}

/// True when the spherical triangle with corner directions `dirs` lies wholly outside the cone
/// of half-angle `angle` around `axis`.
fn outside_cone(axis: DVec3, angle: f64, dirs: &[DVec3; 3]) -> bool {
    let angle_to = |d: DVec3| axis.dot(d).clamp(-1.0, 1.0).acos();
    if dirs.iter().any(|&d| angle_to(d) <= angle) {
        return false;
    }
    // The axis inside the triangle?
    let side = |a: DVec3, b: DVec3| a.cross(b).dot(axis);
    let s = [
        side(dirs[0], dirs[1]),
        side(dirs[1], dirs[2]),
        side(dirs[2], dirs[0]),
    ];
    let in_front = dirs.iter().any(|d| d.dot(axis) > 0.0);
    if in_front && (s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)) {
        return false;
    }
    // Closest approach of each edge's great-circle arc to the axis.
    for k in 0..3 {
        let (a, b) = (dirs[k], dirs[(k + 1) % 3]);
        let g = a.cross(b).normalize_or_zero();
        if g == DVec3::ZERO {
            continue;
        }
        let proj = axis - g * axis.dot(g);
        if proj.length_squared() == 0.0 {
            continue;
        }
        let within = a.cross(proj).dot(g) >= 0.0 && proj.cross(b).dot(g) >= 0.0;
        if within && axis.dot(g).abs().asin() <= angle && proj.dot(a + b) > 0.0 {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(inner: f64, outer: f64) -> Light {
        Light {
            name: None,
            source_path: String::new(),
            node: 0,
            kind: LightKind::Spot {
                inner_cone_angle: inner,
                outer_cone_angle: outer,
            },
            intensity: 1000.0,
            color: DVec3::ONE,
            position: DVec3::ZERO,
            direction: -DVec3::Y,
            range: None,
        }
    }

    #[test]
    fn spot_flux_matches_numerical_integral() {
        for &(inner, outer) in &[
            (0.0, 0.785),
            (0.15, 0.2),
            (0.5, std::f64::consts::FRAC_PI_2),
            (0.3, 0.3005),
        ] {
            let light = spot(inner, outer);
            let n = 200_000;
            let mut sum = 0.0;
            for k in 0..n {
                let theta = (k as f64 + 0.5) / n as f64 * PI / 2.0;
                let dir = DVec3::new(theta.sin(), -theta.cos(), 0.0);
                sum += intensity(&light, dir) * theta.sin() * (PI / 2.0 / n as f64);
            }
            let numeric = 2.0 * PI * sum;
            let closed = emitted_flux(&light).unwrap();
            assert!(
                (numeric - closed).abs() < 1e-6 * closed,
                "{inner} {outer}: {numeric} vs {closed}"
            );
        }
    }

    #[test]
    fn spot_flux_into_a_floor_of_patches_matches_emitted_flux() {
        // A floor of 0.25 m patches under the spot catches the whole cone.
        let light = spot(0.3, 0.6);
        let occ =
            crate::visibility::Occluder::build(&crate::scene::Scene::default(), Default::default());
        let mut total = 0.0;
        let h = 0.25;
        for i in 0..40 {
            for j in 0..40 {
                let p =
                    |a: usize, b: usize| DVec3::new(-5.0 + h * a as f64, -2.0, -5.0 + h * b as f64);
                for t in [
                    [p(i, j), p(i, j + 1), p(i + 1, j + 1)],
                    [p(i, j), p(i + 1, j + 1), p(i + 1, j)],
                ] {
                    total += patch_flux(&light, &occ, &t, DVec3::Y, 1e-9).0;
                }
            }
        }
        let want = emitted_flux(&light).unwrap();
        assert!((total - want).abs() < 1e-3 * want, "{total} vs {want}");
    }
}
