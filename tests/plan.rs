//! `bake plan` (`src/plan/`): isolux contours against the closed form of a point light over a
//! floor (the working plane, the floor from its vertices and from its lightmap), the SVG
//! well-formed with its labels, legend and scale bar, the PNG of the right size with the field's
//! colours, byte-identical repeats, and the errors (no working plane, unknown node, non-planar
//! node, output = input, bad options).

mod support;

use glam::{DVec2, DVec3};
use luxbake::fixtures::SceneBuilder;
use luxbake::plan::{self, Options, Plan, Quantity, Source};
use luxbake::readback::BakedOutput;
use luxbake::scene::Scene;
use luxbake::settings::{LightmapSettings, ProbeGrid, Quality, Settings};
use std::path::PathBuf;
use std::sync::OnceLock;
use support::cli::{assert_error_line, bake as run_bake};

/// The lamp's intensity (cd), its height above the floor (m), the working plane's height.
const I: f64 = 1000.0;
const LAMP_Y: f64 = 2.0;
const PLANE_Y: f64 = 0.5;

/// A 4 × 4 m floor (ρ 0.5) at y = 0 under an isotropic point light of I cd at (0, 2, 0), +Y up,
/// nothing else: nothing reflects light back down, so the illuminance of any upward face is the
/// direct E = I·h/(h² + r²)^{3/2} (h: the lamp's height above it, r: the horizontal distance).
/// Also a bent node `tent` (two triangles in different planes) above a corner, away from the
/// light's path to the plane's middle.
fn scene() -> Scene {
    let mut b = SceneBuilder::new();
    let grey = b.material("grey", 0.5);
    b.floor("floor", 2.0, 0.0, grey);
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    b.surface(
        "tent",
        vec![
            p(1.8, 1.0, 1.8),
            p(1.9, 1.1, 1.8),
            p(1.9, 1.1, 1.9),
            p(2.0, 1.0, 1.9),
        ],
        vec![DVec3::Y; 4],
        vec![[0, 2, 1], [1, 2, 3]],
        grey,
    );
    b.point_light("lamp", p(0.0, LAMP_Y, 0.0), I * 4.0 * std::f64::consts::PI);
    b.build()
}

fn settings(working_plane: bool) -> Settings {
    Settings {
        quality: Quality::Draft,
        working_plane: working_plane.then_some(ProbeGrid {
            spacing: 0.1,
            height: PLANE_Y,
        }),
        ..Settings::default()
    }
}

/// The bake with a working plane, in memory and as `lit.gltf` on disk; and one without.
struct Baked {
    output: BakedOutput,
    /// With 5 cm lightmaps, no working plane.
    lightmapped: BakedOutput,
    file: PathBuf,
    without: PathBuf,
}

fn baked() -> &'static Baked {
    static BAKED: OnceLock<Baked> = OnceLock::new();
    BAKED.get_or_init(|| {
        let dir = support::scratch("plan");
        let scene = scene();
        let file = support::bakes::write(&dir, "wp", "gltf", &scene, &settings(true));
        let without = support::bakes::write(&dir, "none", "glb", &scene, &settings(false));
        let output = luxbake::readback::read(&file).unwrap();
        let lightmaps = Settings {
            lightmaps: Some(LightmapSettings {
                texel_size: Some(0.05),
                max_size: 2048,
                tolerance: None,
            }),
            ..settings(false)
        };
        let lm = support::bakes::write(&dir, "lm", "gltf", &scene, &lightmaps);
        let lightmapped = luxbake::readback::read(&lm).unwrap();
        Baked {
            output,
            lightmapped,
            file,
            without,
        }
    })
}

/// Contours every 50 lx from 0 to 500 lx.
fn options(source: Source) -> Options {
    Options {
        source,
        range: Some([0.0, 500.0]),
        steps: 10,
        ..Options::default()
    }
}

/// Radius (m) of the circle where a plane `h` below the lamp receives `e` lx.
fn radius(h: f64, e: f64) -> f64 {
    ((I * h / e).powf(2.0 / 3.0) - h * h).sqrt()
}

