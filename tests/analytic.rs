//! The physics against closed forms (docs/ANALYTIC.md): energy balance in closed rooms, furnace,
//! CIE 171:2006 test 5.8, Lambert's formula for an area source, the inverse-square cosine law,
//! and shadows. Every number below comes from a formula, never from an earlier bake.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::{self, SceneBuilder};
use luxbake::progress::Silent;
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::{Quality, Settings};
use std::f64::consts::PI;

fn run(scene: &Scene, settings: &Settings) -> BakeResult {
    bake(scene, settings, &Silent).expect("bake")
}

/// Area-weighted mean over all vertices of f(surface, vertex); vertex weight = ⅓ of the areas of
/// its triangles.
fn area_mean(r: &BakeResult, f: impl Fn(&luxbake::result::BakedSurface, usize) -> f64) -> f64 {
    let (mut sum, mut total) = (0.0, 0.0);
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
            for &v in t {
                sum += f(s, v as usize) * a / 3.0;
                total += a / 3.0;
            }
        }
    }
    sum / total
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn closed_box_mean_illuminance_is_sumpner_at_any_reflectance() {
    // 3 × 2.5 × 4 m box, a 0.6 m emitting square in the ceiling (L = 2000 cd/m²).
    let size = DVec3::new(3.0, 2.5, 4.0);
    let s_total = 2.0 * (3.0 * 2.5 + 3.0 * 4.0 + 2.5 * 4.0);
    let phi = PI * 2000.0 * 0.36;
    for rho in [0.3, 0.9, 0.99] {
        let scene = fixtures::closed_box_with_panel(size, rho, 0.6, 2000.0);
        let r = run(&scene, &Settings::default());
        let mean = area_mean(&r, |s, v| s.illuminance[v] as f64);
        let want = phi / (s_total * (1.0 - rho));
        eprintln!(
            "rho {rho}: mean {mean:.4} want {want:.4} rel {:.2e}",
            rel(mean, want)
        );
        eprintln!("oracle: box/{rho} measured {:.3e}", rel(mean, want));
        assert!(
            rel(mean, want) < 0.005,
            "rho {rho}: mean {mean} vs Φ/(S(1−ρ)) = {want}"
        );
        let balance = &r.summary.energy;
        assert!(balance.balance_error_relative < 0.005, "{balance:?}");
        assert_eq!(balance.escaped_lm, 0.0, "a closed box lets nothing escape");
    }
}

