//! EULUMDAT (`.ldt`) → absolute candela on a [`Grid`].
//!
//! Input: the file's text. Output: [`Parsed`] or a [`ParseError`] naming the line.
//!
//! Fixed line layout (1-based): 1 company, 2 type indicator Ityp, 3 symmetry Isym (0–4), 4 Mc
//! (C planes in 0°–360°), 5 Dc, 6 Ng (γ angles per plane), 7 Dg, 8 measurement report, 9 luminaire
//! name, 10 luminaire number, 11 file name, 12 date/user, 13–15 luminaire length/width/height
//! (mm), 16–17 luminous area length/width (mm; width 0 = round, diameter = length), 18–21
//! luminous area heights at C0/C90/C180/C270 (mm), 22 DFF (%), 23 LORL (%), 24 conversion factor,
//! 25 tilt during measurement, 26 number of lamp sets n; then per set six lines (number of lamps,
//! type, total flux (lm), colour temperature, colour rendering, wattage); ten direct ratios; then,
//! read as numbers across lines, the Mc C angles, the Ng γ angles and the intensities (cd/klm)
//! of the stored planes, plane by plane: Isym 0 all Mc planes, 1 one plane, 2 C0–C180, 3
//! C90–C270, 4 C0–C90. A decimal comma is a decimal point everywhere.
//!
//! Invariants and conventions: absolute cd = value × Φ/1000 × conversion factor, Φ = Σ over lamp
//! sets of their total flux. A negative number of lamps (DIALux's convention for absolute
//! photometry, e.g. LED luminaires) makes the photometry absolute: the same formula, with Φ the
//! luminaire's flux, and no rated lamp lumens. Opening: luminous area length along X (C0), width
//! along Y (C90), height the largest of the four heights.

use super::frame::{Frame, PhotometricType};
use super::grid::{EPS_DEG, Grid};
use super::symmetry::{Plane, Symmetry, complete_c};
use super::tokens::{
    Tokens, check_increasing, err, last_content_line, lines as split_lines, number,
};
use super::{FileInfo, Opening, OpeningShape, ParseError, Parsed};

/// The file's lines with typed access by 1-based line number.
struct Fields<'a> {
    lines: Vec<&'a str>,
    last: usize,
}

impl<'a> Fields<'a> {
    fn text(&self, n: usize, what: &str) -> Result<&'a str, ParseError> {
        if n > self.last {
            return Err(err(
                n,
                format!("expected {what}, but the file ends at line {}", self.last),
            ));
        }
        Ok(self.lines[n - 1].trim())
    }

    fn number(&self, n: usize, what: &str) -> Result<f64, ParseError> {
        let s = self.text(n, what)?;
        number(s, true).ok_or_else(|| {
            let found = if s.is_empty() {
                "an empty line".to_owned()
            } else {
                format!("`{s}`")
            };
            err(n, format!("expected {what} (a number), found {found}"))
        })
    }

    fn integer(&self, n: usize, what: &str) -> Result<i64, ParseError> {
        let v = self.number(n, what)?;
        if v.fract() != 0.0 || v.abs() > 1e6 {
            return Err(err(
                n,
                format!("expected {what} (a whole number), found {v}"),
            ));
        }
        Ok(v as i64)
    }

    fn label(&self, n: usize) -> Result<Option<String>, ParseError> {
        let s = self.text(n, "a text line")?;
        Ok((!s.is_empty()).then(|| s.to_owned()))
    }
}

struct LampSets {
    count: u32,
    flux: f64,
    watts: f64,
    absolute: bool,
    types: Vec<String>,
}

fn lamp_sets(f: &Fields, n: usize) -> Result<LampSets, ParseError> {
    let mut sets = LampSets {
        count: 0,
        flux: 0.0,
        watts: 0.0,
        absolute: false,
        types: Vec::new(),
    };
    for s in 0..n {
        let base = 27 + 6 * s;
        let k = s + 1;
        let lamps = f.integer(base, &format!("the number of lamps of lamp set {k}"))?;
        let ty = f.text(base + 1, &format!("the lamp type of lamp set {k}"))?;
        let flux = f.number(
            base + 2,
            &format!("the total lamp flux (lm) of lamp set {k}"),
        )?;
        if flux <= 0.0 {
            return Err(err(
                base + 2,
                format!("expected a lamp flux > 0 lm, found {flux}"),
            ));
        }
        f.text(base + 3, &format!("the colour temperature of lamp set {k}"))?;
        f.text(base + 4, &format!("the colour rendering of lamp set {k}"))?;
        let watts = f.number(base + 5, &format!("the wattage of lamp set {k}"))?;
        sets.count += lamps.unsigned_abs() as u32;
        sets.absolute |= lamps < 0;
        sets.flux += flux;
        sets.watts += watts;
        if !ty.is_empty() {
            sets.types.push(ty.to_owned());
        }
    }
    Ok(sets)
}

