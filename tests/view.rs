//! `bake view` against closed forms and exact expectations: the furnace room (every pixel
//! L_e/(1 − ρ)), a floor under a point light seen from above (lightmapped: ρ·I·cos θ/(π·d²) at the
//! point each centre ray hits; vertex-only: ρ/π × the baked vertex illuminance interpolated
//! there), a luminaire's opening seen from below (I/A), the same bytes on one and two threads,
//! glTF camera nodes, and the errors and the inside-a-solid warning. Axes: glTF, +Y up.

mod support;

use glam::{DVec2, DVec3};
use luxbake::export;
use luxbake::fixtures::{self, SceneBuilder};
use luxbake::scene::{LocalTransform, Node, Scene};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use support::cli::{Run, assert_error_line, bake, bake_draft};

/// Write `scene` as `NAME/in/scene.gltf`, bake it at draft quality with `extra` into
/// `NAME/out/lit.gltf`.
fn baked(name: &str, scene: &Scene, extra: &[&str]) -> PathBuf {
    let (input, out) = support::in_out(name);
    let source = input.join("scene.gltf");
    export::write_scene(&source, scene).unwrap();
    let lit = out.join("lit.gltf");
    let run = bake_draft(&source, &lit, extra);
    assert!(run.ok(), "{run:?}");
    lit
}

fn view(lit: &Path, exr: &Path, args: &[&str]) -> Run {
    let mut all: Vec<&str> = vec!["view", lit.to_str().unwrap(), "-o", exr.to_str().unwrap()];
    all.extend_from_slice(args);
    bake(all)
}

/// The EXR's (width, height, R, G, B, luminance).
fn read_exr(path: &Path) -> (usize, usize, Vec<Vec<f32>>) {
    let bytes = std::fs::read(path).unwrap();
    let c = luxbake::import::exr::decode(&bytes, &["R", "G", "B", "luminance"]).unwrap();
    (c.width, c.height, c.channels)
}

/// The unit ray through pixel centre (col, row) of a `w` × `h` image, independently of the
/// crate: vertical field of view `fov_deg`, row 0 at the top.
fn centre_ray(
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    fov_deg: f64,
    (w, h): (usize, usize),
    col: usize,
    row: usize,
) -> DVec3 {
    let f = (target - eye).normalize();
    let r = f.cross(up).normalize();
    let u = r.cross(f);
    let t = (fov_deg.to_radians() / 2.0).tan();
    let p = DVec2::new(col as f64 + 0.5, row as f64 + 0.5);
    let x = (2.0 * p.x / w as f64 - 1.0) * t * (w as f64 / h as f64);
    let y = (1.0 - 2.0 * p.y / h as f64) * t;
    (f + r * x + u * y).normalize()
}

#[test]
fn furnace_every_pixel_is_the_exitance_over_pi() {
    let (rho, l) = (0.5, 100.0);
    let lit = baked(
        "view-furnace",
        &fixtures::furnace(DVec3::new(2.0, 3.0, 5.0), rho, l),
        &[],
    );
    let exr = lit.with_file_name("furnace.exr");
    // From the middle of the room toward a corner (walls, floor and ceiling all in view).
    let run = view(
        &lit,
        &exr,
        &[
            "--eye",
            "1,1.5,2.5",
            "--target",
            "0,0,0",
            "--fov",
            "100",
            "--size",
            "48x32",
        ],
    );
    assert!(run.ok(), "{run:?}");
    let (w, h, c) = read_exr(&exr);
    assert_eq!((w, h), (48, 32));
    let want = l / (1.0 - rho);
    for channel in &c {
        for (k, &v) in channel.iter().enumerate() {
            let err = (v as f64 / want - 1.0).abs();
            assert!(err < 0.005, "pixel {k}: {v} cd/m² against {want}");
        }
    }
}

/// A floor of reflectance ρ (y = 0, ±2 m) under an isotropic point light; (scene, light
/// position, intensity in cd).
fn floor_under_a_light(rho: f64) -> (Scene, DVec3, f64) {
    let mut b = SceneBuilder::new();
    let m = b.material("grey", rho);
    b.floor("floor", 2.0, 0.0, m);
    let light = DVec3::new(0.3, 2.0, -0.2);
    let flux = 10_000.0;
    b.point_light("bulb", light, flux);
    (b.build(), light, flux / (4.0 * PI))
}

