//! The inter-reflection operator at the receivers, built once and applied at every solver step.
//!
//! Input: a [`Gatherer`] over the tree of all patches, and the receivers. Output: [`ReceiverLinks`]
//! in compressed rows: receiver r gathers E_r = Σ coeff·B(node) over its row's leaf links (one
//! patch each, 8 bytes) and far-field and cluster links ([`Link`]).
//!
//! Closure: a receiver inside a closed space sees geometry in every direction, so its true
//! coverage is exactly 1; the far-field expansion and sampled visibility leave it off by a little,
//! and at reflectance 0.99 a per-bounce loss of 0.1 % costs 10 % of the answer. Rows of closed
//! receivers are therefore normalised to coverage 1 (energy conservation per bounce). A receiver is
//! closed when its coverage is ≥ 0.999, or when none of 64 stratified cosine-weighted escape rays
//! leaves the scene (a lower coverage then comes from sampled visibility, e.g. where objects
//! touch). A receiver that sees (almost) nothing (coverage ≤ 0.05: pressed against another face)
//! is left alone. Open receivers keep their rows as computed.

use super::field::{ClusterSlots, NodeField};
use super::gather::{Gatherer, SharedRays};
use super::link::{Leaf, Link};
use crate::geom::samples;
use crate::patches::Vertex;
use glam::DVec3;
use rayon::prelude::*;

pub struct ReceiverLinks {
    /// The rows of receivers `k·CHUNK .. (k+1)·CHUNK` in chunk k, each chunk's links in one
    /// exactly sized allocation: the rows are never copied into one array, whose doubling (and
    /// the slack of rows grown link by link) set the bake's peak memory on large scenes.
    chunks: Vec<RowChunk>,
    /// Coverage before normalisation.
    pub coverage: Vec<f32>,
    /// Fraction covered by back faces (after normalisation for closed receivers).
    pub back: Vec<f32>,
    /// Rows normalised because the receiver is enclosed.
    pub closed: Vec<bool>,
    /// Fraction covered by black nodes, which get no links (after normalisation, like `back`);
    /// empty when the gatherer has no black nodes ([`ReceiverLinks::dark`]).
    dark: Vec<f32>,
    /// The nodes cluster links name: the only ones whose normal distributions the solver's
    /// node fields need.
    pub clusters: ClusterSlots,
}

/// The rows of [`CHUNK`] consecutive receivers: row j is `leaves[leaf_at[j]..leaf_at[j + 1]]`
/// and `far[far_at[j]..far_at[j + 1]]`.
struct RowChunk {
    leaf_at: Vec<u32>,
    leaves: Vec<Leaf>,
    far_at: Vec<u32>,
    far: Vec<Link>,
}

/// One receiver's row: its leaf links and the rest (far-field and cluster links).
#[derive(Clone, Copy)]
pub struct RowRef<'a> {
    pub leaves: &'a [Leaf],
    pub far: &'a [Link],
}

/// Rows are built in parallel over fixed chunks, kept in order: deterministic.
const CHUNK: usize = 64;

impl ReceiverLinks {
    pub fn build(gatherer: &Gatherer, receivers: &[Vertex]) -> Self {
        type Built = (RowChunk, Vec<(f32, f32, bool, f32)>);
        let built: Vec<Built> = receivers
            .par_chunks(CHUNK)
            .map(|chunk| {
                let rows: Vec<Row> = chunk
                    .iter()
                    .map(|r| gather_row(gatherer, r.point, r.normal))
                    .collect();
                let is_leaf = |l: &&Link| l.coeff > 0.0 && l.grad == [0.0; 3];
                let all = rows.iter().flat_map(|r| &r.links);
                let n_leaves = all.clone().filter(is_leaf).count();
                let mut leaves = Vec::with_capacity(n_leaves);
                let mut far = Vec::with_capacity(all.count() - n_leaves);
                let (mut leaf_at, mut far_at) = (vec![0], vec![0]);
                for row in &rows {
                    for l in &row.links {
                        if is_leaf(&l) {
                            leaves.push(Leaf {
                                node: l.node,
                                coeff: l.coeff,
                            });
                        } else {
                            far.push(*l);
                        }
                    }
                    leaf_at.push(leaves.len() as u32);
                    far_at.push(far.len() as u32);
                }
                let stats = rows
                    .iter()
                    .map(|r| (r.coverage as f32, r.back as f32, r.closed, r.dark as f32))
                    .collect();
                let chunk = RowChunk {
                    leaf_at,
                    leaves,
                    far_at,
                    far,
                };
                (chunk, stats)
            })
            .collect();
        let mut chunks = Vec::with_capacity(built.len());
        let mut coverage = Vec::with_capacity(receivers.len());
        let mut back = Vec::with_capacity(receivers.len());
        let mut closed = Vec::with_capacity(receivers.len());
        let mut dark = Vec::with_capacity(gatherer.dark.map_or(0, |_| receivers.len()));
        for (chunk, stats) in built {
            chunks.push(chunk);
            for (c, b, k, d) in stats {
                coverage.push(c);
                back.push(b);
                closed.push(k);
                if gatherer.dark.is_some() {
                    dark.push(d);
                }
            }
        }
        let clusters = ClusterSlots::named(
            gatherer.tree.nodes.len(),
            chunks
                .iter()
                .flat_map(|c| c.far.iter())
                .filter(|l| l.is_cluster())
                .map(|l| l.node),
        );
        ReceiverLinks {
            chunks,
            coverage,
            back,
            closed,
            dark,
            clusters,
        }
    }

