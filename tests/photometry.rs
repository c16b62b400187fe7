//! Photometry: IES LM-63 and EULUMDAT parsing, interpolation, flux, summary and polar SVG,
//! against analytic distributions (tests/data/photometry/make_profiles.py writes the files and
//! profiles.json, which names each file's distribution and closed-form flux).

use std::path::PathBuf;

use glam::DVec3;
use luxbake::photometry::{Format, OpeningShape, PhotometricType, Photometry, Symmetry};
use serde::Deserialize;

#[derive(Deserialize)]
struct Manifest {
    profiles: Vec<Profile>,
    pairs: Vec<(String, String)>,
}

#[derive(Deserialize)]
struct Profile {
    file: String,
    dist: String,
    n: i32,
    a: f64,
    b: f64,
    i0: f64,
    flux: f64,
    #[serde(rename = "type")]
    ty: String,
    absolute: bool,
    h: Vec<f64>,
    v: Vec<f64>,
}

impl Profile {
    /// The analytic intensity (cd) the file samples.
    fn intensity(&self, d: DVec3) -> f64 {
        let down = (-d.z).max(0.0);
        let (a, b) = (self.a, self.b);
        self.i0
            * match self.dist.as_str() {
                "cos" => down,
                "cosn" => down.powi(self.n),
                "iso" => 1.0,
                "up" => d.z.max(0.0),
                "bilat0" => down * (1.0 + a * d.x),
                "bilat90" => down * (1.0 + a * d.y),
                "quad" => down * (1.0 + a * (d.x * d.x - d.y * d.y)),
                "none" => down * (1.0 + a * d.x + b * d.y),
                other => panic!("unknown distribution {other}"),
            }
    }

    fn ptype(&self) -> PhotometricType {
        match self.ty.as_str() {
            "A" => PhotometricType::A,
            "B" => PhotometricType::B,
            _ => PhotometricType::C,
        }
    }
}

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/photometry")
}

