//! The patch hierarchy: a binary tree over a set of patches whose nodes carry what a far-away
//! receiver needs to treat the node as one source (area moments, bounding sphere, normal cone).
//!
//! Input: the patch mesh and the subset of patches to organise (all of them for inter-reflection,
//! the emitting ones for direct light). Output: a [`PatchTree`].
//!
//! Construction is top-down and deterministic. A node holding both patches of curved clutter
//! (surfaces facing more than [`CURVED`] directions: chairs, columns) and patches of planar
//! surfaces is split into the two. A node of clutter ([`CURVED`] directions itself) or whose
//! normals spread over at most [`SPLIT_CONE`] is split at the middle of its centroids' longest
//! extent, so its children are compact in space whatever the tessellation. Other nodes (planes
//! facing several ways) are split by normal, so far-field nodes are nearly coplanar; where every
//! centroid lies at the middle, at the median (by normal unless the normals agree). Ties are
//! broken by patch index. Leaves hold one patch.
//!
//! Why planes and clutter apart, and clutter split at its middle: so a far-field test from
//! across the room accepts a chair as one node instead of refining a node that mixes chairs with
//! the room's planes. Where chairs are most of the patches (the open-plan floors), median splits
//! follow the chairs' tessellation rather than space and make such mixed nodes.
//! Invariants: `nodes[0]` is the root; children have larger indices than their parent (so a
//! reverse sweep visits children first); a node's patches are `order[range]`.

use super::silhouette;
pub use super::skeleton::{NO_CHILD, TreeNode};
use super::skeleton::{Shared, Skeleton, Topology};
use crate::geom::farfield::AreaMoments;
use crate::geom::sh;
use crate::patches::PatchMesh;
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// Normal-cone half-angle above which a node is split by normal rather than by position.
const SPLIT_CONE: f64 = 0.35; // ≈ 20°
/// A node is curved clutter when its patches face more than this many distinct directions
/// (quantised to about 7°): a handful of planes (a room, a desk) never is.
const CURVED: usize = 12;

/// Area quantiles of a node's representative patches ([`PatchTree::reps`]): two rays go to the
/// outer ones, a single ray to the median.
pub const REP_QUANTILES: [f64; 3] = [0.25, 0.5, 0.75];

/// An inner node's [`AreaMoments`] less its area and centroid, the second moments by their upper
/// triangle (they are symmetric exactly: sums of outer products of a vector with itself).
#[derive(Debug, Clone, Copy, PartialEq)]
struct InnerMoments {
    normal_sum: DVec3,
    /// xx, xy, xz, yy, yz, zz.
    second: [f64; 6],
}

impl InnerMoments {
    fn of(m: &AreaMoments) -> Self {
        let c = m.second.to_cols_array_2d();
        debug_assert!(c[0][1] == c[1][0] && c[0][2] == c[2][0] && c[1][2] == c[2][1]);
        InnerMoments {
            normal_sum: m.normal_sum,
            second: [c[0][0], c[0][1], c[0][2], c[1][1], c[1][2], c[2][2]],
        }
    }
}

/// Sort `slice` by zone (then patch) and return the zone boundary nearest its middle, when it
/// holds more than one zone.
fn split_by_zone(mesh: &PatchMesh, slice: &mut [u32]) -> Option<usize> {
    let zone = |p: u32| mesh.zone.get(p as usize).copied().unwrap_or(0);
    let first = zone(*slice.first()?);
    if slice.iter().all(|&p| zone(p) == first) {
        return None;
    }
    slice.sort_unstable_by_key(|&p| (zone(p), p));
    let half = slice.len() / 2;
    (1..slice.len())
        .filter(|&k| zone(slice[k - 1]) != zone(slice[k]))
        .min_by_key(|&k| k.abs_diff(half))
}

/// A node while the tree is built (kept afterwards as [`TreeNode`] and [`NodeBounds`]).
#[derive(Debug, Clone)]
struct Building {
    area: f64,
    centroid: DVec3,
    children: [u32; 2],
    single_sided_area: f64,
    /// Its patches face more than [`CURVED`] distinct directions (a tessellated chair, not a
    /// room's planes): only such nodes are split in space and treated as two-sided clusters.
    curved: bool,
    /// Range into `PatchTree::order`.
    start: u32,
    end: u32,
}

impl Building {
    fn is_leaf(&self) -> bool {
        self.children[0] == NO_CHILD
    }
}

/// A node's box and normal cone while the tree is built (kept afterwards only as
/// [`NodeBounds`]).
#[derive(Debug, Clone, Copy)]
pub struct Shape {
    /// Bounding box of the node's patches (the sphere around it is centred on the box).
    pub lo: DVec3,
    pub hi: DVec3,
    /// Unit axis and half-angle (rad) of a cone containing every patch normal.
    pub cone_axis: DVec3,
    pub cone_angle: f64,
}

/// The part of a [`TreeNode`] a gather reads at every node it visits, packed apart from the rest
/// (a third of the size) so traversals stay in cache: the same values, so the same answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeBounds {
    pub center: DVec3,
    /// Half the bounding box's extent.
    pub half: DVec3,
    pub radius: f64,
    /// Area centroid of the node's patches.
    pub centroid: DVec3,
    pub cone_axis: DVec3,
    /// 2·sin(half the cone's half-angle): how far a normal in the cone strays from its axis.
    pub cone_chord: f64,
    /// The cone's half-angle is 90° or more: the node may face any way.
    pub cone_wide: bool,
    pub curved: bool,
    /// Its patches lie in more than one zone (`transport::zones`) or a wall parts them
    /// ([`PatchTree::mark_walled`]): it is never one source.
    pub mixed: bool,
    /// A wall parts its two children ([`PatchTree::mark_walled`]).
    pub walled: bool,
    pub children: [u32; 2],
    pub start: u32,
    pub end: u32,
}

