//! Receivers that share gathers: the inter-reflected light is gathered fully at an adaptive
//! subset of the receivers; every other receiver reads a weighted mean of nearby gathered rows,
//! where an error estimate says the mean is good enough. Direct light is not touched: it stays
//! exact at every receiver.
//!
//! Input: a [`Gatherer`], the mesh's receivers (vertices, each in a group: one side of one
//! surface) and [`Sharing`]: the tolerance and what the light is estimated from (the direct
//! illuminance at each receiver, the first-bounce exitance of each patch). Output:
//! [`ReceiverLinks`] with a [`Blend`]: which rows each receiver reads, weights summing to 1 (so
//! a blend of rows normalised to coverage 1 keeps coverage 1).
//!
//! Levels of halving spacing s, from the patch size: at each level the receivers not yet settled
//! are binned in cubes of edge s per group, and in each cube, in receiver order, a receiver is
//! gathered unless one gathered there this level already faces its way (within [`PICK_COS`]).
//! Then each unsettled receiver looks for gathered receivers of its own group within 1.5 s that
//! are valid for it by Ward's criterion, d/R + √(1 − n·n′) ≤ [`WARD`] (R: the harmonic mean
//! distance of what the gathered receiver sees, so the spacing shrinks near other surfaces;
//! R also at most the harmonic mean distance of what 16 rays from either end hit, so a
//! receiver beside a leg it stands next to, or pressed against a face, reads only its own row),
//! nearest first, at most [`MAX_TERMS`], each confirmed by a shadow ray between the two lifted
//! off the surface by a quarter of their distance (so nothing is read across a leg, a wall or a
//! screen standing on the surface). It reads their mean with Ward's weights 1/ε when at least two
//! are valid and their first-bounce illuminances (their rows applied to the first-bounce field)
//! spread by at most the tolerance × its estimated illuminance (direct + interpolated first
//! bounce); else it waits for the next level. The spread is the residual of a weighted plane
//! through four rows or more; for three (which a plane fits exactly) the plane's value less
//! Ward's mean; for two, or rows in a line, their range, and only for a receiver within
//! [`OFF_LINE`] of their line (off it they say nothing: a receiver behind a card hung above the
//! floor would read two rows from under its edge). After the last level every receiver still
//! unsettled is gathered. Nothing is read across groups, so never across the outline of a
//! contact (covered parts are not receivers) or from another surface.
//!
//! Deterministic: every level's picks, gathers and decisions depend only on the previous
//! levels' results, made in parallel over fixed chunks and kept in receiver order.

use super::field::{ClusterSlots, NodeField};
use super::gather::Gatherer;
use super::links::{Blend, ReceiverLinks, RowStats};
use crate::patches::Vertex;
use crate::scene::luma;
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// Ward's acceptance: d/R + √(1 − n·n′) at most this.
pub const WARD: f64 = 0.3;
/// Receivers of one cube and level gathered together face apart by more than this cosine.
const PICK_COS: f64 = 1.0 - WARD * WARD / 4.0;
/// A receiver reads at most this many gathered rows.
const MAX_TERMS: usize = 8;
/// A gathered receiver seeing more back faces than this share of its hemisphere lends its row
/// to nobody.
const MAX_BACK: f32 = 0.05;
/// A receiver reading two rows (or rows in a line) lies at most this share of their distance
/// off their line.
const OFF_LINE: f64 = 0.1;
/// Linear weights below this extrapolate too far: the Ward mean is read instead.
const MIN_WEIGHT: f64 = -0.25;
/// Rays per side of the stratified pattern [`nearness`] traces.
const NEAR_RAYS: usize = 4;
/// Levels of halving spacing before every unsettled receiver is gathered.
const LEVELS: usize = 6;

/// What receivers may share, and what the error estimate reads.
pub struct Sharing<'a> {
    /// Largest spread of the first-bounce estimate across the rows a receiver reads, as a
    /// fraction of its estimated illuminance.
    pub tolerance: f64,
    /// Direct illuminance at each receiver (lx, RGB).
    pub direct: &'a [DVec3],
    /// First-bounce exitance of each patch (lm/m², RGB): emitted plus reflected direct light.
    pub first_bounce: &'a [DVec3],
}

/// A gathered receiver, as the others see it.
#[derive(Clone, Copy)]
struct Gathered {
    point: DVec3,
    normal: DVec3,
    group: u32,
    /// Harmonic mean distance of what it sees (m).
    reach: f64,
    /// Its row applied to the first-bounce field (lx, photometric).
    first: f64,
}

const NONE: u32 = u32::MAX;

/// Rows for `receivers`, shared where [`Sharing`] allows (see the module doc).
pub(crate) fn build(gatherer: &Gatherer, receivers: &[Vertex], sharing: &Sharing) -> ReceiverLinks {
    let all: Vec<u32> = (0..receivers.len() as u32).collect();
    assemble(
        vec![part(gatherer, receivers, &all, sharing)],
        receivers.len(),
        gatherer.tree.nodes.len(),
    )
}

