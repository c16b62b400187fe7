//! IES LM-63 (1986, 1991, 1995, 2002, 2019) → absolute candela on a [`Grid`].
//!
//! Input: the file's text. Output: [`Parsed`] (header data, the expanded table, the opening) or a
//! [`ParseError`] naming the line and what was expected.
//!
//! Layout: an optional version line (`IESNA91`, `IESNA:LM-63-1995`, `IESNA:LM-63-2002`,
//! `IES:LM-63-2019`; without one the file is LM-63-1986 with a free-text header), keyword lines
//! `[KEYWORD] value` (`[MORE]` continues the previous one), the `TILT=` line, then numbers
//! separated by white space and/or commas, free-form across lines: the tilt table
//! (`TILT=INCLUDE`: geometry, pair count, angles, multipliers), lamps, lumens per lamp (−1 =
//! absolute photometry), candela multiplier, vertical and horizontal angle counts, photometric
//! type (1 = C, 2 = B, 3 = A), units (1 = feet, 2 = metres), width, length, height; ballast
//! factor, ballast-lamp photometric factor (1986/1991; "future use" in 1995/2002, file generation
//! type in 2019), input watts; the vertical angles, the horizontal angles, and the candela values
//! plane by plane (all vertical angles of the first horizontal angle first).
//!
//! Invariants and conventions: absolute cd = value × multiplier × ballast factor (× ballast-lamp
//! factor for 1986/1991) × tilt multiplier at 0°. `TILT=<file>` is refused. Angle ranges are
//! LM-63-2002's: type C vertical 0°/90° → 90°/180°, horizontal 0° → 0° (axial), 90° (quadrant),
//! 180° (bilateral), 360° (none), or LM-63-95's 90° → 270° (bilateral about C90–C270); a
//! horizontal run ending short of 360° by exactly its last step is taken as "none" with the 360°
//! plane omitted. Types A/B: both ranges −90° or 0° → 90°; a range starting at 0° is mirrored.
//! Opening: width along Y (C90), length along X (C0, the luminaire's length), height along Z;
//! feet are converted to metres; any negative dimension (LM-63-2002/2019: round, elliptical,
//! cylindrical or spherical shapes) gives [`OpeningShape::Round`] with the absolute values (a zero
//! length or width of a round opening takes the other: a circle).

use super::frame::PhotometricType;
use super::ies_grid::{Ranges, grid_ab, grid_c, opening};
use super::symmetry::Plane;
use super::tokens::{Tokens, check_increasing, err, last_content_line, lines as split_lines};
use super::{FileInfo, ParseError, Parsed, TiltTable};

const FOOT: f64 = 0.3048;

/// The standard year of a version line, if the line is one.
fn version_of(line: &str) -> Option<u16> {
    let l = line.trim().to_ascii_uppercase();
    if l == "IESNA91" {
        return Some(1991);
    }
    let year = l
        .strip_prefix("IESNA:LM-63-")
        .or_else(|| l.strip_prefix("IES:LM-63-"))?;
    match year.trim() {
        "1995" => Some(1995),
        "2002" => Some(2002),
        "2019" => Some(2019),
        _ => None,
    }
}

/// A line of numbers only (the data begun without a TILT line).
fn is_numeric(line: &str) -> bool {
    let mut toks = line
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty());
    let first = toks.next();
    first.is_some()
        && first
            .into_iter()
            .chain(toks)
            .all(|t| t.parse::<f64>().is_ok())
}

pub(super) fn parse(text: &str) -> Result<Parsed, ParseError> {
    let lines = split_lines(text);
    let year = lines.first().and_then(|l| version_of(l));
    let mut keywords: Vec<(String, String)> = Vec::new();
    let mut i = usize::from(year.is_some());
    let tilt_index = loop {
        let Some(line) = lines.get(i) else {
            return Err(err(
                last_content_line(&lines),
                "expected a `TILT=` line (TILT=NONE, TILT=INCLUDE or TILT=<file>) after the \
                 header, but the file ends without one",
            ));
        };
        let t = line.trim();
        if t.get(..5).is_some_and(|p| p.eq_ignore_ascii_case("TILT=")) {
            break i;
        }
        if let Some((key, value)) = t.strip_prefix('[').and_then(|r| r.split_once(']')) {
            let (key, value) = (key.trim().to_ascii_uppercase(), value.trim().to_owned());
            match keywords.last_mut() {
                Some(last) if key == "MORE" => {
                    last.1.push('\n');
                    last.1.push_str(&value);
                }
                _ => keywords.push((key, value)),
            }
        } else if is_numeric(t) {
            return Err(err(
                i + 1,
                format!(
                    "expected a `TILT=` line (TILT=NONE, TILT=INCLUDE or TILT=<file>) before \
                     the photometric data, found `{t}`"
                ),
            ));
        }
        i += 1;
    };
    let tilt_value = lines[tilt_index].trim()[5..].trim();
    let mut tokens = Tokens::new(&lines, tilt_index + 1, true);
    let tilt = if tilt_value.eq_ignore_ascii_case("NONE") {
        None
    } else if tilt_value.eq_ignore_ascii_case("INCLUDE") {
        Some(tilt_table(&mut tokens)?)
    } else if tilt_value.is_empty() {
        return Err(err(
            tilt_index + 1,
            "expected NONE, INCLUDE or a file name after `TILT=`",
        ));
    } else {
        return Err(err(
            tilt_index + 1,
            format!(
                "TILT={tilt_value} refers to a separate tilt file, which is not supported; \
                 expected TILT=NONE or TILT=INCLUDE (the tilt table in this file)"
            ),
        ));
    };
    body(year.unwrap_or(1986), keywords, tilt, &mut tokens)
}

