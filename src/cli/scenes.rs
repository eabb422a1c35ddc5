//! `dalembert scenes [--json]`: the scenes as their files describe them.

use dalembert::protocol;
use serde_json::Value;

/// One JSON object, or a plain-text listing of the same content.
pub fn render(as_json: bool) -> String {
    let v = protocol::scenes();
    if as_json {
        return v.to_string();
    }
    let strs = |x: &Value| -> Vec<String> {
        x.as_array()
            .into_iter()
            .flatten()
            .filter_map(|s| s.as_str().map(str::to_string))
            .collect()
    };
    let mut out = String::new();
    for s in v["scenes"].as_array().into_iter().flatten() {
        let text = |k: &str| s[k].as_str().unwrap_or_default().to_string();
        out.push_str(&format!("{}: {}\n", text("name"), text("summary")));
        out.push_str(&format!(
            "  q = ({}), u = ({}), n = {}, k = {}\n",
            strs(&s["coordinates"]).join(", "),
            strs(&s["velocities"]).join(", "),
            s["n"],
            s["k"]
        ));
        for p in s["parameters"].as_array().into_iter().flatten() {
            out.push_str(&format!(
                "  --param {}={} ({})\n",
                p["name"].as_str().unwrap_or_default(),
                p["default"],
                p["description"].as_str().unwrap_or_default()
            ));
        }
        out.push_str(&format!("  {}\n", text("lagrangian")));
        for m in strs(&s["mu"]) {
            out.push_str(&format!("  {m}\n"));
        }
        for e in strs(&s["basis"]) {
            out.push_str(&format!("  {e}\n"));
        }
        for i in strs(&s["invariants"]) {
            out.push_str(&format!("  invariant: {i}\n"));
        }
        out.push('\n');
    }
    out.trim_end().to_string()
}
