//! Chart packers for lightmap atlases, compared on the inputs of issue 24: luxbake's skyline
//! (`src/lightmap/pack.rs`) and etagere, guillotiere, crunch, rectangle-pack driven to the same
//! rules (groups whole in one atlas, no rotation, first atlas that fits, then trimmed to the
//! extent used, edges multiples of 4). Every result is checked (inside, no overlap, groups whole).
//!
//! `pack-bench` runs every packer on every input, each in a child process with a time limit, and
//! prints a Markdown table; `pack-bench PACKER INPUT` runs one and prints one line;
//! `pack-bench seeds P1,P2,… INPUT N` prints each packer's efficiency over seeds 1..=N;
//! `pack-bench info INPUT` describes an input (also `e-mixed`, `f-clutter-4k`: larger ones).

#[path = "../../../src/lightmap/pack.rs"]
#[allow(dead_code)]
mod pack;

use pack::{Packing, Place, Rect, TooBig};
use std::collections::BTreeMap;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const PACKERS: &[&str] = &[
    "skyline",
    "etagere-0.2",
    "etagere-0.3",
    "guillotiere-0.6",
    "guillotiere-0.7",
    "guillotiere-0.7+grow",
    "crunch-0.5",
    "rectangle-pack-0.4",
];
const INPUTS: &[&str] = &["a-room", "b-clutter", "c-tiny", "d-floor"];
/// Wall-time limit of one child (all its repeats).
const LIMIT: Duration = Duration::from_secs(120);

/// Deterministic sequence (64-bit LCG, Knuth's constants).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + ((self.next() * (hi - lo + 1) as f64) as u32).min(hi - lo)
    }
    /// Log-uniform in lo..=hi: as many charts of 4–8 texels as of 200–400.
    fn log(&mut self, lo: u32, hi: u32) -> u32 {
        let (a, b) = ((lo as f64).ln(), ((hi + 1) as f64).ln());
        ((a + self.next() * (b - a)).exp() as u32).clamp(lo, hi)
    }
}

fn clutter(rng: &mut Lcg, n: usize) -> Vec<Vec<Rect>> {
    (0..n)
        .map(|_| {
            let k = rng.int(1, 20);
            (0..k)
                .map(|_| Rect {
                    w: rng.log(3, 40),
                    h: rng.log(3, 40),
                })
                .collect()
        })
        .collect()
}

/// (groups, max_edge) of an input.
fn input(name: &str) -> (Vec<Vec<Rect>>, u32) {
    input_seeded(name, 24)
}

/// An input drawn from another seed of the same sequence.
fn input_seeded(name: &str, seed: u64) -> (Vec<Vec<Rect>>, u32) {
    let mut rng = Lcg(seed);
    let groups = match name {
        // A room: 30 surfaces of 1–6 charts, 4 × 4 to 400 × 300 (walls, floor, desks).
        "a-room" => (0..30)
            .map(|_| {
                let k = rng.int(1, 6);
                (0..k)
                    .map(|_| Rect {
                        w: rng.log(4, 400),
                        h: rng.log(4, 300),
                    })
                    .collect()
            })
            .collect(),
        // Clutter: 2000 objects of 1–20 charts, 3 × 3 to 40 × 40.
        "b-clutter" => clutter(&mut rng, 2000),
        // One tessellated object split per triangle: 50 000 charts of 3 × 3 to 8 × 8.
        "c-tiny" => vec![
            (0..50_000)
                .map(|_| Rect {
                    w: rng.int(3, 8),
                    h: rng.int(3, 8),
                })
                .collect(),
        ],
        // A big floor (1900 × 1900) first, then 500 clutter objects.
        "d-floor" => {
            let mut g = vec![vec![Rect { w: 1900, h: 1900 }]];
            g.extend(clutter(&mut rng, 500));
            g
        }
        // Stress, not in the default table: 50 000 charts of 3–40 in one group, 4096² atlases.
        "e-mixed" => {
            let g: Vec<Vec<Rect>> = clutter(&mut rng, 5000);
            return (vec![g.into_iter().flatten().collect()], 4096);
        }
        // Stress, not in the default table: 10 000 clutter objects, 4096² atlases.
        "f-clutter-4k" => return (clutter(&mut rng, 10_000), 4096),
        _ => panic!("unknown input {name}"),
    };
    (groups, 2048)
}

