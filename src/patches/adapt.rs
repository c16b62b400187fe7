//! Adaptive refinement: coarse patches where light is smooth, finer ones where its gradient, a
//! shadow edge or a contact line needs them.
//!
//! Input: one surface's refined mesh (positions, shading normals, optional UVs, triangles), the
//! sides it receives light on, and a [`Probe`] that estimates illuminance at points (the
//! meshing stage's estimate: direct light, plus indirect light where nothing covers the point).
//! Output: the same surface with some triangles split; every new vertex is the midpoint of an
//! edge, its normal and UVs the mean of the edge's ends.
//!
//! The error estimate of an edge is how far the estimated illuminance at its midpoint is from
//! the linear interpolation of its ends — exactly what linear (vertex) interpolation of the output
//! and the trapezoid quadrature of the solver miss there. An edge is split when that error
//! exceeds `RELATIVE` of the brightest of the three values or `ABSOLUTE` of the scene's mean
//! direct illuminance, and it is longer than the smallest patch size. Edges shorter than
//! `sharp_below` split only where the error is [`SHARP`] times those thresholds (a shadow or a
//! cut-off edge, not a gradient), the midpoint is open (nothing lying on the surface in front
//! of it) and the surface is broad (its given triangles' longest edges longer on average: not
//! clutter's tessellation). Both sides of a
//! double-sided surface are judged and split alike (a patch and its twin stay coincident).
//!
//! Splitting is conforming within the surface: an edge is split for both triangles beside it
//! (its midpoint is shared); a triangle with one split edge becomes two, with two becomes three
//! (the quad cut along its shorter diagonal), with three becomes four. Orientation is kept. The
//! result depends only on the inputs (edges are visited in a fixed order), whatever the thread
//! count of the probe.

use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// Split when the midpoint misses linear interpolation by this share of the local brightness…
pub const RELATIVE: f64 = 0.08;
/// …or by this share of the scene's mean direct illuminance (dark regions need less).
pub const ABSOLUTE: f64 = 0.03;

/// Edges shorter than [`Adapt::sharp_below`] (× 1.5) split only where interpolation misses by
/// this many times the thresholds above: a shadow or cut-off edge, not a gradient.
pub const SHARP: f64 = 8.0;

/// How far (× the local edge length) judged points are pulled into their triangles.
const PULL: f64 = 1e-3;

/// Estimated illuminance (lx) at each `(point, unit normal)`; evaluated in one batch.
pub type Probe<'p> = &'p (dyn Fn(&[(DVec3, DVec3)]) -> Vec<f64> + Sync);

/// Whether each `(point, unit normal)` is open (nothing lies on the surface in front of it).
pub type Openness<'p> = &'p (dyn Fn(&[(DVec3, DVec3)]) -> Vec<bool> + Sync);

/// What adaptive refinement needs beyond the mesh.
pub struct Adapt<'p> {
    pub probe: Probe<'p>,
    /// Edges are not split below this length (m).
    pub min_edge: f64,
    /// Below this length (m) edges split only at sharp edges of the light ([`SHARP`]), and only
    /// on broad surfaces: those whose given triangles' longest edges are on average longer
    /// (a chair's tessellation is not refined past it).
    pub sharp_below: f64,
    /// Whether each `(point, unit normal)` has nothing lying on the surface in front of it;
    /// edges below `sharp_below` split only where their midpoint is open.
    pub open: Option<Openness<'p>>,
    /// Rounds of splitting (each can halve an edge once).
    pub levels: u32,
    /// The scene's mean direct illuminance (lx), the scale of [`ABSOLUTE`].
    pub mean: f64,
}

/// An edge's midpoint query (point, normal) and the illuminance found there.
type Judged = ((DVec3, DVec3), f64);

/// A surface mesh being refined.
pub struct SurfaceMesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, a tag its pieces keep when it is split (or empty: none kept).
    pub tags: Vec<u32>,
}