impl NodeBounds {
    fn of(node: &Building, shape: &Shape) -> Self {
        NodeBounds {
            center: (shape.lo + shape.hi) * 0.5,
            half: (shape.hi - shape.lo) * 0.5,
            radius: (shape.hi - shape.lo).length() * 0.5,
            centroid: node.centroid,
            cone_axis: shape.cone_axis,
            cone_chord: 2.0 * (shape.cone_angle / 2.0).sin(),
            cone_wide: shape.cone_angle >= std::f64::consts::FRAC_PI_2,
            curved: node.curved,
            mixed: false,
            walled: false,
            children: node.children,
            start: node.start,
            end: node.end,
        }
    }

    pub(crate) fn is_leaf(&self) -> bool {
        self.children[0] == NO_CHILD
    }

    /// Range of n·(x − p) over the node's bounding box: how far below/above the plane through
    /// `p` with normal `n` the node reaches. The range is narrowed by a rounding tolerance
    /// (10⁻⁹ of the distance) so a node that touches the plane counts as touching at every scale,
    /// not as crossing it at some and not at others.
    pub(crate) fn height_range(&self, p: DVec3, n: DVec3) -> (f64, f64) {
        let mid = n.dot(self.center - p);
        let half = n.abs().dot(self.half);
        let tol = 1e-9 * ((self.center - p).length() + self.radius);
        (mid - half + tol, mid + half - tol)
    }

    /// A bound on the form factor from `p` (unit normal `n`) to the part of the node above the
    /// plane through `p`, for a node whose centre lies at `dist` > its radius. Seen from `p`
    /// the bounding sphere is a cap of angular radius at most α = r/(dist − r), its centre at
    /// elevation β; the part above the plane is at most the segment of a disk of radius α cut
    /// off by the horizon, and no direction in it rises above β + α, so the form factor is at
    /// most that area × sin(β + α) / π. (The flat disk's area bounds the cap's: r/(dist − r)
    /// exceeds the cap's true angular radius by a factor 1/(1 − r/dist) and more.)
    pub(crate) fn horizon_bound(&self, p: DVec3, n: DVec3, dist: f64) -> f64 {
        use std::f64::consts::{FRAC_PI_2, PI};
        let alpha = self.radius / (dist - self.radius);
        let beta = (n.dot(self.center - p) / dist).clamp(-1.0, 1.0).asin();
        // The horizon cuts the disk at signed distance −β from its centre: t = −β/α in radii.
        let t = (-beta / alpha).clamp(-1.0, 1.0);
        let segment = alpha * alpha * (t.acos() - t * (1.0 - t * t).sqrt());
        segment * (beta + alpha).clamp(0.0, FRAC_PI_2).sin() / PI
    }

    /// `Some(true)` when every patch of the node faces point `p` (p is in front of each), `Some(false)`
    /// when every patch turns its back to it, `None` when mixed or too close to tell.
    pub(crate) fn facing(&self, p: DVec3) -> Option<bool> {
        let a = self.cone_axis;
        let (lo, hi) = self.height_range(p, a);
        // n·(p − x) for normals n within the cone around a: a·(p − x) ± |n − a|·|p − x|.
        let slack = self.cone_chord * ((p - self.center).length() + self.radius);
        if self.cone_wide {
            None
        } else if -hi - slack > 0.0 {
            Some(true)
        } else if -lo + slack < 0.0 {
            Some(false)
        } else {
            None
        }
    }
}

#[derive(Default)]
pub struct PatchTree {
    pub nodes: Vec<TreeNode>,
    /// The nodes while [`PatchTree::build`] runs (empty after).
    building: Vec<Building>,
    /// Per node: what every visit reads ([`NodeBounds`]).
    pub bounds: Vec<NodeBounds>,
    /// Patch indices in leaf order.
    pub order: Vec<u32>,
    /// Prefix sums of patch area in leaf order (`len = order.len() + 1`).
    pub area_prefix: Vec<f64>,
    /// Per node: its patches at the area quantiles [`REP_QUANTILES`], by their positions in
    /// leaf order, whose centroids and normals ([`PatchTree::rep`]) are the shadow-ray targets
    /// that stand for the node. Positions rather than points: 12 bytes a node instead of 144.
    pub reps: Vec<[u32; 3]>,
    /// Per position in leaf order: the patch's corners and normal, read by every leaf visit and
    /// representative ray. A copy in traversal order (96 bytes a patch): read through the patch
    /// and its three vertices, these scattered loads were a tenth of a floor's links stage.
    pub leaf_geom: Vec<LeafGeom>,
    /// Per inner node ([`PatchTree::slot`]): its normal distribution (`geom::sh::Dist`: axis
    /// bins, the rest to order 2), for far receivers that see its patches from both sides (a
    /// chair across the room). A leaf's is its patch's, [`leaf_sh`].
    pub normal_sh: Vec<sh::Dist>,
    /// Per inner node ([`PatchTree::slot`]): its area moments to second order beyond its area
    /// and centroid, which its node and bounds hold (a far-field source's geometry;
    /// [`PatchTree::moments`]).
    inner_moments: Vec<InnerMoments>,
    /// Per inner node ([`PatchTree::slot`]): the share of its front-facing area it does not
    /// hide from itself, along ±x, ±y, ±z (`silhouette`; 1 for nodes that are never two-sided
    /// clusters).
    pub visible: Vec<[f32; 6]>,
    /// Does any node hold curved clutter (so receivers may link to it as a two-sided cluster)?
    curved: bool,
    /// For trees with curved nodes, built on first use ([`PatchTree::own_hits`]): the patches
    /// as ray targets, and each patch's position in `order` (`u32::MAX` outside the tree), so a
    /// cluster's shadow ray can tell a blocker that is part of the cluster (its own far side,
    /// which `visible` accounts for) from one that is not.
    own_hits: std::sync::OnceLock<OwnHits>,
    /// Per node: its index among the inner nodes (in node order), [`LEAF_SLOT`] for leaves.
    /// Only inner nodes are far-field or cluster sources, so what only those read (a field's
    /// first moments and normal distributions) is stored per inner node: half the nodes.
    pub slot: std::sync::Arc<[u32]>,
    /// Number of inner nodes (the length of per-inner-node arrays).
    pub inner_nodes: usize,
}