const EYE: DVec3 = DVec3::new(0.2, 4.0, 0.1);
const TARGET: DVec3 = DVec3::ZERO;
const UP: DVec3 = DVec3::new(0.0, 0.0, -1.0);
const FOV: f64 = 30.0;
const SIZE: (usize, usize) = (40, 30);

/// Per pixel: the floor point its centre ray hits, and the view's luminance there.
fn floor_view(lit: &Path) -> Vec<(DVec3, [f64; 4])> {
    let exr = lit.with_file_name("floor.exr");
    let run = view(
        lit,
        &exr,
        &[
            "--eye",
            "0.2,4,0.1",
            "--target",
            "0,0,0",
            "--up",
            "0,0,-1",
            "--fov",
            "30",
            "--size",
            "40x30",
            "--samples",
            "1",
        ],
    );
    assert!(run.ok(), "{run:?}");
    let (w, h, c) = read_exr(&exr);
    assert_eq!((w, h), SIZE);
    let mut out = Vec::new();
    for row in 0..h {
        for col in 0..w {
            let d = centre_ray(EYE, TARGET, UP, FOV, SIZE, col, row);
            let p = EYE + d * (-EYE.y / d.y);
            assert!(
                p.x.abs() < 1.5 && p.z.abs() < 1.5,
                "{p} should be well inside the floor"
            );
            let k = row * w + col;
            out.push((p, [0, 1, 2, 3].map(|i| c[i][k] as f64)));
        }
    }
    out
}

#[test]
fn lightmapped_floor_every_pixel_within_half_a_percent_of_the_closed_form() {
    let rho = 0.5;
    let (scene, light, i) = floor_under_a_light(rho);
    let lit = baked(
        "view-floor-lightmapped",
        &scene,
        &["--lightmaps", "--texel-size", "0.05"],
    );
    let mut worst = 0.0f64;
    for (p, values) in floor_view(&lit) {
        let d = light - p;
        let want = rho * i * (d.y / d.length()) / (PI * d.length_squared());
        for v in values {
            worst = worst.max((v / want - 1.0).abs());
        }
    }
    assert!(worst < 0.005, "worst pixel off by {:.3} %", worst * 100.0);
}

#[test]
fn vertex_floor_every_pixel_is_the_interpolated_vertex_luminance() {
    let rho = 0.5;
    let (scene, _, _) = floor_under_a_light(rho);
    let lit = baked("view-floor-vertices", &scene, &[]);
    let output = luxbake::readback::read(&lit).unwrap();
    assert_eq!(output.primitives.len(), 1);
    let prim = &output.primitives[0];
    assert!(prim.lightmap.is_none());
    // ρ/π × the vertex illuminance interpolated at p (the floor's triangles in x, z).
    let interpolated = |p: DVec3| -> f64 {
        let q = |v: u32| {
            let w = prim.positions[v as usize];
            DVec2::new(w.x, w.z)
        };
        let x = DVec2::new(p.x, p.z);
        for t in &prim.triangles {
            let [a, b, c] = t.map(q);
            let den = (b - a).perp_dot(c - a);
            let l1 = (x - a).perp_dot(c - a) / den;
            let l2 = (b - a).perp_dot(x - a) / den;
            let l0 = 1.0 - l1 - l2;
            if l0.min(l1).min(l2) >= -1e-9 {
                let e = t.map(|v| prim.illuminance[v as usize] as f64);
                return l0 * e[0] + l1 * e[1] + l2 * e[2];
            }
        }
        panic!("{p} is on no triangle of the floor");
    };
    assert!(
        prim.triangles.len() > 20,
        "an adaptive mesh, not two triangles"
    );
    let mut worst = 0.0f64;
    for (p, values) in floor_view(&lit) {
        let want = rho / PI * interpolated(p);
        for v in values {
            worst = worst.max((v / want - 1.0).abs());
        }
    }
    assert!(worst < 0.005, "worst pixel off by {:.3} %", worst * 100.0);
}

