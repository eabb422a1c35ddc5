//! Text renderings for people (the JSON forms live in `dalembert::protocol`).

use serde_json::Value;

/// Plain-text rendering of an answer object.
pub fn human(v: &Value) -> String {
    let mut out = String::new();
    if let Value::Object(m) = v {
        for (k, val) in m {
            out.push_str(&format!("{k:>8}: {val}\n"));
        }
    }
    out.trim_end().to_string()
}
