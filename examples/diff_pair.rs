//! Writes the two 10⁶-vertex outputs `bench/diff_timing.py` times `bake diff` on: a 1000 × 1000
//! vertex floor (20 × 20 m at y = 0, glTF +Y up) with smoothly varying values, as `a.glb` and
//! `b.glb` in the folder given, B 1 % higher than A on one vertex in 1000.
//!
//!     cargo run --release --example diff_pair -- DIR

use glam::DVec3;
use luxbake::export::{self, ExportOptions};
use luxbake::fixtures::SceneBuilder;
use luxbake::result::{BakeResult, BakedSurface, Side};
use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).expect("usage: diff_pair DIR"));
    std::fs::create_dir_all(&dir).expect("cannot create the output folder");
    let n = 1000usize;
    let mut b = SceneBuilder::new();
    let grey = b.material("grey", 0.5);
    b.floor("floor", 10.0, 0.0, grey);
    let scene = b.build();
    let s = 20.0 / (n - 1) as f64;
    let mut positions = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            positions.push(DVec3::new(-10.0 + s * j as f64, 0.0, -10.0 + s * i as f64));
        }
    }
    let mut triangles = Vec::with_capacity(2 * (n - 1) * (n - 1));
    let v = |i: usize, j: usize| (i * n + j) as u32;
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    for (name, bump) in [("a", 1.0f32), ("b", 1.01)] {
        let e: Vec<f32> = positions
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let base = (300.0 / (1.0 + p.length_squared() / 20.0)) as f32;
                if k % 1000 == 0 { base * bump } else { base }
            })
            .collect();
        let surface = BakedSurface {
            surface: 0,
            side: Side::Front,
            positions: positions.clone(),
            normals: vec![DVec3::Y; positions.len()],
            uv0: None,
            uv1: None,
            triangles: triangles.clone(),
            luminance: e.iter().map(|x| x * 0.5 / std::f32::consts::PI).collect(),
            illuminance_direct: e.iter().map(|x| x * 0.7).collect(),
            color: vec![[0.5; 3]; positions.len()],
            illuminance: e,
            lightmap: None,
            covered_from: None,
        };
        let result = BakeResult {
            surfaces: vec![surface],
            probes: Vec::new(),
            lightmaps: None,
            openings: Vec::new(),
            summary: Default::default(),
            timings: Default::default(),
        };
        let path = dir.join(format!("{name}.glb"));
        export::write(&path, &scene, &result, &ExportOptions::default()).expect("export");
        println!("{}", path.display());
    }
}
