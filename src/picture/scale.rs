//! A false-colour scale: values (cd/m², lx, …) → colours, linear or logarithmic, smooth or in
//! bands, with round automatic ranges and short labels for the legend.
//!
//! Input: the range [lo, hi], `log`, and `steps` (bands; 0 = smooth). Output: colours of a
//! palette running dark blue → blue → cyan → green → yellow → orange → red → magenta (in the
//! spirit of RADIANCE `falsecolor`; control points chosen here, interpolated linearly in sRGB),
//! band edges (`levels`) and their labels. Invariants: `position` is monotone and clamped to
//! [0, 1]; a banded colour is the smooth colour at its band's middle, so bands and the smooth
//! palette agree; NaN has position 0 (callers draw "no data" themselves).

/// A false-colour scale over [lo, hi], linear or logarithmic, smooth or in `steps` bands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColourScale {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    pub steps: u32,
}

/// Palette control points (position, sRGB), evenly spaced.
const PALETTE: [[u8; 3]; 9] = [
    [24, 0, 84],    // dark indigo
    [38, 42, 196],  // blue
    [18, 128, 238], // azure
    [0, 200, 206],  // cyan
    [44, 214, 92],  // green
    [176, 226, 30], // yellow-green
    [252, 196, 20], // amber
    [240, 88, 22],  // orange-red
    [196, 10, 96],  // crimson-magenta
];

/// Decades a logarithmic automatic range spans at most below its top.
const MAX_DECADES: i32 = 6;

impl ColourScale {
    /// A round range covering the finite values: linear lo = 0 and hi = bands × the smallest
    /// round band width (1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 6, 7.5 or 8 × 10^k) that covers the maximum,
    /// so every band edge is a short number (1 when no value is positive); log: whole decades
    /// from the one at or below the smallest positive value to the one at or above the largest,
    /// at most 6 decades (values further below are clamped to the bottom colour), with `steps`
    /// (when not 0) rounded to a whole number of bands per decade; 1 … 10 when no value is
    /// positive.
    pub fn auto(values: &[f64], log: bool, steps: u32) -> ColourScale {
        let finite = values.iter().copied().filter(|v| v.is_finite());
        let max = finite.clone().fold(f64::NEG_INFINITY, f64::max);
        if !log {
            // Round band edges: hi = bands × a round step, the smallest covering the maximum.
            let bands = if steps == 0 { 8 } else { steps };
            let hi = if max > 0.0 {
                f64::from(bands) * round_step(max / f64::from(bands))
            } else {
                1.0
            };
            return ColourScale {
                lo: 0.0,
                hi,
                log,
                steps,
            };
        }
        let min_pos = finite.filter(|&v| v > 0.0).fold(f64::INFINITY, f64::min);
        if !(min_pos.is_finite() && max > 0.0) {
            return ColourScale {
                lo: 1.0,
                hi: 10.0,
                log,
                steps,
            };
        }
        let top = decade_ceil(max);
        let mut bottom = decade_floor(min_pos).max(top - MAX_DECADES);
        if bottom >= top {
            bottom = top - 1;
        }
        // Bands a whole number per decade, so every decade is a band edge.
        let decades = (top - bottom) as u32;
        let steps = match steps {
            0 => 0,
            n => decades * ((f64::from(n) / f64::from(decades)).round() as u32).max(1),
        };
        ColourScale {
            lo: pow10(bottom),
            hi: pow10(top),
            log,
            steps,
        }
    }

