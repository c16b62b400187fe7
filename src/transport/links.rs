//! The inter-reflection operator at the receivers, built once and applied at every solver step.
//!
//! Input: a [`Gatherer`] over the tree of all patches, and the points to gather at. Output:
//! [`ReceiverLinks`] in compressed rows: row g gathers E_g = Σ coeff·B(node) over its leaf links
//! (one patch each) and far-field and cluster links ([`Link`]), stored packed
//! ([`super::packed`]: about 3 and 7 bytes a link). Receiver r reads row r,
//! or with a [`Blend`] (`transport::sharing`) a weighted mean of rows, weights summing to 1.
//!
//! Closure: a receiver inside a closed space sees geometry in every direction, so its true
//! coverage is exactly 1; the far-field expansion and sampled visibility leave it off by a little,
//! and at reflectance 0.99 a per-bounce loss of 0.1 % costs 10 % of the answer. Rows of closed
//! receivers are therefore normalised to coverage 1 (energy conservation per bounce). A receiver is
//! closed when its coverage is ≥ 0.999, or when none of 64 stratified cosine-weighted escape rays
//! leaves the scene (a lower coverage then comes from sampled visibility, e.g. where objects
//! touch). A receiver that sees (almost) nothing (coverage ≤ 0.05: pressed against another face)
//! is left alone. Open receivers keep their rows as computed. What covered parts cover (the
//! slot between two contacts) is measured first and counted as back faces
//! (`transport::covered`): absorbed, not spread over the rest.

use super::field::{ClusterSlots, FieldValue, NodeField};
use super::gather::{CLOSED, Gatherer, SharedRays};
use super::link::{Leaf, Link};
use super::packed::{FarLinks, Leaves, PackedRows};
use crate::geom::samples;
use crate::patches::Vertex;
use glam::DVec3;
use rayon::prelude::*;

pub struct ReceiverLinks {
    /// The gathered rows, `CHUNK` to a chunk, each chunk's links in one exactly sized
    /// allocation: the rows are never copied into one array, whose doubling (and the slack of
    /// rows grown link by link) set the bake's peak memory on large scenes. Rows are appended
    /// in batches ([`ReceiverLinks::append`]); a batch's last chunk may be short.
    chunks: Vec<PackedRows>,
    /// Per batch: its first row and its first chunk.
    batches: Vec<(u32, u32)>,
    /// How receivers read rows; `None`: receiver r reads row r.
    blend: Option<Blend>,
    /// Coverage before normalisation, per receiver.
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

/// Receivers whose rows are weighted means of gathered rows (`transport::sharing`): receiver
/// r's row is Σ weight × row over `terms[at[r]..at[r + 1]]`, the weights summing to 1.
pub struct Blend {
    pub at: Vec<u32>,
    pub terms: Vec<(u32, f32)>,
    /// The receiver each row was gathered at.
    pub gathered_at: Vec<u32>,
}

impl Blend {
    /// The rows receiver `r` reads, with their weights.
    pub(crate) fn of(&self, r: usize) -> &[(u32, f32)] {
        &self.terms[self.at[r] as usize..self.at[r + 1] as usize]
    }
}

/// What a gather says of its receiver besides the links: coverage, back, closed, dark.
#[derive(Clone, Copy)]
pub struct RowStats {
    pub coverage: f32,
    pub back: f32,
    pub closed: bool,
    pub dark: f32,
}

/// One receiver's row: its leaf links and the rest (far-field and cluster links).
#[derive(Clone, Copy)]
pub struct RowRef<'a> {
    pub leaves: Leaves<'a>,
    pub far: FarLinks<'a>,
}

/// Rows are built in parallel over fixed chunks, kept in order: deterministic.
const CHUNK: usize = 64;

impl ReceiverLinks {
    pub(crate) fn build(gatherer: &Gatherer, receivers: &[Vertex]) -> Self {
        let points: Vec<(DVec3, DVec3)> = receivers.iter().map(|r| (r.point, r.normal)).collect();
        let mut links = ReceiverLinks::empty(gatherer.dark.is_some());
        let stats = links.append(gatherer, &points);
        links.finish(None, &stats, gatherer.tree.nodes.len());
        links
    }

    /// No rows yet; `dark`: the gatherer has black nodes.
    pub(crate) fn empty(dark: bool) -> Self {
        ReceiverLinks {
            chunks: Vec::new(),
            batches: Vec::new(),
            blend: None,
            coverage: Vec::new(),
            back: Vec::new(),
            closed: Vec::new(),
            dark: if dark { vec![0.0] } else { Vec::new() },
            clusters: ClusterSlots::named(0, std::iter::empty()),
        }
    }