/// The rows of some receivers (whole groups: nothing is shared across groups), gathered and
/// shared as [`build`] does, before [`assemble`] numbers them among every other part's.
pub struct Part {
    /// The rows gathered, one batch per level (unfinished: no blend, no stats).
    pub links: ReceiverLinks,
    /// What each row's gather said.
    pub stats: Vec<RowStats>,
    /// Per level, the receivers gathered there, in row order.
    pub picks: Vec<Vec<u32>>,
    /// The part's receivers, ascending, and what each reads: `terms[at[k]..at[k + 1]]`, rows
    /// of this part with weights (a gathered receiver reads its own row with weight 1).
    pub receivers: Vec<u32>,
    pub at: Vec<u32>,
    pub terms: Vec<(u32, f32)>,
}

impl Part {
    /// No rows for `subset`: nothing to gather (the scene is black throughout).
    pub(crate) fn nothing(dark: bool, subset: &[u32]) -> Part {
        Part {
            links: ReceiverLinks::empty(dark),
            stats: Vec::new(),
            picks: Vec::new(),
            receivers: subset.to_vec(),
            at: vec![0; subset.len() + 1],
            terms: Vec::new(),
        }
    }
}

/// The [`Part`] of `subset` (ascending receiver indices, whole groups).
pub(crate) fn part(
    gatherer: &Gatherer,
    receivers: &[Vertex],
    subset: &[u32],
    sharing: &Sharing,
) -> Part {
    let n = receivers.len();
    let mut links = ReceiverLinks::empty(gatherer.dark.is_some());
    if sharing.tolerance <= 0.0 {
        // Nothing shared: every receiver gathered, in order.
        let points: Vec<(DVec3, DVec3)> = (subset.iter())
            .map(|&r| (receivers[r as usize].point, receivers[r as usize].normal))
            .collect();
        let stats = links.append(gatherer, &points);
        return Part {
            links,
            stats,
            picks: vec![subset.to_vec()],
            receivers: subset.to_vec(),
            at: (0..=subset.len() as u32).collect(),
            terms: (0..subset.len() as u32).map(|g| (g, 1.0)).collect(),
        };
    }
    let mut stats: Vec<RowStats> = Vec::new();
    let mut gathered: Vec<Gathered> = Vec::new();
    let mut own = vec![NONE; n];
    let mut blended: Vec<Vec<(u32, f32)>> = vec![Vec::new(); n];
    let mut open: Vec<u32> = subset.to_vec();
    let mut picked: Vec<Vec<u32>> = Vec::new();
    let h = gatherer.mesh.patch_size.max(1e-9);
    let near = nearness(gatherer, receivers, subset);
    for level in 0..=LEVELS {
        if open.is_empty() {
            break;
        }
        let last = level == LEVELS;
        let spacing = h / (1u64 << level) as f64;
        let picks = match last {
            // What the levels before gathered is read only to settle others: freed before the
            // last gather, which holds every row.
            true => {
                gathered = Vec::new();
                std::mem::take(&mut open)
            }
            false => pick(receivers, &open, spacing),
        };
        let points: Vec<(DVec3, DVec3)> = picks
            .iter()
            .map(|&r| (receivers[r as usize].point, receivers[r as usize].normal))
            .collect();
        let first = links.rows();
        let new = links.append(gatherer, &points);
        // After the last level nobody is left to read the rows: no estimates (their field is
        // the largest thing built while every row is held).
        if !last {
            let at = estimates(gatherer, &links, &new, first, &picks, receivers, sharing);
            gathered.extend(at.into_iter().zip(&picks).map(|(mut g, &r)| {
                g.reach = g.reach.min(near[r as usize]);
                g
            }));
        }
        stats.extend(new);
        for (k, &r) in picks.iter().enumerate() {
            own[r as usize] = (first + k) as u32;
        }
        picked.push(picks);
        if last {
            break;
        }
        let reach = 1.5 * spacing;
        let grid = Grid::new(&gathered, reach);
        let waiting: Vec<u32> = open
            .into_iter()
            .filter(|&r| own[r as usize] == NONE)
            .collect();
        let settled: Vec<Option<Vec<(u32, f32)>>> = waiting
            .par_chunks(64)
            .flat_map_iter(|chunk| {
                chunk.iter().map(|&r| {
                    let v = &receivers[r as usize];
                    let direct = luma(sharing.direct[r as usize]);
                    let reach = reach.min(WARD * near[r as usize]);
                    settle(gatherer, &grid, &gathered, v, reach, direct, sharing)
                })
            })
            .collect();
        open = Vec::new();
        for (r, s) in waiting.into_iter().zip(settled) {
            match s {
                Some(terms) => blended[r as usize] = terms,
                None => open.push(r),
            }
        }
    }
    let mut at = Vec::with_capacity(subset.len() + 1);
    let mut terms = Vec::with_capacity(subset.len());
    at.push(0);
    for &r in subset {
        match own[r as usize] {
            NONE => terms.append(&mut blended[r as usize]),
            g => terms.push((g, 1.0)),
        }
        at.push(terms.len() as u32);
    }
    Part {
        links,
        stats,
        picks: picked,
        receivers: subset.to_vec(),
        at,
        terms,
    }
}

