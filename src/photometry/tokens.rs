//! The text of a photometric file: decoding, lines and numbers with their line numbers.
//!
//! Input: the file's bytes. Output: its lines (1-based numbers in every message) and a stream of
//! numeric tokens. Invariants: a byte-order mark or CR line ends never shift a line number;
//! bytes that are not UTF-8 are read as Latin-1 (EULUMDAT files from Windows tools often are);
//! every number returned is finite.

use super::ParseError;

/// A [`ParseError`] at a 1-based line.
pub(super) fn err(line: usize, message: impl Into<String>) -> ParseError {
    ParseError {
        line,
        message: message.into(),
    }
}

/// The file's text: UTF-8 without a BOM, or Latin-1 when the bytes are not UTF-8.
pub(super) fn decode(bytes: &[u8]) -> String {
    let bytes = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]).unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_owned(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

/// The lines of `text` (line `i + 1` is `lines[i]`), without their CR/LF.
pub(super) fn lines(text: &str) -> Vec<&str> {
    text.split('\n')
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .collect()
}

/// The number of the last line with any content (0 for an empty file).
pub(super) fn last_content_line(lines: &[&str]) -> usize {
    lines
        .iter()
        .rposition(|l| !l.trim().is_empty())
        .map_or(0, |i| i + 1)
}

/// A finite number; with `decimal_comma`, one `,` is read as the decimal point.
pub(super) fn number(s: &str, decimal_comma: bool) -> Option<f64> {
    let s = s.trim();
    let v: f64 = if decimal_comma && s.contains(',') {
        s.replacen(',', ".", 1).parse().ok()?
    } else {
        s.parse().ok()?
    };
    v.is_finite().then_some(v)
}

/// Numeric tokens of a run of lines, in order, each with its line number.
pub(super) struct Tokens<'a> {
    items: Vec<(usize, &'a str)>,
    pos: usize,
    last_line: usize,
    decimal_comma: bool,
}

impl<'a> Tokens<'a> {
    /// The tokens of `lines[first..]`, split at white space and, if `comma_separates`, at
    /// commas (IES); otherwise a comma is a decimal point (EULUMDAT).
    pub(super) fn new(lines: &[&'a str], first: usize, comma_separates: bool) -> Tokens<'a> {
        let mut items = Vec::new();
        for (i, line) in lines.iter().enumerate().skip(first) {
            let parts = line.split(|c: char| c.is_whitespace() || (comma_separates && c == ','));
            items.extend(parts.filter(|t| !t.is_empty()).map(|t| (i + 1, t)));
        }
        Tokens {
            items,
            pos: 0,
            last_line: last_content_line(lines),
            decimal_comma: !comma_separates,
        }
    }

    /// The next token as a number, with its line; `what` names it in the error.
    pub(super) fn number(&mut self, what: &str) -> Result<(f64, usize), ParseError> {
        let Some(&(line, tok)) = self.items.get(self.pos) else {
            return Err(err(
                self.last_line,
                format!("expected {what}, but the file ends here"),
            ));
        };
        self.pos += 1;
        number(tok, self.decimal_comma)
            .map(|v| (v, line))
            .ok_or_else(|| err(line, format!("expected {what} (a number), found `{tok}`")))
    }

    /// The next token as a whole number.
    pub(super) fn integer(&mut self, what: &str) -> Result<(i64, usize), ParseError> {
        let (v, line) = self.number(what)?;
        if v.fract() != 0.0 || v.abs() > 1e9 {
            return Err(err(
                line,
                format!("expected {what} (a whole number), found {v}"),
            ));
        }
        Ok((v as i64, line))
    }

    /// `n` numbers (values and lines); `what(i)` names the i-th in errors.
    pub(super) fn numbers(
        &mut self,
        n: usize,
        what: impl Fn(usize) -> String,
    ) -> Result<(Vec<f64>, Vec<usize>), ParseError> {
        let mut values = Vec::with_capacity(n);
        let mut lines = Vec::with_capacity(n);
        for i in 0..n {
            let (v, line) = self.number(&what(i))?;
            values.push(v);
            lines.push(line);
        }
        Ok((values, lines))
    }

    /// The next unread token and its line, if any.
    pub(super) fn peek(&self) -> Option<(usize, &'a str)> {
        self.items.get(self.pos).copied()
    }
}

/// Checks that `angles` strictly increase; the error names the first offending angle's line.
pub(super) fn check_increasing(
    angles: &[f64],
    lines: &[usize],
    what: &str,
) -> Result<(), ParseError> {
    for i in 1..angles.len() {
        if angles[i] <= angles[i - 1] {
            return Err(err(
                lines[i],
                format!(
                    "{what} must increase, but {}° follows {}°",
                    angles[i],
                    angles[i - 1]
                ),
            ));
        }
    }
    Ok(())
}