/// Refine `m` (receiving light on the given sides: `+1` front, `−1` back) in place; returns how
/// many edges were split.
pub(crate) fn refine(m: &mut SurfaceMesh, signs: &[f64], a: &Adapt) -> usize {
    let mut split_total = 0;
    let sharp = a.sharp_below * 1.5 * (1.0 + 1e-9);
    let min_edge = if mean_longest_edge(m) > sharp {
        a.min_edge * 1.5 * (1.0 + 1e-9)
    } else {
        sharp.max(a.min_edge * 1.5 * (1.0 + 1e-9))
    };
    // Illuminance per vertex and side, extended as vertices are added; NaN until a candidate
    // edge needs it. Each vertex is judged where the mesh of the round that added it puts it
    // (`asked`), but probed only when an edge ending there is long enough to split: a surface
    // whose edges are all short (a chair's tessellation) costs no probe at all.
    let mut at: Vec<Vec<f64>> = signs.iter().map(|_| Vec::new()).collect();
    let mut asked: Vec<Vec<(DVec3, DVec3)>> = signs.iter().map(|_| Vec::new()).collect();
    // Each side's last query and answer per edge: an edge left whole keeps its midpoint, and
    // unless a neighbouring triangle was split its query point is the same, so it is not
    // probed again in the next round.
    let mut judged: Vec<HashMap<(u32, u32), Judged>> =
        signs.iter().map(|_| HashMap::new()).collect();
    for _ in 0..a.levels {
        // Where each vertex is judged: pulled a little into its triangles, so a vertex on a room's
        // corner edge is not tested edge-on against the neighbouring wall (which would read as a
        // shadow edge and split every corner).
        let (inward, _, local) = super::around(&m.positions, &m.triangles);
        let pulled = |i: usize| m.positions[i] + inward[i].normalize_or_zero() * (PULL * local[i]);
        for (s, sign) in signs.iter().enumerate() {
            let from = at[s].len();
            asked[s].extend((from..m.positions.len()).map(|i| (pulled(i), m.normals[i] * *sign)));
            at[s].resize(m.positions.len(), f64::NAN);
        }
        let (edges, into) = candidates(m, min_edge);
        if edges.is_empty() {
            break;
        }
        // The candidate edges' ends not probed yet, in vertex order, one batch per side.
        let mut ends: Vec<u32> = edges.iter().flat_map(|&(u, v)| [u, v]).collect();
        ends.sort_unstable();
        ends.dedup();
        for s in 0..signs.len() {
            let fresh: Vec<u32> = ends
                .iter()
                .copied()
                .filter(|&v| at[s][v as usize].is_nan())
                .collect();
            let probed = (a.probe)(
                &fresh
                    .iter()
                    .map(|&v| asked[s][v as usize])
                    .collect::<Vec<_>>(),
            );
            for (&v, e) in fresh.iter().zip(probed) {
                at[s][v as usize] = e;
            }
        }
        let mut split = vec![false; edges.len()];
        let mut below: Vec<(usize, (DVec3, DVec3))> = Vec::new();
        for (s, sign) in signs.iter().enumerate() {
            let queries: Vec<(DVec3, DVec3)> = edges
                .iter()
                .zip(&into)
                .map(|(e, d)| {
                    let (p, n) = mid(m, e);
                    let len = (m.positions[e.0 as usize] - m.positions[e.1 as usize]).length();
                    (p + d.normalize_or_zero() * (PULL * len), n * *sign)
                })
                .collect();
            let fresh: Vec<usize> = (0..edges.len())
                .filter(|&i| {
                    judged[s]
                        .get(&edges[i])
                        .is_none_or(|(q, _)| *q != queries[i])
                })
                .collect();
            let probed = (a.probe)(&fresh.iter().map(|&i| queries[i]).collect::<Vec<_>>());
            for (&i, v) in fresh.iter().zip(probed) {
                judged[s].insert(edges[i], (queries[i], v));
            }
            let e_mid: Vec<f64> = edges.iter().map(|e| judged[s][e].1).collect();
            for (i, &(u, v)) in edges.iter().enumerate() {
                let (eu, ev, em) = (at[s][u as usize], at[s][v as usize], e_mid[i]);
                let error = (em - 0.5 * (eu + ev)).abs();
                let local = eu.max(ev).max(em);
                let len = (m.positions[u as usize] - m.positions[v as usize]).length();
                let k = if len <= sharp { SHARP } else { 1.0 };
                if error > k * RELATIVE * local || (error > k * ABSOLUTE * a.mean && local > 0.0) {
                    if len <= sharp {
                        below.push((i, queries[i]));
                    } else {
                        split[i] = true;
                    }
                }
            }
            // A sharp edge under something lying on the surface is a contact, not light: the
            // contact lines were refined above, and points under a cover too small to cut away
            // would read its darkness into the open triangle round them.
            let q: Vec<(DVec3, DVec3)> = below.iter().map(|b| b.1).collect();
            let open = a.open.map_or_else(|| vec![true; q.len()], |open| open(&q));
            for (&(i, _), o) in below.iter().zip(open) {
                split[i] |= o;
            }
            below.clear();
        }
        let count = split.iter().filter(|s| **s).count();
        if count == 0 {
            break;
        }
        split_total += count;
        apply(m, &edges, &split);
    }
    split_total
}

