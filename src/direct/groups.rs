//! Luminaires grouped in space, so that a far group's visibility from a point is settled by one
//! query instead of one shadow ray per luminaire (and per sub-source).
//!
//! Input: the scene's direct sources. Output: [`Groups`], a binary tree over the luminaires among
//! them (median splits along the longest axis of their positions; deterministic), each node
//! holding the box of its luminaires' openings. Queried with a point and the normals of its
//! planes (one for a vertex, six for a probe, a patch's two sides), it names every source once
//! with what is known of its visibility ([`Known`]). Only visibility is shared: each luminaire's
//! intensity, distance and cosine are still evaluated exactly.
//!
//! A group of `MIN_GROUP` (8) luminaires or more, whose radius is below [`GROUP_TAU`] × its
//! distance and whose box lies wholly in front of one of the planes, is handed to the caller's
//! `settle` ([`crate::visibility::Occluder::settle`]), which answers only what it proves: seen
//! when no triangle meets the convex hull of the ray starts and the box (then every shadow ray
//! to every point of every opening in it is clear), hidden when one plane of triangles, unbroken
//! across the hull's cross-section, separates the starts from the box. Otherwise the group's
//! halves are tried in turn, down to single luminaires, which are traced as before.
//!
//! The bound: grouping changes no luminaire's visibility, so the direct light at a receiver and
//! into a patch is that of tracing every luminaire (the proofs keep a margin above the f32
//! rounding and the slack of [`crate::visibility::Occluder::clear`], so they cannot disagree
//! with its rays). Two rays to two members, the rule this replaces, cannot see a shadow edge
//! that crosses a group between them. (Without groups, an open-plan floor's direct light costs
//! receivers × luminaires shadow rays, quadratic in its size.)

use glam::DVec3;

/// Radius / distance below which a group is settled as one.
pub const GROUP_TAU: f64 = 0.2;

/// Fewest luminaires a group must hold to be settled as one (for fewer, their own rays cost no
/// more than the query).
const MIN_GROUP: u32 = 8;

const LEAF: u32 = u32::MAX;

/// What a group's query proved about a source's visibility from the query point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Known {
    /// Nothing: trace it as usual.
    Trace,
    /// Seen (every sub-source of it).
    Seen,
    /// Hidden (every sub-source of it).
    Hidden,
}

struct Node {
    /// Box of the luminaires' openings.
    lo: DVec3,
    hi: DVec3,
    /// Range of `order`.
    start: u32,
    end: u32,
    children: [u32; 2],
}

/// The luminaires of a source list in a tree; other sources are always traced.
pub struct Groups {
    nodes: Vec<Node>,
    /// Source indices (into the list the groups were built from), luminaires only.
    order: Vec<u32>,
    /// Sources that are not luminaires.
    others: Vec<u32>,
}

impl Groups {
    /// Groups over sources given by their place: `Some((position, lo, hi))` for a luminaire (its
    /// opening within the box `[lo, hi]`), `None` for a source that is always traced.
    pub(crate) fn from_places(places: impl Iterator<Item = Option<(DVec3, DVec3, DVec3)>>) -> Self {
        let mut order = Vec::new();
        let mut others = Vec::new();
        let mut place = Vec::new();
        for (k, p) in places.enumerate() {
            match p {
                Some(_) => order.push(k as u32),
                None => others.push(k as u32),
            }
            place.push(p.unwrap_or((DVec3::ZERO, DVec3::ZERO, DVec3::ZERO)));
        }
        let mut groups = Groups {
            nodes: Vec::new(),
            order,
            others,
        };
        if !groups.order.is_empty() {
            groups.split(&place, 0, groups.order.len() as u32);
        }
        groups
    }

