//! The summary of a distribution: names, flux, light output ratio, peak, beam and field angles.
//!
//! Input: a [`Photometry`]. Output: a serde-serialisable [`Summary`] (camelCase) and its
//! multi-line `Display`. Beam (50 %) and field (10 %) angles are full angles measured in the two
//! great circles through the peak direction p: the "C0–C180" circle, which contains p and the
//! direction of +X (C = 0°) projected square to p, and the "C90–C270" circle, which contains p
//! and +Y projected likewise. For a peak at the nadir these are the C0–C180 and C90–C270 planes.
//! From p the walk goes both ways in 0.25° steps until I < fraction × Imax, then bisects; the
//! full angle is the sum of both sides, `None` if a side never drops that low within 180°.

use std::fmt;

use glam::DVec3;

use super::{Format, Opening, OpeningShape, PhotometricType, Photometry, Symmetry};

/// A direction as (C, γ) in degrees in the photometric frame (type C angles for every type).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PeakDirection {
    pub c: f64,
    pub gamma: f64,
}

/// A full angle (degrees) in each of the two planes through the peak.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PlaneAngles {
    pub c0_c180: Option<f64>,
    pub c90_c270: Option<f64>,
}

/// What a lighting designer reads off a photometric file.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Summary {
    pub format: Format,
    /// `LM-63-2002`, `EULUMDAT`, …
    pub version: String,
    pub manufacturer: Option<String>,
    pub luminaire: Option<String>,
    pub catalog_number: Option<String>,
    pub lamp: Option<String>,
    pub photometric_type: PhotometricType,
    pub symmetry: Symmetry,
    pub absolute_photometry: bool,
    /// Declared lamp flux (lm); `None` for absolute photometry.
    pub rated_lumens: Option<f64>,
    /// Flux integrated over the interpolated distribution (lm).
    pub flux: f64,
    /// flux / rated lumens.
    pub light_output_ratio: Option<f64>,
    /// EULUMDAT's declared LORL and DFF (%).
    pub declared_lorl_percent: Option<f64>,
    pub declared_dff_percent: Option<f64>,
    /// Largest tabulated intensity (cd) and its direction.
    pub max_intensity: f64,
    pub max_direction: PeakDirection,
    /// Full angle to 50 % of the maximum.
    pub beam_angle: PlaneAngles,
    /// Full angle to 10 % of the maximum.
    pub field_angle: PlaneAngles,
    pub opening: Opening,
}

pub(super) fn summarise(p: &Photometry) -> Summary {
    let info = p.info();
    let (max, dir) = p.max_intensity();
    let (t0, t90) = tangents(dir);
    let angles = |fraction: f64| PlaneAngles {
        c0_c180: spread(p, dir, t0, max * fraction),
        c90_c270: spread(p, dir, t90, max * fraction),
    };
    let (c, gamma) = PhotometricType::C.angles(dir);
    Summary {
        format: p.format(),
        version: info.version.clone(),
        manufacturer: info.manufacturer.clone(),
        luminaire: info.luminaire.clone(),
        catalog_number: info.catalog_number.clone(),
        lamp: info.lamp.clone(),
        photometric_type: info.photometric_type,
        symmetry: info.symmetry,
        absolute_photometry: info.rated_lumens.is_none(),
        rated_lumens: info.rated_lumens,
        flux: p.flux(),
        light_output_ratio: p.light_output_ratio(),
        declared_lorl_percent: info.declared_lorl_percent,
        declared_dff_percent: info.declared_dff_percent,
        max_intensity: max,
        max_direction: PeakDirection { c, gamma },
        beam_angle: angles(0.5),
        field_angle: angles(0.1),
        opening: p.opening(),
    }
}

/// Unit tangents at `p` towards +X and +Y (Gram–Schmidt; a fallback when p is along an axis).
fn tangents(p: DVec3) -> (DVec3, DVec3) {
    let project = |a: DVec3| (a - a.dot(p) * p).try_normalize();
    let t90 = project(DVec3::Y).unwrap_or_else(|| p.cross(DVec3::X).normalize());
    let t0 = (DVec3::X - DVec3::X.dot(p) * p - DVec3::X.dot(t90) * t90)
        .try_normalize()
        .unwrap_or_else(|| t90.cross(p).normalize());
    (t0, t90)
}

/// Full angle (degrees) about `p` along the great circle with tangent `t` where I ≥ `level`.
fn spread(ph: &Photometry, p: DVec3, t: DVec3, level: f64) -> Option<f64> {
    let at = |s: f64, side: f64| {
        let (sn, cs) = s.to_radians().sin_cos();
        ph.intensity(cs * p + side * sn * t)
    };
    let half = |side: f64| {
        const STEP: f64 = 0.25;
        let mut s = 0.0;
        while s < 180.0 {
            let next = s + STEP;
            if at(next, side) < level {
                let (mut lo, mut hi) = (s, next);
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if at(mid, side) < level {
                        hi = mid
                    } else {
                        lo = mid
                    }
                }
                return Some(0.5 * (lo + hi));
            }
            s = next;
        }
        None
    };
    Some(half(1.0)? + half(-1.0)?)
}

fn or_dash(v: Option<f64>, unit: &str) -> String {
    v.map_or("—".into(), |x| format!("{x:.1}{unit}"))
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fmt_name = match self.format {
            Format::Ies => "IES",
            Format::Eulumdat => "EULUMDAT",
        };
        writeln!(f, "Format:          {fmt_name} ({})", self.version)?;
        let names = [
            ("Manufacturer:", &self.manufacturer),
            ("Luminaire:", &self.luminaire),
            ("Catalog number:", &self.catalog_number),
            ("Lamp:", &self.lamp),
        ];
        for (label, value) in names {
            if let Some(v) = value {
                writeln!(f, "{label:<16} {}", v.replace('\n', " "))?;
            }
        }
        writeln!(
            f,
            "Photometry:      type {:?}, symmetry {}",
            self.photometric_type,
            self.symmetry.describe()
        )?;
        match self.rated_lumens {
            Some(r) => writeln!(f, "Rated lamp flux: {r:.1} lm")?,
            None => writeln!(f, "Rated lamp flux: — (absolute photometry)")?,
        }
        let lor = self
            .light_output_ratio
            .map_or(String::new(), |l| format!(" (LOR {:.1} %)", 100.0 * l));
        writeln!(f, "Flux:            {:.1} lm{lor}", self.flux)?;
        if let (Some(lorl), Some(dff)) = (self.declared_lorl_percent, self.declared_dff_percent) {
            writeln!(f, "Declared:        LORL {lorl:.1} %, DFF {dff:.1} %")?;
        }
        let d = self.max_direction;
        writeln!(
            f,
            "Peak intensity:  {:.1} cd at C {:.1}°, γ {:.1}°",
            self.max_intensity, d.c, d.gamma
        )?;
        for (label, a) in [
            ("Beam (50 %):", self.beam_angle),
            ("Field (10 %):", self.field_angle),
        ] {
            writeln!(
                f,
                "{label:<16} C0-C180 {}, C90-C270 {}",
                or_dash(a.c0_c180, "°"),
                or_dash(a.c90_c270, "°")
            )?;
        }
        let o = self.opening;
        let shape = match o.shape {
            OpeningShape::Rectangular => "rectangular",
            OpeningShape::Round => "round",
        };
        write!(
            f,
            "Opening:         {:.3} × {:.3} × {:.3} m (length × width × height), {shape}",
            o.length, o.width, o.height
        )
    }
}
