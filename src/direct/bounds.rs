//! Upper bounds of a photometric distribution over pieces of its sphere of directions, so the
//! flux integrator ([`super::flux`]) can tell a piece whose samples speak for it from one that
//! may hide a narrow beam between them.
//!
//! Input: a distribution I(direction) in its photometric frame (γ from the nadir −Z, C from +X
//! toward +Y). Output: [`AngleBounds`], a table of maxima on 1° × 10° (γ, C) cells answering
//! "at most how bright over this spherical triangle (or cone)" with two lookups per C sector;
//! [`ProfileBounds`] builds each profile's table once per bake, for every source and stage that
//! uses it. Invariant: a bound is never below the distribution anywhere in the piece, up to the
//! table's sampling (0.25° in γ, 1° in C), covered by margins of one step in γ and 1° in C
//! (see [`GAMMA_MARGIN`]). Beside the maxima, a table of minima on the same cells gives a lower
//! bound over a cone ([`AngleBounds::range_over_cone`], for the light cut, `super::cut`), exact
//! up to the same sampling.

use crate::scene::Scene;
use glam::{DMat3, DVec3};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Upper bounds of a distribution's intensity on cells of 1° in γ (angle from the nadir,
/// photometric −Z) by 10° in C (azimuth from photometric +X toward +Y), sampled every 0.25° in γ
/// and 1° in C, each cell also covering its neighbours' edges.
pub struct AngleBounds {
    /// `cells[k][b][s]`: the maximum over the γ bands `b .. b + 2^k` of C sector `s` (a sparse
    /// table: any band range is the union of two overlapping power-of-two runs).
    cells: Vec<Vec<[f64; 36]>>,
    /// `bands[k][b]`: the same over all C.
    bands: Vec<Vec<f64>>,
    /// `lit[k][b]`: every C sector of `cells[k][b]` is above zero, so any range of C in those
    /// bands holds some light ([`AngleBounds::lights_cone`] answers without finding its sectors).
    lit: Vec<Vec<bool>>,
    /// `low[k][b][s]` and `low_bands[k][b]`: the minima, as `cells` and `bands` hold the maxima.
    low: Vec<Vec<[f64; 36]>>,
    low_bands: Vec<Vec<f64>>,
}

impl AngleBounds {
    pub(crate) fn new(intensity: impl Fn(DVec3) -> f64 + Sync) -> Self {
        // The 721 × 360 samples in parallel (rows in order), then their maxima per cell.
        let rows: Vec<Vec<f64>> = (0..=720usize)
            .into_par_iter()
            .map(|ig| {
                let g = (ig as f64 / 4.0).to_radians();
                (0..360)
                    .map(|ic| {
                        let c = (ic as f64).to_radians();
                        intensity(DVec3::new(g.sin() * c.cos(), g.sin() * c.sin(), -g.cos()))
                    })
                    .collect()
            })
            .collect();
        let mut max = vec![[0.0f64; 36]; 180];
        let mut min = vec![[f64::INFINITY; 36]; 180];
        for (ig, row) in rows.iter().enumerate() {
            let band = (ig / 4).min(179);
            for (ic, &i) in row.iter().enumerate() {
                let sector = ic / 10;
                for b in [Some(band), (ig % 4 == 0 && band > 0).then(|| band - 1)]
                    .into_iter()
                    .flatten()
                {
                    max[b][sector] = max[b][sector].max(i);
                    min[b][sector] = min[b][sector].min(i);
                    if ic % 10 == 0 {
                        let prev = (sector + 35) % 36;
                        max[b][prev] = max[b][prev].max(i);
                        min[b][prev] = min[b][prev].min(i);
                    }
                }
            }
        }
        let (cells, bands) = sparse(max, f64::max, 0.0);
        let (low, low_bands) = sparse(min, f64::min, f64::INFINITY);
        let lit = cells
            .iter()
            .map(|level| {
                level
                    .iter()
                    .map(|row| row.iter().all(|&m| m > 0.0))
                    .collect()
            })
            .collect();
        AngleBounds {
            cells,
            bands,
            lit,
            low,
            low_bands,
        }
    }

