//! Numerical stability: reflectance near 1, huge and tiny scales, degenerate and overlapping
//! geometry, open scenes, a light shut in a box, a scene without light, and random closed boxes
//! (property test, and its recorded narrow shaft) against Sumpner's balance Φ/(S(1−ρ)).

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::{self, SceneBuilder, box_faces};
use luxbake::geom::lambert::form_factor;
use luxbake::progress::Progress;
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::{Quality, Settings};
use luxbake::summary::EnergyBalance;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use std::sync::Mutex;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Records warnings.
#[derive(Default)]
struct Warnings(Mutex<Vec<String>>);

impl Progress for Warnings {
    fn stage(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn warn(&self, m: &str) {
        self.0.lock().unwrap().push(m.to_string());
    }
}

fn run(scene: &Scene, quality: Quality) -> BakeResult {
    run_with(
        scene,
        &Settings {
            quality,
            ..Default::default()
        },
    )
}

fn run_with(scene: &Scene, settings: &Settings) -> BakeResult {
    let r = bake(scene, settings, &Warnings::default()).unwrap();
    for s in &r.surfaces {
        assert!(
            s.illuminance
                .iter()
                .chain(&s.luminance)
                .all(|x| x.is_finite() && *x >= 0.0)
        );
        assert!(s.color.iter().flatten().all(|c| (0.0..=1.0).contains(c)));
    }
    r
}

fn area_mean(r: &BakeResult) -> f64 {
    let (mut sum, mut total) = (0.0, 0.0);
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
            for &v in t {
                sum += s.illuminance[v as usize] as f64 * a / 3.0;
                total += a / 3.0;
            }
        }
    }
    sum / total
}

fn energy(r: &BakeResult) -> &EnergyBalance {
    &r.summary.energy
}

#[test]
fn reflectance_0_999_converges_and_reports_its_residual() {
    let size = DVec3::new(3.0, 2.5, 4.0);
    let r = run(
        &fixtures::closed_box_with_panel(size, 0.999, 0.6, 2000.0),
        Quality::Draft,
    );
    let s = 2.0 * (3.0 * 2.5 + 3.0 * 4.0 + 2.5 * 4.0);
    let want = std::f64::consts::PI * 2000.0 * 0.36 / (s * 0.001);
    let solver = &r.summary.solver;
    eprintln!(
        "ρ 0.999: mean {:.1} vs {want:.1}, solver {solver:?}",
        area_mean(&r)
    );
    assert!(solver.converged);
    assert!(solver.relative_residual < 1e-4);
    assert!(
        rel(area_mean(&r), want) < 0.02,
        "{} vs {want}",
        area_mean(&r)
    );
}

/// The same room at 1 mm, 1 m and 1 km scale: lux from an area source depends only on angles;
/// from a point source scaled as I·s², likewise.
#[test]
fn millimetre_metre_and_kilometre_scenes_agree() {
    let build = |s: f64| {
        let mut b = SceneBuilder::new();
        let walls = b.material("walls", 0.5);
        let lamp = b.emitter("lamp", 0.5, 1000.0);
        b.axis_box(
            "room",
            DVec3::ZERO,
            DVec3::new(4.0, 3.0, 5.0) * s,
            true,
            walls,
        );
        let c = |x: f64, z: f64| DVec3::new(x, 2.9, z) * s;
        b.quad(
            "panel",
            [c(1.5, 2.0), c(2.5, 2.0), c(2.5, 3.0), c(1.5, 3.0)].map(|p| p),
            lamp,
        );
        b.point_light("bulb", DVec3::new(1.0, 1.5, 1.0) * s, 500.0 * s * s);
        // A table, so shadows and rays matter too.
        b.axis_box(
            "table",
            DVec3::new(2.5, 0.7, 3.0) * s,
            DVec3::new(3.5, 0.75, 4.0) * s,
            false,
            walls,
        );
        b.build()
    };
    // Exact per-vertex equality is not to be had: rounding at another scale breaks ties in the
    // patch hierarchy differently, and flips the shadow ray of a vertex lying right on a shadow
    // edge. So: every surface's mean within 0.2 %, and 99 % of vertices within 1 %, on uniform
    // patches (the same vertices at every scale). Adaptive meshing decides edge by edge on
    // illuminance values, so a vertex on a shadow edge may split one edge more or less (and
    // sharp edges split down to h/4, so a flip there costs up to three levels). Measured: 2032
    // patches at 1 m, 2272 at 1 mm, 2042 at 1 km (1934, 2192, 1944 with splits down to h/2 only);
    // the rest is shadow rays grazing the table's
    // edges, which line up with grid vertices here, so the counts are held within 20 %.
    let uniform = Settings {
        quality: Quality::Draft,
        uniform_patches: true,
        ..Default::default()
    };
    let patches = |r: &BakeResult| r.summary.counts.patches as f64;
    let adaptive = patches(&run(&build(1.0), Quality::Draft));
    for s in [1e-3, 1e3] {
        let n = patches(&run(&build(s), Quality::Draft));
        println!("adaptive patches at scale {s}: {n} (at 1 m: {adaptive})");
        assert!(
            rel(n, adaptive) < 0.2,
            "scale {s}: {n} vs {adaptive} adaptive patches"
        );
    }
    let reference = run_with(&build(1.0), &uniform);
    let mean = |s: &luxbake::result::BakedSurface| {
        s.illuminance.iter().map(|e| *e as f64).sum::<f64>() / s.illuminance.len() as f64
    };
    for s in [1e-3, 1e3] {
        let r = run_with(&build(s), &uniform);
        let mut diffs = Vec::new();
        for (a, b) in reference.surfaces.iter().zip(&r.surfaces) {
            assert!(
                rel(mean(b), mean(a)) < 2e-3,
                "scale {s}: surface mean {} vs {}",
                mean(b),
                mean(a)
            );
            for (x, y) in a.illuminance.iter().zip(&b.illuminance) {
                diffs.push((x - y).abs() as f64 / (*x as f64).max(1.0));
            }
        }
        diffs.sort_by(f64::total_cmp);
        let p99 = diffs[diffs.len() * 99 / 100];
        eprintln!(
            "scale {s}: 99th percentile vertex difference {p99:.2e}, worst {:.2e}",
            diffs.last().unwrap()
        );
        assert!(p99 < 1e-2, "scale {s}: {p99}");
    }
}

