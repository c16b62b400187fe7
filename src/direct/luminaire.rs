//! Direct light from luminaires with measured distributions (IES LM-63, EULUMDAT), including the
//! near field of large luminous openings.
//!
//! Input: a scene [`Luminaire`] and its [`Photometry`]. Output: illuminance at receiver points
//! and flux into patches.
//!
//! A photometric file describes the far field: I(C, γ) as if all light came from one point. Close
//! to a large opening (a 1.5 m fluorescent 1.6 m above a desk) that is wrong, so the opening is
//! split into sub-sources, each emitting the same distribution scaled by its share of the area
//! (the usual near-field model). The split depends on the receiver: a rectangle of the opening
//! is halved along its longer side while that side is longer than [`NEAR_FIELD_RATIO`] × its
//! distance to the receiver. Relative to integrating the opening exactly, the midpoint rule this
//! amounts to errs by well under 0.5 % at that ratio (measured in the tests for a 1.5 × 0.2 m
//! opening at 0.3, 1 and 3 m). Each sub-source gets its own shadow ray, so extended luminaires cast
//! soft shadows. Round openings are treated as the square of equal area. Sub-sources lie in the
//! photometric XY plane through the luminaire's position.

use super::bounds::{AngleBounds, ProfileBounds};
use super::flux::{self, Radiator, Spread};
use super::groups::Known;
use super::penumbra;
use crate::geom::lambert;
use crate::photometry::{Opening, OpeningShape, Photometry};
use crate::scene::{Luminaire, Scene};
use crate::visibility::Occluder;
use glam::{DMat3, DVec3};
use std::f64::consts::PI;
use std::sync::Arc;

/// A rectangle of the opening is split while its longer side exceeds this fraction of its
/// distance to the receiver.
pub const NEAR_FIELD_RATIO: f64 = 0.1;

/// At most this many halvings per receiver (2¹⁰ = 1024 sub-sources).
const MAX_SPLITS: u32 = 10;

/// In a luminaire's soft shadow (some sub-sources seen, some hidden) the opening is split this
/// many times finer than [`NEAR_FIELD_RATIO`] where the shadow edge crosses it (`penumbra`):
/// one ray per sub-source makes the penumbra a staircase of as many steps as there are
/// sub-sources.
pub const PENUMBRA_REFINE: f64 = 4.0;

/// For the flux into a patch (the input of the inter-reflection, not a value users read) the split
/// may be coarser. Splits chosen per patch do not conserve the flux over a room (+2.1·10⁻³ for a
/// 1.5 m fitting in an empty box at 0.3, +8·10⁻⁵ at 0.1 for 2.6× the rays): `bake::direct::closure`
/// gives a closed source's patches their whole flux back.
const PATCH_RATIO: f64 = 0.3;
const PATCH_MAX_SPLITS: u32 = 6;

/// A patch whose bounding radius is below this fraction of its distance to a luminaire takes its
/// visibility from one ray at its centroid (per sub-source) rather than from its corners: a
/// shadow edge across it then moves at most its own flux, a 2 cm chair facet 3 m from the light.
const TINY_PATCH: f64 = 0.01;

/// A luminaire ready for evaluation.
pub struct Source<'a> {
    pub name: Option<String>,
    pub source_path: String,
    /// Index into `Scene::profiles`.
    pub profile: usize,
    pub photometry: &'a Photometry,
    /// Intensity scale (multiplier × colour luminance × maintenance factor).
    pub scale: f64,
    /// Relative RGB colour (luminance 1).
    pub color: DVec3,
    pub position: DVec3,
    pub world_from_photometric: DMat3,
    /// Half sizes of the (square-equivalent) opening along photometric X and Y (m).
    pub half: [f64; 2],
    /// Bounds of the unscaled distribution per band of γ, for refinement.
    bounds: Arc<AngleBounds>,
    /// Flux of the scaled distribution (lm).
    pub flux: f64,
}

impl<'a> Source<'a> {
    pub fn new(scene: &'a Scene, l: &'a Luminaire) -> Self {
        let photometry = &scene.profiles[l.profile].photometry;
        Self::with_bounds(
            scene,
            l,
            Arc::new(AngleBounds::new(|d| photometry.intensity(d))),
        )
    }