/// The largest distance of a level's contour points (in the plane's frame: x, z) from the
/// analytic circle, and how many points there were.
fn worst_miss(plan: &Plan, level: f64, h: f64) -> (f64, usize) {
    let f = &plan.field;
    let r = radius(h, level);
    let lines = luxbake::picture::contours::isolines(&f.values, f.w, f.h, level);
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for p in lines.iter().flatten() {
        let q: DVec2 = f.at(*p);
        worst = worst.max((q.length() - r).abs());
        n += 1;
    }
    (worst, n)
}

#[test]
fn working_plane_contours_are_the_analytic_circles() {
    let plan = plan::build(&baked().output, &options(Source::WorkingPlane)).unwrap();
    let h = LAMP_Y - PLANE_Y;
    // The probes first: each within 0.5 % of the closed form.
    for p in &baked().output.working_plane.as_ref().unwrap().points {
        let r2 = p.position.x.powi(2) + p.position.z.powi(2);
        let e = I * h / (h * h + r2).powf(1.5);
        assert!(
            (p.total as f64 / e - 1.0).abs() < 5e-3,
            "{p:?}: {e} lx expected"
        );
    }
    // Levels whose circle (r 0.53 … 1.55 m) lies inside the 4 m plane: every contour point
    // within 1 cm of it (the probes are 0.1 m apart; bilinear reads between them).
    for level in [150.0, 200.0, 250.0, 300.0, 350.0, 400.0] {
        let (miss, n) = worst_miss(&plan, level, h);
        assert!(n > 100, "{level} lx: only {n} contour points");
        eprintln!("working plane {level} lx: {n} points, worst {miss:.5} m");
        assert!(
            miss < 0.01,
            "{level} lx: a contour point {miss} m off the circle"
        );
    }
    assert_eq!(plan.frame.right, DVec3::X);
    assert_eq!(plan.frame.down, DVec3::Z);
    // Figures: the probes' own (E max at the middle, U₀ = min/avg).
    let e_max = I * h / (h * h + 2.0 * 0.05f64.powi(2)).powf(1.5);
    assert!(
        (plan.max / e_max - 1.0).abs() < 5e-3,
        "{} vs {e_max}",
        plan.max
    );
    assert!((plan.uniformity() - plan.min / plan.avg).abs() < 1e-12);
}

#[test]
fn surface_contours_are_the_analytic_circles() {
    let plan = plan::build(&baked().output, &options(Source::Surface("floor".into()))).unwrap();
    assert_eq!(plan.name, "floor");
    // The floor is 2 m under the lamp; read from vertex values interpolated over draft patches.
    for level in [100.0, 150.0, 200.0] {
        let (miss, n) = worst_miss(&plan, level, LAMP_Y);
        assert!(n > 100, "{level} lx: only {n} contour points");
        eprintln!("floor {level} lx: {n} points, worst {miss:.5} m");
        assert!(
            miss < 0.03,
            "{level} lx: a contour point {miss} m off the circle"
        );
    }
    // The cells cover the floor exactly: 4 m at 0.02 m.
    assert_eq!(
        (plan.field.w, plan.field.h, plan.field.cell),
        (200, 200, 0.02)
    );
    assert!(plan.field.values.iter().all(|v| v.is_finite()));
    // A larger page gets a finer field (a cell per 4 px), as fine as the contours: 3000 px, 750
    // cells wanted, 4 m / 750 = 5.3 mm rounded up to a round 1 cm: 400 (200 before).
    let large = Options {
        size: 3000,
        ..options(Source::Surface("floor".into()))
    };
    let fine = plan::build(&baked().output, &large).unwrap();
    assert_eq!((fine.field.w, fine.field.cell), (400, 0.01));
    // Its outline is the square's four sides (cut where the patches' vertices are): 16 m.
    let total: f64 = plan.outline.iter().map(|[a, b]| a.distance(*b)).sum();
    assert!((total - 16.0).abs() < 1e-5, "{total}");
    for [a, b] in &plan.outline {
        let on_side = |p: DVec2| (p.x.abs() - 2.0).abs() < 1e-6 || (p.y.abs() - 2.0).abs() < 1e-6;
        assert!(on_side(*a) && on_side(*b), "{a} {b}");
    }
}

