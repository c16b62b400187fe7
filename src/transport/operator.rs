//! The patch-to-patch transport operator the solver iterates, made energy-conserving.
//!
//! Input: the receiver rows ([`ReceiverLinks`]) over the patch tree. Output: a
//! [`PatchOperator`] G with E_i = rᵢ·Σ_j G_ij·c_j·B_j: patch irradiance from patch exitance, where
//! G = (mean over a patch's three receivers) ∘ (receiver rows) ∘ (area-mean over tree nodes).
//!
//! Why the scalings r and c: receivers are the patches' vertices, and the vertex (trapezoid)
//! quadrature of a patch's irradiance is poor for the sharply peaked transfer between patches
//! that meet at a corner. Rows (everything one patch receives) are exact for a closed receiver —
//! they are normalised to 1 — but columns (where one patch's light goes, Σ_i A_i·G_ij / A_j) then
//! scatter by tens of percent near corners. Any correlation between that scatter and exitance
//! loses or creates light every bounce, and at ρ = 0.99 a 0.1 % loss per bounce costs 10 %. For
//! a closed space the exact operator has unit rows and unit area-weighted columns, so
//! [`PatchOperator::balance`] finds diagonal scalings that restore both (Sinkhorn–Knopp iteration) on the closed patches,
//! leaving open ones as computed. The values users see are gathered at receivers without these
//! scalings; only the solver's energy bookkeeping uses them.

use super::field::{FieldValue, NodeField};
use super::link::moment_scale;
use super::links::ReceiverLinks;
use super::skeleton::Skeleton;
use super::tree::LEAF_SLOT;
use crate::geom::sh::DIST;
use crate::patches::PatchMesh;
use glam::DVec3;
use rayon::prelude::*;

const OVERRELAX: f64 = 1.5;

/// Patches whose target (the front-face share of their hemisphere) is below this are not
/// balanced: they are inside a solid.
const MIN_TARGET: f64 = 0.005;

/// The transpose's scatter runs in this many parts (in parallel), summed in order. Each part
/// holds 8 bytes per tree node and 144 per inner node while the transpose runs, so the part
/// count multiplies the transpose's memory on large scenes: few parts.
const TRANSPOSE_PARTS: usize = 2;

pub struct PatchOperator<'a> {
    pub mesh: &'a PatchMesh,
    pub tree: &'a Skeleton,
    pub links: &'a ReceiverLinks,
    /// Row and column scalings (1 until [`PatchOperator::balance`]).
    pub row: Vec<f64>,
    pub col: Vec<f64>,
}

/// How well the balancing went.
/// What the balancing did (recorded in the run summary).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct BalanceStats {
    pub iterations: usize,
    /// Area-weighted mean |row sum − target| and |column sum − target| over closed patches
    /// before balancing, and the largest column deviation.
    pub row_error_before: f64,
    pub column_error_before: f64,
    pub worst_column_before: f64,
    /// The same after.
    pub row_error_after: f64,
    pub column_error_after: f64,
    pub worst_column_after: f64,
    pub closed_patches: usize,
}

impl<'a> PatchOperator<'a> {
    pub(crate) fn new(mesh: &'a PatchMesh, tree: &'a Skeleton, links: &'a ReceiverLinks) -> Self {
        let n = mesh.patches.len();
        PatchOperator {
            mesh,
            tree,
            links,
            row: vec![1.0; n],
            col: vec![1.0; n],
        }
    }

    /// Irradiance per receiver from per-patch exitance (unscaled: what users see).
    pub(crate) fn gather_receivers(&self, b: &[DVec3]) -> Vec<DVec3> {
        self.gather_scaled(|p| b[p])
    }

    /// Irradiance per receiver from the per-patch exitance `b(patch)` (RGB, or one channel).
    fn gather_scaled<V: FieldValue>(&self, b: impl Fn(usize) -> V) -> Vec<V> {
        let field = NodeField::for_clusters(self.tree, self.mesh, b, &self.links.clusters);
        let mut out = vec![V::ZERO; self.mesh.receivers.len()];
        self.links.apply(&field, &mut out);
        out
    }