/// Rectangle indices of a group, tallest first (then widest, then input order): the order every
/// one-at-a-time allocator gets, as the skyline sorts its own.
fn by_height(group: &[Rect]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..group.len()).collect();
    order.sort_by_key(|&i| {
        (
            std::cmp::Reverse(group[i].h),
            std::cmp::Reverse(group[i].w),
            i,
        )
    });
    order
}

fn trim(v: u32) -> u32 {
    v.div_ceil(4).max(1) * 4
}

/// An allocator that places one rectangle at a time and can free it again.
trait Dynamic {
    type Id: Copy;
    fn new(edge: u32) -> Self;
    fn alloc(&mut self, w: u32, h: u32) -> Option<(u32, u32, Self::Id)>;
    fn free(&mut self, id: Self::Id);
}

macro_rules! euclid_allocator {
    ($name:ident, $krate:ident) => {
        struct $name($krate::AtlasAllocator);
        impl Dynamic for $name {
            type Id = $krate::AllocId;
            fn new(edge: u32) -> Self {
                Self($krate::AtlasAllocator::new($krate::size2(
                    edge as i32,
                    edge as i32,
                )))
            }
            fn alloc(&mut self, w: u32, h: u32) -> Option<(u32, u32, Self::Id)> {
                let a = self.0.allocate($krate::size2(w as i32, h as i32))?;
                Some((a.rectangle.min.x as u32, a.rectangle.min.y as u32, a.id))
            }
            fn free(&mut self, id: Self::Id) {
                self.0.deallocate(id)
            }
        }
    };
}
euclid_allocator!(Etagere02, etagere02);
euclid_allocator!(Etagere03, etagere03);
euclid_allocator!(Guillotiere06, guillotiere06);
euclid_allocator!(Guillotiere07, guillotiere07);

/// Groups in order, each to the first atlas that takes all of it (its rectangles freed again
/// when one does not fit), else to a new atlas.
fn drive<A: Dynamic>(groups: &[Vec<Rect>], edge: u32) -> Result<Packing, TooBig> {
    let mut atlases: Vec<(A, u32, u32)> = Vec::new();
    let mut places = Vec::new();
    for (gi, group) in groups.iter().enumerate() {
        let order = by_height(group);
        let attempt = |a: &mut A| -> Option<Vec<(u32, u32)>> {
            let mut xy = vec![(0, 0); group.len()];
            let mut ids = Vec::new();
            for &i in &order {
                match a.alloc(group[i].w, group[i].h) {
                    Some((x, y, id)) => {
                        xy[i] = (x, y);
                        ids.push(id);
                    }
                    None => {
                        for id in ids {
                            a.free(id);
                        }
                        return None;
                    }
                }
            }
            Some(xy)
        };
        let mut found = None;
        for (ai, (a, _, _)) in atlases.iter_mut().enumerate() {
            if let Some(xy) = attempt(a) {
                found = Some((ai, xy));
                break;
            }
        }
        let (ai, xy) = match found {
            Some(f) => f,
            None => {
                let mut a = A::new(edge);
                let xy = attempt(&mut a).ok_or(TooBig { group: gi })?;
                atlases.push((a, 0, 0));
                (atlases.len() - 1, xy)
            }
        };
        let (_, uw, uh) = &mut atlases[ai];
        for (r, &(x, y)) in group.iter().zip(&xy) {
            *uw = (*uw).max(x + r.w);
            *uh = (*uh).max(y + r.h);
        }
        places.push(xy.iter().map(|&(x, y)| Place { atlas: ai, x, y }).collect());
    }
    Ok(Packing {
        atlases: atlases
            .iter()
            .map(|&(_, w, h)| (trim(w), trim(h)))
            .collect(),
        places,
    })
}

