//! Text renderings for people (the JSON forms live in `crate::protocol`).

use serde_json::Value;

/// Plain-text rendering of an answer object; an array of objects (the stops of `flow
/// --times`) one object a block, indented.
pub fn human(v: &Value) -> String {
    let mut out = String::new();
    if let Value::Object(m) = v {
        for (k, val) in m {
            match val {
                Value::Array(a) if !a.is_empty() && a.iter().all(Value::is_object) => {
                    out.push_str(&format!("{k:>8}:\n"));
                    for o in a {
                        for line in human(o).lines() {
                            out.push_str(&format!("    {line}\n"));
                        }
                        out.push('\n');
                    }
                }
                _ => out.push_str(&format!("{k:>8}: {val}\n")),
            }
        }
    }
    out.trim_end().to_string()
}
