//! `bake generate openplan`: the benchmark's open-plan office, written as an input glTF.
//! - the same seed gives byte-identical files (.gltf + .bin and .glb), another seed differs;
//! - the triangle count lands within 40 triangles of any target from 1.2 × 10⁴ up (the small
//!   preset, the smallest layout, has ~10⁴ + 5 %), and the count in the scene's extras is the one
//!   written;
//! - the file loads back with `luxbake::import::load` as the scene built in code: its materials
//!   (with `LUXBAKE_material` reflectance and emission), its three IES profiles under
//!   `EXT_lights_ies` and the small preset's 18 luminaires (12 linear, 4 downlights, 2 spots);
//! - every luminaire hangs just under the ceiling, inside the floor plate, aiming down;
//! - the Khronos glTF-Validator finds no error or warning (skipped when absent, except under
//!   CI: see `support/tools.rs`);
//! - a draft bake of the small preset runs, emits what the profiles and panels say, loses nothing
//!   out of the closed room and closes its energy balance within 1 %.

mod support;

use glam::DVec3;
use luxbake::fixtures::openplan::{CEILING, DEFAULT_SEED};
use luxbake::fixtures::{OpenPlan, open_plan};
use luxbake::import::load;
use luxbake::scene::{EmissionAmount, Scene};
use serde_json::Value;
use std::path::{Path, PathBuf};
use support::cli::{bake, listing};
use support::{scratch, tools};

/// Run `bake generate openplan` with `args` and `-o out`; panics unless it succeeds.
fn generate(args: &[&str], out: &Path) {
    let mut all = vec!["generate", "openplan", "-q", "-o", out.to_str().unwrap()];
    all.extend_from_slice(args);
    let run = bake(&all);
    assert!(run.ok(), "bake {all:?}: {run:?}");
    assert!(run.stderr.is_empty(), "-q prints nothing: {}", run.stderr);
}

/// The small preset (default seed) written as `dir/office.gltf` (+ `office.<hash>.bin`).
fn small(dir: &Path) -> PathBuf {
    let path = dir.join("office.gltf");
    generate(&["--size", "small"], &path);
    path
}

fn triangles(scene: &Scene) -> usize {
    scene.surfaces.iter().map(|s| s.triangles.len()).sum()
}

fn generator(scene: &Scene) -> &Value {
    &scene.extras.as_ref().expect("scene extras")["generator"]
}

#[test]
fn same_seed_same_bytes_other_seed_other_bytes() {
    let dir = scratch("generate-determinism");
    let read = |p: PathBuf| std::fs::read(p).unwrap();
    let mut runs = Vec::new();
    for (sub, seed) in [("a", "7"), ("b", "7"), ("c", "8")] {
        let d = dir.join(sub);
        std::fs::create_dir(&d).unwrap();
        let args = ["--size", "small", "--seed", seed];
        generate(&args, &d.join("office.gltf"));
        generate(&args, &d.join("office.glb"));
        assert_eq!(listing(&d), ["office.#.bin", "office.glb", "office.gltf"]);
        runs.push((
            read(d.join("office.gltf")),
            read(support::hashed(&d, "office.#.bin")),
            read(d.join("office.glb")),
        ));
    }
    let (a, b, c) = (&runs[0], &runs[1], &runs[2]);
    // Lengths first, so that a failure does not print megabytes.
    for (name, x, y) in [
        ("office.gltf", &a.0, &b.0),
        ("office.bin", &a.1, &b.1),
        ("office.glb", &a.2, &b.2),
    ] {
        assert_eq!(x.len(), y.len(), "{name}: length differs for the same seed");
        let first = x.iter().zip(y).position(|(p, q)| p != q);
        assert_eq!(
            first, None,
            "{name}: first differing byte for the same seed"
        );
    }
    assert_ne!(a.1, c.1, "seeds 7 and 8 give the same geometry");
    assert_ne!(a.2, c.2, "seeds 7 and 8 give the same .glb");
    // The library gives the same scene as the file (the CLI adds nothing of its own).
    let scene = open_plan(&OpenPlan::new(OpenPlan::small().target_triangles, 7));
    let loaded = load(&dir.join("a/office.glb"), &Default::default()).unwrap();
    assert_eq!(triangles(&scene), triangles(&loaded));
    assert_eq!(scene.extras, loaded.extras);
}

