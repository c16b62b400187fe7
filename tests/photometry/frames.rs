//! Symmetric expansions and the type A/B/C angle mapping into the photometric frame.

use glam::DVec3;
use luxbake::photometry::{PhotometricType, Photometry, Symmetry};

use super::load;

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
