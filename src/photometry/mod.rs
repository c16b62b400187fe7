//! Photometric data files — IES LM-63 (1986, 1991, 1995, 2002, 2019) and EULUMDAT — parsed into
//! a [`Photometry`]: absolute luminous intensity (cd) over the whole sphere, smoothly
//! interpolated and exact at the measured angles, with its flux, summary and polar curve.
//!
//! The photometric frame: unit vectors `dir` are given in the luminaire's own axes, where −Z is
//! the nadir — the direction of (C, γ) = (0°, 0°) for type C photometry — +X is the C = 0° half
//! plane and +Y the C = 90° half plane (C increases counter-clockwise seen from above, i.e. from
//! +Z). This is EXT_lights_ies' convention (the X/Z plane is the vertical photometric plane of
//! C = 0/180; an untransformed light points down −Z). Types A and B map into the same frame (see
//! [`PhotometricType`]: the aim (0°, 0°) is −Z, V > 0 towards +X, H > 0 (clockwise) towards −Y).
//!
//! The parsers are written here (no AGPL/GPL crate). Malformed files give a [`ParseError`] with the
//! line number and what was expected.
//!
//! Module map: `text` (decoding, numbers with line numbers), `ies` (+ `ies_grid`, its angle ranges) and `ldt` (the two formats),
//! `symmetry` (declared symmetries, expansion), `frame` (types A/B/C → directions), `grid`
//! (interpolation), `flux` (integration), `summary` (beam/field angles, the report) and `polar`
//! (the SVG diagram).

mod flux;
mod frame;
mod grid;
mod ies;
mod ies_grid;
mod ldt;
mod polar;
mod summary;
mod symmetry;
mod tokens;

use glam::DVec3;

pub use frame::PhotometricType;
pub use summary::{PeakDirection, PlaneAngles, Summary};
pub use symmetry::Symmetry;

/// The file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Format {
    /// IES LM-63 (`application/x-ies-lm-63`, `.ies`).
    Ies,
    /// EULUMDAT (`application/x-eulumdat`, `.ldt`).
    Eulumdat,
}

impl Format {
    /// The format for a media type or a file extension (`ies`, `ldt`), case-insensitive.
    pub fn from_mime_or_extension(s: &str) -> Option<Format> {
        match s.to_ascii_lowercase().as_str() {
            "application/x-ies-lm-63" | "ies" => Some(Format::Ies),
            "application/x-eulumdat" | "ldt" => Some(Format::Eulumdat),
            _ => None,
        }
    }
}

/// The luminous opening: the emitting area the photometry was measured from (m). `length` runs
/// along photometric X (C = 0°), `width` along Y (C = 90°), `height` along Z. A zero dimension is
/// a point or flat source. IES negative dimensions (round openings) are given as `Round`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Opening {
    pub length: f64,
    pub width: f64,
    pub height: f64,
    pub shape: OpeningShape,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum OpeningShape {
    Rectangular,
    /// Circular (length = width = diameter) or elliptical in plan.
    Round,
}

/// Largest photometric amount accepted anywhere in cd, cd/m², lm or lx: a million times the
/// brightest lamps made; larger ones overflow a bake's sums or come from a wrong unit.
pub const MAX_PHOTOMETRIC: f64 = 1e12;

/// A parse failure: 1-based line number (0 when it concerns the whole file) and the message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{message}", line_prefix(*.line))]
pub struct ParseError {
    pub line: usize,
    pub message: String,
}

fn line_prefix(line: usize) -> String {
    if line > 0 {
        format!("line {line}: ")
    } else {
        String::new()
    }
}

/// An IES `TILT=INCLUDE` table as read. The candela values were multiplied by `applied_factor`,
/// the table's multiplier at 0° tilt (linear between entries, the nearest entry outside them):
/// the luminaire is taken as mounted as measured; tilted mountings are not modelled.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TiltTable {
    /// Lamp-to-luminaire geometry: 1 (vertical base-up/down), 2 (horizontal, stays horizontal
    /// when tilted along the 0° plane), 3 (horizontal, tilts with the luminaire).
    pub geometry: u8,
    pub angles: Vec<f64>,
    pub factors: Vec<f64>,
    pub applied_factor: f64,
}

