//! Chart packing for lightmap atlases: groups of rectangles (one surface's charts each) into as
//! few atlases as fit, every group whole in one atlas (a glTF primitive references one texture),
//! charts never rotated (the UV mapping assumes none).
//!
//! A skyline packer with a waste map (J. Jylänki, "A Thousand Ways to Pack the Bin", 2010, §4,
//! SKYLINE-BL-WM): the free space of an atlas is a staircase of horizontal segments, and a
//! rectangle goes where its far edge (y + h, y down) ends least far, leftmost on ties; the free
//! texels a rectangle closes off between itself and the skyline are kept as holes and filled
//! first (best short-side fit). Groups are taken tallest first, each group's rectangles tallest
//! first, so rows of like heights form.
//! Chosen over etagere, guillotiere, crunch and rectangle-pack on the figures in
//! `bench/results/lightmaps/packers.md`. Deterministic: no hashing, no threads.

use std::cmp::Reverse;

/// A chart's rectangle in texels, padding already included by the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    pub w: u32,
    pub h: u32,
}

/// Where a rectangle went: atlas index and its top-left texel (x right, y down).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Place {
    pub atlas: usize,
    pub x: u32,
    pub y: u32,
}

/// The atlases used and where every rectangle went.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Packing {
    /// Width and height of each atlas in texels, multiples of 4.
    pub atlases: Vec<(u32, u32)>,
    /// Per group, per rectangle, in the caller's order.
    pub places: Vec<Vec<Place>>,
}

/// A group that cannot fit one empty atlas of `max_edge`²: its index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooBig {
    pub group: usize,
}

/// Edges above this are treated as this (keeps every sum of two coordinates inside `u32`).
const EDGE_CAP: u32 = 1 << 30;

/// A new atlas is filled first to a width of √(A / FILL), A the area still to place, so that a
/// last, partly filled atlas comes out near square rather than a strip `max_edge` wide.
const FILL: f64 = 0.85;

/// Pack groups of rectangles (each group = one surface's charts; a group must land whole in one
/// atlas, since a glTF primitive references one texture) into as few atlases of at most
/// `max_edge` texels a side as it can; deterministic (same input → same output, no hashing
/// order, no threads). Groups are taken tallest rectangle first (then larger area, then input
/// order); each goes to the first atlas that takes all of it, else to a new one. Each atlas is
/// then trimmed to the extent used (width and height rounded up to a multiple of 4, at least 4).
/// The usable square is `max_edge` rounded down to a multiple of 4. Zero-sized rectangles take
/// no space: they are placed at (0, 0) of their group's atlas.
pub(crate) fn pack(groups: &[Vec<Rect>], max_edge: u32) -> Result<Packing, TooBig> {
    let edge = max_edge.min(EDGE_CAP) / 4 * 4;
    let area = |g: &[Rect]| g.iter().map(|r| r.w as u64 * r.h as u64).sum::<u64>();
    let tallest = |g: &[Rect]| g.iter().map(|r| r.h).max().unwrap_or(0);
    let mut by_height: Vec<usize> = (0..groups.len()).collect();
    by_height.sort_by_key(|&g| (Reverse(tallest(&groups[g])), Reverse(area(&groups[g])), g));
    // Area and widest rectangle of the groups from the k-th taken on.
    let mut remaining = vec![0u64; groups.len() + 1];
    let mut widest = vec![0u32; groups.len() + 1];
    for (k, &g) in by_height.iter().enumerate().rev() {
        remaining[k] = remaining[k + 1] + area(&groups[g]);
        widest[k] = widest[k + 1].max(groups[g].iter().map(|r| r.w).max().unwrap_or(0));
    }
    // Holes narrower or lower than every rectangle can take none: they are not kept.
    let nonzero = || groups.iter().flatten().filter(|r| r.w > 0 && r.h > 0);
    let least = (
        nonzero().map(|r| r.w).min().unwrap_or(1),
        nonzero().map(|r| r.h).min().unwrap_or(1),
    );

    let mut atlases: Vec<Atlas> = Vec::new();
    let mut places = vec![Vec::new(); groups.len()];
    for (k, &g) in by_height.iter().enumerate() {
        let group = &groups[g];
        if group.is_empty() {
            continue;
        }
        if group.iter().any(|r| r.w > edge || r.h > edge) {
            return Err(TooBig { group: g });
        }
        let mut order: Vec<usize> = (0..group.len()).collect();
        order.sort_by_key(|&i| (Reverse(group[i].h), Reverse(group[i].w), i));
        let need = area(group);

        let mut found = None;
        for (a, atlas) in atlases.iter_mut().enumerate() {
            if atlas.free_area() >= need
                && let Some(xy) = atlas.try_group(group, &order)
            {
                found = Some((a, xy));
                break;
            }
        }
        let (a, xy) = match found {
            Some(f) => f,
            None => {
                let soft = soft_width(remaining[k], widest[k], edge);
                let mut atlas = Atlas::new(edge, soft, least);
                let xy = atlas.try_group(group, &order).ok_or(TooBig { group: g })?;
                atlases.push(atlas);
                (atlases.len() - 1, xy)
            }
        };
        places[g] = xy
            .into_iter()
            .map(|(x, y)| Place { atlas: a, x, y })
            .collect();
    }
    let trim = |v: u32| v.div_ceil(4).max(1) * 4;
    Ok(Packing {
        atlases: atlases
            .iter()
            .map(|a| (trim(a.used.0), trim(a.used.1)))
            .collect(),
        places,
    })
}

