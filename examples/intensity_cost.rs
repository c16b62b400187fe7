//! Times `Photometry::intensity` (the interpolated intensity in one direction) for
//! `bench/intensity_timing.py`: 4096 directions spread over the sphere, 250 times each, in
//! `repeats` rounds; prints the nanoseconds per call of each round, one line each.
//!
//!     cargo run --release --example intensity_cost -- PROFILE.ies|PROFILE.ldt [repeats]

use luxbake::geom::samples::scattered_directions;
use luxbake::photometry::{Format, Photometry};
use std::hint::black_box;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: intensity_cost PROFILE [repeats]");
    let repeats: usize = args.next().map_or(5, |r| r.parse().expect("repeats"));
    let ext = path.rsplit('.').next().unwrap_or_default();
    let format = Format::from_mime_or_extension(ext).expect("an .ies or .ldt file");
    let bytes = std::fs::read(&path).expect("cannot read the profile");
    let ph = Photometry::parse(&bytes, format).expect("profile parses");
    let dirs = scattered_directions(4096);
    let rounds = 250;
    for _ in 0..repeats {
        let start = Instant::now();
        let mut sum = 0.0;
        for _ in 0..rounds {
            for d in &dirs {
                sum += ph.intensity(black_box(*d));
            }
        }
        let per = start.elapsed().as_secs_f64() / (rounds * dirs.len()) as f64;
        black_box(sum);
        println!("ns_per_call {:.2}", per * 1e9);
    }
}