/// Every receiver's rows from `parts` (together covering the `n` receivers once), numbered as
/// one [`part`] of all of them numbers them: level by level, in receiver order within a level.
/// So the links, and all that is computed from them, do not depend on how the receivers were
/// split. `nodes`: the tree's node count.
pub(crate) fn assemble(mut parts: Vec<Part>, n: usize, nodes: usize) -> ReceiverLinks {
    let whole = parts.len() == 1 && parts[0].receivers.len() == n;
    let (mut links, stats, numbering) = match whole {
        // One part of all receivers: its rows are numbered already.
        true => {
            let p = &mut parts[0];
            let links = std::mem::replace(&mut p.links, ReceiverLinks::empty(false));
            let numbering = vec![(0..p.stats.len() as u32).collect::<Vec<u32>>()];
            (links, std::mem::take(&mut p.stats), numbering)
        }
        false => renumber(&mut parts),
    };
    let mut gathered_at = vec![0; links.rows()];
    let mut reads: Vec<(u32, u32)> = vec![(u32::MAX, 0); n];
    for (p, part) in parts.iter().enumerate() {
        let mut row = 0;
        for picks in &part.picks {
            for &r in picks {
                gathered_at[numbering[p][row] as usize] = r;
                row += 1;
            }
        }
        for (k, &r) in part.receivers.iter().enumerate() {
            reads[r as usize] = (p as u32, k as u32);
        }
    }
    let mut at = Vec::with_capacity(n + 1);
    let mut terms = Vec::with_capacity(n);
    at.push(0);
    for &(p, k) in &reads {
        assert!(p != u32::MAX, "every receiver is in a part");
        let part = &parts[p as usize];
        let mine = &part.terms[part.at[k as usize] as usize..part.at[k as usize + 1] as usize];
        let number = &numbering[p as usize];
        terms.extend(mine.iter().map(|&(g, w)| (number[g as usize], w)));
        at.push(terms.len() as u32);
    }
    // Every receiver reading its own row, numbered as the receivers: no blend at all (what
    // `ReceiverLinks::build` makes).
    let own = gathered_at.len() == n
        && (gathered_at.iter().enumerate()).all(|(g, &r)| r as usize == g)
        && (at.windows(2).enumerate())
            .all(|(r, w)| w[1] - w[0] == 1 && terms[w[0] as usize] == (r as u32, 1.0));
    let blend = (!own).then_some(Blend {
        at,
        terms,
        gathered_at,
    });
    links.finish(blend, &stats, nodes);
    links
}

/// The rows of several parts gathered into one set, level by level in receiver order; their
/// stats in that order; per part, each of its rows' new number. Where a level's rows in
/// receiver order are the parts' own, part after part (parts of ascending receiver ranges, as a
/// distributed bake's tasks are), each part's batch is moved, not copied: a merge then holds
/// the rows once, not twice.
fn renumber(parts: &mut [Part]) -> (ReceiverLinks, Vec<RowStats>, Vec<Vec<u32>>) {
    let dark = parts.iter().any(|p| p.links.has_dark());
    let mut links = ReceiverLinks::empty(dark);
    let mut stats = Vec::new();
    let mut numbering: Vec<Vec<u32>> = parts.iter().map(|p| vec![0; p.stats.len()]).collect();
    let mut first: Vec<usize> = vec![0; parts.len()];
    let levels = parts.iter().map(|p| p.picks.len()).max().unwrap_or(0);
    for level in 0..levels {
        // (receiver, part, row in the part) of every row gathered at this level.
        let mut rows: Vec<(u32, usize, usize)> = Vec::new();
        for (p, part) in parts.iter().enumerate() {
            if let Some(picks) = part.picks.get(level) {
                rows.extend(picks.iter().enumerate().map(|(k, &r)| (r, p, first[p] + k)));
                first[p] += picks.len();
            }
        }
        // Already in receiver order as the parts hold them: their batches can move.
        let moved = rows.is_sorted();
        if !moved {
            rows.sort_unstable();
        }
        let at = links.rows() as u32;
        for (k, &(_, p, g)) in rows.iter().enumerate() {
            numbering[p][g] = at + k as u32;
            stats.push(parts[p].stats[g]);
        }
        if moved {
            for part in parts.iter_mut().filter(|p| level < p.picks.len()) {
                links.take_batch(&mut part.links, level);
            }
            continue;
        }
        let refs: Vec<_> = rows
            .iter()
            .map(|&(_, p, g)| parts[p].links.row(g))
            .collect();
        links.append_rows(&refs);
    }
    (links, stats, numbering)
}

/// Per receiver of `subset` (others: infinity), the harmonic mean distance (m) of what
/// [`NEAR_RAYS`]² cosine-distributed rays hit (misses count as infinitely far): small beside a
/// leg it stands next to, or pressed against a face.
fn nearness(gatherer: &Gatherer, receivers: &[Vertex], subset: &[u32]) -> Vec<f64> {
    let occ = gatherer.occluder;
    let mut near = vec![f64::INFINITY; receivers.len()];
    let values: Vec<f64> = subset
        .par_iter()
        .map(|&r| {
            let v = &receivers[r as usize];
            let from = v.point + v.normal * occ.epsilon;
            let inverse: f64 = crate::geom::samples::cosine_directions(v.normal, NEAR_RAYS)
                .map(|d| {
                    occ.closest(from, d)
                        .map_or(0.0, |hit| 1.0 / hit.distance.max(1e-9))
                })
                .sum();
            match inverse > 0.0 {
                true => (NEAR_RAYS * NEAR_RAYS) as f64 / inverse,
                false => f64::INFINITY,
            }
        })
        .collect();
    for (&r, v) in subset.iter().zip(values) {
        near[r as usize] = v;
    }
    near
}

