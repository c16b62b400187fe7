//! The report of a lightmapped bake takes its surface figures from the texels: a black floor
//! under a point light (no inter-reflection, so E = I·cos θ/d² exactly) has the texel-weighted
//! mean of the closed form I·Ω/A (Ω: the floor's solid angle from the light) within 0.5 %, and
//! nearer it than the vertex-based mean of the same bake at a coarse patch size; the report read
//! back from the written files equals the one made in memory (every format) and says its source;
//! broken lightmaps (EXR missing, truncated, outside the folder, a channel missing, another size)
//! are errors naming the file, the material's pointer and the EXR. Axes: +Y up.

mod support;

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::export::{self, ExportOptions};
use luxbake::fixtures::SceneBuilder;
use luxbake::progress::Silent;
use luxbake::report::rows::{Filter, by_material, by_node, row_from};
use luxbake::report::{self, By, Format, Options, Source};
use luxbake::scene::Scene;
use luxbake::settings::{LightmapSettings, Quality, Settings};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use support::bakes::floor_and_walls;
use support::cli::bake as run_bake;
use support::scratch;

const LIGHT: DVec3 = DVec3::new(0.3, 2.0, -0.2);
const FLUX: f64 = 10_000.0;
const HALF: f64 = 2.0;

/// A black 4 × 4 m floor (y = 0, facing +Y) under an isotropic point light of 10⁴ lm.
fn black_floor() -> Scene {
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    b.floor("floor", HALF, 0.0, black);
    b.point_light("bulb", LIGHT, FLUX);
    b.build()
}

fn settings(patch: f64, texel: f64) -> Settings {
    Settings {
        quality: Quality::Draft,
        patch_size: Some(patch),
        lightmaps: Some(LightmapSettings::with_texel(texel)),
        ..Settings::default()
    }
}

/// Solid angle of the rectangle [0, a] × [0, b] seen from height h above its corner (signed in
/// a and b).
fn corner(a: f64, b: f64, h: f64) -> f64 {
    (a * b / (h * (a * a + b * b + h * h).sqrt())).atan()
}

/// The floor's mean illuminance: I·Ω/A, Ω the solid angle of [−2, 2]² from the light.
fn exact_mean() -> f64 {
    let (x, z, h) = (LIGHT.x, LIGHT.z, LIGHT.y);
    let omega = corner(HALF - x, HALF - z, h)
        - corner(-HALF - x, HALF - z, h)
        - corner(HALF - x, -HALF - z, h)
        + corner(-HALF - x, -HALF - z, h);
    FLUX / (4.0 * PI) * omega / (2.0 * HALF).powi(2)
}

#[test]
fn the_closed_form_is_the_mean_of_the_inverse_square_cosine_law() {
    // Midpoint rule on a 1000² grid over the floor, as a check of the formula above.
    let (n, i) = (1000, FLUX / (4.0 * PI));
    let step = 2.0 * HALF / n as f64;
    let mut sum = 0.0;
    for r in 0..n {
        for c in 0..n {
            let p = DVec3::new(
                -HALF + (c as f64 + 0.5) * step,
                0.0,
                -HALF + (r as f64 + 0.5) * step,
            );
            let d = LIGHT - p;
            sum += i * d.y / d.length().powi(3);
        }
    }
    let numeric = sum / (n * n) as f64;
    assert!(
        (numeric / exact_mean() - 1.0).abs() < 1e-5,
        "{numeric} vs {}",
        exact_mean()
    );
}

#[test]
fn texel_mean_of_a_black_floor_is_the_closed_form() {
    let scene = black_floor();
    let r = bake(&scene, &settings(2.0, 0.1), &Silent).unwrap();
    let input = luxbake::readback::as_written(&scene, &r).unwrap();
    assert_eq!(input.lightmaps.len(), 1);
    let rows = by_node(&input, &Filter::All);
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    assert_eq!(row.source, Source::Texels);
    assert!((row.area - 16.0).abs() < 1e-4, "area {}", row.area);
    let exact = exact_mean();
    let texels = (row.e_avg / exact - 1.0).abs();
    assert!(
        texels < 0.005,
        "texel mean {} vs {exact}: {:.3} %",
        row.e_avg,
        texels * 100.0
    );
    // Black: everything is direct, nothing leaves the surface.
    assert_eq!(row.e_direct_avg, row.e_avg);
    assert_eq!(
        (row.e_indirect_avg, row.l_avg, row.reflectance),
        (0.0, 0.0, 0.0)
    );
    // Extremes over texels: the brightest texel is near the foot of the light (I/h² there).
    let peak = FLUX / (4.0 * PI) / (LIGHT.y * LIGHT.y);
    assert!(
        row.e_max <= peak && row.e_max > 0.99 * peak,
        "{} vs {peak}",
        row.e_max
    );
    assert!(row.e_min > 0.0 && row.uniformity == row.e_min / row.e_avg);

    // The same bake's vertices (a coarse mesh: 2 m patches) miss the mean by more.
    let prims: Vec<_> = input.primitives.iter().collect();
    let vertex = row_from(&input, "floor", &prims, &Filter::All, false).unwrap();
    assert_eq!(vertex.source, Source::Vertices);
    let vertices = (vertex.e_avg / exact - 1.0).abs();
    assert!(
        texels < vertices,
        "texels {:.3} % vs vertices {:.3} %",
        texels * 100.0,
        vertices * 100.0
    );
    eprintln!(
        "mean {exact:.3} lx: texels {:.3} ({:.3} %), vertices {:.3} ({:.3} %)",
        row.e_avg,
        texels * 100.0,
        vertex.e_avg,
        vertices * 100.0
    );
    // Upward faces only: the whole floor.
    let up = row_from(&input, "up", &prims, &Filter::Facing(DVec3::Y), true).unwrap();
    assert_eq!((up.area, up.e_avg), (row.area, row.e_avg));
    assert!(row_from(&input, "down", &prims, &Filter::Facing(-DVec3::Y), true).is_none());
}

