//! A surface cut along the outlines of what covers it: every triangle of the result lies wholly
//! under a cover or wholly outside every cover, on each side.
//!
//! Input: one scene surface and its [`Cover`]s. Output: [`CutSurface`]: the surface's vertices
//! plus the new ones on outlines (normals and UVs interpolated), its triangles (cut ones
//! replaced by their pieces) and, per triangle, which sides are covered.
//!
//! Invariants: a point where an outline crosses an input edge is computed from the edge's ends in
//! a fixed order (by position) and the outline's half-plane, so the two triangles beside the edge
//! get the same point and share it; points closer than the tolerance to an outline count as on
//! it (no slivers); pieces are convex and fanned into triangles.

use super::{Cover, Seam};
use crate::scene::Surface;
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// Bit of `CutSurface::covered` for a side.
pub const FRONT: u8 = 1;
pub const BACK: u8 = 2;

/// A surface cut along its covers' outlines.
#[derive(Debug, Default)]
pub struct CutSurface {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: [`FRONT`] | [`BACK`] for the covered sides.
    pub covered: Vec<u8>,
    /// Per triangle: the largest depth of the covers over it (m; 0 when uncovered).
    pub gap: Vec<f64>,
    /// Per triangle: a piece of a triangle cut along a seam (its sides are judged by what is in
    /// front of them, see `contacts::find`).
    pub seamed: Vec<bool>,
    /// Edges (vertex pairs, smaller first) along a crease: see [`part_creases`].
    pub creases: Vec<(u32, u32)>,
}

/// Where a piece's vertex came from: an input vertex, a point on an input edge (its ends'
/// indices, smaller first), or a point inside input triangle `t`. Points are shared by key and
/// position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Origin {
    Vertex(u32),
    Edge(u32, u32),
    Inner(u32),
}

#[derive(Debug, Clone, Copy)]
struct Point {
    pos: DVec3,
    origin: Origin,
    /// Barycentric weights over the input triangle's three vertices.
    bary: DVec3,
}

