//! What exact direct light at a scene's vertices costs with this engine's visibility, and the
//! least it could cost. At every vertex (every k-th with a stride), each luminaire whose
//! unshadowed light there is above zero is a pair that needs a visibility answer. The groups'
//! proofs ([`Groups::visit`] with [`Occluder::settle`], as the bake runs them) settle some pairs
//! without rays; every other pair is summed three ways, each timed on all of rayon's threads:
//! one shadow ray to the luminaire's centre (the least any per-pair answer costs), one ray per
//! near-field sub-source ([`DirectSource::illuminance_faces`] without its penumbra pass), and as the
//! bake sums it (the corner check and the penumbra pass too). Prints the pairs per vertex, what
//! the proofs settled, and each way's rays and wall seconds (finding the pairs and the proofs
//! are timed apart).
//!
//! The points can come from another file with the same geometry: the bake's output, whose
//! vertices are the bake's receivers (meshing adds vertices).
//!
//! With fractions f after the points, it also tries, one thread at a time on every 20th point, a
//! budget for the penumbra pass: pairs are summed over their sub-sources first; those the bake
//! spends more rays on get the bake's sum, in decreasing unshadowed light u, until the u of those
//! left is at most f × the vertex's light summed over sub-sources (each is off by at most its
//! u). Errors are relative to the bake's sum.
//!
//!     cargo run --release --example direct_floor -- SCENE.gltf [stride] [POINTS.glb] [f ...]

mod shared;

use glam::DVec3;
use luxbake::direct::bounds::ProfileBounds;
use luxbake::direct::groups::Known;
use luxbake::direct::sources::DirectSource;
use luxbake::visibility::{Occluder, OccluderOptions};
use rayon::prelude::*;
use std::time::Instant;

/// Vertices whose pairs are found, then traced, together (bounds the pairs held at once).
const BLOCK: usize = 8192;

/// What the proofs said of one vertex's reaching pairs, and the luminaires left to trace.
#[derive(Default)]
struct Pairs {
    seen: u64,
    hidden: u64,
    trace: Vec<usize>,
}

/// How a traced pair is summed: one ray to the luminaire's centre; one ray per near-field
/// sub-source ([`DirectSource::illuminance_faces`] without its penumbra pass); as the bake sums it.
#[derive(Clone, Copy, Debug)]
enum Way {
    Centre,
    SubSources,
    Bake,
}

const WAYS: [Way; 3] = [Way::Centre, Way::SubSources, Way::Bake];

/// Source `s`'s light (lx) at `p` on the plane of unit normal `n`: `known` and `soft` as
/// [`DirectSource::illuminance_faces`] takes them.
fn light(
    s: &DirectSource,
    occ: &Occluder,
    (p, n): (DVec3, DVec3),
    known: Known,
    soft: bool,
) -> f64 {
    let mut e = [0.0];
    s.illuminance_faces(occ, p, &[n], &mut e, (known, soft));
    e[0]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: direct_floor SCENE [stride] [POINTS] [f ...]");
    let stride: usize = args.next().map_or(1, |x| x.parse().expect("stride"));
    let points_from = args.next();
    let fractions: Vec<f64> = args.map(|x| x.parse().expect("f")).collect();
    let t0 = Instant::now();
    let scene = shared::scene(&path);
    let occ = Occluder::build(&scene, OccluderOptions::default());
    let bounds = ProfileBounds::new(&scene);
    let sources = shared::luminaires(&scene, &bounds);
    let groups = DirectSource::groups(&sources);
    let centres: Vec<DVec3> = (sources.iter())
        .map(|s| match s {
            DirectSource::Luminaire(l) => l.position,
            _ => unreachable!("only luminaires"),
        })
        .collect();
    let baked = points_from.map(|f| shared::scene(&f));
    let points: Vec<(DVec3, DVec3)> = shared::vertices(baked.as_ref().unwrap_or(&scene))
        .step_by(stride)
        .collect();
    println!(
        "{} luminaires, {} vertices (stride {stride}), {} threads; loaded in {:.1} s",
        sources.len(),
        points.len(),
        rayon::current_num_threads(),
        t0.elapsed().as_secs_f64()
    );
    let (mut seen, mut hidden, mut traced, mut clear) = (0u64, 0u64, 0u64, 0u64);
    let (mut find_s, mut seconds, mut rays) = (0.0, [0.0; 3], [0u64; 3]);
    for block in points.chunks(BLOCK) {
        let t = Instant::now();
        let pairs: Vec<Pairs> = block
            .par_iter()
            .map(|&(p, n)| {
                let starts = [p + n * occ.epsilon];
                let settle = |lo: DVec3, hi: DVec3, _: DVec3| occ.settle(&starts, lo, hi);
                let mut out = Pairs::default();
                groups.visit(p, &[n], settle, |k, known| {
                    if light(&sources[k], &occ, (p, n), Known::Seen, true) <= 0.0 {
                        return;
                    }
                    match known {
                        Known::Seen => out.seen += 1,
                        Known::Hidden => out.hidden += 1,
                        Known::Trace => out.trace.push(k),
                    }
                });
                out
            })
            .collect();
        find_s += t.elapsed().as_secs_f64();
        for (w, way) in WAYS.into_iter().enumerate() {
            let (t, before) = (Instant::now(), occ.rays_traced());
            let light: f64 = block
                .par_iter()
                .zip(&pairs)
                .map(|(&(p, n), v)| {
                    (v.trace.iter())
                        .map(|&k| match way {
                            Way::Centre => occ.clear(p, n, centres[k], DVec3::ZERO) as u8 as f64,
                            Way::SubSources => {
                                light(&sources[k], &occ, (p, n), Known::Trace, false)
                            }
                            Way::Bake => light(&sources[k], &occ, (p, n), Known::Trace, true),
                        })
                        .sum::<f64>()
                })
                .sum();
            seconds[w] += t.elapsed().as_secs_f64();
            rays[w] += occ.rays_traced() - before;
            if let Way::Centre = way {
                clear += light as u64;
            }
        }
        for v in &pairs {
            seen += v.seen;
            hidden += v.hidden;
            traced += v.trace.len() as u64;
        }
    }
    let n = points.len().max(1) as f64;
    let reaching = seen + hidden + traced;
    println!(
        "pairs reaching a vertex: {reaching} ({:.1} per vertex); settled by the groups' proofs: \
         {seen} seen + {hidden} hidden; left to trace: {traced} ({:.1} per vertex, {clear} clear \
         to the centre); finding them: {find_s:.2} s",
        reaching as f64 / n,
        traced as f64 / n
    );
    for (w, way) in WAYS.into_iter().enumerate() {
        println!(
            "{way:?}: {} rays ({:.1} per vertex), {:.2} s wall ({:.2} M rays/s)",
            rays[w],
            rays[w] as f64 / n,
            seconds[w],
            rays[w] as f64 / seconds[w].max(1e-9) / 1e6
        );
    }
    if !fractions.is_empty() {
        penumbra_budget(&occ, &sources, &points, &fractions);
    }
}

