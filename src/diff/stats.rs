//! The arithmetic of `bake diff`: the tolerance test of one value, max/mean/p95 of groups of
//! differences, and the running list of the worst places.
//!
//! Input: pairs (a, b) pushed into a [`Columns`] in a fixed order, in runs that belong to a node
//! and/or a material group. Output: [`Group`] figures per run set, and [`Candidate`]s for the
//! worst places. All linear in the number of values except the percentile (`select_nth`, linear
//! on average) and the final sort of at most a few × N candidates; results depend only on the
//! order values are pushed in.

use super::{Group, Stats};

/// The tolerance of one quantity, in its unit.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tolerance {
    pub atol: f64,
    pub rtol: f64,
    pub floor: f64,
}

/// The test of one value.
#[derive(Debug, Clone, Copy)]
pub(super) struct Check {
    /// |a − b| (infinite when not finite).
    pub abs: f64,
    /// |a − b| / max(|b|, floor).
    pub rel: f64,
    /// atol + rtol·max(|b|, floor).
    pub tolerance: f64,
    pub pass: bool,
    /// |a − b| / tolerance (how badly it fails; infinite for a difference at zero tolerance).
    pub ratio: f64,
}

impl Tolerance {
    /// A non-finite value on either side fails, even against the same value on the other.
    pub(crate) fn check(&self, a: f64, b: f64) -> Check {
        let finite = a.is_finite() && b.is_finite();
        let abs = if finite { (a - b).abs() } else { f64::INFINITY };
        let scale = if finite { b.abs().max(self.floor) } else { 1.0 };
        let tolerance = self.atol + self.rtol * scale;
        let ratio = if tolerance > 0.0 {
            abs / tolerance
        } else if abs > 0.0 {
            f64::INFINITY
        } else {
            0.0
        };
        Check {
            abs,
            rel: abs / scale,
            tolerance,
            pass: finite && abs <= tolerance,
            ratio,
        }
    }
}

/// Nearest-rank percentile `q` (0 < q ≤ 1) of `values` (reorders them); 0 when empty.
pub(super) fn percentile(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((q * values.len() as f64).ceil() as usize).clamp(1, values.len()) - 1;
    *values.select_nth_unstable_by(rank, f64::total_cmp).1
}

/// Max, mean and p95 of non-negative `values` (reorders them); all 0 when empty.
fn stats(values: &mut [f64]) -> Stats {
    if values.is_empty() {
        return Stats::default();
    }
    Stats {
        max: values.iter().copied().fold(0.0, f64::max),
        mean: values.iter().sum::<f64>() / values.len() as f64,
        p95: percentile(values, 0.95),
    }
}

/// Where a compared value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Loc {
    /// Node pair, primitive within the node, vertex.
    Vertex {
        pair: usize,
        primitive: usize,
        vertex: usize,
    },
    /// Node pair, primitive within the node, texel index in its atlas.
    Texel {
        pair: usize,
        primitive: usize,
        texel: u32,
    },
    /// A texel of atlas `lightmap` (index in B) no primitive of B stands on.
    AtlasTexel { lightmap: usize, texel: u32 },
    /// Node pair, primitive within the node, point: a vertex, or (vertex count + t) the centroid
    /// of triangle t.
    Sample {
        pair: usize,
        primitive: usize,
        point: usize,
    },
    /// Probe pair, face (0..6, `+x -x +y -y +z -z`).
    Probe { pair: usize, face: usize },
    /// The area-weighted mean of a node pair.
    NodeMean { pair: usize },
    /// The area-weighted mean of a material group.
    MaterialMean { group: usize },
}

/// A candidate for the worst places.
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub ratio: f64,
    pub rel: f64,
    /// Index into `Quantity::ALL`.
    pub quantity: usize,
    pub loc: Loc,
    pub a: f64,
    pub b: f64,
}

/// Worst first: by |a − b| / tolerance, then relative difference, then quantity and place.
fn worse(x: &Candidate, y: &Candidate) -> std::cmp::Ordering {
    y.ratio
        .total_cmp(&x.ratio)
        .then(y.rel.total_cmp(&x.rel))
        .then(x.quantity.cmp(&y.quantity))
        .then(x.loc.cmp(&y.loc))
}

/// The N worst candidates, kept in amortised linear time.
pub(super) struct Worst {
    n: usize,
    list: Vec<Candidate>,
}

impl Worst {
    pub(crate) fn new(n: usize) -> Self {
        Worst {
            n: n.max(1),
            list: Vec::new(),
        }
    }

    pub(crate) fn push(&mut self, c: Candidate) {
        self.list.push(c);
        if self.list.len() >= 4 * self.n + 64 {
            self.trim();
        }
    }

    fn trim(&mut self) {
        if self.list.len() > self.n {
            self.list.select_nth_unstable_by(self.n - 1, worse);
            self.list.truncate(self.n);
        }
    }

    /// At most N candidates, worst first.
    pub(crate) fn finish(mut self) -> Vec<Candidate> {
        self.trim();
        self.list.sort_by(worse);
        self.list
    }
}

