//! The plan of one planar node (`--surface NODE`): its baked values sampled on a regular grid in
//! its plane.
//!
//! Input: the output, the node (its name, or its path of names from the root joined by `/`:
//! `desk_light/top`), optionally with a face as report keys take it (`desk_light/top[+y]`:
//! only the triangles facing within ~8° of +Y, `readback::keys`), the quantity. The node's own
//! baked primitives (not its children's), or the face's triangles, must be coplanar: every triangle parallel to the first primitive's largest one (|cos| > 0.999)
//! and every vertex within 0.1 mm + 10⁻⁵ of the surface's size of its plane, else an error
//! naming the node and the faces it could be drawn by. The primitives facing that triangle's way are drawn (a double-sided
//! surface's back is skipped), in the [`Frame`] of its normal.
//!
//! Cells (about `cells` along the longer side: 200, or a cell per 4 px of a larger plan; a round
//! size in metres) are read at their centres:
//! from the lightmap bilinearly where the primitive is lightmapped (`Lightmap::bilinear` at the
//! UV interpolated there), else from the vertex values interpolated linearly over the triangle.
//! Cells whose centre no triangle holds are no data (NaN), and so are covered parts (marked by
//! the bake, `Primitive::covered_from`; in outputs without the marker, a triangle without UV area
//! in a lightmapped primitive, or whose vertices all hold exactly 0 lx in another: what a desk leg
//! stands on). The figures are cell means, minimum and maximum.

use super::Quantity;
use super::field::{Field, Sampled};
use super::frame::Frame;
use super::outline::{self, normal};
use crate::picture::scale::round_up;
use crate::readback::{BakedOutput, Primitive, keys};
use crate::{Error, Result};
use glam::{DVec2, DVec3};

/// The plan of the node named (or with path) `node`.
pub(crate) fn sample(
    input: &BakedOutput,
    key: &str,
    quantity: Quantity,
    cells: f64,
) -> Result<Sampled> {
    let (node, face) =
        keys::split_face(key).map_err(|m| Error::Settings(format!("--surface {key}: {m}")))?;
    let i = find_node(input, node)?;
    let at = Node {
        input,
        i,
        path: input.node_path(i),
    };
    let path = &at.path;
    let prims = drawn(input, i, face);
    if prims.is_empty() && face.is_some() {
        return Err(at.error(format!(
            "node '{path}' has no baked face facing {key}'s way"
        )));
    }
    let Some((first, first_tris)) = prims.first() else {
        return Err(at.error(format!(
            "node '{path}' has no baked surface (no primitive with _ILLUMINANCE)"
        )));
    };
    let (n, p0) =
        largest(first, first_tris).ok_or_else(|| at.not_planar("its triangles have no area"))?;
    let chosen = facing(&at, &prims, n, p0)?;
    let frame = Frame::of_normal(n);
    let mut field = grid(&chosen, &frame, cells);
    let mut set = vec![false; field.w * field.h];
    let mut edges = Vec::new();
    for (p, tris) in &chosen {
        fill(input, p, tris, &frame, quantity, &mut field, &mut set);
        edges.extend(outline::boundary(p, tris, &frame));
    }
    let Some(figures) = figures(&field.values) else {
        return Err(at.error(format!(
            "node '{path}': no baked value to draw (all of it is covered)"
        )));
    };
    // The title names the face drawn too.
    let shown = format!("{path}{}", &key[node.len()..]);
    Ok((shown, frame, field, outline::tidy(edges), figures))
}

/// The node drawn: its index and path, for the errors that name it.
struct Node<'a> {
    input: &'a BakedOutput,
    i: usize,
    path: String,
}

