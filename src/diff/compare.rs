//! [`compare`]: the values of each quantity pushed in a fixed order (nodes in A's order, their
//! primitives and vertices, texels or sample points ([`super::surfaces`]); then materials;
//! probes in A's order, faces `+x … -z`), tested against the tolerance, summarised per node, per
//! material and overall; the worst places resolved to names and positions at the end.

use super::lightmaps::{explain, plan};
use super::matching::{Matched, match_outputs};
use super::stats::{Candidate, Check, Columns, Loc, Tolerance, Worst, percentile};
use super::surfaces::{self, Push};
use super::{BakedOutput, Diff, Mismatch, Mode, Options, Place, Quantity, QuantityDiff};
use crate::probes::FACE_NAMES;
use crate::readback::Texel;
use crate::report::Row;
use crate::report::rows::{Filter, row_from};
use glam::DVec3;

/// The default floor: 1 % of the nearest-rank 99th percentile of |b| of B's vertex
/// `_ILLUMINANCE` (1 lx when that is 0).
pub fn default_floor(b: &BakedOutput) -> f64 {
    let mut all: Vec<f64> = b
        .primitives
        .iter()
        .flat_map(|p| p.illuminance.iter().map(|&e| f64::from(e).abs()))
        .filter(|e| e.is_finite())
        .collect();
    let p99 = percentile(&mut all, 0.99);
    if p99 > 0.0 { 0.01 * p99 } else { 1.0 }
}

/// A group's area-weighted means (`[E, E direct, L]`, 0 without area) and centroid.
struct Means {
    values: [f64; 3],
    centroid: DVec3,
}

fn means(input: &BakedOutput, prims: &[usize], texels: bool) -> Means {
    let members: Vec<_> = prims.iter().map(|&k| &input.primitives[k]).collect();
    let values = row_from(input, "", &members, &Filter::All, texels)
        .map_or([0.0; 3], |r: Row| [r.e_avg, r.e_direct_avg, r.l_avg]);
    let (mut area, mut sum) = (0.0, DVec3::ZERO);
    for p in &members {
        for t in &p.triangles {
            let [a, b, c] = t.map(|v| p.positions[v as usize]);
            let w = (b - a).cross(c - a).length() / 2.0;
            area += w;
            sum += w * (a + b + c) / 3.0;
        }
    }
    let centroid = if area > 0.0 { sum / area } else { DVec3::ZERO };
    Means { values, centroid }
}

/// The per-group means of both files (means mode only): per node pair and per material group.
struct GroupMeans {
    nodes: Vec<(Means, Means)>,
    materials: Vec<Option<(Means, Means)>>,
}

fn group_means(a: &BakedOutput, b: &BakedOutput, m: &Matched, texels: bool) -> GroupMeans {
    let nodes = m
        .nodes
        .iter()
        .map(|p| (means(a, &p.prims_a, texels), means(b, &p.prims_b, texels)))
        .collect();
    let members = |input: &BakedOutput, group_of: &[usize], g: usize| -> Vec<usize> {
        (0..input.primitives.len())
            .filter(|&k| group_of[input.primitives[k].material] == g)
            .collect()
    };
    let materials = (0..m.materials.len())
        .map(|g| {
            let (pa, pb) = (
                members(a, &m.material_of_a, g),
                members(b, &m.material_of_b, g),
            );
            (!pb.is_empty()).then(|| (means(a, &pa, texels), means(b, &pb, texels)))
        })
        .collect();
    GroupMeans { nodes, materials }
}

/// Quantity `q`'s tolerance in its unit.
fn tolerance(q: Quantity, options: &Options, floor: f64) -> Tolerance {
    Tolerance {
        atol: q.in_unit(options.atol),
        rtol: options.rtol,
        floor: q.in_unit(floor),
    }
}