/// guillotiere with atlases that start at √(remaining area / 0.85) square and grow by 1/4 up to
/// `edge` when a group does not fit (so that trimming has something to trim).
fn guillotiere_grow(groups: &[Vec<Rect>], edge: u32) -> Result<Packing, TooBig> {
    use guillotiere07::{AtlasAllocator, size2};
    let mut remaining = vec![0u64; groups.len() + 1];
    for (g, group) in groups.iter().enumerate().rev() {
        remaining[g] =
            remaining[g + 1] + group.iter().map(|r| r.w as u64 * r.h as u64).sum::<u64>();
    }
    let attempt =
        |a: &mut AtlasAllocator, group: &[Rect], order: &[usize]| -> Option<Vec<(u32, u32)>> {
            let mut xy = vec![(0, 0); group.len()];
            let mut ids = Vec::new();
            for &i in order {
                match a.allocate(size2(group[i].w as i32, group[i].h as i32)) {
                    Some(al) => {
                        xy[i] = (al.rectangle.min.x as u32, al.rectangle.min.y as u32);
                        ids.push(al.id);
                    }
                    None => {
                        for id in ids {
                            a.deallocate(id);
                        }
                        return None;
                    }
                }
            }
            Some(xy)
        };
    let mut atlases: Vec<(AtlasAllocator, u32, u32, u32)> = Vec::new(); // allocator, side, used w, h
    let mut places = Vec::new();
    for (gi, group) in groups.iter().enumerate() {
        let order = by_height(group);
        let mut found = None;
        'atlases: for (ai, (a, side, _, _)) in atlases.iter_mut().enumerate() {
            loop {
                if let Some(xy) = attempt(a, group, &order) {
                    found = Some((ai, xy));
                    break 'atlases;
                }
                if *side >= edge {
                    break;
                }
                *side = (*side + *side / 4).div_ceil(4).saturating_mul(4).min(edge);
                a.grow(size2(*side as i32, *side as i32));
            }
        }
        let (ai, xy) = match found {
            Some(f) => f,
            None => {
                let big = group.iter().map(|r| r.w.max(r.h)).max().unwrap_or(1);
                let mut side = (((remaining[gi] as f64 / 0.85).sqrt().ceil() as u32).div_ceil(4)
                    * 4)
                .max(big)
                .min(edge);
                let mut a = AtlasAllocator::new(size2(side as i32, side as i32));
                let xy = loop {
                    if let Some(xy) = attempt(&mut a, group, &order) {
                        break xy;
                    }
                    if side >= edge {
                        return Err(TooBig { group: gi });
                    }
                    side = (side + side / 4).div_ceil(4).saturating_mul(4).min(edge);
                    a.grow(size2(side as i32, side as i32));
                };
                atlases.push((a, side, 0, 0));
                (atlases.len() - 1, xy)
            }
        };
        let (_, _, uw, uh) = &mut atlases[ai];
        for (r, &(x, y)) in group.iter().zip(&xy) {
            *uw = (*uw).max(x + r.w);
            *uh = (*uh).max(y + r.h);
        }
        places.push(xy.iter().map(|&(x, y)| Place { atlas: ai, x, y }).collect());
    }
    Ok(Packing {
        atlases: atlases
            .iter()
            .map(|&(_, _, w, h)| (trim(w), trim(h)))
            .collect(),
        places,
    })
}