impl Node<'_> {
    /// An error at the node.
    fn error(&self, message: String) -> Error {
        Error::input(&self.input.file, format!("/nodes/{}", self.i), message)
    }

    /// The node is not flat (`why`), with the faces it could be drawn by, if any.
    fn not_planar(&self, why: &str) -> Error {
        let path = &self.path;
        let faces = solid_faces(self.input, self.i);
        let hint = match faces.is_empty() {
            true => String::new(),
            false => format!(
                "; name one of its faces: {}",
                (faces.iter().map(|f| format!("{path}[{f}]")))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        self.error(format!(
            "node '{path}' is not planar ({why}): --surface draws one flat surface (a floor, \
             a wall, a table top modelled as a node of its own, or one face of a solid){hint}"
        ))
    }
}

/// Node `i`'s baked primitives with the triangles drawn: all of its own, or those of the face
/// named; primitives left with none are dropped.
fn drawn(input: &BakedOutput, i: usize, face: Option<DVec3>) -> Vec<(&Primitive, Vec<usize>)> {
    let drawn = |p: &Primitive| -> Vec<usize> {
        (0..p.triangles.len())
            .filter(|&j| face.is_none_or(|d| keys::faces(p, j, d)))
            .collect()
    };
    (input.primitives.iter())
        .filter(|p| p.node == i)
        .map(|p| (p, drawn(p)))
        .filter(|(_, t)| !t.is_empty())
        .collect()
}

/// The primitives whose triangles face `n` on the whole (a double-sided surface's back is
/// skipped), once every triangle is found parallel to `n` and in the plane through `p0`
/// (within 0.1 mm + 10⁻⁵ of the surface's size).
fn facing<'a>(
    at: &Node,
    prims: &'a [(&'a Primitive, Vec<usize>)],
    n: DVec3,
    p0: DVec3,
) -> Result<Vec<(&'a Primitive, &'a [usize])>> {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for (p, tris) in prims {
        for &j in tris {
            for v in p.triangles[j] {
                lo = lo.min(p.positions[v as usize]);
                hi = hi.max(p.positions[v as usize]);
            }
        }
    }
    let tol = 1e-4 + 1e-5 * (hi - lo).length();
    let mut chosen = Vec::new();
    for (p, tris) in prims {
        let mut facing = 0.0;
        for &j in tris {
            let q = p.triangles[j].map(|v| p.positions[v as usize]);
            let m = normal(q);
            if m == DVec3::ZERO {
                continue;
            }
            if m.dot(n).abs() < 0.999 {
                return Err(at.not_planar("its triangles face different ways"));
            }
            if q.iter().any(|x| (x - p0).dot(n).abs() > tol) {
                return Err(at.not_planar("its triangles lie in parallel planes apart"));
            }
            facing += m.dot(n);
        }
        if facing > 0.0 {
            chosen.push((*p, tris.as_slice()));
        }
    }
    Ok(chosen)
}

/// A field of no data over the triangles' extent in `frame`, in whole cells of a round size
/// giving about `cells` along the longer side.
fn grid(chosen: &[(&Primitive, &[usize])], frame: &Frame, cells: f64) -> Field {
    let (mut a, mut b) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for (p, tris) in chosen {
        for &j in *tris {
            for v in p.triangles[j] {
                let q = frame.on_page(p.positions[v as usize]);
                a = a.min(q);
                b = b.max(q);
            }
        }
    }
    let extent = b - a;
    let cell = round_up(extent.max_element() / cells);
    // Whole cells over the extent (an extent of 64.000001 cells is 64: f32 positions).
    let w = ((extent.x / cell - 1e-4).ceil() as usize).max(1);
    let h = ((extent.y / cell - 1e-4).ceil() as usize).max(1);
    Field {
        values: vec![f64::NAN; w * h],
        w,
        h,
        origin: a,
        cell,
    }
}

/// The mean, minimum and maximum of the cells with a value; `None` when no cell has one.
fn figures(cells: &[f64]) -> Option<[f64; 3]> {
    let values: Vec<f64> = cells.iter().copied().filter(|v| v.is_finite()).collect();
    if values.is_empty() {
        return None;
    }
    let avg = values.iter().sum::<f64>() / values.len() as f64;
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Some([avg, min, max])
}

/// The faces (`+x` … `-z`) of node `i`'s baked triangles that have any, in that order: the
/// keys a non-planar node can be drawn by.
fn solid_faces(input: &BakedOutput, i: usize) -> Vec<&'static str> {
    let prims: Vec<&Primitive> = input.primitives.iter().filter(|p| p.node == i).collect();
    (crate::probes::FACE_NAMES.iter().zip(crate::probes::FACES))
        .filter(|(_, d)| {
            (prims.iter()).any(|p| (0..p.triangles.len()).any(|j| keys::faces(p, j, *d)))
        })
        .map(|(name, _)| *name)
        .collect()
}

/// The node whose path is `name`, else the one node so named.
fn find_node(input: &BakedOutput, name: &str) -> Result<usize> {
    let n = input.nodes.len();
    if let Some(i) = (0..n).find(|&i| input.node_path(i) == name) {
        return Ok(i);
    }
    let named: Vec<usize> = (0..n)
        .filter(|&i| input.nodes[i].name.as_deref() == Some(name))
        .collect();
    match named[..] {
        [i] => Ok(i),
        [] => Err(Error::input(
            &input.file,
            "/nodes",
            format!(
                "unknown node '{name}': no node has that name or path (path: names from the root joined by '/')"
            ),
        )),
        _ => {
            let paths: Vec<String> = named.iter().take(4).map(|&i| input.node_path(i)).collect();
            Err(Error::input(
                &input.file,
                "/nodes",
                format!(
                    "{} nodes are named '{name}': give its path ({}{})",
                    named.len(),
                    paths.join(", "),
                    if named.len() > 4 { ", …" } else { "" }
                ),
            ))
        }
    }
}

