//! Per-patch fields (RGB, or one channel) summarised on the nodes of a [`PatchTree`]: what every link of a gather
//! row reads (a node's mean, its first moment for far-field links, its exitance-weighted normal
//! distribution for cluster links).
//!
//! Input: a tree (or its skeleton), its patch mesh and a value per patch. Output: a
//! [`NodeField`]. Sums run bottom-up in a fixed order, so equal inputs give equal bits.

use super::link::{Link, moment_scale};
use super::packed::Leaves;
use super::skeleton::Topology;
use super::tree::{LEAF_SLOT, PatchTree, leaf_sh};
use crate::geom::sh;
use crate::patches::PatchMesh;
use glam::DVec3;

/// The nodes a node field keeps normal distributions for, numbered: a map from node to its
/// index among them ([`LEAF_SLOT`] for the others). Only cluster links read a node's
/// distribution, and they name few of the inner nodes, so the solver's fields keep those alone
/// ([`ClusterSlots::named`]) while a field read from new points (probes) keeps every inner
/// node's ([`ClusterSlots::all`]).
#[derive(Clone)]
pub struct ClusterSlots {
    map: std::sync::Arc<[u32]>,
    len: usize,
}

impl ClusterSlots {
    /// Every inner node of a tree with curved clutter (none otherwise: no cluster links).
    pub(crate) fn all(tree: &PatchTree) -> Self {
        match tree.has_curved() {
            true => ClusterSlots {
                map: tree.slot.clone(),
                len: tree.inner_nodes,
            },
            false => ClusterSlots::none(tree.nodes.len()),
        }
    }

    /// The given nodes (any order, repeats allowed) of a tree of `nodes` nodes, numbered in node
    /// order.
    pub(crate) fn named(nodes: usize, named: impl Iterator<Item = u32>) -> Self {
        let mut map = vec![LEAF_SLOT; nodes];
        for i in named {
            map[i as usize] = 0;
        }
        let mut len = 0;
        for m in map.iter_mut().filter(|m| **m != LEAF_SLOT) {
            *m = len;
            len += 1;
        }
        ClusterSlots {
            map: map.into(),
            len: len as usize,
        }
    }

    fn none(nodes: usize) -> Self {
        ClusterSlots::named(nodes, std::iter::empty())
    }

    /// Node `i`'s index among the kept nodes, or `None`.
    pub(crate) fn get(&self, i: usize) -> Option<usize> {
        match self.map[i] {
            LEAF_SLOT => None,
            s => Some(s as usize),
        }
    }

    /// Number of kept nodes.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// What a node field sums: RGB exitance ([`DVec3`]) or one channel of it (`f64`: the
/// luminance estimates sharing reads, a third of the memory).
pub trait FieldValue:
    Copy
    + Send
    + Sync
    + std::ops::Add<Output = Self>
    + std::ops::Mul<f64, Output = Self>
    + std::ops::Div<f64, Output = Self>
{
    const ZERO: Self;
    /// A first moment: one vector per channel.
    type Moment: Copy + Send + Sync;
    const NO_MOMENT: Self::Moment;
    /// A parent's moment from its two children's.
    fn parent_moment(a: Child<Self>, b: Child<Self>) -> Self::Moment;
    fn scaled(m: Self::Moment, s: f64) -> Self::Moment;
    /// The gradient `g` dotted with each channel's moment.
    fn along(g: DVec3, m: &Self::Moment) -> Self;
}

/// A child node as its parent's first moment reads it.
pub struct Child<V: FieldValue> {
    pub moment: V::Moment,
    /// Its centroid less its parent's.
    pub offset: DVec3,
    pub mean: V,
    pub area: f64,
}

impl FieldValue for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    type Moment = [DVec3; 3];
    const NO_MOMENT: Self::Moment = [DVec3::ZERO; 3];
    fn parent_moment(a: Child<Self>, b: Child<Self>) -> Self::Moment {
        std::array::from_fn(|ch| {
            a.moment[ch]
                + b.moment[ch]
                + a.offset * (a.mean[ch] * a.area)
                + b.offset * (b.mean[ch] * b.area)
        })
    }
    fn scaled(m: Self::Moment, s: f64) -> Self::Moment {
        m.map(|v| v * s)
    }
    fn along(g: DVec3, m: &Self::Moment) -> Self {
        DVec3::new(g.dot(m[0]), g.dot(m[1]), g.dot(m[2]))
    }
}

impl FieldValue for f64 {
    const ZERO: Self = 0.0;
    type Moment = DVec3;
    const NO_MOMENT: Self::Moment = DVec3::ZERO;
    fn parent_moment(a: Child<Self>, b: Child<Self>) -> DVec3 {
        a.moment + b.moment + a.offset * (a.mean * a.area) + b.offset * (b.mean * b.area)
    }
    fn scaled(m: DVec3, s: f64) -> DVec3 {
        m * s
    }
    fn along(g: DVec3, m: &DVec3) -> f64 {
        g.dot(*m)
    }
}

/// A per-patch field (RGB unless said) summarised on every node: its area-mean, and on inner
/// nodes (indexed by [`PatchTree::slot`]; a leaf's is zero) its first moment over its area to
/// the power 3/2 (`dipole[channel]` = Σₖ Aₖ·Bₖ·(cₖ − c_node) / A_node^(3/2): what a far-field
/// link's stored gradient is relative to, [`Link::relative`]), which far-field links use to
/// first order.
pub struct NodeField<V: FieldValue = DVec3> {
    pub mean: Vec<V>,
    pub dipole: Vec<V::Moment>,
    /// The exitance-weighted normal distribution (`geom::sh::Dist` per channel) of the nodes in
    /// `clusters`: what cluster links read.
    pub sh: Vec<[V; sh::DIST]>,
    slot: std::sync::Arc<[u32]>,
    clusters: ClusterSlots,
}