#[test]
fn lightmapped_surface_contours_are_the_analytic_circles() {
    let output = &baked().lightmapped;
    assert!(output.primitives.iter().any(|p| p.lightmap.is_some()));
    let plan = plan::build(output, &options(Source::Surface("floor".into()))).unwrap();
    // Texels 5 cm apart, read bilinearly: within 2 mm (the vertices: 3 cm).
    for level in [100.0, 150.0, 200.0] {
        let (miss, n) = worst_miss(&plan, level, LAMP_Y);
        eprintln!("lightmapped floor {level} lx: {n} points, worst {miss:.5} m");
        assert!(n > 100, "{level} lx: only {n} contour points");
        assert!(
            miss < 0.002,
            "{level} lx: a contour point {miss} m off the circle"
        );
    }
}

/// Every `<text>` of the SVG, which must parse as XML.
fn svg_texts(svg: &str) -> Vec<String> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(svg);
    let (mut texts, mut inside, mut depth) = (Vec::new(), false, 0i32);
    loop {
        match reader.read_event().expect("the SVG is well-formed XML") {
            Event::Start(e) => {
                depth += 1;
                inside = AsRef::<str>::as_ref(&e.name()) == "text";
                if inside {
                    texts.push(String::new());
                }
            }
            Event::End(_) => {
                depth -= 1;
                inside = false;
            }
            Event::Text(t) if inside => {
                let s = t.xml10_content().into_owned();
                texts.last_mut().unwrap().push_str(&s);
            }
            Event::GeneralRef(r) if inside => {
                let s = match &*r {
                    "amp" => "&",
                    "lt" => "<",
                    "gt" => ">",
                    _ => "?",
                };
                texts.last_mut().unwrap().push_str(s);
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(depth, 0);
    texts
}

#[test]
fn svg_holds_labels_legend_scale_bar_and_title() {
    let plan = plan::build(&baked().output, &options(Source::WorkingPlane)).unwrap();
    let svg = plan.svg();
    assert!(svg.len() < 400_000, "{} bytes", svg.len());
    let texts = svg_texts(&svg);
    let has = |t: &str| texts.iter().any(|x| x == t);
    // Contour labels on the lines (each level inside the values' range).
    for level in ["150 lx", "200 lx", "300 lx", "400 lx"] {
        assert!(has(level), "no label {level}: {texts:?}");
    }
    // The legend: unit and every level of the scale.
    assert!(has("E (lx)"), "{texts:?}");
    for level in ["0", "100", "250", "500"] {
        assert!(has(level), "no legend level {level}: {texts:?}");
    }
    // The scale bar (4 m plan: 1 m) and the note.
    assert!(has("1 m"), "{texts:?}");
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("seen from above, +Y up"))
    );
    // The title: the name, then the figures on a line of their own.
    assert_eq!(texts[0], "working plane, 0.5 m above the floor");
    let figures = &texts[1];
    assert!(figures.starts_with("E avg "), "{figures}");
    assert!(figures.contains(&format!("U\u{2080} = min/avg = {:.2}", plan.uniformity())));
    // The field: rectangles coloured by the scale.
    let middle = plan.scale.colour(plan.max);
    let hex = format!("#{:02x}{:02x}{:02x}", middle[0], middle[1], middle[2]);
    assert!(svg.contains(&format!("fill=\"{hex}\"")));
}

