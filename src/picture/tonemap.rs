//! Tone mapping of a luminance image for the adapted eye: the histogram adjustment of Ward
//! Larson, Rushmeier & Piatko 1997 ("A Visibility Matching Tone Reproduction Operator for High
//! Dynamic Range Scenes", IEEE TVCG 3(4)) with its human contrast-sensitivity ceiling — the core
//! of RADIANCE `pcond -h`. Of the paper's other parts (veiling glare, acuity loss, scotopic
//! colour loss) none is done here: colours are kept as computed.
//!
//! Input: linear RGB in cd/m² per pixel (row 0 at the top; R = G = B = L for a grey of
//! luminance L), the view's vertical field of view. Steps:
//! 1. foveal samples: the mean luminance Y (Rec. 709 weights) of square blocks about 1° wide
//!    (⌊h / vfov⌉ pixels, at least 1);
//! 2. a histogram of log10 Lw over the samples of at least 10⁻⁶ cd/m² (100 bins from the
//!    smallest to the largest sample);
//! 3. the mapping log10 Ld = log10 Ldmin + log10(Ldmax / Ldmin) · P(log10 Lw), P the
//!    cumulative of the histogram (linear within a bin), Ld in [Ldmin, Ldmax] = [1, 100] cd/m²;
//! 4. the ceiling: no bin may make the display slope dLd/dLw exceed ΔLt(Ld)/ΔLt(Lw) (ΔLt the
//!    threshold-versus-intensity function of the paper, after Ferwerda et al. 1996), i.e.
//!    f(b) ≤ ΔLt(Ld)/ΔLt(Lw) · (Lw/Ld) · T·Δb / log10(Ldmax/Ldmin); bins above it are cut to it
//!    and the mapping recomputed, until the counts cut in a pass are at most 2.5 % of the total
//!    T (the paper's rule), so the inequality holds within that tolerance;
//! 5. linear instead (Ld = Lw · ΔLt(Lda)/ΔLt(Lwa), Lda = √(Ldmin·Ldmax), Lwa the adaptation:
//!    the visibility-matching scale factor) when the samples' range already fits the display's
//!    (log10(max/min) ≤ 2) or when the cutting leaves less than 2.5 % of the samples;
//! 6. each pixel's RGB scaled by Ld/Lw (its chromaticity kept), divided by Ldmax, clamped to
//!    [0, 1] per component, sRGB-encoded. Pixels with Lw ≤ 0 (no hit) or not finite are black.
//!
//! Output: the 8-bit image and the adaptation luminance (10^(mean log10 Lw) of the histogram's
//! samples; 0 when there are none). Invariants: deterministic (no threads, fixed order); the
//! mapping is monotone (brighter world, never darker display); a uniform image is one grey.

use super::{Rgb8Image, srgb8};

/// Display luminance range (cd/m²).
pub const LD_MIN: f64 = 1.0;
pub const LD_MAX: f64 = 100.0;
/// Histogram bins over the foveal samples' log10 range.
pub const BINS: usize = 100;
/// The paper's tolerance: a pass cutting at most this share of the counts ends the iteration;
/// fewer counts than this share of the samples left means the scene needs no compression.
pub const TOLERANCE: f64 = 0.025;
/// Foveal samples darker than this (cd/m²) stay out of the histogram (below absolute threshold).
pub const L_FLOOR: f64 = 1e-6;

/// A tone-mapped image and the adaptation luminance used.
#[derive(Debug, Clone)]
pub struct ToneMapped {
    pub image: Rgb8Image,
    /// Mean log of the foveal samples, as a luminance (cd/m²).
    pub adaptation_cd_m2: f64,
}

/// How world luminance becomes display luminance.
#[derive(Debug, Clone, PartialEq)]
pub enum ToneCurve {
    /// Ld = scale · Lw (clamped to Ldmax on output).
    Linear { scale: f64 },
    /// The adjusted histogram: `counts` over [b_min, b_max] (log10 cd/m²), after the ceiling;
    /// `cumulative[i]`: the share of the counts below bin i (`BINS + 1` values, 0 … 1).
    Histogram {
        b_min: f64,
        b_max: f64,
        counts: Vec<f64>,
        cumulative: Vec<f64>,
    },
}

