//! The lighting report (`src/report/`): rows with known answers on tiny scenes, every format
//! well-formed, the report read back from an output equal to the one made at bake time (byte for
//! byte, every format; the office with a working plane), the run summary read back typed (an
//! output lacking a field is an error naming it), and the errors of `bake report`.

mod support;

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::export::{self, ExportOptions};
use luxbake::fixtures::SceneBuilder;
use luxbake::progress::Silent;
use luxbake::report::{self, By, Filter, Format, Options, Targets};
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::{ProbeGrid, Quality, Settings};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::Path;
use support::bakes::{floor_and_walls, group};
use support::cli::{Mini, bake as run_bake, repo_file};
use support::scratch;

const FORMATS: [(Format, &str); 4] = [
    (Format::Table, "table"),
    (Format::Markdown, "markdown"),
    (Format::Csv, "csv"),
    (Format::Json, "json"),
];

fn draft() -> Settings {
    Settings {
        quality: Quality::Draft,
        ..Settings::default()
    }
}

/// A 2 × 2 m floor (ρ 0.5) centred under an isotropic point light of `flux` lm, 1 m above it.
fn floor_under_light(flux: f64) -> Scene {
    let mut b = SceneBuilder::new();
    let grey = b.material("grey", 0.5);
    b.floor("floor", 1.0, 0.0, grey);
    b.point_light("lamp", DVec3::new(0.0, 1.0, 0.0), flux);
    b.build()
}

/// The floor with two 1 m high walls at x = ±1 facing it (`grey` 0.5 at +1, `white` 0.8 at −1),
/// all three under a parent node `room`.
fn room() -> Scene {
    let mut b = SceneBuilder::new();
    floor_and_walls(&mut b);
    b.point_light("lamp", DVec3::new(0.0, 1.0, 0.0), 2400.0);
    let mut scene = b.build();
    group(&mut scene, "room", vec![0, 1, 2]);
    scene
}

/// Area-weighted mean of a per-vertex value over a baked surface, computed here on its own.
fn area_mean(r: &BakeResult, surface: usize, value: impl Fn(usize, usize) -> f64) -> (f64, f64) {
    let (mut area, mut integral) = (0.0, 0.0);
    for (k, b) in r.surfaces.iter().enumerate() {
        if b.surface != surface {
            continue;
        }
        for t in &b.triangles {
            let [a, bb, c] = t.map(|v| b.positions[v as usize]);
            let w = (bb - a).cross(c - a).length() / 2.0;
            area += w;
            integral += w * t.iter().map(|&v| value(k, v as usize)).sum::<f64>() / 3.0;
        }
    }
    (area, integral / area)
}

#[test]
fn floor_under_a_point_light_has_known_figures() {
    let flux = 2400.0;
    let scene = floor_under_light(flux);
    let r = bake(&scene, &draft(), &Silent).unwrap();
    let input = luxbake::readback::as_written(&scene, &r).unwrap();
    let rows = report::rows::by_node(&input, &Filter::All);
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    let (area, mean) = area_mean(&r, 0, |k, v| r.surfaces[k].illuminance[v] as f64);
    assert!((row.area - 4.0).abs() < 1e-6 && (area - 4.0).abs() < 1e-9);
    assert!((row.e_avg - mean).abs() < 1e-4 * mean, "{row:?} vs {mean}");
    // ∫ I·h/d³ dA is I times the solid angle of the square seen from the lamp, 2π/3; I = Φ/4π.
    let exact = flux / (4.0 * PI) * (2.0 * PI / 3.0) / 4.0;
    assert!(
        (row.e_avg - exact).abs() < 0.01 * exact,
        "{} vs {exact}",
        row.e_avg
    );
    // No other surface: everything is direct; the corners (d = √3) are the minimum.
    let i = flux / (4.0 * PI);
    assert_eq!(row.e_indirect_avg, 0.0);
    assert_eq!(row.e_direct_avg, row.e_avg);
    assert!(
        (row.e_min - i / 3f64.powf(1.5)).abs() < 1e-4 * row.e_min,
        "{row:?}"
    );
    assert!(
        row.e_max <= i * (1.0 + 1e-5) && row.e_max > 0.95 * i,
        "{row:?}"
    );
    assert!((row.uniformity - row.e_min / row.e_avg).abs() < 1e-12);
    assert!((row.reflectance - 0.5).abs() < 1e-12);
    assert!((row.l_avg - 0.5 * row.e_avg / PI).abs() < 1e-4 * row.l_avg);
}