/// A patch's geometry as gathers read it ([`PatchTree::leaf_geom`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeafGeom {
    /// Its corners, counter-clockwise seen from the front (`Patch::corners`).
    pub corners: [DVec3; 3],
    /// Its unit normal.
    pub normal: DVec3,
}

/// A BVH over every patch of a mesh, and each patch's position in a tree's leaf order
/// (`u32::MAX` outside the tree).
pub type OwnHits = (crate::visibility::Occluder, Vec<u32>);

fn own_hits(mesh: &PatchMesh, order: &[u32]) -> OwnHits {
    let tris: Vec<[DVec3; 3]> = (mesh.patches.iter())
        .map(|p| p.corners(&mesh.receivers))
        .collect();
    let mut rank = vec![u32::MAX; mesh.patches.len()];
    for (k, &p) in order.iter().enumerate() {
        rank[p as usize] = k as u32;
    }
    (
        crate::visibility::Occluder::from_triangles(&tris, false),
        rank,
    )
}

/// [`PatchTree::slot`] of a leaf.
pub const LEAF_SLOT: u32 = u32::MAX;

impl PatchTree {
    /// Does any node hold curved clutter (so receivers may link to it as a two-sided cluster)?
    pub(crate) fn has_curved(&self) -> bool {
        self.curved
    }

    /// [`PatchTree::own_hits`](field) of a tree with curved nodes over `mesh` (the mesh it was
    /// built over), built on first use (a BVH over every patch; the build is single-threaded,
    /// obvhs having no `parallel` feature here, so threads that ask meanwhile wait for it and
    /// no rayon job can re-enter it).
    pub(crate) fn own_hits(&self, mesh: &PatchMesh) -> Option<&OwnHits> {
        self.curved
            .then(|| self.own_hits.get_or_init(|| own_hits(mesh, &self.order)))
    }

    /// Build the hierarchy over `subset` (patch indices) of `mesh`.
    pub(crate) fn build(mesh: &PatchMesh, subset: Vec<u32>) -> Self {
        let mut tree = PatchTree::unbuilt(subset);
        if tree.order.is_empty() {
            return tree;
        }
        tree.building.reserve(2 * tree.order.len());
        let leaf = leaf_moments(mesh);
        let n = tree.order.len() as u32;
        tree.split(mesh, &leaf, &clutter_patches(mesh), 0, n);
        let mut inner = 0;
        tree.slot = tree
            .building
            .iter()
            .map(|node| match node.is_leaf() {
                true => LEAF_SLOT,
                false => {
                    inner += 1;
                    inner - 1
                }
            })
            .collect();
        tree.inner_nodes = inner as usize;
        tree.assemble(mesh, &leaf);
        tree
    }

    /// The tree's [`Skeleton`]; the rest is freed before the skeleton's arrays are made.
    pub(crate) fn into_skeleton(mut self) -> Skeleton {
        let nodes = std::mem::take(&mut self.nodes);
        let bounds = std::mem::take(&mut self.bounds);
        let order = std::mem::take(&mut self.order);
        let slot = std::mem::replace(&mut self.slot, std::sync::Arc::from([]));
        let inner_nodes = self.inner_nodes;
        drop(self);
        Skeleton {
            nodes,
            centroid: bounds.iter().map(|b| b.centroid).collect(),
            children: bounds.iter().map(|b| b.children).collect(),
            range: bounds.iter().map(|b| [b.start, b.end]).collect(),
            curved: bounds.iter().map(|b| b.curved).collect(),
            walled: bounds.iter().map(|b| b.walled).collect(),
            order,
            slot,
            inner_nodes,
        }
    }

    /// The tree `skeleton` was taken from, over the same `mesh`: its nodes as they were split,
    /// everything else computed again by the same sums as [`PatchTree::build`] (the same bits).
    pub(crate) fn from_skeleton(skeleton: Skeleton, mesh: &PatchMesh) -> Self {
        let Skeleton {
            nodes,
            centroid,
            children,
            range,
            curved,
            walled,
            order,
            slot,
            inner_nodes,
        } = skeleton;
        // Summed again below: freed before the rebuild's own arrays are made.
        drop((nodes, centroid));
        let mut tree = PatchTree::unbuilt(order);
        if tree.order.is_empty() {
            return tree;
        }
        tree.building = (children.iter().zip(&range).zip(&curved))
            .map(|((&children, &[start, end]), &curved)| Building {
                area: 0.0,
                centroid: DVec3::ZERO,
                children,
                single_sided_area: 0.0,
                curved,
                start,
                end,
            })
            .collect();
        drop((children, range, curved));
        tree.slot = slot;
        tree.inner_nodes = inner_nodes;
        tree.assemble(mesh, &leaf_moments(mesh));
        if walled.iter().any(|&w| w) {
            tree.set_walled(&walled);
        }
        tree
    }

