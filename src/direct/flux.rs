//! Flux a point-like source sends into a triangle patch: ∫ I(ω)·V(ω) dω over the patch's solid
//! angle, integrated adaptively.
//!
//! Input: a [`Radiator`] (a KHR light, or one sub-source of a luminaire), the occluder, the
//! patch. Output: `(front, back)` flux (lm): what reaches the patch's front, and what lands on its
//! back (absorbed by a single-sided patch).
//!
//! A piece of the patch whose corners agree on visibility and over which the radiator says its
//! intensity is uniform is exact (I·Ω, Van Oosterom–Strackee). Other pieces are split in four,
//! down to a depth limit or until the piece could carry less than `budget`; so beam edges, narrow
//! beams and shadow edges crossing a patch are followed, and summed over a closed room the patch
//! fluxes give back the source's flux. Shadow rays are spent only where the corners of a piece
//! disagree: a piece whose corners all see the source is taken to see it wholly.

use crate::visibility::Occluder;
use glam::DVec3;

/// How a radiator's intensity behaves over a piece of its sphere of directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Spread {
    /// No light goes there.
    Zero,
    /// This intensity everywhere in the piece (cd, or lx for a directional light).
    Uniform(f64),
    /// It varies: `mean` estimates its average over the piece, within about `error`; `hi` bounds
    /// it from above.
    Varies { mean: f64, error: f64, hi: f64 },
}

/// A source the integrator can ask about directions and visibility.
pub trait Radiator {
    /// Intensity (cd) toward the unit direction `dir` (pointing away from the source).
    fn intensity(&self, dir: DVec3) -> f64;
    /// What the intensity does over the spherical triangle spanned by the piece `t` (world points).
    /// `at`, when given, holds the intensities toward the corners (`intensity(toward(t[k]))`,
    /// known from the parent piece), so they are not looked up again.
    fn spread(&self, t: &[DVec3; 3], at: Option<&[f64; 3]>) -> Spread;
    /// Whether [`Radiator::spread`] samples the intensity at the corners (then refinement hands
    /// the corner values down to the pieces).
    fn samples_corners(&self) -> bool {
        false
    }
    /// The geometric measure of the piece: its solid angle seen from the source (sr), or, for a
    /// directional light, its area projected across the beam (m²).
    fn measure(&self, t: &[DVec3; 3], n: DVec3) -> f64;
    /// The direction toward the piece's centre (for sampling a varying intensity).
    fn toward(&self, p: DVec3) -> DVec3;
    /// Does point `p` (surface normal `n`) see the source?
    fn sees(&self, occ: &Occluder, p: DVec3, n: DVec3) -> bool;
}

const MAX_DEPTH: u32 = 7;

/// Angular radius (rad) below which a piece's intensity is judged from its corners and centre.
pub const ANGULAR_RESOLUTION: f64 = 0.04;

/// Relative spread of a piece's sampled intensities below which it counts as uniform.
const SMOOTH: f64 = 2e-3;

/// A large piece can hide a narrow beam between its samples only if the bound over its
/// directions exceeds the samples by more than this factor (beams stand far above their
/// surroundings: a spot's peak is tens of times its spill).
const HIDDEN_PEAK: f64 = 2.0;

/// Refinement stops when a piece's possible error is below this share of the whole patch's.
const PATCH_SHARE: f64 = 3e-3;

/// A piece is accurate enough when its estimated error is this fraction of its value.
const RELATIVE: f64 = 3e-3;

/// The spread of a tabulated distribution over a piece: `dirs` its unit corner directions (from
/// the source), `intensity` the distribution, `bound(enough)` an upper bound of the intensity
/// over the piece (used when the piece is larger than [`ANGULAR_RESOLUTION`]; it may stop
/// refining once it is below `enough`).
pub(crate) fn sampled_spread(
    dirs: &[DVec3; 3],
    at: Option<&[f64; 3]>,
    intensity: impl Fn(DVec3) -> f64,
    bound: impl FnOnce(f64) -> f64,
) -> Spread {
    let centre = (dirs[0] + dirs[1] + dirs[2]).normalize_or_zero();
    let min_cos = dirs.iter().map(|d| d.dot(centre)).fold(1.0, f64::min);
    let c = match at {
        Some(at) => *at,
        None => dirs.map(&intensity),
    };
    let values = [c[0], c[1], c[2], intensity(centre)];
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(*v), b.max(*v)));
    // The mean of a smooth distribution over the piece (corners 1/12 each, centre 3/4: exact for
    // a quadratic), and its error: corners and centre agree for a linear variation, so their
    // disagreement bounds what the estimate misses.
    let corners = (values[0] + values[1] + values[2]) / 3.0;
    let mean = 0.25 * corners + 0.75 * values[3];
    let smooth = Spread::Varies {
        mean,
        error: (corners - values[3]).abs(),
        hi,
    };
    if min_cos < ANGULAR_RESOLUTION.cos() {
        // A large piece: its samples speak for it only when the (γ, C) bound rules out a peak
        // between them (a narrow beam inside the piece).
        let b = bound(hi * HIDDEN_PEAK);
        return if b <= 0.0 {
            Spread::Zero
        } else if hi > 0.0 && b <= hi * HIDDEN_PEAK {
            if hi - lo <= SMOOTH * hi {
                Spread::Uniform(mean)
            } else {
                smooth
            }
        } else {
            Spread::Varies {
                mean,
                error: b - lo,
                hi: b.max(hi),
            }
        };
    }
    if hi <= 0.0 {
        Spread::Zero
    } else if hi - lo <= SMOOTH * hi {
        Spread::Uniform(mean)
    } else {
        smooth
    }
}