/// crunch packs a whole set at once: each atlas takes the longest run of the remaining groups
/// that packs into it (galloping, then bisection, on the run's length).
fn crunch_pack(groups: &[Vec<Rect>], edge: u32) -> Result<Packing, TooBig> {
    let try_run = |from: usize, to: usize| -> Option<Vec<(usize, usize, u32, u32)>> {
        let items = (from..to).flat_map(|g| {
            groups[g].iter().enumerate().map(move |(i, r)| {
                crunch::Item::new((g, i), r.w as usize, r.h as usize, crunch::Rotation::None)
            })
        });
        let packed =
            crunch::pack(crunch::Rect::of_size(edge as usize, edge as usize), items).ok()?;
        Some(
            packed
                .into_iter()
                .map(|p| (p.data.0, p.data.1, p.rect.x as u32, p.rect.y as u32))
                .collect(),
        )
    };
    let mut places: Vec<Vec<Place>> = groups
        .iter()
        .map(|g| {
            vec![
                Place {
                    atlas: 0,
                    x: 0,
                    y: 0
                };
                g.len()
            ]
        })
        .collect();
    let mut atlases = Vec::new();
    let mut from = 0;
    while from < groups.len() {
        // Longest n with groups[from..from + n] packing: gallop 1, 2, 4, … then bisect.
        let Some(mut best) = try_run(from, from + 1) else {
            return Err(TooBig { group: from });
        };
        let (mut lo, mut hi) = (1, None);
        let mut n = 2;
        while hi.is_none() {
            let m = n.min(groups.len() - from);
            match try_run(from, from + m) {
                Some(p) => {
                    best = p;
                    lo = m;
                    if m == groups.len() - from {
                        break;
                    }
                    n *= 2;
                }
                None => hi = Some(m),
            }
        }
        if let Some(mut hi) = hi {
            while hi - lo > 1 {
                let mid = (lo + hi) / 2;
                match try_run(from, from + mid) {
                    Some(p) => {
                        best = p;
                        lo = mid;
                    }
                    None => hi = mid,
                }
            }
        }
        let ai = atlases.len();
        let (mut uw, mut uh) = (0, 0);
        for (g, i, x, y) in best {
            places[g][i] = Place { atlas: ai, x, y };
            uw = uw.max(x + groups[g][i].w);
            uh = uh.max(y + groups[g][i].h);
        }
        atlases.push((trim(uw), trim(uh)));
        from += lo;
    }
    Ok(Packing { atlases, places })
}

/// rectangle-pack places grouped rectangles into a given set of bins: start with as many
/// `edge`² bins as the area needs and add one until everything fits.
fn rectangle_pack(groups: &[Vec<Rect>], edge: u32) -> Result<Packing, TooBig> {
    use rectangle_pack::{GroupedRectsToPlace, RectToInsert, TargetBin};
    let mut rects: GroupedRectsToPlace<(usize, usize), usize> = GroupedRectsToPlace::new();
    for (g, group) in groups.iter().enumerate() {
        for &i in &by_height(group) {
            let r = group[i];
            rects.push_rect((g, i), Some(vec![g]), RectToInsert::new(r.w, r.h, 1));
        }
    }
    let area: u64 = groups
        .iter()
        .flatten()
        .map(|r| r.w as u64 * r.h as u64)
        .sum();
    let mut bins = area.div_ceil(edge as u64 * edge as u64).max(1) as usize;
    loop {
        let mut targets: BTreeMap<usize, TargetBin> = (0..bins)
            .map(|b| (b, TargetBin::new(edge, edge, 1)))
            .collect();
        match rectangle_pack::pack_rects(
            &rects,
            &mut targets,
            &rectangle_pack::volume_heuristic,
            &rectangle_pack::contains_smallest_box,
        ) {
            Ok(ok) => {
                let mut places: Vec<Vec<Place>> = groups
                    .iter()
                    .map(|g| {
                        vec![
                            Place {
                                atlas: 0,
                                x: 0,
                                y: 0
                            };
                            g.len()
                        ]
                    })
                    .collect();
                let mut used = vec![(0u32, 0u32); bins];
                for (&(g, i), (bin, loc)) in ok.packed_locations() {
                    places[g][i] = Place {
                        atlas: *bin,
                        x: loc.x(),
                        y: loc.y(),
                    };
                    used[*bin].0 = used[*bin].0.max(loc.x() + loc.width());
                    used[*bin].1 = used[*bin].1.max(loc.y() + loc.height());
                }
                // Bins left empty are dropped; the rest renumbered in order.
                let keep: Vec<usize> = (0..bins).filter(|&b| used[b] != (0, 0)).collect();
                let renum: BTreeMap<usize, usize> =
                    keep.iter().enumerate().map(|(n, &b)| (b, n)).collect();
                for p in places.iter_mut().flatten() {
                    p.atlas = renum[&p.atlas];
                }
                let atlases = keep
                    .iter()
                    .map(|&b| (trim(used[b].0), trim(used[b].1)))
                    .collect();
                return Ok(Packing { atlases, places });
            }
            Err(_) if bins < 64 => bins += 1,
            Err(_) => return Err(TooBig { group: 0 }),
        }
    }
}

