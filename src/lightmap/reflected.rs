//! Inter-reflected light at texels: interpolated from a sparse set of gathers, refined where an
//! error estimate asks for it.
//!
//! Input: the solved scene, the re-indexed surfaces and each texel's triangle and barycentric
//! point. Output: the inter-reflected illuminance at every texel (lx, RGB) and the number of
//! gathers made.
//!
//! Each triangle starts as one linear piece with its vertices' values (the solve's own gathers;
//! a vertex on a contact's outline, whose solve value is read off the outline, is gathered half
//! a texel inside, toward where the solve read: a texel's worth of surface, not the outline's
//! foot, where any step hides a quarter of the sphere). A piece holding at least [`MIN_CHECKED`] texels, or any triangle with a corner on an
//! outline, is checked by one gather
//! at its centroid: where the linear value misses it by more than the tolerance (a fraction of
//! the total illuminance there), the piece is split into four at its edge midpoints, each
//! midpoint gathered, and the pieces checked in turn; a failing piece of few texels is gathered
//! texel by texel. A piece never crosses its triangle, so interpolation never crosses a contact
//! or a chart edge. Gathers run level by level in a fixed order, in parallel.

use super::Options;
use crate::progress::Progress;
use crate::result::BakedSurface;
use crate::scene::luma;
use crate::solution::{Planes, Receiver, Receivers, Solution, receivers};
use glam::DVec3;
use std::collections::{BTreeMap, HashMap};

/// Where vertex `v` of surface `surface` is on a contact's outline: the step the solve took off
/// it (longer than a hundredth of a texel), else `None`. `origins`: each vertex's receiver in
/// its mesh group.
pub(crate) fn outline_step(
    s: &Solution,
    surface: usize,
    origins: &[u32],
    v: u32,
    texel: f64,
) -> Option<DVec3> {
    let mesh = s.mesh();
    let g = &mesh.groups[surface];
    let k = origins[v as usize] as usize;
    if k >= g.receivers.len() {
        return None;
    }
    let r = &mesh.receivers[g.receivers.start + k];
    let nudge = r.point - r.position;
    (nudge.length() > 0.01 * texel).then_some(nudge)
}

/// Pieces with fewer texels are interpolated unchecked.
pub const MIN_CHECKED: usize = 6;
/// A failing piece with at most this many texels is gathered texel by texel.
const GATHER_ALL: usize = 4;
/// Splits at most this deep.
const MAX_DEPTH: usize = 6;

/// Points to read light at, each with one plane: (point, unit normal).
pub struct Points<'a>(pub &'a [(DVec3, DVec3)]);

impl Receivers for Points<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }

    fn receiver(&self, i: usize) -> Receiver {
        Receiver {
            point: self.0[i].0,
            planes: Planes::one(self.0[i].1),
        }
    }
}

/// A texel of a piece: its index and barycentric coordinates in the piece.
type Local = (usize, [f64; 3]);

/// A linear piece of a triangle: its corners (barycentric in the triangle), values there, and
/// its texels (index into `lit`, barycentric in the piece).
struct Piece {
    surface: u32,
    triangle: u32,
    corners: [[f64; 3]; 3],
    values: [DVec3; 3],
    texels: Vec<Local>,
    depth: usize,
    /// A corner is on a contact's outline, where the light changes fastest: checked however
    /// few texels the piece holds.
    outline: bool,
}

/// Where a texel reads: its triangle and barycentric coordinates there, and the point and
/// normal it reads at (the point may have been moved off a nearby surface).
pub struct At {
    pub surface: u32,
    pub triangle: u32,
    pub bary: [f64; 3],
    pub point: DVec3,
    pub normal: DVec3,
}

/// What reading light at texels shares: the solve, its re-indexed surfaces with each vertex's
/// receiver in its mesh group (`origins`), the settings and where progress goes.
pub struct Reading<'a> {
    pub s: &'a Solution<'a>,
    pub surfaces: &'a [BakedSurface],
    pub origins: &'a [Vec<u32>],
    pub o: &'a Options,
    pub progress: &'a dyn Progress,
}