    /// A tree over `order` with no nodes yet.
    fn unbuilt(order: Vec<u32>) -> Self {
        PatchTree {
            nodes: Vec::new(),
            building: Vec::new(),
            bounds: Vec::new(),
            order,
            area_prefix: Vec::new(),
            reps: Vec::new(),
            leaf_geom: Vec::new(),
            normal_sh: Vec::new(),
            inner_moments: Vec::new(),
            visible: Vec::new(),
            curved: false,
            own_hits: std::sync::OnceLock::new(),
            slot: std::sync::Arc::from([]),
            inner_nodes: 0,
        }
    }

    /// Everything but the split, from the split nodes (`building`, `order`, `slot`): moments,
    /// boxes, cones and normal distributions bottom-up, visible shares, representatives.
    fn assemble(&mut self, mesh: &PatchMesh, leaf: &[AreaMoments]) {
        let shapes = self.finish(mesh, leaf);
        let building = std::mem::take(&mut self.building);
        self.bounds = (building.iter().zip(&shapes))
            .map(|(n, s)| NodeBounds::of(n, s))
            .collect();
        self.nodes = (building.iter())
            .map(|n| TreeNode {
                area: n.area,
                single_sided_area: n.single_sided_area,
            })
            .collect();
        drop(building);
        self.mark_mixed(mesh);
        self.visible = visible_shares(self, mesh, &shapes);
        drop(shapes);
        self.curved = self.bounds.iter().any(|n| n.curved);
        let mut acc = 0.0;
        self.area_prefix.push(0.0);
        for &p in &self.order {
            acc += mesh.patches[p as usize].area;
            self.area_prefix.push(acc);
        }
        self.reps = (0..self.nodes.len())
            .map(|i| REP_QUANTILES.map(|q| self.representative(i, q)))
            .collect();
        self.leaf_geom = (self.order.iter())
            .map(|&p| {
                let patch = &mesh.patches[p as usize];
                LeafGeom {
                    corners: patch.corners(&mesh.receivers),
                    normal: patch.normal,
                }
            })
            .collect();
    }

    /// Mark the nodes whose patches lie in more than one zone (children before parents).
    fn mark_mixed(&mut self, mesh: &PatchMesh) {
        if mesh.zone.is_empty() {
            return;
        }
        let mut zone = vec![0u32; self.bounds.len()];
        for i in (0..self.bounds.len()).rev() {
            let b = self.bounds[i];
            if b.is_leaf() {
                zone[i] = mesh.zone[self.order[b.start as usize] as usize];
                continue;
            }
            let [l, r] = b.children.map(|c| c as usize);
            let mixed = self.bounds[l].mixed || self.bounds[r].mixed || zone[l] != zone[r];
            self.bounds[i].mixed = mixed;
            zone[i] = zone[l];
        }
    }

    /// Mark the inner nodes whose two children a wall separates, and so their ancestors, mixed
    /// (never one source, like nodes of two zones). Zones part rooms no opening joins; this
    /// parts rooms an open door joins (one slab under both, a partition's two faces): a cluster
    /// holding the bright floor of one room and the dark floor of the next otherwise shows the
    /// dark room the bright one's light wherever one of its representatives is in sight (the
    /// building sample's office lit through its door read +8.4 % against RADIANCE).
    ///
    /// The evidence: rays between each of the children's three representatives, each end lifted
    /// off its patch to 0.45 of the way to the surface its normal meets (the middle of the room
    /// it faces), all blocked. A wall blocks all three; furniture lower than the room's middle
    /// does not. Pairs nearer than `room` (m) to each other that face spaces under it
    /// across (under a desk, between a screen's faces, a crevice) are not tested: an open-plan
    /// floor has thousands astride desk panels and chair feet, and marking them doubled its
    /// links. Curved clutter (chairs) is one
    /// object: not tested. Deterministic: fixed points, at most nine rays per inner node.
    pub(crate) fn mark_walled(&mut self, occ: &Occluder, room: f64) {
        // 0.45 of the way to the surface a point's normal meets (`room` when none).
        let lift = |p: DVec3, n: DVec3| {
            0.45 * (occ.closest(p + n * (4.0 * occ.epsilon), n)).map_or(room, |h| h.distance)
        };
        let walled: Vec<bool> = (0..self.bounds.len())
            .into_par_iter()
            .map(|i| {
                let b = &self.bounds[i];
                if b.is_leaf() || b.mixed || b.curved {
                    return false;
                }
                let [l, r] = b.children.map(|k| k as usize);
                (0..REP_QUANTILES.len()).all(|k| {
                    let ((a, na), (c, nc)) = (self.rep(l, k), self.rep(r, k));
                    let (la, lc) = (lift(a, na), lift(c, nc));
                    let roomy = la.min(lc) >= 0.45 * room || a.distance(c) >= room;
                    roomy && !occ.clear(a + na * la, DVec3::ZERO, c + nc * lc, DVec3::ZERO)
                })
            })
            .collect();
        self.set_walled(&walled);
    }