fn manifest() -> Manifest {
    let text = std::fs::read_to_string(dir().join("profiles.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn format_of(file: &str) -> Format {
    Format::from_mime_or_extension(file.rsplit('.').next().unwrap()).unwrap()
}

fn load(file: &str) -> Photometry {
    let bytes = std::fs::read(dir().join(file)).unwrap();
    Photometry::parse(&bytes, format_of(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// Deterministic directions spread over the sphere.
fn directions(n: usize) -> Vec<DVec3> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let z = 2.0 * next() - 1.0;
            let phi = std::f64::consts::TAU * next();
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

#[test]
fn flux_is_within_half_a_percent_of_the_declared_flux() {
    for p in manifest().profiles {
        let ph = load(&p.file);
        let err = (ph.flux() - p.flux) / p.flux;
        eprintln!(
            "{:34} flux {:10.3} lm, declared {:10.3} lm, error {:+.4} %",
            p.file,
            ph.flux(),
            p.flux,
            100.0 * err
        );
        assert!(
            err.abs() < 0.005,
            "{}: flux {} vs {}",
            p.file,
            ph.flux(),
            p.flux
        );
        if p.absolute {
            assert_eq!(ph.rated_lumens(), None, "{}", p.file);
            assert_eq!(ph.light_output_ratio(), None);
        } else {
            let rated = ph.rated_lumens().unwrap();
            assert!(
                (rated - p.flux).abs() < 1e-9 * p.flux,
                "{}: rated {rated}",
                p.file
            );
            assert!((ph.light_output_ratio().unwrap() - 1.0).abs() < 0.005);
        }
    }
}

#[test]
fn interpolation_is_exact_at_the_tabulated_angles() {
    for p in manifest().profiles {
        let ph = load(&p.file);
        assert_eq!(ph.photometric_type(), p.ptype(), "{}", p.file);
        for &h in &p.h {
            for &v in &p.v {
                let want = p.intensity(p.ptype().direction(h, v));
                let got = ph.intensity_at(h, v);
                assert!(
                    (got - want).abs() <= 1e-9 * want.abs() + 1e-12 * p.i0,
                    "{} at ({h}, {v}): {got} vs {want}",
                    p.file
                );
            }
        }
    }
}

#[test]
fn interpolation_follows_the_analytic_distribution_everywhere() {
    let dirs = directions(20_000);
    for p in manifest().profiles {
        let ph = load(&p.file);
        let worst = dirs
            .iter()
            .map(|&d| (ph.intensity(d) - p.intensity(d)).abs() / p.i0)
            .fold(0.0, f64::max);
        eprintln!("{:34} max |I - I_analytic| / I0 = {worst:.2e}", p.file);
        assert!(worst < 5e-3, "{}: {worst}", p.file);
    }
}

#[test]
fn ies_and_eulumdat_versions_agree_in_every_direction() {
    let dirs = directions(20_000);
    for (ies, ldt) in manifest().pairs {
        let (a, b) = (load(&ies), load(&ldt));
        let peak = a.max_intensity().0;
        for &d in &dirs {
            let (x, y) = (a.intensity(d), b.intensity(d));
            assert!(
                (x - y).abs() <= 1e-3 * x.max(y) + 1e-9 * peak,
                "{ies} vs {ldt} at {d}: {x} vs {y}"
            );
        }
        assert_eq!(a.symmetry(), b.symmetry(), "{ies} vs {ldt}");
    }
}

fn agree(ph: &Photometry, a: (f64, f64), b: (f64, f64)) -> bool {
    let (x, y) = (ph.intensity_at(a.0, a.1), ph.intensity_at(b.0, b.1));
    (x - y).abs() <= 1e-12 * x.abs().max(y.abs()) + 1e-12
}

#[test]
fn symmetric_data_expands_to_the_full_range() {
    for file in ["ies1991_quadrant.ies", "ldt_isym4_commas.ldt"] {
        let ph = load(file);
        assert_eq!(ph.symmetry(), Symmetry::Quadrant);
        for g in [7.0, 33.0, 61.0, 88.0] {
            for c in [150.0, 210.0, 330.0] {
                assert!(
                    agree(&ph, (30.0, g), (c, g)),
                    "{file}: C30 vs C{c} at γ {g}"
                );
            }
        }
    }
    for file in ["ies2002_bilateral.ies", "ldt_isym2.ldt"] {
        let ph = load(file);
        assert_eq!(ph.symmetry(), Symmetry::BilateralC0C180);
        assert!(agree(&ph, (30.0, 40.0), (330.0, 40.0)));
        assert!(
            !agree(&ph, (30.0, 40.0), (150.0, 40.0)),
            "{file} is not quadrant-symmetric"
        );
    }
    for file in ["ies1995_bilateral_90_270.ies", "ldt_isym3.ldt"] {
        let ph = load(file);
        assert_eq!(ph.symmetry(), Symmetry::BilateralC90C270);
        assert!(agree(&ph, (30.0, 40.0), (150.0, 40.0)));
        assert!(agree(&ph, (200.0, 40.0), (340.0, 40.0)));
        assert!(
            !agree(&ph, (30.0, 40.0), (330.0, 40.0)),
            "{file} is not quadrant-symmetric"
        );
    }
    let b = load("ies2002_typeB_lateral.ies");
    assert_eq!(b.symmetry(), Symmetry::BilateralC0C180);
    assert!(agree(&b, (20.0, 35.0), (-20.0, 35.0)));
    let a = load("ies1995_typeA_quadrant.ies");
    assert_eq!(a.symmetry(), Symmetry::Quadrant);
    for other in [(-20.0, 30.0), (20.0, -30.0), (-20.0, -30.0)] {
        assert!(agree(&a, (20.0, 30.0), other), "type A ({other:?})");
    }
    assert_eq!(load("ies2002_none_tilt.ies").symmetry(), Symmetry::None);
    assert_eq!(load("ies1986_axial_commas.ies").symmetry(), Symmetry::Axial);
}

#[test]
fn type_a_and_b_angles_map_into_the_photometric_frame() {
    let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-12;
    use PhotometricType::{A, B, C};
    for ty in [A, B, C] {
        assert!(
            close(ty.direction(0.0, 0.0), DVec3::NEG_Z),
            "{ty:?} aims down −Z"
        );
    }
    assert!(close(C.direction(90.0, 90.0), DVec3::Y));
    assert!(
        close(B.direction(0.0, 90.0), DVec3::X),
        "B: V > 0 towards +X"
    );
    assert!(
        close(B.direction(90.0, 0.0), DVec3::NEG_Y),
        "B: H > 0 clockwise, towards −Y"
    );
    assert!(
        close(A.direction(0.0, 90.0), DVec3::X),
        "A: V > 0 towards +X"
    );
    assert!(
        close(A.direction(90.0, 0.0), DVec3::NEG_Y),
        "A: H > 0 clockwise, towards −Y"
    );
    // B planes share the Y axis (V fixed: a great circle through ±Y); A planes share X.
    let b = B.direction(40.0, 25.0);
    assert!((b.x.atan2(-b.z).to_degrees() - 25.0).abs() < 1e-9);
    let a = A.direction(25.0, 40.0);
    assert!(((-a.y).atan2(-a.z).to_degrees() - 25.0).abs() < 1e-9);
    for ty in [A, B, C] {
        for (h, v) in [(10.0_f64, 20.0_f64), (-35.0, 60.0), (80.0, -15.0)] {
            let (h, v) = if ty == C {
                ((h + 360.0) % 360.0, v.abs())
            } else {
                (h, v)
            };
            let (h2, v2) = ty.angles(ty.direction(h, v));
            assert!(
                (h - h2).abs() < 1e-9 && (v - v2).abs() < 1e-9,
                "{ty:?} ({h}, {v}) → ({h2}, {v2})"
            );
        }
    }
    // A flood aimed at −Z whose lobe leans towards +X and +Y, sampled as type B and type A:
    // I = I0·cos α·(1 + 0.5x + 0.3y), so the +X side is brighter than −X, +Y brighter than −Y.
    for file in ["ies2002_typeB.ies", "ies2019_typeA.ies"] {
        let ph = load(file);
        let i0 = 1000.0 / std::f64::consts::PI;
        let s = 40f64.to_radians().sin();
        let tilt = |d: DVec3| ph.intensity(d.normalize());
        let x_plus = tilt(DVec3::new(s, 0.0, -40f64.to_radians().cos()));
        assert!(
            (x_plus - i0 * 40f64.to_radians().cos() * (1.0 + 0.5 * s)).abs() < 1e-3 * i0,
            "{file}"
        );
        assert!(
            tilt(DVec3::new(0.3, 0.0, -1.0)) > tilt(DVec3::new(-0.3, 0.0, -1.0)),
            "{file}: +X side"
        );
        assert!(
            tilt(DVec3::new(0.0, 0.3, -1.0)) > tilt(DVec3::new(0.0, -0.3, -1.0)),
            "{file}: +Y side"
        );
        assert_eq!(
            ph.intensity(DVec3::new(0.2, 0.1, 1.0).normalize()),
            0.0,
            "{file}: nothing behind"
        );
    }
}

#[test]
fn summary_gives_beam_and_field_angles_of_a_cos_n_lobe() {
    let n = 10.0_f64;
    let beam = 2.0 * 0.5f64.powf(1.0 / n).acos().to_degrees();
    let field = 2.0 * 0.1f64.powf(1.0 / n).acos().to_degrees();
    for file in ["ies2019_axial_cosn_absolute.ies", "ldt_isym1.ldt"] {
        let s = load(file).summary();
        eprintln!(
            "{file}: beam {:?} (closed form {beam:.3}), field {:?} ({field:.3})",
            s.beam_angle, s.field_angle
        );
        for got in [s.beam_angle.c0_c180, s.beam_angle.c90_c270] {
            assert!(
                (got.unwrap() - beam).abs() < 0.1,
                "{file}: beam {got:?} vs {beam}"
            );
        }
        for got in [s.field_angle.c0_c180, s.field_angle.c90_c270] {
            assert!(
                (got.unwrap() - field).abs() < 0.1,
                "{file}: field {got:?} vs {field}"
            );
        }
        assert!(s.max_direction.gamma.abs() < 1e-9);
        assert!((s.max_intensity - 800.0 * (n + 1.0) / std::f64::consts::TAU).abs() < 1e-6);
        assert_eq!(s.symmetry, Symmetry::Axial);
    }
    let s = load("ies2019_axial_cosn_absolute.ies").summary();
    assert!(s.absolute_photometry && s.rated_lumens.is_none() && s.light_output_ratio.is_none());
    assert_eq!(s.version, "LM-63-2019");
    let json = serde_json::to_value(&s).unwrap();
    for key in [
        "beamAngle",
        "fieldAngle",
        "maxIntensity",
        "maxDirection",
        "photometricType",
        "ratedLumens",
        "lightOutputRatio",
    ] {
        assert!(json.get(key).is_some(), "summary JSON has {key}: {json}");
    }
    assert!(json["beamAngle"].get("c0C180").is_some());
    let text = s.to_string();
    for part in [
        "LM-63-2019",
        "Beam (50 %)",
        "Field (10 %)",
        "absolute photometry",
        "cd at C",
    ] {
        assert!(text.contains(part), "Display shows {part}:\n{text}");
    }
    // An isotropic source never drops to half: no beam angle.
    assert_eq!(
        load("ies2002_isotropic.ies").summary().beam_angle.c0_c180,
        None
    );
}

#[test]
fn summary_reports_names_lamps_and_declared_ratios() {
    let ldt = load("ldt_isym0_two_sets.ldt");
    let info = ldt.info();
    assert_eq!(info.lamp_count, 3);
    assert_eq!(info.lamp.as_deref(), Some("T16 28W; T16 35W"));
    assert_eq!(ldt.rated_lumens(), Some(3000.0));
    assert_eq!(info.input_watts, Some(98.0));
    let s = ldt.summary();
    assert_eq!(
        (s.declared_lorl_percent, s.declared_dff_percent),
        (Some(100.0), Some(100.0))
    );
    assert_eq!(s.luminaire.as_deref(), Some("no symmetry"));
    assert_eq!(s.format, Format::Eulumdat);
    let abs = load("ldt_absolute.ldt");
    assert_eq!(abs.rated_lumens(), None);
    let ies = load("ies1991_quadrant.ies");
    let s = ies.summary();
    assert_eq!(s.version, "LM-63-1991");
    assert_eq!(s.manufacturer.as_deref(), Some("luxbake tests"));
    assert_eq!(s.catalog_number.as_deref(), Some("QUADRANT"));
    assert_eq!(s.lamp.as_deref(), Some("analytic"));
    assert_eq!(ies.info().rated_lumens, Some(1500.0));
    let bilateral = load("ies2002_bilateral.ies");
    let kw = &bilateral.info().keywords;
    assert!(
        kw.contains(&("OTHER".into(), "a keyword\ncontinued".into())),
        "{kw:?}"
    );
    assert_eq!(
        load("ies1986_axial_commas.ies").info().version,
        "LM-63-1986"
    );
    assert_eq!(
        load("ies1995_bilateral_90_270.ies").info().version,
        "LM-63-1995"
    );
}

#[test]
fn openings_are_converted_to_metres_and_shaped() {
    let o = load("ies1986_axial_commas.ies").opening();
    assert!(
        (o.width - 0.3048).abs() < 1e-12 && (o.length - 0.6096).abs() < 1e-12,
        "{o:?}"
    );
    assert_eq!(o.shape, OpeningShape::Rectangular);
    let o = load("ies2002_bilateral.ies").opening();
    assert_eq!(
        (o.length, o.width, o.height, o.shape),
        (0.2, 0.2, 0.0, OpeningShape::Round)
    );
    let o = load("ldt_isym1.ldt").opening();
    assert_eq!(
        (o.length, o.width, o.shape),
        (0.3, 0.3, OpeningShape::Round)
    );
    let o = load("ldt_isym2.ldt").opening();
    assert_eq!(
        (o.length, o.width, o.shape),
        (0.5, 0.25, OpeningShape::Rectangular)
    );
}

#[test]
fn tilt_include_tables_are_parsed_and_applied_at_zero_tilt() {
    let t = load("ies2002_none_tilt.ies").info().tilt.clone().unwrap();
    assert_eq!(t.geometry, 1);
    assert_eq!(t.angles, vec![0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]);
    assert_eq!(t.factors[6], 0.75);
    assert_eq!(t.applied_factor, 1.0);
    let none =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n100 50 0\n";
    let half = none.replace("TILT=NONE", "TILT=INCLUDE\n3\n2\n-10 10\n0.4 0.6");
    let (a, b) = (parse_ies(none).unwrap(), parse_ies(&half).unwrap());
    assert_eq!(b.info().tilt.as_ref().unwrap().applied_factor, 0.5);
    assert!((b.intensity_at(0.0, 20.0) - 0.5 * a.intensity_at(0.0, 20.0)).abs() < 1e-12);
}

#[test]
fn polar_svg_is_well_formed_xml() {
    for file in [
        "ies2002_none_tilt.ies",
        "ldt_isym1.ldt",
        "ies2002_typeB.ies",
        "ies2019_uplight.ies",
    ] {
        let svg = load(file).polar_svg();
        let mut reader = quick_xml::Reader::from_str(&svg);
        let (mut depth, mut paths, mut root) = (0i32, 0, None);
        loop {
            match reader.read_event() {
                Ok(quick_xml::events::Event::Start(e)) => {
                    root.get_or_insert_with(|| e.name().0.to_owned());
                    depth += 1;
                }
                Ok(quick_xml::events::Event::Empty(e)) => {
                    paths += usize::from(e.name().0 == "path");
                }
                Ok(quick_xml::events::Event::End(_)) => depth -= 1,
                Ok(quick_xml::events::Event::Eof) => break,
                Ok(_) => {}
                Err(e) => panic!("{file}: {e}\n{svg}"),
            }
        }
        assert_eq!(
            (root.as_deref(), depth, paths),
            (Some("svg"), 0, 2),
            "{file}"
        );
        assert!(svg.contains("C0–C180") && svg.contains("C90–C270") && svg.contains("(cd)"));
    }
}

#[test]
fn intensity_is_cheap() {
    let ph = load("ldt_isym0_two_sets.ldt");
    let dirs = directions(4096);
    let start = std::time::Instant::now();
    let mut sum = 0.0;
    for k in 0..250 {
        for d in &dirs {
            sum += ph.intensity(*d) * (k as f64 + 1.0);
        }
    }
    let per = start.elapsed().as_secs_f64() / (250.0 * 4096.0);
    eprintln!("intensity(): {:.0} ns per call", per * 1e9);
    assert!(sum > 0.0 && per < 5e-6, "{per} s per call");
}

fn parse_ies(text: &str) -> Result<Photometry, luxbake::photometry::ParseError> {
    Photometry::parse(text.as_bytes(), Format::Ies)
}

/// A valid type C file; line numbers 1..=8.
const GOOD: [&str; 8] = [
    "IESNA:LM-63-2002",
    "[TEST] t",
    "TILT=NONE",
    "1 1000 1 3 1 1 2 0 0 0",
    "1 1 50",
    "0 45 90",
    "0",
    "100 50 0",
];

/// GOOD with line `n` (1-based) replaced by `with` (which may hold several lines, or none).
fn ies_with(n: usize, with: &str) -> String {
    let mut lines: Vec<String> = GOOD.iter().map(|s| s.to_string()).collect();
    lines[n - 1] = with.to_string();
    lines.retain(|l| !l.is_empty());
    lines.join("\n") + "\n"
}

fn expect_err(
    result: Result<Photometry, luxbake::photometry::ParseError>,
    line: usize,
    words: &[&str],
) {
    let e = result.err().expect("the file must be refused");
    assert_eq!(e.line, line, "{e}");
    for w in words {
        assert!(
            e.message.contains(w),
            "`{}` should mention `{w}`",
            e.message
        );
    }
}

#[test]
fn malformed_ies_files_name_the_line_and_what_was_expected() {
    assert!(parse_ies(&ies_with(2, "[TEST] t")).is_ok());
    expect_err(parse_ies(&ies_with(3, "")), 3, &["TILT=", "found `1 1000"]);
    expect_err(
        parse_ies("IESNA:LM-63-2002\n[TEST] t\n"),
        2,
        &["TILT=", "ends"],
    );
    expect_err(
        parse_ies(&ies_with(3, "TILT=lamp.tlt")),
        3,
        &["TILT=lamp.tlt", "tilt file", "not supported"],
    );
    expect_err(
        parse_ies(&ies_with(8, "100 50")),
        8,
        &["candela value 3 of 3", "ends"],
    );
    expect_err(
        parse_ies(&ies_with(8, "100 50 0\n7")),
        9,
        &["3 candela values", "found more: `7`"],
    );
    expect_err(
        parse_ies(&ies_with(6, "0 4x5 90")),
        6,
        &["vertical angle 2 of 3", "a number", "`4x5`"],
    );
    expect_err(
        parse_ies(&ies_with(4, "1 1000 1 3 1 4 2 0 0 0")),
        4,
        &["photometric type 1 (C), 2 (B) or 3 (A)", "found 4"],
    );
    expect_err(
        parse_ies(&ies_with(6, "0 90 45")),
        6,
        &["vertical angles must increase", "45° follows 90°"],
    );
    expect_err(
        parse_ies(&ies_with(6, "0 45 80")),
        6,
        &[
            "type C vertical angles from 0° or 90° to 90° or 180°",
            "0° to 80°",
        ],
    );
    let two = ies_with(4, "1 1000 1 3 2 1 2 0 0 0");
    let wide = two.replace("\n0\n100 50 0\n", "\n0 120\n100 50 0\n100 50 0\n");
    expect_err(parse_ies(&wide), 7, &["horizontal angles", "0° to 120°"]);
    expect_err(
        parse_ies(&ies_with(4, "1 1000 1 3 1 1 3 0 0 0")),
        4,
        &["units type 1 (feet) or 2 (metres)", "found 3"],
    );
    expect_err(
        parse_ies(&ies_with(4, "1 0 1 3 1 1 2 0 0 0")),
        4,
        &["lumens per lamp", "absolute photometry"],
    );
    expect_err(
        parse_ies(&ies_with(8, "100 -50 0")),
        8,
        &["candela value ≥ 0", "-50"],
    );
    expect_err(
        parse_ies(&ies_with(3, "TILT=INCLUDE\n4\n1\n0\n1")),
        4,
        &["lamp-to-luminaire geometry 1, 2 or 3", "found 4"],
    );
    expect_err(
        parse_ies(&ies_with(3, "TILT=INCLUDE\n1\n2\n0 0\n1 1")),
        6,
        &["tilt angles must increase"],
    );
    let type_b = ies_with(4, "1 1000 1 3 1 2 2 0 0 0");
    expect_err(
        parse_ies(&type_b),
        7,
        &[
            "type B horizontal angles from −90° or 0° to 90°",
            "0° to 0°",
        ],
    );
    expect_err(
        parse_ies(&ies_with(4, "1 1000 1 3.5 1 1 2 0 0 0")),
        4,
        &["number of vertical angles", "whole number"],
    );
}

fn ldt_lines() -> Vec<String> {
    let text = std::fs::read_to_string(dir().join("ldt_isym2.ldt")).unwrap();
    text.lines().map(str::to_owned).collect()
}

fn parse_ldt(lines: &[String]) -> Result<Photometry, luxbake::photometry::ParseError> {
    Photometry::parse((lines.join("\r\n") + "\r\n").as_bytes(), Format::Eulumdat)
}

#[test]
fn malformed_eulumdat_files_name_the_line_and_what_was_expected() {
    let good = ldt_lines();
    assert!(parse_ldt(&good).is_ok());
    let with = |n: usize, s: &str| {
        let mut l = good.clone();
        l[n - 1] = s.to_owned();
        l
    };
    expect_err(parse_ldt(&good[..20]), 21, &["height", "ends at line 20"]);
    expect_err(
        parse_ldt(&with(3, "7")),
        3,
        &["symmetry indicator Isym 0, 1, 2, 3 or 4", "found 7"],
    );
    expect_err(
        parse_ldt(&with(4, "abc")),
        4,
        &["number of C planes Mc", "`abc`"],
    );
    let mut quad = with(3, "4");
    quad[3] = "22".into();
    expect_err(parse_ldt(&quad), 4, &["divisible by 4", "found 22"]);
    expect_err(
        parse_ldt(&with(29, "lots")),
        29,
        &["total lamp flux (lm) of lamp set 1", "`lots`"],
    );
    let n = good.len();
    expect_err(parse_ldt(&good[..n - 5]), n - 5, &["intensity", "ends"]);
    let mut extra = good.clone();
    extra.push("12.5".into());
    expect_err(
        parse_ldt(&extra),
        n + 1,
        &["intensities and then the end of the file", "`12.5`"],
    );
    expect_err(
        parse_ldt(&with(n - 3, "1.2.3")),
        n - 3,
        &["intensity", "`1.2.3`"],
    );
    expect_err(
        parse_ldt(&with(6, "")),
        6,
        &["number of γ angles Ng", "empty line"],
    );
}

#[test]
fn latin1_bytes_and_a_byte_order_mark_are_accepted() {
    let mut bytes = vec![0xEF, 0xBB, 0xBF];
    bytes.extend(GOOD.join("\n").as_bytes());
    assert!(Photometry::parse(&bytes, Format::Ies).is_ok());
    let mut ldt = ldt_lines().join("\r\n").into_bytes();
    let at = ldt.windows(9).position(|w| w == b"bilateral").unwrap();
    ldt[at] = 0xE9; // Latin-1 'é'
    let ph = Photometry::parse(&ldt, Format::Eulumdat).unwrap();
    assert!(ph.info().luminaire.as_deref().unwrap().starts_with('é'));
}
