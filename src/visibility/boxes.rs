//! Boxes that meet a box: a BVH over axis-aligned boxes, for neighbour searches that are not
//! rays (what can cover a triangle or cut it along a seam, `crate::contacts`).
//!
//! Input: boxes in world metres. Output: for a query box, every box that meets it (touching
//! counts), each once, in ascending index order. The BVH (obvhs, f32) holds every box rounded
//! outward and is traversed with the query rounded outward too, so it can only name too many;
//! each candidate is then decided in f64, and the answer does not depend on the BVH's layout.
//! A query costs the depth of the tree plus its candidates, whatever the boxes' sizes (a uniform
//! grid sized for a chair's triangles visits hundreds of thousands of empty cells for a query a
//! metre wide).

use glam::{DVec3, Vec3A};
use obvhs::{Boundable, BvhBuildParams, aabb::Aabb, bvh2::Bvh2, bvh2::builder::build_bvh2};
use std::time::Duration;

/// Boxes indexed for overlap queries.
pub struct BoxIndex {
    bvh: Option<Bvh2>,
    boxes: Vec<(DVec3, DVec3)>,
}

/// A box as the BVH sees it.
struct Outward(Aabb);

impl Boundable for Outward {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

impl BoxIndex {
    /// Index `boxes` (`(lo, hi)`, m).
    pub(crate) fn new(boxes: Vec<(DVec3, DVec3)>) -> Self {
        let outward: Vec<Outward> = boxes.iter().map(|&b| Outward(outward(b))).collect();
        let bvh = (!boxes.is_empty()).then(|| {
            build_bvh2(
                &outward,
                BvhBuildParams::fast_build(),
                &mut Duration::default(),
            )
        });
        BoxIndex { bvh, boxes }
    }

    /// The boxes that meet `lo..hi`, ascending, each once, into `out`.
    pub(crate) fn near(&self, lo: DVec3, hi: DVec3, out: &mut Vec<u32>) {
        out.clear();
        let Some(bvh) = &self.bvh else {
            return;
        };
        bvh.aabb_traverse(outward((lo, hi)), |bvh, node| {
            let node = &bvh.nodes[node as usize];
            let first = node.first_index as usize;
            for &i in &bvh.primitive_indices[first..first + node.prim_count as usize] {
                let (l, h) = self.boxes[i as usize];
                if l.cmple(hi).all() && h.cmpge(lo).all() {
                    out.push(i);
                }
            }
            true
        });
        out.sort_unstable();
    }
}

/// The f32 box holding the f64 box `(lo, hi)`.
fn outward((lo, hi): (DVec3, DVec3)) -> Aabb {
    let down = |x: f64| {
        let f = x as f32;
        if f as f64 > x { f.next_down() } else { f }
    };
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x { f.next_up() } else { f }
    };
    Aabb {
        min: Vec3A::new(down(lo.x), down(lo.y), down(lo.z)),
        max: Vec3A::new(up(hi.x), up(hi.y), up(hi.z)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic scatter of small, medium and huge boxes (glTF +Y up), some far from the
    /// origin so that f32 rounds their corners.
    fn scatter() -> Vec<(DVec3, DVec3)> {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..3000)
            .map(|i| {
                let size = match i % 100 {
                    0 => 30.0,
                    1..=9 => 2.0,
                    _ => 0.05,
                };
                let shift = if i % 7 == 0 { 1.0e5 } else { 0.0 };
                let o = DVec3::new(next() * 20.0 + shift, next() * 3.0, next() * 15.0);
                let d = DVec3::new(next(), next(), next()) * size;
                (o, o + d)
            })
            .collect()
    }

    #[test]
    fn near_names_every_box_that_meets_the_query_once_in_order() {
        let boxes = scatter();
        let index = BoxIndex::new(boxes.clone());
        let mut out = Vec::new();
        let queries = [
            (DVec3::new(5.0, 1.0, 5.0), DVec3::new(5.3, 1.2, 5.1)),
            (DVec3::new(-1.0, -1.0, -1.0), DVec3::new(25.0, 4.0, 20.0)),
            (DVec3::new(10.0, 0.0, 0.0), DVec3::new(10.0, 3.0, 15.0)),
            (
                DVec3::new(100.0, 100.0, 100.0),
                DVec3::new(101.0, 101.0, 101.0),
            ),
        ];
        let mut total = 0;
        // Every box as a query, grown a little, and exactly: touching boxes meet.
        let grown = boxes.iter().flat_map(|&(l, h)| {
            let p = DVec3::new(0.0, 0.02, 0.0);
            [(l - p, h + p), (l, h)]
        });
        for (lo, hi) in queries.into_iter().chain(grown) {
            index.near(lo, hi, &mut out);
            let expected: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| {
                    let (l, h) = boxes[i as usize];
                    l.cmple(hi).all() && h.cmpge(lo).all()
                })
                .collect();
            assert_eq!(out, expected, "query {lo} .. {hi}");
            total += out.len();
        }
        assert!(
            total > 2 * boxes.len(),
            "queries found neighbours, not only themselves"
        );
        BoxIndex::new(Vec::new()).near(DVec3::ZERO, DVec3::ONE, &mut out);
        assert!(out.is_empty());
    }
}