    /// Set nodes walled (and so mixed) from a flag per node, with their ancestors mixed.
    fn set_walled(&mut self, walled: &[bool]) {
        for i in (0..self.bounds.len()).rev() {
            let b = self.bounds[i];
            self.bounds[i].walled |= walled[i];
            if !b.is_leaf() {
                let [l, r] = b.children.map(|c| c as usize);
                let below = self.bounds[l].mixed || self.bounds[r].mixed;
                self.bounds[i].mixed |= walled[i] || below;
            }
        }
    }

    /// Centroid and unit normal of node `i`'s representative `k` (at area quantile
    /// `REP_QUANTILES[k]`).
    pub(crate) fn rep(&self, i: usize, k: usize) -> (DVec3, DVec3) {
        let g = &self.leaf_geom[self.reps[i][k] as usize];
        let c = g.corners;
        ((c[0] + c[1] + c[2]) / 3.0, g.normal)
    }

    /// The patch at position `k` of leaf order's geometry.
    pub(crate) fn leaf(&self, k: u32) -> &LeafGeom {
        &self.leaf_geom[k as usize]
    }

    /// Inner node `i`'s area moments (panics on a leaf: leaves are never far-field sources).
    pub(crate) fn moments(&self, i: usize) -> AreaMoments {
        let m = &self.inner_moments[self.slot[i] as usize];
        let [xx, xy, xz, yy, yz, zz] = m.second;
        AreaMoments {
            area: self.nodes[i].area,
            centroid: self.bounds[i].centroid,
            normal_sum: m.normal_sum,
            second: glam::DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz]),
        }
    }

    /// Node `i`'s normal distribution: its own for an inner node, its patch's for a leaf.
    pub fn node_sh(&self, mesh: &PatchMesh, i: usize) -> sh::Dist {
        match self.slot[i] {
            LEAF_SLOT => leaf_sh(&mesh.patches[self.order[self.bounds[i].start as usize] as usize]),
            s => self.normal_sh[s as usize],
        }
    }

    /// [`PatchTree::node_sh`] while the tree is built.
    fn building_sh(&self, mesh: &PatchMesh, i: usize) -> sh::Dist {
        match self.slot[i] {
            LEAF_SLOT => {
                leaf_sh(&mesh.patches[self.order[self.building[i].start as usize] as usize])
            }
            s => self.normal_sh[s as usize],
        }
    }

    /// The position in leaf order of node `i`'s patch at area quantile `q`.
    fn representative(&self, i: usize, q: f64) -> u32 {
        let node = &self.bounds[i];
        let (a0, a1) = (
            self.area_prefix[node.start as usize],
            self.area_prefix[node.end as usize],
        );
        let target = a0 + (a1 - a0) * q;
        let k = self.area_prefix[node.start as usize..=node.end as usize]
            .partition_point(|&a| a <= target)
            .saturating_sub(1)
            .min((node.end - node.start - 1) as usize);
        node.start + k as u32
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Per node: does every one of its patches pass `patch` (given a patch index)? `None` when
    /// no patch does, so callers keep their plain path.
    pub(crate) fn nodes_where(&self, patch: impl Fn(usize) -> bool) -> Option<Vec<bool>> {
        let mut passing = Vec::with_capacity(self.order.len() + 1);
        passing.push(0u32);
        for &p in &self.order {
            passing.push(passing[passing.len() - 1] + patch(p as usize) as u32);
        }
        if passing[passing.len() - 1] == 0 {
            return None;
        }
        let all =
            |n: &NodeBounds| passing[n.end as usize] - passing[n.start as usize] == n.end - n.start;
        Some(self.bounds.iter().map(all).collect())
    }

    /// Create the node for `order[start..end]` and its subtree (pre-order); returns its index.
    fn split(
        &mut self,
        mesh: &PatchMesh,
        leaf: &[AreaMoments],
        clutter: &[bool],
        start: u32,
        end: u32,
    ) -> u32 {
        let index = self.building.len() as u32;
        self.building.push(Building {
            area: 0.0,
            centroid: DVec3::ZERO,
            single_sided_area: 0.0,
            curved: false,
            children: [NO_CHILD; 2],
            start,
            end,
        });
        if end - start <= 1 {
            return index;
        }
        let slice = &mut self.order[start as usize..end as usize];
        let mut mid = slice.len() / 2;
        let by = |slice: &mut [u32], by_normal: bool| {
            let key = split_key(mesh, leaf, slice, by_normal);
            slice.select_nth_unstable_by(mid, |&a, &b| key(a).total_cmp(&key(b)).then(a.cmp(&b)));
        };
        let curved = curved(mesh, slice);
        self.building[index as usize].curved = curved;
        let flat = spread(mesh, slice) <= SPLIT_CONE;
        let planar = slice.iter().filter(|&&p| !clutter[p as usize]).count();
        if let Some(k) = split_by_zone(mesh, slice) {
            // Zones apart first: no node below holds patches from both sides of a wall.
            mid = k;
        } else if planar > 0 && planar < slice.len() {
            // Planes and clutter apart (planes first).
            mid = partition(slice, |p| !clutter[p as usize]);
        } else if let Some(k) = (curved || flat)
            .then(|| split_in_space_at_middle(mesh, leaf, slice))
            .flatten()
        {
            mid = k;
        } else {
            // Planes facing several ways: by normal (far-field nodes nearly coplanar). A node
            // whose centroids all lie at the middle (up to rounding): at the median, in space
            // when its normals agree.
            by(slice, !flat);
        }
        let m = start + mid as u32;
        let left = self.split(mesh, leaf, clutter, start, m);
        let right = self.split(mesh, leaf, clutter, m, end);
        self.building[index as usize].children = [left, right];
        index
    }

    /// Fill in moments and normal distributions bottom-up; returns every node's box and cone.
    fn finish(&mut self, mesh: &PatchMesh, leaf: &[AreaMoments]) -> Vec<Shape> {
        let unset = Shape {
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            cone_axis: DVec3::Y,
            cone_angle: 0.0,
        };
        let mut shapes = vec![unset; self.building.len()];
        self.normal_sh = vec![[0.0; sh::DIST]; self.inner_nodes];
        let mut inner_moments = vec![AreaMoments::ZERO; self.inner_nodes];
        // A child's moments: its patch's for a leaf.
        let moments_of = |tree: &Self, inner: &[AreaMoments], c: usize| match tree.slot[c] {
            LEAF_SLOT => leaf[tree.order[tree.building[c].start as usize] as usize],
            s => inner[s as usize],
        };
        for i in (0..self.building.len()).rev() {
            let node = &self.building[i];
            if node.is_leaf() {
                let p = self.order[node.start as usize] as usize;
                let patch = &mesh.patches[p];
                let corners = patch.corners(&mesh.receivers);
                let (lo, hi) = bounds(corners.iter().copied());
                shapes[i] = Shape {
                    lo,
                    hi,
                    cone_axis: patch.normal,
                    cone_angle: 0.0,
                };
                let node = &mut self.building[i];
                node.area = leaf[p].area;
                node.centroid = leaf[p].centroid;
                node.single_sided_area = if patch.double_sided { 0.0 } else { patch.area };
            } else {
                let [ia, ib] = node.children.map(|c| c as usize);
                let [a, b] = [&self.building[ia], &self.building[ib]];
                let [sa, sb] = [shapes[ia], shapes[ib]];
                let moments = moments_of(self, &inner_moments, ia).combine(&moments_of(
                    self,
                    &inner_moments,
                    ib,
                ));
                let axis = moments.normal_sum.try_normalize().unwrap_or(sa.cone_axis);
                let spread =
                    |c: &Shape| c.cone_axis.dot(axis).clamp(-1.0, 1.0).acos() + c.cone_angle;
                let cone_angle = spread(&sa).max(spread(&sb)).min(std::f64::consts::PI);
                shapes[i] = Shape {
                    lo: sa.lo.min(sb.lo),
                    hi: sa.hi.max(sb.hi),
                    cone_axis: axis,
                    cone_angle,
                };
                let single = a.single_sided_area + b.single_sided_area;
                let (da, db) = (self.building_sh(mesh, ia), self.building_sh(mesh, ib));
                self.normal_sh[self.slot[i] as usize] = std::array::from_fn(|k| da[k] + db[k]);
                let node = &mut self.building[i];
                node.single_sided_area = single;
                node.area = moments.area;
                node.centroid = moments.centroid;
                inner_moments[self.slot[i] as usize] = moments;
            }
        }
        self.inner_moments = inner_moments.iter().map(InnerMoments::of).collect();
        shapes
    }
}