impl Reading<'_> {
    /// The inter-reflected illuminance gathered at each (point, normal), in parallel.
    fn gather(&self, pts: &[(DVec3, DVec3)]) -> Vec<DVec3> {
        let s = self.s;
        receivers::map(&Points(pts), self.progress, |_, r| {
            s.indirect_at(r.point, r.planes.as_slice()[0])
        })
    }

    /// The point and normal read at barycentric `l` of a triangle, moved inside it: half a
    /// texel where `off` (a point on a contact's outline), else a hair.
    fn world(&self, surface: u32, triangle: u32, l: [f64; 3], off: bool) -> (DVec3, DVec3) {
        let b = &self.surfaces[surface as usize];
        let tri = b.triangles[triangle as usize];
        let (mut p, mut n, mut c) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for j in 0..3 {
            p += b.positions[tri[j] as usize] * l[j];
            n += b.normals[tri[j] as usize] * l[j];
            c += b.positions[tri[j] as usize] / 3.0;
        }
        // A midpoint on the triangle's edge may lie where surfaces meet: read a hair inside
        // (the same point for both triangles of an edge); on a contact's outline, half a texel
        // inside, as its corners (at the outline's foot any step hides a quarter of the sphere).
        let inward = c - p;
        let reach = if off {
            0.5 * self.o.texel_size
        } else {
            0.01 * self.o.texel_size
        };
        let step = reach.min(0.5 * inward.length());
        (
            p + inward.normalize_or_zero() * step,
            n.normalize_or(b.normals[tri[0] as usize]),
        )
    }

    /// The solve's value at vertex `v` of `surface`, or, where the solve read it off a
    /// contact's outline, the point and normal half a texel inside to gather it at instead.
    fn solved(&self, surface: u32, v: u32) -> Result<DVec3, (DVec3, DVec3)> {
        let (s, o) = (self.s, self.o);
        let g = &s.mesh().groups[surface as usize];
        let b = &self.surfaces[surface as usize];
        let k = self.origins[surface as usize][v as usize] as usize;
        if k >= g.receivers.len() {
            return Ok(DVec3::ZERO);
        }
        match outline_step(
            s,
            surface as usize,
            &self.origins[surface as usize],
            v,
            o.texel_size,
        ) {
            None => Ok(s.vertex(g.receivers.start + k).indirect),
            // Read half a texel off the outline (the solve read farther, up to the contact's
            // gap): a texel stands for that much surface, and at the outline itself a step of
            // any height — a 2 mm panel as a 30 cm box — hides a quarter of the sphere.
            Some(nudge) => {
                let off = nudge.length().min(0.5 * o.texel_size);
                let p = b.positions[v as usize] + nudge.normalize() * off;
                Err((p, b.normals[v as usize]))
            }
        }
    }

    /// The gathered values at the outline vertices of the given triangles, by (surface,
    /// vertex), gathered in (surface, vertex) order.
    fn outline_values<'t>(
        &self,
        triangles: impl Iterator<Item = &'t (u32, u32)>,
    ) -> HashMap<(u32, u32), DVec3> {
        let mut outline: BTreeMap<(u32, u32), (DVec3, DVec3)> = BTreeMap::new();
        for &(surface, triangle) in triangles {
            for v in self.surfaces[surface as usize].triangles[triangle as usize] {
                if let Err(p) = self.solved(surface, v) {
                    outline.insert((surface, v), p);
                }
            }
        }
        let pts: Vec<_> = outline.values().copied().collect();
        outline.keys().copied().zip(self.gather(&pts)).collect()
    }
}

/// The texels of each triangle (by surface and triangle, in order), with their barycentric
/// coordinates.
fn by_triangle(at: &[At]) -> BTreeMap<(u32, u32), Vec<Local>> {
    let mut by_triangle: BTreeMap<(u32, u32), Vec<Local>> = BTreeMap::new();
    for (k, a) in at.iter().enumerate() {
        by_triangle
            .entry((a.surface, a.triangle))
            .or_default()
            .push((k, a.bary));
    }
    by_triangle
}