#[test]
fn triangle_count_lands_near_the_target() {
    // Two neighbouring chair tessellations are shared out among the chairs; below 3000
    // triangles a chair, neighbouring tessellations are at most 80 triangles apart, so the total
    // lands within 40 triangles of any target from 1.2 × 10⁴ up (0.34 % at 1.2 × 10⁴, 0.004 % at
    // 10⁶), whatever the seed.
    for target in [12_000, 20_000, 50_000, 100_000, 258_532, 1_000_000] {
        for seed in [DEFAULT_SEED, 2, 99] {
            let scene = open_plan(&OpenPlan::new(target, seed));
            let n = triangles(&scene);
            assert_eq!(generator(&scene)["triangles"], n, "extras count");
            assert!(
                n.abs_diff(target) <= 40,
                "target {target}, seed {seed}: {n} triangles"
            );
        }
    }
    // The small preset is the smallest floor with the coarsest chairs: ~10⁴ (+5 %), and no
    // smaller target gives less.
    let small = open_plan(&OpenPlan::small());
    let n = triangles(&small);
    assert!(
        (10_000..=10_500).contains(&n),
        "small preset: {n} triangles"
    );
    assert_eq!(triangles(&open_plan(&OpenPlan::new(1, DEFAULT_SEED))), n);
}

