//! `bake fit`: dimming factors fitted to a design.
//!
//! - A room built so that an exact solution exists (the targets are what a bake of the room with
//!   known factors gives): the fit reaches every target within 1 % and finds the factors.
//! - The office with the seed's design (Table 1): baking the fitted scene gives, on every
//!   surface, what `fit` reported, within 0.5 %.
//! - Bad groups, a working-plane target without a working plane, an output over the input.

use glam::DVec3;
use luxbake::fixtures::SceneBuilder;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bake(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bake"))
        .args(args)
        .output()
        .expect("bake runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn ok(args: &[&str]) -> String {
    let (code, out, err) = bake(args);
    assert_eq!(code, Some(0), "bake {args:?}: {err}");
    out
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("luxbake-fit-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A 6 × 3 × 4 m room (+Y up) with two point lights (left and right), an emitting panel on the
/// ceiling and a desk standing on the floor; each light multiplied by `factors`.
fn room(factors: [f64; 3]) -> luxbake::scene::Scene {
    let mut b = SceneBuilder::new();
    let walls = b.material("walls", 0.6);
    let floor = b.material("floor_mat", 0.25);
    let desk = b.material("desk_mat", 0.4);
    let panel = b.emitter("panel", 0.0, 400.0 * factors[2]);
    let q = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let (w, h, d) = (6.0, 3.0, 4.0);
    b.quad(
        "floor",
        [q(0., 0., 0.), q(0., 0., d), q(w, 0., d), q(w, 0., 0.)],
        floor,
    );
    b.quad(
        "ceiling",
        [q(0., h, 0.), q(w, h, 0.), q(w, h, d), q(0., h, d)],
        walls,
    );
    b.quad(
        "wall_west",
        [q(0., 0., 0.), q(0., h, 0.), q(0., h, d), q(0., 0., d)],
        walls,
    );
    b.quad(
        "wall_east",
        [q(w, 0., 0.), q(w, 0., d), q(w, h, d), q(w, h, 0.)],
        walls,
    );
    b.quad(
        "wall_north",
        [q(0., 0., 0.), q(w, 0., 0.), q(w, h, 0.), q(0., h, 0.)],
        walls,
    );
    b.quad(
        "wall_south",
        [q(0., 0., d), q(0., h, d), q(w, h, d), q(w, 0., d)],
        walls,
    );
    b.axis_box("desk", q(2.5, 0.0, 1.5), q(3.5, 0.75, 2.5), false, desk);
    // The panel 1 mm under the ceiling, facing down, over the east half.
    b.quad(
        "panel",
        [
            q(4.0, h - 0.001, 1.5),
            q(5.0, h - 0.001, 1.5),
            q(5.0, h - 0.001, 2.5),
            q(4.0, h - 0.001, 2.5),
        ],
        panel,
    );
    b.point_light("lamp_left", q(1.5, 2.5, 2.0), 3000.0 * factors[0]);
    b.point_light("lamp_right", q(4.5, 2.5, 2.0), 3000.0 * factors[1]);
    b.build()
}

fn json(text: &str) -> Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[test]
fn a_room_with_an_exact_solution_is_fitted_to_its_targets() {
    let d = dir("exact");
    let (input, truth) = (d.join("room.gltf"), d.join("truth.gltf"));
    luxbake::export::write_scene(&input, &room([1.0, 1.0, 1.0])).unwrap();
    let factors = [0.7, 0.35, 0.5];
    luxbake::export::write_scene(&truth, &room(factors)).unwrap();
    // The targets: what the room gives with the known factors.
    let lit = d.join("truth-lit.gltf");
    ok(&["--quality", "draft", s(&truth), "-o", s(&lit), "-q"]);
    let keys = [
        "floor",
        "ceiling",
        "wall_west",
        "wall_east",
        "wall_north",
        "wall_south",
        "desk_1",
    ];
    let report = json(&ok(&[
        "report",
        s(&lit),
        "--by",
        "node",
        "--format",
        "json",
    ]));
    let rows = report["byNode"].as_array().unwrap();
    let mut targets = serde_json::Map::new();
    for k in keys {
        let row = rows.iter().find(|r| r["name"] == k).expect(k);
        targets.insert(k.into(), row["eAvg"].clone());
    }
    let targets_file = d.join("targets.json");
    std::fs::write(&targets_file, Value::Object(targets.clone()).to_string()).unwrap();

    let fitted = d.join("fitted.gltf");
    let out = json(&ok(&[
        "fit",
        s(&input),
        "--targets",
        s(&targets_file),
        "-o",
        s(&fitted),
        "--group",
        "left=lamp_left",
        "--group",
        "right=lamp_right",
        "--group",
        "panel=material:panel",
        "--quality",
        "draft",
        "--format",
        "json",
        "-q",
    ]));
    let groups = out["groups"].as_array().unwrap();
    let mut worst: f64 = 0.0;
    for (g, want) in groups.iter().zip(factors) {
        let got = g["factor"].as_f64().unwrap();
        worst = worst.max((got / want - 1.0).abs());
    }
    // The fit ends on the mesh of the fitted scene, nearly the truth's (adaptive meshing follows
    // the light, which differs by the factors' last digits): measured 2.8·10⁻⁴. At most
    // `PASSES` meshes.
    let passes = out["passes"].as_u64().unwrap();
    println!("exact room: factors within {worst:.1e} of the truth, {passes} meshes");
    assert!(worst < 1e-3, "factors off by {worst:e}: {groups:?}");
    assert!((1..=3).contains(&passes), "{passes} meshes");
    for row in out["surfaces"].as_array().unwrap() {
        let ratio = row["ratio"].as_f64().unwrap();
        assert!((ratio - 1.0).abs() < 0.01, "{row}");
    }
    assert!(out["fixedSources"].as_array().unwrap().is_empty());

    // Baking the fitted scene gives what the fit reported.
    check_fitted_bake(&fitted, &targets_file, &out, &["--quality", "draft"]);

    // Allowed at most 0.6, the left light stops there and says so; the others make up for it.
    let capped = d.join("capped.gltf");
    let args = [
        "fit",
        s(&input),
        "--targets",
        s(&targets_file),
        "-o",
        s(&capped),
        "--group",
        "left=lamp_left",
        "--group",
        "right=lamp_right",
        "--group",
        "panel=material:panel",
        "--quality",
        "draft",
        "--max-factor",
        "0.6",
        "-q",
    ];
    let text = ok(&args);
    assert!(text.contains("0.6000 (max)"), "{text}");
    assert!(
        text.contains("note: a group at (max) wants more light"),
        "{text}"
    );
    let mut json_args = args.to_vec();
    json_args.extend(["--format", "json"]);
    let capped_fit = json(&ok(&json_args));
    let g = capped_fit["groups"].as_array().unwrap();
    assert_eq!(g[0]["factor"], 0.6);
    assert_eq!(g[0]["atMaximum"], true);
    assert!(
        g[1..]
            .iter()
            .all(|g| g["atMaximum"] == false && g["off"] == false)
    );
    std::fs::remove_dir_all(&d).ok();
}

/// Bake `fitted`, report it against `targets`, and compare with the fit's achieved values.
fn check_fitted_bake(fitted: &Path, targets: &Path, fit: &Value, settings: &[&str]) {
    let lit = fitted.with_file_name("fitted-lit.gltf");
    let mut args = settings.to_vec();
    args.extend([s(fitted), "-o", s(&lit), "-q"]);
    ok(&args);
    let report = json(&ok(&[
        "report",
        s(&lit),
        "--targets",
        s(targets),
        "--by",
        "node",
        "--format",
        "json",
    ]));
    let achieved = report["targets"].as_array().unwrap();
    let surfaces = fit["surfaces"].as_array().unwrap();
    assert_eq!(achieved.len(), surfaces.len());
    for (a, f) in achieved.iter().zip(surfaces) {
        let (baked, reported) = (
            a["achieved"].as_f64().unwrap(),
            f["achieved"].as_f64().unwrap(),
        );
        assert!(
            (baked / reported - 1.0).abs() < 0.005,
            "{}: fit said {reported} lx, the fitted bake gives {baked} lx",
            f["key"]
        );
    }
}

#[test]
fn the_office_fitted_to_the_seeds_design_bakes_to_what_fit_reported() {
    let d = dir("office");
    let fitted = d.join("fitted.gltf");
    let out = json(&ok(&[
        "fit",
        "samples/office/office.gltf",
        "--design",
        "samples/office/table1.csv",
        "-o",
        s(&fitted),
        "--quality",
        "draft",
        "--format",
        "json",
        "-q",
    ]));
    // Two groups by profile: the spotlight and the six louvred fittings; dimming only.
    let groups = out["groups"].as_array().unwrap();
    assert_eq!(groups.len(), 2, "{out}");
    assert_eq!(groups[1]["sources"].as_array().unwrap().len(), 6);
    for g in groups {
        let x = g["factor"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&x), "{g}");
    }
    let surfaces = out["surfaces"].as_array().unwrap();
    assert_eq!(surfaces.len(), 9);
    assert_eq!(surfaces[0]["name"], "Roof");
    assert_eq!(surfaces[0]["key"], "ceiling");
    // The design as a targets file (the table's surface column), to report the fitted bake.
    let targets: serde_json::Map<String, Value> = surfaces
        .iter()
        .map(|r| (r["key"].as_str().unwrap().to_owned(), r["design"].clone()))
        .collect();
    let targets_file = d.join("targets.json");
    std::fs::write(&targets_file, Value::Object(targets).to_string()).unwrap();
    check_fitted_bake(&fitted, &targets_file, &out, &["--quality", "draft"]);
    // The fitted scene is the input with multipliers: the spotlight's factor is in its node.
    let doc = json(&std::fs::read_to_string(&fitted).unwrap());
    let spot = doc["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"] == "spotlight")
        .unwrap();
    let m = spot["extensions"]["LUXBAKE_luminaire"]["multiplier"]
        .as_f64()
        .unwrap();
    assert!(
        (m - groups[0]["factor"].as_f64().unwrap()).abs() < 1e-12,
        "{spot}"
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_fits_are_refused() {
    let d = dir("bad");
    let out = d.join("f.gltf");
    let office = "samples/office/office.gltf";
    let design = "samples/office/table1.csv";
    let cases: [(Vec<&str>, i32, &str); 5] = [
        (
            vec!["--group", "x=nothing_*"],
            2,
            "'nothing_*' matches no light source",
        ),
        (
            vec!["--group", "a=luminaire_*", "--group", "b=luminaire_1*"],
            2,
            "is already in group 'a'",
        ),
        (vec!["--group", "noequals"], 2, "expected NAME=PATTERN"),
        (
            vec!["--max-factor", "0"],
            2,
            "--max-factor must be a number > 0",
        ),
        (
            vec!["--targets", "samples/office/targets.json"],
            2,
            "cannot be used with",
        ),
    ];
    for (extra, code, message) in &cases {
        let mut args = vec!["fit", office, "--design", design, "-o", s(&out), "-q"];
        args.extend(extra.iter().copied());
        let (got, _, err) = bake(&args);
        assert_eq!(got, Some(*code), "{extra:?}: {err}");
        assert!(err.contains(message), "{extra:?}: {err}");
        assert!(!out.exists());
    }
    // A working-plane target needs --working-plane.
    let (code, _, err) = bake(&[
        "fit",
        office,
        "--targets",
        "samples/office/targets.json",
        "-o",
        s(&out),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("--working-plane"), "{err}");
    // A surface designed at 0 lx has no relative error.
    let zero = d.join("zero.csv");
    std::fs::write(
        &zero,
        "name,area_m2,reflectance,illuminance_lx,surface\nRoof,40,0.7,0,ceiling\n",
    )
    .unwrap();
    let (code, _, err) = bake(&["fit", office, "--design", s(&zero), "-o", s(&out)]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("zero.csv") && err.contains("designed at 0 lx"),
        "{err}"
    );
    assert!(!out.exists());
    // Never over the input.
    let (code, _, err) = bake(&["fit", office, "--design", design, "-o", office]);
    assert_ne!(code, Some(0), "{err}");
    assert!(err.contains("office.gltf"), "{err}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_fit_is_the_same_whatever_the_thread_count() {
    let d = dir("threads");
    let run = |threads: &str| {
        // One name in two folders: the .bin's name (in the glTF) comes from the output's.
        let out = d.join(threads).join("fitted.gltf");
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        let text = ok(&[
            "fit",
            "samples/office/office.gltf",
            "--design",
            "samples/office/table1.csv",
            "-o",
            s(&out),
            "--quality",
            "draft",
            "--group-by",
            "source",
            "--format",
            "json",
            "--threads",
            threads,
            "-q",
        ]);
        let gltf = std::fs::read(&out).unwrap();
        let uri = json(std::str::from_utf8(&gltf).unwrap())["buffers"][0]["uri"]
            .as_str()
            .unwrap()
            .to_owned();
        let bin = std::fs::read(out.with_file_name(uri)).unwrap();
        (text, gltf, bin)
    };
    let (one, two) = (run("1"), run("2"));
    assert_eq!(one.0, two.0);
    assert!(one.1 == two.1 && one.2 == two.2, "fitted files differ");
    // Seven sources, each its own group.
    assert_eq!(json(&one.0)["groups"].as_array().unwrap().len(), 7);
    std::fs::remove_dir_all(&d).ok();
}