/// The receivers of `open` to gather at this level: per group and cube of edge `spacing`, in
/// receiver order, each one facing away from every one picked there before; in receiver order.
fn pick(receivers: &[Vertex], open: &[u32], spacing: f64) -> Vec<u32> {
    let cell = |r: u32| {
        let v = &receivers[r as usize];
        let c = (v.point / spacing).floor();
        (v.group, c.x as i64, c.y as i64, c.z as i64)
    };
    let mut keyed: Vec<((u32, i64, i64, i64), u32)> = open.iter().map(|&r| (cell(r), r)).collect();
    keyed.par_sort_unstable();
    let mut picks = Vec::new();
    let mut normals: Vec<DVec3> = Vec::new();
    let mut current = None;
    for (key, r) in keyed {
        if current != Some(key) {
            current = Some(key);
            normals.clear();
        }
        let n = receivers[r as usize].normal;
        if normals.iter().all(|m| m.dot(n) < PICK_COS) {
            normals.push(n);
            picks.push(r);
        }
    }
    picks.sort_unstable();
    picks
}

/// What the rows `first..` (gathered at `picks`) say: reach and first-bounce illuminance.
fn estimates(
    gatherer: &Gatherer,
    links: &ReceiverLinks,
    stats: &[RowStats],
    first: usize,
    picks: &[u32],
    receivers: &[Vertex],
    sharing: &Sharing,
) -> Vec<Gathered> {
    let rows = first..links.rows();
    let named = rows.clone().flat_map(|g| {
        let row = links.row(g);
        row.far.iter().filter(|l| l.is_cluster()).map(|l| l.node)
    });
    let slots = ClusterSlots::named(
        gatherer.tree.nodes.len(),
        named.collect::<Vec<_>>().into_iter(),
    );
    // Only the luminance is read, and a row's reading is linear in the field: one channel.
    let field: NodeField<f64> = NodeField::for_clusters(
        gatherer.tree,
        gatherer.mesh,
        |p| luma(sharing.first_bounce[p]),
        &slots,
    );
    let tree = gatherer.tree;
    picks
        .par_iter()
        .enumerate()
        .map(|(k, &r)| {
            let v = &receivers[r as usize];
            let row = links.row(first + k);
            let (mut sum, mut inverse) = (0.0, 0.0);
            let mut add = |d: f64, c: f32| {
                let c = (c as f64).abs();
                sum += c;
                inverse += c / d.max(1e-6);
            };
            for l in row.leaves.iter() {
                let node = &tree.bounds[l.node as usize];
                let patch = &gatherer.mesh.patches[tree.order[node.start as usize] as usize];
                add(
                    to_triangle(v.point, patch.corners(&gatherer.mesh.receivers)),
                    l.coeff,
                );
            }
            for l in row.far.iter() {
                add(
                    tree.bounds[l.node as usize].centroid.distance(v.point),
                    l.coeff,
                );
            }
            // A receiver that sees back faces (inside a solid, or under an open panel) or
            // nothing at all lends its row to nobody.
            let s = &stats[k];
            let lends = sum > 0.0 && s.back <= MAX_BACK;
            Gathered {
                point: v.point,
                normal: v.normal,
                group: v.group,
                reach: if lends { sum / inverse } else { 0.0 },
                first: field.gather_leaves(row.leaves) + field.gather(row.far.iter()),
            }
        })
        .collect()
}

