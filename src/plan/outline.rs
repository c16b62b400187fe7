//! A plan's outline as line segments in the plane's 2-D frame (m).
//!
//! - The working plane ([`slice`]): every baked triangle cut by the horizontal plane y = `height`
//!   (+Y up): walls and whatever stands at that height; plus the boundary edges of upward-facing
//!   horizontal surfaces up to 0.1 m below it (desk tops at the working plane's height, which a cut
//!   just above them would miss). Triangles lying in the plane itself give no cut.
//! - A surface ([`boundary`]): the edges its chosen triangles use once (per primitive, by vertex
//!   index), so covered parts cut out of it (a desk leg on a floor) show as outlines too.
//!
//! Segments are deduplicated (a double-sided wall gives each once) and sorted, so the drawing
//! does not depend on the order surfaces were baked in.

use super::frame::Frame;
use crate::readback::{BakedOutput, Primitive};
use glam::{DVec2, DVec3};
use std::collections::BTreeMap;

/// How far below the working plane an upward-facing surface's edges are still drawn (m).
pub const TOPS_BELOW: f64 = 0.1;

/// The baked geometry cut by the plane y = `height`, and the tops just under it.
pub(crate) fn slice(input: &BakedOutput, height: f64, frame: &Frame) -> Vec<[DVec2; 2]> {
    let mut out = Vec::new();
    for prim in &input.primitives {
        let mut tops = Vec::new();
        for (t, tri) in prim.triangles.iter().enumerate() {
            let p = tri.map(|v| prim.positions[v as usize]);
            let d = p.map(|q| q.y - height);
            if normal(p).y > 0.999 && d.iter().all(|&x| (-TOPS_BELOW..=1e-6).contains(&x)) {
                tops.push(t);
                continue;
            }
            if d.iter().all(|x| x.abs() < 1e-6) {
                continue;
            }
            let mut cut = Vec::with_capacity(2);
            for k in 0..3 {
                let (a, b) = (k, (k + 1) % 3);
                if (d[a] > 0.0) != (d[b] > 0.0) {
                    let s = d[a] / (d[a] - d[b]);
                    cut.push(p[a] + (p[b] - p[a]) * s);
                }
            }
            if let [a, b] = cut[..] {
                out.push([frame.on_page(a), frame.on_page(b)]);
            }
        }
        out.extend(boundary(prim, &tops, frame));
    }
    tidy(out)
}

/// The edges that the `chosen` triangles of `prim` use once, in the frame.
pub(crate) fn boundary(prim: &Primitive, chosen: &[usize], frame: &Frame) -> Vec<[DVec2; 2]> {
    let mut count: BTreeMap<(u32, u32), (u32, [u32; 2])> = BTreeMap::new();
    for &t in chosen {
        let tri = prim.triangles[t];
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let e = count.entry((a.min(b), a.max(b))).or_insert((0, [a, b]));
            e.0 += 1;
        }
    }
    let at = |v: u32| frame.on_page(prim.positions[v as usize]);
    (count.values())
        .filter(|(n, _)| *n == 1)
        .map(|(_, [a, b])| [at(*a), at(*b)])
        .collect()
}

/// Segments without zero-length ones and duplicates (endpoints compared at 10 µm), sorted.
pub(crate) fn tidy(segments: Vec<[DVec2; 2]>) -> Vec<[DVec2; 2]> {
    let key = |p: DVec2| ((p.x * 1e5).round() as i64, (p.y * 1e5).round() as i64);
    // Keyed by the endpoints in order (first the smaller): a BTreeMap sorts and deduplicates.
    let mut out: BTreeMap<[(i64, i64); 2], [DVec2; 2]> = BTreeMap::new();
    for [a, b] in segments {
        let (ka, kb) = (key(a), key(b));
        if ka == kb {
            continue;
        }
        let (k, s) = if ka <= kb {
            ([ka, kb], [a, b])
        } else {
            ([kb, ka], [b, a])
        };
        out.entry(k).or_insert(s);
    }
    out.into_values().collect()
}

/// A triangle's unit normal (zero when it has no area).
pub(crate) fn normal(p: [DVec3; 3]) -> DVec3 {
    (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
}