/// Visible shares ([`silhouette`]) of every inner node, in node order (1 for nodes that are not
/// curved: they are never two-sided clusters).
fn visible_shares(tree: &PatchTree, mesh: &PatchMesh, shapes: &[Shape]) -> Vec<[f32; 6]> {
    tree.bounds
        .par_iter()
        .zip(shapes)
        .filter(|(node, _)| !node.is_leaf())
        .map(|(node, shape)| match node.curved {
            false => [1.0; 6],
            true => {
                let patches = &tree.order[node.start as usize..node.end as usize];
                silhouette::shares(mesh, patches, shape.lo, shape.hi)
            }
        })
        .collect()
}

impl Topology for PatchTree {
    fn shared(&self) -> Shared<'_> {
        Shared::new(&self.nodes, &self.order, &self.slot, self.inner_nodes)
    }
    fn centroid(&self, i: usize) -> DVec3 {
        self.bounds[i].centroid
    }
    fn children(&self, i: usize) -> [u32; 2] {
        self.bounds[i].children
    }
    fn range(&self, i: usize) -> (u32, u32) {
        (self.bounds[i].start, self.bounds[i].end)
    }
}

/// Every patch's area moments (a leaf's).
fn leaf_moments(mesh: &PatchMesh) -> Vec<AreaMoments> {
    (mesh.patches.iter())
        .map(|p| AreaMoments::triangle(&p.corners(&mesh.receivers), p.area, p.normal))
        .collect()
}

/// A leaf's normal distribution: its patch's area at its normal.
pub(crate) fn leaf_sh(patch: &crate::patches::Patch) -> sh::Dist {
    sh::dist_point(patch.normal, patch.area)
}

