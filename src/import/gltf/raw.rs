//! Reading numbers and verbatim values from the raw glTF JSON.
//!
//! The `gltf` crate stores numbers as `f32`; the scene model is `f64`, and values the output
//! writes back (factors, transforms, light parameters) should survive unchanged, so they are read
//! here from the `serde_json::Value` at full precision. Inputs: the raw JSON and a JSON pointer.
//! Outputs: `None` when the member is absent or not of the expected shape (the typed document has
//! already been validated, so shapes only differ for absent members).

use serde_json::Value;

/// A number at `pointer`.
pub(super) fn number(raw: &Value, pointer: &str) -> Option<f64> {
    raw.pointer(pointer)?.as_f64()
}

/// A number at `pointer`, or `default` when absent.
pub(super) fn number_or(raw: &Value, pointer: &str, default: f64) -> f64 {
    number(raw, pointer).unwrap_or(default)
}

/// An array of exactly `N` numbers at `pointer`.
pub(super) fn numbers<const N: usize>(raw: &Value, pointer: &str) -> Option<[f64; N]> {
    let array = raw.pointer(pointer)?.as_array()?;
    if array.len() != N {
        return None;
    }
    let mut out = [0.0; N];
    for (o, v) in out.iter_mut().zip(array) {
        *o = v.as_f64()?;
    }
    Some(out)
}

/// The value at `pointer`, cloned (for data kept verbatim, such as `extras`).
pub(super) fn cloned(raw: &Value, pointer: &str) -> Option<Value> {
    raw.pointer(pointer).cloned()
}