    /// `new` with the bounds of the luminaire's profile already built (they depend on the
    /// profile only; a 721 × 360 sampling each).
    fn with_bounds(scene: &'a Scene, l: &'a Luminaire, bounds: Arc<AngleBounds>) -> Self {
        let photometry = &scene.profiles[l.profile].photometry;
        let opening = l.opening.unwrap_or_else(|| photometry.opening());
        Source {
            name: l.name.clone(),
            source_path: l.source_path.clone(),
            profile: l.profile,
            photometry,
            scale: l.multiplier,
            color: l.color,
            position: l.position,
            world_from_photometric: l.world_from_photometric,
            half: half_sizes(&opening),
            bounds,
            flux: l.multiplier * photometry.flux(),
        }
    }

    /// All luminaires of a scene (each profile's bounds from `bounds`).
    pub fn all(scene: &'a Scene, bounds: &ProfileBounds) -> Vec<Source<'a>> {
        scene
            .luminaires
            .iter()
            .map(|l| Source::with_bounds(scene, l, bounds.get(l.profile)))
            .collect()
    }

    /// Intensity (cd) toward the world direction `dir` (unit, away from the luminaire).
    pub fn intensity(&self, dir: DVec3) -> f64 {
        self.scale
            * self
                .photometry
                .intensity(self.world_from_photometric.transpose() * dir)
    }

    /// The corners of the opening (world, m): every sub-source lies in this rectangle.
    pub(crate) fn opening_corners(&self) -> [DVec3; 4] {
        let [x, y] = self.half;
        [(-x, -y), (x, -y), (x, y), (-x, y)]
            .map(|(a, b)| self.position + self.world_from_photometric * DVec3::new(a, b, 0.0))
    }

    /// The sub-sources seen from `p`: world position and share of the output.
    pub(crate) fn split(&self, p: DVec3) -> Vec<(DVec3, f64)> {
        let mut out = Vec::new();
        self.each_sub(p, (NEAR_FIELD_RATIO, MAX_SPLITS), &mut |q, share| {
            out.push((q, share))
        });
        out
    }

    /// Call `f(position, share)` for each sub-source seen from `p` under `rule` (ratio, most
    /// halvings), without allocating: most luminaires are far enough to stay whole, and this
    /// runs for every receiver and luminaire.
    fn each_sub(&self, p: DVec3, rule: (f64, u32), f: &mut dyn FnMut(DVec3, f64)) {
        let whole = Rect {
            centre: [0.0, 0.0],
            half: self.half,
            share: 1.0,
            depth: 0,
        };
        self.split_rect(whole, p, rule, f);
    }

    /// [`Source::each_sub`] within the piece `r` of the opening: the piece whole when it is
    /// small enough seen from `p` (or `rule`'s halvings are spent), else its halves across its
    /// longer side.
    fn split_rect(&self, r: Rect, p: DVec3, rule: (f64, u32), out: &mut dyn FnMut(DVec3, f64)) {
        let Rect {
            centre,
            half,
            share,
            depth,
        } = r;
        let world =
            self.position + self.world_from_photometric * DVec3::new(centre[0], centre[1], 0.0);
        let longer = if half[0] >= half[1] { 0 } else { 1 };
        let side = 2.0 * half[longer];
        if depth >= rule.1 || side <= rule.0 * (p - world).length() {
            out(world, share);
            return;
        }
        let mut h = half;
        h[longer] /= 2.0;
        for sign in [-1.0, 1.0] {
            let mut c = centre;
            c[longer] += sign * h[longer];
            let piece = Rect {
                centre: c,
                half: h,
                share: share / 2.0,
                depth: depth + 1,
            };
            self.split_rect(piece, p, rule, out);
        }
    }

    /// Whether any light can go from the opening toward `p` (cheap bound on the distribution).
    fn reaches(&self, p: DVec3) -> bool {
        let d = p - self.position;
        let dist = d.length();
        if dist <= 0.0 {
            return false;
        }
        let radius = (self.half[0].hypot(self.half[1]) / dist).min(1.0).asin();
        let dir = d / dist;
        self.bounds
            .lights_cone(&self.world_from_photometric, dir, radius)
    }

    /// Illuminance (lx, photometric) at point `p` with unit normal `n`.
    pub fn illuminance(&self, occ: &Occluder, p: DVec3, n: DVec3) -> f64 {
        let mut e = [0.0];
        self.illuminance_faces(occ, p, &[n], &mut e, (Known::Trace, true));
        e[0]
    }

    /// Illuminance (lx, photometric) at `p` on planes with the unit `normals` (a probe's faces),
    /// added to `out`: the sub-sources, their intensities and each one's shadow ray are shared
    /// (the ray leaves `p` off the first plane that faces the sub-source). `known`: what a
    /// group's query already proved of its visibility ([`super::groups`]). With `soft`, when
    /// some sub-sources are seen and others hidden, or a corner of the opening disagrees
    /// with them all, `p` lies in the luminaire's soft shadow: the opening is integrated again,
    /// down to [`PENUMBRA_REFINE`] times finer where the shadow edge crosses it, so the penumbra
    /// is not a staircase of a few steps. Without, one ray per sub-source (an estimate: meshing's
    /// judgement of where light changes).
    pub(crate) fn illuminance_faces(
        &self,
        occ: &Occluder,
        p: DVec3,
        normals: &[DVec3],
        out: &mut [f64],
        (known, soft): (Known, bool),
    ) {
        if known == Known::Hidden || !self.reaches(p) {
            return;
        }
        if !soft || known != Known::Trace {
            self.sum_subs(occ, p, normals, out, known);
            return;
        }
        // Planes in groups of up to eight, summed on the stack (a probe has six).
        for (normals, out) in normals.chunks(8).zip(out.chunks_mut(8)) {
            let mut e = [0.0; 8];
            let (seen, hidden) = self.sum_subs(occ, p, normals, &mut e, known);
            if (seen && hidden)
                || ((seen || hidden) && self.corners_disagree(occ, p, normals, seen))
            {
                e = [0.0; 8];
                self.soft_shadow(occ, p, normals, &mut e);
            }
            for (o, e) in out.iter_mut().zip(e) {
                *o += e;
            }
        }
    }

    /// Whether, for an opening of some size, a ray to one of its four corners (that lights
    /// one of the planes) says other than the sub-sources, all of which were `seen` or all
    /// hidden: a shadow edge parallel to a row of sub-sources (the top of a partition under a
    /// long fitting) crosses the opening without separating them, and an opening too small to
    /// split (a 15 cm downlight 2.5 m away, one sub-source) still casts a penumbra: a door
    /// jamb's shadow through it is some 10 cm wide on the floor beyond, not a hard line.
    fn corners_disagree(&self, occ: &Occluder, p: DVec3, normals: &[DVec3], seen: bool) -> bool {
        if self.half[0].max(self.half[1]) <= 0.0 {
            return false;
        }
        // All four corners: a straight edge across the opening leaves corners on both sides of
        // it, so one of them disagrees with the rest. Two opposite corners missed an edge that
        // cuts off one of the other two: 3.7 lx read as 0 of 12 lx beside a door jamb.
        self.opening_corners()
            .iter()
            .any(|&q| sight(occ, p, normals, q).is_some_and(|clear| clear != seen))
    }

    /// [`Source::illuminance_faces`] for a receiver in the luminaire's soft shadow: the opening
    /// integrated over what `p` sees of it (`penumbra`), added to `out`.
    fn soft_shadow(&self, occ: &Occluder, p: DVec3, normals: &[DVec3], out: &mut [f64]) {
        let ratios = penumbra::Ratios {
            coarse: NEAR_FIELD_RATIO,
            fine: NEAR_FIELD_RATIO / PENUMBRA_REFINE,
        };
        let world =
            |c: [f64; 2]| self.position + self.world_from_photometric * DVec3::new(c[0], c[1], 0.0);
        let mut sees = |q: DVec3| sight(occ, p, normals, q).unwrap_or(false);
        let mut emit = |q: DVec3, share: f64, fraction: f64| {
            let d = q - p;
            let dist2 = d.length_squared();
            if fraction > 0.0 && dist2 > 0.0 {
                let i = self.intensity(-d / dist2.sqrt()) * share * fraction;
                add_planes(normals, d, i, out);
            }
        };
        penumbra::integrate(self.half, p, &ratios, &world, &mut sees, &mut emit);
    }

    /// One ray per near-field sub-source, the light added to `out`; returns whether some
    /// sub-source was seen and whether some was hidden (of those that light a plane).
    fn sum_subs(
        &self,
        occ: &Occluder,
        p: DVec3,
        normals: &[DVec3],
        out: &mut [f64],
        known: Known,
    ) -> (bool, bool) {
        let (mut seen, mut hidden) = (false, false);
        self.each_sub(p, (NEAR_FIELD_RATIO, MAX_SPLITS), &mut |q, share| {
            let d = q - p;
            let dist2 = d.length_squared();
            let Some(first) = normals.iter().position(|n| n.dot(d) > 0.0) else {
                return;
            };
            if dist2 <= 0.0 {
                return;
            }
            let i = self.intensity(-d / dist2.sqrt()) * share;
            if i <= 0.0 {
                return;
            }
            if known == Known::Trace && !occ.clear(p, normals[first], q, DVec3::ZERO) {
                hidden = true;
                return;
            }
            seen = true;
            add_planes(normals, d, i, out);
        });
        (seen, hidden)
    }

    /// Whether `other` emits the same distribution the same way (profile, frame, colour): then a
    /// group of both has one intensity range per direction ([`super::cut`]).
    pub(crate) fn same_kind(&self, other: &Source) -> bool {
        self.profile == other.profile
            && std::ptr::eq(self.photometry, other.photometry)
            && self.world_from_photometric == other.world_from_photometric
            && self.color == other.color
    }

    /// Lower and upper bounds of the unscaled distribution over the world directions within
    /// `radius` (rad) of the unit `dir` (away from the luminaire).
    pub(crate) fn profile_range(&self, dir: DVec3, radius: f64) -> (f64, f64) {
        self.bounds
            .range_over_cone(&self.world_from_photometric, dir, radius)
    }

    /// What [`Source::illuminance_faces`] multiplies the unscaled intensity by, summed over the
    /// same sub-sources, for a luminaire known seen: scale × share × cos / d² per plane, added to
    /// `out`. The illuminance lies between it times the least and the greatest intensity toward `p`.
    pub(crate) fn geometry_faces(&self, p: DVec3, normals: &[DVec3], out: &mut [f64]) {
        self.each_sub(p, (NEAR_FIELD_RATIO, MAX_SPLITS), &mut |q, share| {
            let d = q - p;
            let dist2 = d.length_squared();
            if dist2 <= 0.0 {
                return;
            }
            let w = self.scale * share / (dist2 * dist2.sqrt());
            for (e, n) in out.iter_mut().zip(normals) {
                let cos = n.dot(d);
                if cos > 0.0 {
                    *e += w * cos;
                }
            }
        });
    }

    /// What [`Source::patch_flux`] multiplies the unscaled intensity by for a patch known to see
    /// it: scale × share × the patch's solid angle from each sub-source (sr), summed.
    pub(crate) fn geometry_patch(&self, corners: &[DVec3; 3]) -> f64 {
        let c = (corners[0] + corners[1] + corners[2]) / 3.0;
        let mut g = 0.0;
        self.each_sub(c, (PATCH_RATIO, PATCH_MAX_SPLITS), &mut |q, share| {
            g += share * lambert::triangle_solid_angle(q, corners);
        });
        self.scale * g
    }

    /// `(front, back)` flux (lm) into a triangle patch, split as seen from its centroid.
    pub(crate) fn patch_flux(
        &self,
        occ: &Occluder,
        corners: &[DVec3; 3],
        normal: DVec3,
        budget: f64,
        known: Known,
    ) -> (f64, f64) {
        if known == Known::Hidden {
            return (0.0, 0.0);
        }
        let c = (corners[0] + corners[1] + corners[2]) / 3.0;
        let size = corners
            .iter()
            .map(|v| (*v - c).length())
            .fold(0.0, f64::max);
        let near = (c - self.position).length() - size;
        if near > 0.0 && size < 0.1 * near && !self.reaches(c) {
            return (0.0, 0.0);
        }
        // A patch tiny against its distance (tessellated clutter across the room) takes one
        // shadow ray per sub-source, from its centroid, instead of one per corner.
        let tiny = near > 0.0 && size < TINY_PATCH * near;
        let mut total = (0.0, 0.0);
        self.each_sub(c, (PATCH_RATIO, PATCH_MAX_SPLITS), &mut |q, share| {
            let seen = match known {
                Known::Seen => Some(true),
                _ if tiny => Some(occ.clear(c, normal, q, DVec3::ZERO)),
                _ => None,
            };
            let sub = SubSource {
                source: self,
                position: q,
                share,
                seen,
            };
            let facing = normal.dot(q - corners[0]) > 0.0;
            let (f, b) = flux::patch_flux(&sub, occ, corners, normal, facing, budget * share);
            total.0 += f;
            total.1 += b;
        });
        total
    }

    /// The flux below which patch-flux integration stops refining (lm).
    pub(crate) fn budget(&self) -> f64 {
        1e-6 * self.flux
    }
}

/// A piece of a luminaire's opening while it is split into sub-sources: its centre and half
/// size (photometric x and y, m), its share of the output, and how many halvings made it.
#[derive(Clone, Copy)]
struct Rect {
    centre: [f64; 2],
    half: [f64; 2],
    share: f64,
    depth: u32,
}

/// One sub-source of an opening.
struct SubSource<'s, 'a> {
    source: &'s Source<'a>,
    position: DVec3,
    share: f64,
    /// Its visibility from the whole patch, when already known (a group's query proved the
    /// luminaire seen, or the patch is tiny and its centroid's ray decided).
    seen: Option<bool>,
}

impl Radiator for SubSource<'_, '_> {
    fn intensity(&self, dir: DVec3) -> f64 {
        self.share * self.source.intensity(dir)
    }