/// Cut `surface` along `covers` and `seams` (each sorted by triangle); `eps`: the tolerance (m).
/// A triangle with no edge as long as `whole_below` (m) is not cut: smaller than a patch, it is
/// covered as a whole on a side where covers hold most of it (tessellated clutter — a chair's
/// tubes under its seat — would otherwise become a patch per sliver).
pub(crate) fn cut(
    surface: &Surface,
    covers: &[Cover],
    seams: &[Seam],
    eps: f64,
    whole_below: f64,
) -> CutSurface {
    let mut out = CutSurface {
        positions: surface.positions.clone(),
        normals: surface.normals.clone(),
        uv0: surface.uv0.clone(),
        uv1: surface.uv1.clone(),
        ..Default::default()
    };
    let mut shared: HashMap<Origin, Vec<u32>> = HashMap::new();
    // First every triangle's pieces, their points registered (so that every point on an input
    // edge is known before any triangle is triangulated)...
    let mut cuts: Vec<Cut> = Vec::with_capacity(surface.triangles.len());
    // Points put on each input edge, by the edge's place (its ends' positions, ordered): two
    // triangles beside one edge may not share vertex indices (a crease, or an exporter's
    // duplicates), yet each must have the other's points.
    let mut on_edges: HashMap<[[u64; 3]; 2], Vec<DVec3>> = HashMap::new();
    let (mut at, mut seam_at) = (0, 0);
    for (k, tri) in surface.triangles.iter().enumerate() {
        let start = at;
        while at < covers.len() && covers[at].triangle as usize == k {
            at += 1;
        }
        let seam_start = seam_at;
        while seam_at < seams.len() && seams[seam_at].triangle as usize == k {
            seam_at += 1;
        }
        let corners: Vec<Point> = (0..3)
            .map(|i| Point {
                pos: surface.positions[tri[i] as usize],
                origin: Origin::Vertex(tri[i]),
                bary: DVec3::AXES[i],
            })
            .collect();
        let p = corners.iter().map(|c| c.pos).collect::<Vec<_>>();
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let mut pieces = vec![(corners, 0u8, 0.0)];
        for cover in &covers[start..at] {
            pieces = split_by(pieces, cover, k as u32, eps);
        }
        let seamed = seam_start < seam_at;
        let longest = (0..3)
            .map(|i| p[i].distance(p[(i + 1) % 3]))
            .fold(0.0, f64::max);
        // A seam is cut along however small the triangle: a floor's piece in a door's opening
        // under a leaf would otherwise join the rooms on either side of the leaf.
        if longest < whole_below && !seamed {
            let (mask, gap) = whole(&pieces, normal);
            let ids: Vec<(u32, Point)> = (0..3)
                .map(|i| {
                    (
                        tri[i],
                        Point {
                            pos: surface.positions[tri[i] as usize],
                            origin: Origin::Vertex(tri[i]),
                            bary: DVec3::AXES[i],
                        },
                    )
                })
                .collect();
            cuts.push(Cut {
                normal,
                pieces: vec![(ids, mask, gap)],
                seamed,
                creases: seam_start..seam_at,
            });
            continue;
        }
        for seam in &seams[seam_start..seam_at] {
            // An end closer than a quarter patch to the triangle's outline is taken to it (no
            // sliver across the triangle's corner).
            let [a, b] = seam.ends.map(|x| inside_triangle(&p, x, whole_below / 4.0));
            pieces = split_along(pieces, seam, [a, b], k as u32, eps);
        }
        // Pieces meet along their cut lines; a corner of one lying on another's edge is put
        // into that edge too, so the pieces share every point (no T-junctions inside a triangle).
        let all: Vec<Point> = pieces.iter().flat_map(|p| p.0.iter().copied()).collect();
        let pieces = (pieces.into_iter())
            .map(|(piece, mask, gap)| {
                let piece = match all.len() > 3 {
                    true => with_points_on_edges(&piece, &all, eps),
                    false => piece,
                };
                let ids = (piece.iter())
                    .map(|pt| {
                        if let Origin::Edge(p, q) = pt.origin {
                            let key = geometric(
                                surface.positions[p as usize],
                                surface.positions[q as usize],
                            );
                            on_edges.entry(key).or_default().push(pt.pos);
                        }
                        (vertex(&mut out, &mut shared, surface, *tri, pt, eps), *pt)
                    })
                    .collect();
                (ids, mask, gap)
            })
            .collect();
        cuts.push(Cut {
            normal,
            pieces,
            seamed,
            creases: seam_start..seam_at,
        });
    }
    // ...then each piece with the points of its neighbours' cuts on its edges put in (no
    // T-junctions across input edges either), fanned by ears.
    let crease_edges = fan(&mut out, &mut shared, surface, cuts, &on_edges, seams, eps);
    out.creases = crease_edges.into_iter().collect();
    out.creases.sort_unstable();
    out
}

/// A triangle judged whole: covered on a side where its covered `pieces` hold more than half
/// of it; the mask and the deepest cover's depth there.
fn whole(pieces: &[Piece], normal: DVec3) -> (u8, f64) {
    let area = |poly: &[Point]| {
        let pos: Vec<DVec3> = poly.iter().map(|x| x.pos).collect();
        area_centroid(&pos, normal).0
    };
    let total: f64 = pieces.iter().map(|x| area(&x.0)).sum();
    let mut mask = 0;
    let mut gap = 0.0f64;
    for bit in [FRONT, BACK] {
        let under: f64 = (pieces.iter())
            .filter(|x| x.1 & bit != 0)
            .map(|x| area(&x.0))
            .sum();
        if under > 0.5 * total {
            mask |= bit;
            gap = pieces
                .iter()
                .filter(|x| x.1 & bit != 0)
                .fold(gap, |g, x| g.max(x.2));
        }
    }
    (mask, gap)
}

/// A triangle's pieces, their points registered, before triangulation.
struct Cut {
    normal: DVec3,
    pieces: Vec<Placed>,
    seamed: bool,
    creases: std::ops::Range<usize>,
}

