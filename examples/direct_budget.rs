//! What the direct-light budget (`direct::cut`, `--direct-budget`) saves and costs at a scene's
//! vertices: the luminaires' direct light at every k-th vertex (facing its normal) summed as
//! the bake sums it (`Cut::run` with `AtPoint`), at budget 0 (`--exact-direct`) and at each
//! budget given, timed on all of rayon's threads. Prints wall seconds and rays per budget, and
//! each budget's error against budget 0: mean, the 99th percentile and the largest relative
//! error over vertices with light (> 1 lx), and the mean's change.
//!
//!     cargo run --release --example direct_budget -- SCENE.gltf [stride] [b ...]

mod shared;

use glam::DVec3;
use luxbake::direct::bounds::ProfileBounds;
use luxbake::direct::cut::Cut;
use luxbake::direct::sources::DirectSource;
use luxbake::direct::targets::AtPoint;
use luxbake::visibility::{Occluder, OccluderOptions};
use rayon::prelude::*;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: direct_budget SCENE [stride] [b ...]");
    let stride: usize = args.next().map_or(1, |x| x.parse().expect("stride"));
    let budgets: Vec<f64> = args.map(|x| x.parse().expect("b")).collect();
    let scene = shared::scene(&path);
    let occ = Occluder::build(&scene, OccluderOptions::default());
    let bounds = ProfileBounds::new(&scene);
    let sources = shared::luminaires(&scene, &bounds);
    let groups = DirectSource::groups(&sources);
    let points: Vec<(DVec3, DVec3)> = shared::vertices(&scene).step_by(stride).collect();
    println!(
        "{} luminaires, {} vertices (stride {stride}), {} threads",
        sources.len(),
        points.len(),
        rayon::current_num_threads()
    );
    let sum = |b: f64| {
        let cut = Cut::new(&sources, &groups, 0.0).with_budget(b);
        let (t, before) = (Instant::now(), occ.rays_traced());
        let light: Vec<f64> = points
            .par_iter()
            .map(|&(p, n)| {
                let starts = [p + n * occ.epsilon];
                let settle = |lo: DVec3, hi: DVec3, _: DVec3| occ.settle(&starts, lo, hi);
                let normals = [n];
                let mut at = AtPoint::new(&sources, &occ, p, &normals);
                cut.run(&sources, &groups, p, &normals, settle, &mut at);
                at.luma[0]
            })
            .collect();
        let rays = occ.rays_traced() - before;
        (light, t.elapsed().as_secs_f64(), rays)
    };
    let (exact, seconds, rays) = sum(0.0);
    println!("budget 0: {seconds:.2} s, {:.1} M rays", rays as f64 / 1e6);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    for b in budgets {
        let (light, seconds_b, rays_b) = sum(b);
        let mut rel: Vec<f64> = (exact.iter().zip(&light))
            .filter(|(e, _)| **e > 1.0)
            .map(|(e, l)| (l - e).abs() / e)
            .collect();
        rel.sort_by(f64::total_cmp);
        let n = rel.len();
        println!(
            "budget {b}: {seconds_b:.2} s ({:.3}×), {:.1} M rays ({:.3}×); over {n} lit \
             vertices: mean |error| {:.2e}, p99 {:.2e}, max {:.2e}; mean {:+.4} %",
            seconds_b / seconds,
            rays_b as f64 / 1e6,
            rays_b as f64 / rays as f64,
            mean(&rel),
            rel[(n * 99) / 100],
            rel[n - 1],
            (mean(&light) / mean(&exact) - 1.0) * 100.0
        );
    }
}