#[test]
fn png_has_the_layout_size_and_the_field_colours() {
    let plan = plan::build(&baked().output, &options(Source::WorkingPlane)).unwrap();
    let image = plan.image();
    let bytes = luxbake::export::display::png_rgb8(&image).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let drawing = plan::layout::draw(&plan);
    assert_eq!((info.width, info.height), (drawing.width, drawing.height));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    // The widest run of one colour (the disc round the light's foot, far from any line or
    // label): its middle pixel has its colour.
    let widest = (drawing.field.iter())
        .filter_map(|i| match i {
            plan::layout::Item::Rect { x, y, w, h, fill } => {
                Some((*x + w / 2.0, *y + h / 2.0, *w, *fill))
            }
            _ => None,
        })
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .unwrap();
    assert!(widest.2 > 100.0, "{widest:?}");
    let at = (widest.1 as usize * info.width as usize + widest.0 as usize) * 3;
    assert_eq!(buf[at..at + 3], widest.3);
    // The light's foot, in the middle of the plan: the band of the highest values.
    let f = &plan.field;
    let (c, r) = (f.w / 2, f.h / 2);
    let first = drawing.field.first().unwrap();
    let plan::layout::Item::Rect { x, y, .. } = first else {
        panic!()
    };
    let px_per_m = 800.0 / f.extent().max_element();
    let (px, py) = (
        x + (c as f64 + 0.5) * f.cell * px_per_m,
        y + (r as f64 + 0.5) * f.cell * px_per_m,
    );
    let at = (py as usize * info.width as usize + px as usize) * 3;
    assert_eq!(buf[at..at + 3], plan.scale.colour(f.values[r * f.w + c]));
    assert_eq!(
        plan.scale.colour(f.values[r * f.w + c]),
        plan.scale.colour(440.0)
    );
}

#[test]
fn plans_are_byte_identical_from_run_to_run() {
    let b = baked();
    let dir = b.file.parent().unwrap();
    for ext in ["svg", "png"] {
        let mut outputs = Vec::new();
        for k in 0..2 {
            let out = dir.join(format!("plan{k}.{ext}"));
            let run = run_bake([
                "plan".as_ref(),
                b.file.as_os_str(),
                "-o".as_ref(),
                out.as_os_str(),
            ]);
            assert!(run.ok(), "{run:?}");
            outputs.push(std::fs::read(&out).unwrap());
        }
        assert_eq!(outputs[0], outputs[1], "{ext}");
    }
    // The library gives the same bytes as the command.
    let plan = plan::build(&b.output, &Options::default()).unwrap();
    assert_eq!(
        std::fs::read(dir.join("plan0.svg")).unwrap(),
        plan.svg().into_bytes()
    );
}

#[test]
fn errors_name_the_file_and_what_is_wrong() {
    let b = baked();
    let dir = b.file.parent().unwrap();
    let out = dir.join("e.svg");
    let plan = |file: &PathBuf, extra: &[&str]| {
        let mut args = vec!["plan", file.to_str().unwrap(), "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        run_bake(args)
    };
    let run = plan(&b.without, &[]);
    assert_error_line(&run, &["lit.glb", "no working plane", "--working-plane"]);
    assert_eq!(run.code, Some(1));
    assert_error_line(
        &plan(&b.file, &["--surface", "desk"]),
        &["lit.gltf", "unknown node 'desk'"],
    );
    assert_error_line(
        &plan(&b.file, &["--surface", "tent"]),
        &["lit.gltf", "/nodes/1", "node 'tent' is not planar"],
    );
    let run = plan(&b.file, &["--scale", "9:3"]);
    assert_error_line(&run, &["--scale 9:3"]);
    assert_eq!(run.code, Some(2));
    let run = plan(&b.file, &["--quantity", "luminance"]);
    assert_error_line(&run, &["working plane has illuminance only"]);
    assert_eq!(run.code, Some(2));
    let run = plan(&b.file, &["--size", "10"]);
    assert_error_line(&run, &["--size 10"]);
    // Output = input, and an output that is neither SVG nor PNG.
    let gltf = b.file.to_str().unwrap();
    let run = run_bake(["plan", gltf, "-o", gltf]);
    assert_error_line(&run, &["refusing to overwrite an input"]);
    let run = run_bake(["plan", gltf, "-o", "plan.jpg"]);
    assert_error_line(&run, &["plan.jpg", ".svg or .png"]);
    assert_eq!(run.code, Some(2));
    assert!(!out.exists());
    // The library: the same errors typed.
    let e = plan::build(&b.output, &options(Source::Surface("nowhere".into()))).unwrap_err();
    assert!(e.to_string().contains("unknown node 'nowhere'"), "{e}");
    let luminance = Options {
        quantity: Quantity::Luminance,
        ..options(Source::Surface("floor".into()))
    };
    assert!(plan::build(&b.output, &luminance).is_ok());
}

/// samples/office baked at draft quality with a working plane at 0.8 m, once for the tests.
fn office() -> &'static std::path::Path {
    static LIT: OnceLock<PathBuf> = OnceLock::new();
    LIT.get_or_init(|| support::cli::office_draft("plan-office", &["--working-plane", "0.8"]))
}

