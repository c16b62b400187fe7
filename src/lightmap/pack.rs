//! Chart packing for lightmap atlases: groups of rectangles (one surface's charts each) into as
//! few atlases as fit, every group whole in one atlas (a glTF primitive references one texture),
//! charts never rotated (the UV mapping assumes none).
//!
//! A skyline packer, bottom-left rule (J. Jylänki, "A Thousand Ways to Pack the Bin", 2010, §4):
//! the free space of an atlas is a staircase of horizontal segments; a rectangle goes where its
//! far edge (y + h, y down) ends lowest, leftmost on ties. Chosen over etagere, guillotiere,
//! crunch and rectangle-pack on the figures in `bench/results/lightmaps/packers.md`.
//! Deterministic: groups in input order, a group's rectangles by height, no hashing, no threads.

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
    /// Per group, per rectangle (in the caller's order).
    pub places: Vec<Vec<Place>>,
}

/// A group that cannot fit one empty atlas of `max_edge`²: its index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooBig {
    pub group: usize,
}

/// Edges above this are treated as this (keeps every sum of two coordinates inside `u32`).
const EDGE_CAP: u32 = 1 << 30;

/// Packing variants measured in bench/packers (temporary).
#[derive(Debug, Clone)]
pub(crate) struct Opts {
    pub sort_groups: bool,
    pub fills: Vec<f64>,
    pub min_waste: bool,
    pub waste_map: bool,
}

impl Default for Opts {
    fn default() -> Self {
        Self {
            sort_groups: false,
            fills: vec![0.85],
            min_waste: false,
            waste_map: false,
        }
    }
}

/// Pack groups of rectangles (each group = one surface's charts; a group must land whole in one
/// atlas, since a glTF primitive references one texture) into as few atlases of at most
/// `max_edge` texels a side as it can; groups in order, deterministic (same input → same output,
/// no hashing order, no threads). A group goes to the first atlas it fits, else to a new one.
/// Each atlas is then trimmed to the extent used (width and height rounded up to a multiple of
/// 4, at least 4). The usable square is `max_edge` rounded down to a multiple of 4.
/// Zero-sized rectangles take no space; they are placed at (0, 0) of their group's atlas.
pub fn pack(groups: &[Vec<Rect>], max_edge: u32) -> Result<Packing, TooBig> {
    pack_with(groups, max_edge, &Opts::default())
}

pub(crate) fn pack_with(
    groups: &[Vec<Rect>],
    max_edge: u32,
    opts: &Opts,
) -> Result<Packing, TooBig> {
    let mut best: Option<Packing> = None;
    let cost = |p: &Packing| {
        (
            p.atlases.len(),
            p.atlases
                .iter()
                .map(|&(w, h)| w as u64 * h as u64)
                .sum::<u64>(),
        )
    };
    for &fill in &opts.fills {
        let p = pack_once(groups, max_edge, opts, fill)?;
        if best.as_ref().is_none_or(|b| cost(&p) < cost(b)) {
            best = Some(p);
        }
    }
    Ok(best.unwrap())
}

fn pack_once(
    groups: &[Vec<Rect>],
    max_edge: u32,
    opts: &Opts,
    fill: f64,
) -> Result<Packing, TooBig> {
    let edge = max_edge.min(EDGE_CAP) / 4 * 4;
    let area = |g: &Vec<Rect>| g.iter().map(|r| r.w as u64 * r.h as u64).sum::<u64>();
    let mut gorder: Vec<usize> = (0..groups.len()).collect();
    if opts.sort_groups {
        let tallest = |g: &Vec<Rect>| g.iter().map(|r| r.h).max().unwrap_or(0);
        gorder.sort_by_key(|&g| {
            (
                std::cmp::Reverse(tallest(&groups[g])),
                std::cmp::Reverse(area(&groups[g])),
                g,
            )
        });
    }
    // Area and widest rectangle of the groups from the k-th on (processing order).
    let mut remaining: Vec<u64> = vec![0; groups.len() + 1];
    let mut widest: Vec<u32> = vec![0; groups.len() + 1];
    for (k, &g) in gorder.iter().enumerate().rev() {
        remaining[k] = remaining[k + 1] + area(&groups[g]);
        widest[k] = widest[k + 1].max(groups[g].iter().map(|r| r.w).max().unwrap_or(0));
    }

    let nonzero = || groups.iter().flatten().filter(|r| r.w > 0 && r.h > 0);
    let min_w = nonzero().map(|r| r.w).min().unwrap_or(1);
    let min_h = nonzero().map(|r| r.h).min().unwrap_or(1);
    let mut atlases: Vec<Atlas> = Vec::new();
    let mut places = vec![Vec::new(); groups.len()];
    for (k, &gi) in gorder.iter().enumerate() {
        let group = &groups[gi];
        if group.is_empty() {
            continue;
        }
        if group.iter().any(|r| r.w > edge || r.h > edge) {
            return Err(TooBig { group: gi });
        }
        // Tallest first (then widest, then the caller's order): rows of like heights.
        let mut order: Vec<usize> = (0..group.len()).collect();
        order.sort_by_key(|&i| {
            (
                std::cmp::Reverse(group[i].h),
                std::cmp::Reverse(group[i].w),
                i,
            )
        });
        let need = area(group);

        let mut found = None;
        for (ai, atlas) in atlases.iter_mut().enumerate() {
            if atlas.free_area() < need {
                continue;
            }
            if let Some(xy) = atlas.try_group(group, &order, opts.min_waste) {
                found = Some((ai, xy));
                break;
            }
        }
        let (ai, xy) = match found {
            Some(f) => f,
            None => {
                let soft = soft_width(remaining[k], widest[k], edge, fill);
                let mut atlas = Atlas::new(edge, soft);
                atlas.waste_map = opts.waste_map;
                atlas.min_w = min_w;
                atlas.min_h = min_h;
                let xy = atlas
                    .try_group(group, &order, opts.min_waste)
                    .ok_or(TooBig { group: gi })?;
                atlases.push(atlas);
                (atlases.len() - 1, xy)
            }
        };
        places[gi] = xy
            .into_iter()
            .map(|(x, y)| Place { atlas: ai, x, y })
            .collect();
    }
    let trim = |v: u32| v.div_ceil(4).max(1) * 4;
    Ok(Packing {
        atlases: atlases
            .iter()
            .map(|a| (trim(a.used_w), trim(a.used_h)))
            .collect(),
        places,
    })
}