#[test]
fn rows_by_node_and_material_split_direct_and_indirect() {
    let scene = room();
    let r = bake(&scene, &draft(), &Silent).unwrap();
    let input = luxbake::readback::as_written(&scene, &r).unwrap();
    let nodes = report::rows::by_node(&input, &Filter::All);
    let names: Vec<&str> = nodes.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["room/floor", "room/wall_grey", "room/wall_white"]);
    let materials = report::rows::by_material(&input, &Filter::All);
    let names: Vec<&str> = materials.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["grey", "white"]);

    let floor = &nodes[0];
    let (_, direct) = area_mean(&r, 0, |k, v| r.surfaces[k].illuminance_direct[v] as f64);
    assert!((floor.e_direct_avg - direct).abs() < 1e-4 * direct);
    assert!(
        floor.e_indirect_avg > 1.0,
        "the walls reflect onto the floor: {floor:?}"
    );
    assert!((floor.e_direct_avg + floor.e_indirect_avg - floor.e_avg).abs() < 1e-9 * floor.e_avg);
    // Material `grey` = floor + grey wall, area-weighted; `white` = the white wall alone.
    let (f, g, w) = (&nodes[0], &nodes[1], &nodes[2]);
    let grey = &materials[0];
    assert!((grey.area - (f.area + g.area)).abs() < 1e-9);
    let weighted = (f.e_avg * f.area + g.e_avg * g.area) / grey.area;
    assert!((grey.e_avg - weighted).abs() < 1e-9 * weighted);
    assert_eq!(grey.e_min, f.e_min.min(g.e_min));
    assert_eq!(grey.e_max, f.e_max.max(g.e_max));
    assert!((grey.reflectance - 0.5).abs() < 1e-12);
    assert_eq!(materials[1].e_avg, w.e_avg);
    assert!((materials[1].reflectance - 0.8).abs() < 1e-12);
    // Upward faces of the whole room: the floor only.
    let up = report::rows::by_material(&input, &Filter::Facing(DVec3::Y));
    assert_eq!(up.len(), 1);
    assert_eq!(up[0].e_avg, f.e_avg);
}

/// Each format of the report made from the bake in memory equals the one read from its output.
fn assert_same_reports(scene: &Scene, r: &BakeResult, path: &Path, options: &Options) {
    let memory = report::build(&luxbake::readback::as_written(scene, r).unwrap(), options).unwrap();
    let file = report::build(&luxbake::readback::read(path).unwrap(), options).unwrap();
    for (format, name) in FORMATS {
        assert_eq!(memory.render(format), file.render(format), "{name}");
    }
}

#[test]
fn office_report_from_the_file_equals_the_bake_time_report() {
    let office = repo_file("samples/office/office.gltf");
    let scene = luxbake::import::load(&office, &Default::default()).unwrap();
    let settings = Settings {
        working_plane: Some(ProbeGrid {
            spacing: 0.5,
            height: 0.8,
        }),
        ..draft()
    };
    let r = bake(&scene, &settings, &Silent).unwrap();
    let dir = scratch("report-office");
    let path = dir.join("lit.gltf");
    export::write(&path, &scene, &r, &ExportOptions::default()).unwrap();
    let targets = Targets::read(&repo_file("samples/office/targets.json")).unwrap();
    let options = Options {
        by: By::Both,
        targets: Some(targets),
        border: 0.0,
    };
    assert_same_reports(&scene, &r, &path, &options);

    let report = report::build(&luxbake::readback::read(&path).unwrap(), &options).unwrap();
    let plane = report.working_plane.as_ref().expect("a working plane");
    assert!(plane.points > 50, "{plane:?}");
    assert_eq!((plane.height, plane.spacing), (Some(0.8), Some(0.5)));
    assert!(plane.e_min <= plane.e_avg && plane.e_avg <= plane.e_max);
    assert!((plane.e_direct_avg + plane.e_indirect_avg - plane.e_avg).abs() < 1e-3);
    let targets = report.targets.as_ref().unwrap();
    assert_eq!(targets[0].name, "working_plane");
    assert_eq!(targets[0].achieved, Some(plane.e_avg));
    assert!(
        targets
            .iter()
            .all(|t| t.ratio.is_some_and(|x| x > 0.5 && x < 3.0))
    );
    let md = report.render(Format::Markdown);
    eprintln!("{md}");
}