/// Ityp, Isym, Mc, Dc, Ng and Dg (lines 2–7): the symmetry indicator and the numbers of C planes
/// and γ angles, checked.
fn grid_header(f: &Fields) -> Result<(i64, usize, usize), ParseError> {
    f.integer(2, "the type indicator Ityp")?;
    let isym = f.integer(3, "the symmetry indicator Isym")?;
    if !(0..=4).contains(&isym) {
        return Err(err(
            3,
            format!("expected the symmetry indicator Isym 0, 1, 2, 3 or 4, found {isym}"),
        ));
    }
    let mc = f.integer(4, "the number of C planes Mc")?;
    let divisor = match isym {
        2 | 3 => 2,
        4 => 4,
        _ => 1,
    };
    if !(1..=3600).contains(&mc) || mc % divisor != 0 {
        return Err(err(
            4,
            format!(
                "expected a number of C planes Mc ≥ 1 and divisible by {divisor} for Isym {isym}, found {mc}"
            ),
        ));
    }
    f.number(5, "the C plane spacing Dc")?;
    let ng = f.integer(6, "the number of γ angles Ng")?;
    if !(2..=3600).contains(&ng) {
        return Err(err(
            6,
            format!("expected a number of γ angles Ng ≥ 2, found {ng}"),
        ));
    }
    f.number(7, "the γ angle spacing Dg")?;
    Ok((isym, mc as usize, ng as usize))
}

/// The symmetry Isym declares and which of the `mc` C planes the file stores, checked against
/// the C angles read (`c`, on the lines `c_lines`).
fn stored_planes(
    isym: i64,
    mc: usize,
    c: &[f64],
    c_lines: &[usize],
) -> Result<(Symmetry, std::ops::Range<usize>), ParseError> {
    let (symmetry, stored, range) = match isym {
        0 => (Symmetry::None, 0..mc, None),
        1 => (Symmetry::Axial, 0..1, None),
        2 => (Symmetry::BilateralC0C180, 0..mc / 2 + 1, Some((0.0, 180.0))),
        3 => (
            Symmetry::BilateralC90C270,
            mc / 4..mc / 4 + mc / 2 + 1,
            Some((90.0, 270.0)),
        ),
        _ => (Symmetry::Quadrant, 0..mc / 4 + 1, Some((0.0, 90.0))),
    };
    if stored.end > mc {
        return Err(err(
            4,
            format!("expected more C planes for Isym {isym}, found Mc = {mc}"),
        ));
    }
    if let Some((lo, hi)) = range {
        let (a, b) = (c[stored.start], c[stored.end - 1]);
        if (a - lo).abs() > 1e-6 || (b - hi).abs() > 1e-6 {
            return Err(err(
                c_lines[stored.start],
                format!(
                    "expected Isym {isym} to store the C planes {lo}° to {hi}°, but its C angles give {a}° to {b}°"
                ),
            ));
        }
    }
    Ok((symmetry, stored))
}

/// The luminous opening from the dimensions of lines 13–21 (mm): round when its width is 0,
/// as tall as its largest height.
fn opening_of(dims: &[f64]) -> Opening {
    let (la, wa) = (dims[3] / 1000.0, dims[4] / 1000.0);
    let height = dims[5..9].iter().fold(0.0_f64, |m, &h| m.max(h.abs())) / 1000.0;
    if wa == 0.0 {
        Opening {
            length: la,
            width: la,
            height,
            shape: OpeningShape::Round,
        }
    } else {
        Opening {
            length: la,
            width: wa,
            height,
            shape: OpeningShape::Rectangular,
        }
    }
}