/// The gathered rows `v` may read and their weights, or `None` when it must wait.
fn settle(
    gatherer: &Gatherer,
    grid: &Grid,
    gathered: &[Gathered],
    v: &Vertex,
    reach: f64,
    direct: f64,
    sharing: &Sharing,
) -> Option<Vec<(u32, f32)>> {
    let mut near: Vec<(f64, u32)> = grid
        .near(v.point)
        .filter_map(|g| {
            let c = &gathered[g as usize];
            let cos = c.normal.dot(v.normal);
            let d = c.point.distance(v.point);
            if c.group != v.group || cos <= 0.0 || d > reach {
                return None;
            }
            let e = d / c.reach + (1.0 - cos).max(0.0).sqrt();
            (e <= WARD).then_some((e, g))
        })
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    near.truncate(MAX_TERMS);
    near.retain(|&(_, g)| {
        let c = &gathered[g as usize];
        let lift = 0.25 * c.point.distance(v.point);
        gatherer.occluder.clear(
            c.point + c.normal * lift,
            c.normal,
            v.point + v.normal * lift,
            v.normal,
        )
    });
    if near.len() < 2 {
        return None;
    }
    let ward: Vec<f64> = near.iter().map(|&(e, _)| 1.0 / e.max(1e-3)).collect();
    let total: f64 = ward.iter().sum();
    let ward: Vec<f64> = ward.iter().map(|w| w / total).collect();
    let first: Vec<f64> = near
        .iter()
        .map(|&(_, g)| gathered[g as usize].first)
        .collect();
    let points: Vec<DVec3> = near
        .iter()
        .map(|&(_, g)| gathered[g as usize].point)
        .collect();
    let (weights, error) = match linear(&points, &first, &ward, v) {
        // Three rows fit a plane exactly, so their residual says nothing: how far the plane's
        // value is from Ward's mean bounds the error instead (large across a kink in the light).
        Some((w, _)) if near.len() == 3 => {
            let at = |w: &[f64]| w.iter().zip(&first).map(|(w, f)| w * f).sum::<f64>();
            let error = (at(&w) - at(&ward)).abs();
            (w, error)
        }
        Some(fit) => fit,
        None => {
            // Two rows, in a line, or a plane that would extrapolate: the spread of their
            // estimates bounds the mean's error along their line only; off it the light may
            // change in a way they cannot show (a receiver behind a screen reading two rows from
            // beneath it). For the extrapolating plane the test is conservative.
            if off_line(&points, v.point) > OFF_LINE {
                return None;
            }
            let (lo, hi) = (first.iter()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(*x), b.max(*x))
            });
            (ward, hi - lo)
        }
    };
    let estimate: f64 = weights.iter().zip(&first).map(|(w, f)| w * f).sum();
    if error > sharing.tolerance * (direct + estimate.max(0.0)) {
        return None;
    }
    Some(
        near.iter()
            .zip(&weights)
            .map(|(&(_, g), &w)| (g, w as f32))
            .collect(),
    )
}

/// How far from the line through the two farthest of `points` `p` lies, as a share of their
/// distance.
fn off_line(points: &[DVec3], p: DVec3) -> f64 {
    let mut far = (0.0, points[0], points[0]);
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            let d = a.distance_squared(*b);
            if d > far.0 {
                far = (d, *a, *b);
            }
        }
    }
    let (span, a, b) = (far.0.sqrt(), far.1, far.2);
    if span <= 0.0 {
        return f64::INFINITY;
    }
    let u = (b - a) / span;
    let w = p - a;
    (w - u * w.dot(u)).length() / span
}

/// Weights that reproduce any linear function over `points` at `v` (a weighted least-squares
/// plane in `v`'s tangent plane, weights `ward`), and the largest residual of `values` from
/// that plane: the error estimate of reading `v` from them. `None` with fewer than three points,
/// points in a line, or weights extrapolating (one below [`MIN_WEIGHT`]).
fn linear(points: &[DVec3], values: &[f64], ward: &[f64], v: &Vertex) -> Option<(Vec<f64>, f64)> {
    if points.len() < 3 {
        return None;
    }
    let t1 = v.normal.any_orthonormal_vector();
    let t2 = v.normal.cross(t1);
    let centre: DVec3 = points.iter().zip(ward).map(|(p, w)| *p * *w).sum();
    let local: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [(*p - centre).dot(t1), (*p - centre).dot(t2)])
        .collect();
    // Normal equations of the weighted fit f ≈ a + g·(x − centre): a is the weighted mean (the
    // centre is the weighted centroid), g = S⁻¹ Σ w·x·f.
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (x, w) in local.iter().zip(ward) {
        sxx += w * x[0] * x[0];
        sxy += w * x[0] * x[1];
        syy += w * x[1] * x[1];
    }
    let det = sxx * syy - sxy * sxy;
    let scale = (sxx + syy).max(1e-300);
    if det <= 1e-3 * scale * scale {
        return None;
    }
    let at = [(v.point - centre).dot(t1), (v.point - centre).dot(t2)];
    // q = S⁻¹·at: the value at v is Σ w·f·(1 + q·x).
    let q = [
        (syy * at[0] - sxy * at[1]) / det,
        (sxx * at[1] - sxy * at[0]) / det,
    ];
    let weights: Vec<f64> = local
        .iter()
        .zip(ward)
        .map(|(x, w)| w * (1.0 + q[0] * x[0] + q[1] * x[1]))
        .collect();
    if weights.iter().any(|w| *w < MIN_WEIGHT) {
        return None;
    }
    let mean: f64 = values.iter().zip(ward).map(|(f, w)| f * w).sum();
    let (mut bx, mut by) = (0.0, 0.0);
    for ((x, w), f) in local.iter().zip(ward).zip(values) {
        bx += w * x[0] * (f - mean);
        by += w * x[1] * (f - mean);
    }
    let g = [(syy * bx - sxy * by) / det, (sxx * by - sxy * bx) / det];
    let residual = local
        .iter()
        .zip(values)
        .map(|(x, f)| (f - mean - g[0] * x[0] - g[1] * x[1]).abs())
        .fold(0.0, f64::max);
    Some((weights, residual))
}