#[test]
fn closed_box_with_curved_clutter_is_sumpner() {
    // Sumpner holds for any closed enclosure of uniform reflectance, objects inside included:
    // the area-mean illuminance is Φ/(S(1−ρ)) with S every surface's area. Twelve tessellated
    // balls 5 cm above the floor are seen from across the room as two-sided clusters.
    let size = DVec3::new(4.0, 3.0, 5.0);
    let phi = PI * 2000.0 * 0.36;
    for rho in [0.5, 0.9] {
        let scene = fixtures::closed_box_with_balls(size, rho, 0.6, 2000.0);
        let r = run(&scene, &Settings::default());
        let clusters = r.summary.counts.cluster_links;
        assert!(
            clusters > 1000,
            "{clusters} cluster links: the clusters are not exercised"
        );
        // The summary's rays by stage account for every ray, and the balls make the links trace.
        let counts = &r.summary.counts;
        let by_stage = &counts.rays_by_stage;
        assert_eq!(by_stage.total(), counts.rays, "{by_stage:?}");
        assert!(by_stage.links > 0, "{by_stage:?}");
        let s_total: f64 = r
            .surfaces
            .iter()
            .flat_map(|s| {
                s.triangles.iter().map(|t| {
                    let p = t.map(|v| s.positions[v as usize]);
                    (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0
                })
            })
            .sum();
        let mean = area_mean(&r, |s, v| s.illuminance[v] as f64);
        let want = phi / (s_total * (1.0 - rho));
        eprintln!(
            "clutter rho {rho}: {clusters} cluster links, mean {mean:.4} want {want:.4} rel {:.2e}",
            rel(mean, want)
        );
        eprintln!("oracle: balls/{rho} measured {:.3e}", rel(mean, want));
        assert!(
            rel(mean, want) < 0.005,
            "rho {rho}: mean {mean} vs Φ/(S(1−ρ)) = {want}"
        );
    }
}

#[test]
fn inside_a_sphere_inter_reflected_light_is_sumpner_at_every_vertex() {
    // Inside a sphere every element sees every other in proportion to its area, so Sumpner's
    // balance holds pointwise: E_ind = ρ·Φ/(S·(1−ρ)) at every vertex, S the facets' area. A
    // concave curved surface: its vertices' receivers must not slip behind the facets around
    // them (they did, and read a sixth of this).
    let flux = 1000.0;
    for rho in [0.5, 0.8, 0.99] {
        let sphere = fixtures::sphere_interior(2.0, (24, 48), f64::NEG_INFINITY, rho, flux);
        let r = run(&sphere.scene, &Settings::default());
        let want = rho * flux / (sphere.area * (1.0 - rho));
        let mut worst: f64 = 0.0;
        for s in &r.surfaces {
            for (e, d) in s.illuminance.iter().zip(&s.illuminance_direct) {
                worst = worst.max(rel((e - d) as f64, want));
            }
        }
        eprintln!("sphere rho {rho}: want {want:.4} lx, worst vertex {worst:.2e}");
        eprintln!("oracle: sphere/{rho} measured {worst:.3e}");
        assert!(worst < 0.005, "rho {rho}: worst vertex off by {worst}");
    }
}

#[test]
fn furnace_exitance_is_uniform_and_exact_at_every_vertex() {
    let (l, rho) = (100.0, 0.9);
    let scene = fixtures::furnace(DVec3::new(2.0, 3.0, 5.0), rho, l);
    let r = run(&scene, &Settings::default());
    let want = PI * l / (1.0 - rho);
    let mut worst: f64 = 0.0;
    for s in &r.surfaces {
        for &lum in &s.luminance {
            worst = worst.max(rel(PI * lum as f64, want));
        }
    }
    eprintln!("furnace worst {worst:.2e}");
    eprintln!("oracle: furnace measured {worst:.3e}");
    assert!(worst < 0.005, "worst vertex exitance off by {worst}");
}

#[test]
fn cie_171_test_5_8_indirect_illuminance() {
    // E_ind = ρΦ/(S(1−ρ)), S = 96 m², Φ = 10 000 lm (docs/ANALYTIC.md §3 Sumpner).
    for (rho, published) in [(0.2, 26.0), (0.5, 104.0), (0.9, 937.0), (0.95, 1979.0)] {
        let r = run(&fixtures::cie_5_8(rho), &Settings::default());
        let mean_indirect = area_mean(&r, |s, v| {
            (s.illuminance[v] - s.illuminance_direct[v]) as f64
        });
        let want = rho * 10_000.0 / (96.0 * (1.0 - rho));
        assert!(rel(want, published) < 0.005, "formula check");
        eprintln!(
            "cie 5.8 rho {rho}: {mean_indirect:.3} vs {want:.3} rel {:.2e}",
            rel(mean_indirect, want)
        );
        eprintln!(
            "oracle: cie5.8/{rho} measured {:.3e}",
            rel(mean_indirect, want)
        );
        assert!(
            rel(mean_indirect, want) < 0.005,
            "ρ {rho}: mean indirect {mean_indirect} vs {want}"
        );
        // The direct part is exact at every vertex: I·cos/d² with I = Φ/4π.
        let i = 10_000.0 / (4.0 * PI);
        for s in &r.surfaces {
            for (v, p) in s.positions.iter().enumerate() {
                let d = DVec3::splat(2.0) - *p;
                let want = i * s.normals[v].dot(d.normalize()) / d.length_squared();
                assert!(
                    rel(s.illuminance_direct[v] as f64, want) < 2e-3,
                    "direct at {p}"
                );
            }
        }
    }
}

/// E below a parallel rectangle [x0,x1]×[z0,z1] at height c over the point (px, pz), by
/// superposition of the corner formula (docs/ANALYTIC.md §2 Lambert), times π·L.
fn parallel_rect_illuminance(l: f64, c: f64, x: [f64; 2], z: [f64; 2], px: f64, pz: f64) -> f64 {
    let corner = |a: f64, b: f64| -> f64 {
        // Signed: the rectangle from the foot point to (a, b).
        let (sa, sb) = (a.signum(), b.signum());
        let (a, b) = (a.abs() / c, b.abs() / c);
        let sx = (1.0 + a * a).sqrt();
        let sy = (1.0 + b * b).sqrt();
        sa * sb * (a / sx * (b / sx).atan() + b / sy * (a / sy).atan()) / (2.0 * PI)
    };
    let f =
        corner(x[1] - px, z[1] - pz) - corner(x[0] - px, z[1] - pz) - corner(x[1] - px, z[0] - pz)
            + corner(x[0] - px, z[0] - pz);
    PI * l * f
}

#[test]
fn lambertian_panel_over_floor_matches_lamberts_formula() {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", 0.5);
    let lamp = b.emitter("panel", 0.0, 1000.0);
    b.floor("floor", 3.0, 0.0, floor);
    // 1 × 0.5 m panel, 2 m up, facing down.
    b.quad(
        "panel",
        [
            DVec3::new(-0.5, 2.0, -0.25),
            DVec3::new(0.5, 2.0, -0.25),
            DVec3::new(0.5, 2.0, 0.25),
            DVec3::new(-0.5, 2.0, 0.25),
        ],
        lamp,
    );
    let r = run(&b.build(), &Settings::default());
    let floor = r.surfaces.iter().find(|s| s.surface == 0).unwrap();
    let mut worst: f64 = 0.0;
    for (v, p) in floor.positions.iter().enumerate() {
        let want = parallel_rect_illuminance(1000.0, 2.0, [-0.5, 0.5], [-0.25, 0.25], p.x, p.z);
        worst = worst.max(rel(floor.illuminance[v] as f64, want));
    }
    eprintln!("panel worst {worst:.2e}");
    eprintln!("oracle: panel-floor measured {worst:.3e}");
    assert!(worst < 0.005, "worst vertex off Lambert by {worst}");
}

#[test]
fn point_light_over_floor_follows_inverse_square_cosine_law() {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", 0.4);
    b.floor("floor", 4.0, 0.0, floor);
    let light = DVec3::new(0.3, 2.5, -0.2);
    b.point_light("bulb", light, 1000.0);
    let r = run(&b.build(), &Settings::default());
    let i = 1000.0 / (4.0 * PI);
    let mut worst: f64 = 0.0;
    for s in &r.surfaces {
        for (v, p) in s.positions.iter().enumerate() {
            let d = light - *p;
            let want = i * d.y / d.length().powi(3);
            worst = worst.max(rel(s.illuminance[v] as f64, want));
            assert!(
                rel(s.illuminance[v] as f64, want) < 0.002,
                "at {p}: {} vs {want}",
                s.illuminance[v]
            );
        }
    }
    eprintln!("point light worst {worst:.2e}");
    eprintln!("oracle: point-floor measured {worst:.3e}");
}

#[test]
fn opaque_box_casts_a_black_umbra() {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", 0.5);
    let black = b.material("blocker", 0.0);
    b.floor("floor", 4.0, 0.0, floor);
    // A 1 m cube from y = 1 to 2 under a light at y = 3: umbra on the floor is |x|,|z| < 0.5·(3/1)… clipped.
    b.axis_box(
        "blocker",
        DVec3::new(-0.5, 1.0, -0.5),
        DVec3::new(0.5, 2.0, 0.5),
        false,
        black,
    );
    b.point_light("bulb", DVec3::new(0.0, 3.0, 0.0), 1000.0);
    let r = run(&b.build(), &Settings::default());
    let floor = r.surfaces.iter().find(|s| s.surface == 0).unwrap();
    let mut in_umbra = 0;
    for (v, p) in floor.positions.iter().enumerate() {
        // Shadow of the cube's top edge at y = 2 from height 3 projects to ±1.5 on the floor; the
        // bottom edge at y = 1 to ±0.75. Points well inside |x|,|z| < 1.4 are in the umbra.
        if p.x.abs() < 1.4 && p.z.abs() < 1.4 {
            in_umbra += 1;
            assert_eq!(
                floor.illuminance_direct[v], 0.0,
                "direct light in the umbra at {p}"
            );
        } else if p.x.abs() > 1.6 || p.z.abs() > 1.6 {
            assert!(floor.illuminance_direct[v] > 0.0, "lit point dark at {p}");
        }
    }
    assert!(in_umbra > 10, "test must see umbra vertices ({in_umbra})");
    let umbra_max = (floor.positions.iter().zip(&floor.illuminance_direct))
        .filter(|(p, _)| p.x.abs() < 1.4 && p.z.abs() < 1.4)
        .fold(0.0f32, |m, (_, e)| m.max(*e));
    eprintln!("oracle: umbra measured {umbra_max:e}");
}

#[test]
fn same_bake_with_one_and_two_threads_is_bit_identical() {
    let scene = fixtures::closed_box_with_panel(DVec3::new(3.0, 2.5, 4.0), 0.7, 0.6, 2000.0);
    let mut settings = Settings {
        quality: Quality::Draft,
        always_trace: true,
        ..Default::default()
    };
    settings.threads = Some(1);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| run(&scene, &settings));
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| run(&scene, &settings));
    assert_eq!(one.surfaces.len(), two.surfaces.len());
    let differing = (one.surfaces.iter().zip(&two.surfaces))
        .flat_map(|(a, b)| {
            (a.illuminance.iter().zip(&b.illuminance)).chain(a.luminance.iter().zip(&b.luminance))
        })
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count();
    eprintln!("oracle: threads measured {differing}");
    for (a, b) in one.surfaces.iter().zip(&two.surfaces) {
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.illuminance), bits(&b.illuminance));
        assert_eq!(bits(&a.luminance), bits(&b.luminance));
    }
    assert_eq!(one.summary, two.summary);
}