    /// No rows at all, for `n` receivers over a tree of `nodes` nodes: a scene that is black
    /// throughout reflects nothing, so nothing needs gathering (each receiver covered by
    /// nothing, enclosed by nothing).
    pub fn none(n: usize, nodes: usize) -> Self {
        ReceiverLinks {
            chunks: (0..n.div_ceil(CHUNK))
                .map(|k| RowChunk {
                    leaf_at: vec![0; CHUNK.min(n - k * CHUNK) + 1],
                    leaves: Vec::new(),
                    far_at: vec![0; CHUNK.min(n - k * CHUNK) + 1],
                    far: Vec::new(),
                })
                .collect(),
            coverage: vec![0.0; n],
            back: vec![0.0; n],
            closed: vec![false; n],
            dark: Vec::new(),
            clusters: ClusterSlots::named(nodes, std::iter::empty()),
        }
    }

    /// Did the gatherer have black nodes (so rows leave out what they cover)?
    pub fn has_dark(&self) -> bool {
        !self.dark.is_empty()
    }

    /// Fraction of receiver `r`'s hemisphere covered by black nodes, which its row does not
    /// link (normalised like [`ReceiverLinks::back`]).
    pub fn dark(&self, r: usize) -> f32 {
        self.dark.get(r).copied().unwrap_or(0.0)
    }

    /// Receiver `r`'s row.
    pub fn row(&self, r: usize) -> RowRef<'_> {
        let chunk = &self.chunks[r / CHUNK];
        let j = r % CHUNK;
        let span = |at: &[u32]| at[j] as usize..at[j + 1] as usize;
        RowRef {
            leaves: &chunk.leaves[span(&chunk.leaf_at)],
            far: &chunk.far[span(&chunk.far_at)],
        }
    }

    /// Every far-field and cluster link of every row (the leaf links aside).
    pub fn far_links(&self) -> impl Iterator<Item = &Link> {
        self.chunks.iter().flat_map(|c| c.far.iter())
    }

    /// Number of links, leaves included.
    pub fn link_count(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| c.leaves.len() + c.far.len())
            .sum()
    }

    /// E at every receiver from a node-summarised exitance field.
    pub fn apply(&self, field: &NodeField, out: &mut [DVec3]) {
        out.par_chunks_mut(256).enumerate().for_each(|(c, chunk)| {
            for (k, e) in chunk.iter_mut().enumerate() {
                let row = self.row(c * 256 + k);
                *e = field.gather_leaves(row.leaves) + field.gather(row.far);
            }
        });
    }
}

/// One point's gather row, normalised when the point is enclosed.
pub struct Row {
    pub links: Vec<Link>,
    /// Coverage before normalisation.
    pub coverage: f64,
    /// Back-face fraction (after normalisation).
    pub back: f64,
    /// Fraction covered by black nodes, which have no links (after normalisation).
    pub dark: f64,
    pub closed: bool,
}

/// The links seen from `p` (unit normal `n`), with the closure rule of this module.
pub fn gather_row(gatherer: &Gatherer, p: DVec3, n: DVec3) -> Row {
    gather_row_shared(gatherer, p, n, None)
}

/// [`gather_row`] sharing shadow-ray answers with other rows at the same point (`shared`).
pub fn gather_row_shared(
    gatherer: &Gatherer,
    p: DVec3,
    n: DVec3,
    shared: Option<&mut SharedRays>,
) -> Row {
    let mut links = Vec::new();
    let c = gatherer.links_shared(p, n, &mut links, shared);
    let closed = c.total >= 0.999 || (c.total > 0.05 && enclosed(gatherer, p, n));
    let (mut back, mut dark) = (c.back, c.dark);
    if closed && c.total > 0.0 {
        let scale = 1.0 / c.total;
        for l in &mut links {
            l.coeff *= scale as f32;
            l.grad = l.grad.map(|g| g * scale as f32);
        }
        back *= scale;
        dark *= scale;
    }
    Row {
        links,
        coverage: c.total,
        back,
        dark,
        closed,
    }
}

/// True when none of 64 stratified cosine-weighted rays from the point escapes the scene.
fn enclosed(gatherer: &Gatherer, p: DVec3, n: DVec3) -> bool {
    samples::cosine_directions(n, 8).all(|d| !gatherer.occluder.escapes(p, n, d))
}
