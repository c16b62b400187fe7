//! Cubic illuminance at probes against closed forms (docs/ANALYTIC.md §4) and against a brute-force
//! integration of incoming luminance over the sphere.

use glam::{DMat3, DVec3};
use luxbake::bake::{bake, solve};
use luxbake::fixtures::{self, SceneBuilder};
use luxbake::probes::{FACES, Probe, ProbeOrigin};
use luxbake::progress::Silent;
use luxbake::settings::Settings;
use luxbake::solution::{Planes, Receiver, sphere};
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// The bundled sample office.
fn office() -> luxbake::scene::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/office/office.gltf");
    luxbake::import::load(&path, &Default::default()).unwrap()
}

fn probe(name: &str, p: DVec3) -> Probe {
    Probe {
        name: name.into(),
        position: p,
        world_from_probe: DMat3::IDENTITY,
        origin: ProbeOrigin::File { line: 1 },
        toward: None,
    }
}

/// Furnace: every surface emits and reflects alike, so the luminance field is uniform,
/// L = M_e/(π(1−ρ)): all six faces read π·L, the vector vanishes.
#[test]
fn furnace_probe_sees_a_uniform_field() {
    let (l, rho) = (100.0, 0.9);
    let scene = fixtures::furnace(DVec3::new(2.0, 3.0, 5.0), rho, l);
    let settings = Settings {
        extra_probes: vec![
            probe("centre", DVec3::new(1.0, 1.5, 2.5)),
            probe("near a corner", DVec3::new(0.2, 0.3, 4.7)),
        ],
        ..Default::default()
    };
    let r = bake(&scene, &settings, &Silent).unwrap();
    let want = PI * l / (1.0 - rho);
    for p in &r.probes {
        for (k, e) in p.cubic.total.iter().enumerate() {
            assert!(
                rel(*e, want) < 5e-3,
                "{} face {k}: {e} vs {want}",
                p.probe.name
            );
        }
        let m = &p.metrics;
        eprintln!(
            "furnace {}: faces {:?} ratio {:.2e}",
            p.probe.name, p.cubic.total, m.vector_scalar_ratio
        );
        assert!(m.vector_magnitude < 5e-3 * want, "{m:?}");
        assert!(m.vector_scalar_ratio < 0.02);
        assert!(
            rel(m.exact_scalar.unwrap(), want) < 5e-3,
            "{:?}",
            m.exact_scalar
        );
    }
}

/// One point source above a probe in a black room: each face follows the inverse-square cosine
/// law exactly; along the beam E_sr = E/4 and the vector/scalar ratio is 4.
#[test]
fn single_source_in_a_black_room() {
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, black);
    let light = DVec3::new(2.0, 2.8, 2.0);
    b.point_light("lamp", light, 2000.0);
    let i = 2000.0 / (4.0 * PI);
    let below = DVec3::new(2.0, 0.8, 2.0);
    let off = DVec3::new(0.7, 1.1, 3.1);
    let settings = Settings {
        extra_probes: vec![probe("below", below), probe("off axis", off)],
        ..Default::default()
    };
    let r = bake(&b.build(), &settings, &Silent).unwrap();
    for p in &r.probes {
        let d = light - p.probe.position;
        for (k, n) in FACES.iter().enumerate() {
            let want = i * n.dot(d.normalize()).max(0.0) / d.length_squared();
            let got = p.cubic.total[k];
            assert!(
                (got - want).abs() <= 1e-3 * want + 1e-9,
                "{} face {k}: {got} vs {want}",
                p.probe.name
            );
            assert_eq!(p.cubic.indirect[k], 0.0, "black room: no indirect light");
        }
    }
    let m = &r.probes[0].metrics;
    let e = i / (light - below).length_squared();
    assert!(
        rel(m.scalar, e / 4.0) < 5e-3 && rel(m.vector_scalar_ratio, 4.0) < 5e-3,
        "{m:?}"
    );
    assert!(rel(m.exact_scalar.unwrap(), e / 4.0) < 5e-3);
}

/// The office with its real luminaires: every probe face against a brute-force integration of
/// the incoming luminance over the sphere (plus the luminaires as beams), within 2 %.
#[test]
fn office_probes_match_brute_force_sphere_integration() {
    let scene = office();
    let settings = Settings::default();
    let solved = solve(&scene, &settings, &Silent).unwrap();
    let s = &solved.solution;
    let points = [
        DVec3::new(2.5, 1.2, 4.0), // room centre, eye height
        DVec3::new(1.5, 1.2, 2.2), // beside the dark desk
        DVec3::new(4.2, 1.7, 6.5), // near the right wall, towards the picture
        DVec3::new(0.6, 2.4, 0.8), // high, in a corner
    ];
    let probes: Vec<Probe> = (points.iter().enumerate())
        .map(|(i, p)| probe(&format!("p{i}"), *p))
        .collect();
    let measured = luxbake::bake::probes::measure(s, &probes, &Silent);
    let mut worst = 0.0f64;
    for (i, (p, r)) in points.iter().zip(&measured).enumerate() {
        let brute = sphere::integrate(s, *p, DVec3::Y, &FACES, 256);
        for k in 0..6 {
            let err = rel(r.cubic.total[k], brute.planes[k]);
            eprintln!(
                "office probe {i} face {k}: {:.2} vs brute {:.2} ({err:.2e})",
                r.cubic.total[k], brute.planes[k]
            );
            worst = worst.max(err);
        }
    }
    assert!(worst < 0.02, "worst face error {worst}");
}

/// A probe's six faces are measured together (sub-sources, intensities and shadow rays shared
/// between the faces): each must read what it reads measured alone.
#[test]
fn faces_measured_together_equal_each_face_alone() {
    let scene = office();
    let settings = Settings::default();
    let solved = solve(&scene, &settings, &Silent).unwrap();
    let s = &solved.solution;
    let tilted = DMat3::from_rotation_y(0.4) * DMat3::from_rotation_x(0.3);
    let normals = FACES.map(|f| tilted * f);
    let mut worst = 0.0f64;
    // Under a luminaire, beside a desk (partly shadowed), in a corner.
    for p in [
        DVec3::new(2.5, 1.2, 4.0),
        DVec3::new(1.5, 0.5, 2.2),
        DVec3::new(0.6, 2.4, 0.8),
    ] {
        let together = s.light_at(&Receiver {
            point: p,
            planes: Planes::of(&normals),
        });
        let lit = together.iter().filter(|l| l.direct.x > 1.0).count();
        assert!(lit >= 2, "{lit} faces at {p} get direct light");
        for (k, n) in normals.iter().enumerate() {
            let alone = s.light_at(&Receiver {
                point: p,
                planes: Planes::one(*n),
            })[0];
            assert!(
                alone.indirect.x > 1.0,
                "face {k} at {p} gets no inter-reflected light"
            );
            // Relative to the value, or to 1 lx where a face is dark.
            let diff = |a: f64, b: f64| (a - b).abs() / b.abs().max(1.0);
            worst = worst
                .max(diff(together[k].direct.x, alone.direct.x))
                .max(diff(together[k].indirect.x, alone.indirect.x));
        }
    }
    assert!(worst < 1e-9, "worst difference {worst:e}");
}
