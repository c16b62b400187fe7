//! Direct light from an emitting patch at a point: Lambert's exact form factor summed over the
//! parts of the patch the point sees.
//!
//! Input: the receiver (point, unit normal), the patch's triangle and normal, the occluder.
//! Output: the visible form factor (≤ the patch's). The triangle is split at its edges'
//! midpoints while a piece is longer than [`COARSE`] × its distance (as luminaire openings are);
//! each piece's visibility is then sampled at its corners and centroid, and a piece whose points
//! disagree (a shadow edge crosses it: a panel seen past a chair's back) is split again, down to
//! [`REFINE`] times finer. There a piece whose corners disagree has the shadow edge's crossing
//! of each such side found by bisection ([`EDGE_STEPS`]) and counts the exact form factor of
//! its part on the seen side of the line through them; so the seen part moves continuously as
//! the receiver does (a penumbra without steps) and a straight edge is exact. A piece whose
//! corners agree but whose centroid does not (something small inside it) counts the seen share
//! of its four points.
//! Neighbouring pieces share corners and sides, and a piece's middle quarter shares its
//! centroid: each sample point is traced once per call and each side bisected once (points are
//! named by their barycentric coordinates in the patch, exact integers; a side is bisected from
//! its lower-named end). Deterministic: fixed splits and sample points. Used only for emitting
//! surfaces' direct light, whose shadows are as sharp as a luminaire's; the reflected field
//! keeps the cheaper fixed patterns.

use crate::geom::hash::IntMap;
use crate::geom::lambert;
use crate::visibility::Occluder;
use glam::DVec3;
use std::cell::RefCell;

/// Whether each sample point traced so far (by its key) is seen, and where on each side
/// bisected so far (by its ends' keys) the shadow edge crosses it.
#[derive(Default)]
struct Traced {
    points: IntMap<u32, bool>,
    sides: IntMap<u64, f64>,
}

/// A piece is split while longer than this × its distance from the point (at 0.1, a shadow's
/// corner could hide 2 % of a Cornell box wall texel's light between a piece's four points).
const COARSE: f64 = 0.05;
/// Where a shadow edge crosses a piece, split down to COARSE / REFINE.
const REFINE: f64 = 4.0;
/// Bisection steps locating a shadow edge on a side of the finest pieces (to 2⁻⁷ of the side):
/// cheaper than splitting further, which doubles the pieces along the edge at every level.
const EDGE_STEPS: u32 = 7;
/// At most this many splits (a piece 4⁻¹⁰ of the patch's area).
const MAX_DEPTH: u32 = 10;
/// Barycentric coordinates are integers over this: corners of pieces MAX_DEPTH splits down
/// (multiples of 3) and their centroids (sums of three corners' coordinates ÷ 3) are exact.
const WHOLE: u32 = 3 << MAX_DEPTH;
/// Sample points on the patch's edges are moved this far into it, as a fraction of their
/// distance from the receiver (at most [`EDGE_SHARE`] of their distance from its centroid):
/// off the edges a panel shares with the ceiling it is set in. About a hundredth of the
/// smallest piece.
const EDGE_PULL: f64 = 1e-4;
const EDGE_SHARE: f64 = 0.01;

/// A point of the patch by its barycentric weights on corners 0 and 1 (over [`WHOLE`]).
type Bary = [u32; 2];

/// The point's name in [`Traced`]: both weights, exact.
fn key(b: Bary) -> u32 {
    b[0] << 16 | b[1]
}

/// The call's patch and receiver, and what each sample point's ray said.
struct Patch<'a> {
    occ: &'a Occluder,
    p: DVec3,
    n: DVec3,
    t: [DVec3; 3],
    m: DVec3,
    centroid: DVec3,
    traced: &'a mut Traced,
}

thread_local! {
    static TRACED: RefCell<Traced> = RefCell::new(Traced::default());
}

/// Form factor of the part of triangle `t` (unit normal `m`) seen from `p` (unit normal `n`).
pub(crate) fn visible_form_factor(
    occ: &Occluder,
    p: DVec3,
    n: DVec3,
    t: [DVec3; 3],
    m: DVec3,
) -> f64 {
    TRACED.with_borrow_mut(|traced| {
        traced.points.clear();
        traced.sides.clear();
        let mut patch = Patch {
            occ,
            p,
            n,
            t,
            m,
            centroid: (t[0] + t[1] + t[2]) / 3.0,
            traced,
        };
        patch.piece([[WHOLE, 0], [0, WHOLE], [0, 0]], 0)
    })
}