    /// A scale over [lo, hi]; Err(message) when lo >= hi, either is not finite, or log with
    /// lo <= 0.
    pub fn fixed(lo: f64, hi: f64, log: bool, steps: u32) -> Result<ColourScale, String> {
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(format!("the scale {lo}:{hi} is not finite"));
        }
        if lo >= hi {
            return Err(format!("the scale {lo}:{hi} is empty (low ≥ high)"));
        }
        if log && lo <= 0.0 {
            return Err(format!(
                "a logarithmic scale needs a positive low end, not {lo}"
            ));
        }
        Ok(ColourScale { lo, hi, log, steps })
    }

    /// Where `v` lies on the scale: 0 at lo, 1 at hi (in log10 when logarithmic), clamped; NaN
    /// and (log) values ≤ 0 give 0.
    pub fn position(&self, v: f64) -> f64 {
        let p = if self.log {
            if v <= 0.0 {
                return 0.0;
            }
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        };
        if p.is_nan() { 0.0 } else { p.clamp(0.0, 1.0) }
    }

    /// The value at position t ∈ [0, 1] (the inverse of [`ColourScale::position`]).
    pub fn value_at(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, 1.0);
        if self.log {
            10f64.powf(self.lo.log10() + t * (self.hi.log10() - self.lo.log10()))
        } else {
            self.lo + t * (self.hi - self.lo)
        }
    }

    /// The band of `v` (0 … bands − 1; the top edge belongs to the last band).
    pub fn band(&self, v: f64) -> u32 {
        let n = self.bands();
        ((self.position(v) * f64::from(n)).floor() as u32).min(n - 1)
    }

    /// The number of bands `levels` and `band` use: `steps`, or 8 when smooth.
    pub fn bands(&self) -> u32 {
        if self.steps == 0 { 8 } else { self.steps }
    }

    /// The colour of `v`: the smooth palette, or with `steps` > 0 the colour at the middle of
    /// its band.
    pub fn colour(&self, v: f64) -> [u8; 3] {
        if self.steps == 0 {
            palette(self.position(v))
        } else {
            let n = f64::from(self.steps);
            palette((f64::from(self.band(v)) + 0.5) / n)
        }
    }

    /// Band edges from lo to hi, `bands() + 1` values (geometric when logarithmic).
    pub fn levels(&self) -> Vec<f64> {
        let n = self.bands();
        (0..=n)
            .map(|i| {
                let t = f64::from(i) / f64::from(n);
                match i {
                    0 => self.lo,
                    _ if i == n => self.hi,
                    _ => self.value_at(t),
                }
            })
            .collect()
    }

    /// A short plain number: three significant digits, no exponent, no trailing zeros
    /// ("0", "0.5", "12.5", "250", "1500").
    pub fn label(&self, v: f64) -> String {
        label(v)
    }
}

/// `v` with three significant digits as plain text (see [`ColourScale::label`]).
pub fn label(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let magnitude = v.abs().log10().floor() as i32;
    let decimals = (2 - magnitude).clamp(0, 12) as usize;
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".to_string() } else { s }
}

/// The palette at t ∈ [0, 1], piecewise linear between the control points (sRGB).
pub fn palette(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (PALETTE.len() - 1) as f64;
    let i = (x.floor() as usize).min(PALETTE.len() - 2);
    let f = x - i as f64;
    let (a, b) = (PALETTE[i], PALETTE[i + 1]);
    std::array::from_fn(|k| {
        (f64::from(a[k]) + f * (f64::from(b[k]) - f64::from(a[k]))).round() as u8
    })
}

/// The smallest 1, 2, 2.5 or 5 × 10^k ≥ v (v > 0), robust to rounding (1000 stays 1000).
pub fn round_up(v: f64) -> f64 {
    let k = v.log10().floor() as i32;
    for e in [k - 1, k, k + 1] {
        for m in [1.0, 2.0, 2.5, 5.0] {
            let c = if e >= 0 { m * pow10(e) } else { m / pow10(-e) };
            if c >= v * (1.0 - 1e-12) {
                return c;
            }
        }
    }
    pow10(k + 2)
}

/// The smallest 1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 6, 7.5 or 8 × 10^k ≥ v (v > 0): a band width whose
/// multiples print short.
fn round_step(v: f64) -> f64 {
    let k = v.log10().floor() as i32;
    for e in [k - 1, k, k + 1] {
        for m in [1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.5, 8.0] {
            let c = if e >= 0 { m * pow10(e) } else { m / pow10(-e) };
            if c >= v * (1.0 - 1e-12) {
                return c;
            }
        }
    }
    pow10(k + 2)
}

/// 10^k, correctly rounded for negative k too (1 / 10^−k: 0.1, not 0.1000…02).
fn pow10(k: i32) -> f64 {
    if k >= 0 {
        10f64.powi(k)
    } else {
        1.0 / 10f64.powi(-k)
    }
}

/// The exponent of the decade at or above v (v > 0), robust to rounding.
fn decade_ceil(v: f64) -> i32 {
    let l = v.log10();
    let k = l.round();
    if (l - k).abs() < 1e-9 {
        k as i32
    } else {
        l.ceil() as i32
    }
}

