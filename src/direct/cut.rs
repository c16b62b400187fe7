//! The light cut (after Lightcuts, Walter et al. 2005): at a receiver or into a patch, groups of
//! luminaires already proved seen ([`super::groups`]) are taken as clusters with a lower and an
//! upper bound on their light instead of one by one, and split (widest first, down to single
//! luminaires evaluated exactly) until the bounds' summed half-widths fit the budget.
//!
//! Input: the direct sources, their [`Groups`], a fraction f, and a [`Target`] (a receiver's
//! planes, a patch's front). Output, through the target: the exact light of every source not
//! clustered, and an estimate for each luminaire of every cluster kept.
//!
//! A cluster is a group node whose luminaires share a kind ([`Source::same_kind`]: profile,
//! frame, colour). Its light on a plane is Σⱼ I(ωⱼ)·gⱼ: gⱼ the exact geometry of member j (scale
//! × share × cos/d²/d at a receiver, × solid angle into a patch; cheap, no intensity lookup), ωⱼ
//! its directions toward the target, all inside the cone from the node's box to the target; so
//! it lies in [L, U] = [I_min, I_max]·Σⱼ gⱼ, I_min and I_max the profile's table range over that
//! cone ([`super::bounds`]). It is estimated by (L + U)/2, each member getting (I_min + I_max)/2·gⱼ,
//! off by at most (U − L)/2. Clusters are split while on some plane Σ (U − L)/2 exceeds f × (the
//! light summed exactly + Σ L); that sum never exceeds the full sum, so on every plane
//! |cut − full| ≤ f·full, in luminance (colours have luminance 1), up to the tables' sampling.
//! f = 0 forms no cluster: every luminaire summed as without the cut. Deterministic: a target's
//! refinement is sequential, ties broken by node index.

use super::groups::{Groups, Known};
use super::luminaire::Source;
use super::sources::DirectSource;
use glam::DVec3;
use std::cell::RefCell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Where light is summed: the planes of a receiver, or a patch's front.
pub trait Target {
    /// Values the bound is kept on, one a plane.
    fn planes(&self) -> usize;
    /// Of the normals handed to [`Cut::run`], how many (the first ones) may have clusters in
    /// front of them.
    fn cluster_planes(&self) -> usize;
    /// Sum source `k` exactly (`known`: its visibility, as [`Groups::visit`] gives it), adding
    /// its light (photometric) on each plane to `out`.
    fn exact(&mut self, k: usize, known: Known, out: &mut [f64]);
    /// Is the shadow ray from the target (pulled off the side facing along `n`) to point `q`
    /// (normal `nq`) clear?
    fn sees(&self, n: DVec3, q: DVec3, nq: DVec3) -> bool;
    /// Luminaire `s`'s geometry (what its unscaled intensity is multiplied by) added to `out`.
    fn geometry(&self, s: &Source, out: &mut [f64]);
    /// The cone holding every direction from the box `[lo, hi]` to the target: unit axis (away
    /// from the box) and angular radius (rad); `None` when the box is too near for one.
    fn cone(&self, lo: DVec3, hi: DVec3) -> Option<(DVec3, f64)>;
    /// Luminaire `k`'s estimated light (photometric) on each plane.
    fn accept(&mut self, k: usize, values: &[f64]);
}

/// The kinds of the group nodes and the budget.
pub struct Cut {
    /// Per node of the groups: a member whose kind every member shares, or `None`.
    kind: Vec<Option<u32>>,
    fraction: f64,
    /// The direct-light budget b ([`Cut::with_budget`]); 0: every group's visibility traced.
    budget: f64,
}

/// How the direct light is summed at receivers and into patches: the light cut's fraction f
/// and the direct-light budget b ([`Cut::with_budget`]). Both 0: every luminaire exactly.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CutSettings {
    pub fraction: f64,
    pub budget: f64,
}

/// A cluster in the cut.
struct Item {
    /// Σ over planes of U − L: the widest is split first.
    key: f64,
    node: u32,
    set: u32,
    lo: f64,
    hi: f64,
}

impl PartialEq for Item {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Item {}
impl PartialOrd for Item {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Item {
    fn cmp(&self, o: &Self) -> Ordering {
        self.key.total_cmp(&o.key).then(o.node.cmp(&self.node))
    }
}

impl Cut {
    /// `fraction`: the bound f (0: no cut).
    pub fn new(sources: &[DirectSource], groups: &Groups, fraction: f64) -> Self {
        let lum = |k: u32| luminaire(sources, k);
        let kind = (0..groups.len() as u32)
            .map(|i| {
                let (_, _, members, _) = groups.node(i);
                let first = lum(*members.first()?)?;
                (members
                    .iter()
                    .all(|&k| lum(k).is_some_and(|s| s.same_kind(first))))
                .then_some(members[0])
            })
            .collect();
        Cut {
            kind,
            fraction,
            budget: 0.0,
        }
    }