/// `--surface` takes the face keys report, targets and design take (issue 57): the office's desk
/// tops are boxes, so `desk_dark/top` alone is refused naming the faces it can be drawn by,
/// and `desk_dark/top[+y]` draws the upper face.
#[test]
fn a_solid_node_is_drawn_by_its_face_key() {
    let lit = office();
    let svg = lit.parent().unwrap().join("top.svg");
    let lit = lit.to_str().unwrap();
    let run = run_bake([
        "plan",
        lit,
        "-o",
        svg.to_str().unwrap(),
        "--surface",
        "desk_dark/top",
    ]);
    assert_error_line(
        &run,
        &["is not planar", "desk_dark/top[+y]", "desk_dark/top[-y]"],
    );
    assert!(!svg.exists());
    let run = run_bake([
        "plan",
        lit,
        "-o",
        svg.to_str().unwrap(),
        "--surface",
        "desk_dark/top[+y]",
    ]);
    assert!(run.ok(), "{run:?}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("desk_dark/top[+y]"),
        "the title names the face"
    );
    let run = run_bake([
        "plan",
        lit,
        "-o",
        svg.to_str().unwrap(),
        "--surface",
        "desk_dark/top[up]",
    ]);
    assert_error_line(&run, &["unknown face [up]"]);
}

/// Isolux labels never overlap, at any page size (issue 57: `--surface wall_back --size 3000`
/// printed labels over each other): every label's white box (a rectangle followed by its
/// centred text) is disjoint from every other, on the office's back wall and working plane at
/// 200, 800 and 3000 px, in 10 and 30 bands.
#[test]
fn isolux_labels_never_overlap_at_any_size() {
    use luxbake::plan::layout::{Anchor, Item, draw};
    let output = luxbake::readback::read(office()).unwrap();
    for source in [Source::Surface("wall_back".into()), Source::WorkingPlane] {
        for size in [200, 800, 3000] {
            for steps in [10, 30] {
                let o = Options {
                    size,
                    steps,
                    ..options(source.clone())
                };
                let plan = plan::build(&output, &o).unwrap();
                let items = draw(&plan).items;
                let boxes: Vec<[f64; 4]> = (items.windows(2))
                    .filter_map(|w| match (&w[0], &w[1]) {
                        (
                            Item::Rect { x, y, w: bw, h, .. },
                            Item::Text {
                                x: tx,
                                anchor: Anchor::Middle,
                                ..
                            },
                        ) if (x + bw / 2.0 - tx).abs() < 1e-9 => Some([*x, *y, x + bw, y + h]),
                        _ => None,
                    })
                    .collect();
                assert!(
                    !boxes.is_empty() || steps == 10,
                    "{size} px, {steps}: some label"
                );
                for (i, a) in boxes.iter().enumerate() {
                    for b in &boxes[..i] {
                        let apart = a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1];
                        assert!(
                            apart,
                            "{size} px, {steps} bands: labels {a:?} and {b:?} overlap"
                        );
                    }
                }
            }
        }
    }
}