    /// Lower and upper bounds of the distribution over the directions within `radius` (rad) of
    /// the unit world direction `dir` (placed by `world_from_photometric`), widened as
    /// [`AngleBounds::over_cone`] widens.
    pub(crate) fn range_over_cone(
        &self,
        world_from_photometric: &DMat3,
        dir: DVec3,
        radius: f64,
    ) -> (f64, f64) {
        let local = world_from_photometric.transpose() * dir;
        let g = gamma_deg(local);
        let widen = radius.to_degrees() + C_MARGIN;
        let gammas = (g - widen, g + widen);
        let (k, a, b) = band_runs(gammas);
        let (g0, g1) = (gammas.0.max(0.0), gammas.1.min(180.0));
        match c_sectors(&[local; 3], g0, g1, widen) {
            None => (
                self.low_bands[k][a].min(self.low_bands[k][b]),
                self.bands[k][a].max(self.bands[k][b]),
            ),
            Some((first, count)) => {
                (0..count)
                    .map(|i| (first + i) % 36)
                    .fold((f64::INFINITY, 0.0f64), |(lo, hi), s| {
                        (
                            lo.min(self.low[k][a][s]).min(self.low[k][b][s]),
                            hi.max(self.cells[k][a][s]).max(self.cells[k][b][s]),
                        )
                    })
            }
        }
    }

    /// Bound over the directions within `radius` (rad) of the unit world direction `dir`, for a
    /// distribution placed by `world_from_photometric`. When the bound over whole γ bands is
    /// already at most `enough`, that coarser bound is returned without looking at C.
    fn over_cone(
        &self,
        world_from_photometric: &DMat3,
        dir: DVec3,
        radius: f64,
        enough: f64,
    ) -> f64 {
        let local = world_from_photometric.transpose() * dir;
        let g = gamma_deg(local);
        let widen = radius.to_degrees() + C_MARGIN;
        self.over_range(&[local; 3], (g - widen, g + widen), widen, enough)
    }

    /// Is the bound over the cone of [`AngleBounds::over_cone`] above zero: can any light leave
    /// in those directions? The same answer as `over_cone(..) > 0.0`, without looking at C where
    /// every C sector of the γ bands is lit (a downlight seen from below: most queries).
    pub(crate) fn lights_cone(
        &self,
        world_from_photometric: &DMat3,
        dir: DVec3,
        radius: f64,
    ) -> bool {
        let g = gamma_deg(world_from_photometric.transpose() * dir);
        let widen = radius.to_degrees() + C_MARGIN;
        let (k, a, b) = band_runs((g - widen, g + widen));
        self.lit[k][a]
            || self.lit[k][b]
            || self.over_cone(world_from_photometric, dir, radius, 0.0) > 0.0
    }

    /// Bound over the spherical triangle with unit world corner directions `dirs` (its exact
    /// range of γ, interior and edges included, widened only by the table's sampling step).
    pub(crate) fn over_triangle(
        &self,
        world_from_photometric: &DMat3,
        dirs: &[DVec3; 3],
        enough: f64,
    ) -> f64 {
        let local = dirs.map(|d| world_from_photometric.transpose() * d);
        let (lo, hi) = gamma_range(&local);
        self.over_range(
            &local,
            (lo - GAMMA_MARGIN, hi + GAMMA_MARGIN),
            C_MARGIN,
            enough,
        )
    }

    /// Bound over γ in `gammas` (degrees) and the C sectors the corners `local` (photometric
    /// frame) span, widened by `widen_c` degrees of arc.
    fn over_range(&self, local: &[DVec3; 3], gammas: (f64, f64), widen_c: f64, enough: f64) -> f64 {
        let (g0, g1) = (gammas.0.max(0.0), gammas.1.min(180.0));
        let (k, a, b) = band_runs(gammas);
        let coarse = self.bands[k][a].max(self.bands[k][b]);
        if coarse <= enough {
            return coarse;
        }
        let Some((first, count)) = c_sectors(local, g0, g1, widen_c) else {
            return coarse;
        };
        let (ra, rb) = (&self.cells[k][a], &self.cells[k][b]);
        (0..count)
            .map(|i| (first + i) % 36)
            .fold(0.0f64, |m, s| m.max(ra[s]).max(rb[s]))
    }
}

/// Sparse tables of one cell table under `pick` (max or min): level k holds runs of 2^k bands;
/// and per level the same over all C sectors.
type Tables = (Vec<Vec<[f64; 36]>>, Vec<Vec<f64>>);
fn sparse(level0: Vec<[f64; 36]>, pick: fn(f64, f64) -> f64, start: f64) -> Tables {
    let mut cells = vec![level0];
    while 1usize << cells.len() <= 180 {
        let half = 1usize << (cells.len() - 1);
        let last = cells.last().expect("level 0 exists");
        let next: Vec<[f64; 36]> = (0..last.len() - half)
            .map(|b| std::array::from_fn(|s| pick(last[b][s], last[b + half][s])))
            .collect();
        cells.push(next);
    }
    let bands = cells
        .iter()
        .map(|level| {
            level
                .iter()
                .map(|row| row.iter().fold(start, |a, b| pick(a, *b)))
                .collect()
        })
        .collect();
    (cells, bands)
}

