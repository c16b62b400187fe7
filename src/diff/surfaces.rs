//! The surface values of matched primitives, pushed in a fixed order (nodes in A's order, their
//! primitives, then within a primitive its vertices, its texels in atlas order, or its sample
//! points: vertices, then triangle centroids), one run per primitive (its node pair and B's
//! material group).
//!
//! - [`vertices`]: the vertex attributes, vertex by vertex.
//! - [`texels`]: the same layout in both bakes: each texel B's primitive stands on that has a
//!   footprint in either bake; then, in a run of no node or material, the texels with a
//!   footprint in either bake that no primitive of B stands on (none when charts are as the
//!   baker makes them).
//! - [`samples`]: each bake's lightmap read bilinearly at its own TEXCOORD_1 at every vertex and
//!   at the centroid of every triangle (B's triangles; the vertices are matched by index).
//!
//! A matched pair of primitives not lightmapped in both bakes is compared vertex by vertex in
//! every mode.

use super::matching::Matched;
use super::stats::{Columns, Loc};
use super::{BakedOutput, Quantity};
use crate::readback::{LightmapUse, Primitive};
use glam::DVec2;

/// Test a pair of values (A, B) at a place and add it to the columns.
pub(super) type Push<'a> = dyn FnMut(&mut Columns, Loc, f64, f64) + 'a;

/// The matched primitive pairs: (node pair, primitive in the node, A's, B's).
fn pairs<'o>(
    a: &'o BakedOutput,
    b: &'o BakedOutput,
    m: &'o Matched,
) -> impl Iterator<Item = (usize, usize, &'o Primitive, &'o Primitive)> + 'o {
    m.nodes.iter().enumerate().flat_map(move |(k, np)| {
        (np.prims_a.iter().zip(&np.prims_b).enumerate())
            .map(move |(j, (&ia, &ib))| (k, j, &a.primitives[ia], &b.primitives[ib]))
    })
}

/// One primitive pair vertex by vertex (B's vertices; A's by index, or through `by_position`).
fn vertex_run(
    q: Quantity,
    (k, j): (usize, usize),
    (pa, pb): (&Primitive, &Primitive),
    by_position: Option<&[u32]>,
    cols: &mut Columns,
    push: &mut Push,
) {
    let (xs, ys) = (q.values(pa), q.values(pb));
    for (v, &y) in ys.iter().enumerate() {
        let x = by_position.map_or(xs[v], |map| xs[map[v] as usize]);
        let loc = Loc::Vertex {
            pair: k,
            primitive: j,
            vertex: v,
        };
        push(cols, loc, x.into(), y.into());
    }
}

/// Every matched primitive vertex by vertex.
pub(super) fn vertices(
    q: Quantity,
    a: &BakedOutput,
    b: &BakedOutput,
    m: &Matched,
    cols: &mut Columns,
    push: &mut Push,
) {
    for (k, j, pa, pb) in pairs(a, b, m) {
        cols.run(Some(k), Some(m.material_of_b[pb.material]));
        let map = m.nodes[k].by_position.get(j).map(Vec::as_slice);
        vertex_run(q, (k, j), (pa, pb), map, cols, push);
    }
}

/// Every matched primitive texel by texel (the layouts are the same: checked by the caller).
pub(super) fn texels(
    q: Quantity,
    a: &BakedOutput,
    b: &BakedOutput,
    m: &Matched,
    cols: &mut Columns,
    push: &mut Push,
) {
    let mut seen: Vec<Vec<bool>> = (b.lightmaps.iter())
        .map(|l| vec![false; l.footprint.len()])
        .collect();
    lightmapped_pairs(q, a, b, m, cols, push, |k, j, _, (la, lb), cols, push| {
        let (ma, mb) = (&a.lightmaps[la.lightmap], &b.lightmaps[lb.lightmap]);
        for t in &lb.texels {
            let i = t.index as usize;
            seen[lb.lightmap][i] = true;
            if ma.footprint[i] > 0.0 || mb.footprint[i] > 0.0 {
                let loc = Loc::Texel {
                    pair: k,
                    primitive: j,
                    texel: t.index,
                };
                push(cols, loc, q.texel(ma, i), q.texel(mb, i));
            }
        }
    });
    cols.run(None, None);
    for (l, (ma, mb)) in a.lightmaps.iter().zip(&b.lightmaps).enumerate() {
        for (i, &on) in seen[l].iter().enumerate() {
            if !on && (ma.footprint[i] > 0.0 || mb.footprint[i] > 0.0) {
                let loc = Loc::AtlasTexel {
                    lightmap: l,
                    texel: i as u32,
                };
                push(cols, loc, q.texel(ma, i), q.texel(mb, i));
            }
        }
    }
}

/// Every matched primitive at its vertices and triangle centroids, each bake's lightmap read at
/// its own layout.
pub(super) fn samples(
    q: Quantity,
    a: &BakedOutput,
    b: &BakedOutput,
    m: &Matched,
    cols: &mut Columns,
    push: &mut Push,
) {
    lightmapped_pairs(q, a, b, m, cols, push, |k, j, pb, (la, lb), cols, push| {
        let (ma, mb) = (&a.lightmaps[la.lightmap], &b.lightmaps[lb.lightmap]);
        let read_a = |uv: DVec2| ma.bilinear(|i| q.texel(ma, i), uv);
        let read_b = |uv: DVec2| mb.bilinear(|i| q.texel(mb, i), uv);
        let n = lb.uv.len();
        for v in 0..n {
            let loc = Loc::Sample {
                pair: k,
                primitive: j,
                point: v,
            };
            push(cols, loc, read_a(la.uv[v]), read_b(lb.uv[v]));
        }
        for (t, tri) in pb.triangles.iter().enumerate() {
            let centroid = |uv: &[DVec2]| tri.iter().map(|&v| uv[v as usize]).sum::<DVec2>() / 3.0;
            let loc = Loc::Sample {
                pair: k,
                primitive: j,
                point: n + t,
            };
            push(
                cols,
                loc,
                read_a(centroid(&la.uv)),
                read_b(centroid(&lb.uv)),
            );
        }
    });
}

/// One run per matched primitive pair: `each` (node pair, primitive, B's primitive, the two
/// lightmap uses) where both are lightmapped, vertex by vertex where not.
fn lightmapped_pairs(
    q: Quantity,
    a: &BakedOutput,
    b: &BakedOutput,
    m: &Matched,
    cols: &mut Columns,
    push: &mut Push,
    mut each: impl FnMut(
        usize,
        usize,
        &Primitive,
        (&LightmapUse, &LightmapUse),
        &mut Columns,
        &mut Push,
    ),
) {
    for (k, j, pa, pb) in pairs(a, b, m) {
        cols.run(Some(k), Some(m.material_of_b[pb.material]));
        match (&pa.lightmap, &pb.lightmap) {
            (Some(la), Some(lb)) => each(k, j, pb, (la, lb), cols, push),
            _ => vertex_run(q, (k, j), (pa, pb), None, cols, push),
        }
    }
}