/// The inter-reflected illuminance at each texel `at` (lx, RGB) and the number of gathers made:
/// interpolated over pieces of triangles and refined where a check misses (see the module's
/// doc). `direct`: each texel's direct illuminance, which scales the tolerance.
pub(crate) fn at_texels(r: &Reading, at: &[At], direct: &[DVec3]) -> (Vec<DVec3>, usize) {
    let out = vec![DVec3::ZERO; at.len()];
    if r.o.tolerance <= 0.0 {
        let pts: Vec<_> = at.iter().map(|a| (a.point, a.normal)).collect();
        return (r.gather(&pts), at.len());
    }
    // The solve's value at each vertex, or where it was read off an outline, a gather half a
    // texel inside (toward where the solve read).
    let by_triangle = by_triangle(at);
    let outline = r.outline_values(by_triangle.keys());
    let gathers = outline.len();
    let mut pieces: Vec<Piece> = by_triangle
        .into_iter()
        .map(|((surface, triangle), texels)| {
            let tri = r.surfaces[surface as usize].triangles[triangle as usize];
            Piece {
                surface,
                triangle,
                corners: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                values: tri.map(|v| {
                    r.solved(surface, v)
                        .unwrap_or_else(|_| outline[&(surface, v)])
                }),
                texels,
                depth: 0,
                outline: tri.iter().any(|&v| outline.contains_key(&(surface, v))),
            }
        })
        .collect();
    let mut refinement = Refinement {
        r,
        at,
        direct,
        outline,
        out,
        gathers,
    };
    while !pieces.is_empty() {
        pieces = refinement.level(pieces);
    }
    (refinement.out, refinement.gathers)
}

/// One refinement of texel values, level by level: the values so far and the gathers made.
struct Refinement<'a> {
    r: &'a Reading<'a>,
    at: &'a [At],
    direct: &'a [DVec3],
    /// The gathered values at outline vertices, by (surface, vertex).
    outline: HashMap<(u32, u32), DVec3>,
    out: Vec<DVec3>,
    gathers: usize,
}

impl Refinement<'_> {
    /// One level: small pieces interpolated, the others checked at their centroids; failing
    /// pieces gathered texel by texel or split. Returns the next level's pieces.
    fn level(&mut self, pieces: Vec<Piece>) -> Vec<Piece> {
        let (small, checked): (Vec<Piece>, Vec<Piece>) = pieces
            .into_iter()
            .partition(|p| p.texels.len() < MIN_CHECKED && !p.outline);
        for p in &small {
            interpolate(p, &mut self.out);
        }
        let (failed, texelwise) = self.check(checked);
        let pts: Vec<_> = texelwise
            .iter()
            .map(|&k| (self.at[k].point, self.at[k].normal))
            .collect();
        self.gathers += pts.len();
        for (k, g) in texelwise.iter().zip(self.r.gather(&pts)) {
            self.out[*k] = g;
        }
        self.split_failed(failed)
    }

    /// Checks each piece by a gather at its centroid: interpolates the pieces that pass and
    /// returns those that fail, to split, and the texels of failing pieces too small or too
    /// deep to split, to gather one by one.
    fn check(&mut self, checked: Vec<Piece>) -> (Vec<Piece>, Vec<usize>) {
        let centroid = |p: &Piece| -> [f64; 3] {
            let c = p.corners;
            [0, 1, 2].map(|j| (c[0][j] + c[1][j] + c[2][j]) / 3.0)
        };
        let pts: Vec<_> = (checked.iter())
            .map(|p| self.r.world(p.surface, p.triangle, centroid(p), false))
            .collect();
        self.gathers += pts.len();
        let mut failed = Vec::new();
        let mut texelwise = Vec::new();

        for (p, g) in checked.into_iter().zip(self.r.gather(&pts)) {
            let linear = (p.values[0] + p.values[1] + p.values[2]) / 3.0;
            let d = p
                .texels
                .iter()
                .map(|(k, _)| luma(self.direct[*k]))
                .sum::<f64>()
                / p.texels.len() as f64;
            let miss = (luma(g) - luma(linear)).abs();

            if miss <= self.r.o.tolerance * (luma(g) + d) {
                interpolate(&p, &mut self.out);
            } else if p.texels.len() <= GATHER_ALL || p.depth >= MAX_DEPTH {
                texelwise.extend(p.texels.iter().map(|(k, _)| *k));
            } else {
                failed.push(p);
            }
        }
        (failed, texelwise)
    }

    /// The failing pieces split at their edge midpoints (AB, BC, CA), each midpoint gathered.
    fn split_failed(&mut self, failed: Vec<Piece>) -> Vec<Piece> {
        let mid = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|j| (a[j] + b[j]) / 2.0);
        let pts: Vec<_> = (failed.iter())
            .flat_map(|p| {
                let c = p.corners;
                [mid(c[0], c[1]), mid(c[1], c[2]), mid(c[2], c[0])].map(|m| {
                    let off = self.on_outline(p.surface, p.triangle, m);
                    self.r.world(p.surface, p.triangle, m, off)
                })
            })
            .collect();
        self.gathers += pts.len();
        let mids = self.r.gather(&pts);
        let mut pieces = Vec::new();
        for (p, m) in failed.into_iter().zip(mids.chunks(3)) {
            pieces.extend(split(p, [m[0], m[1], m[2]]));
        }
        pieces
    }

    /// Whether the point `l` of a triangle lies on one of its edges whose two ends are both on
    /// a contact's outline.
    fn on_outline(&self, surface: u32, triangle: u32, l: [f64; 3]) -> bool {
        let tri = self.r.surfaces[surface as usize].triangles[triangle as usize];
        let values = &self.outline;
        (0..3).any(|k| {
            let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            l[k] < 1e-12 && values.contains_key(&(surface, a)) && values.contains_key(&(surface, b))
        })
    }
}