/// Distance (m) from `p` to the triangle `t`.
fn to_triangle(p: DVec3, t: [DVec3; 3]) -> f64 {
    let [a, b, c] = t;
    let n = (b - a).cross(c - a);
    let len = n.length();
    if len > 0.0 {
        let n = n / len;
        let q = p - n * (p - a).dot(n);
        // Inside when q is on the inner side of every edge.
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|(u, w)| (*w - *u).cross(q - *u).dot(n) >= 0.0);
        if inside {
            return (p - a).dot(n).abs();
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|(u, w)| {
            let e = *w - *u;
            let t = ((p - *u).dot(e) / e.length_squared().max(1e-300)).clamp(0.0, 1.0);
            p.distance(*u + e * t)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Gathered receivers binned in cubes of edge `cell`: those within `cell` of a point are in its
/// cube or the 26 around it.
struct Grid {
    cell: f64,
    bins: HashMap<(i64, i64, i64), Vec<u32>>,
}

impl Grid {
    fn new(gathered: &[Gathered], cell: f64) -> Self {
        let mut bins: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
        for (g, c) in gathered.iter().enumerate() {
            let k = (c.point / cell).floor();
            bins.entry((k.x as i64, k.y as i64, k.z as i64))
                .or_default()
                .push(g as u32);
        }
        Grid { cell, bins }
    }

    fn near(&self, p: DVec3) -> impl Iterator<Item = u32> + '_ {
        let k = (p / self.cell).floor();
        let (x, y, z) = (k.x as i64, k.y as i64, k.z as i64);
        (-1..=1)
            .flat_map(move |i| {
                (-1..=1).flat_map(move |j| (-1..=1).map(move |l| (x + i, y + j, z + l)))
            })
            .filter_map(|key| self.bins.get(&key))
            .flatten()
            .copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::patches::PatchMesh;
    use crate::transport::tree::PatchTree;
    use crate::visibility::{Occluder, OccluderOptions};

    /// A room (8 × 3 × 6 m, glTF +Y up) whose floor a 1.2 m screen at x = 4 m divides, with
    /// tessellated balls on the floor: flat surfaces, a wall standing on one, and clutter.
    fn room() -> crate::scene::Scene {
        let mut b = SceneBuilder::new();
        let walls = b.material("walls", 0.6);
        let screen = b.material("screen", 0.5);
        let balls = b.material("balls", 0.4);
        b.axis_box("room", DVec3::ZERO, DVec3::new(8.0, 3.0, 6.0), true, walls);
        let (lo, hi) = (DVec3::new(3.95, 0.0, 0.0), DVec3::new(4.05, 1.2, 6.0));
        b.axis_box("screen", lo, hi, false, screen);
        for k in 0..4 {
            let c = DVec3::new(1.0 + k as f64 * 2.0, 0.3, 1.5 + 0.8 * k as f64);
            b.ball(&format!("ball{k}"), c, 0.3, (8, 12), balls);
        }
        b.point_light("lamp", DVec3::new(2.0, 2.8, 3.0), 1000.0);
        b.build()
    }

    struct Built {
        mesh: PatchMesh,
        tree: PatchTree,
        occluder: Occluder,
    }

    fn built(scene: &crate::scene::Scene) -> Built {
        let occluder = Occluder::build(scene, OccluderOptions::default());
        let mesh = crate::patches::build(scene, 0.25, None);
        let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        Built {
            mesh,
            tree,
            occluder,
        }
    }

    fn gatherer(b: &Built) -> Gatherer<'_> {
        Gatherer {
            mesh: &b.mesh,
            tree: &b.tree,
            occluder: &b.occluder,
            tau: 0.3,
            split_leaves: false,
            fronts_only: false,
            dark: None,
            covered: None,
        }
    }

    /// Full rows and shared rows of `b`, a field lit brighter toward −x (lm/m²).
    fn both(b: &Built, tolerance: f64) -> (ReceiverLinks, ReceiverLinks, Vec<DVec3>) {
        let gatherer = gatherer(b);
        let field: Vec<DVec3> = (b.mesh.patches.iter())
            .map(|p| {
                let c = p.corners(&b.mesh.receivers);
                let x = (c[0].x + c[1].x + c[2].x) / 3.0;
                DVec3::splat(100.0 * (1.0 + 0.1 * (8.0 - x)))
            })
            .collect();
        let direct = vec![DVec3::ZERO; b.mesh.receivers.len()];
        let sharing = Sharing {
            tolerance,
            direct: &direct,
            first_bounce: &field,
        };
        let full = ReceiverLinks::build(&gatherer, &b.mesh.receivers);
        let shared = build(&gatherer, &b.mesh.receivers, &sharing);
        (full, shared, field)
    }

    fn apply(b: &Built, links: &ReceiverLinks, field: &[DVec3]) -> Vec<f64> {
        let f = NodeField::new(&b.tree, &b.mesh, field);
        let mut out = vec![DVec3::ZERO; b.mesh.receivers.len()];
        links.apply(&f, &mut out);
        out.iter().map(|e| e.x).collect()
    }

    #[test]
    fn receivers_read_weighted_means_of_their_own_surface_in_sight() {
        let b = built(&room());
        let (_, shared, _) = both(&b, 0.01);
        let n = b.mesh.receivers.len();
        let rows = shared.rows();
        assert!(rows < n * 3 / 4, "{rows} rows gathered for {n} receivers");
        let mut blended = 0;
        for r in 0..n {
            let terms = shared.terms(r);
            let sum: f32 = terms.iter().map(|t| t.1).sum();
            assert!(
                (sum - 1.0).abs() < 1e-5,
                "receiver {r}: weights sum to {sum}"
            );
            let v = &b.mesh.receivers[r];
            for &(g, _) in &terms {
                let c = &b.mesh.receivers[shared.gathered_at(g as usize)];
                assert_eq!(c.group, v.group, "receiver {r} reads another surface");
                // Never across the screen standing on the floor.
                if v.normal.y > 0.9 && v.point.y < 1e-3 {
                    assert_eq!(
                        c.point.x < 4.0,
                        v.point.x < 4.0,
                        "receiver {r} reads across"
                    );
                }
            }
            blended += (terms.len() > 1) as usize;
        }
        assert!(blended > n / 4, "{blended} of {n} blended");
    }

    #[test]
    fn shared_rows_read_the_light_of_full_gathers_within_the_tolerance() {
        let b = built(&room());
        let (full, shared, field) = both(&b, 0.01);
        let (e_full, e_shared) = (apply(&b, &full, &field), apply(&b, &shared, &field));
        let (mut sum, mut sum_abs, mut worse) = (0.0, 0.0, 0);
        for (a, s) in e_full.iter().zip(&e_shared) {
            sum += a;
            sum_abs += (s - a).abs();
            worse += ((s - a).abs() > 0.03 * a.max(1.0)) as usize;
        }
        let mean_error = sum_abs / sum;
        assert!(mean_error < 2e-3, "mean |error| {mean_error:e} of the mean");
        assert!(worse * 100 < e_full.len(), "{worse} receivers off by > 3 %");
    }

    /// A receiver behind a card hung 10 cm above a floor reads no row from under the card's
    /// edge, where the light its front reflects still arrives. Here three rows (which fit a
    /// plane exactly) are what misled it; the two-row case (rows in a line say nothing off their
    /// line) is held by tests/diff.rs's draft-against-high bound on the same card.
    #[test]
    fn receivers_behind_a_hung_card_read_the_light_behind_it() {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        let card = b.material_full("card", DVec3::splat(0.6), None, true);
        b.floor("floor", 1.0, 0.0, grey);
        let p = DVec3::new;
        let corners = [
            p(-0.5, 0.1, 0.5),
            p(0.5, 0.1, 0.5),
            p(0.5, 0.6, 0.5),
            p(-0.5, 0.6, 0.5),
        ];
        b.quad("card", corners, card);
        b.point_light("lamp", p(0.0, 1.0, 0.0), 1000.0);
        let built = built(&b.build());
        let gatherer = gatherer(&built);
        // The card's side facing −z (toward the lamp) bright, everything else dim.
        let field: Vec<DVec3> = (built.mesh.patches.iter())
            .map(|p| {
                let c = p.corners(&built.mesh.receivers);
                let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
                DVec3::splat(if n.z < -0.5 { 1000.0 } else { 10.0 })
            })
            .collect();
        let direct = vec![DVec3::ZERO; built.mesh.receivers.len()];
        let sharing = Sharing {
            tolerance: 0.03,
            direct: &direct,
            first_bounce: &field,
        };
        let full = ReceiverLinks::build(&gatherer, &built.mesh.receivers);
        let shared = build(&gatherer, &built.mesh.receivers, &sharing);
        assert!(shared.rows() < built.mesh.receivers.len(), "nothing shared");
        let (e_full, e_shared) = (apply(&built, &full, &field), apply(&built, &shared, &field));
        for (r, v) in built.mesh.receivers.iter().enumerate() {
            let behind = v.normal.y > 0.9 && v.point.z > 0.5;
            let (a, s) = (e_full[r], e_shared[r]);
            assert!(
                !behind || (s - a).abs() <= 0.1 * a,
                "floor receiver at {} reads {s} lx, its own row {a} lx",
                v.point
            );
        }
    }

    /// Parts of whole groups, assembled, give the links of one build, row for row.
    #[test]
    fn parts_of_whole_groups_assemble_into_the_links_of_one_build() {
        // Three parts of interleaved groups (so no part is a contiguous range of receivers),
        // assembled in an order that is not the groups': the rows are copied.
        assert_parts_assemble_into_one_build(|group, _| group % 3, [2, 0, 1], false);
        // Three parts of consecutive groups, in order (a distributed bake's tasks): every
        // level's rows are moved.
        assert_parts_assemble_into_one_build(|group, groups| 3 * group / groups, [0, 1, 2], true);
    }

    /// Build the parts `part_of(group, groups)` says, in `order`; renumbered, their rows are
    /// the rows of one build, moved (each part's own chunks, leaving it none) when `moved`,
    /// else copied; assembled, the links of one build.
    fn assert_parts_assemble_into_one_build(
        part_of: impl Fn(u32, u32) -> u32,
        order: [u32; 3],
        moved: bool,
    ) {
        let b = built(&room());
        let gatherer = gatherer(&b);
        let (_, whole, field) = both(&b, 0.01);
        let direct = vec![DVec3::ZERO; b.mesh.receivers.len()];
        let sharing = Sharing {
            tolerance: 0.01,
            direct: &direct,
            first_bounce: &field,
        };
        let groups = b.mesh.groups.len() as u32;
        assert!(groups >= 6, "{groups} groups");
        let n = b.mesh.receivers.len();
        let parts = || -> Vec<Part> {
            (order.iter())
                .map(|&k| {
                    let subset: Vec<u32> = (0..n as u32)
                        .filter(|&r| part_of(b.mesh.receivers[r as usize].group, groups) == k)
                        .collect();
                    part(&gatherer, &b.mesh.receivers, &subset, &sharing)
                })
                .collect()
        };
        let mut first = parts();
        assert!(first.iter().all(|p| !p.receivers.is_empty()));
        let rows: Vec<usize> = first.iter().map(|p| p.links.rows()).collect();
        let (renumbered, _, numbering) = renumber(&mut first);
        assert!(rows.iter().all(|&r| r > 0));
        assert!(numbering.iter().zip(&rows).all(|(m, &r)| m.len() == r));
        let left: Vec<usize> = first.iter().map(|p| p.links.rows()).collect();
        assert_eq!(
            left.iter().all(|&r| r == 0),
            moved,
            "rows left in the parts: {left:?}"
        );
        // Parts made again (renumber took the rows of the first), assembled whole.
        let parted = assemble(parts(), n, b.tree.nodes.len());
        assert_eq!(parted.rows(), whole.rows());
        for g in 0..whole.rows() {
            let (a, c, d) = (whole.row(g), parted.row(g), renumbered.row(g));
            assert_eq!(a.leaves, c.leaves, "row {g}");
            assert_eq!(a.far, c.far, "row {g}");
            assert_eq!((a.leaves, a.far), (d.leaves, d.far), "row {g}");
            assert_eq!(whole.gathered_at(g), parted.gathered_at(g));
        }
        for r in 0..n {
            assert_eq!(whole.terms(r), parted.terms(r), "receiver {r}");
        }
        assert_eq!(whole.coverage, parted.coverage);
        assert_eq!(whole.closed, parted.closed);
        let (e1, e2) = (apply(&b, &whole, &field), apply(&b, &parted, &field));
        assert!(e1.iter().zip(&e2).all(|(x, y)| x.to_bits() == y.to_bits()));
    }

    /// A closed room: rows normalised to coverage 1 blend into rows of coverage 1 (energy
    /// conservation per bounce holds at every receiver), to the precision rows are stored with
    /// (`transport::packed`: a row's sum within half a step of its largest link, at most 2⁻¹¹ in
    /// a row whose links are at most 1).
    #[test]
    fn blends_of_closed_rows_keep_coverage_one() {
        let b = built(&room());
        let (_, shared, _) = both(&b, 0.03);
        let ones = vec![DVec3::ONE; b.mesh.patches.len()];
        let e = apply(&b, &shared, &ones);
        for (r, got) in e.iter().enumerate() {
            if shared.closed[r] {
                let expected = 1.0 - shared.back[r] as f64;
                assert!(
                    (got - expected).abs() <= 2f64.powi(-11),
                    "receiver {r}: {got} vs {expected}"
                );
            }
        }
        let closed = shared.closed.iter().filter(|c| **c).count();
        assert!(closed > e.len() * 9 / 10, "{closed} closed");
    }

    #[test]
    fn linear_weights_reproduce_a_plane_and_measure_curvature() {
        let v = Vertex {
            position: DVec3::new(0.3, 0.0, 0.2),
            normal: DVec3::Y,
            point: DVec3::new(0.3, 0.0, 0.2),
            group: 0,
        };
        let points = [(0.0, 0.0), (1.0, 0.1), (0.2, 0.9), (0.8, 0.7), (0.5, -0.2)]
            .map(|(x, z)| DVec3::new(x, 0.0, z));
        let ward = [0.3, 0.2, 0.2, 0.1, 0.2];
        let plane = |p: DVec3| 5.0 + 2.0 * p.x - 3.0 * p.z;
        let values = points.map(plane);
        let (w, residual) = linear(&points, &values, &ward, &v).expect("a fit");
        let at: f64 = w.iter().zip(&values).map(|(w, f)| w * f).sum();
        assert!((at - plane(v.point)).abs() < 1e-12, "{at}");
        assert!(residual < 1e-12, "{residual}");
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // A bowl is not a plane: the residual says so.
        let bowl = points.map(|p| plane(p) + 4.0 * p.length_squared());
        let (_, residual) = linear(&points, &bowl, &ward, &v).expect("a fit");
        assert!(residual > 0.1, "{residual}");
        // Points in a line give no plane.
        let line = [(0.0, 0.0), (0.5, 0.5), (1.0, 1.0)].map(|(x, z)| DVec3::new(x, 0.0, z));
        assert!(linear(&line, &[1.0, 2.0, 3.0], &[0.4, 0.3, 0.3], &v).is_none());
    }
}
