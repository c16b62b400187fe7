//! Direct light against closed forms: CIE 171:2006 test 5.3 (a Lambertian panel in a room with
//! black walls, against Lambert's formula) and the KHR_lights_punctual spot cone.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::{SceneBuilder, box_faces};
use luxbake::geom::lambert;
use luxbake::progress::Silent;
use luxbake::scene::LightKind;
use luxbake::settings::Settings;
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

/// CIE 171:2006 test 5.3: a 1 × 1 m Lambertian panel (L = 1000 cd/m²) in the centre of the
/// ceiling of a 4 × 4 × 3 m room with black walls: E at every floor and wall vertex equals π·L
/// times Lambert's point-to-polygon form factor to the panel.
#[test]
fn cie_171_test_5_3_area_source_in_black_room() {
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    let panel = b.emitter("panel", 0.0, 1000.0);
    let size = DVec3::new(4.0, 3.0, 4.0);
    for (i, f) in box_faces(DVec3::ZERO, size)
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != 1)
    {
        b.quad(&format!("face_{i}"), *f, black);
    }
    // Ceiling cut around the panel (x, z in 1.5..2.5), all facing down.
    let cut = [0.0, 1.5, 2.5, 4.0];
    for i in 0..3 {
        for j in 0..3 {
            let c = |x: f64, z: f64| DVec3::new(x, 3.0, z);
            let q = [
                c(cut[i], cut[j]),
                c(cut[i + 1], cut[j]),
                c(cut[i + 1], cut[j + 1]),
                c(cut[i], cut[j + 1]),
            ];
            b.quad(
                &format!("ceiling_{i}{j}"),
                q,
                if i == 1 && j == 1 { panel } else { black },
            );
        }
    }
    let r = bake(&b.build(), &Settings::default(), &Silent).unwrap();
    let square = [
        DVec3::new(1.5, 3.0, 1.5),
        DVec3::new(2.5, 3.0, 1.5),
        DVec3::new(2.5, 3.0, 2.5),
        DVec3::new(1.5, 3.0, 2.5),
    ];
    let (mut worst, mut checked) = (0.0f64, 0);
    for s in r.surfaces.iter().filter(|s| s.surface < 5) {
        for (v, p) in s.positions.iter().enumerate() {
            // Nudge the oracle's point into the face like the receiver (corners see walls as limits).
            let n = s.normals[v];
            let want = PI * 1000.0 * lambert::form_factor(*p + n * 1e-9, n, &square);
            if want < 1.0 {
                continue; // points seeing the panel at grazing angles: relative error meaningless
            }
            checked += 1;
            worst = worst.max(rel(s.illuminance[v] as f64, want));
        }
    }
    eprintln!("CIE 5.3: {checked} vertices, worst {worst:.2e}");
    assert!(checked > 200);
    assert!(worst < 0.005, "worst vertex off Lambert by {worst}");
}

/// The spot's reference falloff (KHR_lights_punctual): intensity I inside the inner cone,
/// I·t² with t linear in cos θ between the cones, 0 outside the outer cone.
#[test]
fn spot_follows_the_khr_cone_definition() {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", 0.0);
    b.floor("floor", 5.0, 0.0, floor);
    let (inner, outer, i0, h) = (0.2f64, 0.4f64, 5000.0, 3.0);
    b.light(
        "spot",
        LightKind::Spot {
            inner_cone_angle: inner,
            outer_cone_angle: outer,
        },
        DVec3::new(0.0, h, 0.0),
        -DVec3::Y,
        i0,
    );
    let r = bake(&b.build(), &Settings::default(), &Silent).unwrap();
    let s = &r.surfaces[0];
    let (mut inside, mut ramp, mut outside) = (0, 0, 0);
    for (v, p) in s.positions.iter().enumerate() {
        let d = DVec3::new(0.0, h, 0.0) - *p;
        let theta = (d.y / d.length()).acos();
        let t = ((theta.cos() - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        let want = i0 * t * t * (d.y / d.length()) / d.length_squared();
        let got = s.illuminance[v] as f64;
        if theta < inner {
            inside += 1;
        } else if theta < outer {
            ramp += 1;
        } else {
            outside += 1;
            assert_eq!(got, 0.0, "light outside the outer cone at {p}");
            continue;
        }
        // Receivers sit a hair (10⁻⁴ of a patch) inside their patches, which moves the steep
        // falloff by ~10⁻⁴ relative: allow twice that in the ramp, 10⁻⁵ inside the inner cone.
        let tol = if theta < inner { 1e-5 } else { 2e-4 };
        let slack = 1e-5 * i0 / (h * h);
        assert!(
            (got - want).abs() <= tol * want + slack,
            "at θ = {theta}: {got} vs {want}"
        );
    }
    assert!(
        inside > 5 && ramp > 5 && outside > 5,
        "{inside} {ramp} {outside}"
    );
}