/// Every piece of `cuts` (one per input triangle) with the points its neighbours put on its
/// edges, fanned by ears into `out`; returns the edges along creases.
fn fan(
    out: &mut CutSurface,
    shared: &mut HashMap<Origin, Vec<u32>>,
    surface: &Surface,
    cuts: Vec<Cut>,
    on_edges: &HashMap<[[u64; 3]; 2], Vec<DVec3>>,
    seams: &[Seam],
    eps: f64,
) -> std::collections::HashSet<(u32, u32)> {
    let mut crease_edges = std::collections::HashSet::new();
    for (k, c) in cuts.into_iter().enumerate() {
        let tri = surface.triangles[k];
        for (piece, mask, gap) in c.pieces {
            let mut id = |pt: &Point| vertex(out, shared, surface, tri, pt, eps);
            let piece = with_edge_points(&piece, on_edges, &surface.positions, &mut id, eps);
            let pos: Vec<DVec3> = piece.iter().map(|p| p.1.pos).collect();
            for t in ears(&pos, c.normal, eps) {
                let t = t.map(|i| piece[i].0);
                for i in 0..3 {
                    let (a, b) = (t[i], t[(i + 1) % 3]);
                    let (pa, pb) = (out.positions[a as usize], out.positions[b as usize]);
                    if (seams[c.creases.clone()].iter())
                        .any(|x| x.crease && on_seam(x, pa, pb, eps))
                    {
                        crease_edges.insert((a.min(b), a.max(b)));
                    }
                }
                out.triangles.push(t);
                out.covered.push(mask);
                out.gap.push(gap);
                out.seamed.push(c.seamed);
            }
        }
    }
    crease_edges
}

/// Whether segment a–b lies on the seam's segment (within `eps`).
fn on_seam(seam: &Seam, a: DVec3, b: DVec3, eps: f64) -> bool {
    let (m, d) = seam.line;
    let along = (seam.ends[1] - seam.ends[0]).normalize_or_zero();
    let (s0, s1) = (along.dot(seam.ends[0]), along.dot(seam.ends[1]));
    [a, b].iter().all(|&x| {
        let s = along.dot(x);
        (m.dot(x) - d).abs() <= eps && s >= s0 - eps && s <= s1 + eps
    })
}

/// Give every vertex on a crease one copy per side: the open triangles around a vertex that
/// meet across edges not on a crease keep one vertex; each other such set gets a copy
/// (positions, normals and UVs the same), so nothing is interpolated across a partition's
/// foot. Around a partition's free end the triangles still meet, and the vertex stays one;
/// covered triangles (`all_sides` covered: under a wall standing where the partition ends)
/// join nothing. Run once the covered sides are known.
/// Returns the number of copies made.
pub(crate) fn part_creases(out: &mut CutSurface, all_sides: u8) -> usize {
    if out.creases.is_empty() {
        return 0;
    }
    let before = out.positions.len();
    let creases: std::collections::HashSet<(u32, u32)> = out.creases.iter().copied().collect();
    let creases = &creases;
    let mut around: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for &(a, b) in creases {
        around.entry(a).or_default();
        around.entry(b).or_default();
    }
    for (i, t) in out.triangles.iter().enumerate() {
        for v in t {
            if let Some(list) = around.get_mut(v) {
                list.push(i as u32);
            }
        }
    }
    for (v, tris) in around {
        // Union the triangles around v that share a non-crease edge at v.
        let mut parent: Vec<usize> = (0..tris.len()).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        let others = |t: u32| -> Vec<u32> {
            let t = out.triangles[t as usize];
            t.into_iter().filter(|&w| w != v).collect()
        };
        let open = |t: u32| out.covered[t as usize] & all_sides != all_sides;
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                if !open(tris[i]) || !open(tris[j]) {
                    continue;
                }
                let (a, b) = (others(tris[i]), others(tris[j]));
                let joined = a
                    .iter()
                    .any(|w| b.contains(w) && !creases.contains(&(v.min(*w), v.max(*w))));
                if joined {
                    let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                    parent[ri.max(rj)] = ri.min(rj);
                }
            }
        }
        // The set holding the first triangle keeps v; each other set gets a copy.
        let mut copy: HashMap<usize, u32> = HashMap::new();
        let Some(first) = (0..tris.len()).find(|&i| open(tris[i])) else {
            continue;
        };
        let keep = root(&mut parent, first);
        for i in 0..tris.len() {
            let r = root(&mut parent, i);
            if r == keep || !open(tris[i]) {
                continue;
            }
            let w = *copy.entry(r).or_insert_with(|| {
                out.positions.push(out.positions[v as usize]);
                out.normals.push(out.normals[v as usize]);
                if let Some(uv) = out.uv0.as_mut() {
                    uv.push(uv[v as usize]);
                }
                if let Some(uv) = out.uv1.as_mut() {
                    uv.push(uv[v as usize]);
                }
                out.positions.len() as u32 - 1
            });
            for c in out.triangles[tris[i] as usize].iter_mut() {
                if *c == v {
                    *c = w;
                }
            }
        }
    }
    out.positions.len() - before
}