/// The γ bands (1° each) a range of γ in degrees touches, clamped to 0..180, as the two
/// power-of-two runs of the sparse tables covering them: `(level, first run's start, second
/// run's start)`.
fn band_runs(gammas: (f64, f64)) -> (usize, usize, usize) {
    let (g0, g1) = (gammas.0.max(0.0), gammas.1.min(180.0));
    let from = (g0.floor() as usize).min(179);
    let to = (g1.ceil() as usize).clamp(from + 1, 180);
    let k = (usize::BITS - 1 - (to - from).leading_zeros()) as usize;
    (k, from, to - (1 << k))
}

/// Degrees added around a range of directions for the table's sampling. In γ one sample step
/// (0.25°): the interpolation is monotone between the data's nodes (Hyman-limited Hermite, see
/// `photometry::grid`), so within a step the samples bracket it (next to a strict peak of the
/// data it may exceed them by a second-order amount over the step), and a band's table entry
/// holds the samples on both its edges. In C the samples are 1° apart and data planes (22.5°)
/// need not fall on them: 1°. The bound only decides where to refine (a piece is refined while
/// the bound exceeds its samples by [`super::flux`]'s factor 2), so those slivers are harmless.
const GAMMA_MARGIN: f64 = 0.25;
const C_MARGIN: f64 = 1.0;

/// γ (degrees from the photometric nadir −Z) of a unit direction.
fn gamma_deg(d: DVec3) -> f64 {
    (-d.z).clamp(-1.0, 1.0).acos().to_degrees()
}

/// The exact range of γ (degrees) over the spherical triangle with unit corners `t`: its corners,
/// the points of its edges nearest to either pole, and 0 or 180 when it contains a pole.
fn gamma_range(t: &[DVec3; 3]) -> (f64, f64) {
    let (mut lo, mut hi) = t
        .iter()
        .map(|d| gamma_deg(*d))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), g| {
            (a.min(g), b.max(g))
        });
    let nadir = DVec3::NEG_Z;
    let normals = [t[0].cross(t[1]), t[1].cross(t[2]), t[2].cross(t[0])];
    let side = normals.map(|n| n.dot(nadir));
    let centre = t[0] + t[1] + t[2];
    // The triangle holds a pole when the pole is on the inner side of all three edges.
    if side.iter().all(|s| *s >= 0.0) || side.iter().all(|s| *s <= 0.0) {
        if centre.dot(nadir) > 0.0 {
            lo = 0.0;
        } else if centre.dot(nadir) < 0.0 {
            hi = 180.0;
        }
    }
    for (k, n) in normals.iter().enumerate() {
        let len = n.length();
        if len <= 1e-12 {
            continue;
        }
        let (a, b) = (t[k], t[(k + 1) % 3]);
        // The great circle's point nearest the nadir, and its antipode nearest the zenith.
        let q = nadir - *n * (n.dot(nadir) / (len * len));
        if q.length_squared() <= 1e-24 {
            continue;
        }
        let off = (n.dot(nadir) / len)
            .abs()
            .clamp(0.0, 1.0)
            .asin()
            .to_degrees();
        for (q, g) in [(q, off), (-q, 180.0 - off)] {
            if a.cross(q).dot(*n) >= 0.0 && q.cross(b).dot(*n) >= 0.0 {
                lo = lo.min(g);
                hi = hi.max(g);
            }
        }
    }
    (lo, hi)
}

/// The run of 10° C sectors (first, count) a piece with these photometric-frame corner directions
/// may cover; `None` when it may cover all of them (always near the poles, where C changes fast).
fn c_sectors(local: &[DVec3; 3], g0: f64, g1: f64, widen: f64) -> Option<(usize, usize)> {
    if g0 <= 2.0 || g1 >= 178.0 {
        return None;
    }
    let mut c = local.map(|d| {
        crate::geom::atan::atan2(d.y, d.x)
            .to_degrees()
            .rem_euclid(360.0)
    });
    c.sort_by(f64::total_cmp);
    // The covered arc is the complement of the largest gap between corner azimuths.
    let gaps = [(c[1] - c[0], 1), (c[2] - c[1], 2), (c[0] + 360.0 - c[2], 0)];
    let (gap, start) = gaps
        .iter()
        .fold((0.0, 0), |m, g| if g.0 > m.0 { *g } else { m });
    if gap < 180.0 {
        // The corners surround a pole.
        return None;
    }
    let w = widen / g0.min(180.0 - g1).to_radians().sin().max(1e-3);
    let span = 360.0 - gap + 2.0 * w;
    if span >= 360.0 {
        return None;
    }
    let first = (c[start] - w).rem_euclid(360.0);
    let n = ((span + (first % 10.0)) / 10.0).ceil() as usize + 1;
    if n >= 36 {
        return None;
    }
    Some(((first / 10.0).floor() as usize % 36, n))
}