/// Slivers (aspect 10⁴), zero-area and duplicate triangles, and coplanar overlapping faces: the
/// bake stays finite and its energy balance closes.
#[test]
fn degenerate_and_overlapping_geometry() {
    let mut b = SceneBuilder::new();
    let walls = b.material("walls", 0.6);
    let lamp = b.emitter("lamp", 0.0, 1000.0);
    let faces = box_faces(DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0));
    for (i, f) in faces.iter().enumerate() {
        b.quad(&format!("face_{i}"), *f, if i == 1 { lamp } else { walls });
    }
    // A sliver 2 m long and 0.2 mm wide on the floor, a zero-area triangle, a duplicated quad
    // and a quad overlapping the floor (coplanar, half its size).
    let y = 1e-9;
    let sliver = vec![
        DVec3::new(1.0, y, 1.0),
        DVec3::new(3.0, y, 1.0),
        DVec3::new(2.0, y, 1.0002),
    ];
    b.surface(
        "sliver",
        sliver.clone(),
        vec![DVec3::Y; 3],
        vec![[0, 2, 1]],
        walls,
    );
    let flat = vec![
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(2.0, 1.0, 1.0),
        DVec3::new(3.0, 1.0, 1.0),
    ];
    b.surface("zero area", flat, vec![DVec3::Y; 3], vec![[0, 1, 2]], walls);
    b.quad("duplicate wall", faces[2], walls);
    b.floor("overlap", 1.0, 0.0, walls);
    let r = run(&b.build(), Quality::Draft);
    let balance = energy(&r).balance_error_relative;
    eprintln!("degenerate: balance {balance:.2e}");
    assert!(balance < 0.02, "{balance}");
}

/// An open scene: a floor under a point light lets light escape; the balance still closes.
#[test]
fn open_scene_balance_closes_with_escape() {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", 0.5);
    b.floor("floor", 3.0, 0.0, floor);
    b.point_light("bulb", DVec3::new(0.0, 2.0, 0.0), 1000.0);
    let r = run(&b.build(), Quality::Default);
    let (emitted, escaped) = (energy(&r).emitted_lm, energy(&r).escaped_lm);
    eprintln!(
        "open: emitted {emitted:.1} escaped {escaped:.1} balance {:.2e}",
        energy(&r).balance_error_relative
    );
    // Half the bulb's flux goes up; of the rest, the floor reflects half and all of that escapes.
    assert!(escaped > 0.5 * emitted && escaped < emitted);
    assert!(energy(&r).balance_error_relative < 5e-3);
}

/// A light shut inside a closed box within a room: the room stays dark, the box absorbs all.
#[test]
fn light_inside_a_closed_box_stays_inside() {
    let mut b = SceneBuilder::new();
    let walls = b.material("walls", 0.7);
    b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, walls);
    b.axis_box("crate", DVec3::splat(1.0), DVec3::splat(2.0), false, walls);
    b.point_light("trapped", DVec3::splat(1.5), 1000.0);
    let r = run(&b.build(), Quality::Draft);
    let room_max = r.surfaces[..6]
        .iter()
        .flat_map(|s| s.illuminance.iter())
        .fold(0.0f32, |m, e| m.max(*e));
    assert_eq!(room_max, 0.0, "light leaked out of the crate");
    // The crate's faces point outward, so the light hits their backs and is absorbed there.
    assert!(rel(energy(&r).absorbed_lm, energy(&r).emitted_lm) < 2e-3);
}