/// Candidate edges (longer than `min_edge`) in first-seen order (deterministic), each with the
/// direction into its triangles from its midpoint.
fn candidates(m: &SurfaceMesh, min_edge: f64) -> (Vec<(u32, u32)>, Vec<DVec3>) {
    let mut index: HashMap<(u32, u32), usize> = HashMap::new();
    let mut edges: Vec<(u32, u32)> = Vec::new();
    let mut into: Vec<DVec3> = Vec::new();
    for t in &m.triangles {
        let c = t.iter().map(|v| m.positions[*v as usize]).sum::<DVec3>() / 3.0;
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            let key = (u.min(v), u.max(v));
            let (pu, pv) = (m.positions[u as usize], m.positions[v as usize]);
            if (pu - pv).length() <= min_edge {
                continue;
            }
            let dir = (c - (pu + pv) * 0.5).normalize_or_zero();
            match index.get(&key) {
                Some(&i) => into[i] += dir,
                None => {
                    index.insert(key, edges.len());
                    edges.push(key);
                    into.push(dir);
                }
            }
        }
    }
    (edges, into)
}

/// An edge's midpoint and mean normal.
fn mid(m: &SurfaceMesh, &(u, v): &(u32, u32)) -> (DVec3, DVec3) {
    let (u, v) = (u as usize, v as usize);
    (
        (m.positions[u] + m.positions[v]) * 0.5,
        (m.normals[u] + m.normals[v]).normalize_or_zero(),
    )
}

/// Split the edges marked in `split` at their midpoints (new vertices in edge order) and every
/// triangle beside them; tags go to the pieces.
fn apply(m: &mut SurfaceMesh, edges: &[(u32, u32)], split: &[bool]) {
    // Midpoints of the split edges.
    let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        if split[i] {
            let (p, n) = mid(m, e);
            midpoint.insert(*e, m.positions.len() as u32);
            m.positions.push(p);
            m.normals.push(n);
            for uv in [&mut m.uv0, &mut m.uv1].into_iter().flatten() {
                let w = (uv[e.0 as usize] + uv[e.1 as usize]) * 0.5;
                uv.push(w);
            }
        }
    }
    let old = std::mem::take(&mut m.triangles);
    let old_tags = std::mem::take(&mut m.tags);
    for (i, t) in old.into_iter().enumerate() {
        let mids: [Option<u32>; 3] = std::array::from_fn(|k| {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            midpoint.get(&(u.min(v), u.max(v))).copied()
        });
        let before = m.triangles.len();
        split_triangle(t, mids, &m.positions, &mut m.triangles);
        if let Some(tag) = old_tags.get(i) {
            m.tags
                .extend(std::iter::repeat_n(*tag, m.triangles.len() - before));
        }
    }
}

/// The mean over `m`'s triangles of their longest edge (m).
fn mean_longest_edge(m: &SurfaceMesh) -> f64 {
    let longest = |t: &[u32; 3]| {
        (0..3)
            .map(|k| (m.positions[t[k] as usize] - m.positions[t[(k + 1) % 3] as usize]).length())
            .fold(0.0, f64::max)
    };
    m.triangles.iter().map(longest).sum::<f64>() / m.triangles.len().max(1) as f64
}