#[test]
fn triangles_zero_is_refused() {
    let dir = scratch("generate-zero");
    let out = dir.join("x.glb");
    let run = bake([
        "generate",
        "openplan",
        "--triangles",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!run.ok(), "{run:?}");
    assert!(run.stderr.starts_with("error: "), "{}", run.stderr);
    assert_eq!(listing(&dir), Vec::<String>::new());
}

#[test]
fn the_file_loads_back_as_the_scene_built_in_code() {
    let dir = scratch("generate-load");
    let loaded = load(&small(&dir), &Default::default()).unwrap();
    let built = open_plan(&OpenPlan::small());
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(loaded.name.as_deref(), Some("open-plan office"));

    // Materials: names, reflectances and the emissive panel, as built.
    let names: Vec<&str> = loaded
        .materials
        .iter()
        .map(|m| m.name.as_deref().unwrap())
        .collect();
    for expected in [
        "carpet",
        "ceiling",
        "wall",
        "meeting_wall",
        "column",
        "desk_top",
        "screen_fabric",
        "monitor",
        "meeting_table",
        "chair_frame",
        "chair_blue",
        "led_panel",
    ] {
        assert!(
            names.contains(&expected),
            "{expected} missing from {names:?}"
        );
    }
    assert_eq!(loaded.materials.len(), built.materials.len());
    for (a, b) in loaded.materials.iter().zip(&built.materials) {
        assert_eq!(a.name, b.name);
        assert!(
            (a.reflectance - b.reflectance).abs().max_element() < 1e-12,
            "{:?}: {} vs {}",
            a.name,
            a.reflectance,
            b.reflectance
        );
        assert_eq!(a.emission.is_some(), b.emission.is_some(), "{:?}", a.name);
    }
    let emitting: Vec<_> = loaded
        .materials
        .iter()
        .filter_map(|m| m.emission.map(|e| (m.name.as_deref().unwrap(), e)))
        .collect();
    assert_eq!(emitting.len(), 1, "only the LED panels emit");
    assert_eq!(emitting[0].0, "led_panel");
    assert!(matches!(
        emitting[0].1.amount,
        EmissionAmount::Luminance(l) if l == 3200.0
    ));

    // Geometry: the same surfaces and triangles, positions to f32 precision.
    assert_eq!(loaded.surfaces.len(), built.surfaces.len());
    for (a, b) in loaded.surfaces.iter().zip(&built.surfaces) {
        assert_eq!(a.triangles, b.triangles, "{}", a.source_path);
        assert_eq!(a.material, b.material, "{}", a.source_path);
        let worst = a
            .positions
            .iter()
            .zip(&b.positions)
            .map(|(p, q)| (*p - *q).abs().max_element())
            .fold(0.0, f64::max);
        assert!(worst < 1e-5, "{}: {worst} m", a.source_path);
    }
    assert_eq!(triangles(&loaded), generator(&loaded)["triangles"]);

    // Profiles under EXT_lights_ies, and the luminaires of each kind.
    let profiles: Vec<(&str, &str)> = loaded
        .profiles
        .iter()
        .map(|p| (p.name.as_deref().unwrap(), p.source_path.as_str()))
        .collect();
    assert_eq!(
        profiles,
        [
            ("miral_58w", "/extensions/EXT_lights_ies/lights/0"),
            ("downlight_wide", "/extensions/EXT_lights_ies/lights/1"),
            ("cns70_50w", "/extensions/EXT_lights_ies/lights/2"),
        ]
    );
    let count = |k: usize| loaded.luminaires.iter().filter(|l| l.profile == k).count();
    assert_eq!((count(0), count(1), count(2)), (12, 4, 2));
    assert_eq!(loaded.luminaires.len(), 18);
    let g = generator(&loaded);
    assert_eq!(
        (&g["linearLuminaires"], &g["downlights"], &g["spots"]),
        (&Value::from(12), &Value::from(4), &Value::from(2))
    );
    for l in &loaded.luminaires {
        assert!(l.source_path.ends_with("/extensions/EXT_lights_ies"));
        assert_eq!((l.multiplier, l.color), (1.0, DVec3::ONE), "{:?}", l.name);
    }
    for (a, b) in loaded.luminaires.iter().zip(&built.luminaires) {
        assert_eq!(a.name, b.name);
        assert!((a.position - b.position).length() < 1e-9, "{:?}", a.name);
    }
}

#[test]
fn luminaires_hang_under_the_ceiling_inside_the_floor_plate() {
    for (target, seed) in [
        (10_000, DEFAULT_SEED),
        (100_000, DEFAULT_SEED),
        (300_000, 5),
    ] {
        let scene = open_plan(&OpenPlan::new(target, seed));
        // The room's extent from its geometry, not from what the generator says.
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for p in scene.surfaces.iter().flat_map(|s| &s.positions) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        assert!(lo.abs_diff_eq(DVec3::ZERO, 1e-9), "{lo}");
        assert!((hi.y - CEILING).abs() < 1e-9, "{hi}");
        let (w, d) = OpenPlan::new(target, seed).floor_plate();
        assert!((hi.x - w).abs() < 1e-9 && (hi.z - d).abs() < 1e-9, "{hi}");
        assert!(!scene.luminaires.is_empty());
        for l in &scene.luminaires {
            let p = l.position;
            let name = l.name.as_deref().unwrap_or("?");
            assert!(
                p.y < CEILING && p.y > CEILING - 0.05,
                "{name}: {p} not just under the ceiling"
            );
            // The luminous opening (the file's, rotated into the room) stays inside too.
            let o = l
                .opening
                .unwrap_or_else(|| scene.profiles[l.profile].photometry.opening());
            let reach = 0.5 * o.length.abs().max(o.width.abs());
            assert!(
                p.x - reach > 0.0 && p.x + reach < w && p.z - reach > 0.0 && p.z + reach < d,
                "{name}: {p} (± {reach}) outside the {w} × {d} m floor plate"
            );
            let nadir = l.world_from_photometric * DVec3::NEG_Z;
            assert!(nadir.abs_diff_eq(-DVec3::Y, 1e-12), "{name} aims {nadir}");
        }
        // The emissive panels too: under the ceiling, facing down, inside the plate.
        let panel = scene
            .materials
            .iter()
            .position(|m| m.emission.is_some())
            .unwrap();
        let panels: Vec<_> = scene
            .surfaces
            .iter()
            .filter(|s| s.material == panel)
            .collect();
        assert!(!panels.is_empty());
        for s in panels {
            for (p, n) in s.positions.iter().zip(&s.normals) {
                assert!(p.y < CEILING && p.y > CEILING - 0.05, "{p}");
                assert!(p.x > 0.0 && p.x < w && p.z > 0.0 && p.z < d, "{p}");
                assert!(n.abs_diff_eq(-DVec3::Y, 1e-12), "{n}");
            }
        }
    }
}

/// Validator: no error or warning (information such as the unvalidated LUXBAKE extensions and
/// the profiles' bufferViews, which only extensions use, is allowed).
fn assert_valid(path: &Path) {
    let report = tools::validate(path);
    assert_eq!(
        (report.errors, report.warnings),
        (0, 0),
        "{}:\n{}",
        path.display(),
        report.listing()
    );
}

#[test]
fn validator_finds_no_errors_or_warnings() {
    if !tools::have_validator() {
        return;
    }
    let dir = scratch("generate-validate");
    assert_valid(&small(&dir));
    let glb = dir.join("office.glb");
    generate(&["--triangles", "30000", "--seed", "3"], &glb);
    assert_valid(&glb);
    let report = tools::validate(&glb);
    let written = report.json["info"]["totalTriangleCount"].as_u64().unwrap();
    let scene = load(&glb, &Default::default()).unwrap();
    assert_eq!(written, generator(&scene)["triangles"].as_u64().unwrap());
}

/// At default quality, as issue 55 asks (no balance warning on the generated floors). A draft
/// bake reads 4.0·10⁻³ since the contacts cut only along seams' own lengths and part creases
/// (2.0·10⁻⁴ before; default went 1.7·10⁻³ → 1.6·10⁻⁴): direct light into the patches exceeds
/// what the sources emit by 0.4 % at draft's coarse patches, open in issue 55's note.
#[test]
fn default_bake_of_the_small_preset_closes_its_energy_balance() {
    let dir = scratch("generate-bake");
    let input = small(&dir);
    let (output, summary) = (dir.join("lit.glb"), dir.join("summary.json"));
    let run = bake([
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "-q",
        "--summary-json",
        summary.to_str().unwrap(),
    ]);
    assert!(run.ok(), "{run:?}");
    assert!(
        !run.stderr.contains("warning"),
        "no warning expected: {}",
        run.stderr
    );
    let s: Value = serde_json::from_slice(&std::fs::read(&summary).unwrap()).unwrap();
    let e = &s["energy"];
    let lm = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("energy.{k}: {e}"));
    // 12 Miral fittings (3380 lm), 4 wide downlights (1800 lm), 2 CNS70 spots (792 lm), and 4
    // panels of 0.6 × 0.6 m at 3200 cd/m² (π · 3200 · 0.36 lm each).
    let lights = 12.0 * 3380.0 + 4.0 * 1800.0 + 2.0 * 792.0;
    let panels = 4.0 * std::f64::consts::PI * 3200.0 * 0.36;
    let close = |got: f64, want: f64| (got - want).abs() <= 0.01 * want;
    assert!(close(lm("emittedByLightsLm"), lights), "{e}");
    assert!(close(lm("emittedBySurfacesLm"), panels), "{e}");
    assert!(close(lm("emittedLm"), lights + panels), "{e}");
    // A closed room: nothing escapes; what is emitted is absorbed.
    assert!(lm("escapedLm") <= 1e-6 * lm("emittedLm"), "{e}");
    let balance = lm("emittedLm") - lm("absorbedLm") - lm("escapedLm");
    assert!(
        (balance - lm("balanceErrorLm")).abs() < 1e-6 * lm("emittedLm"),
        "{e}"
    );
    assert!(lm("balanceErrorRelative").abs() < 0.01, "{e}");
    assert_eq!(s["solver"]["converged"], true, "{}", s["solver"]);
    let patches = s["counts"]["patches"].as_u64().unwrap();
    let n = triangles(&load(&input, &Default::default()).unwrap()) as u64;
    assert!(patches >= n, "{patches} patches for {n} triangles");
    if tools::have_validator() {
        assert_valid(&output);
    }
}
