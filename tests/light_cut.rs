//! The light cut (`direct::cut`) against the full sum: on the 576-luminaire ceiling of
//! `tests/luminaires.rs` (glTF +Y up), every receiver's direct light and every floor patch's
//! front flux with the cut at fraction f lies within f of the sum of every luminaire traced on
//! its own, with and without a screen hiding part of the ceiling, and with two kinds of
//! luminaire (cosine and cos⁴, some tilted) mixed; the bake is byte-identical on 1 and 2 threads.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::direct::bounds::ProfileBounds;
use luxbake::direct::cut::{Cut, Target};
use luxbake::direct::groups::Known;
use luxbake::direct::luminaire::Source;
use luxbake::direct::sources::DirectSource;
use luxbake::direct::targets::{AtPoint, IntoPatch};
use luxbake::fixtures::SceneBuilder;
use luxbake::photometry::Format;
use luxbake::progress::Silent;
use luxbake::scene::Scene;
use luxbake::settings::{Quality, Settings};
use luxbake::visibility::{Occluder, OccluderOptions};
use std::f64::consts::PI;

const F: f64 = 0.01;

/// A target that counts how each luminaire was summed: traced on its own, summed exactly in a
/// group proved seen, skipped in a group proved hidden, or estimated in a kept cluster.
struct Counting<'c, T> {
    inner: T,
    counts: &'c mut [usize; 4],
}

impl<T: Target> Target for Counting<'_, T> {
    fn planes(&self) -> usize {
        self.inner.planes()
    }
    fn cluster_planes(&self) -> usize {
        self.inner.cluster_planes()
    }
    fn exact(&mut self, k: usize, known: Known, out: &mut [f64]) {
        self.counts[match known {
            Known::Trace => 0,
            Known::Seen => 1,
            Known::Hidden => 2,
        }] += 1;
        self.inner.exact(k, known, out)
    }
    fn sees(&self, n: DVec3, q: DVec3, nq: DVec3) -> bool {
        self.inner.sees(n, q, nq)
    }
    fn geometry(&self, s: &Source, out: &mut [f64]) {
        self.inner.geometry(s, out)
    }
    fn cone(&self, lo: DVec3, hi: DVec3) -> Option<(DVec3, f64)> {
        self.inner.cone(lo, hi)
    }
    fn accept(&mut self, k: usize, values: &[f64]) {
        self.counts[3] += 1;
        self.inner.accept(k, values)
    }
}

/// An axially symmetric IES profile, I(γ) = 1000·cosⁿ γ below the horizon, every 2.5°.
fn cos_power(n: i32) -> String {
    let count = 73;
    let values: Vec<String> = (0..count)
        .map(|k| {
            let g = (k as f64 * 2.5).to_radians();
            let i = if g <= PI / 2.0 {
                1000.0 * g.cos().max(0.0).powi(n)
            } else {
                0.0
            };
            format!("{i:.6}")
        })
        .collect();
    let angles: Vec<String> = (0..count).map(|k| format!("{}", k as f64 * 2.5)).collect();
    format!(
        "IESNA:LM-63-2002\r\n[TEST] cos power\r\nTILT=NONE\r\n1 -1 1 {count} 1 1 2 0 0 0\r\n1 1 0\r\n{}\r\n0\r\n{}\r\n",
        angles.join(" "),
        values.join(" ")
    )
}

/// The ceiling: 576 luminaires on a 2.5 m grid 3 m up over a black 60 × 60 m floor; `screen`:
/// a black screen at y = 2.5 m over x ∈ [4.3, 40] m; `mixed`: every third luminaire cos⁴ and
/// every fifth tilted 20° about +X.
fn ceiling(screen: bool, mixed: bool) -> Scene {
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    b.floor("floor", 30.0, 0.0, black);
    if screen {
        let y = 2.5;
        let corners = [(4.3, -40.0), (40.0, -40.0), (40.0, 40.0), (4.3, 40.0)]
            .map(|(x, z)| DVec3::new(x, y, z));
        b.quad("screen", corners, black);
    }
    let cos = b.profile("cos", cos_power(1).as_bytes(), Format::Ies);
    let cos4 = b.profile("cos4", cos_power(4).as_bytes(), Format::Ies);
    for k in 0..576 {
        let (i, j) = ((k / 24) as f64, (k % 24) as f64);
        let q = DVec3::new(2.5 * i - 28.75, 3.0, 2.5 * j - 28.75);
        let profile = if mixed && k % 3 == 0 { cos4 } else { cos };
        let tilt = if mixed && k % 5 == 0 {
            20f64.to_radians()
        } else {
            0.0
        };
        let nadir = DVec3::new(0.0, -tilt.cos(), tilt.sin());
        b.place_luminaire(&format!("l{k}"), profile, q, nadir, DVec3::X, 1.0, None);
    }
    b.build()
}

