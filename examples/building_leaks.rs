//! Light through closed walls and energy lost in rows of rooms (`fixtures::building`): for each
//! way of drawing the row and each reflectance, the largest vertex illuminance in the rooms
//! without a light (and its share of the lit room's mean), the energy report's balance error,
//! and Sumpner's balance Σ(1 − ρ)·E·A from the vertex values against Φ, per room and whole.
//!
//!     cargo run --release --example building_leaks [-- QUALITY]

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::building::{self, Row};
use luxbake::progress::Silent;
use luxbake::settings::{Quality, Settings};

fn main() {
    let quality = match std::env::args().nth(1).as_deref() {
        Some("draft") => Quality::Draft,
        Some("high") => Quality::High,
        _ => Quality::Default,
    };
    let settings = Settings {
        quality,
        ..Settings::default()
    };
    println!(
        "| scene | ρ | dark rooms: max lx (share of lit mean) | balance | Σ(1−ρ)EA/Φ − 1: all | lit room | s |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for (name, slabs) in building::VARIANTS {
        for rho in [0.5, 0.8] {
            let row = building::row(slabs, 3, rho, 1000.0, &[]);
            let start = std::time::Instant::now();
            let r = bake(&row.scene, &settings, &Silent).expect("bake");
            let secs = start.elapsed().as_secs_f64();
            let m = measure(&row, &r, rho);
            if std::env::var("WORST").is_ok() {
                worst(&row, &r, 12);
            }
            println!(
                "| {name} | {rho} | {:.3} ({:.2} %) | {:.1e} | {:+.2} % | {:+.2} % | {secs:.1} |",
                m.dark_max,
                100.0 * m.dark_max / m.lit_mean,
                r.summary.energy.balance_error_relative,
                100.0 * (m.absorbed.iter().sum::<f64>() / row.flux.iter().sum::<f64>() - 1.0),
                100.0 * (m.absorbed[0] / row.flux[0] - 1.0),
            );
        }
    }
}

struct Measured {
    dark_max: f64,
    lit_mean: f64,
    /// Σ(1 − ρ)·E·A per room (lm).
    absorbed: Vec<f64>,
}

fn measure(row: &Row, r: &luxbake::result::BakeResult, rho: f64) -> Measured {
    let n = row.rooms.len();
    let mut absorbed = vec![0.0; n];
    let (mut lit_ea, mut lit_a, mut dark_max) = (0.0, 0.0, 0.0f64);
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let cross = (p[1] - p[0]).cross(p[2] - p[0]);
            let a = cross.length() / 2.0;
            let normal = cross.normalize_or_zero();
            let centre = (p[0] + p[1] + p[2]) / 3.0 + normal * 0.01;
            let Some(room) = row.room_of(centre, 0.0) else {
                continue;
            };
            let e: Vec<f64> = t
                .iter()
                .map(|&v| s.illuminance[v as usize] as f64)
                .collect();
            let mean = e.iter().sum::<f64>() / 3.0;
            absorbed[room] += (1.0 - rho) * mean * a;
            if room == 0 {
                lit_ea += mean * a;
                lit_a += a;
            } else {
                dark_max = e.iter().fold(dark_max, |m, x| m.max(*x));
            }
        }
    }
    let _ = DVec3::ZERO;
    Measured {
        dark_max,
        lit_mean: lit_ea / lit_a.max(1e-300),
        absorbed,
    }
}

/// The `n` brightest vertices in rooms without light: surface, position, illuminance.
#[allow(dead_code)]
pub fn worst(row: &Row, r: &luxbake::result::BakeResult, n: usize) {
    let mut all = Vec::new();
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let centre = (p[0] + p[1] + p[2]) / 3.0 + normal * 0.01;
            if row.room_of(centre, 0.0).is_none_or(|k| k == 0) {
                continue;
            }
            for &v in t {
                all.push((
                    s.illuminance[v as usize],
                    row.scene.surfaces[s.surface].source_path.clone(),
                    s.positions[v as usize],
                    centre,
                ));
            }
        }
    }
    all.sort_by(|a, b| b.0.total_cmp(&a.0));
    for x in all.iter().take(n) {
        println!(
            "  {:.3} lx {} v {:.3?} tri centre {:.3?}",
            x.0, x.1, x.2, x.3
        );
    }
}
