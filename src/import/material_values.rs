//! Checks and conversions of photometric material values shared by the importers.
//!
//! Inputs: reflectances, luminances, fluxes and emissive RGB triples as the files give them.
//! Outputs: validated values for [`crate::scene::Material`], or a message (the caller adds the
//! file and the element). Invariants: an accepted reflectance has every channel finite and in
//! [0, 1); an accepted emission amount is finite and > 0 and its colour has luminance 1.

use crate::scene::{Emission, EmissionAmount, luma, normalise_color};
use glam::DVec3;

const CHANNELS: [&str; 3] = ["R", "G", "B"];

/// Check a diffuse reflectance; `hint` tells the user how to fix it at its source.
pub(crate) fn check_reflectance(rho: DVec3, hint: &str) -> Result<(), String> {
    for (i, &v) in rho.to_array().iter().enumerate() {
        let channel = CHANNELS[i];
        if v.is_nan() {
            return Err(format!("reflectance is NaN in channel {channel}; {hint}"));
        }
        if v < 0.0 {
            return Err(format!(
                "reflectance {v} < 0 in channel {channel} is impossible; {hint}"
            ));
        }
        if v >= 1.0 {
            return Err(format!(
                "reflectance {v} ≥ 1 in channel {channel}: a surface cannot reflect all (or \
                 more than all) of the light it receives, and the bake would not converge; \
                 {hint}"
            ));
        }
    }
    Ok(())
}

/// Check a luminance (cd/m²) or flux (lm) value; `what` names it in messages.
pub(crate) fn check_amount(value: f64, what: &str) -> Result<f64, String> {
    if !value.is_finite() || value < 0.0 {
        return Err(format!("{what} {value} must be a finite number ≥ 0"));
    }
    Ok(value)
}

/// Lambertian emission whose luminance (cd/m²) is the luminance-Y of the linear `rgb` triple
/// times `scale`, coloured like `rgb`. `None` when it emits nothing.
pub(crate) fn emission_from_rgb(rgb: DVec3, scale: f64) -> Result<Option<Emission>, String> {
    if rgb.to_array().iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(format!(
            "emissive colour [{}, {}, {}] must be finite and ≥ 0",
            rgb.x, rgb.y, rgb.z
        ));
    }
    check_amount(scale, "emissive strength")?;
    let luminance = luma(rgb) * scale;
    if luminance <= 0.0 {
        return Ok(None);
    }
    let color = normalise_color(rgb).ok_or("emissive colour has no luminance")?;
    Ok(Some(Emission {
        profile: None,
        amount: EmissionAmount::Luminance(luminance),
        color,
    }))
}

/// Normalise a relative emission/light colour to luminance 1, or explain why it cannot be.
pub(crate) fn unit_luminance_color(rgb: DVec3, what: &str) -> Result<DVec3, String> {
    normalise_color(rgb).ok_or_else(|| {
        format!(
            "{what} [{}, {}, {}] has no luminance (it must be ≥ 0 with a positive \
             0.2126 R + 0.7152 G + 0.0722 B)",
            rgb.x, rgb.y, rgb.z
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflectance_limits() {
        assert!(check_reflectance(DVec3::new(0.0, 0.5, 0.999), "").is_ok());
        assert!(check_reflectance(DVec3::new(0.2, 1.0, 0.2), "").is_err());
        assert!(check_reflectance(DVec3::new(-0.1, 0.5, 0.2), "").is_err());
        assert!(check_reflectance(DVec3::new(f64::NAN, 0.5, 0.2), "").is_err());
    }

    #[test]
    fn emission_luminance_is_luma() {
        let e = emission_from_rgb(DVec3::new(1.0, 0.0, 0.0), 10.0)
            .unwrap()
            .unwrap();
        let EmissionAmount::Luminance(l) = e.amount else {
            panic!("luminance expected")
        };
        assert!((l - 2.126).abs() < 1e-12);
        assert!((luma(e.color) - 1.0).abs() < 1e-12);
        assert!(emission_from_rgb(DVec3::ZERO, 5.0).unwrap().is_none());
    }
}