#[test]
fn every_format_is_well_formed() {
    let scene = room();
    let r = bake(&scene, &draft(), &Silent).unwrap();
    let input = luxbake::readback::as_written(&scene, &r).unwrap();
    // A working-plane target for a bake without a working plane is an error, not a blank.
    let plane_target = Targets::parse(Path::new("t.json"), r#"{"working_plane": 300}"#).unwrap();
    let options = Options {
        by: By::Both,
        targets: Some(plane_target),
        border: 0.0,
    };
    let err = report::build(&input, &options).unwrap_err().to_string();
    assert!(
        err.contains("t.json") && err.contains("no working plane"),
        "{err}"
    );

    let targets = Targets::parse(
        Path::new("t.json"),
        r#"{"room/floor": 100, "material:white": 50, "room/wall_grey[-x]": 80}"#,
    )
    .unwrap();
    let options = Options {
        by: By::Both,
        targets: Some(targets),
        border: 0.0,
    };
    let rep = report::build(&input, &options).unwrap();
    let t = rep.targets.as_ref().unwrap();
    assert_eq!(t.len(), 3);

    let json: Value = serde_json::from_str(&rep.render(Format::Json)).unwrap();
    assert_eq!(json["byMaterial"].as_array().unwrap().len(), 2);
    assert_eq!(json["byNode"][0]["name"], "room/floor");
    assert!(json["byNode"][0]["eAvg"].as_f64().unwrap() > 0.0);
    assert!(json["workingPlane"].is_null());
    assert_eq!(json["targets"][1]["name"], "material:white");

    let csv = rep.render(Format::Csv);
    let blocks: Vec<&str> = csv.trim_end().split("\n\n").collect();
    // The fixture's point light makes a luminaire schedule.
    assert_eq!(blocks.len(), 4, "{csv}");
    let sections = ["byMaterial", "byNode", "targets", "luminaires"];
    for (block, section) in blocks.iter().zip(sections) {
        let mut lines = block.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(header[0], "section");
        for line in lines {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), header.len(), "{line}");
            assert_eq!(fields[0], section);
            for (f, name) in fields[2..].iter().zip(&header[2..]) {
                // A surface row's `source`: what its figures come from (this bake: vertices).
                if *name == "source" {
                    assert_eq!(*f, "vertices", "{line}");
                    continue;
                }
                if *name == "pass" {
                    assert!(*f == "true" || *f == "false", "{line}");
                    continue;
                }
                if ["kind", "profile", "names"].contains(name) {
                    continue;
                }
                assert!(f.is_empty() || f.parse::<f64>().is_ok(), "{line}");
            }
        }
    }

    let table = rep.render(Format::Table);
    for block in table.trim_end().split("\n\n") {
        let lines: Vec<&str> = block.lines().collect();
        // Title, header, rule, rows; the rule spans the header exactly.
        assert!(lines[2].chars().all(|c| c == '-' || c == ' '), "{block}");
        assert_eq!(
            lines[1].chars().count(),
            lines[2].chars().count(),
            "{block}"
        );
        assert!(lines.len() > 3);
    }

    let md = rep.render(Format::Markdown);
    for block in md.trim_end().split("\n\n### ") {
        let rows: Vec<&str> = block.lines().filter(|l| l.starts_with('|')).collect();
        let pipes = rows[0].matches('|').count();
        assert!(rows.len() >= 3 && rows[1].starts_with("| --- |"), "{block}");
        assert!(
            rows.iter().all(|r| r.matches('|').count() == pipes),
            "{block}"
        );
    }

    let only = report::build(
        &input,
        &Options {
            by: By::Material,
            targets: None,
            border: 0.0,
        },
    )
    .unwrap();
    assert!(only.by_node.is_none() && only.targets.is_none());
    assert!(!only.render(Format::Json).contains("byNode"));
}