    fn samples_corners(&self) -> bool {
        true
    }

    fn spread(&self, t: &[DVec3; 3], at: Option<&[f64; 3]>) -> Spread {
        let dirs = t.map(|v| (v - self.position).normalize_or_zero());
        let s = self.source;
        flux::sampled_spread(
            &dirs,
            at,
            |d| self.intensity(d),
            |enough| {
                let scale = self.share * s.scale;
                scale
                    * s.bounds.over_triangle(
                        &s.world_from_photometric,
                        &dirs,
                        enough / scale.max(1e-300),
                    )
            },
        )
    }

    fn measure(&self, t: &[DVec3; 3], _n: DVec3) -> f64 {
        lambert::triangle_solid_angle(self.position, t)
    }

    fn toward(&self, p: DVec3) -> DVec3 {
        (p - self.position).normalize_or_zero()
    }

    fn sees(&self, occ: &Occluder, p: DVec3, n: DVec3) -> bool {
        self.seen
            .unwrap_or_else(|| occ.clear(p, n, self.position, DVec3::ZERO))
    }
}

/// The light of intensity `i` (cd) from `d` away (m) on each plane facing it, added to `out`.
fn add_planes(normals: &[DVec3], d: DVec3, i: f64, out: &mut [f64]) {
    let dist2 = d.length_squared();
    let dist = dist2.sqrt();
    for (e, n) in out.iter_mut().zip(normals) {
        let cos = n.dot(d);
        if cos > 0.0 {
            *e += i * (cos / dist) / dist2;
        }
    }
}

/// Whether the segment from `p` to `q` is clear, the ray leaving `p` off the first of `normals`
/// that faces `q`; `None` when none does.
fn sight(occ: &Occluder, p: DVec3, normals: &[DVec3], q: DVec3) -> Option<bool> {
    let first = normals.iter().position(|n| n.dot(q - p) > 0.0)?;
    Some(occ.clear(p, normals[first], q, DVec3::ZERO))
}

/// Half sizes along photometric X and Y; a round opening becomes the square of equal area.
fn half_sizes(o: &Opening) -> [f64; 2] {
    match o.shape {
        OpeningShape::Rectangular => [o.length.max(0.0) / 2.0, o.width.max(0.0) / 2.0],
        OpeningShape::Round => {
            let (a, b) = (o.length.max(0.0), o.width.max(0.0));
            let side = (PI * a * b / 4.0).sqrt();
            [side / 2.0, side / 2.0]
        }
    }
}