/// `(front, back)` flux into the triangle `corners` (unit normal `normal`); `facing` says whether
/// the source is in front of the patch.
pub(crate) fn patch_flux(
    r: &dyn Radiator,
    occ: &Occluder,
    corners: &[DVec3; 3],
    normal: DVec3,
    facing: bool,
    budget: f64,
) -> (f64, f64) {
    // Shadow rays start from points pulled a hair inside the patch, so a vertex in a room
    // corner is not tested edge-on against the neighbouring wall; the geometry (the measure of
    // each piece) stays the patch's own, so the patches of a closed room sum to the whole sphere.
    let c = (corners[0] + corners[1] + corners[2]) / 3.0;
    let t = *corners;
    let at = r
        .samples_corners()
        .then(|| t.map(|p| r.intensity(r.toward(p))));
    let spread = r.spread(&t, at.as_ref());
    // Pieces are refined until their possible error is below the source's budget or a small
    // share of what the whole patch could receive (a shadow edge across a patch is followed to a
    // few per mille of the patch's flux, not to the source's millionth).
    let top = match spread {
        Spread::Zero => return (0.0, 0.0),
        Spread::Uniform(i) => i,
        Spread::Varies { hi, .. } => hi,
    } * r.measure(&t, normal);
    let tolerance = budget.max(PATCH_SHARE * top);
    // Shadow rays only once light can arrive at all.
    let sees = |p: DVec3| r.sees(occ, p + (c - p) * 1e-4, normal);
    let vis = t.map(sees);
    let integration = Integration {
        r,
        sees: &sees,
        n: normal,
        budget: tolerance,
    };
    let flux = integration.integrate(&t, spread, at, vis, 0);
    if facing { (flux, 0.0) } else { (0.0, flux) }
}

/// What the integration of one patch's flux keeps while it refines: the radiator, whether a
/// point on the patch sees it, the patch's unit normal and the error budget (lm).
struct Integration<'a> {
    r: &'a dyn Radiator,
    sees: &'a dyn Fn(DVec3) -> bool,
    n: DVec3,
    budget: f64,
}

impl Integration<'_> {
    /// The flux into the piece `t` (its intensity `spread`, its corners' intensities `at` when
    /// the radiator samples them, and their visibility `vis`), `depth` splits deep: its four
    /// pieces summed until the possible error is below the budget or small beside the value.
    fn integrate(
        &self,
        t: &[DVec3; 3],
        spread: Spread,
        at: Option<[f64; 3]>,
        vis: [bool; 3],
        depth: u32,
    ) -> f64 {
        let (r, sees, n, budget) = (self.r, self.sees, self.n, self.budget);
        let measure = r.measure(t, n);
        let same = vis[0] == vis[1] && vis[1] == vis[2];
        let seen = vis.iter().filter(|v| **v).count() as f64 / 3.0;
        // The value if this piece is a leaf, and the largest error that could make.
        let (value, error) = match spread {
            Spread::Zero => return 0.0,
            Spread::Uniform(i) if same => return if vis[0] { i * measure } else { 0.0 },
            Spread::Uniform(i) => (i, i),
            Spread::Varies { mean, error, hi } => (mean, if same { error } else { hi }),
        };
        // Stop when the piece's possible error is negligible against the source (the budget) or
        // against the piece itself (relative accuracy; shadow edges get the full bound as error).
        if depth >= MAX_DEPTH || error * measure < budget || error <= RELATIVE * value {
            return value * measure * seen;
        }
        let m = [
            (t[0] + t[1]) * 0.5,
            (t[1] + t[2]) * 0.5,
            (t[2] + t[0]) * 0.5,
        ];
        let pieces = [
            [t[0], m[0], m[2]],
            [m[0], t[1], m[1]],
            [m[2], m[1], t[2]],
            [m[0], m[1], m[2]],
        ];
        // Corner intensities of the pieces: the parent's corners and the three midpoints.
        let ats = at.map(|a| {
            let am = m.map(|p| r.intensity(r.toward(p)));
            [
                [a[0], am[0], am[2]],
                [am[0], a[1], am[1]],
                [am[2], am[1], a[2]],
                [am[0], am[1], am[2]],
            ]
        });
        let spreads: [Spread; 4] =
            std::array::from_fn(|k| r.spread(&pieces[k], ats.as_ref().map(|a| &a[k])));
        // Shadow rays only where some light can arrive, and only where the corners disagree: a
        // piece whose corners all see the source (or none does) is refined for its intensity alone,
        // its pieces inheriting that visibility.
        if spreads.iter().all(|s| *s == Spread::Zero) {
            return 0.0;
        }
        let mv = if same { [vis[0]; 3] } else { m.map(sees) };
        let vis = [
            [vis[0], mv[0], mv[2]],
            [mv[0], vis[1], mv[1]],
            [mv[2], mv[1], vis[2]],
            [mv[0], mv[1], mv[2]],
        ];
        (0..4)
            .map(|k| {
                let at = ats.map(|a| a[k]);
                self.integrate(&pieces[k], spreads[k], at, vis[k], depth + 1)
            })
            .sum()
    }
}