#[test]
fn scene_without_light_is_dark_and_warned() {
    let mut b = SceneBuilder::new();
    let walls = b.material("walls", 0.5);
    b.axis_box("room", DVec3::ZERO, DVec3::splat(3.0), true, walls);
    let warnings = Warnings::default();
    let r = bake(&b.build(), &Settings::default(), &warnings).unwrap();
    assert!(
        r.surfaces
            .iter()
            .all(|s| s.illuminance.iter().all(|e| *e == 0.0))
    );
    let w = warnings.0.lock().unwrap();
    assert!(w.iter().any(|m| m.contains("no light source")), "{w:?}");
}

/// The case the property test shrank to (`tests/stress.proptest-regressions`; the seed there
/// replays the unshrunk 6.2 × 4.9 × 7.1 m box): a 1 × 1 m shaft 4.9 m high (glTF +Y up) with a
/// 0.1 m ceiling panel and ρ = 0.05, so nearly all its light is direct.
#[test]
fn recorded_narrow_shaft_obeys_sumpner_within_its_limit() {
    let (w, h, d, rho, side, l) = (1.0, 4.9271053172695405, 1.0, 0.05, 0.1, 10.0);
    let r = run(
        &fixtures::closed_box_with_panel(DVec3::new(w, h, d), rho, side, l),
        Quality::Default,
    );
    // The vertex values are right: direct light is Lambert's formula at every vertex below the
    // ceiling (the panel's plane).
    let (x, z) = ((w - side) / 2.0, (d - side) / 2.0);
    let panel = [
        DVec3::new(x, h, z),
        DVec3::new(x + side, h, z),
        DVec3::new(x + side, h, z + side),
        DVec3::new(x, h, z + side),
    ];
    let mut worst = 0.0f64;
    for s in &r.surfaces {
        for (v, p) in s.positions.iter().enumerate() {
            let want = std::f64::consts::PI * l * form_factor(*p, s.normals[v], &panel);
            if p.y < h - 1e-9 && want > 1e-6 {
                worst = worst.max(rel(s.illuminance_direct[v] as f64, want));
            }
        }
    }
    let s = 2.0 * (w * h + w * d + h * d);
    let want = std::f64::consts::PI * l * side * side / (s * (1.0 - rho));
    let mean = area_mean(&r);
    eprintln!(
        "shaft: mean {mean:.6e} vs {want:.6e} ({:+.3} %), direct vs Lambert worst {worst:.1e}",
        100.0 * (mean / want - 1.0)
    );
    assert!(worst < 1e-3, "direct light vs Lambert's formula: {worst}");
    // Their area mean is not within 0.5 %: between 0.1 m patches, linear interpolation cuts the
    // steep peak of direct light on the walls' top 0.5 m (an O(h²) loss), and adaptive meshing,
    // which would refine there, does not see light from emitting surfaces.
    assert!(rel(mean, want) < 7.5e-3, "mean {mean} vs {want}");
}

proptest! {
    // A fixed seed: the same 24 boxes every run, so CI cannot flake (change the seed to explore);
    // the failures recorded next to this file (stress.proptest-regressions) replay first.
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x1b_a4e5),
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions"
        ))),
        ..ProptestConfig::default()
    })]
    /// Random closed boxes (1–8 m, shafts included) with a random ceiling panel and uniform
    /// reflectance: the area mean of the vertices' illuminance is Φ/(S(1−ρ)) within 0.5 %
    /// (default quality; a narrow shaft with a small panel is the exception tested above).
    #[test]
    fn random_closed_boxes_obey_sumpner(
        w in 1.0f64..8.0, h in 1.0f64..5.0, d in 1.0f64..8.0,
        rho in 0.05f64..0.95, panel in 0.1f64..0.9, l in 10.0f64..5000.0,
    ) {
        let size = DVec3::new(w, h, d);
        let side = panel * w.min(d);
        let r = run(&fixtures::closed_box_with_panel(size, rho, side, l), Quality::Default);
        let s = 2.0 * (w * h + w * d + h * d);
        let want = std::f64::consts::PI * l * side * side / (s * (1.0 - rho));
        prop_assert!(rel(area_mean(&r), want) < 5e-3, "mean {} vs {}", area_mean(&r), want);
    }
}