/// A 2 × 2 m floor between walls (ρ 0.5 and 0.8) under a 2400 lm point light 1 m up,
/// lightmapped, written to `dir/lit.<ext>`.
fn write_room(dir: &Path, ext: &str, texel: f64) -> (Scene, PathBuf) {
    let mut b = SceneBuilder::new();
    floor_and_walls(&mut b);
    b.point_light("lamp", DVec3::new(0.0, 1.0, 0.0), 2400.0);
    let scene = b.build();
    let r = bake(&scene, &settings(0.25, texel), &Silent).unwrap();
    let path = dir.join(format!("lit.{ext}"));
    export::write(&path, &scene, &r, &ExportOptions::default()).unwrap();
    (scene, path)
}

#[test]
fn report_from_the_files_equals_the_report_in_memory() {
    let dir = scratch("report-lm-files");
    for ext in ["gltf", "glb"] {
        let (scene, path) = write_room(&dir, ext, 0.05);
        let r = bake(&scene, &settings(0.25, 0.05), &Silent).unwrap();
        let memory = luxbake::readback::as_written(&scene, &r).unwrap();
        let file = luxbake::readback::read(&path).unwrap();
        // The same channels (the URIs differ: the bake in memory is named bake.glb).
        assert_eq!(file.lightmaps.len(), memory.lightmaps.len());
        for (f, m) in file.lightmaps.iter().zip(&memory.lightmaps) {
            assert_eq!((f.width, f.height, &f.at), (m.width, m.height, &m.at));
            let same = f.luminance == m.luminance
                && f.illuminance == m.illuminance
                && f.illuminance_direct == m.illuminance_direct
                && f.footprint == m.footprint;
            assert!(same, "the EXR holds other values than the bake in memory");
        }
        let options = Options {
            by: By::Both,
            targets: None,
            border: 0.0,
        };
        let (a, b) = (
            report::build(&memory, &options).unwrap(),
            report::build(&file, &options).unwrap(),
        );
        for format in [Format::Table, Format::Markdown, Format::Csv, Format::Json] {
            assert_eq!(a.render(format), b.render(format), "{ext} {format:?}");
        }
        // Every material once (their lightmapped variants count as them), from texels.
        let rows = by_material(&file, &Filter::All);
        let names: Vec<&str> = rows.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["grey", "white"]);
        assert!(rows.iter().all(|r| r.source == Source::Texels));
        let text = b.render(Format::Table);
        assert!(
            text.contains("Surfaces by material (from lightmap texels)"),
            "{text}"
        );
        let json: Value = serde_json::from_str(&b.render(Format::Json)).unwrap();
        assert_eq!(json["byNode"][0]["source"], "texels");
        let csv = b.render(Format::Csv);
        let header = csv.lines().next().unwrap();
        assert!(header.ends_with(",lAvg,coveredArea,source"), "{header}");
        assert!(csv.lines().nth(1).unwrap().ends_with(",texels"), "{csv}");
    }
}

/// `bake report` of `path`: its exit code and stderr.
fn report_error(path: &Path) -> (Option<i32>, String) {
    let run = run_bake(["report".as_ref(), path.as_os_str()]);
    (run.code, run.stderr)
}

/// Apply `edit` to every material's `LUXBAKE_lightmap` of the `.gltf` at `path`.
fn edit_lightmaps(path: &Path, mut edit: impl FnMut(&mut Value)) {
    let mut json: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    for m in json["materials"].as_array_mut().unwrap() {
        if let Some(ext) = m.pointer_mut("/extensions/LUXBAKE_lightmap") {
            edit(ext);
        }
    }
    std::fs::write(path, serde_json::to_vec_pretty(&json).unwrap()).unwrap();
}