/// One quantity's per-value differences in push order, and the runs they come in.
#[derive(Default)]
pub(super) struct Columns {
    abs: Vec<f64>,
    rel: Vec<f64>,
    failed: Vec<bool>,
    /// (node group, material group, start, end) of each run of values.
    runs: Vec<(Option<usize>, Option<usize>, usize, usize)>,
    open: Option<(Option<usize>, Option<usize>, usize)>,
}

impl Columns {
    /// Start a run of values belonging to `node` and/or `material` (closes the previous run).
    pub(crate) fn run(&mut self, node: Option<usize>, material: Option<usize>) {
        self.close();
        self.open = Some((node, material, self.abs.len()));
    }

    fn close(&mut self) {
        if let Some((n, m, s)) = self.open.take() {
            self.runs.push((n, m, s, self.abs.len()));
        }
    }

    /// Test one value; a differing one becomes a candidate for the worst places.
    pub(crate) fn push(
        &mut self,
        c: Check,
        worst: &mut Worst,
        at: (usize, Loc),
        (a, b): (f64, f64),
    ) {
        self.abs.push(c.abs);
        self.rel.push(c.rel);
        self.failed.push(!c.pass);
        if c.abs > 0.0 {
            worst.push(Candidate {
                ratio: c.ratio,
                rel: c.rel,
                quantity: at.0,
                loc: at.1,
                a,
                b,
            });
        }
    }

    /// The figures over all values, per node group (`nodes` of them) and per material group
    /// (`materials` of them; groups without values left out). Names come from `node_name` and
    /// `material_name`.
    pub(crate) fn groups(
        mut self,
        nodes: &[String],
        materials: &[String],
    ) -> (Group, Vec<Group>, Vec<Group>) {
        self.close();
        let mut scratch = Vec::new();
        let all = self.group("all".into(), &[(0, self.abs.len())], &mut scratch);
        let mut node_ranges = vec![Vec::new(); nodes.len()];
        let mut material_ranges = vec![Vec::new(); materials.len()];
        for &(n, m, s, e) in &self.runs {
            if let Some(n) = n {
                node_ranges[n].push((s, e));
            }
            if let Some(m) = m {
                material_ranges[m].push((s, e));
            }
        }
        let by = |names: &[String], ranges: &[Vec<(usize, usize)>], scratch: &mut Vec<f64>| {
            names
                .iter()
                .zip(ranges)
                .filter(|(_, r)| !r.is_empty())
                .map(|(name, r)| self.group(name.clone(), r, scratch))
                .collect::<Vec<_>>()
        };
        let by_node = by(nodes, &node_ranges, &mut scratch);
        let by_material = by(materials, &material_ranges, &mut scratch);
        (all, by_node, by_material)
    }

    fn group(&self, name: String, ranges: &[(usize, usize)], scratch: &mut Vec<f64>) -> Group {
        let mut gather = |column: &[f64]| {
            scratch.clear();
            for &(s, e) in ranges {
                scratch.extend_from_slice(&column[s..e]);
            }
            stats(scratch)
        };
        let abs = gather(&self.abs);
        let rel = gather(&self.rel);
        let values = ranges.iter().map(|(s, e)| e - s).sum();
        let failed = ranges
            .iter()
            .map(|&(s, e)| self.failed[s..e].iter().filter(|f| **f).count())
            .sum();
        Group {
            name,
            values,
            failed,
            abs,
            rel,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_is_nearest_rank() {
        let mut v: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(percentile(&mut v, 0.95), 19.0);
        let mut v = vec![3.0];
        assert_eq!(percentile(&mut v, 0.95), 3.0);
        assert_eq!(percentile(&mut [], 0.5), 0.0);
    }

    #[test]
    fn the_tolerance_is_atol_plus_rtol_times_the_floored_reference() {
        let t = Tolerance {
            atol: 0.5,
            rtol: 0.01,
            floor: 10.0,
        };
        let c = t.check(3.0, 2.0); // floor wins: 0.5 + 0.1
        assert_eq!((c.abs, c.rel, c.tolerance, c.pass), (1.0, 0.1, 0.6, false));
        let c = t.check(201.0, 200.0); // 0.5 + 2
        assert_eq!((c.rel, c.tolerance, c.pass), (0.005, 2.5, true));
        let c = t.check(f64::NAN, 1.0);
        assert!(c.abs.is_infinite() && !c.pass);
        // Infinity in B made the tolerance infinite and passed (issue 25); on both sides too.
        for (a, b) in [
            (5.0, f64::INFINITY),
            (f64::INFINITY, f64::INFINITY),
            (1.0, f64::NAN),
        ] {
            let c = t.check(a, b);
            assert!(
                !c.pass && c.abs.is_infinite() && c.ratio.is_infinite(),
                "{a} {b}: {c:?}"
            );
        }
    }

    #[test]
    fn worst_keeps_the_n_worst_in_order() {
        let mut w = Worst::new(3);
        for k in 0..1000 {
            let r = ((k * 7919) % 1000) as f64;
            w.push(Candidate {
                ratio: r,
                rel: 0.0,
                quantity: 0,
                loc: Loc::NodeMean { pair: k },
                a: 0.0,
                b: 0.0,
            });
        }
        let ratios: Vec<f64> = w.finish().iter().map(|c| c.ratio).collect();
        assert_eq!(ratios, [999.0, 998.0, 997.0]);
    }
}