fn bounds(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// For every patch of the mesh: does it belong to curved clutter — a surface (both sides
/// together) whose patches face more than [`CURVED`] distinct directions (a chair, a column)?
fn clutter_patches(mesh: &PatchMesh) -> Vec<bool> {
    let surfaces = mesh.groups.iter().map(|g| g.surface + 1).max().unwrap_or(0);
    let mut patches: Vec<Vec<u32>> = vec![Vec::new(); surfaces];
    for (i, p) in mesh.patches.iter().enumerate() {
        patches[mesh.groups[p.group as usize].surface].push(i as u32);
    }
    let curved: Vec<bool> = patches.iter().map(|ps| curved(mesh, ps)).collect();
    mesh.patches
        .iter()
        .map(|p| curved[mesh.groups[p.group as usize].surface])
        .collect()
}

/// Split a node in space at the middle of its centroids' longest extent (not at the median
/// patch): returns the first part's length after reordering `patches`, or `None` when every
/// centroid lies on one side. Clutter is tessellated far more finely in some places than in
/// others (a chair's castors against its seat), and a median split followed the tessellation
/// rather than the space the far-field test measures.
fn split_in_space_at_middle(
    mesh: &PatchMesh,
    leaf: &[AreaMoments],
    patches: &mut [u32],
) -> Option<usize> {
    // Keys run over 0..=2³² across the extent (quantised as for every spatial split).
    let key = split_key(mesh, leaf, patches, false);
    let k = partition(patches, |p| key(p) < 2_147_483_648.0);
    (k > 0 && k < patches.len()).then_some(k)
}

/// Reorder `patches` so that those `first` accepts come first, each side in its former order;
/// returns how many it accepted: linear, and as deterministic as the order it was given.
fn partition(patches: &mut [u32], first: impl Fn(u32) -> bool) -> usize {
    let (front, back): (Vec<u32>, Vec<u32>) = patches.iter().partition(|&&p| first(p));
    patches[..front.len()].copy_from_slice(&front);
    patches[front.len()..].copy_from_slice(&back);
    front.len()
}

/// Do the patches face more than [`CURVED`] distinct directions (normals quantised to 1/8)?
fn curved(mesh: &PatchMesh, patches: &[u32]) -> bool {
    let mut seen: Vec<[i8; 3]> = Vec::with_capacity(CURVED + 1);
    for &p in patches {
        let n = mesh.patches[p as usize].normal * 8.0;
        let q = [n.x.round() as i8, n.y.round() as i8, n.z.round() as i8];
        if !seen.contains(&q) {
            seen.push(q);
            if seen.len() > CURVED {
                return true;
            }
        }
    }
    false
}

/// Largest angle (rad) between a patch normal and the mean normal (π when they cancel).
fn spread(mesh: &PatchMesh, patches: &[u32]) -> f64 {
    let normal = |p: u32| mesh.patches[p as usize].normal;
    let mean = patches
        .iter()
        .map(|&p| normal(p))
        .sum::<DVec3>()
        .normalize_or_zero();
    if mean == DVec3::ZERO {
        return std::f64::consts::PI;
    }
    patches
        .iter()
        .map(|&p| normal(p).dot(mean).clamp(-1.0, 1.0).acos())
        .fold(0.0, f64::max)
}

/// The sort key that splits `patches`: a normal component (`by_normal`), else the centroid
/// coordinate along the longest axis of the centroids' bounds.
fn split_key<'a>(
    mesh: &'a PatchMesh,
    leaf: &'a [AreaMoments],
    patches: &[u32],
    by_normal: bool,
) -> impl Fn(u32) -> f64 + 'a {
    let normal = |p: u32| mesh.patches[p as usize].normal;
    let centroid = |p: u32| leaf[p as usize].centroid;
    let (axis, origin, span) = if by_normal {
        let (nlo, nhi) = bounds(patches.iter().map(|&p| normal(p)));
        (longest_axis(nhi - nlo), -1.0, 2.0)
    } else {
        let (lo, hi) = bounds(patches.iter().map(|&p| centroid(p)));
        let axis = longest_axis(hi - lo);
        (axis, lo[axis], (hi[axis] - lo[axis]).max(1e-300))
    };
    // Keys are quantised relative to the node's extent, so coordinates that are equal up to
    // rounding sort as equal (then by patch index) whatever the scene's scale: the hierarchy does
    // not change when a room is modelled in millimetres instead of metres.
    move |p: u32| {
        let v = if by_normal { normal(p) } else { centroid(p) };
        ((v[axis] - origin) / span * 4_294_967_296.0).round()
    }
}

