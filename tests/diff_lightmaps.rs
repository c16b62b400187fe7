//! `bake diff` of lightmapped bakes: the same layout compares texel by texel (a bake against
//! itself passes; one texel changed through the library's writer fails naming its node, atlas,
//! texel and place), other layouts (another `--texel-size`) compare at surface points (a smooth
//! scene within 5 % everywhere, 0.5 % on average), `--mode texels` refuses other layouts, lightmaps in one bake only fall back
//! to vertices (or vertex means), `--no-lightmaps` compares vertices, a missing EXR file is exit
//! 2 with one line naming it. Axes: +Y up.

mod support;

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::export::{self, ExportOptions};
use luxbake::fixtures::SceneBuilder;
use luxbake::progress::Silent;
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::{LightmapSettings, Quality, Settings};
use std::path::{Path, PathBuf};
use support::bakes::{diff, diff_json, floor_and_walls, last_line, number, quantity};
use support::scratch;

/// A 2 × 2 m floor (ρ 0.5) between two 1 m walls (ρ 0.5 at x = 1, 0.8 at x = −1) under an
/// isotropic point light 1 m up: nothing casts a shadow, light varies smoothly.
fn smooth_room() -> Scene {
    let mut b = SceneBuilder::new();
    floor_and_walls(&mut b);
    b.point_light("lamp", DVec3::new(0.0, 1.0, 0.0), 2400.0);
    b.build()
}

fn settings(texel: Option<f64>) -> Settings {
    Settings {
        quality: Quality::Draft,
        patch_size: Some(0.25),
        lightmaps: texel.map(LightmapSettings::with_texel),
        ..Settings::default()
    }
}

/// Write `r` as `dir/name/lit.gltf`.
fn write(dir: &Path, name: &str, scene: &Scene, r: &BakeResult) -> PathBuf {
    let sub = dir.join(name);
    std::fs::create_dir_all(&sub).unwrap();
    let path = sub.join("lit.gltf");
    export::write(&path, scene, r, &ExportOptions::default()).unwrap();
    path
}

