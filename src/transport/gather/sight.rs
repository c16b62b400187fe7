//! What shadow rays say about a far node or a leaf patch seen from a receiver: the two rays that
//! settle a node [`Gatherer`] cannot take as one source ([`Gatherer::sight`]), and the visible
//! fraction of a leaf's sample points, of a node's representatives and of a cluster's.

use super::{Gatherer, SMALL_NODE, SharedRays};
use crate::transport::tree::NodeBounds;
use crate::visibility::{Blocker, Occluder};
use glam::DVec3;

/// What a far node's representatives say about its visibility from a receiver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Sight {
    Hidden,
    Seen,
    Unknown,
}

/// Key offsets in [`SharedRays`]: leaf sample points (0..16), node representatives, cluster
/// representatives.
const REP_KEY: u8 = 16;
const CLUSTER_KEY: u8 = 32;
/// Offset (after the representatives 0..3) of the ray to [`Gatherer::patch_above`]'s point.
const ABOVE_KEY: u8 = 3;

/// Nodes [`Gatherer::patch_above`] visits at most.
const ABOVE_SEARCH: usize = 32;

/// Patches a far node must hold before its rays may settle it ([`Gatherer::sight`]): two rays
/// on a smaller node cost about what tracing its leaves would, and where little is hidden (a
/// small office) they are mostly spent for nothing.
const HIDDEN_MIN_PATCHES: u32 = 8;

