//! The part of a patch tree (`tree::PatchTree`) that fields and the solve read: each node's
//! area, centroid, children and patch range, the leaf order and the inner-node slots. A gather
//! needs the rest (boxes, normal cones, moments, normal distributions, representatives); the
//! solve iterates on precomputed rows and does not, so it runs on a [`Skeleton`] (about a fifth
//! of the tree) and the full tree is rebuilt from it afterwards, the same bits
//! (`PatchTree::from_skeleton`).
//!
//! Input: a patch tree (consumed: `PatchTree::into_skeleton`). Output: a [`Skeleton`].
//! [`Topology`] is what a node field reads, served by either; the operator reads a skeleton.

use glam::DVec3;
use std::sync::Arc;

pub const NO_CHILD: u32 = u32::MAX;

/// A node of the hierarchy: its areas. Its centroid, children and patch range are a tree's
/// `NodeBounds` (with its box and normal cone, as a visit reads them) or a [`Skeleton`]'s arrays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeNode {
    /// Area of the node's patches (a far-field source's full moments, needed by inner nodes
    /// only, are `PatchTree::moments`).
    pub area: f64,
    /// Area of the node's single-sided patches: only their backs absorb (a double-sided patch's
    /// back is its twin, counted on its own).
    pub single_sided_area: f64,
}

/// What a tree and its skeleton hold alike (borrowed).
pub struct Shared<'a> {
    pub nodes: &'a [TreeNode],
    /// Patch indices in leaf order.
    pub order: &'a [u32],
    /// Per node: its index among the inner nodes, `LEAF_SLOT` for leaves.
    pub slot: &'a Arc<[u32]>,
    /// Number of inner nodes (the length of per-inner-node arrays).
    pub inner_nodes: usize,
}

impl<'a> Shared<'a> {
    pub(crate) fn new(
        nodes: &'a [TreeNode],
        order: &'a [u32],
        slot: &'a Arc<[u32]>,
        inner_nodes: usize,
    ) -> Self {
        Shared {
            nodes,
            order,
            slot,
            inner_nodes,
        }
    }
}

/// A tree's nodes as fields and the operator read them (the root is node 0; children follow
/// their parent in pre-order).
pub trait Topology {
    fn shared(&self) -> Shared<'_>;
    fn centroid(&self, i: usize) -> DVec3;
    fn children(&self, i: usize) -> [u32; 2];
    /// The node's patches are `order[start..end]`.
    fn range(&self, i: usize) -> (u32, u32);

    fn is_leaf(&self, i: usize) -> bool {
        self.children(i)[0] == NO_CHILD
    }
}

/// A patch tree's [`Topology`] alone.
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    pub nodes: Vec<TreeNode>,
    pub centroid: Vec<DVec3>,
    pub children: Vec<[u32; 2]>,
    /// Per node: `[start, end)` into `order`.
    pub range: Vec<[u32; 2]>,
    /// Per node: does it hold curved clutter (decided while splitting, so kept for the rebuild).
    pub curved: Vec<bool>,
    /// Per node: found split by a wall (`PatchTree::mark_walled`), kept for the rebuild.
    pub walled: Vec<bool>,
    pub order: Vec<u32>,
    pub slot: Arc<[u32]>,
    pub inner_nodes: usize,
}

impl Topology for Skeleton {
    fn shared(&self) -> Shared<'_> {
        Shared::new(&self.nodes, &self.order, &self.slot, self.inner_nodes)
    }
    fn centroid(&self, i: usize) -> DVec3 {
        self.centroid[i]
    }
    fn children(&self, i: usize) -> [u32; 2] {
        self.children[i]
    }
    fn range(&self, i: usize) -> (u32, u32) {
        let [s, e] = self.range[i];
        (s, e)
    }
}
