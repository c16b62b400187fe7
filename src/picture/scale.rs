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
    /// Tick intervals of a smooth scale (`steps` 0): its levels, legend ticks and contours.
    pub ticks: u32,
    /// Some values lie below `lo` / above `hi` (an automatic range leaves the extremes out):
    /// the legend labels that end "≤ lo" / "≥ hi".
    pub open_low: bool,
    pub open_high: bool,
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

/// The share of the values an automatic range leaves out at each end (nearest-rank
/// percentiles 2 and 98): light sources, a few hot pixels or a dark corner do not set it.
pub const ROBUST: f64 = 0.02;

impl ColourScale {
    /// A round range over the finite values' 2nd–98th percentiles ([`ROBUST`]); values beyond
    /// it take the end colours and the legend says so (`open_low`, `open_high`).
    /// Linear: band edges at whole multiples of a 1-2-5 step (1, 2 or 5 × 10^k), lo the
    /// multiple at or below the 2nd percentile, hi the first at or above the 98th, so the range
    /// overshoots each percentile by less than a band: as many bands as the smallest step that
    /// needs at most `steps` (8 when smooth) gives, so a range never runs far past the values. Log: whole decades from the one at or below the 2nd percentile of
    /// the positive values to the one at or above their 98th, at most 6, with `steps` (when not
    /// 0) rounded to a whole number of bands per decade. Nothing positive: 0 … 1 (log 1 … 10).
    pub fn auto(values: &[f64], log: bool, steps: u32) -> ColourScale {
        let mut finite: Vec<f64> = (values.iter().copied())
            .filter(|v| v.is_finite() && (!log || *v > 0.0))
            .collect();
        finite.sort_by(f64::total_cmp);
        let Some((&min, &max)) = finite.first().zip(finite.last()) else {
            return ColourScale::empty(log, steps);
        };
        let at =
            |q: f64| finite[((q * finite.len() as f64).ceil() as usize).clamp(1, finite.len()) - 1];
        let (p_lo, p_hi) = (at(ROBUST), at(1.0 - ROBUST));
        let mut scale = match log {
            false if p_hi > 0.0 => linear(p_lo, p_hi, steps),
            false => return ColourScale::empty(log, steps),
            true => logarithmic(p_lo, p_hi, steps),
        };
        scale.open_low = min < scale.lo;
        scale.open_high = max > scale.hi;
        scale
    }

    /// The scale when no value can set one: 0 … 1, or 1 … 10 when logarithmic.
    fn empty(log: bool, steps: u32) -> ColourScale {
        let (lo, hi) = if log { (1.0, 10.0) } else { (0.0, 1.0) };
        ColourScale {
            lo,
            hi,
            log,
            steps,
            ticks: if log { 1 } else { 5 },
            open_low: false,
            open_high: false,
        }
    }

    /// The legend's labels of [`ColourScale::levels`]: empty where the level is not labelled,
    /// "≤ lo" / "≥ hi" at an end beyond which values lie.
    pub(crate) fn legend_labels(&self) -> Vec<String> {
        let levels = self.levels();
        let last = levels.len() - 1;
        (levels.iter().enumerate())
            .map(|(k, &v)| match (k, self.labelled(v)) {
                (_, false) => String::new(),
                (0, true) if self.open_low => format!("≤ {}", self.label(v)),
                (k, true) if k == last && self.open_high => format!("≥ {}", self.label(v)),
                _ => self.label(v),
            })
            .collect()
    }

    /// Whether the legend labels the level `v`: every level of a linear scale; on a
    /// logarithmic one only 1, 2 and 5 × 10^k (whole decades, and their halves and fifths).
    pub(crate) fn labelled(&self, v: f64) -> bool {
        if !self.log {
            return true;
        }
        let k = v.log10().floor();
        let m = v / 10f64.powf(k);
        [1.0, 2.0, 5.0, 10.0]
            .iter()
            .any(|r| (m - r).abs() < 1e-6 * r)
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
        Ok(ColourScale {
            lo,
            hi,
            log,
            steps,
            ticks: 8,
            open_low: false,
            open_high: false,
        })
    }

    /// Where `v` lies on the scale: 0 at lo, 1 at hi (in log10 when logarithmic), clamped; NaN
    /// and (log) values ≤ 0 give 0.
    pub(crate) fn position(&self, v: f64) -> f64 {
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
    pub(crate) fn value_at(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, 1.0);
        if self.log {
            10f64.powf(self.lo.log10() + t * (self.hi.log10() - self.lo.log10()))
        } else {
            self.lo + t * (self.hi - self.lo)
        }
    }

    /// The band of `v` (0 … bands − 1; the top edge belongs to the last band).
    pub(crate) fn band(&self, v: f64) -> u32 {
        let n = self.bands();
        ((self.position(v) * f64::from(n)).floor() as u32).min(n - 1)
    }

