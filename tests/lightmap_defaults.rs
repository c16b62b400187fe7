//! The lightmaps' default texel size and the coarser layout, as docs/lightmaps.md states them:
//! a quarter of the patch size, at most the quality's edge (0.1 / 0.05 / 0.025 m) and at least
//! what keeps the texel count under the quality's cap (0.25 / 1 / 4 million); a surface too
//! large for one atlas laid out coarser and named in the summary. Every other lightmap test
//! passes `--texel-size`.

mod support;

use glam::DVec3;
use luxbake::fixtures::SceneBuilder;
use serde_json::Value;
use std::path::Path;
use support::cli::{bake, repo_file};
use support::scratch;

/// Bake `input` with lightmaps and `extra` options; the run summary.
fn lightmapped(input: &Path, dir: &Path, extra: &[&str]) -> Value {
    let (out, summary) = (dir.join("lit.glb"), dir.join("summary.json"));
    let mut args = vec![
        input.as_os_str().to_owned(),
        "-o".into(),
        out.as_os_str().to_owned(),
        "--lightmaps".into(),
        "--summary-json".into(),
        summary.as_os_str().to_owned(),
        "-q".into(),
    ];
    args.extend(extra.iter().map(|a| a.into()));
    let run = bake(args);
    assert!(run.ok(), "{}", run.stderr);
    serde_json::from_slice(&std::fs::read(summary).unwrap()).unwrap()
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn the_default_texel_is_a_quarter_patch_at_most_the_qualitys_edge() {
    // The office: h/4 is above the default quality's 5 cm, so 5 cm (about 71 000 texels).
    let s = lightmapped(
        &repo_file("samples/office/office.gltf"),
        &scratch("lm-default-office"),
        &[],
    );
    let (h, texel) = (num(&s["patchSize"]), num(&s["lightmaps"]["texelSizeM"]));
    let texels = num(&s["lightmaps"]["texels"]);
    println!("office: patch {h:.4} m, texel {texel} m, {texels} texels");
    assert!(h / 4.0 > 0.05 && texel == 0.05, "h {h}, texel {texel}");
    assert!((texels / 71_000.0 - 1.0).abs() < 0.05, "{texels} texels");
    // The Cornell box (0.55 m): a quarter of its patch size, under the 5 cm edge.
    let s = lightmapped(
        &repo_file("samples/cornell-box/cornell-box.obj"),
        &scratch("lm-default-cornell"),
        &[],
    );
    let (h, texel) = (num(&s["patchSize"]), num(&s["lightmaps"]["texelSizeM"]));
    println!("cornell box: patch {h:.5} m, texel {texel:.5} m");
    assert!((texel - h / 4.0).abs() < 1e-12, "h {h}, texel {texel}");
    assert!(
        (texel - 0.0077).abs() < 0.00005,
        "texel {texel} (docs: 7.7 mm)"
    );
}

#[test]
fn a_large_room_is_held_to_the_qualitys_texel_count() {
    // A 50 × 50 × 3 m hall (5 600 m²) at draft: 0.1 m texels would be 560 000, over the
    // 250 000 cap, so the texel is √(area / cap) = 0.15 m.
    let mut b = SceneBuilder::new();
    let walls = b.material("walls", 0.5);
    b.axis_box(
        "hall",
        DVec3::ZERO,
        DVec3::new(50.0, 3.0, 50.0),
        true,
        walls,
    );
    b.point_light("lamp", DVec3::new(25.0, 2.8, 25.0), 10_000.0);
    let dir = scratch("lm-default-hall");
    let input = dir.join("hall.gltf");
    luxbake::export::write_scene(&input, &b.build()).unwrap();
    let s = lightmapped(&input, &dir, &["--quality", "draft"]);
    let texel = num(&s["lightmaps"]["texelSizeM"]);
    let want = (5_600.0f64 / 250_000.0).sqrt();
    let texels = num(&s["lightmaps"]["texels"]);
    println!("hall: texel {texel:.4} m (cap rule {want:.4} m), {texels} texels");
    assert!(
        (texel / want - 1.0).abs() < 1e-9,
        "texel {texel}, want {want}"
    );
    assert!(texels <= 250_000.0 * 1.05, "{texels} texels");
}

#[test]
fn a_surface_too_large_for_one_atlas_is_laid_out_coarser_and_named() {
    // The Cornell box's walls are 0.55 m: 275 texels at 2 mm, more than a 128-texel atlas.
    let max = 128;
    let s = lightmapped(
        &repo_file("samples/cornell-box/cornell-box.obj"),
        &scratch("lm-coarser"),
        &["--texel-size", "0.002", "--lightmap-size", &max.to_string()],
    );
    let lm = &s["lightmaps"];
    assert_eq!(num(&lm["texelSizeM"]), 0.002);
    let coarser = lm["coarser"].as_array().unwrap();
    println!("coarser: {coarser:?}");
    assert!(coarser.len() >= 5, "{coarser:?}");
    for c in coarser {
        let t = num(&c["texelSizeM"]);
        // Coarser than asked, and the surface's 0.55 m then fits one atlas.
        assert!(t > 0.002 && 0.55 / t <= max as f64, "{c}");
    }
    for a in lm["atlases"].as_array().unwrap() {
        let [w, h] = [num(&a[0]), num(&a[1])];
        assert!(w <= max as f64 && h <= max as f64, "atlas {a}");
    }
}