/// Writes the texels of `p` interpolated linearly from its corners' values.
fn interpolate(p: &Piece, out: &mut [DVec3]) {
    for (k, l) in &p.texels {
        out[*k] = p.values[0] * l[0] + p.values[1] * l[1] + p.values[2] * l[2];
    }
}

/// The four pieces of `p` cut at its edge midpoints (values `m` at AB, BC, CA), its texels
/// handed to the piece holding them (barycentric coordinates carried over).
fn split(p: Piece, m: [DVec3; 3]) -> [Piece; 4] {
    let [a, b, c] = p.corners;
    let mid = |x: [f64; 3], y: [f64; 3]| [0, 1, 2].map(|j| (x[j] + y[j]) / 2.0);
    let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
    let [va, vb, vc] = p.values;
    let [mab, mbc, mca] = m;
    let piece = |corners, values| Piece {
        surface: p.surface,
        triangle: p.triangle,
        corners,
        values,
        texels: Vec::new(),
        depth: p.depth + 1,
        outline: false,
    };
    let mut out = [
        piece([a, ab, ca], [va, mab, mca]),
        piece([ab, b, bc], [mab, vb, mbc]),
        piece([ca, bc, c], [mca, mbc, vc]),
        piece([bc, ca, ab], [mbc, mca, mab]),
    ];
    for (k, l) in p.texels {
        let (child, local) = if l[0] >= 0.5 {
            (0, [2.0 * l[0] - 1.0, 2.0 * l[1], 2.0 * l[2]])
        } else if l[1] >= 0.5 {
            (1, [2.0 * l[0], 2.0 * l[1] - 1.0, 2.0 * l[2]])
        } else if l[2] >= 0.5 {
            (2, [2.0 * l[0], 2.0 * l[1], 2.0 * l[2] - 1.0])
        } else {
            (3, [1.0 - 2.0 * l[0], 1.0 - 2.0 * l[1], 1.0 - 2.0 * l[2]])
        };
        out[child].texels.push((k, local));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_pieces_reproduce_a_linear_field_and_keep_every_texel() {
        // Texels at many points of the triangle; a field linear in the barycentrics.
        let field = |l: [f64; 3]| DVec3::new(3.0 * l[0] + 5.0 * l[1] - 2.0 * l[2], 1.0, 0.0);
        let mut texels = Vec::new();
        for i in 0..=10 {
            for j in 0..=(10 - i) {
                let l = [i as f64 / 10.0, j as f64 / 10.0, (10 - i - j) as f64 / 10.0];
                texels.push((texels.len(), l));
            }
        }
        let n = texels.len();
        let want: Vec<DVec3> = texels.iter().map(|(_, l)| field(*l)).collect();
        let p = Piece {
            surface: 0,
            triangle: 0,
            corners: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            values: [
                field([1.0, 0.0, 0.0]),
                field([0.0, 1.0, 0.0]),
                field([0.0, 0.0, 1.0]),
            ],
            texels,
            depth: 0,
            outline: false,
        };
        let mid = |a: [f64; 3], b: [f64; 3]| field([0, 1, 2].map(|j| (a[j] + b[j]) / 2.0));
        let m = [
            mid([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            mid([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            mid([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        ];
        let mut seen = 0;
        for c in split(p, m) {
            for (k, l) in &c.texels {
                seen += 1;
                assert!(l.iter().all(|x| *x >= -1e-12 && *x <= 1.0 + 1e-12));
                let v = c.values[0] * l[0] + c.values[1] * l[1] + c.values[2] * l[2];
                assert!((v - want[*k]).length() < 1e-12);
            }
        }
        assert_eq!(seen, n);
    }
}