    /// The number of bands `levels` and `band` use: `steps`, or `ticks` when smooth.
    pub fn bands(&self) -> u32 {
        if self.steps == 0 {
            self.ticks.max(1)
        } else {
            self.steps
        }
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
    pub(crate) fn label(&self, v: f64) -> String {
        label(v)
    }
}

/// `v` with three significant digits as plain text (see [`ColourScale::label`]).
pub(crate) fn label(v: f64) -> String {
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
pub(crate) fn palette(t: f64) -> [u8; 3] {
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
pub(crate) fn round_up(v: f64) -> f64 {
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

/// The linear automatic scale over [p_lo, p_hi] (p_hi > 0; see [`ColourScale::auto`]).
fn linear(p_lo: f64, p_hi: f64, steps: u32) -> ColourScale {
    let most = if steps == 0 { 8 } else { steps };
    // A flat field still gets a range a fifth of its value wide.
    let spread = (p_hi - p_lo).max(0.2 * p_hi);
    let mut step = step125(spread / f64::from(most));
    let mut lo = (p_lo / step).floor() * step;
    // lo moved down a band at most: a step or two larger reaches p_hi.
    while lo + f64::from(most) * step < p_hi * (1.0 - 1e-12) {
        step = step125(step * 1.5);
        lo = (p_lo / step).floor() * step;
    }
    // As many bands as reach the 98th percentile (at most `most`).
    let bands = (((p_hi - lo) / step) * (1.0 - 1e-12))
        .ceil()
        .clamp(1.0, f64::from(most)) as u32;
    ColourScale {
        lo: clean(lo),
        hi: clean(lo + f64::from(bands) * step),
        log: false,
        steps: if steps == 0 { 0 } else { bands },
        ticks: bands,
        open_low: false,
        open_high: false,
    }
}

/// The logarithmic automatic scale over [p_lo, p_hi] (both > 0; see [`ColourScale::auto`]).
fn logarithmic(p_lo: f64, p_hi: f64, steps: u32) -> ColourScale {
    let top = decade_ceil(p_hi);
    let mut bottom = decade_floor(p_lo).max(top - MAX_DECADES);
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
        log: true,
        steps,
        ticks: decades,
        open_low: false,
        open_high: false,
    }
}

/// The smallest 1, 2 or 5 × 10^k ≥ v (v > 0), robust to rounding (1000 stays 1000).
fn step125(v: f64) -> f64 {
    let k = v.log10().floor() as i32;
    for e in [k - 1, k, k + 1] {
        for m in [1.0, 2.0, 5.0] {
            let c = if e >= 0 { m * pow10(e) } else { m / pow10(-e) };
            if c >= v * (1.0 - 1e-12) {
                return c;
            }
        }
    }
    pow10(k + 2)
}

/// `v` rounded to 12 significant digits: multiples of a decimal step print as they read.
fn clean(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let k = 11 - v.abs().log10().floor() as i32;
    if k >= 0 {
        (v * pow10(k)).round() / pow10(k)
    } else {
        (v / pow10(-k)).round() * pow10(-k)
    }
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

    /// Nearest-rank percentile q of `v` (finite values).
    fn percentile(v: &[f64], q: f64) -> f64 {
        let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1]
    }

    fn is_125(step: f64) -> bool {
        let m = step / 10f64.powf(step.log10().floor());
        [1.0, 2.0, 5.0, 10.0].iter().any(|r| (m - r).abs() < 1e-9)
    }

    #[test]
    fn auto_linear_spans_the_robust_range_in_1_2_5_steps() {
        // A room (120 … 870 lx) with a few hot spots (a luminaire's opening, 5·10⁴) and dark
        // corners; the same shifted, scaled and flat.
        let room: Vec<f64> = (0..1000)
            .map(|i| match i % 100 {
                0 => 5e4,
                1 => 0.5,
                k => 120.0 + 750.0 * (f64::from(k) / 99.0).powi(2),
            })
            .collect();
        let shifted: Vec<f64> = room.iter().map(|v| v * 1e-3 + 7.0).collect();
        let flat = vec![500.0; 50];
        for (name, values) in [("room", &room), ("shifted", &shifted), ("flat", &flat)] {
            for steps in [0, 5, 8, 12] {
                let s = ColourScale::auto(values, false, steps);
                let step = (s.hi - s.lo) / f64::from(s.bands());
                let (p2, p98) = (percentile(values, 0.02), percentile(values, 0.98));
                assert!(is_125(step), "{name} {steps}: step {step}");
                assert!(
                    s.lo <= p2 && p2 < s.lo + step,
                    "{name} {steps}: {s:?} p2 {p2}"
                );
                assert!(
                    p98 <= s.hi * (1.0 + 1e-12),
                    "{name} {steps}: {s:?} p98 {p98}"
                );
                // (a flat field: one band above its value)
                assert!(
                    s.hi - step < p98 || p98 == s.lo,
                    "{name} {steps}: {s:?} p98 {p98}"
                );
                assert!(s.bands() <= if steps == 0 { 8 } else { steps });
                {}
                for l in s.levels() {
                    let k = l / step;
                    assert!((k - k.round()).abs() < 1e-6, "{name} {steps}: level {l}");
                    assert_eq!(
                        label(l).parse::<f64>().unwrap(),
                        l,
                        "{name}: {l} prints as it is"
                    );
                }
            }
        }
        let s = ColourScale::auto(&room, false, 0);
        assert!(
            s.open_high && s.open_low,
            "the hot spots and dark corners lie beyond it"
        );
        assert_eq!((s.lo, s.hi), (100.0, 900.0));
        assert!(!ColourScale::auto(&flat, false, 0).open_high);
        assert_eq!(ColourScale::auto(&[], false, 8).hi, 1.0);
        assert_eq!(ColourScale::auto(&[-3.0, 0.0], false, 8).hi, 1.0);
    }

    #[test]
    fn log_scales_label_1_2_5_levels_only() {
        let s = ColourScale::fixed(1.0, 1e3, true, 9).unwrap();
        let labelled: Vec<bool> = s.levels().iter().map(|&v| s.labelled(v)).collect();
        // edges 1, 2.15, 4.64, 10, 21.5, …: the decades only
        assert_eq!(labelled.iter().filter(|&&b| b).count(), 4);
        assert!(s.labelled(200.0) && s.labelled(5e-3) && !s.labelled(300.0));
        assert!(
            ColourScale::fixed(0.0, 7.0, false, 7)
                .unwrap()
                .labelled(3.0)
        );
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
