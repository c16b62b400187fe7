//! Shadow rays per second: this engine's visibility (`Occluder::clear`, as every stage calls it)
//! against obvhs's own traversal at its best — its compressed wide BVH built with its slow,
//! high-quality build over the scene's triangles in world space, any-hit queries that stop at
//! the first hit (`ray_traverse_miss`) and obvhs's own ray–triangle test — on one set of
//! segments, each timed on all of rayon's threads. The segments are link-like: from every
//! `stride`-th vertex (its normal) to the centroids of up to `per` triangles drawn at random
//! (a fixed seed) that face it and lie in front of it — the long, mostly blocked rays of a
//! gather in clutter. Prints each way's rays, seconds, rays per second and how often the two
//! answers differ (segments that graze an edge may: the engine pulls its ends off their
//! surfaces and pads its boxes).
//!
//!     cargo run --release --example ray_speed -- SCENE.gltf [stride] [per]

#[allow(dead_code)] // the luminaires' helpers are the other examples'
mod shared;

use glam::DVec3;
use luxbake::visibility::{Occluder, OccluderOptions};
use obvhs::{BvhBuildParams, cwbvh::builder::build_cwbvh_from_tris, ray::Ray, triangle::Triangle};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// A segment: its ends and their surfaces' normals.
type Segment = (DVec3, DVec3, DVec3, DVec3);

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .expect("usage: ray_speed SCENE.gltf [stride] [per]");
    let stride: usize = args.get(2).map_or(8, |s| s.parse().expect("stride"));
    let per: usize = args.get(3).map_or(256, |s| s.parse().expect("per"));
    let scene = shared::scene(path);
    let tris: Vec<([DVec3; 3], DVec3)> = (scene.surfaces.iter())
        .flat_map(|s| {
            s.triangles.iter().map(|t| {
                let c = t.map(|v| s.positions[v as usize]);
                (c, (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero())
            })
        })
        .filter(|(_, n)| *n != DVec3::ZERO)
        .collect();
    let segments = segments(&scene, &tris, stride, per);
    println!(
        "{path}: {} triangles, {} segments ({} a vertex at most, every {stride}th vertex)",
        tris.len(),
        segments.len(),
        per
    );

    let t = Instant::now();
    let occ = Occluder::build(&scene, OccluderOptions::default());
    println!(
        "engine: occluder built in {:.2} s",
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let engine: Vec<bool> = (segments.par_iter())
        .map(|&(a, na, b, nb)| occ.clear(a, na, b, nb))
        .collect();
    report("engine (Occluder::clear)", t.elapsed(), &engine, &engine);

    let t = Instant::now();
    let world: Vec<Triangle> = (tris.iter())
        .map(|(c, _)| Triangle {
            v0: c[0].as_vec3a(),
            v1: c[1].as_vec3a(),
            v2: c[2].as_vec3a(),
        })
        .collect();
    let mut core = Duration::ZERO;
    let bvh = build_cwbvh_from_tris(&world, BvhBuildParams::slow_build(), &mut core);
    println!("obvhs: CwBvh built in {:.2} s", t.elapsed().as_secs_f64());
    let eps = occ.epsilon;
    let t = Instant::now();
    let raw: Vec<bool> = (segments.par_iter())
        .map(|&(a, na, b, nb)| {
            let from = a + na * eps * na.dot(b - a).signum();
            let to = b + nb * eps * nb.dot(a - b).signum();
            let d = to - from;
            let len = d.length();
            let ray = Ray::new(
                from.as_vec3a(),
                (d / len).as_vec3a(),
                0.0,
                (len - eps) as f32,
            );
            bvh.ray_traverse_miss(ray, |r, id| {
                world[bvh.primitive_indices[id] as usize].intersect(r)
            })
        })
        .collect();
    report("obvhs (CwBvh, any hit)", t.elapsed(), &raw, &engine);
}

fn report(name: &str, took: Duration, answers: &[bool], engine: &[bool]) {
    let s = took.as_secs_f64();
    let clear = answers.iter().filter(|c| **c).count();
    let differ = answers.iter().zip(engine).filter(|(a, b)| a != b).count();
    println!(
        "{name}: {} rays in {s:.3} s = {:.2} M rays/s; clear {:.1} %; answers differing from the engine's: {differ}",
        answers.len(),
        answers.len() as f64 / s / 1e6,
        100.0 * clear as f64 / answers.len().max(1) as f64
    );
}

/// Link-like segments: from every `stride`-th vertex to the centroids of up to `per` random
/// triangles in front of it that face it (a fixed-seed generator: the same segments each run).
fn segments(
    scene: &luxbake::scene::Scene,
    tris: &[([DVec3; 3], DVec3)],
    stride: usize,
    per: usize,
) -> Vec<Segment> {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut out = Vec::new();
    for (p, n) in shared::vertices(scene).step_by(stride.max(1)) {
        let mut found = 0;
        for _ in 0..per * 8 {
            if found == per {
                break;
            }
            let (c, nc) = &tris[(next() % tris.len() as u64) as usize];
            let q = (c[0] + c[1] + c[2]) / 3.0;
            if n.dot(q - p) > 1e-6 && nc.dot(p - q) > 1e-6 {
                out.push((p, n, q, *nc));
                found += 1;
            }
        }
    }
    out
}