fn run(packer: &str, groups: &[Vec<Rect>], edge: u32) -> Result<Packing, TooBig> {
    match packer {
        "skyline" => pack::pack(groups, edge),
        "etagere-0.2" => drive::<Etagere02>(groups, edge),
        "etagere-0.3" => drive::<Etagere03>(groups, edge),
        "guillotiere-0.6" => drive::<Guillotiere06>(groups, edge),
        "guillotiere-0.7" => drive::<Guillotiere07>(groups, edge),
        "guillotiere-0.7+grow" => guillotiere_grow(groups, edge),
        "crunch-0.5" => crunch_pack(groups, edge),
        "rectangle-pack-0.4" => rectangle_pack(groups, edge),
        _ => panic!("unknown packer {packer}"),
    }
}

/// Panics unless the packing keeps every rule.
fn check(groups: &[Vec<Rect>], edge: u32, p: &Packing) {
    assert_eq!(p.places.len(), groups.len());
    for &(w, h) in &p.atlases {
        assert!(
            w % 4 == 0 && h % 4 == 0 && w <= edge && h <= edge,
            "atlas {w}×{h}"
        );
    }
    let mut per: Vec<Vec<(u32, u32, u32, u32)>> = vec![Vec::new(); p.atlases.len()];
    for (g, (group, places)) in groups.iter().zip(&p.places).enumerate() {
        assert_eq!(group.len(), places.len());
        assert!(
            places.iter().all(|q| q.atlas == places[0].atlas),
            "group {g} split"
        );
        for (r, q) in group.iter().zip(places) {
            let (aw, ah) = p.atlases[q.atlas];
            assert!(
                q.x + r.w <= aw && q.y + r.h <= ah,
                "group {g}: {r:?} at {q:?} outside"
            );
            per[q.atlas].push((q.x, q.y, r.w, r.h));
        }
    }
    for rs in &mut per {
        rs.sort();
        for (i, a) in rs.iter().enumerate() {
            for b in &rs[i + 1..] {
                if b.0 >= a.0 + a.2 {
                    break;
                }
                assert!(b.1 >= a.1 + a.3 || a.1 >= b.1 + b.3, "{a:?} overlaps {b:?}");
            }
        }
    }
}

/// One packer on one input: repeats (at least 3, up to ~2 s) and prints
/// `atlases efficiency median_ms min_ms sizes`.
fn one(packer: &str, name: &str) {
    let (groups, edge) = input(name);
    let used: u64 = groups
        .iter()
        .flatten()
        .map(|r| r.w as u64 * r.h as u64)
        .sum();
    let mut times = Vec::new();
    let start = Instant::now();
    let mut first: Option<Packing> = None;
    while times.len() < 3 || (start.elapsed() < Duration::from_secs(2) && times.len() < 50) {
        let t = Instant::now();
        let p = run(packer, &groups, edge);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        let p = match p {
            Ok(p) => p,
            Err(e) => {
                println!("TooBig {}", e.group);
                return;
            }
        };
        match &first {
            None => {
                check(&groups, edge, &p);
                first = Some(p);
            }
            Some(f) => assert!(*f == p, "{packer} not deterministic on {name}"),
        }
    }
    let p = first.unwrap();
    let area: u64 = p.atlases.iter().map(|&(w, h)| w as u64 * h as u64).sum();
    times.sort_by(f64::total_cmp);
    let sizes: Vec<String> = p.atlases.iter().map(|(w, h)| format!("{w}×{h}")).collect();
    println!(
        "{} {:.4} {:.3} {:.3} {}",
        p.atlases.len(),
        used as f64 / area as f64,
        times[times.len() / 2],
        times[0],
        sizes.join(",")
    );
}