/// Compare A (the candidate) with B (the reference). `names` are the two files' names for the
/// output.
pub fn compare(
    a: &BakedOutput,
    b: &BakedOutput,
    options: &Options,
    names: (&str, &str),
) -> Result<Diff, Mismatch> {
    let m = match_outputs(a, b, options.mode).map_err(|e| explain(e, a, b, options.mode))?;
    let plan = plan(a, b, &m, options)?;
    let mode = plan.mode;
    let floor = options.floor.unwrap_or_else(|| default_floor(b));
    let means = (mode == Mode::Means).then(|| group_means(a, b, &m, plan.texel_means));
    let pair = Pair {
        a,
        b,
        m: &m,
        mode,
        means: means.as_ref(),
        node_names: m.nodes.iter().map(|p| p.name.clone()).collect(),
        probe_names: m.probes.iter().map(|p| p.name.clone()).collect(),
    };

    let mut worst = Worst::new(options.worst);
    let mut quantities = Vec::with_capacity(Quantity::ALL.len());
    for (qi, q) in Quantity::ALL.into_iter().enumerate() {
        let tolerance = tolerance(q, options, floor);
        quantities.push(pair.quantity(qi, q, tolerance, &mut worst));
    }

    let mut worst: Vec<Place> = worst
        .finish()
        .into_iter()
        .map(|c| place(&c, options, floor, b, &m, means.as_ref()))
        .collect();
    let worst_failure = worst.first().filter(|p| !p.pass).cloned();
    worst.truncate(options.worst);
    let counted = || quantities.iter().filter(|q| q.quantity != "workingPlane");
    let values = counted().map(|q| q.overall.values).sum();
    let failed = counted().map(|q| q.overall.failed).sum();
    Ok(Diff {
        a: names.0.to_owned(),
        b: names.1.to_owned(),
        mode,
        lightmaps: plan.note,
        rtol: options.rtol,
        atol: options.atol,
        floor,
        floor_is_default: options.floor.is_none(),
        pass: failed == 0,
        values,
        failed,
        quantities,
        worst,
        worst_failure,
    })
}

/// What every quantity is compared over: both files, their matching, the mode, the group means
/// (means mode only) and the groups' names.
struct Pair<'a> {
    a: &'a BakedOutput,
    b: &'a BakedOutput,
    m: &'a Matched,
    mode: Mode,
    means: Option<&'a GroupMeans>,
    node_names: Vec<String>,
    probe_names: Vec<String>,
}

impl Pair<'_> {
    /// Quantity `q` (number `qi`) tested against `tolerance` and summarised; its failures are
    /// offered to `worst`.
    fn quantity(
        &self,
        qi: usize,
        q: Quantity,
        tolerance: Tolerance,
        worst: &mut Worst,
    ) -> QuantityDiff {
        let mut cols = Columns::default();
        // The working plane's values are also probe faces: no second entry among the worst.
        let mut elsewhere = Worst::new(1);
        let w = if q == Quantity::WorkingPlane {
            &mut elsewhere
        } else {
            worst
        };
        let mut push = |cols: &mut Columns, loc: Loc, x: f64, y: f64| {
            cols.push(tolerance.check(x, y), w, (qi, loc), (x, y));
        };
        self.values(qi, q, &mut cols, &mut push);
        let (node_groups, material_groups): (&[String], &[String]) = match q {
            Quantity::ProbeFaces => (&self.probe_names, &[]),
            Quantity::WorkingPlane => (&[], &[]),
            _ => (&self.node_names, &self.m.materials),
        };
        let (overall, by_node, by_material) = cols.groups(node_groups, material_groups);
        QuantityDiff {
            quantity: q.key(),
            unit: q.unit(),
            atol: tolerance.atol,
            floor: tolerance.floor,
            overall,
            by_node,
            by_material,
        }
    }

    /// Pushes quantity `q`'s pairs of values in their fixed order: probe faces (or the working
    /// plane's upward face), else the surfaces' values by the mode, else the group means.
    fn values(&self, qi: usize, q: Quantity, cols: &mut Columns, push: &mut Push) {
        let (a, b, m) = (self.a, self.b, self.m);
        match q {
            Quantity::ProbeFaces | Quantity::WorkingPlane => {
                for (k, pp) in m.probes.iter().enumerate() {
                    let (fa, fb) = (&a.probes[pp.a].faces, &b.probes[pp.b].faces);
                    if q == Quantity::ProbeFaces {
                        cols.run(Some(k), None);
                        for f in 0..6 {
                            push(cols, Loc::Probe { pair: k, face: f }, fa[f], fb[f]);
                        }
                    } else if pp.working_plane {
                        push(cols, Loc::Probe { pair: k, face: 2 }, fa[2], fb[2]);
                    }
                }
            }
            _ if self.mode.by_vertex() => {
                let each = match self.mode {
                    Mode::Texels => surfaces::texels,
                    Mode::Samples => surfaces::samples,
                    _ => surfaces::vertices,
                };
                each(q, a, b, m, cols, push);
            }
            _ => {
                if let Some(gm) = self.means {
                    for (k, (ma, mb)) in gm.nodes.iter().enumerate() {
                        cols.run(Some(k), None);
                        push(
                            cols,
                            Loc::NodeMean { pair: k },
                            ma.values[qi],
                            mb.values[qi],
                        );
                    }
                    for (g, pair) in gm.materials.iter().enumerate() {
                        if let Some((ma, mb)) = pair {
                            cols.run(None, Some(g));
                            let (x, y) = (ma.values[qi], mb.values[qi]);
                            push(cols, Loc::MaterialMean { group: g }, x, y);
                        }
                    }
                }
            }
        }
    }
}

