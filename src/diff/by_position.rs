//! Vertices paired by place instead of by index: for two bakes of one scene of which only one
//! has lightmaps, whose lightmapped primitives' vertices were laid out anew on their charts
//! (re-ordered, and repeated where a chart edge splits them). Each of B's vertices goes with
//! the nearest of A's vertices of the same primitive within the matching tolerance; the values
//! a repeated vertex carries are copies, so any of them will do.
//!
//! Input: one primitive of each bake and the tolerance (m). Output: A's vertex for each of B's,
//! or the first of B's vertices with no vertex of A there. Linear on average: A's vertices are
//! hashed into cells of the tolerance's size and each of B's looks in the 27 cells around it.

use crate::readback::Primitive;
use glam::{DVec3, IVec3};
use std::collections::HashMap;

/// A's vertex for each of B's, or (B's vertex, its place) when A has none there.
pub(super) fn pair_vertices(
    pa: &Primitive,
    pb: &Primitive,
    tolerance: f64,
) -> Result<Vec<u32>, (usize, DVec3)> {
    let cell = tolerance.max(f64::MIN_POSITIVE);
    let key = |p: DVec3| (p / cell).floor().as_ivec3();
    let mut grid: HashMap<IVec3, Vec<u32>> = HashMap::new();
    for (v, &p) in pa.positions.iter().enumerate() {
        grid.entry(key(p)).or_default().push(v as u32);
    }
    let mut map = Vec::with_capacity(pb.positions.len());
    for (v, &q) in pb.positions.iter().enumerate() {
        let k = key(q);
        let mut best: Option<(f64, u32)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let cands = grid.get(&(k + IVec3::new(dx, dy, dz)));
                    for &c in cands.into_iter().flatten() {
                        let d = pa.positions[c as usize].distance(q);
                        if d <= tolerance && best.is_none_or(|(bd, bc)| (d, c) < (bd, bc)) {
                            best = Some((d, c));
                        }
                    }
                }
            }
        }
        map.push(best.ok_or((v, q))?.1);
    }
    Ok(map)
}