/// The width a new atlas is filled to first: √(remaining area / FILL), at least the widest
/// rectangle, at most the edge, a multiple of 4.
fn soft_width(remaining: u64, widest: u32, edge: u32, fill: f64) -> u32 {
    let w = ((remaining as f64 / fill).sqrt().ceil() as u64).min(edge as u64) as u32;
    (w.div_ceil(4) * 4).max(widest).min(edge)
}

/// One atlas: its skyline, the width it is filled to first, the extent used.
struct Atlas {
    sky: Skyline,
    edge: u32,
    soft: u32,
    used_w: u32,
    used_h: u32,
    used_area: u64,
    /// Holes left under placed rectangles (x, y, w, h), filled before the skyline.
    holes: Vec<(u32, u32, u32, u32)>,
    waste_map: bool,
    /// Narrowest and lowest rectangle of the input: smaller holes are not kept.
    min_w: u32,
    min_h: u32,
}

impl Atlas {
    fn new(edge: u32, soft: u32) -> Self {
        Self {
            sky: Skyline::new(edge),
            edge,
            soft,
            used_w: 0,
            used_h: 0,
            used_area: 0,
            holes: Vec::new(),
            waste_map: false,
            min_w: 1,
            min_h: 1,
        }
    }

    /// An upper bound of the area still free (waste under the skyline not subtracted).
    fn free_area(&self) -> u64 {
        self.edge as u64 * self.edge as u64 - self.used_area
    }

    /// Place the whole group (in `order`) or nothing: top-left corners in the group's order.
    fn try_group(
        &mut self,
        group: &[Rect],
        order: &[usize],
        min_waste: bool,
    ) -> Option<Vec<(u32, u32)>> {
        let saved = self.sky.segs.clone();
        let saved_holes = self.holes.clone();
        let mut xy = vec![(0, 0); group.len()];
        let (mut used_w, mut used_h) = (self.used_w, self.used_h);
        for &i in order {
            let r = group[i];
            if r.w == 0 || r.h == 0 {
                continue;
            }
            if self.waste_map {
                if let Some((x, y)) = self.fill_hole(r.w, r.h) {
                    xy[i] = (x, y);
                    used_w = used_w.max(x + r.w);
                    used_h = used_h.max(y + r.h);
                    continue;
                }
            }
            // Within the soft width if it fits there, else anywhere in the atlas.
            let at = self
                .sky
                .find(r.w, r.h, self.soft, self.edge, min_waste)
                .or_else(|| self.sky.find(r.w, r.h, self.edge, self.edge, min_waste));
            let Some((seg, x, y)) = at else {
                self.sky.segs = saved;
                self.holes = saved_holes;
                return None;
            };
            if self.waste_map {
                // Segments below y under the rectangle become holes.
                for t in &self.sky.segs[seg..] {
                    if t.x >= x + r.w {
                        break;
                    }
                    if y - t.y >= self.min_h && (t.x + t.w).min(x + r.w) - t.x >= self.min_w {
                        let span = (t.x + t.w).min(x + r.w) - t.x;
                        self.holes.push((t.x, t.y, span, y - t.y));
                    }
                }
            }
            self.sky.place(seg, x, y + r.h, r.w);
            xy[i] = (x, y);
            used_w = used_w.max(x + r.w);
            used_h = used_h.max(y + r.h);
        }
        self.used_w = used_w;
        self.used_h = used_h;
        self.used_area += group.iter().map(|r| r.w as u64 * r.h as u64).sum::<u64>();
        Some(xy)
    }