/// A candidate with its names and position.
fn place(
    c: &Candidate,
    options: &Options,
    floor: f64,
    b: &BakedOutput,
    m: &Matched,
    means: Option<&GroupMeans>,
) -> Place {
    let q = Quantity::ALL[c.quantity];
    let Check {
        abs,
        rel,
        tolerance,
        pass,
        ..
    } = tolerance(q, options, floor).check(c.a, c.b);
    let mut p = Place {
        quantity: q.key(),
        kind: "",
        node: None,
        material: None,
        primitive: None,
        vertex: None,
        triangle: None,
        atlas: None,
        texel: None,
        face: None,
        position: [0.0; 3],
        a: c.a,
        b: c.b,
        abs,
        rel,
        tolerance,
        pass,
    };
    locate(&mut p, c.loc, b, m, means);
    p
}

/// Fills in `p`'s kind, names and position (in B) from where the value is.
fn locate(p: &mut Place, loc: Loc, b: &BakedOutput, m: &Matched, means: Option<&GroupMeans>) {
    // A value on primitive `primitive` of node pair `pair`: its kind, node, material, index.
    let on_primitive = |p: &mut Place, kind: &'static str, pair: usize, primitive: usize| {
        let prim = &b.primitives[m.nodes[pair].prims_b[primitive]];
        p.kind = kind;
        p.node = Some(m.nodes[pair].name.clone());
        p.material = Some(m.materials[m.material_of_b[prim.material]].clone());
        p.primitive = Some(primitive);
        prim
    };
    match loc {
        Loc::Vertex {
            pair,
            primitive,
            vertex,
        } => {
            let prim = on_primitive(p, "vertex", pair, primitive);
            p.vertex = Some(vertex);
            p.position = prim.positions[vertex].to_array();
        }
        Loc::Texel {
            pair,
            primitive,
            texel,
        } => {
            let prim = on_primitive(p, "texel", pair, primitive);
            if let Some(layout) = &prim.lightmap {
                let lm = &b.lightmaps[layout.lightmap];
                p.atlas = Some(lm.atlas);
                p.texel = Some(lm.col_row(texel));
                let triangle = (layout.texels.binary_search_by_key(&texel, |t| t.index))
                    .map_or(0, |i| layout.texels[i].triangle);
                let t = Texel {
                    index: texel,
                    triangle,
                };
                p.position = prim.texel_point(lm, t).to_array();
            }
        }
        Loc::AtlasTexel { lightmap, texel } => {
            let lm = &b.lightmaps[lightmap];
            p.kind = "texel";
            p.atlas = Some(lm.atlas);
            p.texel = Some(lm.col_row(texel));
            p.position = [f64::NAN; 3];
        }
        Loc::Sample {
            pair,
            primitive,
            point,
        } => {
            let prim = on_primitive(p, "sample", pair, primitive);
            let n = prim.positions.len();
            if point < n {
                p.vertex = Some(point);
                p.position = prim.positions[point].to_array();
            } else {
                let tri = prim.triangles[point - n];
                p.triangle = Some(point - n);
                let sum: DVec3 = tri.iter().map(|&v| prim.positions[v as usize]).sum();
                p.position = (sum / 3.0).to_array();
            }
        }
        Loc::Probe { pair, face } => {
            let pp = &m.probes[pair];
            p.kind = "probe";
            p.node = Some(pp.name.clone());
            p.face = Some(FACE_NAMES[face]);
            p.position = b.probes[pp.b].position.to_array();
        }
        Loc::NodeMean { pair } => {
            p.kind = "nodeMean";
            p.node = Some(m.nodes[pair].name.clone());
            p.position = means.map_or([0.0; 3], |g| g.nodes[pair].1.centroid.to_array());
        }
        Loc::MaterialMean { group } => {
            p.kind = "materialMean";
            p.material = Some(m.materials[group].clone());
            let centroid = means.and_then(|g| g.materials[group].as_ref().map(|x| x.1.centroid));
            p.position = centroid.unwrap_or(DVec3::ZERO).to_array();
        }
    }
}