/// The width a new atlas is filled to first: √(remaining area / FILL), at least the widest
/// rectangle still to place, at most the edge, a multiple of 4.
fn soft_width(remaining: u64, widest: u32, edge: u32) -> u32 {
    let w = ((remaining as f64 / FILL).sqrt().ceil() as u64).min(edge as u64) as u32;
    (w.div_ceil(4) * 4).max(widest).min(edge)
}

/// A hole under the skyline: x, y, w, h.
type Hole = (u32, u32, u32, u32);

/// One atlas: its skyline and holes, the width it is filled to first, the extent and area used.
struct Atlas {
    sky: Vec<Seg>,
    holes: Vec<Hole>,
    edge: u32,
    soft: u32,
    /// Holes smaller than this (w, h) are not kept.
    least: (u32, u32),
    used: (u32, u32),
    used_area: u64,
}

impl Atlas {
    fn new(edge: u32, soft: u32, least: (u32, u32)) -> Self {
        Self {
            sky: vec![Seg {
                x: 0,
                y: 0,
                w: edge,
            }],
            holes: Vec::new(),
            edge,
            soft,
            least,
            used: (0, 0),
            used_area: 0,
        }
    }

    /// An upper bound of the area still free.
    fn free_area(&self) -> u64 {
        self.edge as u64 * self.edge as u64 - self.used_area
    }

    /// Place the whole group (in `order`) or nothing: top-left corners in the group's order.
    fn try_group(&mut self, group: &[Rect], order: &[usize]) -> Option<Vec<(u32, u32)>> {
        let saved = (self.sky.clone(), self.holes.clone());
        let mut xy = vec![(0, 0); group.len()];
        let mut used = self.used;
        for &i in order {
            let Rect { w, h } = group[i];
            if w == 0 || h == 0 {
                continue;
            }
            let at = match self.fill_hole(w, h) {
                Some(at) => at,
                // Within the soft width if it fits there, else anywhere in the atlas.
                None => match find(&self.sky, w, h, self.soft, self.edge)
                    .or_else(|| find(&self.sky, w, h, self.edge, self.edge))
                {
                    Some((seg, x, y)) => {
                        self.cover(seg, x, y, w, h);
                        (x, y)
                    }
                    None => {
                        (self.sky, self.holes) = saved;
                        return None;
                    }
                },
            };
            xy[i] = at;
            used = (used.0.max(at.0 + w), used.1.max(at.1 + h));
        }
        self.used = used;
        self.used_area += group.iter().map(|r| r.w as u64 * r.h as u64).sum::<u64>();
        Some(xy)
    }

