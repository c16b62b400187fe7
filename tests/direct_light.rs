//! Direct light against closed forms: CIE 171:2006 test 5.3 (a Lambertian panel in a room with
//! black walls, against the point-to-rectangle form factors) and the KHR_lights_punctual spot cone.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::{SceneBuilder, box_faces};
use luxbake::progress::Silent;
use luxbake::scene::LightKind;
use luxbake::settings::Settings;
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

/// The panel of CIE 171 test 5.3: x and z in [1.5, 2.5] m, at y = 3 m (glTF +Y up), facing down.
const PANEL: [f64; 2] = [1.5, 2.5];
const PANEL_Y: f64 = 3.0;

/// Form factor from a point to a rectangle in a parallel plane at distance `c`, spanning [0, a] ×
/// [0, b] from the point's foot (one corner straight across from the point). Odd in a and in b,
/// so signed corner rectangles add up to any rectangle.
fn parallel_corner(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Form factor from a point to a rectangle in a perpendicular plane at distance `c`, spanning
/// [0, a] parallel to both planes and [0, b] along the point's normal, one corner at the foot of
/// the perpendicular from the point to the rectangle's plane. Odd in a; b ≥ 0.
fn perpendicular_corner(a: f64, b: f64, c: f64) -> f64 {
    let r = (b * b + c * c).sqrt();
    ((a / c).atan() - c / r * (a / r).atan()) / (2.0 * PI)
}

/// Form factor from a floor or wall point `p` (normal `n` along an axis) of the test 5.3 room to
/// its panel, by superposition of corner rectangles.
fn panel_form_factor(p: DVec3, n: DVec3) -> f64 {
    let c = PANEL_Y - p.y;
    if c <= 0.0 {
        return 0.0; // at or above the panel's plane: it faces away
    }
    let sum = |corner: &dyn Fn(f64, f64) -> f64, a: [f64; 2], b: [f64; 2]| {
        corner(a[1], b[1]) - corner(a[0], b[1]) - corner(a[1], b[0]) + corner(a[0], b[0])
    };
    if n.y > 0.99 {
        let (a, b) = (PANEL.map(|e| e - p.x), PANEL.map(|e| e - p.z));
        return sum(&|a, b| parallel_corner(a, b, c), a, b);
    }
    // A wall: b along its inward normal, a along the wall, both horizontal.
    let (b, a) = if n.x.abs() > 0.99 {
        (
            PANEL.map(|e| n.x.signum() * (e - p.x)),
            PANEL.map(|e| e - p.z),
        )
    } else if n.z.abs() > 0.99 {
        (
            PANEL.map(|e| n.z.signum() * (e - p.z)),
            PANEL.map(|e| e - p.x),
        )
    } else {
        panic!("normal {n} is neither the floor's nor a wall's");
    };
    let b = [b[0].min(b[1]), b[0].max(b[1])];
    assert!(b[0] >= 0.0, "the panel is in front of every wall");
    sum(&|a, b| perpendicular_corner(a, b, c), a, b)
}

/// The form factor to the panel by the midpoint rule on a k × k grid over it: the check of the
/// closed form above.
fn panel_form_factor_numerically(p: DVec3, n: DVec3, k: usize) -> f64 {
    let h = (PANEL[1] - PANEL[0]) / k as f64;
    let mut f = 0.0;
    for i in 0..k {
        for j in 0..k {
            let at = |i: usize| PANEL[0] + (i as f64 + 0.5) * h;
            let d = DVec3::new(at(i), PANEL_Y, at(j)) - p;
            let r2 = d.length_squared();
            // The panel faces down (−Y): toward p, its cosine is d.y / r.
            let (cos_p, cos_panel) = (n.dot(d) / r2.sqrt(), d.y / r2.sqrt());
            if cos_p > 0.0 && cos_panel > 0.0 {
                f += cos_p * cos_panel / (PI * r2) * h * h;
            }
        }
    }
    f
}

/// The closed-form oracle of test 5.3 against numerical integration, on the floor and on each
/// wall, near the panel's plane and in corners.
#[test]
fn cie_171_test_5_3_oracle_matches_numerical_integration() {
    let mut worst = 0.0f64;
    for (p, n) in [
        (DVec3::new(2.0, 0.0, 2.0), DVec3::Y),
        (DVec3::new(0.0, 0.0, 0.0), DVec3::Y),
        (DVec3::new(3.7, 0.0, 0.4), DVec3::Y),
        (DVec3::new(0.0, 1.2, 2.0), DVec3::X),
        (DVec3::new(4.0, 0.3, 0.5), -DVec3::X),
        (DVec3::new(1.0, 2.9, 0.0), DVec3::Z),
        (DVec3::new(3.5, 2.0, 4.0), -DVec3::Z),
        (DVec3::new(4.0, 0.0, 4.0), -DVec3::Z),
    ] {
        let (closed, numeric) = (
            panel_form_factor(p, n),
            panel_form_factor_numerically(p, n, 400),
        );
        assert!(closed > 1e-4, "{p}: {closed}");
        worst = worst.max(rel(closed, numeric));
    }
    eprintln!("CIE 5.3 oracle against the midpoint rule (400²): worst {worst:.2e}");
    assert!(worst < 1e-5, "closed form off the integration by {worst}");
}

/// CIE 171:2006 test 5.3: a 1 × 1 m Lambertian panel (L = 1000 cd/m²) in the centre of the
/// ceiling of a 4 × 4 × 3 m room with black walls: E at every floor and wall vertex equals π·L
/// times the point-to-rectangle form factor to the panel (closed form above).
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
    let (mut worst, mut checked) = (0.0f64, 0);
    for s in r.surfaces.iter().filter(|s| s.surface < 5) {
        for (v, p) in s.positions.iter().enumerate() {
            let want = PI * 1000.0 * panel_form_factor(*p, s.normals[v]);
            if want < 1.0 {
                continue; // points seeing the panel at grazing angles: relative error meaningless
            }
            checked += 1;
            worst = worst.max(rel(s.illuminance[v] as f64, want));
        }
    }
    eprintln!("CIE 5.3: {checked} vertices, worst {worst:.2e}");
    eprintln!("oracle: cie5.3 measured {worst:.3e}");
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
    // Worst relative error inside the inner cone; worst share of its tolerance in the ramp.
    let (mut worst_inner, mut worst_ramp, mut outside_max) = (0.0f64, 0.0f64, 0.0f64);
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
            outside_max = outside_max.max(got);
            assert_eq!(got, 0.0, "light outside the outer cone at {p}");
            continue;
        }
        // Receivers sit a hair (10⁻⁴ of a patch) inside their patches, which moves the steep
        // falloff by ~10⁻⁴ relative: allow twice that in the ramp, 10⁻⁵ inside the inner cone.
        let tol = if theta < inner { 1e-5 } else { 2e-4 };
        let slack = 1e-5 * i0 / (h * h);
        if theta < inner {
            worst_inner = worst_inner.max((got - want).abs() / want);
        } else {
            worst_ramp = worst_ramp.max((got - want).abs() / (tol * want + slack));
        }
        assert!(
            (got - want).abs() <= tol * want + slack,
            "at θ = {theta}: {got} vs {want}"
        );
    }
    eprintln!("oracle: spot/inner measured {worst_inner:.3e}");
    eprintln!("oracle: spot/ramp measured {worst_ramp:.3e}");
    eprintln!("oracle: spot/outside measured {outside_max:e}");
    assert!(
        inside > 5 && ramp > 5 && outside > 5,
        "{inside} {ramp} {outside}"
    );
}
