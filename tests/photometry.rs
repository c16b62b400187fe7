//! Photometry: IES LM-63 and EULUMDAT parsing, interpolation, flux, summary and polar SVG,
//! against analytic distributions (tests/data/photometry/make_profiles.py writes the files and
//! profiles.json, which names each file's distribution and closed-form flux).

use std::path::PathBuf;

use glam::DVec3;
use luxbake::geom::samples::scattered_directions;
use luxbake::photometry::{Format, PhotometricType, Photometry};
use serde::Deserialize;

#[path = "photometry/frames.rs"]
mod frames;
#[path = "photometry/malformed.rs"]
mod malformed;
#[path = "photometry/report.rs"]
mod report;

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

#[test]
fn flux_is_within_half_a_percent_of_the_declared_flux() {
    let profiles = manifest().profiles;
    let worst = (profiles.iter())
        .map(|p| ((load(&p.file).flux() - p.flux) / p.flux).abs())
        .fold(0.0, f64::max);
    eprintln!("oracle: profile-flux/files measured {}", profiles.len());
    eprintln!("oracle: profile-flux measured {worst:.3e}");
    for p in profiles {
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
    let dirs = scattered_directions(20_000);
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
    let dirs = scattered_directions(20_000);
    let mut worst = 0.0f64;
    for (ies, ldt) in manifest().pairs {
        let (a, b) = (load(&ies), load(&ldt));
        let peak = a.max_intensity().0;
        for &d in &dirs {
            let (x, y) = (a.intensity(d), b.intensity(d));
            worst = worst.max((x - y).abs() / x.max(y).max(1e-9 * peak));
            assert!(
                (x - y).abs() <= 1e-3 * x.max(y) + 1e-9 * peak,
                "{ies} vs {ldt} at {d}: {x} vs {y}"
            );
        }
        assert_eq!(a.symmetry(), b.symmetry(), "{ies} vs {ldt}");
    }
    eprintln!("oracle: ies-ldt/intensity measured {worst:.3e}");
}