/// The input edge two points both lie on, if any (smaller index first).
fn common_edge(a: Origin, b: Origin) -> Option<(u32, u32)> {
    match (a, b) {
        (Origin::Vertex(i), Origin::Vertex(j)) if i != j => Some((i.min(j), i.max(j))),
        (Origin::Vertex(i), Origin::Edge(p, q)) | (Origin::Edge(p, q), Origin::Vertex(i))
            if i == p || i == q =>
        {
            Some((p, q))
        }
        (Origin::Edge(p, q), Origin::Edge(r, u)) if (p, q) == (r, u) => Some((p, q)),
        _ => None,
    }
}

/// The place of the edge between `a` and `b`, whichever way it runs.
fn geometric(a: DVec3, b: DVec3) -> [[u64; 3]; 2] {
    let (a, b) = if lex_less(b, a) { (b, a) } else { (a, b) };
    [
        a.to_array().map(f64::to_bits),
        b.to_array().map(f64::to_bits),
    ]
}

/// `poly` (ids and points) with the points put on each input edge it runs along (by any
/// triangle) inserted between its ends, in order; `id` gives a point's vertex.
fn with_edge_points(
    poly: &[(u32, Point)],
    on_edges: &HashMap<[[u64; 3]; 2], Vec<DVec3>>,
    input: &[DVec3],
    id: &mut dyn FnMut(&Point) -> u32,
    eps: f64,
) -> Vec<(u32, Point)> {
    let mut out = Vec::with_capacity(poly.len());
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        out.push(a);
        let Some((p, q)) = common_edge(a.1.origin, b.1.origin) else {
            continue;
        };
        let Some(on) = on_edges.get(&geometric(input[p as usize], input[q as usize])) else {
            continue;
        };
        let d = b.1.pos - a.1.pos;
        let len = d.length();
        if len <= eps {
            continue;
        }
        let mut inner: Vec<(f64, DVec3)> = (on.iter())
            .map(|&x| ((x - a.1.pos).dot(d) / len, x))
            .filter(|(t, _)| *t > eps && *t < len - eps)
            .collect();
        inner.sort_by(|x, y| x.0.total_cmp(&y.0));
        inner.dedup_by(|x, y| x.1.distance(y.1) <= eps);
        for (t, x) in inner {
            let s = t / len;
            let pt = Point {
                pos: x,
                origin: Origin::Edge(p, q),
                bary: a.1.bary + (b.1.bary - a.1.bary) * s,
            };
            out.push((id(&pt), pt));
        }
    }
    out
}