/// The exponent of the decade at or below v (v > 0), robust to rounding.
fn decade_floor(v: f64) -> i32 {
    let l = v.log10();
    let k = l.round();
    if (l - k).abs() < 1e-9 {
        k as i32
    } else {
        l.floor() as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_linear_rounds_up() {
        let s = |m: f64| ColourScale::auto(&[0.001, m, f64::NAN], false, 8);
        assert_eq!((s(870.0).lo, s(870.0).hi), (0.0, 1000.0));
        assert_eq!(s(1000.0).hi, 1000.0);
        assert_eq!(s(1001.0).hi, 1200.0);
        assert_eq!(s(2100.0).hi, 2400.0);
        assert_eq!(s(3.2).hi, 3.2);
        assert_eq!(s(0.0121).hi, 0.016);
        // every band edge a short number
        for m in [0.37, 12.0, 498.0, 870.0, 1234.5, 7777.0] {
            for l in s(m).levels() {
                assert!(
                    label(l)
                        .trim_start_matches('0')
                        .trim_start_matches('.')
                        .len()
                        <= 4,
                    "{l}"
                );
                assert!(
                    (label(l).parse::<f64>().unwrap() - l).abs() <= 1e-9 * s(m).hi,
                    "{l}"
                );
            }
        }
        assert_eq!(ColourScale::auto(&[], false, 8).hi, 1.0);
        assert_eq!(ColourScale::auto(&[-3.0, 0.0], false, 8).hi, 1.0);
    }

    #[test]
    fn auto_log_whole_decades() {
        let s = ColourScale::auto(&[0.0, 0.37, 45.0, -1.0], true, 8);
        assert_eq!((s.lo, s.hi), (0.1, 100.0));
        let s = ColourScale::auto(&[100.0, 100.0], true, 8);
        assert_eq!((s.lo, s.hi), (10.0, 100.0));
        let s = ColourScale::auto(&[1e-9, 5e3], true, 8);
        assert_eq!((s.lo, s.hi), (1e-2, 1e4)); // at most 6 decades
        let s = ColourScale::auto(&[0.0], true, 8);
        assert_eq!((s.lo, s.hi), (1.0, 10.0));
        // bands a whole number per decade: 3 decades and 8 asked → 9, each decade an edge
        let s = ColourScale::auto(&[0.37, 45.0], true, 8);
        assert_eq!(s.steps, 9);
        assert!((s.levels()[3] - 1.0).abs() < 1e-12 && (s.levels()[6] - 10.0).abs() < 1e-12);
    }

    #[test]
    fn fixed_checks() {
        assert!(ColourScale::fixed(0.0, 500.0, false, 5).is_ok());
        assert!(ColourScale::fixed(5.0, 5.0, false, 5).is_err());
        assert!(ColourScale::fixed(0.0, f64::INFINITY, false, 5).is_err());
        assert!(ColourScale::fixed(0.0, 10.0, true, 5).is_err());
    }

    #[test]
    fn positions_bands_levels() {
        let lin = ColourScale::fixed(0.0, 800.0, false, 8).unwrap();
        assert_eq!(lin.position(200.0), 0.25);
        assert_eq!(lin.position(-5.0), 0.0);
        assert_eq!(lin.position(9e9), 1.0);
        assert_eq!(lin.band(99.9), 0);
        assert_eq!(lin.band(100.0), 1);
        assert_eq!(lin.band(800.0), 7);
        assert_eq!(
            lin.levels(),
            vec![0.0, 100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0]
        );
        // banded colour = the smooth colour at the band's middle
        let smooth = ColourScale { steps: 0, ..lin };
        assert_eq!(lin.colour(120.0), smooth.colour(150.0));
        let log = ColourScale::fixed(1.0, 1e4, true, 4).unwrap();
        assert!((log.position(100.0) - 0.5).abs() < 1e-15);
        let l = log.levels();
        assert_eq!(l.len(), 5);
        assert!((l[1] - 10.0).abs() < 1e-12 && (l[3] - 1000.0).abs() < 1e-9);
        assert_eq!(log.position(0.0), 0.0);
    }

    #[test]
    fn palette_runs_blue_to_red() {
        assert_eq!(palette(0.0), PALETTE[0]);
        assert_eq!(palette(1.0), PALETTE[8]);
        assert_eq!(palette(0.0625), [31, 21, 140]); // halfway between the first two
        let b = palette(0.1);
        let r = palette(0.9);
        assert!(b[2] > b[0] && r[0] > r[2]);
    }

    #[test]
    fn labels_are_plain() {
        let cases = [
            (0.0, "0"),
            (0.5, "0.5"),
            (12.5, "12.5"),
            (250.0, "250"),
            (1500.0, "1500"),
            (1.0 / 3.0, "0.333"),
            (0.001, "0.001"),
            (-2.5, "-2.5"),
            (31.622_776, "31.6"),
        ];
        for (v, text) in cases {
            assert_eq!(label(v), text, "{v}");
        }
    }
}