/// Efficiency of packers over seeds 1..=n of one input: mean, least, most, and atlas counts.
fn seeds(packers: &[&str], name: &str, n: u64) {
    println!("\n### {name}, seeds 1–{n}\n");
    println!(
        "| packer | efficiency mean | least | most | atlases (least–most) | atlases, all seeds |"
    );
    println!("| --- | ---: | ---: | ---: | --- | ---: |");
    for packer in packers {
        let mut effs = Vec::new();
        let mut counts = Vec::new();
        for seed in 1..=n {
            let (groups, edge) = input_seeded(name, seed);
            let p = run(packer, &groups, edge).expect("fits");
            check(&groups, edge, &p);
            let used: u64 = groups
                .iter()
                .flatten()
                .map(|r| r.w as u64 * r.h as u64)
                .sum();
            let area: u64 = p.atlases.iter().map(|&(w, h)| w as u64 * h as u64).sum();
            effs.push(used as f64 / area as f64);
            counts.push(p.atlases.len());
        }
        let mean = effs.iter().sum::<f64>() / effs.len() as f64;
        let (lo, hi) = (
            effs.iter().cloned().fold(1.0, f64::min),
            effs.iter().cloned().fold(0.0, f64::max),
        );
        println!(
            "| {packer} | {:.1} % | {:.1} % | {:.1} % | {}–{} | {} |",
            mean * 100.0,
            lo * 100.0,
            hi * 100.0,
            counts.iter().min().unwrap(),
            counts.iter().max().unwrap(),
            counts.iter().sum::<usize>()
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 3 && args[1] == "info" {
        let (groups, edge) = input(&args[2]);
        let n: usize = groups.iter().map(Vec::len).sum();
        let area: u64 = groups
            .iter()
            .flatten()
            .map(|r| r.w as u64 * r.h as u64)
            .sum();
        println!(
            "{} groups, {n} rectangles, {:.2} Mtexel, max_edge {edge}",
            groups.len(),
            area as f64 / 1e6
        );
        return;
    }
    if args.len() == 5 && args[1] == "seeds" {
        let packers: Vec<&str> = args[2].split(',').collect();
        seeds(&packers, &args[3], args[4].parse().unwrap());
        return;
    }
    if args.len() == 3 {
        one(&args[1], &args[2]);
        return;
    }
    let packers: Vec<&str> = match args.get(1) {
        Some(list) => list.split(',').collect(),
        None => PACKERS.to_vec(),
    };
    let exe = std::env::current_exe().unwrap();
    for name in INPUTS {
        let (groups, edge) = input(name);
        let n: usize = groups.iter().map(Vec::len).sum();
        let area: u64 = groups
            .iter()
            .flatten()
            .map(|r| r.w as u64 * r.h as u64)
            .sum();
        println!(
            "\n### {name}: {} groups, {n} rectangles, {:.2} Mtexel, max_edge {edge}\n",
            groups.len(),
            area as f64 / 1e6
        );
        println!("| packer | atlases | efficiency | ms (median) | ms (min) | atlas sizes |");
        println!("| --- | ---: | ---: | ---: | ---: | --- |");
        for packer in &packers {
            let mut child = Command::new(&exe)
                .args([packer, name])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap();
            let t = Instant::now();
            let status = loop {
                if let Some(s) = child.try_wait().unwrap() {
                    break Some(s);
                }
                if t.elapsed() > LIMIT {
                    child.kill().unwrap();
                    child.wait().unwrap();
                    break None;
                }
                std::thread::sleep(Duration::from_millis(20));
            };
            let out = child.wait_with_output().unwrap();
            let line = String::from_utf8_lossy(&out.stdout).trim().to_string();
            match status {
                None => println!(
                    "| {packer} | – | – | > {} s | | killed after {} s |",
                    LIMIT.as_secs(),
                    LIMIT.as_secs()
                ),
                Some(s) if !s.success() => {
                    let err = String::from_utf8_lossy(&out.stderr);
                    let msg = err
                        .lines()
                        .find(|l| {
                            l.contains("panicked") || l.contains("overlap") || l.contains("outside")
                        })
                        .unwrap_or("failed");
                    println!("| {packer} | – | – | – | | failed: {} |", msg.trim());
                    eprintln!("{err}");
                }
                Some(_) if line.starts_with("TooBig") => {
                    println!("| {packer} | – | – | – | | {line} |")
                }
                Some(_) => {
                    let f: Vec<&str> = line.split(' ').collect();
                    let eff: f64 = f[1].parse().unwrap();
                    println!(
                        "| {packer} | {} | {:.1} % | {} | {} | {} |",
                        f[0],
                        eff * 100.0,
                        f[2],
                        f[3],
                        f[4]
                    );
                }
            }
        }
    }
}