#[test]
fn unknown_or_malformed_targets_are_errors() {
    let scene = room();
    let r = bake(&scene, &draft(), &Silent).unwrap();
    let input = luxbake::readback::as_written(&scene, &r).unwrap();
    let file = Path::new("targets.json");
    let build = |text: &str| {
        let targets = Targets::parse(file, text)?;
        report::build(
            &input,
            &Options {
                by: By::Both,
                targets: Some(targets),
                border: 0.0,
            },
        )
    };
    for (text, says) in [
        (r#"{"floor": 100}"#, "'floor'"), // nodes are named by their path: room/floor
        (r#"{"material:black": 100}"#, "'material:black'"),
        (r#"{"room/floor[+w]": 100}"#, "unknown face"),
        (r#"{"room/floor[-y]": 100}"#, "no face"),
        (r#"{"room/floor": -1}"#, "positive"),
        (r#"[500]"#, "JSON object"),
        ("{", "not valid JSON"),
    ] {
        let e = build(text).expect_err(text).to_string();
        assert!(
            e.contains(says) && e.starts_with("targets.json: "),
            "{text}: {e}"
        );
    }
}

#[test]
fn cli_report_equals_bake_time_report_in_every_format() {
    let dir = scratch("report-cli");
    let input = Mini::new().write_gltf(&dir, "mini.gltf", Some("mini.bin"));
    let lit = dir.join("lit.glb");
    for (_, format) in FORMATS {
        let baked = run_bake([
            input.to_str().unwrap(),
            "-o",
            lit.to_str().unwrap(),
            "--quality",
            "draft",
            "-q",
            "--report",
            format,
        ]);
        assert!(baked.ok(), "{baked:?}");
        let read = run_bake(["report", lit.to_str().unwrap(), "--format", format]);
        assert!(read.ok(), "{read:?}");
        assert_eq!(baked.stdout, read.stdout, "{format}");
        assert!(read.stdout.contains("floor"), "{}", read.stdout);
    }
}

#[test]
fn cli_office_markdown_with_targets_to_a_file() {
    let dir = scratch("report-cli-office");
    let lit = dir.join("lit.gltf");
    let (out, targets) = (
        dir.join("report.md"),
        repo_file("samples/office/targets.json"),
    );
    let office = repo_file("samples/office/office.gltf");
    let args = [
        office.to_str().unwrap(),
        "-o",
        lit.to_str().unwrap(),
        "--quality",
        "draft",
        "-q",
        "--report",
        "markdown",
        "--targets",
        targets.to_str().unwrap(),
        "--working-plane",
        "0.75",
        "--report-out",
        out.to_str().unwrap(),
    ];
    let baked = run_bake(args);
    assert!(baked.ok() && baked.stdout.is_empty(), "{baked:?}");
    let read = run_bake([
        "report",
        lit.to_str().unwrap(),
        "--format",
        "markdown",
        "--targets",
        targets.to_str().unwrap(),
    ]);
    assert!(read.ok(), "{read:?}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), read.stdout);
    assert!(
        read.stdout.contains("| desk_dark/top[+y] | 500 |"),
        "{}",
        read.stdout
    );
}

#[test]
fn cli_report_errors_are_one_line() {
    let dir = scratch("report-errors");
    let missing = dir.join("missing.gltf");
    let office = repo_file("samples/office/office.gltf");
    let obj = repo_file("samples/cornell-box/cornell-box.obj");
    for (file, says) in [
        (
            office.as_path(),
            "not a luxbake output: no primitive has an _ILLUMINANCE",
        ),
        (missing.as_path(), "cannot open the file"),
        (obj.as_path(), "not a luxbake output"),
    ] {
        let run = run_bake(["report", file.to_str().unwrap()]);
        assert_eq!(run.code, Some(1), "{run:?}");
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        assert!(
            run.stderr.starts_with("error: ") && run.stderr.contains(says),
            "{}",
            run.stderr
        );
        assert!(run.stdout.is_empty());
    }
    let bad = dir.join("targets.json");
    std::fs::write(&bad, "{\"nowhere\": 300}").unwrap();
    let lit = dir.join("lit.gltf");
    let input = Mini::new().write_gltf(&dir, "mini.gltf", Some("mini.bin"));
    let run = run_bake([
        input.to_str().unwrap(),
        "-o",
        lit.to_str().unwrap(),
        "--quality",
        "draft",
        "--targets",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(run.code, Some(1), "{run:?}");
    assert!(run.stderr.contains("target 'nowhere'"), "{}", run.stderr);
    assert!(!lit.exists(), "nothing is written when the report fails");
}

/// The run summary written into an output reads back typed, equal to the bake's; an output
/// lacking a summary field (as one written by another version would) makes `bake report` fail
/// with one line naming the field, never print a default, while `bake diff` (which reads no
/// summary) still compares it.
#[test]
fn run_summary_reads_back_typed_and_a_missing_field_is_named() {
    let scene = floor_under_light(2400.0);
    let settings = Settings {
        working_plane: Some(ProbeGrid {
            spacing: 0.5,
            height: 0.3,
        }),
        ..draft()
    };
    let r = bake(&scene, &settings, &Silent).unwrap();
    let dir = scratch("report-summary");
    let path = dir.join("lit.gltf");
    export::write(&path, &scene, &r, &ExportOptions::default()).unwrap();
    let read = luxbake::readback::read(&path).unwrap();
    assert_eq!(read.run_summary().unwrap().as_ref(), Some(&r.summary));
    let report = report::build(&read, &Options::default()).unwrap();
    let plane = report.working_plane.expect("a working plane");
    assert_eq!((plane.height, plane.spacing), (Some(0.3), Some(0.5)));

    for (field, pointer) in [
        ("workingPlane", "/scenes/0/extras/luxbake/settings"),
        ("raysByStage", "/scenes/0/extras/luxbake/counts"),
        ("energy", "/scenes/0/extras/luxbake"),
    ] {
        let mut doc: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        let summary = &mut doc["scenes"][0]["extras"]["luxbake"];
        let parent = match pointer.rsplit('/').next().unwrap() {
            "luxbake" => summary,
            key => &mut summary[key],
        };
        assert!(parent.as_object_mut().unwrap().remove(field).is_some());
        let old = dir.join(format!("old-{field}.gltf"));
        std::fs::write(&old, serde_json::to_vec(&doc).unwrap()).unwrap();
        let bin = support::hashed(&dir, "lit.#.bin");
        std::fs::copy(&bin, dir.join(format!("old-{field}.bin"))).unwrap();
        let bin_name = bin.file_name().unwrap().to_str().unwrap();
        std::fs::write(
            &old,
            String::from_utf8(std::fs::read(&old).unwrap())
                .unwrap()
                .replace(&format!("\"{bin_name}\""), &format!("\"old-{field}.bin\"")),
        )
        .unwrap();
        let run = run_bake([Path::new("report"), old.as_path()]);
        assert_eq!(run.code, Some(1), "{field}: {}", run.stdout);
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        assert!(
            run.stderr.contains(pointer)
                && run.stderr.contains(&format!("missing field `{field}`"))
                && run.stderr.contains(&format!("old-{field}.gltf")),
            "{}",
            run.stderr
        );
        let diff = run_bake([Path::new("diff"), old.as_path(), path.as_path()]);
        assert_eq!(diff.code, Some(0), "{field}: {}", diff.stderr);
    }
}