#[test]
fn a_coloured_vertex_floor_under_a_coloured_light_keeps_both_colours() {
    // A floor of RGB reflectance ρ under a light of relative colour ĉ (luminance 1) leaves
    // L_c ∝ ρ_c·ĉ_c in each channel, its Y the baked `_LUMINANCE`: the colour the view rebuilds
    // from COLOR_0 and the material's reflectance (ρ alone would miss the light's colour).
    let rho = DVec3::new(0.6, 0.4, 0.2);
    let (scene, _, _) = floor_under_a_light(0.5);
    let mut b = SceneBuilder::from_scene(scene);
    let m = b.material_full("tinted", rho, None, false);
    let mut scene = b.build();
    scene.surfaces[0].material = m;
    let c = DVec3::new(1.0, 0.8, 0.3);
    let c = c / luxbake::scene::luma(c);
    scene.lights[0].color = c;
    let lit = baked("view-colour", &scene, &[]);
    let tint = rho * c;
    let y = luxbake::scene::luma(tint);
    let mut worst = 0.0f64;
    for (_, [r, g, b, l]) in floor_view(&lit) {
        for (v, t) in [r, g, b].into_iter().zip(tint.to_array()) {
            worst = worst.max((v / (l * t / y) - 1.0).abs());
        }
    }
    assert!(worst < 1e-3, "worst channel off by {:.4} %", worst * 100.0);
}

/// A 6 × 6 m grey floor and, 2.5 m above its centre facing down (+Y up), the office's louvred
/// fitting profile with a flat `length` × `width` m opening, its C0 plane along `c0`.
fn opening_above_a_floor(length: f64, width: f64, c0: DVec3) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.material("grey", 0.3);
    b.floor("floor", 3.0, 0.0, m);
    let ies = std::fs::read(support::cli::repo_file(
        "samples/office/profiles/miral_58w.ies",
    ))
    .unwrap();
    let opening = luxbake::photometry::Opening {
        length,
        width,
        height: 0.0,
        shape: luxbake::photometry::OpeningShape::Rectangular,
    };
    b.luminaire(
        "panel",
        &ies,
        luxbake::photometry::Format::Ies,
        DVec3::new(0.0, 2.5, 0.0),
        -DVec3::Y,
        c0,
        1.0,
        Some(opening),
    );
    b.build()
}

#[test]
fn a_luminaire_opening_seen_from_below_shows_its_intensity_over_its_area() {
    // A 0.6 × 0.3 m flat opening 2.5 m above a floor, facing down; the view looks straight up
    // at it from 1 m above the floor, the opening filling the centre of the image.
    let scene = opening_above_a_floor(0.6, 0.3, DVec3::X);
    let i0 = scene.profiles[0]
        .photometry
        .intensity(DVec3::new(0.0, 0.0, -1.0));
    let lit = baked("view-luminaire", &scene, &[]);
    let exr = lit.with_file_name("up.exr");
    let run = view(
        &lit,
        &exr,
        &[
            "--eye",
            "0,1,0",
            "--target",
            "0,2.5,0",
            "--up",
            "1,0,0",
            "--fov",
            "2",
            "--size",
            "9x9",
            "--samples",
            "1",
        ],
    );
    assert!(run.ok(), "{run:?}");
    let (_, _, c) = read_exr(&exr);
    // The centre pixel looks along the nadir: L = I(0, 0) / 0.18 m².
    let want = i0 / 0.18;
    let got = c[3][4 * 9 + 4] as f64;
    assert!(
        (got / want - 1.0).abs() < 1e-4,
        "{got} against {want} cd/m²"
    );
    // Every pixel of this 2° view is on the opening (it spans ±0.15 m at 1.5 m: ±5.7°).
    for (k, &v) in c[3].iter().enumerate() {
        assert!((v as f64 / want - 1.0).abs() < 0.01, "pixel {k}: {v}");
    }
}