    /// Irradiance per patch from per-patch exitance, with the balancing scalings.
    pub(crate) fn apply(&self, b: &[DVec3]) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; b.len()];
        self.apply_fn(|p| b[p], &mut out);
        out
    }

    /// [`PatchOperator::apply`] of the exitance `b(patch)`, into `out`.
    pub(crate) fn apply_fn(&self, b: impl Fn(usize) -> DVec3, out: &mut [DVec3]) {
        let at = self.gather_scaled(|p| b(p) * self.col[p]);
        self.mesh
            .patches
            .par_iter()
            .zip(&self.row)
            .zip(out)
            .for_each(|((p, r), o)| {
                *o = p.v.iter().map(|&v| at[v as usize]).sum::<DVec3>() * (r / 3.0)
            });
    }

    /// One channel of `apply` (for the balancing: a third of the RGB field's work, the same
    /// sums in the same order).
    fn apply_scalar(&self, b: &[f64]) -> Vec<f64> {
        let at = self.gather_scaled(|p| b[p] * self.col[p]);
        (self.mesh.patches.par_iter())
            .zip(&self.row)
            .map(|(p, r)| p.v.iter().map(|&v| at[v as usize]).sum::<f64>() * (r / 3.0))
            .collect()
    }

    /// zⱼ = Σᵢ yᵢ·G_ij·c_j·rᵢ (the transpose of `apply`, scalar).
    fn apply_transpose(&self, y: &[f64]) -> Vec<f64> {
        let mesh = self.mesh;
        // Patch → receiver (each patch gives a third of its scaled value to each vertex).
        let mut at = vec![0.0; mesh.receivers.len()];
        for (i, p) in mesh.patches.iter().enumerate() {
            for &v in &p.v {
                at[v as usize] += y[i] * self.row[i] / 3.0;
            }
        }
        // Receiver → the rows it reads (itself, or the gathered rows it is blended from).
        let at = self.links.to_rows(at);
        let mut scattered = self.scatter(&at);
        // The links' gradients are stored relative to their node's size: scaled back per node.
        for (node, &s) in self.tree.nodes.iter().zip(self.tree.slot.iter()) {
            if let Some(g) = scattered.grad.get_mut(s as usize) {
                *g = match node.area > 0.0 {
                    true => *g / moment_scale(node.area),
                    false => DVec3::ZERO,
                };
            }
        }
        self.push_down(scattered)
    }

    /// Receiver → node (scatter along the links) of the receivers' values `at`: leaf and
    /// far-field coefficients per node, first moments and cluster distributions per inner node
    /// (only they are far sources).
    fn scatter(&self, at: &[f64]) -> Scattered {
        // A fixed number of parts (never the thread count), each accumulated over its receivers
        // in order into its own arrays, the parts summed in order: deterministic. The count is
        // fixed rather than the part size because every part costs a pass over all nodes: parts
        // of a fixed number of receivers would make that pass quadratic in the scene.
        let n = at.len();
        let per_part = n.div_ceil(TRANSPOSE_PARTS).max(1);
        let parts: Vec<Scattered> = (0..TRANSPOSE_PARTS)
            .into_par_iter()
            .map(|k| {
                let part = (k * per_part).min(n)..((k + 1) * per_part).min(n);
                self.scatter_part(at, part)
            })
            .collect();
        // The parts summed into the first, in order.
        let mut parts = parts.into_iter();
        let mut sum = parts.next().expect("parts");
        for part in parts {
            sum.add(&part);
        }
        sum
    }

    /// [`PatchOperator::scatter`] of the receivers `part`, in order, into arrays of its own.
    fn scatter_part(&self, at: &[f64], part: std::ops::Range<usize>) -> Scattered {
        let slot = &self.tree.slot;
        // Cluster accumulators only for the nodes cluster links name.
        let clusters = &self.links.clusters;
        let mut acc = vec![0.0; self.tree.nodes.len()];
        let mut grad = vec![DVec3::ZERO; self.tree.inner_nodes];
        let mut sh = vec![[0.0; DIST]; clusters.len()];
        for r in part {
            if at[r] == 0.0 {
                continue;
            }
            let row = self.links.row(r);
            for l in row.leaves.iter() {
                acc[l.node as usize] += at[r] * l.coeff as f64;
            }
            for l in row.far.iter() {
                if l.is_cluster() {
                    let (k, w) = l.cluster();
                    let weights = crate::geom::sh::dist_weights(w);
                    let c = clusters.get(l.node as usize).expect("a named node");
                    for (a, x) in sh[c].iter_mut().zip(weights) {
                        *a += at[r] * k * x;
                    }
                    continue;
                }
                acc[l.node as usize] += at[r] * l.coeff as f64;
                let s = slot[l.node as usize] as usize;
                if s != LEAF_SLOT as usize {
                    grad[s] += l.relative() * (l.coeff as f64 * at[r]);
                }
            }
        }
        Scattered { acc, grad, sh }
    }

    /// Node → patches (top-down push), in place. A node's mean is Σ Aⱼ·Bⱼ / A and its dipole
    /// Σ Aⱼ·Bⱼ·(cⱼ − c), so patch j collects Aⱼ·Σ_ancestors [acc/A − grad·c + grad·cⱼ]: each
    /// inner node's (acc/A − grad·c, grad) is added into its inner children's, parents first
    /// (the nodes are in pre-order), and a leaf reads its parent's sums. Cluster links read
    /// Σ Bⱼ·(Aⱼ's normal distribution): patch j collects its own (the leaf's `normal_sh`)
    /// against the sum of its ancestors' accumulations, pushed down the same way.
    fn push_down(&self, scattered: Scattered) -> Vec<f64> {
        let Scattered {
            acc: mut node_acc,
            grad: mut node_grad,
            sh: node_sh,
        } = scattered;
        let (nodes, slot) = (self.tree.nodes.len(), &self.tree.slot);
        let clusters = &self.links.clusters;
        node_acc.par_iter_mut().enumerate().for_each(|(i, a)| {
            *a /= self.tree.nodes[i].area;
            if slot[i] != LEAF_SLOT {
                *a -= node_grad[slot[i] as usize].dot(self.tree.centroid[i]);
            }
        });
        let mut z = vec![0.0; self.mesh.patches.len()];
        if nodes > 0 && slot[0] == LEAF_SLOT {
            let (p, v) = self.leaf(0, node_acc[0], 0.0, DVec3::ZERO, None); // a tree of one patch
            z[p] = v;
        }
        // Cluster sums go down a stack of the inner nodes above the current one (their ends in
        // `order` and cumulative sums): only the named nodes have accumulators of their own.
        let mut path: Vec<(u32, [f64; DIST])> = Vec::new();
        for i in 0..nodes {
            if slot[i] == LEAF_SLOT {
                continue;
            }
            let si = slot[i] as usize;
            let (a, g) = (node_acc[i], node_grad[si]);
            let sh = (!clusters.is_empty()).then(|| {
                let own = clusters.get(i).map(|c| node_sh[c]);
                cluster_sum(&mut path, own, self.tree.range[i])
            });
            for c in self.tree.children[i] {
                let c = c as usize;
                match slot[c] {
                    LEAF_SLOT => {
                        let (p, v) = self.leaf(c, node_acc[c], a, g, sh.as_ref());
                        z[p] = v;
                    }
                    sc => {
                        node_acc[c] += a;
                        node_grad[sc as usize] += g;
                    }
                }
            }
        }
        z
    }

    /// The patch of leaf `c` (own value `own`) under ancestors whose sums are `s`, `g` and `sh`,
    /// and its value in the transpose.
    fn leaf(&self, c: usize, own: f64, s: f64, g: DVec3, sh: Option<&[f64; DIST]>) -> (usize, f64) {
        let mesh = self.mesh;
        let p = self.tree.order[self.tree.range[c][0] as usize] as usize;
        let cj = self.tree.centroid[c];
        let clusters: f64 = sh.map_or(0.0, |sh| {
            let own = super::tree::leaf_sh(&mesh.patches[p]);
            (0..DIST).map(|k| sh[k] * own[k]).sum()
        });
        (
            p,
            ((own + s + g.dot(cj)) * mesh.patches[p].area + clusters) * self.col[p],
        )
    }

    /// Scale rows and columns of the closed patches to their targets: one minus the part of the
    /// patch's hemisphere covered by back faces (which absorb). By reciprocity the same fraction
    /// of what a patch sends lands on front faces. Patches with nothing but back faces in view
    /// (over 99.5 % of the hemisphere: inside solid objects) are left alone; a ceiling over the
    /// single-sided back of a panel hung below it sees 90–99 % back faces and is balanced like
    /// any other, or the light it passes on is lost.
    ///
    /// Black nodes get no links (`Gatherer::dark`), so a row sums to one minus the back faces
    /// and the black nodes it sees; the columns of `black` patches (whose exitance is zero
    /// whatever the scaling) are neither scaled nor measured.
    ///
    /// `open` (empty, or one per patch): the measured share of an open patch's hemisphere that
    /// leaves the scene (`transport::escape`). Such a patch's column (where its light goes) is
    /// scaled to one minus its back faces and that share, so what it sends is neither lost nor
    /// made by the links' quadrature (the Cornell box's light sent 0.35 % too little into the box
    /// at default quality); its row is left as computed.
    pub(crate) fn balance(
        &mut self,
        max_iterations: usize,
        tolerance: f64,
        black: &dyn Fn(usize) -> bool,
        open: &[f64],
    ) -> BalanceStats {
        let t = self.targets(black, open);
        let areas: Vec<f64> = self.mesh.patches.iter().map(|p| p.area).collect();
        let ones = vec![1.0; self.mesh.patches.len()];
        let errors = Errors {
            areas: &areas,
            t: &t,
        };
        let mut cols = self.column_sums(&areas);
        let mut stats = BalanceStats {
            iterations: 0,
            row_error_before: errors.rows(&self.apply_scalar(&ones)),
            column_error_before: errors.columns(&cols),
            worst_column_before: errors.worst(&cols),
            row_error_after: 0.0,
            column_error_after: 0.0,
            worst_column_after: 0.0,
            closed_patches: t.closed.iter().filter(|c| **c).count(),
        };
        let row_target = t.rows();
        let mut previous = f64::INFINITY;
        for _ in 0..max_iterations {
            // `cols` holds the current scalings' column sums (before the first step, the ones
            // measured above).
            stats.column_error_after = errors.columns(&cols);
            stats.worst_column_after = errors.worst(&cols);
            // Stop at the tolerance, or when an iteration no longer gains 5 %: the rest is
            // inconsistency between the estimated targets, not something more sweeps remove.
            if stats.column_error_after < tolerance || stats.column_error_after > 0.95 * previous {
                break;
            }
            previous = stats.column_error_after;
            stats.iterations += 1;
            self.scale_columns(&cols, &t, true);
            let rows = self.apply_scalar(&ones);
            for i in 0..rows.len() {
                if t.closed[i] && rows[i] > 0.0 {
                    self.row[i] *= row_target[i] / rows[i];
                }
            }
            cols = self.column_sums(&areas);
        }
        // Rows and columns cannot both reach targets whose area-weighted totals differ (a floor
        // patch with a vertex pressed under a desk leg's foot gathers two thirds of what it
        // sends): the columns decide whether light is kept, so a last plain column step makes
        // them exact and the rows carry the inconsistency (about 10⁻⁸ on average).
        if stats.iterations > 0 {
            self.scale_columns(&cols, &t, false);
            cols = self.column_sums(&areas);
            stats.column_error_after = errors.columns(&cols);
            stats.worst_column_after = errors.worst(&cols);
        }
        stats.row_error_after = errors.rows(&self.apply_scalar(&ones));
        stats
    }

    /// What [`PatchOperator::balance`] scales to: per patch one minus the back faces it sees
    /// (rows also minus the black nodes it sees; columns of open patches also minus their
    /// measured escape), which patches are closed and which columns are balanced.
    fn targets(&self, black: &dyn Fn(usize) -> bool, open: &[f64]) -> Targets {
        let mesh = self.mesh;
        let mean = |p: &crate::patches::Patch, f: &dyn Fn(usize) -> f64| {
            p.v.iter().map(|&v| f(v as usize)).sum::<f64>() / 3.0
        };
        let target: Vec<f64> = mesh
            .patches
            .iter()
            .map(|p| 1.0 - mean(p, &|r| self.links.back[r] as f64))
            .collect();
        let closed: Vec<bool> = mesh
            .patches
            .iter()
            .zip(&target)
            .map(|(p, t)| *t > MIN_TARGET && p.v.iter().all(|&v| self.links.closed[v as usize]))
            .collect();
        // Without black nodes rows and columns share their targets (two patch-sized arrays
        // fewer on a 10⁶-triangle bake).
        let row_target = self.links.has_dark().then(|| {
            mesh.patches
                .iter()
                .zip(&target)
                .map(|(p, t)| (t - mean(p, &|r| self.links.dark(r) as f64)).max(0.0))
                .collect()
        });
        // Columns: the closed patches', and the open ones' whose escape was measured.
        let measured =
            |j: usize| !closed[j] && open.get(j).is_some_and(|o| target[j] - o > MIN_TARGET);
        let col_target = (!open.is_empty()).then(|| {
            (0..target.len())
                .map(|j| match measured(j) {
                    true => target[j] - open[j],
                    false => target[j],
                })
                .collect()
        });
        let closed_column = (self.links.has_dark() || !open.is_empty()).then(|| {
            (0..closed.len())
                .map(|j| (closed[j] || measured(j)) && !black(j))
                .collect()
        });
        Targets {
            target,
            closed,
            row_target,
            col_target,
            closed_column,
        }
    }

    /// Each patch's column sum (where its light goes, Σᵢ Aᵢ·G_ij / Aⱼ) under the current
    /// scalings; `areas`: the patches' areas.
    fn column_sums(&self, areas: &[f64]) -> Vec<f64> {
        self.apply_transpose(areas)
            .iter()
            .zip(areas)
            .map(|(z, a)| z / a)
            .collect()
    }

    /// One Sinkhorn step on the balanced columns toward their targets from their sums `cols`:
    /// over-relaxed (exponent ω = 1.5) where `relax`, the slow, smooth part of the error going
    /// several times faster; the factor bounded for safety.
    fn scale_columns(&mut self, cols: &[f64], t: &Targets, relax: bool) {
        let (target, closed_column) = (t.columns(), t.closed_columns());
        for j in 0..cols.len() {
            if closed_column[j] && cols[j] > 0.0 {
                self.col[j] *= match relax {
                    true => (target[j] / cols[j]).powf(OVERRELAX).clamp(0.5, 2.0),
                    false => (target[j] / cols[j]).clamp(0.5, 2.0),
                };
            }
        }
    }
}

