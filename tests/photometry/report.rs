//! Summary (beam and field angles against closed forms, names, declared ratios), openings,
//! TILT=INCLUDE and the polar SVG. (The cost of `intensity` is measured by
//! `bench/intensity_timing.py`.)

use luxbake::photometry::{Format, OpeningShape, Symmetry};

use super::{load, malformed};

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
    let (a, b) = (
        malformed::parse_ies(none).unwrap(),
        malformed::parse_ies(&half).unwrap(),
    );
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
#[ignore = "writes the polar diagrams to $PHOTOMETRY_SVG_DIR for a look"]
fn dump_polar_svgs() {
    let out = std::env::var("PHOTOMETRY_SVG_DIR").unwrap();
    for file in [
        "ies2002_none_tilt.ies",
        "ldt_isym1.ldt",
        "ies2002_typeB.ies",
    ] {
        std::fs::write(format!("{out}/{file}.svg"), load(file).polar_svg()).unwrap();
        println!("{}", load(file).summary());
    }
}
