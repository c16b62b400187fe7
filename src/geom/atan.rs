//! A faster `atan2` for the hot paths: the luminaires' (C, γ) lookups and the edge angles of
//! Lambert's formula call it millions of times per bake.
//!
//! Input: finite `y`, `x` (infinities fall back to the standard library). Output: the angle of
//! (x, y) in (−π, π], within 10⁻¹⁵ rad of `f64::atan2` (tested), signed zeros and the axes as
//! the standard library has them, without libm's branches for correct rounding: the ratio
//! min/max is reduced to |t| ≤ 2 − √3 by atan(a) = π/6 + atan((a√3 − 1)/(a + √3)), where the
//! alternating series to t²³ is within 2·10⁻¹⁶.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_6, PI};

/// 2 − √3 = tan(π/12).
const TAN_PI_12: f64 = 0.267_949_192_431_122_7;
const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// atan(t)/t = Σₖ (−1)ᵏ t²ᵏ/(2k + 1), k = 0..=11, highest first (Horner).
const SERIES: [f64; 12] = [
    -1.0 / 23.0,
    1.0 / 21.0,
    -1.0 / 19.0,
    1.0 / 17.0,
    -1.0 / 15.0,
    1.0 / 13.0,
    -1.0 / 11.0,
    1.0 / 9.0,
    -1.0 / 7.0,
    1.0 / 5.0,
    -1.0 / 3.0,
    1.0,
];

/// The angle (rad) of the point (x, y), as `y.atan2(x)`.
#[inline]
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den, steep) = if ay > ax {
        (ax, ay, true)
    } else {
        (ay, ax, false)
    };
    if den == 0.0 || den.is_infinite() {
        return y.atan2(x);
    }
    let a = num / den;
    let (t, base) = if a > TAN_PI_12 {
        ((a * SQRT_3 - 1.0) / (a + SQRT_3), FRAC_PI_6)
    } else {
        (a, 0.0)
    };
    let t2 = t * t;
    let series = SERIES.iter().skip(1).fold(SERIES[0], |p, c| p * t2 + c);
    let mut r = base + t * series;
    if steep {
        r = FRAC_PI_2 - r;
    }
    if x.is_sign_negative() {
        r = PI - r;
    }
    r.copysign(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_standard_library() {
        let mut worst = 0.0f64;
        // Every direction around the circle at several radii, and near the axes and diagonals.
        for i in 0..200_000 {
            let phi = (i as f64 / 200_000.0) * 2.0 * PI - PI;
            for r in [1e-300, 1e-8, 1.0, 3.7e5, 1e300] {
                let (y, x) = (r * phi.sin(), r * phi.cos());
                worst = worst.max((atan2(y, x) - y.atan2(x)).abs());
            }
        }
        for e in [1e-16, 1e-9, 1e-3] {
            for (y, x) in [
                (e, 1.0),
                (1.0, e),
                (-e, -1.0),
                (1.0 + e, 1.0),
                (1.0, -1.0 - e),
            ] {
                worst = worst.max((atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 1e-15, "worst {worst:e}");
    }

    #[test]
    fn small_angles_keep_relative_precision() {
        // Lambert's formula takes atan2(|a × b|, a · b) of nearly parallel edges.
        for y in [1e-300, 1e-200, 1e-12, 1e-6, 1e-2] {
            assert!((atan2(y, 1.0) / y.atan2(1.0) - 1.0).abs() < 1e-15, "{y}");
        }
    }

    #[test]
    fn signed_zeros_axes_and_infinities_as_the_standard_library() {
        for (y, x) in [
            (0.0, 0.0),
            (-0.0, 0.0),
            (0.0, -0.0),
            (-0.0, -0.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (0.0, 1.0),
            (1.0, 1.0),
            (f64::INFINITY, 1.0),
            (1.0, f64::NEG_INFINITY),
        ] {
            let (a, b) = (atan2(y, x), y.atan2(x));
            assert!(
                (a - b).abs() < 1e-15 && a.is_sign_negative() == b.is_sign_negative(),
                "atan2({y}, {x}) = {a}, std {b}"
            );
        }
        assert!(atan2(f64::NAN, 1.0).is_nan() && atan2(1.0, f64::NAN).is_nan());
    }
}