#[test]
fn same_bytes_on_one_and_two_threads() {
    let (scene, _, _) = floor_under_a_light(0.5);
    let lit = baked("view-threads", &scene, &["--lightmaps"]);
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let dir = lit.parent().unwrap().join(format!("t{threads}"));
        std::fs::create_dir_all(&dir).unwrap();
        let name = |n: &str| dir.join(n).to_str().unwrap().to_string();
        let (png, fc, display) = (name("v.png"), name("fc.png"), name("d.png"));
        let run = view(
            &lit,
            &dir.join("v.exr"),
            &[
                "--eye",
                "1,2,3",
                "--target",
                "0,0,0",
                "--size",
                "64x48",
                "--threads",
                threads,
                "--png",
                &png,
                "--false-colour",
                &fc,
                "--display",
                &display,
            ],
        );
        assert!(run.ok(), "{run:?}");
        outputs.push(
            ["v.exr", "v.png", "fc.png", "d.png"].map(|n| std::fs::read(dir.join(n)).unwrap()),
        );
    }
    for (k, (one, two)) in outputs[0].iter().zip(&outputs[1]).enumerate() {
        assert!(one == two, "output {k} differs between thread counts");
    }
    // --zip: the same values, smaller, deterministic
    let dir = lit.parent().unwrap().join("t1");
    let args = [
        "--eye", "1,2,3", "--target", "0,0,0", "--size", "64x48", "--zip",
    ];
    for n in ["z1.exr", "z2.exr"] {
        assert!(view(&lit, &dir.join(n), &args).ok());
    }
    let (zipped, plain) = (dir.join("z1.exr"), dir.join("v.exr"));
    assert_eq!(
        std::fs::read(&zipped).unwrap(),
        std::fs::read(dir.join("z2.exr")).unwrap()
    );
    assert!(std::fs::metadata(&zipped).unwrap().len() < std::fs::metadata(&plain).unwrap().len());
    assert_eq!(read_exr(&zipped), read_exr(&plain));
}

/// The floor scene with a camera node `overview` 3 m above the floor looking down (its −Z is
/// world −Y), yfov 0.8 rad, aspect ratio 1.5.
fn with_camera() -> Scene {
    let (mut scene, _, _) = floor_under_a_light(0.5);
    scene.cameras.push(serde_json::json!({
        "type": "perspective",
        "perspective": {"yfov": 0.8, "znear": 0.05, "aspectRatio": 1.5}
    }));
    let rotation = glam::DQuat::from_rotation_x(-PI / 2.0);
    let translation = DVec3::new(0.0, 3.0, 0.0);
    let node = scene.nodes.len();
    scene.nodes.push(Node {
        name: Some("overview".into()),
        source_path: format!("/nodes/{node}"),
        children: Vec::new(),
        local: LocalTransform::Trs {
            translation,
            rotation,
            scale: DVec3::ONE,
        },
        world_from_local: glam::DMat4::from_rotation_translation(rotation, translation),
        mesh_name: None,
        surfaces: Vec::new(),
        light: None,
        camera: Some(0),
        extras: None,
    });
    scene.roots.push(node);
    scene
}

#[test]
fn a_camera_node_by_name_and_the_errors() {
    let lit = baked("view-camera", &with_camera(), &[]);
    let exr = lit.with_file_name("cam.exr");
    let run = view(&lit, &exr, &["--camera", "overview", "--size", "30x20"]);
    assert!(run.ok(), "{run:?}");
    let (w, h, c) = read_exr(&exr);
    assert_eq!((w, h), (30, 20));
    // Looking straight down at a lit floor: every pixel sees it.
    assert!(c[3].iter().all(|&v| v > 0.0));

    let run = view(&lit, &exr, &["--camera", "nobody"]);
    assert_error_line(&run, &["nobody", "overview"]);
    assert_eq!(run.code, Some(2));
    for size in ["0x10", "16385x10", "10x0"] {
        let run = view(
            &lit,
            &exr,
            &["--eye", "0,1,0", "--target", "0,0,0", "--size", size],
        );
        assert_error_line(&run, &[size]);
        assert_eq!(run.code, Some(2), "{size}");
    }
    // The unbaked input is not a luxbake output.
    let input = lit
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("in/scene.gltf");
    let run = view(&input, &exr, &["--eye", "0,1,0", "--target", "0,0,0"]);
    assert_error_line(&run, &["scene.gltf", "not a luxbake output"]);
    assert_eq!(run.code, Some(1));
}

#[test]
fn a_camera_inside_a_solid_is_warned_about() {
    // A closed box with outward faces (a solid) on a floor under a light.
    let (scene, _, _) = floor_under_a_light(0.5);
    let mut b = SceneBuilder::from_scene(scene);
    let m = b.material("crate", 0.5);
    b.axis_box(
        "crate",
        DVec3::new(-0.5, 0.0, -0.5),
        DVec3::new(0.5, 1.0, 0.5),
        false,
        m,
    );
    let lit = baked("view-solid", &b.build(), &[]);
    let exr = lit.with_file_name("inside.exr");
    let run = view(
        &lit,
        &exr,
        &["--eye", "0,0.5,0", "--target", "1,0.5,0", "--size", "8x8"],
    );
    assert!(run.ok(), "{run:?}");
    assert!(run.stderr.contains("inside a solid"), "{}", run.stderr);
    let run = view(
        &lit,
        &exr,
        &["--eye", "0,2,1.5", "--target", "0,0,0", "--size", "8x8"],
    );
    assert!(
        run.ok() && !run.stderr.contains("inside a solid"),
        "{run:?}"
    );
}