/// Worst |cut − full| / (f·full) over receivers (one upward plane on the floor, six faces 1 m
/// up) and floor patches, and the share of receivers the cut changed at all.
fn worst_against_full(scene: &Scene) -> (f64, f64, f64, [usize; 4]) {
    let occ = Occluder::build(scene, OccluderOptions::default());
    let bounds = ProfileBounds::new(scene);
    let sources: Vec<DirectSource> = Source::all(scene, &bounds)
        .into_iter()
        .map(DirectSource::Luminaire)
        .collect();
    let groups = DirectSource::groups(&sources);
    let cut = Cut::new(&sources, &groups, F);
    let exact = Cut::new(&sources, &groups, 0.0);
    let (mut worst_point, mut worst_patch, mut changed, mut count) = (0.0f64, 0.0f64, 0, 0);
    let mut counts = [0usize; 4];
    let faces = [
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ];
    for i in 0..=40 {
        for j in 0..=40 {
            let (x, z) = (
                -29.5 + 59.0 * i as f64 / 40.0,
                -29.5 + 59.0 * j as f64 / 40.0,
            );
            for (p, normals) in [
                (DVec3::new(x, 0.0, z), &[DVec3::Y][..]),
                (DVec3::new(x, 1.0, z), &faces[..]),
            ] {
                let starts: Vec<DVec3> = normals.iter().map(|n| p + *n * occ.epsilon).collect();
                let settle = |lo: DVec3, hi: DVec3, _n: DVec3| occ.settle(&starts, lo, hi);
                let mut at = AtPoint::new(&sources, &occ, p, normals);
                cut.run(&sources, &groups, p, normals, settle, &mut at);
                let mut full = vec![0.0; normals.len()];
                for s in &sources {
                    s.illuminance_faces(&occ, p, normals, &mut full, (Known::Trace, true));
                }
                for (pl, (got, want)) in at.luma.iter().zip(&full).enumerate() {
                    let err = (got - want).abs();
                    assert!(
                        err <= F * want + 1e-12 * want.max(1e-300),
                        "{p} plane {pl}: cut {got} full {want}"
                    );
                    if *want > 0.0 {
                        worst_point = worst_point.max(err / (F * want));
                    }
                    count += 1;
                    changed += usize::from(err > 1e-9 * want);
                }
                // Exact-sum mode (fraction 0) gives the luminaires traced one by one.
                let mut at0 = AtPoint::new(&sources, &occ, p, normals);
                exact.run(&sources, &groups, p, normals, settle, &mut at0);
                for (got, want) in at0.luma.iter().zip(&full) {
                    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
                }
            }
            // A floor triangle of about 1 m² (and a tenth of that) at this point.
            for size in [1.5, 0.5] {
                let p = DVec3::new(x, 0.0, z);
                let corners = [
                    p,
                    p + DVec3::new(0.0, 0.0, size),
                    p + DVec3::new(size, 0.0, 0.0),
                ];
                let c = (corners[0] + corners[1] + corners[2]) / 3.0;
                let flux = |cut: &Cut, counts: &mut [usize; 4]| {
                    let mut row = vec![(0.0, 0.0); sources.len()];
                    let inset = corners.map(|v| v + (c - v) * 1e-4);
                    let settle = |lo: DVec3, hi: DVec3, n: DVec3| {
                        occ.settle(&inset.map(|v| v + n * occ.epsilon), lo, hi)
                    };
                    let into = IntoPatch {
                        sources: &sources,
                        occ: &occ,
                        corners,
                        normal: DVec3::Y,
                        c,
                        size: corners
                            .iter()
                            .map(|v| (*v - c).length())
                            .fold(0.0, f64::max),
                        dark_back: Some(None),
                        double_sided: true,
                        row: &mut row,
                    };
                    let mut counting = Counting {
                        inner: into,
                        counts,
                    };
                    cut.run(
                        &sources,
                        &groups,
                        c,
                        &[DVec3::Y, -DVec3::Y],
                        settle,
                        &mut counting,
                    );
                    row.iter().map(|r| r.0).sum::<f64>()
                };
                let got = flux(&cut, &mut counts);
                let want = flux(&exact, &mut [0; 4]);
                let err = (got - want).abs();
                assert!(
                    err <= F * want + 1e-12 * want,
                    "patch at {p}: cut {got} full {want}"
                );
                worst_patch = worst_patch.max(err / (F * want).max(1e-300));
            }
        }
    }
    (
        worst_point,
        worst_patch,
        changed as f64 / count as f64,
        counts,
    )
}

#[test]
fn every_receiver_and_patch_is_within_the_bound_of_the_full_sum() {
    for (screen, mixed) in [(false, false), (true, false), (true, true)] {
        let (point, patch, changed, [traced, seen, hidden, kept]) =
            worst_against_full(&ceiling(screen, mixed));
        eprintln!(
            "screen {screen} mixed {mixed}: worst error {point:.3} (receivers) {patch:.3} (patches) of the bound f = {F}; {:.0} % of receivers approximated; into patches {traced} luminaires traced, {seen} summed exactly in seen groups, {hidden} in hidden groups, {kept} estimated in kept clusters",
            changed * 100.0
        );
        // The cut must do something: most receivers take some luminaires as clusters.
        assert!(changed > 0.5, "{changed}");
    }
}

#[test]
fn the_cut_bake_is_the_same_on_one_and_two_threads() {
    let scene = ceiling(true, true);
    let run = |threads| {
        let settings = Settings {
            quality: Quality::Draft,
            light_cut: F,
            threads: Some(threads),
            ..Default::default()
        };
        let r = bake(&scene, &settings, &Silent).unwrap();
        r.surfaces
            .iter()
            .map(|s| {
                s.illuminance
                    .iter()
                    .map(|e| e.to_bits())
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(2));
}