fn tilt_table(tokens: &mut Tokens) -> Result<TiltTable, ParseError> {
    let (geometry, line) = tokens.integer("the lamp-to-luminaire geometry (1, 2 or 3)")?;
    if !(1..=3).contains(&geometry) {
        return Err(err(
            line,
            format!("expected the lamp-to-luminaire geometry 1, 2 or 3, found {geometry}"),
        ));
    }
    let (n, line) = tokens.integer("the number of tilt angle/multiplier pairs")?;
    if !(1..=10_000).contains(&n) {
        return Err(err(
            line,
            format!("expected at least one tilt angle/multiplier pair, found {n}"),
        ));
    }
    let n = n as usize;
    let (angles, lines) = tokens.numbers(n, |i| format!("tilt angle {} of {n}", i + 1))?;
    check_increasing(&angles, &lines, "tilt angles")?;
    let (factors, lines) = tokens.numbers(n, |i| format!("tilt multiplier {} of {n}", i + 1))?;
    if let Some(k) = factors.iter().position(|&f| f < 0.0) {
        return Err(err(
            lines[k],
            format!("expected a tilt multiplier ≥ 0, found {}", factors[k]),
        ));
    }
    let k = angles.partition_point(|&a| a <= 0.0);
    let applied_factor = if k == 0 {
        factors[0]
    } else if k == n {
        factors[n - 1]
    } else {
        let t = -angles[k - 1] / (angles[k] - angles[k - 1]);
        factors[k - 1] + t * (factors[k] - factors[k - 1])
    };
    Ok(TiltTable {
        geometry: geometry as u8,
        angles,
        factors,
        applied_factor,
    })
}

fn positive(tokens: &mut Tokens, what: &str) -> Result<f64, ParseError> {
    let (v, line) = tokens.number(what)?;
    if v <= 0.0 {
        return Err(err(line, format!("expected {what} > 0, found {v}")));
    }
    Ok(v)
}

fn count(tokens: &mut Tokens, what: &str, min: i64) -> Result<usize, ParseError> {
    let (n, line) = tokens.integer(what)?;
    if !(min..=100_000).contains(&n) {
        return Err(err(
            line,
            format!("expected {what} of at least {min}, found {n}"),
        ));
    }
    Ok(n as usize)
}

/// The numbers between the tilt data and the angles.
struct Header {
    lamps: usize,
    /// Lumens per lamp, and whether the file is in absolute photometry (−1).
    lumens: f64,
    absolute: bool,
    /// The candela multiplier.
    multiplier: f64,
    /// Vertical and horizontal angle counts.
    nv: usize,
    nh: usize,
    ty: PhotometricType,
    /// Metres per unit of `dims` (width, length, height).
    scale: f64,
    dims: Vec<f64>,
    ballast: f64,
    /// The ballast-lamp photometric factor (1986/1991); else the future-use / file generation
    /// type field.
    second: f64,
    watts: f64,
}

/// Reads the [`Header`], checking each number as it comes.
fn header(old: bool, tokens: &mut Tokens) -> Result<Header, ParseError> {
    let lamps = count(tokens, "the number of lamps", 1)?;
    let (lumens, line) = tokens.number("the lumens per lamp")?;
    let absolute = lumens == -1.0;
    if !absolute && lumens <= 0.0 {
        return Err(err(
            line,
            format!("expected lumens per lamp > 0, or −1 for absolute photometry, found {lumens}"),
        ));
    }
    let multiplier = positive(tokens, "the candela multiplier")?;
    let nv = count(tokens, "the number of vertical angles", 2)?;
    let nh = count(tokens, "the number of horizontal angles", 1)?;
    let (code, line) = tokens.integer("the photometric type")?;
    let ty = match code {
        1 => PhotometricType::C,
        2 => PhotometricType::B,
        3 => PhotometricType::A,
        _ => {
            return Err(err(
                line,
                format!("expected photometric type 1 (C), 2 (B) or 3 (A), found {code}"),
            ));
        }
    };
    let (units, line) = tokens.integer("the units type")?;
    let scale = match units {
        1 => FOOT,
        2 => 1.0,
        _ => {
            return Err(err(
                line,
                format!("expected units type 1 (feet) or 2 (metres), found {units}"),
            ));
        }
    };
    let (dims, _) = tokens.numbers(3, |i| ["the width", "the length", "the height"][i].into())?;
    let ballast = positive(tokens, "the ballast factor")?;
    let second = if old {
        positive(tokens, "the ballast-lamp photometric factor")?
    } else {
        tokens
            .number("the future-use / file generation type field")?
            .0
    };
    let (watts, _) = tokens.number("the input watts")?;
    Ok(Header {
        lamps,
        lumens,
        absolute,
        multiplier,
        nv,
        nh,
        ty,
        scale,
        dims,
        ballast,
        second,
        watts,
    })
}