/// Split triangle `t` (counter-clockwise) at the midpoints `mids[k]` of its edges `t[k]→t[k+1]`.
fn split_triangle(t: [u32; 3], mids: [Option<u32>; 3], pos: &[DVec3], out: &mut Vec<[u32; 3]>) {
    let n = mids.iter().filter(|m| m.is_some()).count();
    match n {
        0 => out.push(t),
        3 => {
            let [m0, m1, m2] = mids.map(|m| m.expect("three midpoints"));
            out.extend([[t[0], m0, m2], [m0, t[1], m1], [m2, m1, t[2]], [m0, m1, m2]]);
        }
        _ => {
            // Rotate so the first split edge is t[0]→t[1].
            let r = (0..3).find(|&k| mids[k].is_some()).expect("one midpoint");
            let r = if n == 2 && mids[(r + 2) % 3].is_some() {
                (r + 2) % 3
            } else {
                r
            };
            let [a, b, c] = [t[r], t[(r + 1) % 3], t[(r + 2) % 3]];
            let mab = mids[r].expect("split edge");
            match mids[(r + 1) % 3] {
                None => out.extend([[a, mab, c], [mab, b, c]]),
                Some(mbc) => {
                    out.push([mab, b, mbc]);
                    // The quad a, mab, mbc, c: cut along its shorter diagonal.
                    let d1 = (pos[a as usize] - pos[mbc as usize]).length_squared();
                    let d2 = (pos[mab as usize] - pos[c as usize]).length_squared();
                    if d1 <= d2 {
                        out.extend([[a, mab, mbc], [a, mbc, c]]);
                    } else {
                        out.extend([[a, mab, c], [mab, mbc, c]]);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_normal(pos: &[DVec3], t: &[u32; 3]) -> DVec3 {
        let p = t.map(|v| pos[v as usize]);
        (p[1] - p[0]).cross(p[2] - p[0]) * 0.5
    }

    fn square(n: u32) -> SurfaceMesh {
        // An n × n grid of unit squares in y = 0, facing +Y, two triangles each.
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(DVec3::new(i as f64, 0.0, j as f64));
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
            }
        }
        SurfaceMesh {
            tags: Vec::new(),
            normals: vec![DVec3::Y; positions.len()],
            positions,
            uv0: None,
            uv1: None,
            triangles,
        }
    }

    /// Edge → number of triangles using it, over the whole mesh.
    fn edge_use(m: &SurfaceMesh) -> HashMap<(u32, u32), usize> {
        let mut e = HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                let (u, v) = (t[k], t[(k + 1) % 3]);
                *e.entry((u.min(v), u.max(v))).or_insert(0) += 1;
            }
        }
        e
    }

    #[test]
    fn a_shadow_edge_is_refined_and_smooth_light_is_not() {
        // Light 100 lx for x < 2.3, 0 beyond: a shadow edge across a 4 × 4 m floor.
        let probe = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| if p.x < 2.3 { 100.0 } else { 0.0 })
                .collect()
        };
        let mut m = square(4);
        let before = m.triangles.len();
        let a = Adapt {
            probe: &probe,
            min_edge: 0.2,
            sharp_below: 0.2,
            open: None,
            levels: 3,
            mean: 50.0,
        };
        let split = refine(&mut m, &[1.0], &a);
        assert!(split > 0 && m.triangles.len() > before);
        // Area and orientation are kept; no triangle is degenerate.
        let total: DVec3 = m
            .triangles
            .iter()
            .map(|t| area_normal(&m.positions, t))
            .sum();
        assert!(
            (total - DVec3::new(0.0, 16.0, 0.0)).length() < 1e-12,
            "{total}"
        );
        for t in &m.triangles {
            let n = area_normal(&m.positions, t);
            assert!(n.y > 1e-6, "flipped or degenerate {t:?}");
        }
        // Conforming: every interior edge has exactly two triangles, boundary ones one.
        for (e, uses) in edge_use(&m) {
            let (p, q) = (m.positions[e.0 as usize], m.positions[e.1 as usize]);
            let boundary = [p, q].iter().all(|v| v.x == 0.0)
                || [p, q].iter().all(|v| v.x == 4.0)
                || [p, q].iter().all(|v| v.z == 0.0)
                || [p, q].iter().all(|v| v.z == 4.0);
            assert_eq!(uses, if boundary { 1 } else { 2 }, "edge {p} – {q}");
        }
        // Fine triangles sit at the shadow edge only: those far from x = 2.3 keep their size.
        for t in &m.triangles {
            let p = t.map(|v| m.positions[v as usize]);
            let far = p.iter().all(|v| (v.x - 2.3).abs() > 1.01);
            if far {
                assert!(area_normal(&m.positions, t).y >= 0.5 - 1e-12, "{p:?}");
            }
        }
        let smallest = m
            .triangles
            .iter()
            .map(|t| area_normal(&m.positions, t).y)
            .fold(f64::INFINITY, f64::min);
        assert!(smallest < 0.5 / 8.0 + 1e-12, "smallest {smallest}");
    }

    /// The smallest triangle's area after refining `square(4)` under `probe` with the sharp
    /// regime below 0.4 m and the floor at 0.1 m.
    fn smallest_after(probe: Probe, open: Option<Openness>, m: &mut SurfaceMesh) -> f64 {
        let a = Adapt {
            probe,
            min_edge: 0.1,
            sharp_below: 0.4,
            open,
            levels: 5,
            mean: 100.0,
        };
        refine(m, &[1.0], &a);
        m.triangles
            .iter()
            .map(|t| area_normal(&m.positions, t).y)
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn only_sharp_edges_of_light_are_refined_below_sharp_below() {
        // A shadow edge goes down to min_edge (0.1 m: triangles of 1/128 m²)…
        let shadow = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| if p.x < 2.3 { 100.0 } else { 0.0 })
                .collect()
        };
        let a = smallest_after(&shadow, None, &mut square(4));
        assert!(a < 1.0 / 128.0 + 1e-12, "shadow: smallest {a}");
        // …but not where something lies on the surface (a cover too small to cut away): the
        // same edge of light stops at sharp_below there…
        let covered = |q: &[(DVec3, DVec3)]| -> Vec<bool> { vec![false; q.len()] };
        let a = smallest_after(&shadow, Some(&covered), &mut square(4));
        assert!(
            (a - 1.0 / 16.0).abs() < 1e-12,
            "under a cover: smallest {a}"
        );
        // …a curved gradient is refined, but no edge at most 1.5 × sharp_below is split (the
        // smallest triangles halve a 0.5 m cell along its diagonal: 1/16 m²)…
        let curved = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| 100.0 + 50.0 * (p.x * 3.0).sin())
                .collect()
        };
        let a = smallest_after(&curved, None, &mut square(4));
        assert!((a - 1.0 / 16.0).abs() < 1e-12, "gradient: smallest {a}");
        // …and a surface already tessellated finer than sharp_below is not refined past it,
        // even at a shadow edge.
        let mut fine = square(4);
        for p in &mut fine.positions {
            *p *= 0.1;
        }
        let narrow = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| if p.x < 0.23 { 100.0 } else { 0.0 })
                .collect()
        };
        let before = fine.triangles.len();
        smallest_after(&narrow, None, &mut fine);
        assert_eq!(fine.triangles.len(), before);
    }

    #[test]
    fn linear_light_needs_no_patches() {
        let probe = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| 10.0 + 20.0 * p.x + 5.0 * p.z)
                .collect()
        };
        let mut m = square(3);
        let before = m.triangles.clone();
        let a = Adapt {
            probe: &probe,
            min_edge: 0.1,
            sharp_below: 0.1,
            open: None,
            levels: 3,
            mean: 50.0,
        };
        assert_eq!(refine(&mut m, &[1.0, -1.0], &a), 0);
        assert_eq!(m.triangles, before);
    }

    #[test]
    fn points_on_the_boundary_are_judged_from_inside() {
        // A shadow ray from a point exactly on a room's corner edge grazes the other wall and
        // reads 0: judged there, every boundary edge would look like a shadow edge.
        let probe = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| {
                    let on_edge = [p.x, p.z].iter().any(|c| *c <= 0.0 || *c >= 3.0);
                    if on_edge { 0.0 } else { 100.0 }
                })
                .collect()
        };
        let mut m = square(3);
        let a = Adapt {
            probe: &probe,
            min_edge: 0.1,
            sharp_below: 0.1,
            open: None,
            levels: 3,
            mean: 100.0,
        };
        assert_eq!(refine(&mut m, &[1.0], &a), 0);
    }

    #[test]
    fn edges_at_the_smallest_size_are_left_alone() {
        let probe = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
            q.iter()
                .map(|(p, _)| (p.x * 40.0).sin().abs() * 100.0)
                .collect()
        };
        let mut m = square(2);
        let a = Adapt {
            probe: &probe,
            min_edge: 1.0,
            sharp_below: 1.0,
            open: None,
            levels: 4,
            mean: 50.0,
        };
        refine(&mut m, &[1.0], &a);
        // Unit edges (and diagonals √2 < 1.5) are never split at min_edge 1.
        assert_eq!(m.triangles.len(), 8);
    }
}