/// Antialiasing against the area each pixel sees of a square opening (0.4 m, turned 30° so its
/// edges cross the pixels at every offset; 1.5 m above the eye, looked at straight on): with 16
/// samples an edge pixel is the luminance times the share of its footprint on the square (from
/// 32 × 32 sub-points in the test) within 0.15, and within 0.05 on average; with one sample per
/// pixel the edge pixels are all or nothing.
#[test]
fn antialiased_edge_pixels_show_the_share_of_the_opening_they_see() {
    let turn = 30f64.to_radians();
    let c0 = DVec3::new(turn.cos(), 0.0, turn.sin());
    let lit = baked("view-antialias", &opening_above_a_floor(0.4, 0.4, c0), &[]);
    let n = 61;
    let shot = |samples: &str| {
        let exr = lit.with_file_name(format!("aa-{samples}.exr"));
        let size = format!("{n}x{n}");
        let args = [
            "--eye",
            "0,1,0",
            "--target",
            "0,2.5,0",
            "--up",
            "1,0,0",
            "--fov",
            "30",
            "--size",
            &size,
            "--samples",
            samples,
        ];
        let run = view(&lit, &exr, &args);
        assert!(run.ok(), "{run:?}");
        read_exr(&exr).2[3].clone()
    };
    let (one, many) = (shot("1"), shot("16"));
    // The share of pixel (col, row)'s footprint on the square: the image plane is parallel to
    // the opening, 1.5 m on; with up = +X the image's right is world −Z and its top +X, so the
    // point at image offsets (x, y) (in pixels from the centre, y up) is world
    // (1.5·t·y, ·, −1.5·t·x) with t the pixel's angular size at unit distance.
    let t = 2.0 * 15f64.to_radians().tan() / n as f64;
    let share = |col: usize, row: usize| {
        let mut inside = 0;
        for i in 0..32 {
            for j in 0..32 {
                let x = col as f64 - n as f64 / 2.0 + (i as f64 + 0.5) / 32.0;
                let y = n as f64 / 2.0 - (row as f64 + (j as f64 + 0.5) / 32.0);
                let w = DVec3::new(1.5 * t * y, 0.0, -1.5 * t * x);
                let (a, b) = (w.dot(c0), w.dot(DVec3::Y.cross(c0)));
                inside += (a.abs() <= 0.2 && b.abs() <= 0.2) as usize;
            }
        }
        inside as f64 / 1024.0
    };
    let centre = many[(n / 2) * n + n / 2] as f64;
    assert!(centre > 0.0);
    let (mut edge, mut sum_many, mut sum_one, mut worst) = (0, 0.0, 0.0, 0.0f64);
    for row in 0..n {
        for col in 0..n {
            let f = share(col, row);
            let k = row * n + col;
            let (a, b) = (many[k] as f64 / centre, one[k] as f64 / centre);
            if f == 0.0 || f == 1.0 {
                // Wholly off or on the disc: both images agree (the disc's luminance varies
                // by well under 1 % over these directions).
                assert!(
                    (a - f).abs() < 0.01 && (b - f).abs() < 0.01,
                    "({col}, {row}): {a} {b} {f}"
                );
                continue;
            }
            edge += 1;
            worst = worst.max((a - f).abs());
            sum_many += (a - f).abs();
            sum_one += (b - f).abs();
            assert!(b.abs() < 0.01 || (b - 1.0).abs() < 0.01, "one sample: {b}");
        }
    }
    let (mean_many, mean_one) = (sum_many / edge as f64, sum_one / edge as f64);
    println!(
        "antialiasing: {edge} edge pixels, 16 samples mean |error| {mean_many:.3} (worst {worst:.3}), 1 sample {mean_one:.3}"
    );
    assert!(edge > 50, "{edge} edge pixels");
    assert!(worst < 0.15 && mean_many < 0.05, "{worst} {mean_many}");
    assert!(mean_one > 3.0 * mean_many, "{mean_one} against {mean_many}");
}
