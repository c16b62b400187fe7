//! Receivers under covers too small to cut along ([`Contacts::uncut`]: a desk leg's foot on a
//! floor, a leg's top under a desk top). The covered spot stays part of the patches around it,
//! so a vertex lying there would read the inside of the leg (0 lx) and spread that over every
//! triangle around it (a 0.4 m desk-top triangle a third dark); its receiver steps out from
//! under the cover instead and reads the light beside it.
//!
//! Input: the surface's uncut covers on one side. Output: per vertex, the step (in the
//! surface's plane) that takes its receiver out from under them, or nothing.

use crate::contacts::Contacts;
use crate::scene::Scene;
use crate::visibility::boxes::BoxIndex;
use glam::{DMat3, DVec3};

/// One uncut cover's outline on the plane of the triangle it covers.
pub struct Under {
    /// Inward half-planes: x is under when m·x ≥ d for all three (see `contacts::Cover`; on the
    /// outline counts, or a point on the line between a foot's two triangles is under neither).
    edges: [(DVec3, f64); 3],
    /// The covered triangle's plane: unit normal and a point on it.
    normal: DVec3,
    at: DVec3,
    /// Distances below this are zero (m).
    eps: f64,
}

/// One side's uncut covers, indexed by their bounds (a floor under a thousand chairs' casters
/// asks a few of them per vertex, not all).
#[derive(Default)]
pub struct Covers {
    under: Vec<Under>,
    index: Option<BoxIndex>,
}

/// The uncut covers of surface `s` on its back (`back`) or front.
pub(crate) fn covers(scene: &Scene, contacts: &Contacts, s: usize, back: bool) -> Covers {
    let Some(uncut) = contacts.uncut.get(s) else {
        return Covers::default();
    };
    let surface = &scene.surfaces[s];
    let under: Vec<Under> = uncut
        .iter()
        .filter(|c| c.back == back)
        .filter_map(|c| {
            let t = surface.triangles.get(c.triangle as usize)?;
            let p = t.map(|v| surface.positions[v as usize]);
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            (normal != DVec3::ZERO).then_some(Under {
                edges: c.edges,
                normal,
                at: p[0],
                eps: contacts.tolerance,
            })
        })
        .collect();
    let index =
        (!under.is_empty()).then(|| BoxIndex::new(under.iter().map(Under::bounds).collect()));
    Covers { under, index }
}

impl Under {
    /// The outline's corners (where two edges' lines meet on the plane), boxed and padded.
    fn bounds(&self) -> (DVec3, DVec3) {
        let corner = |k: usize| {
            let (a, b) = (self.edges[k], self.edges[(k + 1) % 3]);
            let rows = DMat3::from_cols(a.0, b.0, self.normal).transpose();
            rows.inverse() * DVec3::new(a.1, b.1, self.normal.dot(self.at))
        };
        let c = [corner(0), corner(1), corner(2)];
        let pad = DVec3::splat(100.0 * self.eps);
        (
            c[0].min(c[1]).min(c[2]) - pad,
            c[0].max(c[1]).max(c[2]) + pad,
        )
    }

    /// How far `x` can go along the unit `d` before it leaves the outline, when `x` is under it.
    fn exit(&self, x: DVec3, d: DVec3) -> Option<f64> {
        let inside = self.edges.iter().all(|(m, c)| m.dot(x) - c >= -self.eps);
        if !inside || self.normal.dot(x - self.at).abs() > 10.0 * self.eps {
            return None;
        }
        (self.edges.iter())
            .filter(|(m, _)| m.dot(d) < 0.0)
            .map(|(m, c)| (m.dot(x) - c) / -m.dot(d))
            .min_by(f64::total_cmp)
    }
}

/// The step from `p` that takes a receiver at `p + nudge` out from under `under`, going along
/// `into` (the tangent direction into the faces around it; any tangent where that is zero), a
/// thousandth of `reach` past the outline; `None` when the point is under none of them or the
/// way out is longer than half of `reach` (the longest edge around the vertex).
pub(crate) fn step_out(
    covers: &Covers,
    p: DVec3,
    nudge: DVec3,
    into: DVec3,
    normal: DVec3,
    reach: f64,
) -> Option<DVec3> {
    let Some(index) = &covers.index else {
        return None;
    };
    let mut near = Vec::new();
    let mut first_exit = |x: DVec3, d: DVec3| {
        index.near(x, x, &mut near);
        near.iter()
            .find_map(|&k| covers.under[k as usize].exit(x, d))
    };
    let d = match into.normalize_or_zero() {
        DVec3::ZERO => normal.any_orthonormal_vector(),
        d => d,
    };
    let mut x = p + nudge;
    let mut moved = false;
    // Covers overlap (a leg's square foot is two triangles): leave each in turn.
    for _ in 0..8 {
        let Some(t) = first_exit(x, d) else {
            break;
        };
        x += d * (t + 1e-3 * reach);
        moved = true;
    }
    let step = x - p;
    let out = first_exit(x, d).is_none();
    (moved && out && step.length() <= reach / 2.0).then_some(step)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 cm square foot at the corner of a face in the plane y = 0 (normal +Y), as two
    /// triangles' outlines.
    fn foot() -> Covers {
        let edges = |c: [DVec3; 3]| -> [(DVec3, f64); 3] {
            std::array::from_fn(|k| {
                let (a, b) = (c[k], c[(k + 1) % 3]);
                let m = DVec3::Y.cross(b - a).normalize();
                (m, m.dot(a))
            })
        };
        let v = |x: f64, z: f64| DVec3::new(x, 0.0, z);
        let (a, b, c, d) = (v(0.0, 0.0), v(0.0, 0.05), v(0.05, 0.05), v(0.05, 0.0));
        let under: Vec<Under> = [[a, b, c], [a, c, d]]
            .into_iter()
            .map(|t| Under {
                edges: edges(t),
                normal: DVec3::Y,
                at: DVec3::ZERO,
                eps: 1e-9,
            })
            .collect();
        let bounds = under.iter().map(Under::bounds).collect();
        Covers {
            under,
            index: Some(BoxIndex::new(bounds)),
        }
    }

    #[test]
    fn a_corner_vertex_under_a_foot_steps_out_past_it_into_the_face() {
        let under = foot();
        let (lo, hi) = under.under[0].bounds();
        assert!(lo.distance(DVec3::ZERO) < 1e-6 && hi.distance(DVec3::new(0.05, 0.0, 0.05)) < 1e-6);
        // Both triangles' outlines wind so that m points inward.
        let inward = DVec3::new(1.0, 0.0, 1.0).normalize();
        let step = step_out(&under, DVec3::ZERO, inward * 1e-5, inward, DVec3::Y, 0.4)
            .expect("under the foot");
        let x = step;
        assert!(x.x > 0.05 && x.z > 0.05, "{x}: still under the foot");
        assert!(x.length() < 0.075, "{x}: further than needed");
        // A vertex beside the foot stays where it is.
        let beside = DVec3::new(0.2, 0.0, 0.2);
        assert!(step_out(&under, beside, inward * 1e-5, inward, DVec3::Y, 0.4).is_none());
        // Out of reach: a foot wider than half the patches around is not stepped out of.
        assert!(step_out(&under, DVec3::ZERO, inward * 1e-5, inward, DVec3::Y, 0.1).is_none());
    }
}
