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
    /// It varies: `mean` estimates its average over the piece, `lo` and `hi` bracket it (`hi` an
    /// upper bound, `lo` the smallest sample).
    Varies { mean: f64, lo: f64, hi: f64 },
}

/// A source the integrator can ask about directions and visibility.
pub trait Radiator {
    /// Intensity (cd) toward the unit direction `dir` (pointing away from the source).
    fn intensity(&self, dir: DVec3) -> f64;
    /// What the intensity does over the spherical triangle spanned by the piece `t` (world points).
    fn spread(&self, t: &[DVec3; 3]) -> Spread;
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

/// The spread of a tabulated distribution over a piece: `dirs` its unit corner directions (from
/// the source), `intensity` the distribution, `bound` an upper bound of the intensity over a
/// widened piece (used when the piece is larger than [`ANGULAR_RESOLUTION`]).
pub fn sampled_spread(
    dirs: &[DVec3; 3],
    intensity: impl Fn(DVec3) -> f64,
    bound: impl FnOnce(f64) -> f64,
) -> Spread {
    let centre = (dirs[0] + dirs[1] + dirs[2]).normalize_or_zero();
    let size = dirs
        .iter()
        .map(|d| d.dot(centre).clamp(-1.0, 1.0).acos())
        .fold(0.0, f64::max);
    let values = [
        intensity(dirs[0]),
        intensity(dirs[1]),
        intensity(dirs[2]),
        intensity(centre),
    ];
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(*v), b.max(*v)));
    let flat = hi > 0.0 && hi - lo <= SMOOTH * hi;
    let mean = values.iter().sum::<f64>() / 4.0;
    if size > ANGULAR_RESOLUTION {
        // A large piece is taken as uniform only when its samples agree and the band bound
        // rules out a peak between them (a narrow beam inside the piece).
        let b = bound(size);
        return if b <= 0.0 {
            Spread::Zero
        } else if flat && b <= hi * (1.0 + 4.0 * SMOOTH) {
            Spread::Uniform(mean)
        } else {
            Spread::Varies {
                mean,
                lo,
                hi: b.max(hi),
            }
        };
    }
    if hi <= 0.0 {
        Spread::Zero
    } else if flat {
        Spread::Uniform(mean)
    } else {
        Spread::Varies { mean, lo, hi }
    }
}

/// Upper bounds of a distribution's intensity per 1° band of γ (angle from the nadir, photometric
/// −Z), sampled every 0.25° in γ and 1° in C, each band also covering its neighbours' edges.
pub struct GammaBounds(Vec<f64>);

impl GammaBounds {
    pub fn new(intensity: impl Fn(DVec3) -> f64) -> Self {
        let mut max = vec![0.0f64; 180];
        for ig in 0..=720 {
            let g = (ig as f64 / 4.0).to_radians();
            let band = (ig / 4).min(179);
            for ic in 0..360 {
                let c = (ic as f64).to_radians();
                let i = intensity(DVec3::new(g.sin() * c.cos(), g.sin() * c.sin(), -g.cos()));
                max[band] = max[band].max(i);
                if ig % 4 == 0 && band > 0 {
                    max[band - 1] = max[band - 1].max(i);
                }
            }
        }
        GammaBounds(max)
    }

    /// Bound over directions within `size` (rad) of the unit `dirs`, γ measured from `nadir`.
    pub fn over(&self, nadir: DVec3, dirs: &[DVec3; 3], size: f64) -> f64 {
        let gammas = dirs.map(|d| d.dot(nadir).clamp(-1.0, 1.0).acos().to_degrees());
        let (lo, hi) = gammas
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), g| {
                (a.min(*g), b.max(*g))
            });
        let widen = size.to_degrees() + 1.0;
        let from = ((lo - widen).max(0.0).floor() as usize).min(179);
        let to = ((hi + widen).ceil() as usize).clamp(from + 1, 180);
        self.0[from..to].iter().fold(0.0, |a, b| a.max(*b))
    }
}

/// `(front, back)` flux into the triangle `corners` (unit normal `normal`); `facing` says whether
/// the source is in front of the patch.
pub fn patch_flux(
    r: &dyn Radiator,
    occ: &Occluder,
    corners: &[DVec3; 3],
    normal: DVec3,
    facing: bool,
    budget: f64,
) -> (f64, f64) {
    // Sample points pulled a hair inside the patch, so a vertex in a room corner is not tested
    // edge-on against the neighbouring wall.
    let c = (corners[0] + corners[1] + corners[2]) / 3.0;
    let t = corners.map(|v| v + (c - v) * 1e-4);
    let vis = t.map(|p| r.sees(occ, p, normal));
    let flux = integrate(r, occ, normal, &t, r.spread(&t), vis, 0, budget);
    if facing { (flux, 0.0) } else { (0.0, flux) }
}

#[allow(clippy::too_many_arguments)]
fn integrate(
    r: &dyn Radiator,
    occ: &Occluder,
    n: DVec3,
    t: &[DVec3; 3],
    spread: Spread,
    vis: [bool; 3],
    depth: u32,
    budget: f64,
) -> f64 {
    let measure = r.measure(t, n);
    let same = vis[0] == vis[1] && vis[1] == vis[2];
    let seen = vis.iter().filter(|v| **v).count() as f64 / 3.0;
    // The value if this piece is a leaf, and the largest error that could make.
    let (value, error) = match spread {
        Spread::Zero => return 0.0,
        Spread::Uniform(i) if same => return if vis[0] { i * measure } else { 0.0 },
        Spread::Uniform(i) => (i, i),
        Spread::Varies { mean, lo, hi } => (mean, if same { hi - lo } else { hi }),
    };
    if depth >= MAX_DEPTH || error * measure < budget {
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
    let spreads = pieces.map(|p| r.spread(&p));
    // Shadow rays only where some light can arrive, and only where the corners disagree: a
    // piece whose corners all see the source (or none does) is refined for its intensity alone,
    // its pieces inheriting that visibility.
    if spreads.iter().all(|s| *s == Spread::Zero) {
        return 0.0;
    }
    let mv = if same {
        [vis[0]; 3]
    } else {
        m.map(|p| r.sees(occ, p, n))
    };
    let vis = [
        [vis[0], mv[0], mv[2]],
        [mv[0], vis[1], mv[1]],
        [mv[2], mv[1], vis[2]],
        [mv[0], mv[1], mv[2]],
    ];
    (0..4)
        .map(|k| integrate(r, occ, n, &pieces[k], spreads[k], vis[k], depth + 1, budget))
        .sum()
}