/// Replace `from` by `to` (same length) everywhere in the file.
fn patch(path: &Path, from: &[u8], to: &[u8]) {
    let mut bytes = std::fs::read(path).unwrap();
    let mut hits = 0;
    for i in 0..bytes.len().saturating_sub(from.len()) {
        if &bytes[i..i + from.len()] == from {
            bytes[i..i + to.len()].copy_from_slice(to);
            hits += 1;
        }
    }
    assert!(hits > 0, "{} not found", String::from_utf8_lossy(from));
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn broken_lightmaps_are_errors_naming_the_material_and_the_exr() {
    let dir = scratch("report-lm-errors");
    let fresh = |name: &str| {
        let sub = dir.join(name);
        std::fs::create_dir_all(&sub).unwrap();
        write_room(&sub, "gltf", 0.1).1
    };
    let exr = |gltf: &Path| support::hashed(gltf.parent().unwrap(), "lit.lightmap0.#.exr");
    let pointer = regex_free_pointer;

    let path = fresh("missing");
    let missing = exr(&path);
    std::fs::remove_file(&missing).unwrap();
    let (code, err) = report_error(&path);
    assert_eq!(code, Some(1), "{err}");
    let name = missing.file_name().unwrap().to_str().unwrap();
    assert!(pointer(&err) && err.contains(name), "{err}");
    assert!(err.contains("lit.gltf"), "{err}");

    let path = fresh("truncated");
    let bytes = std::fs::read(exr(&path)).unwrap();
    std::fs::write(exr(&path), &bytes[..bytes.len() - 100]).unwrap();
    let (_, err) = report_error(&path);
    assert!(
        pointer(&err)
            && err.contains("lightmap lit.lightmap0.")
            && err.contains(".exr: not a readable OpenEXR"),
        "{err}"
    );

    let path = fresh("outside");
    edit_lightmaps(&path, |e| e["uri"] = "../lightmap0.exr".into());
    std::fs::copy(exr(&path), dir.join("lightmap0.exr")).unwrap();
    let (_, err) = report_error(&path);
    assert!(pointer(&err) && err.contains("outside the folder"), "{err}");

    let path = fresh("channel");
    patch(&exr(&path), b"footprint\0", b"footprinX\0");
    let (_, err) = report_error(&path);
    assert!(
        pointer(&err) && err.contains("no channel 'footprint'"),
        "{err}"
    );

    let path = fresh("size");
    let mut w = 0;
    edit_lightmaps(&path, |e| {
        w = e["width"].as_u64().unwrap();
        e["width"] = (w + 1).into();
    });
    let (_, err) = report_error(&path);
    assert!(
        pointer(&err) && err.contains(&format!("texels but the material says {} ×", w + 1)),
        "{err}"
    );
}

/// Whether an error names a material's `LUXBAKE_lightmap` by its JSON pointer.
fn regex_free_pointer(err: &str) -> bool {
    err.split("/materials/").skip(1).any(|rest| {
        let digits = rest.chars().take_while(char::is_ascii_digit).count();
        digits > 0 && rest[digits..].starts_with("/extensions/LUXBAKE_lightmap")
    })
}

/// `bake IN -o OUT --lightmaps --report` (from the atlases in memory, before the EXR files are
/// written) prints what `bake report OUT` prints from the files.
#[test]
fn cli_bake_time_report_equals_the_report_of_the_files() {
    let dir = scratch("report-lm-cli");
    let input = dir.join("in.gltf");
    export::write_scene(&input, &black_floor()).unwrap();
    for (format, ext) in [("json", "gltf"), ("table", "glb")] {
        let out = dir.join(format!("out.{ext}"));
        let run = run_bake([
            input.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "--lightmaps".as_ref(),
            "--quality".as_ref(),
            "draft".as_ref(),
            "-q".as_ref(),
            "--report".as_ref(),
            format.as_ref(),
        ]);
        assert!(run.ok(), "{}", run.stderr);
        let exr = |e: std::fs::DirEntry| support::unhashed(e.file_name().to_str().unwrap());
        assert!(
            std::fs::read_dir(&dir)
                .unwrap()
                .any(|e| exr(e.unwrap()) == "out.lightmap0.#.exr")
        );
        let again = run_bake([
            "report".as_ref(),
            out.as_os_str(),
            "--format".as_ref(),
            format.as_ref(),
        ]);
        assert!(again.ok(), "{}", again.stderr);
        assert_eq!(run.stdout, again.stdout);
        assert!(
            run.stdout.contains("\"source\": \"texels\"")
                || run.stdout.contains("(from lightmap texels)"),
            "{}",
            run.stdout
        );
    }
}