/// Split the pieces the seam's segment runs through along its line, only within the segment:
/// a piece reaching past an end is first cut across the line there, and only its part beside
/// the segment is split along it (a shelf's foot on a wall parts the wall over the shelf's
/// length, not the wall triangle's).
/// `ends_inside`: which ends of the seam lie inside the triangle (not on its outline, where the
/// seam only leaves this triangle for the next).
fn split_along(
    pieces: Vec<Piece>,
    seam: &Seam,
    ends_inside: [bool; 2],
    t: u32,
    eps: f64,
) -> Vec<Piece> {
    let (m, d) = seam.line;
    let along = (seam.ends[1] - seam.ends[0]).normalize_or_zero();
    let (s0, s1) = (along.dot(seam.ends[0]), along.dot(seam.ends[1]));
    let mut out = Vec::with_capacity(pieces.len() + 1);
    for (piece, mask, gap) in pieces {
        let dist: Vec<f64> = piece.iter().map(|p| m.dot(p.pos) - d).collect();
        let straddles = dist.iter().any(|x| *x > eps) && dist.iter().any(|x| *x < -eps);
        let (lo, hi) = (piece.iter().map(|p| along.dot(p.pos)))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        if !straddles || hi < s0 + eps || lo > s1 - eps {
            out.push((piece, mask, gap));
            continue;
        }
        let mut middle = piece;
        if ends_inside[0] && lo < s0 - eps {
            let (inner, before) = clip_points(&middle, |x| along.dot(x) - s0, t, eps);
            push_part(&mut out, before, mask, gap);
            middle = inner;
        }
        if ends_inside[1] && hi > s1 + eps {
            let (after, inner) = clip_points(&middle, |x| along.dot(x) - s1, t, eps);
            push_part(&mut out, after, mask, gap);
            middle = inner;
        }
        let (a, b) = clip_points(&middle, |x| m.dot(x) - d, t, eps);
        push_part(&mut out, a, mask, gap);
        push_part(&mut out, b, mask, gap);
    }
    out
}

/// Whether `x` (in the triangle's plane) lies inside triangle `p`, further than `eps` from each
/// of its edges.
fn inside_triangle(p: &[DVec3], x: DVec3, eps: f64) -> bool {
    (0..3).all(|i| {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        let e = b - a;
        let t = ((x - a).dot(e) / e.length_squared().max(1e-300)).clamp(0.0, 1.0);
        x.distance(a + e * t) > eps
    })
}

fn push_part(out: &mut Vec<Piece>, part: Vec<Point>, mask: u8, gap: f64) {
    if part.len() >= 3 {
        out.push((part, mask, gap));
    }
}

/// `poly` with every point of `points` that lies inside one of its edges (within `eps`)
/// inserted there, in order along the edge.
fn with_points_on_edges(poly: &[Point], points: &[Point], eps: f64) -> Vec<Point> {
    let mut out = Vec::with_capacity(poly.len());
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        out.push(a);
        let d = b.pos - a.pos;
        let len2 = d.length_squared();
        if len2 <= eps * eps {
            continue;
        }
        let mut on: Vec<(f64, Point)> = points
            .iter()
            .filter_map(|p| {
                let t = (p.pos - a.pos).dot(d) / len2;
                let off = (a.pos + d * t).distance(p.pos);
                let inside = t * len2.sqrt() > eps && (1.0 - t) * len2.sqrt() > eps;
                (inside && off <= eps).then_some((t, *p))
            })
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        on.dedup_by(|x, y| x.1.pos.distance(y.1.pos) <= eps);
        out.extend(on.into_iter().map(|(_, p)| p));
    }
    out
}