/// What a file says about itself, besides the intensities.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FileInfo {
    /// `LM-63-1986` … `LM-63-2019`, or `EULUMDAT`.
    pub version: String,
    pub photometric_type: PhotometricType,
    pub symmetry: Symmetry,
    /// IES keywords in file order (`[MORE]` lines joined with a newline), upper-case names.
    pub keywords: Vec<(String, String)>,
    /// IES `[MANUFAC]`; EULUMDAT line 1 (company).
    pub manufacturer: Option<String>,
    /// IES `[LUMINAIRE]`; EULUMDAT line 9.
    pub luminaire: Option<String>,
    /// IES `[LUMCAT]`; EULUMDAT line 10 (luminaire number).
    pub catalog_number: Option<String>,
    /// IES `[LAMP]`; EULUMDAT lamp types of the lamp sets, joined with "; ".
    pub lamp: Option<String>,
    /// IES `[TEST]`; EULUMDAT line 8 (measurement report).
    pub test: Option<String>,
    /// Number of lamps (EULUMDAT: over all lamp sets).
    pub lamp_count: u32,
    /// Lamp lumens × number of lamps (EULUMDAT: Σ lamp-set flux); `None` for absolute photometry.
    pub rated_lumens: Option<f64>,
    /// IES input watts; EULUMDAT Σ lamp-set wattage.
    pub input_watts: Option<f64>,
    pub tilt: Option<TiltTable>,
    /// EULUMDAT light output ratio of the luminaire (%), as declared.
    pub declared_lorl_percent: Option<f64>,
    /// EULUMDAT downward flux fraction (%), as declared.
    pub declared_dff_percent: Option<f64>,
}

/// What a format parser hands over.
struct Parsed {
    info: FileInfo,
    grid: grid::Grid,
    opening: Opening,
}

/// A measured intensity distribution in absolute candela.
#[derive(Debug, Clone)]
pub struct Photometry {
    format: Format,
    info: FileInfo,
    grid: grid::Grid,
    opening: Opening,
    flux: f64,
}

impl Photometry {
    /// Parse a file's bytes.
    pub fn parse(bytes: &[u8], format: Format) -> Result<Photometry, ParseError> {
        let text = tokens::decode(bytes);
        let parsed = match format {
            Format::Ies => ies::parse(&text)?,
            Format::Eulumdat => ldt::parse(&text)?,
        };
        let flux = flux::integrate(&parsed.grid);
        let (peak, _, _) = parsed.grid.peak();
        for (value, what) in [(peak, "peak intensity (cd)"), (flux, "luminous flux (lm)")] {
            if !(value.is_finite() && value <= MAX_PHOTOMETRIC) {
                return Err(ParseError {
                    line: 0,
                    message: format!(
                        "the {what} after the file's multipliers is {value:e}, not a finite \
                         amount ≤ {MAX_PHOTOMETRIC:e}; check the candela multiplier"
                    ),
                });
            }
        }
        Ok(Photometry {
            format,
            info: parsed.info,
            grid: parsed.grid,
            opening: parsed.opening,
            flux,
        })
    }

    /// Luminous intensity (cd) in unit direction `dir` of the photometric frame.
    #[inline]
    pub fn intensity(&self, dir: DVec3) -> f64 {
        let (phi, theta) = self.grid.frame.angles(dir);
        self.grid.eval(phi, theta)
    }

    /// Luminous intensity (cd) at the file's own angle pair, degrees: (C, γ) for type C,
    /// (H, V) for types A and B.
    pub fn intensity_at(&self, horizontal_deg: f64, vertical_deg: f64) -> f64 {
        self.intensity(
            self.photometric_type()
                .direction(horizontal_deg, vertical_deg),
        )
    }

    /// Total luminous flux (lm) of the distribution, integrated over the sphere.
    pub fn flux(&self) -> f64 {
        self.flux
    }

    /// The luminous opening the file declares (m).
    pub fn opening(&self) -> Opening {
        self.opening
    }

    pub(crate) fn format(&self) -> Format {
        self.format
    }

    /// Header data: names, version, lamps, tilt table, declared ratios.
    pub fn info(&self) -> &FileInfo {
        &self.info
    }

    pub fn photometric_type(&self) -> PhotometricType {
        self.info.photometric_type
    }

    pub fn symmetry(&self) -> Symmetry {
        self.info.symmetry
    }

    /// The declared lamp flux (lm): lamp lumens × number of lamps, or the EULUMDAT lamp sets'
    /// total; `None` for absolute photometry.
    pub fn rated_lumens(&self) -> Option<f64> {
        self.info.rated_lumens
    }

    /// Light output ratio `flux() / rated_lumens()`; `None` for absolute photometry.
    pub fn light_output_ratio(&self) -> Option<f64> {
        self.rated_lumens().map(|r| self.flux / r)
    }

    /// The largest tabulated intensity (cd) and its unit direction.
    pub fn max_intensity(&self) -> (f64, DVec3) {
        let (value, phi, theta) = self.grid.peak();
        (value, self.grid.frame.direction(phi, theta))
    }

    /// The summary a lighting designer reads (see [`Summary`]).
    pub fn summary(&self) -> Summary {
        summary::summarise(self)
    }

    /// The classic polar intensity diagram (C0–C180 and C90–C270, nadir down, cd) as SVG.
    pub fn polar_svg(&self) -> String {
        polar::svg(self)
    }
}