impl Patch<'_> {
    fn at(&self, b: Bary) -> DVec3 {
        let w = |k: u32| k as f64 / WHOLE as f64;
        let c = WHOLE - b[0] - b[1];
        self.t[0] * w(b[0]) + self.t[1] * w(b[1]) + self.t[2] * w(c)
    }

    /// Is the point seen from the receiver (traced at most once per call)?
    fn seen(&mut self, b: Bary) -> bool {
        if let Some(&seen) = self.traced.points.get(&key(b)) {
            return seen;
        }
        let on_edge = b[0] == 0 || b[1] == 0 || b[0] + b[1] == WHOLE;
        let seen = self.trace(self.at(b), on_edge);
        self.traced.points.insert(key(b), seen);
        seen
    }

    /// Is world point `q` of the patch seen? One on the patch's edge is first drawn in.
    fn trace(&self, mut q: DVec3, on_edge: bool) -> bool {
        if on_edge {
            let inward = self.centroid - q;
            let pull = (EDGE_PULL * q.distance(self.p)).min(EDGE_SHARE * inward.length());
            q += inward.normalize_or_zero() * pull;
        }
        self.occ.clear(self.p, self.n, q, self.m)
    }

    /// Where the shadow edge crosses the side from `a` to `b` (whose ends disagree): the
    /// point, found by bisection from the side's lower-named end.
    fn crossing(&mut self, a: Bary, b: Bary) -> DVec3 {
        let (lo, hi) = if key(a) < key(b) { (a, b) } else { (b, a) };
        let (pa, pb) = (self.at(lo), self.at(hi));
        let side = u64::from(key(lo)) << 32 | u64::from(key(hi));
        let t = match self.traced.sides.get(&side) {
            Some(&t) => t,
            None => {
                let on = |k: usize| lo[k] == 0 && hi[k] == 0;
                let on_edge = on(0) || on(1) || (lo[0] + lo[1] == WHOLE && hi[0] + hi[1] == WHOLE);
                let first = self.seen(lo);
                let (mut t0, mut t1) = (0.0, 1.0);
                for _ in 0..EDGE_STEPS {
                    let mid = 0.5 * (t0 + t1);
                    if self.trace(pa.lerp(pb, mid), on_edge) == first {
                        t0 = mid;
                    } else {
                        t1 = mid;
                    }
                }
                let t = 0.5 * (t0 + t1);
                self.traced.sides.insert(side, t);
                t
            }
        };
        pa.lerp(pb, t)
    }

    /// The form factor of the part of piece `b` (corners `t`, whose visibility `corners`
    /// disagrees) on the seen side of the line through the shadow edge's crossings of its sides.
    fn seen_part(&mut self, b: [Bary; 3], t: [DVec3; 3], corners: [bool; 3]) -> f64 {
        let mut part: Vec<DVec3> = Vec::with_capacity(4);
        for k in 0..3 {
            let j = (k + 1) % 3;
            if corners[k] {
                part.push(t[k]);
            }
            if corners[k] != corners[j] {
                part.push(self.crossing(b[k], b[j]));
            }
        }
        lambert::form_factor(self.p, self.n, &part)
    }

    fn piece(&mut self, b: [Bary; 3], depth: u32) -> f64 {
        let t = b.map(|k| self.at(k));
        if !lambert::rises_above(self.p, self.n, &t) {
            return 0.0;
        }
        let size = (0..3)
            .map(|k| t[k].distance(t[(k + 1) % 3]))
            .fold(0.0, f64::max);
        let dist = ((t[0] + t[1] + t[2]) / 3.0).distance(self.p);
        if depth < MAX_DEPTH && size > COARSE * dist {
            return self.split(b, depth);
        }
        // Its centroid and corners: a straight shadow edge crossing the piece leaves corners
        // on both sides of it.
        let centroid = [0, 1].map(|k| (b[0][k] + b[1][k] + b[2][k]) / 3);
        let centre = self.seen(centroid);
        let corners = b.map(|q| self.seen(q));
        let seen = usize::from(centre) + corners.iter().filter(|&&c| c).count();
        if seen == 0 {
            return 0.0;
        }
        if seen < 4 && depth < MAX_DEPTH && size > COARSE / REFINE * dist {
            return self.split(b, depth);
        }
        if corners.contains(&true) && corners.contains(&false) {
            return self.seen_part(b, t, corners);
        }
        lambert::form_factor_rising(self.p, self.n, &t) * seen as f64 / 4.0
    }

    /// The four pieces of `b` split at its edges' midpoints (same winding), summed.
    fn split(&mut self, b: [Bary; 3], depth: u32) -> f64 {
        let mid = |x: Bary, y: Bary| [(x[0] + y[0]) / 2, (x[1] + y[1]) / 2];
        let [a, c, d] = b;
        let (ac, cd, da) = (mid(a, c), mid(c, d), mid(d, a));
        [[a, ac, da], [ac, c, cd], [da, cd, d], [ac, cd, da]]
            .into_iter()
            .map(|s| self.piece(s, depth + 1))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::visibility::OccluderOptions;

    #[test]
    fn pieces_share_their_corners_rays() {
        // A right triangle with 0.15 m legs 2 m above a point facing up (+Y), wholly in sight
        // (the only other surface, a plate, lies off to the side): split twice (longest side
        // 0.21 m, then 0.106 m, against 0.05 × 2 m), its 16 pieces have 15 distinct corners
        // and 16 centroids: 31 rays, not 16 × 4.
        let y = |x: f64, h: f64, z: f64| DVec3::new(x, h, z);
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        let plate = [(5.0, -1.0), (5.0, 1.0), (6.0, 1.0), (6.0, -1.0)];
        b.quad("plate", plate.map(|(x, z)| y(x, 1.0, z)), grey);
        let occ = Occluder::build(&b.build(), OccluderOptions::default());
        let t = [y(0.0, 2.0, 0.0), y(0.15, 2.0, 0.0), y(0.0, 2.0, 0.15)];
        let (p, n, m) = (DVec3::ZERO, DVec3::Y, -DVec3::Y);
        let before = occ.rays_traced();
        let got = visible_form_factor(&occ, p, n, t, m);
        assert_eq!(occ.rays_traced() - before, 31);
        let want = lambert::form_factor(p, n, &t);
        assert!((got - want).abs() <= 1e-12 * want, "{got} against {want}");
    }

    #[test]
    fn a_panel_behind_a_plate_edge_gives_the_form_factor_of_what_is_seen() {
        // A 1 m square panel 2 m above a point facing up (+Y), facing down; an opaque plate at
        // 1 m reaching from x = −2 to its edge at x = e: the point sees the panel for x > 2e,
        // whose form factor is Lambert's of that rectangle, within 2·10⁻⁴ of the whole panel's
        // (measured ≤ 6.4·10⁻⁵: the edge found by bisection on the finest pieces' sides; it was
        // 5.4·10⁻³ when they counted the seen share of four points).
        let y = |x: f64, h: f64, z: f64| DVec3::new(x, h, z);
        let panel = [
            [y(-0.5, 2.0, -0.5), y(0.5, 2.0, -0.5), y(0.5, 2.0, 0.5)],
            [y(-0.5, 2.0, -0.5), y(0.5, 2.0, 0.5), y(-0.5, 2.0, 0.5)],
        ];
        for edge in [0.0, 0.07, -0.13] {
            let mut b = SceneBuilder::new();
            let grey = b.material("grey", 0.5);
            b.quad(
                "plate",
                [
                    y(-2.0, 1.0, -2.0),
                    y(-2.0, 1.0, 2.0),
                    y(edge, 1.0, 2.0),
                    y(edge, 1.0, -2.0),
                ],
                grey,
            );
            let scene = b.build();
            let occ = Occluder::build(&scene, OccluderOptions::default());
            let (p, n, m) = (DVec3::ZERO, DVec3::Y, -DVec3::Y);
            let got: f64 = panel
                .iter()
                .map(|t| visible_form_factor(&occ, p, n, *t, m))
                .sum();
            let seen = 2.0 * edge; // the plate's edge at 1 m projects to twice as far at 2 m
            let want = lambert::form_factor(
                p,
                n,
                &[
                    y(seen, 2.0, -0.5),
                    y(seen, 2.0, 0.5),
                    y(0.5, 2.0, 0.5),
                    y(0.5, 2.0, -0.5),
                ],
            );
            let whole: f64 = panel.iter().map(|t| lambert::form_factor(p, n, t)).sum();
            assert!(
                (got - want).abs() <= 2e-4 * whole,
                "edge {edge}: {got} against {want} (whole panel {whole})"
            );
        }
    }
}