impl<V: FieldValue> NodeField<V> {
    /// Σ over leaf links of coefficient × the patch's exitance.
    pub(crate) fn gather_leaves(&self, leaves: Leaves) -> V {
        leaves
            .iter()
            .map(|l| self.mean[l.node as usize] * l.coeff as f64)
            .fold(V::ZERO, |a, b| a + b)
    }

    /// Σ over `links` of coefficient × mean + gradient · dipole (per channel).
    ///
    /// Panics on a cluster link to a node the field keeps no distribution for.
    pub(crate) fn gather(&self, links: impl IntoIterator<Item = Link>) -> V {
        let mut sum = V::ZERO;
        for l in links {
            let i = l.node as usize;
            if l.is_cluster() {
                let (k, w) = l.cluster();
                let weights = sh::dist_weights(w);
                let s = &self.sh[self.clusters.get(i).expect("a kept cluster node")];
                sum = sum
                    + (0..sh::DIST)
                        .map(|c| s[c] * weights[c])
                        .fold(V::ZERO, |a, b| a + b)
                        * k;
                continue;
            }
            sum = sum + self.mean[i] * l.coeff as f64;
            // Far-field links name inner nodes only (a leaf's moment is zero).
            let slot = self.slot[i] as usize;
            if slot != LEAF_SLOT as usize && l.has_shape() {
                sum = sum + V::along(l.relative(), &self.dipole[slot]) * l.coeff as f64;
            }
        }
        sum
    }

    /// [`NodeField::new`] of the values `patch_value(patch)` (a closure, so a scaled
    /// field needs no scaled copy), keeping the normal distributions of `clusters` only. The
    /// distributions are summed bottom-up through every node all the same (the same sums in the
    /// same order, so the kept ones are bit for bit those of the full field), the pending
    /// children's on a stack: in a reverse pre-order sweep a node's left child was swept last
    /// and its right child's subtree just before, so their values are the stack's top two.
    pub(crate) fn for_clusters(
        tree: &impl Topology,
        mesh: &PatchMesh,
        patch_value: impl Fn(usize) -> V,
        clusters: &ClusterSlots,
    ) -> NodeField<V> {
        let shared = tree.shared();
        let (n, slot) = (shared.nodes.len(), shared.slot);
        let mut mean = vec![V::ZERO; n];
        let mut dipole = vec![V::NO_MOMENT; shared.inner_nodes];
        let with_sh = !clusters.is_empty();
        let mut sh = vec![[V::ZERO; sh::DIST]; clusters.len()];
        let mut pending: Vec<[V; sh::DIST]> = Vec::new();
        for i in (0..n).rev() {
            if tree.is_leaf(i) {
                let p = shared.order[tree.range(i).0 as usize] as usize;
                mean[i] = patch_value(p);
                if with_sh {
                    // A leaf's distribution is its patch's normal, weighted by its value.
                    pending.push(leaf_sh(&mesh.patches[p]).map(|y| mean[i] * y));
                }
                continue;
            }
            let here = slot[i] as usize;
            let [a, b] = tree.children(i).map(|c| c as usize);
            if with_sh {
                debug_assert_eq!(a, i + 1, "children follow their parent in pre-order");
                let sa = pending.pop().expect("left child swept");
                let sb = pending.pop().expect("right child swept");
                let d: [V; sh::DIST] = std::array::from_fn(|k| sa[k] + sb[k]);
                if let Some(s) = clusters.get(i) {
                    sh[s] = d;
                }
                pending.push(d);
            }
            let (wa, wb) = (shared.nodes[a].area, shared.nodes[b].area);
            if wa + wb <= 0.0 {
                continue;
            }
            mean[i] = (mean[a] * wa + mean[b] * wb) / (wa + wb);
            let c = tree.centroid(i);
            let (da, db) = (tree.centroid(a) - c, tree.centroid(b) - c);
            let moment = |c: usize| match slot[c] {
                LEAF_SLOT => V::NO_MOMENT,
                s => dipole[s as usize],
            };
            let child = |c: usize, offset: DVec3, area: f64| Child {
                moment: moment(c),
                offset,
                mean: mean[c],
                area,
            };
            dipole[here] = V::parent_moment(child(a, da, wa), child(b, db, wb));
        }
        // Each first moment over area^(3/2), once every parent has summed its children's.
        for i in 0..n {
            if let Some(d) = dipole.get_mut(slot[i] as usize) {
                let area = shared.nodes[i].area;
                let scale = match area > 0.0 {
                    true => moment_scale(area).recip(),
                    false => 0.0,
                };
                *d = V::scaled(*d, scale);
            }
        }
        NodeField {
            mean,
            dipole,
            sh,
            slot: slot.clone(),
            clusters: clusters.clone(),
        }
    }
}

impl NodeField {
    /// Summarise a per-patch quantity on every node of `tree` (bottom-up), with the normal
    /// distributions of every inner node (a field any new point may gather from).
    pub(crate) fn new(tree: &PatchTree, mesh: &PatchMesh, patch_values: &[DVec3]) -> NodeField {
        NodeField::for_clusters(tree, mesh, |p| patch_values[p], &ClusterSlots::all(tree))
    }
}