    fn split(&mut self, place: &[(DVec3, DVec3, DVec3)], start: u32, end: u32) -> u32 {
        let slice = &mut self.order[start as usize..end as usize];
        let pos = |k: u32| place[k as usize].0;
        let fold = |f: &dyn Fn(u32) -> (DVec3, DVec3)| {
            slice.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), &k| {
                    let (a, b) = f(k);
                    (lo.min(a), hi.max(b))
                },
            )
        };
        let (plo, phi) = fold(&|k| (pos(k), pos(k)));
        let (lo, hi) = fold(&|k| (place[k as usize].1, place[k as usize].2));
        let n = slice.len();
        let index = self.nodes.len() as u32;
        self.nodes.push(Node {
            lo,
            hi,
            start,
            end,
            children: [LEAF; 2],
        });
        if n > 1 {
            let extent = phi - plo;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = n / 2;
            slice.select_nth_unstable_by(mid, |&a, &b| {
                pos(a)[axis].total_cmp(&pos(b)[axis]).then(a.cmp(&b))
            });
            let m = start + mid as u32;
            let left = self.split(place, start, m);
            let right = self.split(place, m, end);
            self.nodes[index as usize].children = [left, right];
        }
        index
    }

    /// Node `i`'s box of openings `(lo, hi)`, its members (source indices, a contiguous run of
    /// [`Groups::order`]) and its children (`None` for a single luminaire).
    pub(crate) fn node(&self, i: u32) -> (DVec3, DVec3, &[u32], Option<[u32; 2]>) {
        let n = &self.nodes[i as usize];
        let children = (n.children[0] != LEAF).then_some(n.children);
        (
            n.lo,
            n.hi,
            &self.order[n.start as usize..n.end as usize],
            children,
        )
    }

    /// Where node `i`'s members start in the tree's order (so a child's members sit at
    /// `start(child) - start(parent)` within its parent's).
    pub(crate) fn start(&self, i: u32) -> usize {
        self.nodes[i as usize].start as usize
    }

    /// Number of nodes (node 0 is the root).
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// No luminaire.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Call `f(source index, what is known of its visibility)` once for every source, as seen
    /// from `p`. A group is settled only when its box lies wholly in front of one of the planes
    /// through `p` with unit `normals`: `settle(lo, hi, n)` says what is proved of the shadow
    /// rays from `p` (pulled off along `n`, that plane's normal) to every point of the box
    /// `[lo, hi]`: `Some(true)` all clear, `Some(false)` all blocked, `None` not known.
    pub fn visit(
        &self,
        p: DVec3,
        normals: &[DVec3],
        settle: impl Fn(DVec3, DVec3, DVec3) -> Option<bool>,
        f: impl FnMut(usize, Known),
    ) {
        self.visit_with(p, normals, settle, |_, _| false, f)
    }

    /// [`Groups::visit`], offering each group proved seen to `cluster(node, n)` first (`n`: the
    /// normal of the plane its box lies in front of): when that takes it (the light cut,
    /// [`super::cut`]), its members are not visited.
    pub(crate) fn visit_with(
        &self,
        p: DVec3,
        normals: &[DVec3],
        settle: impl Fn(DVec3, DVec3, DVec3) -> Option<bool>,
        cluster: impl FnMut(u32, DVec3) -> bool,
        f: impl FnMut(usize, Known),
    ) {
        self.visit_estimated(p, normals, settle, None, cluster, f)
    }

    /// [`Groups::visit_with`], where every group that could be settled is first set aside;
    /// once every other source has been visited, each one set aside (in the order met) is
    /// offered to `estimate(node, n)`, which may answer for it (`Some(seen)`: its members are
    /// visited as seen or hidden, a seen group offered to `cluster` first) or decline (`None`:
    /// `settle` is asked, and when it proves nothing the group's halves are visited, their own
    /// groups set aside in turn). So the estimate can weigh a group against the light of
    /// everything nearer, and a group it answers for costs no proof. With `estimate` `None`,
    /// exactly `visit_with`.
    pub(crate) fn visit_estimated(
        &self,
        p: DVec3,
        normals: &[DVec3],
        settle: impl Fn(DVec3, DVec3, DVec3) -> Option<bool>,
        mut estimate: Option<&mut dyn FnMut(u32, DVec3) -> Option<bool>>,
        mut cluster: impl FnMut(u32, DVec3) -> bool,
        mut f: impl FnMut(usize, Known),
    ) {
        for &k in &self.others {
            f(k as usize, Known::Trace);
        }
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        let mut aside = estimate.is_some().then(Vec::new);
        let view = View {
            p,
            normals,
            settle: &settle,
        };
        self.walk(&mut stack, &view, aside.as_mut(), &mut cluster, &mut f);
        let (Some(estimate), Some(mut aside)) = (estimate.as_mut(), aside) else {
            return;
        };
        // The groups set aside, in the order met; a declined one that no proof settles has its
        // halves visited at once, their own groups joining the end of the line.
        let mut next = 0;
        while let Some(&(i, n)) = aside.get(next) {
            next += 1;
            let node = &self.nodes[i as usize];
            if let Some(seen) = estimate(i, n).or_else(|| settle(node.lo, node.hi, n)) {
                self.settled(i, n, seen, &mut cluster, &mut f);
            } else if node.children[0] == LEAF {
                self.members(i)
                    .iter()
                    .for_each(|&k| f(k as usize, Known::Trace));
            } else {
                stack.extend([node.children[1], node.children[0]]);
                let aside = Some(&mut aside);
                self.walk(&mut stack, &view, aside, &mut cluster, &mut f);
            }
        }
    }

    /// Group `i`'s members (source indices).
    fn members(&self, i: u32) -> &[u32] {
        let node = &self.nodes[i as usize];
        &self.order[node.start as usize..node.end as usize]
    }

    /// Members of group `i` visited as `seen` or hidden (a seen one offered to `cluster`).
    fn settled(
        &self,
        i: u32,
        n: DVec3,
        seen: bool,
        cluster: &mut impl FnMut(u32, DVec3) -> bool,
        f: &mut impl FnMut(usize, Known),
    ) {
        if seen && cluster(i, n) {
            return;
        }
        let known = if seen { Known::Seen } else { Known::Hidden };
        self.members(i).iter().for_each(|&k| f(k as usize, known));
    }

    /// Visit the subtrees on `stack` ([`Groups::visit_with`]'s traversal); groups that could be
    /// settled go to `aside` unasked when given, with the normal of their plane.
    fn walk<S: Fn(DVec3, DVec3, DVec3) -> Option<bool>>(
        &self,
        stack: &mut Vec<u32>,
        view: &View<S>,
        mut aside: Option<&mut Vec<(u32, DVec3)>>,
        cluster: &mut impl FnMut(u32, DVec3) -> bool,
        f: &mut impl FnMut(usize, Known),
    ) {
        let (p, normals, settle) = (view.p, view.normals, view.settle);
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i as usize];
            let (centre, half) = ((node.lo + node.hi) * 0.5, (node.hi - node.lo) * 0.5);
            // A plane the whole box lies in front of.
            let plane = normals
                .iter()
                .find(|n| n.dot(centre - p) > n.abs().dot(half));
            let group = node.end - node.start >= MIN_GROUP
                && half.length() < GROUP_TAU * (centre - p).length();
            if let (true, Some(&n)) = (group, plane) {
                if let Some(aside) = aside.as_deref_mut() {
                    aside.push((i, n));
                    continue;
                }
                if let Some(seen) = settle(node.lo, node.hi, n) {
                    self.settled(i, n, seen, cluster, f);
                    continue;
                }
            }
            if node.children[0] == LEAF {
                self.members(i)
                    .iter()
                    .for_each(|&k| f(k as usize, Known::Trace));
            } else {
                stack.push(node.children[1]);
                stack.push(node.children[0]);
            }
        }
    }
}

