//! How far a light cut could go on a scene: at up to 3 000 of its vertices (every k-th, pulled
//! 0.1 mm off along the normal), every luminaire that reaches the vertex is summed unshadowed
//! (u, an exact upper bound on its light) and traced (e); luminaires are then taken in
//! decreasing u and traced until the untraced rest R = Σu satisfies R ≤ f × the light traced so
//! far, the rest estimated as R × (traced light / traced u). Prints the luminaires reaching a
//! vertex and those this rule traces (means per vertex), and the rule's error against the full
//! sum (lit vertices). No cluster's bound is tighter than its members' u, so a cut that bounds
//! its untraced light this way and estimates it so traces at least this many (one estimating by
//! the midpoint of [0, R] may leave R up to 2f: run with 2f to see that).
//!
//!     cargo run --release --example light_tail -- SCENE.gltf [f]

mod shared;

use glam::DVec3;
use luxbake::direct::bounds::ProfileBounds;
use luxbake::direct::groups::Known;
use luxbake::visibility::{Occluder, OccluderOptions};

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: light_tail SCENE [f]");
    let f: f64 = args.next().map_or(0.01, |x| x.parse().expect("f"));
    let scene = shared::scene(&path);
    let occ = Occluder::build(&scene, OccluderOptions::default());
    let bounds = ProfileBounds::new(&scene);
    let sources = shared::luminaires(&scene, &bounds);
    let points: Vec<(DVec3, DVec3)> = shared::vertices(&scene).collect();
    let step = (points.len() / 3000).max(1);
    let (mut reaching, mut traced, mut n) = (0, 0, 0);
    let mut errors = Vec::new();
    for &(p, normal) in points.iter().step_by(step) {
        let p = p + normal * 1e-4;
        let (mut u, mut e) = (Vec::new(), Vec::new());
        for s in &sources {
            let mut open = [0.0];
            s.illuminance_faces(&occ, p, &[normal], &mut open, (Known::Seen, true));
            if open[0] > 0.0 {
                let mut shadowed = [0.0];
                s.illuminance_faces(&occ, p, &[normal], &mut shadowed, (Known::Trace, true));
                u.push(open[0]);
                e.push(shadowed[0]);
            }
        }
        let mut order: Vec<usize> = (0..u.len()).collect();
        order.sort_by(|&a, &b| u[b].total_cmp(&u[a]).then(a.cmp(&b)));
        let mut rest: f64 = u.iter().sum();
        let (mut lit, mut lit_u, mut k) = (0.0, 0.0, 0);
        while k < order.len() && rest > f * lit {
            lit += e[order[k]];
            lit_u += u[order[k]];
            rest -= u[order[k]];
            k += 1;
        }
        let estimate = lit + if lit_u > 0.0 { rest * lit / lit_u } else { 0.0 };
        let full: f64 = e.iter().sum();
        if full > 0.0 {
            errors.push((estimate - full).abs() / full);
        }
        reaching += u.len();
        traced += k;
        n += 1;
    }
    errors.sort_by(|a, b| a.total_cmp(b));
    let at = |q: f64| {
        errors
            .get(((errors.len() as f64 - 1.0) * q) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    let mean = errors.iter().sum::<f64>() / errors.len().max(1) as f64;
    println!(
        "{} luminaires; {n} vertices ({} lit): reaching {:.1} per vertex, traced by the rule at f = {f}: {:.1}; relative error mean {mean:.2e}, p95 {:.2e}, max {:.2e}",
        sources.len(),
        errors.len(),
        reaching as f64 / n as f64,
        traced as f64 / n as f64,
        at(0.95),
        at(1.0)
    );
}
