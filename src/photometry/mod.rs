//! Photometric data files — IES LM-63 (1986, 1991, 1995, 2002, 2019) and EULUMDAT — parsed into
//! a [`Photometry`]: absolute luminous intensity (cd) over the whole sphere, smoothly
//! interpolated and exact at the measured angles, with its flux, summary and polar curve.
//!
//! The photometric frame: unit vectors `dir` are given in the luminaire's own axes, where −Z is
//! the nadir — the direction of (C, γ) = (0°, 0°) for type C photometry — +X is the C = 0° half
//! plane and +Y the C = 90° half plane (C increases counter-clockwise seen from above, i.e. from
//! +Z). This is EXT_lights_ies' convention (the X/Z plane is the vertical photometric plane of
//! C = 0/180; an untransformed light points down −Z). Types A and B map into the same frame (see
//! the implementation's docs).
//!
//! The parsers are written here (no AGPL/GPL crate). Malformed files give a [`ParseError`] with the
//! line number and what was expected.

use glam::DVec3;

/// The file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

/// A parse failure: 1-based line number (0 when it concerns the whole file) and the message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct ParseError {
    pub line: usize,
    pub message: String,
}

/// A measured intensity distribution in absolute candela.
#[derive(Debug, Clone)]
pub struct Photometry {
    _private: (),
}

impl Photometry {
    /// Parse a file's bytes.
    pub fn parse(bytes: &[u8], format: Format) -> Result<Photometry, ParseError> {
        let _ = (bytes, format);
        Err(ParseError {
            line: 0,
            message: "photometry parsing is not implemented yet".into(),
        })
    }

    /// Luminous intensity (cd) in unit direction `dir` of the photometric frame.
    pub fn intensity(&self, dir: DVec3) -> f64 {
        let _ = dir;
        0.0
    }

    /// Total luminous flux (lm) of the distribution, integrated over the sphere.
    pub fn flux(&self) -> f64 {
        0.0
    }

    /// The luminous opening the file declares (m).
    pub fn opening(&self) -> Opening {
        Opening {
            length: 0.0,
            width: 0.0,
            height: 0.0,
            shape: OpeningShape::Rectangular,
        }
    }
}
