//! A false-colour scale: values → colours (stub; filled in next).

/// A false-colour scale over [lo, hi], linear or logarithmic, smooth or in `steps` bands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColourScale {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    pub steps: u32,
}

impl ColourScale {
    /// A round range covering the values.
    pub fn auto(_values: &[f64], log: bool, steps: u32) -> ColourScale {
        ColourScale {
            lo: if log { 1.0 } else { 0.0 },
            hi: 1000.0,
            log,
            steps,
        }
    }

    /// Err(message) when lo >= hi, not finite, or log with lo <= 0.
    pub fn fixed(lo: f64, hi: f64, log: bool, steps: u32) -> Result<ColourScale, String> {
        Ok(ColourScale { lo, hi, log, steps })
    }

    /// Where `v` lies on the scale, 0..1, clamped.
    pub fn position(&self, v: f64) -> f64 {
        ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
    }

    /// The colour of `v`.
    pub fn colour(&self, v: f64) -> [u8; 3] {
        let p = (self.position(v) * 255.0) as u8;
        [p, p, p]
    }

    /// Band edges lo..=hi.
    pub fn levels(&self) -> Vec<f64> {
        let n = if self.steps == 0 { 8 } else { self.steps };
        (0..=n)
            .map(|i| self.lo + (self.hi - self.lo) * f64::from(i) / f64::from(n))
            .collect()
    }

    /// Short number text.
    pub fn label(&self, v: f64) -> String {
        format!("{v}")
    }
}