    /// This cut with the direct-light budget `b`: a far group of luminaires whose light, with
    /// that of the groups estimated before it, could be at most b × the light summed without
    /// them on every plane (every source not in such a group comes first) takes its visibility
    /// from two shadow rays, to its first and last members' openings, when they agree, instead
    /// of a proof or its members' own rays (see [`Cut::estimate`]; where a proof would settle
    /// it, the rays give the same answer). A target's direct light is then within b of what
    /// budget 0 gives, in luminance. 0: nothing is estimated.
    pub fn with_budget(mut self, b: f64) -> Self {
        self.budget = b;
        self
    }

    /// Visit every source from `at` as [`Groups::visit`] does (`normals`, `settle`: as there),
    /// summing through `t`: exactly, or in clusters within the bound.
    pub fn run(
        &self,
        sources: &[DirectSource],
        groups: &Groups,
        at: DVec3,
        normals: &[DVec3],
        settle: impl Fn(DVec3, DVec3, DVec3) -> Option<bool>,
        t: &mut impl Target,
    ) {
        let m = t.planes();
        let front = &normals[..t.cluster_planes().min(normals.len())];
        let on = self.fraction > 0.0;
        let mut sets = Vec::new();
        let exact = RefCell::new(vec![0.0; m]);
        let mut each = vec![0.0; m];
        let t = RefCell::new(t);
        // Per plane, the bound on the light of the groups estimated so far.
        let mut spent = vec![0.0; m];
        // Only on the planes the bound is kept on (a patch's front: what reaches its back is
        // not summed in `exact`).
        let mut estimate = |i: u32, n: DVec3| {
            let target = &**t.borrow();
            front.contains(&n).then(|| {
                self.estimate(sources, groups, (i, n), &exact.borrow(), &mut spent, target)
            })?
        };
        let estimate: Option<&mut dyn FnMut(u32, DVec3) -> Option<bool>> = match self.budget > 0.0 {
            true => Some(&mut estimate),
            false => None,
        };
        groups.visit_estimated(
            at,
            normals,
            settle,
            estimate,
            |node, n| {
                let take = on && front.contains(&n);
                if take {
                    sets.push(node);
                }
                take
            },
            |k, known| {
                each.fill(0.0);
                t.borrow_mut().exact(k, known, &mut each);
                for (e, x) in exact.borrow_mut().iter_mut().zip(&each) {
                    *e += x;
                }
            },
        );
        if !sets.is_empty() {
            self.refine(sources, groups, &sets, exact.into_inner(), t.into_inner());
        }
    }

    /// The budget's answer for group `i` (its box in front of the plane with normal `n`), given
    /// the light summed so far per plane (`exact`) and the bound on the groups estimated before
    /// (`spent`, which an answer adds to). Its bound U (each member's geometry × its profile's
    /// largest intensity over the cone from the group's box toward the target) must keep
    /// spent + U ≤ b × (exact − spent) on every plane, so that all the estimates of a target
    /// together are off by at most b × the light summed without them, which is at most b × its
    /// full direct light. Then `Some(seen)` when the rays to its first and last members'
    /// opening centres agree; otherwise `None`.
    fn estimate(
        &self,
        sources: &[DirectSource],
        groups: &Groups,
        (i, n): (u32, DVec3),
        exact: &[f64],
        spent: &mut [f64],
        t: &impl Target,
    ) -> Option<bool> {
        let lum = |k: u32| luminaire(sources, k);
        let (lo_box, hi_box, members, _) = groups.node(i);
        let (axis, radius) = t.cone(lo_box, hi_box)?;
        // Each member's geometry times its profile's largest intensity over the cone.
        let m = exact.len();
        let (mut most, mut g) = (vec![0.0; m], vec![0.0; m]);
        for &k in members {
            let s = lum(k)?;
            let (_, top) = s.profile_range(axis, radius);
            if !top.is_finite() {
                return None;
            }
            g.fill(0.0);
            t.geometry(s, &mut g);
            for (u, g) in most.iter_mut().zip(&g) {
                *u += top * g;
            }
        }
        let within = |pl: usize| most[pl] + spent[pl] <= self.budget * (exact[pl] - spent[pl]);
        if !(0..m).all(within) {
            return None;
        }
        let sees = |k: u32| {
            let s = lum(k).expect("a group's members are luminaires");
            t.sees(n, s.position, s.world_from_photometric.z_axis)
        };
        let seen = sees(*members.first()?);
        if seen != sees(*members.last()?) {
            return None;
        }
        for (s, u) in spent.iter_mut().zip(&most) {
            *s += u;
        }
        Some(seen)
    }