pub(super) fn parse(text: &str) -> Result<Parsed, ParseError> {
    let lines = split_lines(text);
    let last = last_content_line(&lines);
    let f = Fields { lines, last };
    let (isym, mc, ng) = grid_header(&f)?;
    const DIMS: [&str; 9] = [
        "the luminaire length (mm)",
        "the luminaire width (mm)",
        "the luminaire height (mm)",
        "the luminous area length (mm)",
        "the luminous area width (mm)",
        "the luminous area height at C0 (mm)",
        "the luminous area height at C90 (mm)",
        "the luminous area height at C180 (mm)",
        "the luminous area height at C270 (mm)",
    ];
    let dims: Vec<f64> = (13..=21)
        .map(|n| f.number(n, DIMS[n - 13]))
        .collect::<Result<_, _>>()?;
    let dff = f.number(22, "the downward flux fraction DFF (%)")?;
    let lorl = f.number(23, "the light output ratio LORL (%)")?;
    let conversion = f.number(24, "the conversion factor for luminous intensities")?;
    if conversion <= 0.0 {
        return Err(err(
            24,
            format!("expected a conversion factor > 0, found {conversion}"),
        ));
    }
    f.number(25, "the tilt during measurement (°)")?;
    let n_sets = f.integer(26, "the number of lamp sets n")?;
    if !(1..=100).contains(&n_sets) {
        return Err(err(
            26,
            format!("expected at least one lamp set, found {n_sets}"),
        ));
    }
    let sets = lamp_sets(&f, n_sets as usize)?;
    let ratios = 27 + 6 * n_sets as usize;
    for k in 0..10 {
        f.number(ratios + k, &format!("direct ratio {} of 10", k + 1))?;
    }
    let mut tokens = Tokens::new(&f.lines, ratios + 9, false);
    let (c, c_lines) = tokens.numbers(mc, |i| format!("C angle {} of {mc}", i + 1))?;
    check_increasing(&c, &c_lines, "C angles")?;
    let (g, g_lines) = tokens.numbers(ng, |i| format!("γ angle {} of {ng}", i + 1))?;
    check_increasing(&g, &g_lines, "γ angles")?;
    if g[0] < -EPS_DEG || g[ng - 1] > 180.0 + EPS_DEG {
        return Err(err(
            g_lines[0],
            format!(
                "expected γ angles within 0°–180°, found {}° to {}°",
                g[0],
                g[ng - 1]
            ),
        ));
    }
    let (symmetry, stored) = stored_planes(isym, mc, &c, &c_lines)?;
    let total = stored.len() * ng;
    let what = |i: usize| {
        format!(
            "intensity {} of {total} ({} C planes × {ng} γ angles, cd/klm)",
            i + 1,
            stored.len()
        )
    };
    let (values, v_lines) = tokens.numbers(total, what)?;
    if let Some(k) = values.iter().position(|&v| v < 0.0) {
        return Err(err(
            v_lines[k],
            format!("expected an intensity ≥ 0, found {}", values[k]),
        ));
    }
    if let Some((line, tok)) = tokens.peek() {
        return Err(err(
            line,
            format!(
                "expected {total} intensities and then the end of the file, found more: `{tok}`"
            ),
        ));
    }
    let scale = sets.flux / 1000.0 * conversion;
    let planes: Vec<Plane> = stored
        .clone()
        .zip(values.chunks(ng))
        .map(|(j, v)| {
            (
                if isym == 1 { 0.0 } else { c[j] },
                v.iter().map(|x| x * scale).collect(),
            )
        })
        .collect();
    let full = complete_c(planes, symmetry);
    let (angles, table): (Vec<f64>, Vec<Vec<f64>>) = full.into_iter().unzip();
    let grid = Grid::new(Frame::of(PhotometricType::C), angles, g, table.concat());
    let opening = opening_of(&dims);
    let info = FileInfo {
        version: "EULUMDAT".into(),
        photometric_type: PhotometricType::C,
        symmetry,
        keywords: Vec::new(),
        manufacturer: f.label(1)?,
        luminaire: f.label(9)?,
        catalog_number: f.label(10)?,
        lamp: (!sets.types.is_empty()).then(|| sets.types.join("; ")),
        test: f.label(8)?,
        lamp_count: sets.count,
        rated_lumens: (!sets.absolute).then_some(sets.flux),
        input_watts: Some(sets.watts),
        tilt: None,
        declared_lorl_percent: Some(lorl),
        declared_dff_percent: Some(dff),
    };
    Ok(Parsed {
        info,
        grid,
        opening,
    })
}
