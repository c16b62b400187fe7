//! Matching two outputs' nodes, primitives, vertices, materials and probes before comparing.
//!
//! Input: A and B ([`BakedOutput`]) and the [`Mode`]. Output: [`Matched`] (index pairs, display
//! names) or a [`Mismatch`] naming the first place where the two differ (A's order first, then
//! B's), with both files' node pointers (`/nodes/N`).
//!
//! - **Nodes** with baked primitives (vertices and means modes) by their path of names from the
//!   root plus occurrence: the k-th node of A with a path goes with the k-th of B with it.
//! - **Primitives** (vertices, texels and samples modes) by order within the node; **vertices**
//!   by index, their world positions within 10⁻⁶ × the scene size (the box diagonal over both
//!   files); in vertices mode, when only one bake has lightmaps and indices do not pair, by
//!   place ([`super::by_position`]).
//! - **Materials**: vertices mode groups by B's material names; means mode needs the same set of
//!   material names on baked primitives in both files.
//! - **Probes** (every mode) by node path and occurrence, positions within the same tolerance.
//!
//! Everything is linear in the size of the outputs (hash maps on paths, one pass over vertices).

use super::by_position::pair_vertices;
use super::{BakedOutput, Mismatch, Mode};
use glam::DVec3;
use std::collections::{HashMap, HashSet};

/// One matched pair of baked nodes (vertices mode: `prims_a[k]` goes with `prims_b[k]`).
pub(super) struct NodePair {
    pub name: String,
    pub prims_a: Vec<usize>,
    pub prims_b: Vec<usize>,
    /// Empty: vertices pair by index; else per primitive, A's vertex for each of B's (vertices
    /// paired by place: [`super::by_position`]).
    pub by_position: Vec<Vec<u32>>,
}

/// One matched pair of probe nodes (indices into the probe lists).
pub(super) struct ProbePair {
    pub name: String,
    pub a: usize,
    pub b: usize,
    /// Under the root `probes` → `working_plane`.
    pub working_plane: bool,
}

/// What is compared with what.
pub(super) struct Matched {
    /// Empty in probes mode.
    pub nodes: Vec<NodePair>,
    pub probes: Vec<ProbePair>,
    /// Material group names: B's material names, deduplicated, in B's material order.
    pub materials: Vec<String>,
    /// Material group of each of B's materials.
    pub material_of_b: Vec<usize>,
    /// Material group of each of A's materials (`usize::MAX`: a name B does not have).
    pub material_of_a: Vec<usize>,
}

/// Every node's path (`a/b/c`) in A and in B as an id: equal ids, equal paths. Paths are
/// interned as (parent's id, name), so a 10⁵-deep chain costs 10⁵ entries, not its strings.
fn path_ids(a: &BakedOutput, b: &BakedOutput) -> (Vec<u32>, Vec<u32>) {
    let mut interned: HashMap<(u32, String), u32> = HashMap::new();
    let mut ids = |input: &BakedOutput| {
        let mut id: Vec<Option<u32>> = vec![None; input.nodes.len()];
        for start in 0..input.nodes.len() {
            // Walk up to the first node with a known id (or a root), then fill in downwards.
            let mut chain = vec![start];
            while let Some(&i) = chain.last() {
                match input.nodes[i].parent {
                    Some(p) if id[i].is_none() && chain.len() <= input.nodes.len() => chain.push(p),
                    _ => break,
                }
            }
            let mut above = u32::MAX;
            for &i in chain.iter().rev() {
                let here = match id[i] {
                    Some(known) => known,
                    None => {
                        let next = interned.len() as u32;
                        *interned.entry((above, input.node_name(i))).or_insert(next)
                    }
                };
                id[i] = Some(here);
                above = here;
            }
        }
        id.into_iter()
            .map(Option::unwrap_or_default)
            .collect::<Vec<u32>>()
    };
    let ids_a = ids(a);
    (ids_a, ids(b))
}

/// Keys (path id, occurrence) for a list of nodes, in order.
fn keyed(paths: &[u32], nodes: &[usize]) -> Vec<(u32, usize)> {
    let mut seen: HashMap<u32, usize> = HashMap::new();
    nodes
        .iter()
        .map(|&n| {
            let k = seen.entry(paths[n]).or_insert(0);
            *k += 1;
            (paths[n], *k - 1)
        })
        .collect()
}

