//! The 576-luminaire ceiling of `tests/luminaires.rs` (cosine luminaires on a 2.5 m grid 3 m up,
//! glTF +Y up, over a 60 × 60 m black floor with a black screen hiding part of them), baked in
//! process for timing the direct stage: prints the stage seconds and the vertex count.
//!
//!     cargo run --release --example ceiling576 -- [quality] [light-cut fraction]

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::SceneBuilder;
use luxbake::photometry::Format;
use luxbake::progress::Silent;
use luxbake::settings::{Quality, Settings};

fn main() {
    let mut args = std::env::args().skip(1);
    let quality = match args.next().as_deref() {
        Some("draft") | None => Quality::Draft,
        Some("high") => Quality::High,
        Some(_) => Quality::Default,
    };
    let fraction: Option<f64> = args.next().map(|f| f.parse().expect("a fraction"));
    let n = 73;
    let values: Vec<String> = (0..n)
        .map(|k| {
            let g = (k as f64 * 2.5).to_radians();
            format!(
                "{:.6}",
                1000.0
                    * if g <= std::f64::consts::FRAC_PI_2 {
                        g.cos().max(0.0)
                    } else {
                        0.0
                    }
            )
        })
        .collect();
    let angles: Vec<String> = (0..n).map(|k| format!("{}", k as f64 * 2.5)).collect();
    let ies = format!(
        "IESNA:LM-63-2002\r\n[TEST] cosine\r\nTILT=NONE\r\n1 -1 1 {n} 1 1 2 0 0 0\r\n1 1 0\r\n{}\r\n0\r\n{}\r\n",
        angles.join(" "),
        values.join(" ")
    );
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    let grey = b.material("grey", 0.5);
    b.floor("floor", 30.0, 0.0, grey);
    let y = 2.5;
    b.quad(
        "screen",
        [
            DVec3::new(4.3, y, -40.0),
            DVec3::new(40.0, y, -40.0),
            DVec3::new(40.0, y, 40.0),
            DVec3::new(4.3, y, 40.0),
        ],
        black,
    );
    let profile = b.profile("cosine", ies.as_bytes(), Format::Ies);
    for k in 0..576 {
        let (i, j) = ((k / 24) as f64, (k % 24) as f64);
        let q = DVec3::new(2.5 * i - 28.75, 3.0, 2.5 * j - 28.75);
        b.place_luminaire(&format!("l{k}"), profile, q, -DVec3::Y, DVec3::X, 1.0, None);
    }
    let mut settings = Settings {
        quality,
        record_timings: true,
        ..Default::default()
    };
    if let Some(f) = fraction {
        settings.light_cut = f;
    }
    let r = bake(&b.build(), &settings, &Silent).expect("bakes");
    let t = r.summary.timings_seconds.expect("timings");
    let vertices: usize = r.surfaces.iter().map(|s| s.positions.len()).sum();
    println!(
        "vertices {vertices} direct {:.3} total_stages {:.3}",
        t.direct,
        t.named().iter().map(|x| x.1).sum::<f64>()
    );
}