impl Gatherer<'_> {
    /// What two rays say about far node `i`, which cannot be one source (it crosses the
    /// receiver's plane or shows it both sides). Two of its representatives above the receiver's
    /// plane (and, when it shows both sides and is not curved clutter, facing `p`) are the
    /// targets. Both blocked (for a curved node, by something not its own): [`Sight::Hidden`],
    /// the node is skipped as a whole, the same inference as for a far source whose two rays
    /// are blocked. Both clear, on a node that is not curved clutter: [`Sight::Seen`], its
    /// patches are gathered without rays of their own, as a far source whose two rays get
    /// through is accepted whole; of a node seen from both sides only the patches facing `p`
    /// (its representatives faced it: they say nothing of the backs behind its front, which
    /// counted as seen absorbers would lose light). Not for curved clutter: its rays ignore its
    /// own patches, which may hide each other. A node whose form factor is below [`SMALL_NODE`]
    /// however its patches turn gets one ray, to its median patch (or another representative
    /// above the plane; when none is, a point on one of its patches above it,
    /// [`Gatherer::patch_above`]: a node the plane cuts near its top otherwise has nothing to
    /// aim at and would be refined). Otherwise — fewer than [`HIDDEN_MIN_PATCHES`] patches, no
    /// targets, or the rays disagree — [`Sight::Unknown`]: it is refined and its patches
    /// traced. In an open-plan office most such nodes are furniture behind other furniture,
    /// whose patches would otherwise be traced one by one and mostly found hidden.
    pub(super) fn sight(
        &self,
        p: DVec3,
        n: DVec3,
        i: u32,
        facing: Option<bool>,
        shared: &mut Option<&mut SharedRays>,
    ) -> Sight {
        if self.occluder.convex_empty {
            return Sight::Seen;
        }
        let node = &self.tree.bounds[i as usize];
        let own_hits = self.tree.own_hits(self.mesh).filter(|_| node.curved);
        // A representative facing away is a fair target when the node's own patches do not
        // count as blockers (a curved node); otherwise its own front would hide it.
        let backs = facing.is_some() || own_hits.is_some();
        let fair = |(q, m): (DVec3, DVec3)| n.dot(q - p) > 0.0 && (backs || m.dot(p - q) > 0.0);
        // Representatives are read only when a test needs them.
        let rep = |k: usize| self.tree.rep(i as usize, k);
        // Worth little (its form factor is below SMALL_NODE however its patches turn), like a
        // small one-sided far node: one ray to the patch at its area median decides.
        let near = (node.center - p).length() - node.radius;
        let area = self.tree.nodes[i as usize].area;
        if area < SMALL_NODE * std::f64::consts::PI * near * near {
            // The median patch, or when it lies below the receiver's plane (or turns its back)
            // another representative: a node crossing the plane often has only one above it.
            let target = [1, 0, 2]
                .into_iter()
                .find_map(|k| Some((k as u8, rep(k))).filter(|(_, r)| fair(*r)))
                .or_else(|| self.patch_above(p, n, i, fair).map(|t| (ABOVE_KEY, t)));
            return match target {
                Some(t) => self.rep_sight(p, n, i, [t], own_hits, shared),
                None => Sight::Unknown,
            };
        }
        if node.end - node.start < HIDDEN_MIN_PATCHES {
            return Sight::Unknown;
        }
        // The first and last quartiles when both are fair targets, else the median with
        // whichever of them is.
        let (r0, r2) = (rep(0), rep(2));
        let targets = match (fair(r0), fair(r2)) {
            (true, true) => [(0, r0), (2, r2)],
            (a, b) if a != b => {
                let r1 = rep(1);
                if !fair(r1) {
                    return Sight::Unknown;
                }
                if a {
                    [(0, r0), (1, r1)]
                } else {
                    [(1, r1), (2, r2)]
                }
            }
            _ => return Sight::Unknown,
        };
        self.rep_sight(p, n, i, targets, own_hits, shared)
    }

    /// [`Gatherer::sight`]'s verdict from rays to `targets` on node `i` (each a key offset for
    /// [`SharedRays`] and a point on one of its patches with the patch's normal): all blocked,
    /// all clear (not for curved clutter), or neither.
    fn rep_sight(
        &self,
        p: DVec3,
        n: DVec3,
        i: u32,
        targets: impl IntoIterator<Item = (u8, (DVec3, DVec3))>,
        own_hits: Option<&(Occluder, Vec<u32>)>,
        shared: &mut Option<&mut SharedRays>,
    ) -> Sight {
        let node = &self.tree.bounds[i as usize];
        let (mut any_clear, mut any_blocked) = (false, false);
        for (k, (q, m)) in targets {
            let clear = match own_hits {
                Some((patches, rank)) => Self::ray(shared, (i, CLUSTER_KEY + k), || {
                    own_first(patches, rank, (p, n), (q, m), node)
                }),
                None => Self::ray(shared, (i, REP_KEY + k), || self.occluder.clear(p, n, q, m)),
            };
            any_clear |= clear;
            any_blocked |= !clear;
        }
        match (any_clear, any_blocked) {
            (false, true) => Sight::Hidden,
            (true, false) if own_hits.is_none() => Sight::Seen,
            _ => Sight::Unknown,
        }
    }

    /// A point on one of node `i`'s patches above the plane through `p` (unit normal `n`), with
    /// the patch's normal: on the first leaf with such a point in a depth-first search that
    /// skips subtrees wholly below the plane, gives up after [`ABOVE_SEARCH`] nodes, and takes
    /// only points `fair` accepts (the test [`Gatherer::sight`] puts its representatives to).
    /// The target of a small node crossing the plane none of whose representatives rises above
    /// it.
    fn patch_above(
        &self,
        p: DVec3,
        n: DVec3,
        i: u32,
        fair: impl Fn((DVec3, DVec3)) -> bool,
    ) -> Option<(DVec3, DVec3)> {
        let mut stack = vec![i];
        for _ in 0..ABOVE_SEARCH {
            let node = &self.tree.bounds[stack.pop()? as usize];
            if node.height_range(p, n).1 <= 0.0 {
                continue;
            }
            if node.is_leaf() {
                // Its centroid, else the highest of three points a quarter of the way in from
                // its corners (a patch the plane cuts near one corner).
                let leaf = self.tree.leaf(node.start);
                let c = node.centroid;
                let height = |q: &DVec3| n.dot(*q - p);
                let q = if height(&c) > 0.0 {
                    c
                } else {
                    let inner = leaf.corners.map(|v| v + (c - v) * 0.25);
                    inner
                        .into_iter()
                        .max_by(|a, b| height(a).total_cmp(&height(b)))?
                };
                if fair((q, leaf.normal)) {
                    return Some((q, leaf.normal));
                }
                continue;
            }
            stack.push(node.children[1]);
            stack.push(node.children[0]);
        }
        None
    }

    /// One shadow ray's answer: from `shared` when it has one for `key`, else traced (and
    /// recorded there).
    fn ray(
        shared: &mut Option<&mut SharedRays>,
        key: (u32, u8),
        trace: impl FnOnce() -> bool,
    ) -> bool {
        match shared {
            Some(s) => *s.0.entry(key).or_insert_with(trace),
            None => trace(),
        }
    }

    /// Fraction of the fixed sample points on leaf `i`'s patch (`leaf`) visible from `p`.
    pub(super) fn patch_visibility(
        &self,
        p: DVec3,
        n: DVec3,
        i: u32,
        leaf: &crate::transport::tree::LeafGeom,
        level: u32,
        shared: &mut Option<&mut SharedRays>,
    ) -> f64 {
        if self.occluder.convex_empty {
            return 1.0;
        }
        let corners = leaf.corners;
        let pts = crate::geom::samples::triangle_points(level);
        let visible = pts
            .iter()
            .enumerate()
            .filter(|(s, b)| {
                Self::ray(shared, (i, *s as u8), || {
                    let q = corners[0] * b[0] + corners[1] * b[1] + corners[2] * b[2];
                    self.occluder.clear(p, n, q, leaf.normal)
                })
            })
            .count();
        visible as f64 / pts.len() as f64
    }

    /// Visible fraction of a cluster: rays toward two representative patches, where a blocker
    /// that is one of the cluster's own patches does not count (the cluster hides its own far
    /// side, which `silhouette` accounts for).
    pub(super) fn cluster_visibility(
        &self,
        p: DVec3,
        n: DVec3,
        i: u32,
        shared: &mut Option<&mut SharedRays>,
    ) -> f64 {
        if self.occluder.convex_empty {
            return 1.0;
        }
        let Some((patches, rank)) = self.tree.own_hits(self.mesh) else {
            return self.ray_visibility(p, n, i, &[0, 2], shared);
        };
        let node = &self.tree.bounds[i as usize];
        let visible = [0, 2]
            .iter()
            .filter(|&&k| {
                Self::ray(shared, (i, CLUSTER_KEY + k as u8), || {
                    let (q, m) = self.tree.rep(i as usize, k);
                    own_first(patches, rank, (p, n), (q, m), node)
                })
            })
            .count();
        visible as f64 / 2.0
    }

    /// Visible fraction of node `i`'s representative patches `at` (indices into
    /// [`crate::transport::tree::REP_QUANTILES`]), one ray each.
    pub(super) fn ray_visibility(
        &self,
        p: DVec3,
        n: DVec3,
        i: u32,
        at: &[usize],
        shared: &mut Option<&mut SharedRays>,
    ) -> f64 {
        if self.occluder.convex_empty {
            return 1.0;
        }
        let visible = at
            .iter()
            .filter(|&&k| {
                Self::ray(shared, (i, REP_KEY + k as u8), || {
                    let (q, m) = self.tree.rep(i as usize, k);
                    self.occluder.clear(p, n, q, m)
                })
            })
            .count();
        visible as f64 / at.len() as f64
    }
}

/// Is the segment from `a` to `b` (points with their normals) clear but for node `node`'s own
/// patches (`patches`: every patch as a ray target, `rank`: each one's position in leaf order),
/// that is, is the first thing it meets, if anything, one of them?
fn own_first(
    patches: &Occluder,
    rank: &[u32],
    a: (DVec3, DVec3),
    b: (DVec3, DVec3),
    node: &NodeBounds,
) -> bool {
    match patches.first_hit_near(a, b, node.center, node.radius) {
        None => true,
        Some(Blocker::Before) => false,
        Some(Blocker::At(hit)) => (node.start..node.end).contains(&rank[hit]),
    }
}