/// The targets of [`PatchOperator::balance`]: one minus the back faces per patch, whether each
/// patch is closed, and where black nodes or measured escape make them differ, the rows' and
/// columns' own targets and the set of columns balanced (`None`: `target` and `closed`).
struct Targets {
    target: Vec<f64>,
    closed: Vec<bool>,
    row_target: Option<Vec<f64>>,
    col_target: Option<Vec<f64>>,
    closed_column: Option<Vec<bool>>,
}

impl Targets {
    /// What each closed patch's row sums to.
    fn rows(&self) -> &[f64] {
        self.row_target.as_deref().unwrap_or(&self.target)
    }

    /// What each balanced column sums to.
    fn columns(&self) -> &[f64] {
        self.col_target.as_deref().unwrap_or(&self.target)
    }

    /// Which columns are balanced (and measured).
    fn closed_columns(&self) -> &[bool] {
        self.closed_column.as_deref().unwrap_or(&self.closed)
    }
}

/// How far row and column sums are from their [`Targets`], weighted by the patches' `areas`.
struct Errors<'a> {
    areas: &'a [f64],
    t: &'a Targets,
}

impl Errors<'_> {
    /// The area-weighted mean |sum − target| over the patches in `set`: what loses or creates
    /// flux each bounce.
    fn mean(&self, sums: &[f64], target: &[f64], set: &[bool]) -> f64 {
        let (mut deviation, mut area) = (0.0, 0.0);
        for i in (0..sums.len()).filter(|&i| set[i]) {
            deviation += self.areas[i] * (sums[i] - target[i]).abs();
            area += self.areas[i];
        }
        deviation / area.max(1e-300)
    }

    /// The mean deviation of the closed patches' row sums.
    fn rows(&self, sums: &[f64]) -> f64 {
        self.mean(sums, self.t.rows(), &self.t.closed)
    }

    /// The mean deviation of the balanced columns' sums.
    fn columns(&self, sums: &[f64]) -> f64 {
        self.mean(sums, self.t.columns(), self.t.closed_columns())
    }

    /// The largest single deviation of a balanced column's sum.
    fn worst(&self, sums: &[f64]) -> f64 {
        let (target, closed_column) = (self.t.columns(), self.t.closed_columns());
        (0..sums.len())
            .filter(|&i| closed_column[i])
            .map(|i| (sums[i] - target[i]).abs())
            .fold(0.0, f64::max)
    }
}