/// Triangulate a convex polygon (counter-clockwise about `normal`) that may have points along
/// its edges, using every point and making no zero-area triangle: clip ears with area.
fn ears(poly: &[DVec3], normal: DVec3, eps: f64) -> Vec<[usize; 3]> {
    let mut left: Vec<usize> = (0..poly.len()).collect();
    let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
    let area = |a: usize, b: usize, c: usize| {
        let (a, b, c) = (poly[a], poly[b], poly[c]);
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        (b - a).cross(c - a).dot(normal) > eps * longest
    };
    // The diagonal a–c of an ear must not run along other points (which it would leave out).
    let on = |a: usize, c: usize, p: usize| {
        let (a, c, p) = (poly[a], poly[c], poly[p]);
        let d = c - a;
        let t = (p - a).dot(d) / d.length_squared().max(1e-300);
        (0.0..=1.0).contains(&t) && (a + d * t).distance(p) <= eps
    };
    while left.len() >= 3 {
        let n = left.len();
        let ear = |i: usize| {
            let (a, b, c) = (left[(i + n - 1) % n], left[i], left[(i + 1) % n]);
            area(a, b, c)
                && !left
                    .iter()
                    .any(|&p| p != a && p != b && p != c && on(a, c, p))
        };
        // The best-shaped ear first (area over the squares of its sides): no needless slivers.
        let quality = |i: usize| {
            let (a, b, c) = (
                poly[left[(i + n - 1) % n]],
                poly[left[i]],
                poly[left[(i + 1) % n]],
            );
            let area = (b - a).cross(c - a).length();
            area / ((b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared())
        };
        let Some(i) = (0..n)
            .filter(|&i| ear(i))
            .max_by(|&x, &y| quality(x).total_cmp(&quality(y)).then(y.cmp(&x)))
        else {
            break; // what is left is a line
        };
        out.push([left[(i + n - 1) % n], left[i], left[(i + 1) % n]]);
        left.remove(i);
    }
    out
}

/// A piece whose points have their vertex ids, its covered sides and its depth.
type Placed = (Vec<(u32, Point)>, u8, f64);

/// Split each piece by `cover`: the part under it gets the cover's side bit.
type Piece = (Vec<Point>, u8, f64);

fn split_by(pieces: Vec<Piece>, cover: &Cover, t: u32, eps: f64) -> Vec<Piece> {
    let bit = if cover.back { BACK } else { FRONT };
    let mut out = Vec::with_capacity(pieces.len() + 3);
    for (piece, mask, gap) in pieces {
        // A piece the cover does not overlap stays whole (no cut lines beyond the outline).
        let mut probe = piece.clone();
        for k in 0..3 {
            probe = clip_points(&probe, |x| cover.inside(k, x), t, eps).0;
        }
        if probe.len() < 3 || mask & bit != 0 {
            out.push((piece, mask, gap));
            continue;
        }
        let mut rest = piece;
        for k in 0..3 {
            let (inside, outside) = clip_points(&rest, |x| cover.inside(k, x), t, eps);
            if outside.len() >= 3 {
                out.push((outside, mask, gap));
            }
            rest = inside;
        }
        if rest.len() >= 3 {
            out.push((rest, mask | bit, gap.max(cover.depth)));
        }
    }
    out
}

/// The index of `pt` in `out`: a point of the same origin within `eps` of it, or a new one.
fn vertex(
    out: &mut CutSurface,
    shared: &mut HashMap<Origin, Vec<u32>>,
    surface: &Surface,
    tri: [u32; 3],
    pt: &Point,
    eps: f64,
) -> u32 {
    if let Origin::Vertex(v) = pt.origin {
        return v;
    }
    let same = shared.entry(pt.origin).or_default();
    if let Some(&v) = (same.iter()).find(|&&v| out.positions[v as usize].distance(pt.pos) <= eps) {
        return v;
    }
    let v = {
        let blend3 = |d: &[DVec3]| {
            (0..3)
                .map(|i| d[tri[i] as usize] * pt.bary[i])
                .sum::<DVec3>()
        };
        let blend2 = |d: &[DVec2]| {
            (0..3)
                .map(|i| d[tri[i] as usize] * pt.bary[i])
                .sum::<DVec2>()
        };
        out.positions.push(pt.pos);
        out.normals
            .push(blend3(&surface.normals).normalize_or_zero());
        if let (Some(uv), Some(src)) = (out.uv0.as_mut(), surface.uv0.as_ref()) {
            uv.push(blend2(src));
        }
        if let (Some(uv), Some(src)) = (out.uv1.as_mut(), surface.uv1.as_ref()) {
            uv.push(blend2(src));
        }
        out.positions.len() as u32 - 1
    };
    same.push(v);
    v
}

/// Split a convex polygon of points by the line `dist = 0` into the parts with dist ≥ 0 and
/// dist ≤ 0 (points within `eps` of the line belong to both).
fn clip_points(
    poly: &[Point],
    dist: impl Fn(DVec3) -> f64,
    t: u32,
    eps: f64,
) -> (Vec<Point>, Vec<Point>) {
    clip_with(poly, |p| p.pos, &dist, |a, b| crossing(a, b, &dist, t), eps)
}

/// The point where segment a–b crosses `dist = 0`, computed from its ends ordered by position.
fn crossing(a: &Point, b: &Point, dist: &impl Fn(DVec3) -> f64, t: u32) -> Point {
    let (a, b) = if lex_less(b.pos, a.pos) {
        (b, a)
    } else {
        (a, b)
    };
    let (da, db) = (dist(a.pos), dist(b.pos));
    let s = da / (da - db);
    let origin = match (a.origin, b.origin) {
        (Origin::Vertex(i), Origin::Vertex(j)) => Origin::Edge(i.min(j), i.max(j)),
        (Origin::Vertex(i), Origin::Edge(p, q)) | (Origin::Edge(p, q), Origin::Vertex(i))
            if i == p || i == q =>
        {
            Origin::Edge(p, q)
        }
        (Origin::Edge(p, q), Origin::Edge(r, u)) if (p, q) == (r, u) => Origin::Edge(p, q),
        _ => Origin::Inner(t),
    };
    Point {
        pos: a.pos + (b.pos - a.pos) * s,
        origin,
        bary: a.bary + (b.bary - a.bary) * s,
    }
}

fn lex_less(a: DVec3, b: DVec3) -> bool {
    (a.x, a.y, a.z) < (b.x, b.y, b.z)
}

/// Split a convex polygon of plain points by `dist = 0` (see [`clip_points`]).
pub(crate) fn clip(
    poly: &[DVec3],
    dist: impl Fn(DVec3) -> f64,
    eps: f64,
) -> (Vec<DVec3>, Vec<DVec3>) {
    let lerp = |a: &DVec3, b: &DVec3| {
        let (a, b) = if lex_less(*b, *a) { (b, a) } else { (a, b) };
        let (da, db) = (dist(*a), dist(*b));
        *a + (*b - *a) * (da / (da - db))
    };
    clip_with(poly, |p| *p, &dist, lerp, eps)
}

/// Sutherland–Hodgman against one line, both sides at once.
fn clip_with<V: Copy>(
    poly: &[V],
    pos: impl Fn(&V) -> DVec3,
    dist: &impl Fn(DVec3) -> f64,
    cross: impl Fn(&V, &V) -> V,
    eps: f64,
) -> (Vec<V>, Vec<V>) {
    let d: Vec<f64> = poly.iter().map(|p| dist(pos(p))).collect();
    let side = |x: f64| {
        if x > eps {
            1
        } else if x < -eps {
            -1
        } else {
            0
        }
    };
    let (mut inside, mut outside) = (Vec::new(), Vec::new());
    for i in 0..poly.len() {
        let j = (i + 1) % poly.len();
        let (si, sj) = (side(d[i]), side(d[j]));
        if si >= 0 {
            inside.push(poly[i]);
        }
        if si <= 0 {
            outside.push(poly[i]);
        }
        if si * sj < 0 {
            let x = cross(&poly[i], &poly[j]);
            inside.push(x);
            outside.push(x);
        }
    }
    // A polygon touching the line from one side is not split.
    if !d.iter().any(|x| side(*x) < 0) {
        outside.clear();
    }
    if !d.iter().any(|x| side(*x) > 0) {
        inside.clear();
    }
    (inside, outside)
}

/// Area (m²) and centroid of a planar convex polygon with unit normal `n`.
pub(crate) fn area_centroid(poly: &[DVec3], n: DVec3) -> (f64, DVec3) {
    let (mut area, mut centre) = (0.0, DVec3::ZERO);
    for i in 1..poly.len().saturating_sub(1) {
        let a = (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]).dot(n) / 2.0;
        area += a;
        centre += (poly[0] + poly[i] + poly[i + 1]) / 3.0 * a;
    }
    if area > 0.0 {
        (area, centre / area)
    } else {
        (0.0, poly.first().copied().unwrap_or(DVec3::ZERO))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square in y = 0 facing +Y (glTF +Y up), as two triangles split along x = z.
    fn square() -> Surface {
        let p = DVec3::new;
        Surface {
            node: 0,
            primitive: 0,
            source_path: "/meshes/0/primitives/0".into(),
            material: 0,
            positions: vec![p(0., 0., 0.), p(0., 0., 1.), p(1., 0., 1.), p(1., 0., 0.)],
            normals: vec![DVec3::Y; 4],
            uv0: None,
            uv1: None,
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    /// A cover of `triangle`'s front by the triangle `corners` (in y = 0).
    fn cover(triangle: u32, corners: [DVec3; 3]) -> Cover {
        let edges = std::array::from_fn(|k| {
            let (u, v, w) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
            let mut m = DVec3::Y.cross(v - u).normalize();
            if m.dot(w - u) < 0.0 {
                m = -m;
            }
            (m, m.dot(u))
        });
        Cover {
            triangle,
            back: false,
            depth: 0.01,
            edges,
            by: 1,
            area: 0.0,
        }
    }

    fn area(c: &CutSurface, t: &[u32; 3]) -> DVec3 {
        let p = t.map(|v| c.positions[v as usize]);
        (p[1] - p[0]).cross(p[2] - p[0]) * 0.5
    }

    #[test]
    fn a_cover_across_two_triangles_is_cut_out_exactly_and_conformingly() {
        let p = DVec3::new;
        let corners = [p(0.2, 0., 0.2), p(0.8, 0., 0.2), p(0.5, 0., 0.8)];
        let covers = [cover(0, corners), cover(1, corners)];
        let c = cut(&square(), &covers, &[], 1e-9, 0.0);
        assert_eq!(c.triangles.len(), c.covered.len());
        // Area and orientation kept; the covered pieces are the covering triangle (0.18 m²).
        let (mut total, mut under) = (0.0, 0.0);
        for (t, &mask) in c.triangles.iter().zip(&c.covered) {
            let a = area(&c, t);
            assert!(a.y > 1e-12 && a.x.abs() + a.z.abs() < 1e-12, "{t:?}: {a}");
            total += a.y;
            if mask & FRONT != 0 {
                under += a.y;
            }
            assert_eq!(mask & BACK, 0, "one-sided cover covers the back");
            // Every piece lies wholly under the cover or wholly outside it.
            let inside = |x: DVec3| {
                (0..3)
                    .map(|k| covers[0].inside(k, x))
                    .fold(f64::MAX, f64::min)
            };
            let least = t.map(|v| inside(c.positions[v as usize]));
            if mask & FRONT != 0 {
                assert!(
                    least.iter().all(|d| *d > -1e-9),
                    "covered piece sticks out: {least:?}"
                );
            } else {
                assert!(
                    least.iter().all(|d| *d < 1e-9),
                    "open piece reaches in: {least:?}"
                );
            }
        }
        assert!((total - 1.0).abs() < 1e-12, "area {total}");
        assert!((under - 0.18).abs() < 1e-12, "covered {under}");
        // Conforming: an edge inside the square has two triangles, one on its rim one, so the
        // points where the outline crosses the diagonal are shared, not duplicated.
        let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &c.triangles {
            for k in 0..3 {
                let (u, v) = (t[k], t[(k + 1) % 3]);
                *uses.entry((u.min(v), u.max(v))).or_insert(0) += 1;
            }
        }
        for ((u, v), n) in uses {
            let (a, b) = (c.positions[u as usize], c.positions[v as usize]);
            let rim = [0.0, 1.0]
                .iter()
                .any(|s| (a.x == *s && b.x == *s) || (a.z == *s && b.z == *s));
            assert_eq!(n, if rim { 1 } else { 2 }, "edge {a} – {b}");
        }
    }

    #[test]
    fn a_triangle_smaller_than_a_patch_is_covered_whole_where_covers_hold_most_of_it() {
        let p = DVec3::new;
        // One cover holds x ≤ 0.5 of the square: three quarters of triangle 0 (z ≥ x), which
        // stays one triangle, covered; a quarter of triangle 1, which stays one triangle, open.
        let half = [p(-10., 0., -10.), p(0.5, 0., -10.), p(0.5, 0., 10.)];
        let covers = [cover(0, half), cover(1, half)];
        let c = cut(&square(), &covers, &[], 1e-9, 2.0);
        // The same two triangles (each may start at another corner).
        let turned = |t: &[u32; 3]| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        };
        let got: Vec<[u32; 3]> = c.triangles.iter().map(turned).collect();
        assert_eq!(got, square().triangles);
        assert_eq!(c.covered, vec![FRONT, 0]);
        assert_eq!(c.gap[0], 0.01);
    }
}
