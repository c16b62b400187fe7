//! The `LUXBAKE_material` material extension (ours; schema in
//! `schemas/LUXBAKE_material.schema.json`).
//!
//! Input: the extension's JSON object, e.g.
//! `{"reflectance": 0.7, "emission": {"luminance": 250, "color": [1, 0.9, 0.8], "profile": 0}}`.
//! Output: [`LuxbakeMaterial`] — the photometric values it sets; omitted members are `None` (the
//! caller then derives them from the core material). `emission.profile` is returned as given (an
//! index into `LUXBAKE_luminaire.profiles`); the caller checks it and maps it to a scene profile.
//! Invariants: unknown members, a reflectance that is neither a number nor three numbers, an
//! emission with not exactly one of `luminance` (cd/m²) / `luminousFlux` (lm), a negative or
//! non-finite amount, a colour without luminance and a profile that is not an integer ≥ 0 are
//! errors. The colour is normalised to
//! luminance 1. The reflectance *range* ([0, 1)) is checked by the caller, like every reflectance.

use crate::import::material_values::{check_amount, unit_luminance_color};
use crate::scene::{Emission, EmissionAmount};
use glam::DVec3;
use serde_json::{Map, Value};

pub(super) struct LuxbakeMaterial {
    pub reflectance: Option<DVec3>,
    /// `Some(None)`: the extension says the material emits nothing (amount 0).
    pub emission: Option<Option<Emission>>,
    /// `emission.profile`: an index into `LUXBAKE_luminaire.profiles`, unchecked.
    pub emission_profile: Option<usize>,
}

pub(super) fn parse(value: &Value) -> Result<LuxbakeMaterial, String> {
    let object = value
        .as_object()
        .ok_or("the extension must be a JSON object")?;
    only_keys(object, &["reflectance", "emission"], "the extension")?;
    let reflectance = object.get("reflectance").map(reflectance).transpose()?;
    let emission = object.get("emission").map(emission).transpose()?;
    let emission_profile = match object.get("emission").and_then(|e| e.get("profile")) {
        None => None,
        Some(p) => Some(index(p, "emission.profile")?),
    };
    Ok(LuxbakeMaterial {
        reflectance,
        emission,
        emission_profile,
    })
}

/// An index into an array: an integer ≥ 0.
pub(super) fn index(v: &Value, what: &str) -> Result<usize, String> {
    v.as_u64()
        .and_then(|i| usize::try_from(i).ok())
        .ok_or_else(|| format!("{what} must be an index (an integer ≥ 0)"))
}

pub(super) fn only_keys(
    object: &Map<String, Value>,
    allowed: &[&str],
    what: &str,
) -> Result<(), String> {
    match object.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(format!(
            "{what} has an unknown member '{k}' (allowed: {})",
            allowed.join(", ")
        )),
        None => Ok(()),
    }
}

pub(super) fn number(v: &Value, what: &str) -> Result<f64, String> {
    v.as_f64().ok_or_else(|| format!("{what} must be a number"))
}

pub(super) fn triple(v: &Value, what: &str) -> Result<DVec3, String> {
    match v.as_array().map(Vec::as_slice) {
        Some([r, g, b]) => Ok(DVec3::new(
            number(r, what)?,
            number(g, what)?,
            number(b, what)?,
        )),
        _ => Err(format!("{what} must be an array of 3 numbers")),
    }
}

fn reflectance(v: &Value) -> Result<DVec3, String> {
    match v {
        Value::Number(_) => Ok(DVec3::splat(number(v, "reflectance")?)),
        Value::Array(_) => triple(v, "reflectance"),
        _ => Err("reflectance must be a number or an array of 3 numbers (linear RGB)".into()),
    }
}

fn emission(v: &Value) -> Result<Option<Emission>, String> {
    let object = v.as_object().ok_or("emission must be a JSON object")?;
    only_keys(
        object,
        &["luminance", "luminousFlux", "color", "profile"],
        "emission",
    )?;
    let amount = match (object.get("luminance"), object.get("luminousFlux")) {
        (Some(l), None) => EmissionAmount::Luminance(check_amount(
            number(l, "emission.luminance")?,
            "emission.luminance (cd/m²)",
        )?),
        (None, Some(f)) => EmissionAmount::LuminousFlux(check_amount(
            number(f, "emission.luminousFlux")?,
            "emission.luminousFlux (lm)",
        )?),
        _ => {
            return Err(
                "emission must give exactly one of luminance (cd/m²) and luminousFlux (lm)".into(),
            );
        }
    };
    let color = match object.get("color") {
        Some(c) => unit_luminance_color(triple(c, "emission.color")?, "emission.color")?,
        None => DVec3::ONE,
    };
    let (EmissionAmount::Luminance(value) | EmissionAmount::LuminousFlux(value)) = amount;
    Ok((value > 0.0).then_some(Emission {
        amount,
        color,
        profile: None,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn parses_all_forms() {
        let m = parse(&json!({"reflectance": 0.7})).unwrap();
        assert_eq!(m.reflectance, Some(DVec3::splat(0.7)));
        assert!(m.emission.is_none());
        let m = parse(&json!({"reflectance": [0.1, 0.2, 0.3],
            "emission": {"luminousFlux": 1000, "color": [2, 2, 2]}}))
        .unwrap();
        assert_eq!(m.reflectance, Some(DVec3::new(0.1, 0.2, 0.3)));
        let e = m.emission.unwrap().unwrap();
        assert_eq!(e.amount, EmissionAmount::LuminousFlux(1000.0));
        assert!((e.color - DVec3::ONE).abs().max_element() < 1e-12);
        assert_eq!(m.emission_profile, None);
        let m = parse(&json!({"emission": {"luminance": 10, "profile": 2}})).unwrap();
        assert_eq!(m.emission_profile, Some(2));
        assert_eq!(m.emission.unwrap().unwrap().profile, None);
    }

    #[test]
    fn rejects_bad_forms() {
        for bad in [
            json!({"reflectance": "high"}),
            json!({"reflectance": [0.1, 0.2]}),
            json!({"colour": 1}),
            json!({"emission": {"luminance": 1, "luminousFlux": 2}}),
            json!({"emission": {}}),
            json!({"emission": {"luminance": -1}}),
            json!({"emission": {"luminance": 1, "color": [0, 0, 0]}}),
            json!({"emission": {"luminance": 1, "profile": -1}}),
            json!({"emission": {"luminance": 1, "profile": 0.5}}),
        ] {
            assert!(parse(&bad).is_err(), "{bad}");
        }
    }
}