/// Tone map linear RGB luminances (cd/m²), row 0 top; `vfov_deg` sets the foveal sample size.
pub fn histogram_adjustment(rgb: &[[f32; 3]], w: u32, h: u32, vfov_deg: f64) -> ToneMapped {
    let samples = foveal(rgb, w, h, vfov_deg);
    let (curve, adaptation) = tone_curve(&samples);
    let mut image = Rgb8Image::new(w, h, [0; 3]);
    for (out, c) in image.pixels.iter_mut().zip(rgb) {
        let lw = luminance(*c);
        if lw > 0.0 && lw.is_finite() {
            let k = curve.display(lw) / lw / LD_MAX;
            *out = c.map(|v| srgb8(f64::from(v) * k));
        }
    }
    ToneMapped {
        image,
        adaptation_cd_m2: adaptation,
    }
}

/// Luminance Y of linear RGB (Rec. 709 / sRGB primaries); negative components count as 0.
pub(crate) fn luminance(c: [f32; 3]) -> f64 {
    let [r, g, b] = c.map(|v| f64::from(v).max(0.0));
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

/// The foveal samples: mean luminance over square blocks of ⌊h / vfov⌉ pixels (about 1° of
/// the view; partial blocks at the right and bottom edges average the pixels they have),
/// row-major. Pixels that are not finite count as 0.
pub fn foveal(rgb: &[[f32; 3]], w: u32, h: u32, vfov_deg: f64) -> Vec<f64> {
    let (w, h) = (w as usize, h as usize);
    if w == 0 || h == 0 || rgb.len() < w * h {
        return Vec::new();
    }
    let per_degree = h as f64 / vfov_deg;
    let block = if per_degree.is_finite() && per_degree > 1.0 {
        (per_degree.round() as usize).min(h.max(w))
    } else {
        1
    };
    let (bw, bh) = (w.div_ceil(block), h.div_ceil(block));
    let mut sum = vec![0.0; bw * bh];
    let mut count = vec![0u32; bw * bh];
    for y in 0..h {
        for x in 0..w {
            let l = luminance(rgb[y * w + x]);
            let k = (y / block) * bw + x / block;
            sum[k] += if l.is_finite() { l } else { 0.0 };
            count[k] += 1;
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(s, &n)| s / f64::from(n))
        .collect()
}

/// The human threshold of luminance difference ΔLt (cd/m²) at adaptation `la` (cd/m²): the
/// paper's threshold-versus-intensity function (rods below about 0.04 cd/m², cones above).
pub fn tvi(la: f64) -> f64 {
    let l = la.max(1e-12).log10();
    let log_dl = if l < -3.94 {
        -2.86
    } else if l < -1.44 {
        (0.405 * l + 1.6).powf(2.18) - 2.86
    } else if l < -0.0184 {
        l - 0.395
    } else if l < 1.9 {
        (0.249 * l + 0.65).powf(2.7) - 0.72
    } else {
        l - 1.255
    };
    10f64.powf(log_dl)
}

/// The tone curve of a set of foveal samples and their adaptation luminance (10^(mean log10)).
pub fn tone_curve(samples: &[f64]) -> (ToneCurve, f64) {
    let logs: Vec<f64> = samples
        .iter()
        .filter(|&&l| l >= L_FLOOR && l.is_finite())
        .map(|l| l.log10())
        .collect();
    if logs.is_empty() {
        return (ToneCurve::Linear { scale: 0.0 }, 0.0);
    }
    let b_avg = logs.iter().sum::<f64>() / logs.len() as f64;
    let adaptation = 10f64.powf(b_avg);
    let linear = ToneCurve::Linear {
        scale: tvi((LD_MIN * LD_MAX).sqrt()) / tvi(adaptation),
    };
    let b_min = logs.iter().copied().fold(f64::INFINITY, f64::min);
    let b_max = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // The paper's rule: a scene whose range fits the display's is mapped linearly.
    if b_max - b_min <= (LD_MAX / LD_MIN).log10() {
        return (linear, adaptation);
    }
    let db = (b_max - b_min) / BINS as f64;
    let mut counts = vec![0.0; BINS];
    for b in &logs {
        counts[(((b - b_min) / db) as usize).min(BINS - 1)] += 1.0;
    }
    let samples_total = logs.len() as f64;
    let display_range = (LD_MAX / LD_MIN).log10();
    loop {
        let total: f64 = counts.iter().sum();
        if total <= TOLERANCE * samples_total {
            return (linear, adaptation); // no compression needed
        }
        let curve = ToneCurve::histogram(b_min, b_max, counts.clone());
        let mut trimmed = 0.0;
        for (i, count) in counts.iter_mut().enumerate() {
            let lw = 10f64.powf(b_min + (i as f64 + 0.5) * db);
            let ld = curve.display(lw);
            let ceiling = tvi(ld) / tvi(lw) * (lw / ld) * total * db / display_range;
            if *count > ceiling {
                trimmed += *count - ceiling;
                *count = ceiling;
            }
        }
        if trimmed <= TOLERANCE * total {
            break;
        }
    }
    (ToneCurve::histogram(b_min, b_max, counts), adaptation)
}

impl ToneCurve {
    /// The histogram curve of `counts` over [b_min, b_max] (log10 cd/m²).
    pub(crate) fn histogram(b_min: f64, b_max: f64, counts: Vec<f64>) -> ToneCurve {
        let total: f64 = counts.iter().sum();
        let mut cumulative = Vec::with_capacity(counts.len() + 1);
        let mut below = 0.0;
        cumulative.push(0.0);
        for c in &counts {
            below += c;
            cumulative.push(if total > 0.0 { below / total } else { 0.0 });
        }
        ToneCurve::Histogram {
            b_min,
            b_max,
            counts,
            cumulative,
        }
    }

    /// Display luminance Ld (cd/m²) for world luminance `lw` > 0: in [Ldmin, Ldmax] for the
    /// histogram (clamped at its ends), scale · Lw for the linear curve.
    pub fn display(&self, lw: f64) -> f64 {
        match self {
            ToneCurve::Linear { scale } => scale * lw,
            ToneCurve::Histogram {
                b_min,
                b_max,
                cumulative,
                ..
            } => {
                let p = share_below(cumulative, (lw.log10() - b_min) / (b_max - b_min));
                10f64.powf(LD_MIN.log10() + p * (LD_MAX / LD_MIN).log10())
            }
        }
    }
}

/// The share of the counts below position x ∈ [0, 1] of the histogram's range, from the
/// `cumulative` shares at the bin edges (clamped; linear within a bin).
fn share_below(cumulative: &[f64], x: f64) -> f64 {
    let bins = cumulative.len() - 1;
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return cumulative[bins];
    }
    let pos = x * bins as f64;
    let i = (pos as usize).min(bins - 1);
    cumulative[i] + (pos - i as f64) * (cumulative[i + 1] - cumulative[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tvi_matches_the_paper_branches() {
        // log10 ΔLt at the branch points (continuous to about 0.01 in log10)
        let cases = [
            (1e-5, -2.86),
            (10f64.powf(-2.0), (0.405f64 * -2.0 + 1.6).powf(2.18) - 2.86),
            (0.1, -1.395),
            (10.0, (0.899f64).powf(2.7) - 0.72),
            (1000.0, 3.0 - 1.255),
        ];
        for (la, log_dl) in cases {
            assert!((tvi(la).log10() - log_dl).abs() < 1e-12, "{la}");
        }
        for x in [-3.94f64, -1.44, -0.0184, 1.9] {
            let (a, b) = (tvi(10f64.powf(x - 1e-9)), tvi(10f64.powf(x + 1e-9)));
            assert!((a.log10() - b.log10()).abs() < 0.02, "{x}: {a} {b}");
        }
    }

    #[test]
    fn foveal_blocks_average() {
        // 4 × 2 image, vfov 1° → 2-pixel blocks: two samples
        let rgb = [
            [1.0f32; 3],
            [3.0; 3],
            [5.0; 3],
            [7.0; 3],
            [1.0; 3],
            [3.0; 3],
            [5.0; 3],
            [7.0; 3],
        ];
        let f = foveal(&rgb, 4, 2, 1.0);
        assert_eq!(f.len(), 2);
        assert!((f[0] - 2.0).abs() < 1e-12 && (f[1] - 6.0).abs() < 1e-12);
    }
}