/// The [`AngleBounds`] of each of a scene's profiles, built when a source first asks for it and
/// then shared (meshing and the direct stage use the same tables).
pub struct ProfileBounds<'a> {
    scene: &'a Scene,
    built: Vec<OnceLock<Arc<AngleBounds>>>,
}

impl<'a> ProfileBounds<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        ProfileBounds {
            scene,
            built: (0..scene.profiles.len()).map(|_| OnceLock::new()).collect(),
        }
    }

    /// The bounds of profile `profile` (an index into `Scene::profiles`).
    pub(crate) fn get(&self, profile: usize) -> Arc<AngleBounds> {
        self.built[profile]
            .get_or_init(|| {
                let photometry = &self.scene.profiles[profile].photometry;
                Arc::new(AngleBounds::new(|d| photometry.intensity(d)))
            })
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// γ over a dense barycentric sampling of the spherical triangle (degrees).
    fn sampled_gammas(t: &[DVec3; 3]) -> (f64, f64) {
        let n = 200;
        let mut range = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let d = (t[0] * u + t[1] * v + t[2] * (1.0 - u - v)).normalize();
                let g = gamma_deg(d);
                range = (range.0.min(g), range.1.max(g));
            }
        }
        range
    }

    fn unit(theta: f64, phi: f64) -> DVec3 {
        DVec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            -theta.cos(),
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The exact γ range holds every direction of the triangle and is no wider than the
        /// sampled one (edges that bulge toward a pole, triangles around a pole included).
        #[test]
        fn gamma_range_is_exact(
            g in 0.0f64..180.0, c in 0.0f64..360.0, size in 0.001f64..1.2,
            a in [0.0f64..6.3, 0.0f64..6.3, 0.0f64..6.3], r in [0.2f64..1.0, 0.2f64..1.0, 0.2f64..1.0],
        ) {
            let centre = unit(g.to_radians(), c.to_radians());
            // An orthonormal frame around the centre; corners at angular radius r·size.
            let e1 = centre.any_orthonormal_vector();
            let e2 = centre.cross(e1);
            let t: [DVec3; 3] = std::array::from_fn(|k| {
                let s = size * r[k];
                (centre * s.cos() + (e1 * a[k].cos() + e2 * a[k].sin()) * s.sin()).normalize()
            });
            let (lo, hi) = gamma_range(&t);
            let (slo, shi) = sampled_gammas(&t);
            // Samples 1/200 of the triangle apart come within one spacing of the extremes.
            let slack = 2.0 * size.to_degrees() / 200.0;
            prop_assert!(lo <= slo + 1e-9 && hi >= shi - 1e-9, "{lo}..{hi} vs sampled {slo}..{shi}");
            prop_assert!(lo >= slo - slack && hi <= shi + slack, "{lo}..{hi} vs sampled {slo}..{shi}");
        }
    }

    /// The shortcut of [`AngleBounds::lights_cone`] (every C sector of the bands lit) gives the
    /// answer of the full bound, across a distribution with dark γ ranges and a dark C sector.
    #[test]
    fn lights_cone_answers_as_the_full_bound() {
        let b = AngleBounds::new(|d| {
            let (g, c) = (gamma_deg(d), d.y.atan2(d.x).to_degrees().rem_euclid(360.0));
            let lit = (g < 60.0 && !(100.0..140.0).contains(&c)) || (120.0..150.0).contains(&g);
            if lit { 1.0 + g / 90.0 } else { 0.0 }
        });
        let frame = DMat3::from_rotation_x(0.3);
        let (mut lit, mut dark) = (0, 0);
        for i in 0..=90 {
            for j in 0..36 {
                let dir = frame
                    * unit(
                        (i as f64 * 2.0).to_radians(),
                        (j as f64 * 10.0).to_radians(),
                    );
                for radius in [0.001, 0.05, 0.3] {
                    let full = b.over_cone(&frame, dir, radius, 0.0) > 0.0;
                    assert_eq!(b.lights_cone(&frame, dir, radius), full, "{dir} {radius}");
                    if full { lit += 1 } else { dark += 1 }
                }
            }
        }
        assert!(lit > 1000 && dark > 1000, "lit {lit}, dark {dark}");
    }

    /// The range over a cone holds the distribution at every direction of the cone (a lumpy
    /// distribution with a dark sector, cones of three sizes all over the sphere) up to the
    /// table's sampling (between samples 1° apart in C a smooth maximum or minimum may pass them
    /// by f''·h²/8, about 2·10⁻⁴ here), and is not vacuous: over a small cone of a smooth piece
    /// it is within 30 %.
    #[test]
    fn range_over_a_cone_holds_the_distribution() {
        let f = |d: DVec3| {
            let (g, c) = (gamma_deg(d), d.y.atan2(d.x));
            let lump = 1.0 + 0.5 * (2.5 * g.to_radians()).sin() * (3.0 * c).cos();
            let dark = (200.0..230.0).contains(&c.to_degrees().rem_euclid(360.0)) && g > 30.0;
            if dark { 0.0 } else { lump }
        };
        let b = AngleBounds::new(f);
        let frame = DMat3::from_rotation_x(0.4) * DMat3::from_rotation_z(0.2);
        let mut tight = 0;
        for i in 0..=36 {
            for j in 0..24 {
                let axis = unit(
                    (i as f64 * 5.0).to_radians(),
                    (j as f64 * 15.0).to_radians(),
                );
                for radius in [0.002f64, 0.03, 0.2] {
                    let (lo, hi) = b.range_over_cone(&frame, frame * axis, radius);
                    let e1 = axis.any_orthonormal_vector();
                    let e2 = axis.cross(e1);
                    for r in 0..=4 {
                        for a in 0..12 {
                            let t = radius * r as f64 / 4.0;
                            let phi = a as f64 * std::f64::consts::PI / 6.0;
                            let d = axis * t.cos() + (e1 * phi.cos() + e2 * phi.sin()) * t.sin();
                            let v = f(d);
                            let slack = 5e-4;
                            assert!(lo <= v + slack && v <= hi + slack, "{lo} {v} {hi}");
                        }
                    }
                    if radius < 0.01 && lo > 0.0 && hi < 1.3 * lo {
                        tight += 1;
                    }
                }
            }
        }
        assert!(tight > 300, "{tight} tight ranges");
    }

    #[test]
    fn a_triangle_around_a_pole_reaches_it() {
        let t = [0.0f64, 120.0, 240.0].map(|c| unit(5f64.to_radians(), c.to_radians()));
        assert_eq!(gamma_range(&t).0, 0.0);
        let t = [0.0f64, 240.0, 120.0].map(|c| unit(175f64.to_radians(), c.to_radians()));
        assert_eq!(gamma_range(&t).1, 180.0);
        // Beside the pole, its edge's nearest point (not a corner) sets the minimum.
        let t = [0.0f64, 90.0, 45.0].map(|c| unit(10f64.to_radians(), c.to_radians()));
        let (lo, _) = gamma_range(&t);
        assert!(lo < 10.0 - 1.0 && lo > 0.0, "{lo}");
    }

    #[test]
    fn range_bounds_equal_the_maximum_over_the_cells() {
        // A lumpy distribution: the sparse table must give the plain maximum over any range.
        let b = AngleBounds::new(|d| {
            let g = (-d.z).clamp(-1.0, 1.0).acos();
            let c = d.y.atan2(d.x);
            1.0 + (5.0 * g).sin().abs() * (1.0 + (3.0 * c).cos())
        });
        for from in [0usize, 1, 7, 90, 150, 178] {
            for to in [from + 1, from + 2, from + 5, from + 33, 180] {
                let to = to.min(180);
                let k = (usize::BITS - 1 - (to - from).leading_zeros()) as usize;
                for s in 0..36 {
                    let plain = (from..to).fold(0.0f64, |m, g| m.max(b.cells[0][g][s]));
                    let table = b.cells[k][from][s].max(b.cells[k][to - (1 << k)][s]);
                    assert_eq!(plain, table, "bands {from}..{to} sector {s}");
                }
                let plain = (from..to).fold(0.0f64, |m, g| m.max(b.bands[0][g]));
                assert_eq!(plain, b.bands[k][from].max(b.bands[k][to - (1 << k)]));
            }
        }
    }
}