    /// Put w × h in the hole it fits best (least leftover on the short side, then on the long
    /// side, first found on ties); the rest of the hole is cut along its shorter leftover.
    fn fill_hole(&mut self, w: u32, h: u32) -> Option<(u32, u32)> {
        let mut best: Option<(u32, u32, usize)> = None;
        for (k, &(_, _, hw, hh)) in self.holes.iter().enumerate() {
            if hw >= w && hh >= h {
                let (a, b) = (hw - w, hh - h);
                let key = (a.min(b), a.max(b), k);
                if best.is_none_or(|b| (key.0, key.1) < (b.0, b.1)) {
                    best = Some(key);
                }
            }
        }
        let (_, _, k) = best?;
        let (x, y, hw, hh) = self.holes.swap_remove(k);
        let (right, below) = if hw - w < hh - h {
            ((x + w, y, hw - w, h), (x, y + h, hw, hh - h))
        } else {
            ((x + w, y, hw - w, hh), (x, y + h, w, hh - h))
        };
        self.keep_hole(right);
        self.keep_hole(below);
        Some((x, y))
    }

    fn keep_hole(&mut self, hole: Hole) {
        if hole.2 >= self.least.0 && hole.3 >= self.least.1 {
            self.holes.push(hole);
        }
    }

    /// Move the skyline over x..x + w (starting at segment `i`, whose x it is) down to y + h; the
    /// free texels between those segments and the rectangle at y become holes.
    fn cover(&mut self, i: usize, x: u32, y: u32, w: u32, h: u32) {
        let end = x + w;
        // Segments i..j are covered whole; segment j (if any) is cut at `end`.
        let mut j = i;
        while j < self.sky.len() && self.sky[j].x < end {
            let s = self.sky[j];
            let span = (s.x + s.w).min(end) - s.x;
            self.keep_hole((s.x, s.y, span, y - s.y));
            if s.x + s.w > end {
                break;
            }
            j += 1;
        }
        if j < self.sky.len() && self.sky[j].x < end {
            let s = &mut self.sky[j];
            s.w -= end - s.x;
            s.x = end;
        }
        let top = y + h;
        self.sky.splice(i..j, [Seg { x, y: top, w }]);
        // Merge with neighbours at the same height.
        if i + 1 < self.sky.len() && self.sky[i + 1].y == top {
            self.sky[i].w += self.sky[i + 1].w;
            self.sky.remove(i + 1);
        }
        if i > 0 && self.sky[i - 1].y == top {
            self.sky[i - 1].w += self.sky[i].w;
            self.sky.remove(i);
        }
    }
}

/// A segment of the skyline: texels x..x + w are free from row y down. An atlas's segments run
/// left to right over 0..edge, no two neighbours at the same y.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Seg {
    x: u32,
    y: u32,
    w: u32,
}