/// What the transpose scatters onto the tree's nodes: per node the summed coefficients, per
/// inner node the first moments, per named cluster node its normal distribution.
struct Scattered {
    acc: Vec<f64>,
    grad: Vec<DVec3>,
    sh: Vec<[f64; DIST]>,
}

impl Scattered {
    /// Adds `other` element by element (each sum on its own: parallel and deterministic).
    fn add(&mut self, other: &Scattered) {
        self.acc
            .par_iter_mut()
            .zip(&other.acc)
            .for_each(|(a, b)| *a += b);
        self.grad
            .par_iter_mut()
            .zip(&other.grad)
            .for_each(|(a, b)| *a += *b);
        self.sh.par_iter_mut().zip(&other.sh).for_each(|(a, b)| {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        });
    }
}

/// The cluster sum at the inner node spanning `start..end` of the tree's order: its own
/// accumulation `own` plus those of the inner nodes above it, kept on `path` (their ends and
/// cumulative sums; nodes come in pre-order, so those ending at or before `start` are done).
fn cluster_sum(
    path: &mut Vec<(u32, [f64; DIST])>,
    own: Option<[f64; DIST]>,
    [start, end]: [u32; 2],
) -> [f64; DIST] {
    while path.last().is_some_and(|(e, _)| *e <= start) {
        path.pop();
    }
    let sum = match (own, path.last()) {
        (Some(own), Some((_, up))) => std::array::from_fn(|k| own[k] + up[k]),
        (Some(own), None) => own,
        (None, Some((_, up))) => *up,
        (None, None) => [0.0; DIST],
    };
    path.push((end, sum));
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::transport::gather::Gatherer;
    use crate::transport::tree::PatchTree;
    use crate::visibility::{Occluder, OccluderOptions};

    /// A room with tessellated balls in it: far receivers see the balls as clusters.
    fn cluttered_room() -> crate::scene::Scene {
        let mut b = SceneBuilder::new();
        let walls = b.material("walls", 0.6);
        let boxes = b.material("boxes", 0.4);
        b.axis_box("room", DVec3::ZERO, DVec3::new(8.0, 3.0, 6.0), true, walls);
        for k in 0..6 {
            // Tessellated balls (curved clutter, 48 facets each) on the floor.
            let c = DVec3::new(1.0 + k as f64 * 1.1, 0.2, 2.0 + 0.3 * (k % 3) as f64);
            b.ball(&format!("ball{k}"), c, 0.2, (6, 8), boxes);
        }
        b.point_light("lamp", DVec3::new(4.0, 2.8, 3.0), 1000.0);
        b.build()
    }

    /// [`cluttered_room`] meshed at 0.2 m, its tree and every receiver's links (τ = 0.3): its
    /// own gather, or with `sharing` the rows `transport::sharing` shares at that tolerance.
    fn cluttered_links(
        sharing: Option<f64>,
    ) -> (crate::patches::PatchMesh, PatchTree, ReceiverLinks) {
        let scene = cluttered_room();
        let occluder = Occluder::build(&scene, OccluderOptions::default());
        let mesh = crate::patches::build(&scene, 0.2, None);
        let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        let gatherer = Gatherer {
            mesh: &mesh,
            tree: &tree,
            occluder: &occluder,
            tau: 0.3,
            split_leaves: false,
            fronts_only: false,
            dark: None,
            covered: None,
        };
        let links = match sharing {
            None => ReceiverLinks::build(&gatherer, &mesh.receivers),
            Some(tolerance) => {
                let first_bounce = vec![DVec3::splat(100.0); mesh.patches.len()];
                let direct = vec![DVec3::ZERO; mesh.receivers.len()];
                let sharing = crate::transport::sharing::Sharing {
                    tolerance,
                    direct: &direct,
                    first_bounce: &first_bounce,
                };
                crate::transport::sharing::build(&gatherer, &mesh.receivers, &sharing)
            }
        };
        (mesh, tree, links)
    }

    #[test]
    fn transpose_matches_apply_with_cluster_links() {
        let (mesh, tree, links) = cluttered_links(None);
        let clusters = links.far_links().filter(|l| l.is_cluster()).count();
        assert!(clusters > 100, "{clusters} cluster links");
        transpose_matches_apply(&mesh, &tree.into_skeleton(), &links);
    }

    /// Receivers that read blends of gathered rows (`transport::sharing`): the transpose carries
    /// their weights back to the rows.
    #[test]
    fn transpose_matches_apply_with_shared_rows() {
        let (mesh, tree, links) = cluttered_links(Some(0.03));
        let blended = (0..links.receivers())
            .filter(|&r| links.terms(r).len() > 1)
            .count();
        assert!(blended > 100, "{blended} blended receivers");
        transpose_matches_apply(&mesh, &tree.into_skeleton(), &links);
    }

    fn transpose_matches_apply(mesh: &PatchMesh, tree: &Skeleton, links: &ReceiverLinks) {
        let mut op = PatchOperator::new(mesh, tree, links);
        // Non-trivial scalings, as after balancing.
        let n = mesh.patches.len();
        let wave = |k: usize, a: f64| 1.0 + 0.3 * ((k as f64) * a).sin();
        op.row = (0..n).map(|k| wave(k, 0.7)).collect();
        op.col = (0..n).map(|k| wave(k, 1.3)).collect();
        let b: Vec<f64> = (0..n).map(|k| wave(k, 2.1)).collect();
        let y: Vec<f64> = (0..n).map(|k| wave(k, 0.37)).collect();
        let gb = op.apply_scalar(&b);
        let gty = op.apply_transpose(&y);
        let lhs: f64 = y.iter().zip(&gb).map(|(a, b)| a * b).sum();
        let rhs: f64 = gty.iter().zip(&b).map(|(a, b)| a * b).sum();
        assert!((lhs / rhs - 1.0).abs() < 1e-9, "{lhs} vs {rhs}");
    }

    /// The solver's fields (on the tree's skeleton) keep the normal distributions of the nodes
    /// cluster links name, and only those: bit for bit the full field's, so every row gathers
    /// the same light from both.
    #[test]
    fn solver_fields_keep_only_the_named_clusters_bit_for_bit() {
        let (mesh, tree, links) = cluttered_links(None);
        let kept = links.clusters.len();
        assert!(
            kept > 0 && kept < tree.inner_nodes / 2,
            "{kept} of {}",
            tree.inner_nodes
        );
        let b: Vec<DVec3> = (0..mesh.patches.len())
            .map(|k| DVec3::new(1.0, 2.0, 0.5) * (1.0 + 0.3 * (k as f64 * 0.9).sin()))
            .collect();
        let full = NodeField::new(&tree, &mesh, &b);
        let on_tree = NodeField::for_clusters(&tree, &mesh, |p| b[p], &links.clusters);
        let skeleton =
            PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect()).into_skeleton();
        let solver = NodeField::for_clusters(&skeleton, &mesh, |p| b[p], &links.clusters);
        assert_eq!(solver.mean, on_tree.mean);
        assert_eq!(solver.dipole, on_tree.dipole);
        assert_eq!(solver.sh, on_tree.sh);
        assert_eq!(solver.sh.len(), kept);
        let mut named = 0;
        for i in 0..tree.nodes.len() {
            if let Some(c) = links.clusters.get(i) {
                assert_eq!(solver.sh[c], full.sh[tree.slot[i] as usize], "node {i}");
                named += 1;
                // Against the definition: Σ over the node's patches of value × distribution.
                let node = &tree.bounds[i];
                let mut direct = [DVec3::ZERO; DIST];
                for &p in &tree.order[node.start as usize..node.end as usize] {
                    let patch = &mesh.patches[p as usize];
                    let d = crate::geom::sh::dist_point(patch.normal, patch.area);
                    for (x, y) in direct.iter_mut().zip(d) {
                        *x += b[p as usize] * y;
                    }
                }
                let scale = direct
                    .iter()
                    .map(|v| v.abs().max_element())
                    .fold(0.0, f64::max);
                for (k, (x, y)) in solver.sh[c].iter().zip(&direct).enumerate() {
                    let err = (*x - *y).abs().max_element();
                    assert!(err <= 1e-12 * scale, "node {i} coefficient {k}: {err}");
                }
            }
        }
        assert_eq!(named, kept);
        for r in 0..mesh.receivers.len() {
            let row = links.row(r);
            assert_eq!(
                solver.gather(row.far.iter()),
                full.gather(row.far.iter()),
                "receiver {r}"
            );
        }
    }
}
