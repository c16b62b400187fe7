//! Malformed IES and EULUMDAT files: each is refused with the line and what was expected.
//! Also: a BOM and Latin-1 bytes are accepted.

use luxbake::photometry::{Format, ParseError, Photometry};

use super::dir;

pub(crate) fn parse_ies(text: &str) -> Result<Photometry, ParseError> {
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

fn expect_err(result: Result<Photometry, ParseError>, line: usize, words: &[&str]) {
    let e = result.expect_err("the file must be refused");
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

fn parse_ldt(lines: &[String]) -> Result<Photometry, ParseError> {
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