    /// Best-short-side-fit hole for w × h; the rest of the hole split along its shorter leftover.
    fn fill_hole(&mut self, w: u32, h: u32) -> Option<(u32, u32)> {
        let mut best: Option<(u32, u32, usize)> = None;
        for (k, &(_, _, fw, fh)) in self.holes.iter().enumerate() {
            if fw >= w && fh >= h {
                let key = ((fw - w).min(fh - h), (fw - w).max(fh - h), k);
                if best.is_none_or(|b| (key.0, key.1) < (b.0, b.1)) {
                    best = Some(key);
                }
            }
        }
        let (_, _, k) = best?;
        let (x, y, fw, fh) = self.holes.swap_remove(k);
        let (right, below) = if fw - w < fh - h {
            ((x + w, y, fw - w, h), (x, y + h, fw, fh - h))
        } else {
            ((x + w, y, fw - w, fh), (x, y + h, w, fh - h))
        };
        for hole in [right, below] {
            if hole.2 >= self.min_w && hole.3 >= self.min_h {
                self.holes.push(hole);
            }
        }
        Some((x, y))
    }
}

/// A segment of the skyline: texels x..x + w are free from row y down.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Seg {
    x: u32,
    y: u32,
    w: u32,
}

/// Segments left to right, covering 0..edge, no two neighbours at the same y.
struct Skyline {
    segs: Vec<Seg>,
}

impl Skyline {
    fn new(edge: u32) -> Self {
        Self {
            segs: vec![Seg {
                x: 0,
                y: 0,
                w: edge,
            }],
        }
    }

    /// Where a w × h rectangle (w, h > 0) ends lowest (least y + h), then leftmost, within
    /// x + w ≤ `limit` and y + h ≤ `max_h`: (index of the segment it starts on, x, y).
    fn find(
        &self,
        w: u32,
        h: u32,
        limit: u32,
        max_h: u32,
        min_waste: bool,
    ) -> Option<(usize, u32, u32)> {
        if min_waste {
            return self.find_min_waste(w, h, limit, max_h);
        }
        let mut best: Option<(u32, usize, u32, u32)> = None; // (y + h, segment, x, y)
        for (i, s) in self.segs.iter().enumerate() {
            let x = s.x;
            if x + w > limit {
                break;
            }
            // The rectangle rests on the lowest-reaching segment under x..x + w.
            let bound = best.map_or(max_h, |b| (b.0 - 1).min(max_h));
            let mut y = 0;
            for t in &self.segs[i..] {
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

    fn find_min_waste(&self, w: u32, h: u32, limit: u32, max_h: u32) -> Option<(usize, u32, u32)> {
        let mut best: Option<(u64, u32, usize, u32, u32)> = None;
        for (i, s) in self.segs.iter().enumerate() {
            let x = s.x;
            if x + w > limit {
                break;
            }
            let mut y = 0;
            for t in &self.segs[i..] {
                if t.x >= x + w {
                    break;
                }
                y = y.max(t.y);
            }
            if y + h > max_h {
                continue;
            }
            let mut waste = 0u64;
            for t in &self.segs[i..] {
                if t.x >= x + w {
                    break;
                }
                let span = (t.x + t.w).min(x + w) - t.x;
                waste += (y - t.y) as u64 * span as u64;
            }
            let key = (waste, y + h, i, x, y);
            if best.is_none_or(|b| (key.0, key.1) < (b.0, b.1)) {
                best = Some(key);
            }
        }
        best.map(|(_, _, i, x, y)| (i, x, y))
    }

    /// Raise x..x + w (starting at segment `i`, whose x it is) to `top`.
    fn place(&mut self, i: usize, x: u32, top: u32, w: u32) {
        let end = x + w;
        // Segments i..j are covered whole; segment j (if any) is cut at `end`.
        let mut j = i;
        while j < self.segs.len() && self.segs[j].x + self.segs[j].w <= end {
            j += 1;
        }
        if j < self.segs.len() && self.segs[j].x < end {
            let s = &mut self.segs[j];
            s.w -= end - s.x;
            s.x = end;
        }
        self.segs.splice(i..j, [Seg { x, y: top, w }]);
        // Merge with neighbours at the same height.
        if i + 1 < self.segs.len() && self.segs[i + 1].y == top {
            self.segs[i].w += self.segs[i + 1].w;
            self.segs.remove(i + 1);
        }
        if i > 0 && self.segs[i - 1].y == top {
            self.segs[i - 1].w += self.segs[i].w;
            self.segs.remove(i);
        }
    }
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
