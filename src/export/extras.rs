//! Attaching luxbake's own data to an element's `extras` without losing the input's.
//!
//! Input: the element's extras as imported (any JSON, or none) and luxbake's value.
//! Output: an object holding the input's keys (in their order) plus `"luxbake"`. Invariants: an
//! input object keeps all its keys, except that a stale `"luxbake"` key (from an earlier bake) is
//! replaced; a non-object input value is kept under `"input"`.

use serde_json::{Map, Value};

/// `extras` with `luxbake` set as its `"luxbake"` key.
pub(crate) fn with_luxbake(extras: Option<&Value>, luxbake: Value) -> Value {
    let mut map = match extras {
        Some(Value::Object(m)) => m.clone(),
        None | Some(Value::Null) => Map::new(),
        Some(other) => Map::from_iter([("input".to_string(), other.clone())]),
    };
    map.insert("luxbake".into(), luxbake);
    Value::Object(map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn merges_or_wraps() {
        assert_eq!(
            with_luxbake(Some(&json!({"a": 1, "luxbake": 0})), json!(2)),
            json!({"a": 1, "luxbake": 2})
        );
        assert_eq!(
            with_luxbake(Some(&json!([1])), json!(2)),
            json!({"input": [1], "luxbake": 2})
        );
        assert_eq!(with_luxbake(None, json!(2)), json!({"luxbake": 2}));
    }
}
