//! The inter-reflection operator at the receivers, built once and applied at every solver step.
//!
//! Input: a [`Gatherer`] over the tree of all patches, and the receivers. Output: [`ReceiverLinks`]
//! in compressed rows: receiver r gathers E_r = Σ coeff·B(node) over `links[offsets[r]..offsets[r+1]]`.
//!
//! Closure: a receiver inside a closed space sees geometry in every direction, so its true
//! coverage is exactly 1; the far-field expansion and sampled visibility leave it off by a little,
//! and at reflectance 0.99 a per-bounce loss of 0.1 % costs 10 % of the answer. Rows of closed
//! receivers are therefore normalised to coverage 1 (energy conservation per bounce). A receiver is
//! closed when its coverage is ≥ 0.999, or when none of 64 stratified cosine-weighted escape rays
//! leaves the scene (a lower coverage then comes from sampled visibility, e.g. where objects
//! touch). A receiver that sees (almost) nothing (coverage ≤ 0.05: pressed against another face)
//! is left alone. Open receivers keep their rows as computed.

use super::gather::{Gatherer, Link, SharedRays};
use super::tree::NodeField;
use crate::geom::samples;
use crate::patches::Receiver;
use glam::DVec3;
use rayon::prelude::*;

pub struct ReceiverLinks {
    pub offsets: Vec<usize>,
    pub links: Vec<Link>,
    /// Coverage before normalisation.
    pub coverage: Vec<f32>,
    /// Fraction covered by back faces (after normalisation for closed receivers).
    pub back: Vec<f32>,
    /// Rows normalised because the receiver is enclosed.
    pub closed: Vec<bool>,
}

/// Rows are built in parallel over fixed chunks and concatenated in order: deterministic.
const CHUNK: usize = 64;

impl ReceiverLinks {
    pub fn build(gatherer: &Gatherer, receivers: &[Receiver]) -> Self {
        let rows: Vec<(Vec<Link>, f32, f32, bool)> = receivers
            .par_chunks(CHUNK)
            .flat_map_iter(|chunk| {
                chunk.iter().map(|r| {
                    let row = gather_row(gatherer, r.point, r.normal);
                    (row.links, row.coverage as f32, row.back as f32, row.closed)
                })
            })
            .collect();
        let mut offsets = Vec::with_capacity(rows.len() + 1);
        offsets.push(0);
        let total: usize = rows.iter().map(|r| r.0.len()).sum();
        let mut links = Vec::with_capacity(total);
        let mut coverage = Vec::with_capacity(rows.len());
        let mut closed = Vec::with_capacity(rows.len());
        let mut back = Vec::with_capacity(rows.len());
        for (l, c, b, k) in rows {
            links.extend_from_slice(&l);
            offsets.push(links.len());
            coverage.push(c);
            back.push(b);
            closed.push(k);
        }
        ReceiverLinks {
            offsets,
            links,
            coverage,
            back,
            closed,
        }
    }

    /// E at every receiver from a node-summarised exitance field.
    pub fn apply(&self, field: &NodeField, out: &mut [DVec3]) {
        out.par_chunks_mut(256).enumerate().for_each(|(c, chunk)| {
            for (k, e) in chunk.iter_mut().enumerate() {
                let r = c * 256 + k;
                *e = field.gather(&self.links[self.offsets[r]..self.offsets[r + 1]]);
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
    let mut back = c.back;
    if closed && c.total > 0.0 {
        let scale = 1.0 / c.total;
        for l in &mut links {
            l.coeff *= scale as f32;
            l.grad = l.grad.map(|g| g * scale as f32);
        }
        back *= scale;
    }
    Row {
        links,
        coverage: c.total,
        back,
        closed,
    }
}

/// True when none of 64 stratified cosine-weighted rays from the point escapes the scene.
fn enclosed(gatherer: &Gatherer, p: DVec3, n: DVec3) -> bool {
    samples::cosine_directions(n, 8).all(|d| !gatherer.occluder.escapes(p, n, d))
}