/// One traced pair at one vertex: unshadowed light, summed over sub-sources, as the bake sums
/// it, and the rays of the last two.
struct Pair {
    u: f64,
    sub: f64,
    bake: f64,
    sub_rays: u64,
    bake_rays: u64,
}

fn penumbra_budget(
    occ: &Occluder,
    sources: &[DirectSource],
    points: &[(DVec3, DVec3)],
    fs: &[f64],
) {
    let mut rows: Vec<Vec<Pair>> = Vec::new();
    for &(p, n) in points.iter().step_by(20) {
        let mut row = Vec::new();
        for s in sources {
            let u = light(s, occ, (p, n), Known::Seen, true);
            if u <= 0.0 {
                continue;
            }
            let r0 = occ.rays_traced();
            let sub = light(s, occ, (p, n), Known::Trace, false);
            let r1 = occ.rays_traced();
            let bake = light(s, occ, (p, n), Known::Trace, true);
            let r2 = occ.rays_traced();
            row.push(Pair {
                u,
                sub,
                bake,
                sub_rays: r1 - r0,
                bake_rays: r2 - r1,
            });
        }
        rows.push(row);
    }
    let n = rows.len().max(1) as f64;
    let all = |f: &dyn Fn(&Pair) -> u64| rows.iter().flatten().map(f).sum::<u64>() as f64 / n;
    println!(
        "penumbra budget on {} vertices: bake {:.1} rays a vertex, sub-sources only {:.1}; \
         pairs the bake integrates again: {:.1} a vertex",
        rows.len(),
        all(&|q| q.bake_rays),
        all(&|q| q.sub_rays),
        all(&|q| (q.bake_rays > q.sub_rays) as u64)
    );
    for &f in fs {
        let (mut rays, mut errors) = (0u64, Vec::new());
        for row in &rows {
            let light: f64 = row.iter().map(|q| q.sub).sum();
            let mut again: Vec<&Pair> = row.iter().filter(|q| q.bake_rays > q.sub_rays).collect();
            again.sort_by(|a, b| b.u.total_cmp(&a.u));
            let mut left: f64 = again.iter().map(|q| q.u).sum();
            let mut sum: f64 = row.iter().map(|q| q.sub).sum();
            rays += row.iter().map(|q| q.sub_rays).sum::<u64>();
            for q in again {
                if left <= f * light {
                    break;
                }
                left -= q.u;
                sum += q.bake - q.sub;
                // The bake's pass over it: its sub-sources again, the corners, the penumbra.
                rays += q.bake_rays - q.sub_rays;
            }
            let exact: f64 = row.iter().map(|q| q.bake).sum();
            if exact > 0.0 {
                errors.push((sum - exact).abs() / exact);
            }
        }
        errors.sort_by(|a, b| a.total_cmp(b));
        let at = |q: f64| errors[((errors.len() as f64 - 1.0) * q) as usize];
        let mean = errors.iter().sum::<f64>() / errors.len().max(1) as f64;
        println!(
            "f = {f}: {:.1} rays a vertex; error against the bake's sum, {} lit vertices: \
             mean {mean:.2e}, p95 {:.2e}, max {:.2e}",
            rays as f64 / n,
            errors.len(),
            at(0.95),
            at(1.0)
        );
    }
}