/// The angles (with the lines they are on) and the candela values plane by plane, as read.
struct Table {
    v: Vec<f64>,
    v_lines: Vec<usize>,
    h: Vec<f64>,
    h_lines: Vec<usize>,
    cd: Vec<f64>,
}

/// Reads `nv` vertical and `nh` horizontal angles (each increasing) and the `nv × nh` candela
/// values (each ≥ 0), which must end the file.
fn table(tokens: &mut Tokens, nv: usize, nh: usize) -> Result<Table, ParseError> {
    let (v, v_lines) = tokens.numbers(nv, |i| format!("vertical angle {} of {nv}", i + 1))?;
    check_increasing(&v, &v_lines, "vertical angles")?;
    let (h, h_lines) = tokens.numbers(nh, |i| format!("horizontal angle {} of {nh}", i + 1))?;
    check_increasing(&h, &h_lines, "horizontal angles")?;
    let total = nv * nh;
    let what = |i: usize| {
        format!(
            "candela value {} of {total} ({nh} horizontal × {nv} vertical angles)",
            i + 1
        )
    };
    let (cd, cd_lines) = tokens.numbers(total, what)?;
    if let Some(k) = cd.iter().position(|&c| c < 0.0) {
        return Err(err(
            cd_lines[k],
            format!("expected a candela value ≥ 0, found {}", cd[k]),
        ));
    }
    if let Some((line, tok)) = tokens.peek() {
        return Err(err(
            line,
            format!(
                "expected {total} candela values ({nh} horizontal × {nv} vertical angles) and \
                 then the end of the file, found more: `{tok}`"
            ),
        ));
    }
    Ok(Table {
        v,
        v_lines,
        h,
        h_lines,
        cd,
    })
}

/// Everything after the tilt data: the header numbers, the table in absolute candela on its
/// grid, and the file's information.
fn body(
    year: u16,
    keywords: Vec<(String, String)>,
    tilt: Option<TiltTable>,
    tokens: &mut Tokens,
) -> Result<Parsed, ParseError> {
    let old = year <= 1991;
    let hd = header(old, tokens)?;
    let (nv, ty) = (hd.nv, hd.ty);
    let Table {
        v,
        v_lines,
        h,
        h_lines,
        cd,
    } = table(tokens, nv, hd.nh)?;
    let factor = hd.multiplier
        * hd.ballast
        * if old { hd.second } else { 1.0 }
        * tilt.as_ref().map_or(1.0, |t| t.applied_factor);
    let planes: Vec<Plane> = h
        .iter()
        .zip(cd.chunks(nv))
        .map(|(&a, c)| (a, c.iter().map(|x| x * factor).collect()))
        .collect();
    let ranges = Ranges {
        v: &v,
        v_lines: &v_lines,
        h: &h,
        h_lines: &h_lines,
    };
    let (symmetry, grid) = match ty {
        PhotometricType::C => grid_c(&ranges, planes)?,
        _ => grid_ab(ty, &ranges, planes)?,
    };
    let find = |k: &str| {
        keywords
            .iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.clone())
    };
    let info = FileInfo {
        version: format!("LM-63-{year}"),
        photometric_type: ty,
        symmetry,
        manufacturer: find("MANUFAC"),
        luminaire: find("LUMINAIRE"),
        catalog_number: find("LUMCAT"),
        lamp: find("LAMP"),
        test: find("TEST"),
        keywords,
        lamp_count: hd.lamps as u32,
        rated_lumens: (!hd.absolute).then_some(hd.lumens * hd.lamps as f64),
        input_watts: Some(hd.watts),
        tilt,
        declared_lorl_percent: None,
        declared_dff_percent: None,
    };
    let (dims, scale) = (&hd.dims, hd.scale);
    Ok(Parsed {
        info,
        grid,
        opening: opening(dims[0] * scale, dims[1] * scale, dims[2] * scale),
    })
}