/// The axis of the largest extent; extents equal within 10⁻⁹ count as equal (lower axis wins),
/// so rounding at another scale does not change the choice.
fn longest_axis(extent: DVec3) -> usize {
    let m = extent.max_element() * (1.0 - 1e-9);
    if extent.x >= m {
        0
    } else if extent.y >= m {
        1
    } else {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::geom::lambert;

    /// [`NodeBounds::horizon_bound`] against Lambert's exact form factor of what rises above the
    /// receiver's plane: a 1 m square facing the receiver from 10 m, the receiver's plane tilted
    /// so the horizon crosses it at every height. The bound holds, and where the square's centre
    /// is above the horizon it is within 8× the exact value (not vacuous).
    #[test]
    fn horizon_bound_bounds_what_rises_above_the_plane() {
        let square = [
            DVec3::new(-0.5, -0.5, -10.0),
            DVec3::new(0.5, -0.5, -10.0),
            DVec3::new(0.5, 0.5, -10.0),
            DVec3::new(-0.5, 0.5, -10.0),
        ];
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.quad("square", square, grey);
        let mesh = crate::patches::build(&b.build(), 2.0, None);
        let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        let root = &tree.bounds[0];
        let dist = root.center.length();
        for k in -12..=12 {
            // The plane through the origin meets the square's plane at height h.
            let h = k as f64 * 0.05;
            let n = DVec3::new(0.0, 10.0, h).normalize();
            let exact = lambert::form_factor(DVec3::ZERO, n, &square);
            let bound = root.horizon_bound(DVec3::ZERO, n, dist);
            assert!(
                bound >= exact,
                "h {h}: bound {bound:e} below exact {exact:e}"
            );
            if h < 0.0 {
                assert!(
                    bound < 8.0 * exact,
                    "h {h}: bound {bound:e}, exact {exact:e}"
                );
            }
        }
    }

    /// Planes and curved clutter go to separate subtrees, and clutter is split at the middle of
    /// its extent: a finely and a coarsely tessellated ball 8 m apart over a floor become two
    /// tight nodes. (Split at the median patch, the coarse ball and half of the fine one shared a
    /// node 8 m across, which the far-field test must refine from anywhere in the room.)
    #[test]
    fn clutter_is_apart_from_planes_and_split_in_space() {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.floor("floor", 6.0, 0.0, grey);
        b.ball("fine", DVec3::new(-4.0, 1.0, 0.0), 0.3, (16, 24), grey);
        b.ball("coarse", DVec3::new(4.0, 1.0, 0.0), 0.3, (6, 8), grey);
        let mesh = crate::patches::build(&b.build(), 1.0, None);
        let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        let surface = |p: u32| mesh.groups[mesh.patches[p as usize].group as usize].surface;
        let floor = surface(tree.order[0]);
        let patches = |i: u32| {
            let n = &tree.bounds[i as usize];
            &tree.order[n.start as usize..n.end as usize]
        };
        let [planes, clutter] = tree.bounds[0].children;
        assert!(patches(planes).iter().all(|&p| surface(p) == floor));
        assert!(patches(clutter).iter().all(|&p| surface(p) != floor));
        let floor_patches = (0..mesh.patches.len() as u32).filter(|&p| surface(p) == floor);
        assert_eq!(patches(planes).len(), floor_patches.count());
        for ball in tree.bounds[clutter as usize].children {
            let node = &tree.bounds[ball as usize];
            assert!(
                node.radius < 1.0,
                "a ball's node has radius {}",
                node.radius
            );
            let first = surface(patches(ball)[0]);
            assert!(patches(ball).iter().all(|&p| surface(p) == first));
        }
    }

    /// The solve holds only a tree's skeleton; the tree rebuilt from it is the tree, every
    /// array bit for bit (on planes and curved clutter, so normal distributions, moments and
    /// visible shares are all exercised).
    #[test]
    fn a_tree_rebuilt_from_its_skeleton_is_the_same_tree() {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.floor("floor", 6.0, 0.0, grey);
        b.ball("fine", DVec3::new(-2.0, 1.0, 0.5), 0.3, (12, 16), grey);
        b.ball("coarse", DVec3::new(2.0, 1.0, 0.0), 0.4, (6, 8), grey);
        let mesh = crate::patches::build(&b.build(), 0.7, None);
        let built = || PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        let tree = built();
        assert!(tree.has_curved() && tree.inner_nodes > 100);
        let skeleton = built().into_skeleton();
        assert_eq!(skeleton.nodes.len(), tree.nodes.len());
        let again = PatchTree::from_skeleton(skeleton, &mesh);
        assert_eq!(again.nodes, tree.nodes);
        assert_eq!(again.bounds, tree.bounds);
        assert_eq!(again.order, tree.order);
        assert_eq!(again.area_prefix, tree.area_prefix);
        assert_eq!(again.reps, tree.reps);
        assert_eq!(again.normal_sh, tree.normal_sh);
        assert_eq!(again.inner_moments, tree.inner_moments);
        assert_eq!(again.visible, tree.visible);
        assert_eq!(again.slot, tree.slot);
        assert_eq!(again.inner_nodes, tree.inner_nodes);
        assert_eq!(again.curved, tree.curved);
        assert!(again.building.is_empty());
    }

    #[test]
    fn no_unmixed_node_holds_both_sides_of_a_partition_in_a_building() {
        // The building floor: offices S1 and S2 share a slab, a ceiling and a 12 cm partition
        // with no opening; both open onto the corridor, so they are one zone. Every node holding
        // patches that face into S1 and patches that face into S2 must be mixed (never one
        // source), or S2 sees S1's light wherever one of its representatives is in sight.
        use crate::fixtures::building_floor::{building_floor, rooms};
        let scene = building_floor();
        let occ = Occluder::build(&scene, Default::default());
        let contacts = crate::contacts::find(&scene, 0.05, &occ);
        let mut mesh = crate::patches::build_cut(&scene, 0.4, None, &contacts);
        mesh.zone = crate::transport::zones::of(&mesh);
        let mut tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        let rooms = rooms();
        let room_of = |p: u32| {
            let patch = &mesh.patches[p as usize];
            let c = patch.corners(&mesh.receivers);
            let front = (c[0] + c[1] + c[2]) / 3.0 + patch.normal * 0.05;
            (rooms.iter().take(2)).position(|r| front.cmpgt(r.lo).all() && front.cmplt(r.hi).all())
        };
        let both = |tree: &PatchTree| -> Vec<usize> {
            (0..tree.bounds.len())
                .filter(|&i| {
                    let b = &tree.bounds[i];
                    let sides = tree.order[b.start as usize..b.end as usize]
                        .iter()
                        .filter_map(|&p| room_of(p))
                        .fold([false; 2], |mut s, k| {
                            s[k] = true;
                            s
                        });
                    sides == [true, true] && !b.mixed
                })
                .collect()
        };
        let before = both(&tree).len();
        tree.mark_walled(&occ, 1.0);
        let after = both(&tree);
        assert!(before > 0, "the fixture has nodes astride the partition");
        assert!(
            after.is_empty(),
            "{} of {before} still unmixed",
            after.len()
        );
    }
}
