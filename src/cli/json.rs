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

/// An `integrate` answer as CSV: `k, q..., p..., energy`.
pub fn trajectory_csv(v: &Value) -> String {
    let rows = |k: &str| v[k].as_array().cloned().unwrap_or_default();
    let (q, p, e) = (rows("q"), rows("p"), rows("energy"));
    let width = |r: &[Value]| r.first().and_then(|x| x.as_array()).map_or(0, |a| a.len());
    let mut out = String::from("k");
    (0..width(&q)).for_each(|i| out.push_str(&format!(",q{i}")));
    (0..width(&p)).for_each(|a| out.push_str(&format!(",p{a}")));
    out.push_str(",energy\n");
    for (k, qk) in q.iter().enumerate() {
        out.push_str(&k.to_string());
        let cells = qk
            .as_array()
            .into_iter()
            .flatten()
            .chain(p.get(k).and_then(|x| x.as_array()).into_iter().flatten())
            .chain(e.get(k));
        for x in cells {
            out.push(',');
            out.push_str(&x.to_string());
        }
        out.push('\n');
    }
    out.trim_end().to_string()
}
