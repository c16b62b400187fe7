//! `bake diff` (`src/diff/`, `src/cli/diff.rs`) vertex by vertex: a bake against itself, against
//! a bake with 1 % more light (every value 1 % higher: radiosity is linear in the emitted flux),
//! against another solver quality on the same patches (figures equal to a computation straight
//! from the files: the benchmark's error measure), against a copy with one vertex edited in its
//! `.bin`; the tolerance boundaries of `--rtol`, `--atol` and `--floor`; the JSON fields.
//! `tests/diff_modes.rs` has the other modes, the mismatches and the timing.

mod support;

use luxbake::settings::Quality;
use serde_json::Value;
use support::bakes::*;
use support::scratch;

#[test]
fn a_bake_against_itself_is_all_zero() {
    let dir = scratch("diff-self");
    let scene = room(2400.0);
    let s = settings(Quality::Draft, 0.25);
    let a = write(&dir, "gltf", "gltf", &scene, &s);
    let glb = write(&dir, "glb", "glb", &scene, &s);
    let (run, d) = diff_json(&a, &a, &[]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(d["pass"], true);
    assert_eq!(d["failed"], 0);
    assert!(d["worst"].as_array().unwrap().is_empty());
    assert!(d["worstFailure"].is_null());
    for q in d["quantities"].as_array().unwrap() {
        let groups = q["byNode"]
            .as_array()
            .unwrap()
            .iter()
            .chain(q["byMaterial"].as_array().unwrap())
            .chain(std::iter::once(&q["overall"]));
        for g in groups {
            for s in ["abs", "rel"] {
                for f in ["max", "mean", "p95"] {
                    assert_eq!(g[s][f], 0.0, "{q}");
                }
            }
        }
    }
    // Every quantity has values: 4 nodes (divider front and back), probes on the grid.
    let ill = quantity(&d, "illuminance");
    let names: Vec<&str> = ill["byNode"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "room/floor",
            "room/wall_grey",
            "room/wall_white",
            "room/divider"
        ]
    );
    assert!(number(&quantity(&d, "probeFaces")["overall"]["values"]) >= 6.0 * 9.0);
    // workingPlane repeats the +y faces of the working-plane probes: not counted twice.
    let values: f64 = QUANTITIES[..4]
        .iter()
        .map(|k| number(&quantity(&d, k)["overall"]["values"]))
        .sum();
    assert_eq!(number(&d["values"]), values);
    assert!(number(&quantity(&d, "workingPlane")["overall"]["values"]) >= 9.0);

    // The text: same verdict, last line; .gltf against .glb of the same bake.
    let run = diff(&a, &glb, &[]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(
        last_line(&run.stdout).starts_with("OK: all "),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("room/divider"), "{}", run.stdout);
}

#[test]
fn one_percent_more_light_is_one_percent_everywhere() {
    let dir = scratch("diff-flux");
    let s = settings(Quality::Draft, 0.25);
    let b = write(&dir, "b", "gltf", &room(2400.0), &s);
    let a = write(&dir, "a", "gltf", &room(2424.0), &s);
    // Well above the floor, |a − b| / b = 0.01 (to f32 rounding); below it, less.
    let (run, d) = diff_json(&a, &b, &[]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    for key in QUANTITIES {
        let q = quantity(&d, key);
        let rel = number(&q["overall"]["rel"]["max"]);
        assert!((rel - 0.01).abs() < 2e-5, "{key}: {rel}");
        assert!(number(&q["overall"]["failed"]) > 0.0);
    }
    // The worst places are all 1 % off (ties broken by the relative difference, then order).
    let worst = d["worst"].as_array().unwrap();
    assert_eq!(worst.len(), 10);
    for w in worst {
        let (abs, b) = (number(&w["abs"]), number(&w["b"]));
        assert!((abs - 0.01 * b).abs() < 2e-5 * b, "{w}");
        assert_eq!(w["pass"], false);
    }
    assert!(number(&worst[0]["rel"]) >= number(&worst[9]["rel"]));
    let (run, d) = diff_json(&a, &b, &["--rtol", "0.0101"]);
    assert_eq!(run.code, Some(0), "{}", run.stdout);
    assert_eq!(d["failed"], 0);
    // The other way round, |a − b| / b = 0.01 / 1.01.
    let (_, d) = diff_json(&b, &a, &[]);
    let rel = number(&quantity(&d, "illuminance")["overall"]["rel"]["max"]);
    assert!((rel - 0.01 / 1.01).abs() < 2e-5, "{rel}");
}

/// The harness's error measure between two qualities of one scene is `bake diff --json`'s: the
/// figures equal a computation straight from the two files.
#[test]
fn two_solver_qualities_give_the_error_computed_from_the_files() {
    let dir = scratch("diff-quality");
    let scene = room(2400.0);
    let draft = write(
        &dir,
        "draft",
        "gltf",
        &scene,
        &settings(Quality::Draft, 0.25),
    );
    let high = write(&dir, "high", "gltf", &scene, &settings(Quality::High, 0.25));
    let (run, d) = diff_json(&draft, &high, &[]);
    let floor = default_floor(&high);
    assert_eq!(number(&d["floor"]), floor);
    let (ea, eb) = (
        attribute(&draft, "_ILLUMINANCE"),
        attribute(&high, "_ILLUMINANCE"),
    );
    let pairs: Vec<(f64, f64)> = ea
        .into_iter()
        .flatten()
        .zip(eb.into_iter().flatten())
        .collect();
    let abs: Vec<f64> = pairs.iter().map(|(a, b)| (a - b).abs()).collect();
    let rel: Vec<f64> = pairs
        .iter()
        .map(|(a, b)| (a - b).abs() / b.abs().max(floor))
        .collect();
    let failed = pairs
        .iter()
        .filter(|(a, b)| (a - b).abs() > 1e-3 * b.abs().max(floor))
        .count();
    let ill = &quantity(&d, "illuminance")["overall"];
    assert_eq!(number(&ill["values"]), pairs.len() as f64);
    assert_eq!(number(&ill["failed"]), failed as f64);
    for (key, expect) in [("abs", max_mean_p95(abs)), ("rel", max_mean_p95(rel))] {
        let got = ["max", "mean", "p95"].map(|f| number(&ill[key][f]));
        assert_eq!(got[0], expect[0], "{key} max");
        assert!(
            (got[1] - expect[1]).abs() <= 1e-12 * expect[1],
            "{key} mean"
        );
        assert_eq!(got[2], expect[2], "{key} p95");
    }
    // The qualities differ (far-field ratio, solver tolerance), but not by much: ~1 % on
    // average, up to ~16 % at a dim floor vertex behind the divider (draft's τ = 0.45: with
    // τ = 0.2 draft reads high's value there).
    let rel_max = number(&ill["rel"]["max"]);
    let rel_mean = number(&ill["rel"]["mean"]);
    assert!(rel_max > 0.0 && rel_max < 0.2, "{rel_max}");
    assert!(rel_mean < 0.02, "{rel_mean}");
    assert_eq!(run.code, Some(if failed > 0 { 1 } else { 0 }));
    // Probes near the divider move more (up to ~20 %): a loose tolerance passes everything.
    let (run, _) = diff_json(&draft, &high, &["--rtol", "1"]);
    assert_eq!(run.code, Some(0), "{}", run.stdout);
}

#[test]
fn an_edited_vertex_is_named_with_its_position() {
    let dir = scratch("diff-edit");
    let b = write(
        &dir,
        "b",
        "gltf",
        &room(2400.0),
        &settings(Quality::Draft, 0.25),
    );
    let a = copy(&b, &dir, "a");
    let vertex = 7;
    let (old, position) = edit(&a, "divider", 1, vertex, 0.0);
    edit(&a, "divider", 1, vertex, old * 1.5 + 10.0);
    assert!(old > 0.0);

    let run = diff(&a, &b, &[]);
    assert_eq!(run.code, Some(1), "{}", run.stdout);
    let last = last_line(&run.stdout);
    let p = position.map(|c| luxbake::diff::render::num(c.into()));
    let expect = format!(
        "node room/divider primitive 1 vertex {vertex} at ({}, {}, {}) m",
        p[0], p[1], p[2]
    );
    assert!(last.starts_with("FAIL: 1 of "), "{last}");
    assert!(last.contains(&expect), "{last}\nexpected {expect}");
    let (_, d) = diff_json(&a, &b, &["--worst", "3"]);
    assert_eq!(d["failed"], 1);
    assert_eq!(d["worst"].as_array().unwrap().len(), 1);
    let w = &d["worstFailure"];
    assert_eq!(w, &d["worst"][0]);
    assert_eq!(w["quantity"], "illuminance");
    assert_eq!(w["kind"], "vertex");
    assert_eq!(w["node"], "room/divider");
    assert_eq!(w["material"], "card");
    assert_eq!(w["primitive"], 1);
    assert_eq!(w["vertex"], vertex);
    assert!(w["face"].is_null());
    assert_eq!(w["pass"], false);
    assert_eq!(number(&w["b"]), f64::from(old));
    assert_eq!(number(&w["a"]), f64::from(old * 1.5 + 10.0));
    for k in 0..3 {
        assert_eq!(number(&w["position"][k]), f64::from(position[k]));
    }
    let by_node = quantity(&d, "illuminance")["byNode"]
        .as_array()
        .unwrap()
        .clone();
    for g in by_node {
        let failed = if g["name"] == "room/divider" { 1 } else { 0 };
        assert_eq!(g["failed"], failed, "{g}");
    }
    // With --worst 0 the list is empty but the verdict still names the place.
    let run = diff(&a, &b, &["--worst", "0"]);
    assert_eq!(run.code, Some(1));
    assert!(!run.stdout.contains("worst places"), "{}", run.stdout);
    assert!(last_line(&run.stdout).contains(&expect));
}

#[test]
fn tolerance_boundaries() {
    let dir = scratch("diff-boundaries");
    let b = write(
        &dir,
        "b",
        "gltf",
        &room(2400.0),
        &settings(Quality::Draft, 0.25),
    );
    let a = copy(&b, &dir, "a");
    let code = |options: &[&str]| diff(&a, &b, options).code;
    // b = 512, a = 513: |a − b| = 1, relative 2⁻⁹ (all exact in binary).
    edit(&b, "floor", 0, 3, 512.0);
    edit(&a, "floor", 0, 3, 513.0);
    assert_eq!(code(&["--rtol", "0.001953125", "--floor", "1"]), Some(0));
    assert_eq!(code(&["--rtol", "0.00195", "--floor", "1"]), Some(1));
    assert_eq!(code(&["--rtol", "0", "--atol", "1"]), Some(0));
    assert_eq!(code(&["--rtol", "0", "--atol", "0.999"]), Some(1));
    // atol and rtol add up: 0.5 + 2⁻¹⁰·512 = 1.
    assert_eq!(
        code(&["--rtol", "0.0009765625", "--atol", "0.5", "--floor", "1"]),
        Some(0)
    );
    assert_eq!(
        code(&["--rtol", "0.0009765625", "--atol", "0.49", "--floor", "1"]),
        Some(1)
    );
    // A dark vertex: b = 1, a = 1.5; rtol 0.25 passes only when the floor is ≥ 2 lx.
    edit(&b, "floor", 0, 3, 1.0);
    edit(&a, "floor", 0, 3, 1.5);
    assert_eq!(code(&["--rtol", "0.25", "--floor", "2"]), Some(0));
    assert_eq!(code(&["--rtol", "0.25", "--floor", "1.9"]), Some(1));
    // The default floor: 1 % of B's nearest-rank 99th percentile of _ILLUMINANCE.
    let (_, d) = diff_json(&a, &b, &[]);
    let mut all: Vec<f64> = Vec::new();
    let json: Value = serde_json::from_slice(&std::fs::read(&b).unwrap()).unwrap();
    let file = support::gltf_read::read(&b);
    for mesh in json["meshes"].as_array().unwrap() {
        for p in mesh["primitives"].as_array().unwrap() {
            if let Some(acc) = p["attributes"]["_ILLUMINANCE"].as_u64() {
                all.extend(
                    file.floats(acc as usize)
                        .iter()
                        .map(|v| f64::from(v[0]).abs()),
                );
            }
        }
    }
    all.sort_by(f64::total_cmp);
    let p99 = all[(0.99 * all.len() as f64).ceil() as usize - 1];
    assert_eq!(number(&d["floor"]), 0.01 * p99);
    assert_eq!(d["floorIsDefault"], true);
    assert_eq!(
        number(&quantity(&d, "luminance")["floor"]),
        0.01 * p99 / std::f64::consts::PI
    );
    // Bad values are usage errors.
    for bad in [["--rtol", "-1"], ["--atol", "nan"], ["--floor", "0"]] {
        let run = diff(&a, &b, &bad);
        assert_eq!(run.code, Some(2), "{bad:?}: {}", run.stderr);
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    }
}

#[test]
fn json_has_the_documented_fields() {
    let dir = scratch("diff-json");
    let b = write(
        &dir,
        "b",
        "gltf",
        &room(2400.0),
        &settings(Quality::Draft, 0.25),
    );
    let a = copy(&b, &dir, "a");
    edit(&a, "floor", 0, 0, 1000.0);
    let (run, d) = diff_json(&a, &b, &["--atol", "0.5", "--rtol", "0.01", "--floor", "3"]);
    assert_eq!(run.code, Some(1));
    let keys = |v: &Value| -> Vec<String> { v.as_object().unwrap().keys().cloned().collect() };
    assert_eq!(
        keys(&d),
        [
            "a",
            "b",
            "mode",
            "rtol",
            "atol",
            "floor",
            "floorIsDefault",
            "pass",
            "values",
            "failed",
            "quantities",
            "worst",
            "worstFailure"
        ]
    );
    assert_eq!(d["a"], a.display().to_string());
    assert_eq!(d["mode"], "vertices");
    assert_eq!(
        (number(&d["rtol"]), number(&d["atol"]), number(&d["floor"])),
        (0.01, 0.5, 3.0)
    );
    assert_eq!(d["floorIsDefault"], false);
    let order: Vec<&str> = d["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["quantity"].as_str().unwrap())
        .collect();
    assert_eq!(order, QUANTITIES);
    for q in d["quantities"].as_array().unwrap() {
        assert_eq!(
            keys(q),
            [
                "quantity",
                "unit",
                "atol",
                "floor",
                "overall",
                "byNode",
                "byMaterial"
            ]
        );
        let group_keys = ["name", "values", "failed", "abs", "rel"];
        assert_eq!(keys(&q["overall"]), group_keys);
        assert_eq!(q["overall"]["name"], "all");
        assert_eq!(keys(&q["overall"]["abs"]), ["max", "mean", "p95"]);
        for g in q["byNode"].as_array().unwrap() {
            assert_eq!(keys(g), group_keys);
        }
    }
    let lum = quantity(&d, "luminance");
    assert_eq!(lum["unit"], "cd/m²");
    assert_eq!(number(&lum["atol"]), 0.5 / std::f64::consts::PI);
    let materials: Vec<&str> = quantity(&d, "illuminance")["byMaterial"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["name"].as_str().unwrap())
        .collect();
    assert_eq!(materials, ["grey", "white", "card"]);
    assert!(
        quantity(&d, "probeFaces")["byMaterial"]
            .as_array()
            .unwrap()
            .is_empty()
    );
    let probe_nodes = quantity(&d, "probeFaces")["byNode"]
        .as_array()
        .unwrap()
        .clone();
    assert!(
        probe_nodes[0]["name"]
            .as_str()
            .unwrap()
            .starts_with("probes/grid/")
    );
    assert_eq!(
        keys(&d["worst"][0]),
        [
            "quantity",
            "kind",
            "node",
            "material",
            "primitive",
            "vertex",
            "face",
            "position",
            "a",
            "b",
            "abs",
            "rel",
            "tolerance",
            "pass"
        ]
    );
    let w = &d["worst"][0];
    let b0 = number(&w["b"]);
    assert_eq!(number(&w["tolerance"]), 0.5 + 0.01 * b0.abs().max(3.0));
    assert_eq!(number(&w["rel"]), number(&w["abs"]) / b0.abs().max(3.0));
}