#[test]
fn the_same_layout_compares_texel_by_texel() {
    let dir = scratch("diff-lm-texels");
    let scene = smooth_room();
    let r = bake(&scene, &settings(Some(0.05)), &Silent).unwrap();
    let b = write(&dir, "b", &scene, &r);

    // Against itself: every texel with a footprint, three quantities, all equal.
    let (run, d) = diff_json(&b, &b, &[]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(d["mode"], "texels");
    assert!(
        d["lightmaps"].as_str().unwrap().contains("same layout"),
        "{d}"
    );
    let read = luxbake::readback::read(&b).unwrap();
    let texels: usize = (read.lightmaps.iter())
        .map(|l| l.footprint.iter().filter(|f| **f > 0.0).count())
        .sum();
    assert!(texels > 2000, "{texels} texels for 6 m² at 5 cm");
    assert_eq!(number(&d["values"]) as usize, 3 * texels);
    let ill = quantity(&d, "illuminance");
    let floor = &ill["byNode"][0];
    assert_eq!(floor["name"], "floor");
    let floor_texels = (read.primitives[0].lightmap.as_ref().unwrap().texels.iter())
        .filter(|t| read.lightmaps[0].footprint[t.index as usize] > 0.0)
        .count();
    assert_eq!(number(&floor["values"]) as usize, floor_texels);
    assert_eq!(floor_texels, 1600, "4 m² at 5 cm");

    // One texel of the floor 1.5 times brighter, written by the library's own writer.
    let layout = read.primitives[0].lightmap.as_ref().unwrap();
    let t = layout.texels[layout.texels.len() / 2];
    let k = t.index as usize;
    let mut edited = r.clone();
    let atlas = &mut edited.lightmaps.as_mut().unwrap().atlases[0];
    let (w, old) = (atlas.width as usize, atlas.illuminance[k]);
    assert!(old > 0.0);
    atlas.illuminance[k] *= 1.5;
    let a = write(&dir, "a", &scene, &edited);
    let (run, d) = diff_json(&a, &b, &[]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert_eq!(d["failed"], 1);
    let worst = &d["worstFailure"];
    assert_eq!(worst["kind"], "texel");
    assert_eq!(worst["quantity"], "illuminance");
    assert_eq!(worst["node"], "floor");
    assert_eq!(worst["material"], "grey");
    assert_eq!(worst["atlas"], 0);
    assert_eq!(worst["texel"], serde_json::json!([k % w, k / w]));
    assert_eq!(number(&worst["b"]), f64::from(old));
    assert_eq!(number(&worst["a"]), f64::from(old * 1.5));
    // Its place: on the floor (y = 0), at the texel's centre: UV ((col + ½)/W, (row + ½)/H) on
    // the floor's affine layout.
    let pos: Vec<f64> = (0..3).map(|i| number(&worst["position"][i])).collect();
    let prim = &read.primitives[0];
    let lm = &read.lightmaps[0];
    let centre = glam::DVec2::new(
        ((k % w) as f64 + 0.5) / lm.width as f64,
        ((k / w) as f64 + 0.5) / lm.height as f64,
    );
    let tri = prim.triangles[0].map(|v| v as usize);
    let q = tri.map(|v| layout.uv[v]);
    let d2 = (q[1] - q[0]).perp_dot(q[2] - q[0]);
    let l1 = (centre - q[0]).perp_dot(q[2] - q[0]) / d2;
    let l2 = (q[1] - q[0]).perp_dot(centre - q[0]) / d2;
    let want = prim.positions[tri[0]] * (1.0 - l1 - l2)
        + prim.positions[tri[1]] * l1
        + prim.positions[tri[2]] * l2;
    assert!(
        (DVec3::from_slice(&pos) - want).length() < 1e-6,
        "{pos:?} vs {want}"
    );
    let run = diff(&a, &b, &[]);
    let verdict = last_line(&run.stdout);
    let named = format!(
        "illuminance node floor primitive 0 atlas 0 texel ({}, {})",
        k % w,
        k / w
    );
    assert!(
        verdict.starts_with("FAIL: 1 of ") && verdict.contains(&named),
        "{verdict}"
    );

    // --no-lightmaps: the vertex values, which the edit did not touch.
    let (run, d) = diff_json(&a, &b, &["--no-lightmaps"]);
    assert_eq!(run.code, Some(0), "{}", run.stdout);
    assert_eq!(d["mode"], "vertices");

    // A missing EXR file: exit 2, one line naming the file, the material and the EXR.
    let exr = support::hashed(a.parent().unwrap(), "lit.lightmap0.#.exr");
    let exr_name = exr.file_name().unwrap().to_str().unwrap().to_string();
    std::fs::remove_file(&exr).unwrap();
    let run = diff(&a, &b, &[]);
    assert_eq!(run.code, Some(2));
    assert!(run.stdout.is_empty());
    let err = run.stderr.trim_end();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("a/lit.gltf")
            && err.contains("/extensions/LUXBAKE_lightmap")
            && err.contains(&format!("{exr_name} cannot be opened")),
        "{err}"
    );
}

#[test]
fn other_layouts_compare_at_surface_points() {
    let dir = scratch("diff-lm-samples");
    let scene = smooth_room();
    let coarse = bake(&scene, &settings(Some(0.1)), &Silent).unwrap();
    let fine = bake(&scene, &settings(Some(0.05)), &Silent).unwrap();
    let (a, b) = (
        write(&dir, "coarse", &scene, &coarse),
        write(&dir, "fine", &scene, &fine),
    );
    // What a viewer shows at a vertex is read between texel centres half a texel inside the
    // chart: where light bends (the floor's corners against the walls) a 10 cm texel and a 5 cm
    // one differ by some per cent there.
    let (run, d) = diff_json(&a, &b, &["--rtol", "0.05"]);
    assert_eq!(run.code, Some(0), "{}", run.stdout);
    assert_eq!(d["mode"], "samples");
    assert!(
        d["lightmaps"].as_str().unwrap().contains("other layouts"),
        "{d}"
    );
    // Every vertex and every triangle's centroid of every primitive, three quantities.
    let read = luxbake::readback::read(&b).unwrap();
    let points: usize = (read.primitives.iter())
        .map(|p| p.positions.len() + p.triangles.len())
        .sum();
    assert_eq!(number(&d["values"]) as usize, 3 * points);
    // Not the same bake: the texels differ somewhere; little on average.
    let rel = &quantity(&d, "illuminance")["overall"]["rel"];
    let (max, mean) = (number(&rel["max"]), number(&rel["mean"]));
    assert!(max > 0.0 && mean < 0.005, "{rel}");

    // Texel by texel needs the same layout.
    let run = diff(&a, &b, &["--mode", "texels"]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("lightmap layouts differ: atlas 0 is"),
        "{}",
        run.stderr
    );
    // Sampling may be asked for the same layout too.
    let (run, d) = diff_json(&b, &b, &["--mode", "samples"]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(
        (d["mode"].as_str(), d["failed"].as_u64()),
        (Some("samples"), Some(0))
    );
}

#[test]
fn lightmaps_in_one_bake_only_fall_back_to_vertices() {
    let dir = scratch("diff-lm-one");
    let scene = smooth_room();
    let lit = bake(&scene, &settings(Some(0.1)), &Silent).unwrap();
    let plain = bake(&scene, &settings(None), &Silent).unwrap();
    let (a, b) = (
        write(&dir, "lit", &scene, &lit),
        write(&dir, "plain", &scene, &plain),
    );
    // Vertex by vertex, paired by place (the layout re-indexed A's vertices): the bakes differ
    // in nothing else, so every vertex value is equal.
    let (run, d) = diff_json(&a, &b, &["--rtol", "0"]);
    assert_eq!(run.code, Some(0), "{}{}", run.stdout, run.stderr);
    assert_eq!(d["mode"], "vertices");
    assert_eq!(
        d["lightmaps"],
        "only A has lightmaps: compared vertex by vertex"
    );
    let read = luxbake::readback::read(&b).unwrap();
    let vertices: usize = read.primitives.iter().map(|p| p.positions.len()).sum();
    assert_eq!(number(&d["values"]) as usize, 3 * vertices);
    let (run, _) = diff_json(&b, &a, &["--rtol", "0"]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    // A vertex moved is named.
    let mut moved = lit.clone();
    moved.surfaces[0].positions[0].y += 0.01;
    let c = write(&dir, "moved", &scene, &moved);
    let run = diff(&c, &b, &[]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("no vertex of A within")
            && run.stderr.contains("(only A has lightmaps)"),
        "{}",
        run.stderr
    );
    let (run, d) = diff_json(&a, &b, &["--mode", "means", "--rtol", "1e-6"]);
    assert_eq!(run.code, Some(0), "{}{}", run.stdout, run.stderr);
    assert_eq!(d["lightmaps"], "only A has lightmaps: means over vertices");
    let run = diff(&b, &a, &["--mode", "texels"]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("only B has lightmaps"),
        "{}",
        run.stderr
    );
}