    /// Gather rows at `points` (point, unit normal), appended as rows `rows()..`, in parallel
    /// over fixed chunks, kept in order: deterministic. Returns what each gather said.
    pub(crate) fn append(
        &mut self,
        gatherer: &Gatherer,
        points: &[(DVec3, DVec3)],
    ) -> Vec<RowStats> {
        let built: Vec<(PackedRows, Vec<RowStats>)> = points
            .par_chunks(CHUNK)
            .map(|chunk| {
                let rows: Vec<Row> = chunk
                    .iter()
                    .map(|&(p, n)| gather_row(gatherer, p, n))
                    .collect();
                let stats = rows
                    .iter()
                    .map(|r| RowStats {
                        coverage: r.coverage as f32,
                        back: r.back as f32,
                        closed: r.closed,
                        dark: r.dark as f32,
                    })
                    .collect();
                (packed(&rows), stats)
            })
            .collect();
        self.batches
            .push((self.rows() as u32, self.chunks.len() as u32));
        let mut out = Vec::with_capacity(points.len());
        for (chunk, stats) in built {
            self.chunks.push(chunk);
            out.extend(stats);
        }
        out
    }

    /// Append copies of `rows` (gathered elsewhere: another part's) as one batch.
    pub(crate) fn append_rows(&mut self, rows: &[RowRef]) {
        self.batches
            .push((self.rows() as u32, self.chunks.len() as u32));
        for chunk in rows.chunks(CHUNK) {
            self.chunks.push(copied(chunk));
        }
    }

    /// Move batch `b` of `other` here as one batch, its rows numbered after these: the chunks
    /// themselves, not copies (`other` keeps that batch with no rows).
    pub(crate) fn take_batch(&mut self, other: &mut ReceiverLinks, b: usize) {
        let start = other.batches[b].1 as usize;
        let end = other
            .batches
            .get(b + 1)
            .map_or(other.chunks.len(), |next| next.1 as usize);
        self.batches
            .push((self.rows() as u32, self.chunks.len() as u32));
        for chunk in &mut other.chunks[start..end] {
            self.chunks.push(std::mem::take(chunk));
        }
    }

    /// Set how receivers read the rows (`None`: receiver r reads row r, one stat per row) and
    /// their stats: a blended receiver's coverage, back and dark are its terms' weighted means;
    /// it is closed when all its terms are. `nodes`: the tree's node count.
    pub(crate) fn finish(&mut self, blend: Option<Blend>, rows: &[RowStats], nodes: usize) {
        let per_receiver: Vec<RowStats> = match &blend {
            None => rows.to_vec(),
            Some(b) => (0..b.at.len() - 1)
                .map(|r| {
                    let terms = b.of(r);
                    let mean = |f: &dyn Fn(&RowStats) -> f32| {
                        terms
                            .iter()
                            .map(|&(g, w)| w * f(&rows[g as usize]))
                            .sum::<f32>()
                    };
                    RowStats {
                        coverage: mean(&|s| s.coverage),
                        back: mean(&|s| s.back),
                        closed: terms.iter().all(|&(g, _)| rows[g as usize].closed),
                        dark: mean(&|s| s.dark),
                    }
                })
                .collect(),
        };
        self.coverage = per_receiver.iter().map(|s| s.coverage).collect();
        self.back = per_receiver.iter().map(|s| s.back).collect();
        self.closed = per_receiver.iter().map(|s| s.closed).collect();
        if !self.dark.is_empty() {
            self.dark = per_receiver.iter().map(|s| s.dark).collect();
        }
        self.blend = blend;
        self.clusters = ClusterSlots::named(
            nodes,
            self.far_links().filter(|l| l.is_cluster()).map(|l| l.node),
        );
    }

    /// No rows at all, for `n` receivers over a tree of `nodes` nodes: a scene that is black
    /// throughout reflects nothing, so nothing needs gathering (each receiver covered by
    /// nothing, enclosed by nothing).
    pub(crate) fn none(n: usize, nodes: usize) -> Self {
        let mut links = ReceiverLinks::empty(false);
        links.batches.push((0, 0));
        links.chunks = (0..n.div_ceil(CHUNK))
            .map(|k| packed(&vec![Row::default(); CHUNK.min(n - k * CHUNK)]))
            .collect();
        let stats = RowStats {
            coverage: 0.0,
            back: 0.0,
            closed: false,
            dark: 0.0,
        };
        links.finish(None, &vec![stats; n], nodes);
        links
    }

    /// Did the gatherer have black nodes (so rows leave out what they cover)?
    pub(crate) fn has_dark(&self) -> bool {
        !self.dark.is_empty()
    }

    /// Fraction of receiver `r`'s hemisphere covered by black nodes, which its row does not
    /// link (normalised like [`ReceiverLinks::back`]).
    pub(crate) fn dark(&self, r: usize) -> f32 {
        self.dark.get(r).copied().unwrap_or(0.0)
    }

    /// Number of gathered rows.
    pub(crate) fn rows(&self) -> usize {
        self.chunks.iter().map(|c| c.rows()).sum()
    }

    /// Number of receivers.
    pub fn receivers(&self) -> usize {
        self.coverage.len()
    }