/// Where a visit of the groups looks from: the point, the unit normals of the planes through
/// it, and what is proved of the shadow rays from it to a box (see [`Groups::visit`]).
struct View<'v, S> {
    p: DVec3,
    normals: &'v [DVec3],
    settle: &'v S,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    /// A 24 × 24 grid of luminaires 2.5 m apart at y = 3 (glTF +Y up), centred over the
    /// origin, each opening 0.6 m square: the 10⁶-triangle open plan's ceiling (60 × 45 m, 580
    /// luminaires).
    fn grid() -> Groups {
        Groups::from_places((0..N).map(|k| {
            let p = lamp(k);
            let o = DVec3::new(0.3, 0.0, 0.3);
            Some((p, p - o, p + o))
        }))
    }

    fn lamp(k: usize) -> DVec3 {
        let (i, j) = ((k / 24) as f64, (k % 24) as f64);
        DVec3::new(2.5 * i - 28.75, 3.0, 2.5 * j - 28.75)
    }

    const N: usize = 576;

    /// Visit from the origin facing up; `settle` answers for a box. Returns each source's
    /// answer and the number of queries.
    fn visit(
        groups: &Groups,
        settle: impl Fn(DVec3, DVec3) -> Option<bool>,
    ) -> (Vec<Option<Known>>, usize) {
        let queries = Cell::new(0);
        let mut known = vec![None; N];
        let settle = |lo: DVec3, hi: DVec3, _n: DVec3| {
            queries.set(queries.get() + 1);
            assert!(lo.cmple(hi).all());
            settle(lo, hi)
        };
        groups.visit(DVec3::ZERO, &[DVec3::Y], settle, |k, answer| {
            assert!(known[k].is_none(), "source {k} visited twice");
            known[k] = Some(answer);
        });
        (known, queries.get())
    }

    #[test]
    fn every_source_is_visited_once_and_far_groups_take_one_query() {
        let groups = grid();
        let (known, queries) = visit(&groups, |_, _| Some(true));
        assert!(known.iter().all(|k| k.is_some()));
        let seen = known.iter().filter(|k| **k == Some(Known::Seen)).count();
        let traced = known.iter().filter(|k| **k == Some(Known::Trace)).count();
        eprintln!("{seen} seen in groups by {queries} queries, {traced} traced");
        // Far luminaires are settled in groups (one query for 8 or more), near ones traced.
        assert!(seen > 250 && traced > 20, "{seen} seen, {traced} traced");
        assert!(
            queries * 8 <= seen,
            "{queries} queries for {seen} luminaires"
        );
    }

    /// A wall at x = 4 hides every luminaire beyond it: a box is proved seen when it lies wholly
    /// on the near side, hidden when wholly beyond, else not proved.
    fn wall(lo: DVec3, hi: DVec3) -> Option<bool> {
        if hi.x <= 4.0 {
            Some(true)
        } else if lo.x > 4.0 {
            Some(false)
        } else {
            None
        }
    }

    #[test]
    fn a_group_is_settled_only_as_its_query_proves() {
        let groups = grid();
        // A wall hides every luminaire with x > 4: the query proves a box seen only when it lies
        // wholly on the near side, hidden only when wholly beyond. No luminaire may then be
        // settled on the wrong side, and a group across the wall is split down to its leaves.
        let (known, _) = visit(&groups, wall);
        let mut wrong = 0;
        for (k, answer) in known.iter().enumerate() {
            let x = lamp(k).x;
            match answer.unwrap() {
                Known::Seen if x > 4.0 => wrong += 1,
                Known::Hidden if x <= 4.0 => wrong += 1,
                _ => {}
            }
        }
        let hidden = known.iter().filter(|k| **k == Some(Known::Hidden)).count();
        let seen = known.iter().filter(|k| **k == Some(Known::Seen)).count();
        eprintln!("{hidden} settled as hidden, {seen} as seen, {wrong} on the wrong side");
        assert!(hidden > 100 && seen > 100, "{hidden} hidden, {seen} seen");
        assert_eq!(wrong, 0, "luminaires settled on the wrong side of the wall");
    }

    #[test]
    fn estimates_come_after_the_near_sources_and_declined_groups_are_proved_or_split() {
        // The grid with a wall at x = 4 as above. The estimate answers "seen" for groups whose
        // box lies wholly beyond x = 10 (behind the wall: a wrong answer, so its use shows) and
        // declines the rest. Every source is visited once; the near luminaires (within 3 m of
        // the receiver, never in a far group) come before the first estimate is asked; a
        // declined group is settled by its proof or split, so nothing else is seen behind the
        // wall.
        let groups = grid();
        let settle = |lo: DVec3, hi: DVec3, _n: DVec3| wall(lo, hi);
        let visited = std::cell::RefCell::new(Vec::new());
        let first_ask = Cell::new(None);
        let mut estimate = |i: u32, _n: DVec3| {
            if first_ask.get().is_none() {
                first_ask.set(Some(visited.borrow().len()));
            }
            let (lo, _, _, _) = groups.node(i);
            (lo.x > 10.0).then_some(true)
        };
        groups.visit_estimated(
            DVec3::ZERO,
            &[DVec3::Y],
            settle,
            Some(&mut estimate),
            |_, _| false,
            |k, a| visited.borrow_mut().push((k, a)),
        );
        let order = visited.into_inner();
        assert_eq!(order.len(), N);
        let mut once = vec![false; N];
        for &(k, _) in &order {
            assert!(!once[k], "source {k} visited twice");
            once[k] = true;
        }
        let asked = first_ask.get().expect("the estimate was asked");
        let near = |k: usize| lamp(k).x.abs() < 3.0 && lamp(k).z.abs() < 3.0;
        let near_before = order[..asked].iter().filter(|(k, _)| near(*k)).count();
        assert_eq!(near_before, (0..N).filter(|&k| near(k)).count());
        let estimated = order
            .iter()
            .filter(|(k, a)| lamp(*k).x > 10.0 && *a == Known::Seen);
        assert!(estimated.count() >= 8);
        let wrong = (order.iter())
            .filter(|(k, a)| *a == Known::Seen && (4.0..=10.0).contains(&lamp(*k).x))
            .count();
        assert_eq!(
            wrong, 0,
            "a declined group settled on the wrong side of the wall"
        );
    }

    #[test]
    fn other_sources_are_always_traced() {
        let groups = Groups::from_places((0..30).map(|k| {
            let p = DVec3::new(k as f64, 50.0, 0.0);
            (k % 3 != 0).then_some((p, p, p))
        }));
        let mut known = Vec::new();
        groups.visit(
            DVec3::ZERO,
            &[DVec3::Y],
            |_, _, _| Some(true),
            |k, a| known.push((k, a)),
        );
        assert_eq!(known.len(), 30);
        for (k, a) in known {
            if k % 3 == 0 {
                assert_eq!(a, Known::Trace);
            }
        }
    }
}