/// Where a w × h rectangle (w, h > 0) ends least far down (least y + h), then leftmost, within
/// x + w ≤ `limit` and y + h ≤ `max_h`: (index of the segment it starts on, x, y).
fn find(sky: &[Seg], w: u32, h: u32, limit: u32, max_h: u32) -> Option<(usize, u32, u32)> {
    let mut best: Option<(u32, usize, u32, u32)> = None; // (y + h, segment, x, y)
    for (i, s) in sky.iter().enumerate() {
        let x = s.x;
        if x + w > limit {
            break;
        }
        // The rectangle starts at the largest y of the segments under x..x + w; stop as soon
        // as it cannot beat the best found (later candidates lie further right).
        let bound = best.map_or(max_h, |b| (b.0 - 1).min(max_h));
        let mut y = 0;
        for t in &sky[i..] {
            if t.x >= x + w {
                break;
            }
            y = y.max(t.y);
            if y + h > bound {
                break;
            }
        }
        if y + h <= bound {
            best = Some((y + h, i, x, y));
        }
    }
    best.map(|(_, i, x, y)| (i, x, y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn r(w: u32, h: u32) -> Rect {
        Rect { w, h }
    }

    /// Every rule of a packing: shapes match the input, a group in one atlas, every rectangle
    /// inside its atlas, no two rectangles of an atlas overlapping, atlas edges multiples of 4
    /// within `max_edge`.
    fn check(groups: &[Vec<Rect>], max_edge: u32, p: &Packing) {
        assert_eq!(p.places.len(), groups.len());
        for &(w, h) in &p.atlases {
            assert!(w % 4 == 0 && h % 4 == 0 && w > 0 && h > 0, "{w}×{h}");
            assert!(w <= max_edge && h <= max_edge, "{w}×{h} > {max_edge}");
        }
        let mut per_atlas: Vec<Vec<(u32, u32, u32, u32)>> = vec![Vec::new(); p.atlases.len()];
        for (g, (group, places)) in groups.iter().zip(&p.places).enumerate() {
            assert_eq!(group.len(), places.len(), "group {g}");
            if let Some(first) = places.first() {
                assert!(
                    places.iter().all(|q| q.atlas == first.atlas),
                    "group {g} split"
                );
            }
            for (rect, q) in group.iter().zip(places) {
                let (aw, ah) = p.atlases[q.atlas];
                assert!(
                    q.x + rect.w <= aw && q.y + rect.h <= ah,
                    "{rect:?} at {q:?} outside"
                );
                if rect.w > 0 && rect.h > 0 {
                    per_atlas[q.atlas].push((q.x, q.y, rect.w, rect.h));
                }
            }
        }
        for rects in &mut per_atlas {
            // Sweep along x: only rectangles whose x ranges meet are compared.
            rects.sort();
            for (i, a) in rects.iter().enumerate() {
                for b in &rects[i + 1..] {
                    if b.0 >= a.0 + a.2 {
                        break;
                    }
                    let apart = b.1 >= a.1 + a.3 || a.1 >= b.1 + b.3;
                    assert!(apart, "{a:?} and {b:?} overlap");
                }
            }
        }
    }

    /// A room-like input from a fixed linear congruential sequence.
    fn room(n_groups: usize, seed: u64) -> Vec<Vec<Rect>> {
        let mut s = seed;
        let mut next = |lo: u32, hi: u32| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + ((s >> 33) as u32) % (hi - lo + 1)
        };
        (0..n_groups)
            .map(|_| {
                let n = next(1, 6);
                (0..n).map(|_| r(next(4, 300), next(4, 200))).collect()
            })
            .collect()
    }

    #[test]
    fn a_room_packs_without_overlap_inside_its_atlases() {
        let groups = room(30, 7);
        let p = pack(&groups, 1024).unwrap();
        check(&groups, 1024, &p);
        assert!(
            p.atlases.len() >= 2,
            "the room needs more than one 1024² atlas"
        );
    }

    #[test]
    fn same_input_same_packing() {
        let groups = room(40, 11);
        let a = pack(&groups, 512).unwrap();
        let b = pack(&groups, 512).unwrap();
        assert_eq!(a, b);
        check(&groups, 512, &a);
    }

    #[test]
    fn four_quarters_fill_one_atlas_exactly() {
        let groups = vec![vec![r(50, 50)]; 4];
        let p = pack(&groups, 100).unwrap();
        assert_eq!(p.atlases, vec![(100, 100)]);
        check(&groups, 100, &p);
    }

    #[test]
    fn a_later_group_goes_back_to_an_earlier_atlas_with_room() {
        let groups = vec![vec![r(90, 90)], vec![r(90, 90)], vec![r(10, 10)]];
        let p = pack(&groups, 100).unwrap();
        assert_eq!(p.atlases.len(), 2);
        assert_eq!(p.places[0][0].atlas, 0);
        assert_eq!(p.places[1][0].atlas, 1);
        assert_eq!(p.places[2][0].atlas, 0);
        check(&groups, 100, &p);
    }

    #[test]
    fn a_group_that_does_not_fit_the_current_atlas_moves_whole() {
        // The 100 × 40 left under the first group takes two of the second's three rectangles.
        let groups = vec![vec![r(100, 60)], vec![r(40, 40), r(60, 40), r(40, 40)]];
        let p = pack(&groups, 100).unwrap();
        assert_eq!(p.atlases.len(), 2);
        assert!(p.places[1].iter().all(|q| q.atlas == 1));
        check(&groups, 100, &p);
    }

    #[test]
    fn the_hole_under_a_wide_rectangle_is_filled_first() {
        let mut atlas = Atlas::new(100, 100, (1, 1));
        assert_eq!(atlas.try_group(&[r(10, 30)], &[0]), Some(vec![(0, 0)]));
        // 100 wide: only below the first, closing off 90 × 30 beside it.
        assert_eq!(atlas.try_group(&[r(100, 10)], &[0]), Some(vec![(0, 30)]));
        assert_eq!(atlas.holes, vec![(10, 0, 90, 30)]);
        // The skyline's place would be (0, 40); the hole takes it.
        assert_eq!(atlas.try_group(&[r(20, 20)], &[0]), Some(vec![(10, 0)]));
        // A group that does not fit leaves skyline and holes as they were.
        let (sky, holes) = (atlas.sky.clone(), atlas.holes.clone());
        assert_eq!(atlas.try_group(&[r(30, 30), r(100, 61)], &[0, 1]), None);
        assert_eq!((atlas.sky, atlas.holes), (sky, holes));
    }

    #[test]
    fn oversized_groups_are_too_big() {
        let ok = vec![r(10, 10)];
        // One rectangle wider than the atlas.
        let groups = vec![ok.clone(), vec![r(101, 5)]];
        assert_eq!(pack(&groups, 100), Err(TooBig { group: 1 }));
        // Rectangles that fit one by one but not together.
        let groups = vec![ok.clone(), ok.clone(), vec![r(60, 60), r(60, 60)]];
        assert_eq!(pack(&groups, 100), Err(TooBig { group: 2 }));
        // The usable edge is max_edge rounded down to a multiple of 4.
        assert_eq!(pack(&[vec![r(101, 1)]], 102), Err(TooBig { group: 0 }));
        assert!(pack(&[vec![r(100, 1)]], 102).is_ok());
    }

    #[test]
    fn atlases_are_trimmed_to_multiples_of_four() {
        let groups = vec![vec![r(5, 7)]];
        let p = pack(&groups, 2048).unwrap();
        assert_eq!(p.atlases, vec![(8, 8)]);
        let groups = vec![vec![r(30, 10), r(30, 9)], vec![r(1, 1)]];
        let p = pack(&groups, 2048).unwrap();
        check(&groups, 2048, &p);
        for &(w, h) in &p.atlases {
            assert!(w <= 64 && h <= 32, "{w}×{h} not trimmed");
        }
    }

    #[test]
    fn empty_groups_and_zero_sized_rectangles() {
        assert_eq!(
            pack(&[], 64),
            Ok(Packing {
                atlases: vec![],
                places: vec![]
            })
        );
        let groups = vec![vec![], vec![r(0, 5), r(8, 8)], vec![r(0, 0)]];
        let p = pack(&groups, 64).unwrap();
        assert!(p.places[0].is_empty());
        check(&groups, 64, &p);
    }

    fn groups_strategy(max_side: u32, max_rects: usize) -> impl Strategy<Value = Vec<Vec<Rect>>> {
        let rect = (1..=max_side, 1..=max_side).prop_map(|(w, h)| r(w, h));
        prop::collection::vec(prop::collection::vec(rect, 0..=max_rects), 0..40)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Up to 4 rectangles of at most 16 texels always fit an empty 64² atlas side by side,
        /// so every such input packs.
        #[test]
        fn random_groups_pack_without_overlap(
            groups in groups_strategy(16, 4),
            max_edge in 64u32..=200,
        ) {
            let p = pack(&groups, max_edge);
            prop_assert!(p.is_ok(), "{p:?}");
            check(&groups, max_edge, &p.unwrap());
        }

        /// Larger rectangles: either a valid packing or the index of a group that has a
        /// rectangle (so something to place).
        #[test]
        fn random_large_groups_pack_or_name_a_group(
            groups in groups_strategy(60, 8),
            max_edge in 16u32..=128,
        ) {
            match pack(&groups, max_edge) {
                Ok(p) => check(&groups, max_edge, &p),
                Err(TooBig { group }) => prop_assert!(!groups[group].is_empty()),
            }
        }
    }
}