    fn refine(
        &self,
        sources: &[DirectSource],
        groups: &Groups,
        sets: &[u32],
        exact: Vec<f64>,
        t: &mut impl Target,
    ) {
        let m = exact.len();
        // Every member's geometry (m values each, in the tree's order) and per set its running
        // sums (one row more than members), so a node's Σ gⱼ is a difference of two rows.
        let (mut geo, mut sums) = (Vec::new(), Vec::new());
        let mut bases = Vec::with_capacity(sets.len());
        let mut acc = vec![0.0; m];
        for &node in sets {
            let (_, _, members, _) = groups.node(node);
            bases.push((geo.len() / m, sums.len() / m));
            acc.fill(0.0);
            sums.extend_from_slice(&acc);
            for &k in members {
                let at = geo.len();
                geo.resize(at + m, 0.0);
                if let DirectSource::Luminaire(s) = &sources[k as usize] {
                    t.geometry(s, &mut geo[at..]);
                }
                for (a, g) in acc.iter_mut().zip(&geo[at..]) {
                    *a += g;
                }
                sums.extend_from_slice(&acc);
            }
        }
        // Row of node `node` of set `set` in `geo`, and its Σ gⱼ on plane `pl`.
        let offset = |set: u32, node: u32| groups.start(node) - groups.start(sets[set as usize]);
        let g_sum = |set: u32, node: u32, pl: usize| {
            let row = bases[set as usize].1 + offset(set, node);
            let n = groups.node(node).2.len();
            sums[(row + n) * m + pl] - sums[row * m + pl]
        };
        let mut s = State {
            err: vec![0.0; m],
            low: exact,
            each: vec![0.0; m],
            heap: BinaryHeap::new(),
        };
        let mut pending: Vec<(u32, u32)> = (0..sets.len() as u32)
            .map(|k| (k, sets[k as usize]))
            .collect();
        loop {
            while let Some((set, node)) = pending.pop() {
                let (lo_box, hi_box, members, children) = groups.node(node);
                let range = self.kind[node as usize].and_then(|k| {
                    let DirectSource::Luminaire(l) = &sources[k as usize] else {
                        return None;
                    };
                    let (axis, radius) = t.cone(lo_box, hi_box)?;
                    Some(l.profile_range(axis, radius)).filter(|r| r.1.is_finite())
                });
                match (range, children) {
                    (Some((lo, hi)), _) => {
                        let mut key = 0.0;
                        for pl in 0..m {
                            let g = g_sum(set, node, pl);
                            s.err[pl] += 0.5 * (hi - lo) * g;
                            s.low[pl] += lo * g;
                            key += (hi - lo) * g;
                        }
                        s.heap.push(Item {
                            key,
                            node,
                            set,
                            lo,
                            hi,
                        });
                    }
                    (None, Some([a, b])) => pending.extend([(set, b), (set, a)]),
                    (None, None) => s.exact(t, members),
                }
            }
            let within = (0..m).all(|pl| s.err[pl] <= self.fraction * s.low[pl]);
            if within {
                break;
            }
            let Some(item) = s.heap.pop() else { break };
            for pl in 0..m {
                let g = g_sum(item.set, item.node, pl);
                s.err[pl] -= 0.5 * (item.hi - item.lo) * g;
                s.low[pl] -= item.lo * g;
            }
            match groups.node(item.node) {
                (_, _, _, Some([a, b])) => pending.extend([(item.set, b), (item.set, a)]),
                (_, _, members, None) => s.exact(t, members),
            }
        }
        let mut values = vec![0.0; m];
        for item in s.heap.into_vec() {
            let mid = 0.5 * (item.lo + item.hi);
            let row = bases[item.set as usize].0 + offset(item.set, item.node);
            for (j, &k) in groups.node(item.node).2.iter().enumerate() {
                for (v, g) in values
                    .iter_mut()
                    .zip(&geo[(row + j) * m..(row + j + 1) * m])
                {
                    *v = mid * g;
                }
                t.accept(k as usize, &values);
            }
        }
    }
}

/// The refinement's running totals per plane: Σ (U − L)/2 of the cut's clusters, and the light
/// summed exactly + Σ L.
struct State {
    err: Vec<f64>,
    low: Vec<f64>,
    each: Vec<f64>,
    heap: BinaryHeap<Item>,
}

impl State {
    /// Sum `members` exactly (they are seen).
    fn exact(&mut self, t: &mut impl Target, members: &[u32]) {
        for &k in members {
            self.each.fill(0.0);
            t.exact(k as usize, Known::Seen, &mut self.each);
            for (l, x) in self.low.iter_mut().zip(&self.each) {
                *l += x;
            }
        }
    }
}

/// Source `k` when it is a luminaire.
fn luminaire<'s, 'a>(sources: &'s [DirectSource<'a>], k: u32) -> Option<&'s Source<'a>> {
    match &sources[k as usize] {
        DirectSource::Luminaire(s) => Some(s),
        _ => None,
    }
}

/// The cone from a box to a target of radius `r` around `c` (m): every direction from a point of
/// the box to a point of the target lies within it, when the box's and the target's radii
/// together stay below half the distance.
pub(crate) fn cone(lo: DVec3, hi: DVec3, c: DVec3, r: f64) -> Option<(DVec3, f64)> {
    let d = c - (lo + hi) * 0.5;
    let dist = d.length();
    let r = r + (hi - lo).length() * 0.5;
    (r < 0.5 * dist).then(|| (d / dist, (r / dist).asin()))
}