/// A node's path, with ` [k]` for the k-th node of that path (k > 1).
fn display_name(input: &BakedOutput, node: usize, k: usize) -> String {
    let path = input.node_path(node);
    if k == 0 {
        path
    } else {
        format!("{path} [{}]", k + 1)
    }
}

/// Baked nodes in order of first primitive, and each node's primitives.
fn baked_nodes(input: &BakedOutput) -> (Vec<usize>, Vec<Vec<usize>>) {
    let mut prims = vec![Vec::new(); input.nodes.len()];
    let mut order = Vec::new();
    for (k, p) in input.primitives.iter().enumerate() {
        if prims[p.node].is_empty() {
            order.push(p.node);
        }
        prims[p.node].push(k);
    }
    (order, prims)
}

pub(super) fn fmt_point(p: DVec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
}

/// The diagonal of the box around both outputs' vertices and probes (m).
fn scene_size(a: &BakedOutput, b: &BakedOutput) -> f64 {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for o in [a, b] {
        let vertices = o.primitives.iter().flat_map(|p| &p.positions);
        for &p in vertices.chain(o.probes.iter().map(|p| &p.position)) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if lo.x > hi.x { 0.0 } else { (hi - lo).length() }
}

/// Within `tolerance` of each other (false for a non-finite position).
fn near(p: DVec3, q: DVec3, tolerance: f64) -> bool {
    p.distance(q) <= tolerance
}

fn too_far(p: DVec3, q: DVec3, tolerance: f64, what: &str) -> Option<Mismatch> {
    (!near(p, q, tolerance)).then(|| {
        Mismatch(format!(
            "{what}: at {} in A vs {} in B, {:.3e} m apart (tolerance {:.3e} m)",
            fmt_point(p),
            fmt_point(q),
            p.distance(q),
            tolerance
        ))
    })
}

/// Match A with B for `mode`, or say where they differ.
pub(super) fn match_outputs(
    a: &BakedOutput,
    b: &BakedOutput,
    mode: Mode,
) -> Result<Matched, Mismatch> {
    let (ra, rb) = (&a, &b);
    let (paths_a, paths_b) = path_ids(ra, rb);
    let tolerance = 1e-6 * scene_size(a, b);
    let (material_of_b, materials) = material_groups(rb);
    let mut material_of_a = vec![usize::MAX; ra.materials.len()];
    let nodes = match mode {
        Mode::Probes => Vec::new(),
        Mode::Vertices | Mode::Texels | Mode::Samples | Mode::Means => {
            let mut nodes = match_nodes(ra, rb, &paths_a, &paths_b)?;
            if mode.by_vertex() {
                let by_index = match_vertices(ra, rb, &nodes, tolerance);
                // Lightmaps in one bake only: its vertices were laid out anew; pair by place.
                let one_sided = has_lightmaps(ra) != has_lightmaps(rb);
                match by_index {
                    Err(_) if mode == Mode::Vertices && one_sided => {
                        match_primitive_counts(ra, rb, &nodes)?;
                        pair_by_position(ra, rb, &mut nodes, tolerance)?;
                    }
                    other => other?,
                }
            } else {
                material_of_a = match_materials(ra, rb, &materials, &material_of_b)?;
            }
            nodes
        }
    };
    let probes = match_probes(a, b, &paths_a, &paths_b, tolerance)?;
    Ok(Matched {
        nodes,
        probes,
        materials,
        material_of_b,
        material_of_a,
    })
}

/// Baked nodes by path; a node in one file only, or without primitives in one, is a mismatch.
fn match_nodes(
    ra: &BakedOutput,
    rb: &BakedOutput,
    paths_a: &[u32],
    paths_b: &[u32],
) -> Result<Vec<NodePair>, Mismatch> {
    let (order_a, prims_a) = baked_nodes(ra);
    let (order_b, prims_b) = baked_nodes(rb);
    let keys_a = keyed(paths_a, &order_a);
    let keys_b = keyed(paths_b, &order_b);
    let index_b: HashMap<&(u32, usize), usize> =
        keys_b.iter().zip(&order_b).map(|(k, &n)| (k, n)).collect();
    let mut pairs = Vec::with_capacity(order_a.len());
    for (key, &na) in keys_a.iter().zip(&order_a) {
        let name = display_name(ra, na, key.1);
        let Some(&nb) = index_b.get(key) else {
            let in_b = paths_b.iter().position(|p| *p == key.0);
            return Err(Mismatch(match in_b {
                Some(nb) => format!(
                    "node {name} (/nodes/{na} in A, /nodes/{nb} in B): {} baked primitives vs 0",
                    prims_a[na].len()
                ),
                None => format!("node {name} (/nodes/{na} in A): missing in B"),
            }));
        };
        pairs.push(NodePair {
            name,
            prims_a: prims_a[na].clone(),
            prims_b: prims_b[nb].clone(),
            by_position: Vec::new(),
        });
    }
    let keys_a_set: HashSet<&(u32, usize)> = keys_a.iter().collect();
    if let Some(key) = keys_b.iter().find(|k| !keys_a_set.contains(k)) {
        let nb = index_b[key];
        let name = display_name(rb, nb, key.1);
        let in_a = paths_a.iter().position(|p| *p == key.0);
        return Err(Mismatch(match in_a {
            Some(na) => format!(
                "node {name} (/nodes/{na} in A, /nodes/{nb} in B): 0 baked primitives vs {}",
                prims_b[nb].len()
            ),
            None => format!("node {name} (/nodes/{nb} in B): missing in A"),
        }));
    }
    Ok(pairs)
}

/// Whether any baked primitive of `o` is lightmapped.
pub(super) fn has_lightmaps(o: &BakedOutput) -> bool {
    o.primitives.iter().any(|p| p.lightmap.is_some())
}

/// The same number of baked primitives in each node pair.
fn match_primitive_counts(
    ra: &BakedOutput,
    rb: &BakedOutput,
    pairs: &[NodePair],
) -> Result<(), Mismatch> {
    for pair in pairs {
        let (pa, pb) = (&pair.prims_a, &pair.prims_b);
        if pa.len() != pb.len() {
            let (na, nb) = (ra.primitives[pa[0]].node, rb.primitives[pb[0]].node);
            return Err(Mismatch(format!(
                "node {} (/nodes/{na} in A, /nodes/{nb} in B): {} baked primitives vs {}",
                pair.name,
                pa.len(),
                pb.len()
            )));
        }
    }
    Ok(())
}

/// Fill `by_position` of every node pair (see [`super::by_position`]).
fn pair_by_position(
    ra: &BakedOutput,
    rb: &BakedOutput,
    pairs: &mut [NodePair],
    tolerance: f64,
) -> Result<(), Mismatch> {
    for pair in pairs.iter_mut() {
        let mut maps = Vec::with_capacity(pair.prims_b.len());
        for (j, (&ia, &ib)) in pair.prims_a.iter().zip(&pair.prims_b).enumerate() {
            let (pa, pb) = (&ra.primitives[ia], &rb.primitives[ib]);
            let map = pair_vertices(pa, pb, tolerance).map_err(|(v, q)| {
                Mismatch(format!(
                    "node {} (/nodes/{} in A, /nodes/{} in B) primitive {j} vertex {v}: no \
                     vertex of A within {tolerance:.3e} m of {} in B",
                    pair.name,
                    pa.node,
                    pb.node,
                    fmt_point(q)
                ))
            })?;
            maps.push(map);
        }
        pair.by_position = maps;
    }
    Ok(())
}

/// Same primitive and vertex counts, vertices at the same places.
fn match_vertices(
    ra: &BakedOutput,
    rb: &BakedOutput,
    pairs: &[NodePair],
    tolerance: f64,
) -> Result<(), Mismatch> {
    for pair in pairs {
        let name = &pair.name;
        let (pa, pb) = (&pair.prims_a, &pair.prims_b);
        let (na, nb) = (ra.primitives[pa[0]].node, rb.primitives[pb[0]].node);
        let nodes = format!("(/nodes/{na} in A, /nodes/{nb} in B)");
        if pa.len() != pb.len() {
            return Err(Mismatch(format!(
                "node {name} {nodes}: {} baked primitives vs {}",
                pa.len(),
                pb.len()
            )));
        }
        for (k, (&ia, &ib)) in pa.iter().zip(pb).enumerate() {
            let (qa, qb) = (&ra.primitives[ia], &rb.primitives[ib]);
            if qa.positions.len() != qb.positions.len() {
                return Err(Mismatch(format!(
                    "node {name} {nodes} primitive {k}: {} vertices vs {}",
                    qa.positions.len(),
                    qb.positions.len()
                )));
            }
            let far = qa
                .positions
                .iter()
                .zip(&qb.positions)
                .position(|(p, q)| !near(*p, *q, tolerance));
            if let Some(v) = far {
                let what = format!("node {name} {nodes} primitive {k} vertex {v}");
                let (p, q) = (qa.positions[v], qb.positions[v]);
                return Err(too_far(p, q, tolerance, &what).expect("found as too far"));
            }
        }
    }
    Ok(())
}

/// B's material names, deduplicated in B's material order: (group of each material, names).
fn material_groups(rb: &BakedOutput) -> (Vec<usize>, Vec<String>) {
    let mut by_name: HashMap<String, usize> = HashMap::new();
    let mut names = Vec::new();
    let groups = (0..rb.materials.len())
        .map(|m| {
            let name = rb.material_name(m);
            *by_name.entry(name.clone()).or_insert_with(|| {
                names.push(name);
                names.len() - 1
            })
        })
        .collect();
    (groups, names)
}

/// Means mode: the material names on baked primitives must be the same set in both files.
fn match_materials(
    ra: &BakedOutput,
    rb: &BakedOutput,
    names: &[String],
    of_b: &[usize],
) -> Result<Vec<usize>, Mismatch> {
    let index: HashMap<&str, usize> = names
        .iter()
        .enumerate()
        .map(|(g, n)| (n.as_str(), g))
        .collect();
    let of_a: Vec<usize> = (0..ra.materials.len())
        .map(|m| {
            index
                .get(ra.material_name(m).as_str())
                .copied()
                .unwrap_or(usize::MAX)
        })
        .collect();
    let used_b: HashSet<usize> = rb.primitives.iter().map(|p| of_b[p.material]).collect();
    let mut used_a = HashSet::new();
    for p in &ra.primitives {
        let m = p.material;
        if !used_b.contains(&of_a[m]) {
            return Err(Mismatch(format!(
                "material {} (/materials/{m} in A): on no baked primitive of B",
                ra.material_name(m)
            )));
        }
        used_a.insert(of_a[m]);
    }
    if let Some(p) = rb
        .primitives
        .iter()
        .find(|p| !used_a.contains(&of_b[p.material]))
    {
        let m = p.material;
        return Err(Mismatch(format!(
            "material {} (/materials/{m} in B): on no baked primitive of A",
            names[of_b[m]]
        )));
    }
    Ok(of_a)
}

/// Probes by node path, at the same places.
fn match_probes(
    a: &BakedOutput,
    b: &BakedOutput,
    paths_a: &[u32],
    paths_b: &[u32],
    tolerance: f64,
) -> Result<Vec<ProbePair>, Mismatch> {
    let probe_nodes = |o: &BakedOutput| o.probes.iter().map(|p| p.node).collect::<Vec<_>>();
    let pk_a = keyed(paths_a, &probe_nodes(a));
    let pk_b = keyed(paths_b, &probe_nodes(b));
    let index_b: HashMap<&(u32, usize), usize> =
        pk_b.iter().enumerate().map(|(i, k)| (k, i)).collect();
    let mut probes = Vec::with_capacity(pk_a.len());
    for (ia, key) in pk_a.iter().enumerate() {
        let na = a.probes[ia].node;
        let path = a.node_path(na);
        let name = display_name(a, na, key.1);
        let Some(&ib) = index_b.get(key) else {
            return Err(Mismatch(format!(
                "probe {name} (/nodes/{na} in A): missing in B"
            )));
        };
        let nb = b.probes[ib].node;
        let what = format!("probe {name} (/nodes/{na} in A, /nodes/{nb} in B)");
        let (p, q) = (a.probes[ia].position, b.probes[ib].position);
        if let Some(m) = too_far(p, q, tolerance, &what) {
            return Err(m);
        }
        let working_plane = path.starts_with("probes/working_plane/");
        probes.push(ProbePair {
            name,
            a: ia,
            b: ib,
            working_plane,
        });
    }
    if pk_b.len() != probes.len() {
        let matched: HashSet<usize> = probes.iter().map(|p| p.b).collect();
        let ib = (0..pk_b.len()).find(|i| !matched.contains(i)).unwrap_or(0);
        return Err(Mismatch(format!(
            "probe {} (/nodes/{} in B): missing in A",
            display_name(b, b.probes[ib].node, pk_b[ib].1),
            b.probes[ib].node
        )));
    }
    Ok(probes)
}
