//! What a glTF viewer shows is what luxbake computed (issue 26): `samples/office` baked at draft
//! quality, seen from its camera node `camera_interior` by three.js (GLTFLoader in headless
//! Chromium, `bench/render/render.mjs`) and by `bake view --display` (the bake's unlit
//! materials, baseColor × COLOR_0 or × the display lightmap, sRGB-encoded), at the same size,
//! compared pixel by pixel.
//!
//! Needs node, Debian `chromium` and npm `three` (`npm ci --prefix bench/render`): skipped with
//! a message when absent, failed under CI (`support::tools::have_three`). With
//! `LUXBAKE_VIEWER_PNGS=DIR` the three PNGs (three.js, bake view, difference × 8) are copied
//! into DIR as `viewer-<variant>-{three,view,diff}.png` to look at.

mod support;

use std::path::{Path, PathBuf};
use support::{cli, scratch, tools};

const CAMERA: &str = "camera_interior";
const WIDTH: usize = 600;
const HEIGHT: usize = 400;

/// 8-bit RGB pixels of a PNG, row 0 at the top.
fn read_png(path: &Path) -> Vec<u8> {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!(
        (info.width as usize, info.height as usize, info.bit_depth),
        (WIDTH, HEIGHT, png::BitDepth::Eight),
        "{}",
        path.display()
    );
    match info.color_type {
        png::ColorType::Rgb => pixels.truncate(info.buffer_size()),
        png::ColorType::Rgba => {
            pixels.truncate(info.buffer_size());
            pixels = pixels.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        }
        other => panic!("{}: colour type {other:?}", path.display()),
    }
    pixels
}

/// |a − b| per channel, scaled × 8 so a 1/255 step is visible, as an RGB PNG.
fn write_difference(a: &[u8], b: &[u8], path: &Path) {
    let diff: Vec<u8> = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (x.abs_diff(y) as u32 * 8).min(255) as u8)
        .collect();
    let mut encoder = png::Encoder::new(
        std::io::BufWriter::new(std::fs::File::create(path).unwrap()),
        WIDTH as u32,
        HEIGHT as u32,
    );
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&diff).unwrap();
}

/// Mean absolute difference per channel (in 1/255 steps) and the fraction of pixels whose
/// three channels all differ by at most `within`.
fn compare(a: &[u8], b: &[u8], within: u8) -> ([f64; 3], f64) {
    let mut sum = [0u64; 3];
    let mut close = 0usize;
    for (p, q) in a.chunks(3).zip(b.chunks(3)) {
        let d: Vec<u8> = p.iter().zip(q).map(|(x, y)| x.abs_diff(*y)).collect();
        for c in 0..3 {
            sum[c] += d[c] as u64;
        }
        close += usize::from(d.iter().all(|&x| x <= within));
    }
    let n = (WIDTH * HEIGHT) as f64;
    (sum.map(|s| s as f64 / n), close as f64 / n)
}

/// Bake the office with `extra`, render `CAMERA` both ways, compare; returns (mean per
/// channel, fraction within 8/255).
fn both_renders(variant: &str, extra: &[&str]) -> Option<([f64; 3], f64)> {
    if !tools::have_three() {
        return None;
    }
    let dir = scratch(&format!("viewer-{variant}"));
    let lit = dir.join("lit.gltf");
    let run = cli::bake_draft(&cli::repo_file("samples/office/office.gltf"), &lit, extra);
    assert!(run.ok(), "{run:?}");

    let three = dir.join("three.png");
    let size = format!("{WIDTH}x{HEIGHT}");
    tools::render_three(&lit, &three, CAMERA, &size);
    let view = dir.join("view.png");
    let run = cli::bake([
        "view".as_ref(),
        lit.as_os_str(),
        "-o".as_ref(),
        dir.join("view.exr").as_os_str(),
        "--camera".as_ref(),
        CAMERA.as_ref(),
        "--size".as_ref(),
        size.as_ref(),
        "--display".as_ref(),
        view.as_os_str(),
    ]);
    assert!(run.ok(), "{run:?}");

    let (a, b) = (read_png(&three), read_png(&view));
    let diff = dir.join("diff.png");
    write_difference(&a, &b, &diff);
    if let Some(to) = std::env::var_os("LUXBAKE_VIEWER_PNGS") {
        for (name, from) in [("three", &three), ("view", &view), ("diff", &diff)] {
            let target: PathBuf = Path::new(&to).join(format!("viewer-{variant}-{name}.png"));
            std::fs::copy(from, target).unwrap();
        }
    }
    let stats = compare(&a, &b, 8);
    eprintln!(
        "{variant}: mean |three − view| = {:.3} {:.3} {:.3} (1/255), {:.3} % of pixels within 8/255",
        stats.0[0],
        stats.0[1],
        stats.0[2],
        100.0 * stats.1
    );
    Some(stats)
}

/// The tolerance (TODO: measured).
fn assert_close(variant: &str, (mean, within): ([f64; 3], f64)) {
    for (c, m) in mean.iter().enumerate() {
        assert!(*m <= 2.0, "{variant}: channel {c} mean difference {m:.3}/255 > 2/255");
    }
    assert!(
        within >= 0.99,
        "{variant}: {:.3} % of pixels within 8/255, want ≥ 99 %",
        100.0 * within
    );
}

#[test]
fn three_js_shows_the_vertex_bake_as_bake_view_display() {
    if let Some(stats) = both_renders("vertex", &[] as &[&str]) {
        assert_close("vertex", stats);
    }
}

#[test]
fn three_js_shows_the_lightmapped_bake_as_bake_view_display() {
    if let Some(stats) = both_renders("lightmaps", &["--lightmaps"]) {
        assert_close("lightmaps", stats);
    }
}