    /// Gathered row `g` (receiver g's own row when nothing is blended).
    pub(crate) fn row(&self, g: usize) -> RowRef<'_> {
        let b = self
            .batches
            .partition_point(|&(first, _)| first as usize <= g)
            - 1;
        let (first, chunk) = self.batches[b];
        let k = g - first as usize;
        let chunk = &self.chunks[chunk as usize + k / CHUNK];
        let j = k % CHUNK;
        let (leaves, far) = chunk.row(j);
        RowRef { leaves, far }
    }

    /// The rows receiver `r` reads, with their weights.
    pub fn terms(&self, r: usize) -> Vec<(u32, f32)> {
        match &self.blend {
            None => vec![(r as u32, 1.0)],
            Some(b) => b.of(r).to_vec(),
        }
    }

    /// The receiver row `g` was gathered at.
    pub fn gathered_at(&self, g: usize) -> usize {
        self.blend.as_ref().map_or(g, |b| b.gathered_at[g] as usize)
    }

    /// Per-receiver weights `at` carried to the rows they read (the blend's transpose), in
    /// receiver order: deterministic.
    pub(crate) fn to_rows(&self, at: Vec<f64>) -> Vec<f64> {
        let Some(b) = &self.blend else { return at };
        let mut out = vec![0.0; self.rows()];
        for (r, a) in at.iter().enumerate() {
            for &(g, w) in b.of(r) {
                out[g as usize] += a * w as f64;
            }
        }
        out
    }

    /// Every far-field and cluster link of every row (the leaf links aside).
    pub(crate) fn far_links(&self) -> impl Iterator<Item = Link> + '_ {
        (self.chunks.iter()).flat_map(|c| (0..c.rows()).flat_map(|j| c.row(j).1.iter()))
    }

    /// Number of links, leaves included.
    pub(crate) fn link_count(&self) -> usize {
        self.chunks.iter().map(|c| c.links()).sum()
    }

    /// E at every receiver from a node-summarised exitance field (RGB, or one channel).
    pub(crate) fn apply<V: FieldValue>(&self, field: &NodeField<V>, out: &mut [V]) {
        let gather = |g: usize| {
            let row = self.row(g);
            field.gather_leaves(row.leaves) + field.gather(row.far.iter())
        };
        let Some(b) = &self.blend else {
            return fill(out, gather);
        };
        let mut at = vec![V::ZERO; self.rows()];
        fill(&mut at, gather);
        fill(out, |r| {
            b.of(r)
                .iter()
                .map(|&(g, w)| at[g as usize] * w as f64)
                .fold(V::ZERO, |a, x| a + x)
        });
    }
}

/// `out[i] = value(i)`, in parallel over fixed chunks.
fn fill<V: Send>(out: &mut [V], value: impl Fn(usize) -> V + Sync) {
    out.par_chunks_mut(256).enumerate().for_each(|(c, chunk)| {
        for (k, e) in chunk.iter_mut().enumerate() {
            *e = value(c * 256 + k);
        }
    });
}

/// Rows copied from elsewhere.
fn copied(rows: &[RowRef]) -> PackedRows {
    let mut c = PackedRows::with_capacity(
        rows.len(),
        rows.iter().map(|r| r.leaves.len()).sum(),
        rows.iter().map(|r| r.far.len()).sum(),
    );
    for r in rows {
        c.push_packed(r.leaves, r.far);
    }
    c.shrink();
    c
}

/// Rows packed: leaf links (no gradient) apart from the rest.
fn packed(rows: &[Row]) -> PackedRows {
    let is_leaf = |l: &&Link| l.coeff > 0.0 && !l.has_shape();
    let all = rows.iter().flat_map(|r| &r.links);
    let n_leaves = all.clone().filter(is_leaf).count();
    let mut out = PackedRows::with_capacity(rows.len(), n_leaves, all.count() - n_leaves);
    let (mut leaves, mut far) = (Vec::new(), Vec::new());
    for row in rows {
        leaves.clear();
        far.clear();
        for l in &row.links {
            match is_leaf(&l) {
                true => leaves.push(Leaf {
                    node: l.node,
                    coeff: l.coeff,
                }),
                false => far.push(*l),
            }
        }
        out.push(&leaves, &far);
    }
    out.shrink();
    out
}

/// One point's gather row, normalised when the point is enclosed.
#[derive(Clone, Default)]
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
pub(crate) fn gather_row(gatherer: &Gatherer, p: DVec3, n: DVec3) -> Row {
    gather_row_shared(gatherer, p, n, None)
}

/// [`gather_row`] sharing shadow-ray answers with other rows at the same point (`shared`).
pub(crate) fn gather_row_shared(
    gatherer: &Gatherer,
    p: DVec3,
    n: DVec3,
    shared: Option<&mut SharedRays>,
) -> Row {
    let mut links = Vec::new();
    let c = gatherer.links_shared(p, n, &mut links, shared);
    let closed = c.total >= CLOSED || (c.total > 0.05 && enclosed(gatherer, p, n));
    let (mut back, mut dark) = (c.back, c.dark);
    if closed && c.total > 0.0 {
        let scale = 1.0 / c.total;
        for l in &mut links {
            l.coeff *= scale as f32;
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
