//! Black surfaces (reflectance 0, emitting nothing) are linked to nothing: nobody gathers light
//! from them, and a scene black throughout skips inter-reflection altogether. Checked against a
//! closed form (a sphere with a black cap, where the inter-reflected light is the same
//! everywhere) and against the same bake with the skip turned off (`Settings::gather_black`).

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::{self, SceneBuilder};
use luxbake::progress::Silent;
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::Settings;
use luxbake::summary::Counts;

fn run(scene: &Scene, gather_black: bool) -> BakeResult {
    let settings = Settings {
        gather_black,
        ..Settings::default()
    };
    bake(scene, &settings, &Silent).expect("bake")
}

fn counts(r: &BakeResult) -> &Counts {
    &r.summary.counts
}

/// Inter-reflected illuminance (lx) at every vertex of every baked surface.
fn indirect(r: &BakeResult) -> Vec<f64> {
    r.surfaces
        .iter()
        .flat_map(|s| s.illuminance.iter().zip(&s.illuminance_direct))
        .map(|(e, d)| (e - d) as f64)
        .collect()
}

#[test]
fn sphere_with_black_cap_matches_the_closed_form_with_and_without_links_to_black() {
    // Inside a sphere every element sees every other in proportion to its area, so the
    // reflected flux R obeys R = ρ·(Φ·(1 − s₀) + (1 − f₀)·R), with f₀ the black cap's share of
    // the area and s₀ its share of the light's flux, and the inter-reflected illuminance is R/S
    // at every point, the black cap included.
    let (rho, flux) = (0.8, 1000.0);
    let sphere = fixtures::sphere_interior(2.0, (24, 48), -0.4, rho, flux);
    let f0 = sphere.black_area / sphere.area;
    assert!((0.35..0.45).contains(&f0), "black share {f0}");
    let reflected = rho * flux * (1.0 - sphere.black_light_share) / (1.0 - rho * (1.0 - f0));
    let want = reflected / sphere.area;
    let mut links = Vec::new();
    for gather_black in [false, true] {
        let r = run(&sphere.scene, gather_black);
        let e = indirect(&r);
        let mean = e.iter().sum::<f64>() / e.len() as f64;
        let worst = e
            .iter()
            .map(|e| (e - want).abs() / want)
            .fold(0.0, f64::max);
        eprintln!(
            "gather_black {gather_black}: {} links, E_ind mean {mean:.4} lx, closed form {want:.4} lx, worst vertex {worst:.2e}",
            counts(&r).links
        );
        let links_to_black = if gather_black { "with" } else { "without" };
        eprintln!(
            "oracle: black-cap/{links_to_black}/mean measured {:.3e}",
            (mean - want).abs() / want
        );
        eprintln!("oracle: black-cap/{links_to_black}/worst measured {worst:.3e}");
        assert!((mean - want).abs() < 0.005 * want, "mean {mean} vs {want}");
        assert!(worst < 0.03, "worst vertex off by {worst}");
        let energy = &r.summary.energy;
        assert!(energy.balance_error_relative < 0.005, "{energy:?}");
        links.push(counts(&r).links);
    }
    // The black cap is 40 % of the sphere: without links to it the rows are much shorter.
    assert!(
        (links[0] as f64) < 0.7 * links[1] as f64,
        "links without black {} vs with {}",
        links[0],
        links[1]
    );
}

#[test]
fn black_room_skips_inter_reflection_and_bakes_the_same_light() {
    // A closed black box with a point light and a black tile standing in it: nothing
    // is reflected, so no receiver gathers anything and the links stage traces no ray. The
    // bake with links to black surfaces computes the same zero and the same direct light.
    let mut b = SceneBuilder::new();
    let walls = b.material("black", 0.0);
    b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 5.0), true, walls);
    b.point_light("lamp", DVec3::new(1.5, 2.5, 2.0), 1000.0);
    b.quad(
        "box_top",
        [
            DVec3::new(2.0, 0.5, 2.0),
            DVec3::new(2.0, 0.5, 3.0),
            DVec3::new(3.0, 0.5, 3.0),
            DVec3::new(3.0, 0.5, 2.0),
        ],
        walls,
    );
    let scene = b.build();
    let skipped = run(&scene, false);
    let gathered = run(&scene, true);
    assert_eq!(counts(&skipped).links, 0);
    assert_eq!(counts(&skipped).rays_by_stage.links, 0);
    assert!(counts(&gathered).links > 1000);
    assert!(counts(&gathered).rays_by_stage.links > 0);
    assert!(indirect(&skipped).iter().all(|e| *e == 0.0));
    assert!(indirect(&gathered).iter().all(|e| *e == 0.0));
    for (a, b) in skipped.surfaces.iter().zip(&gathered.surfaces) {
        assert_eq!(a.illuminance, b.illuminance);
        assert!(
            a.illuminance.iter().any(|e| *e > 1.0),
            "the lamp lights the room"
        );
    }
    let (ea, eb) = (&skipped.summary.energy, &gathered.summary.energy);
    assert_eq!(ea.absorbed_lm, eb.absorbed_lm);
    assert!(ea.balance_error_relative < 0.005, "{ea:?}");
}