/// The unit normal and a vertex of the primitive's largest triangle.
fn largest(p: &Primitive, tris: &[usize]) -> Option<(DVec3, DVec3)> {
    let mut best: Option<(f64, DVec3, DVec3)> = None;
    for &j in tris {
        let q = p.triangles[j].map(|v| p.positions[v as usize]);
        let c = (q[1] - q[0]).cross(q[2] - q[0]);
        let area = c.length();
        if area > 0.0 && best.is_none_or(|(a, _, _)| area > a) {
            best = Some((area, c / area, q[0]));
        }
    }
    best.map(|(_, n, p)| (n, p))
}

/// Set the cells of `field` whose centres `p`'s triangles hold (first triangle wins).
fn fill(
    input: &BakedOutput,
    p: &Primitive,
    tris: &[usize],
    frame: &Frame,
    quantity: Quantity,
    field: &mut Field,
    set: &mut [bool],
) {
    let vertex: &[f32] = match quantity {
        Quantity::Illuminance => &p.illuminance,
        Quantity::Luminance => &p.luminance,
    };
    let lightmap = p
        .lightmap
        .as_ref()
        .map(|l| (l, &input.lightmaps[l.lightmap]));
    for &j in tris {
        let v = p.triangles[j].map(|v| v as usize);
        let q = v.map(|v| frame.on_page(p.positions[v]));
        // The bake's marker where the output has it; in older outputs, how a covered part looks.
        let covered = match lightmap {
            _ if p.covered_from.is_some() => p.is_covered(j),
            Some((l, _)) => {
                let uv = v.map(|v| l.uv[v]);
                (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]) == 0.0
            }
            None => v.iter().all(|&v| p.illuminance[v] == 0.0),
        };
        let lo =
            ((q[0].min(q[1]).min(q[2]) - field.origin) / field.cell - DVec2::splat(0.5)).ceil();
        let hi =
            ((q[0].max(q[1]).max(q[2]) - field.origin) / field.cell - DVec2::splat(0.5)).floor();
        let (c0, r0) = (lo.x.max(0.0) as usize, lo.y.max(0.0) as usize);
        let (c1, r1) = (
            hi.x.min(field.w as f64 - 1.0),
            hi.y.min(field.h as f64 - 1.0),
        );
        if c1 < 0.0 || r1 < 0.0 {
            continue;
        }
        for r in r0..=r1 as usize {
            for c in c0..=c1 as usize {
                let k = r * field.w + c;
                if set[k] {
                    continue;
                }
                let centre = field.at(DVec2::new(c as f64, r as f64));
                let Some(l) = barycentric(&q, centre) else {
                    continue;
                };
                set[k] = true;
                field.values[k] = if covered {
                    f64::NAN
                } else if let Some((layout, lm)) = lightmap {
                    let uv = (0..3).map(|j| layout.uv[v[j]] * l[j]).sum();
                    match quantity {
                        Quantity::Illuminance => lm.bilinear(|k| lm.illuminance[k] as f64, uv),
                        Quantity::Luminance => lm.bilinear(|k| lm.luminance_y(k), uv),
                    }
                } else {
                    (0..3).map(|j| vertex[v[j]] as f64 * l[j]).sum()
                };
            }
        }
    }
}

/// Barycentric coordinates of `x` in triangle `q`, when inside it (edges included, within
/// 10⁻⁹ of its size); `None` outside or for a triangle without area.
fn barycentric(q: &[DVec2; 3], x: DVec2) -> Option<[f64; 3]> {
    let d = (q[1] - q[0]).perp_dot(q[2] - q[0]);
    if d == 0.0 {
        return None;
    }
    let l1 = (x - q[0]).perp_dot(q[2] - q[0]) / d;
    let l2 = (q[1] - q[0]).perp_dot(x - q[0]) / d;
    let l0 = 1.0 - l1 - l2;
    let e = -1e-9;
    (l0 >= e && l1 >= e && l2 >= e).then_some([l0, l1, l2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_cells_and_barycentrics() {
        assert_eq!(round_up(0.04), 0.05);
        assert_eq!(round_up(0.025), 0.025);
        assert_eq!(round_up(0.0026), 0.005);
        assert_eq!(round_up(1.0), 1.0);
        let q = [DVec2::ZERO, DVec2::X, DVec2::Y];
        let l = barycentric(&q, DVec2::new(0.25, 0.5)).unwrap();
        assert!((l[0] - 0.25).abs() < 1e-15 && (l[1] - 0.25).abs() < 1e-15);
        assert!(barycentric(&q, DVec2::new(0.6, 0.6)).is_none());
    }
}
