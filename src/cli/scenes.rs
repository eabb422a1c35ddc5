//! `dalembert scenes [--json]`: the scenes as their files describe them.

use crate::protocol;
use crate::scene::Scene;
use crate::Error;
use serde_json::{json, Value};

/// `scenes [--json]`, or `scenes --scene-file PATH [--param k=v] [--json]`: the file's scene
/// as compiled (checked by `Model::new`, its derived basis written out).
pub fn run(file: Option<&str>, params: &[String], as_json: bool) -> Result<String, Error> {
    let Some(path) = file else {
        if !params.is_empty() {
            return Err(Error::input("--param goes with --scene-file"));
        }
        return Ok(render(protocol::scenes(), as_json));
    };
    let params: Vec<(String, f64)> = params
        .iter()
        .map(|p| protocol::parse_param(p))
        .collect::<Result<_, _>>()?;
    let file = crate::scene::SceneFile::read(std::path::Path::new(path))?.with_params(&params)?;
    let model = crate::Model::new(&file)?;
    let v = json!({ "scenes": [protocol::description(&model.scene.description())] });
    Ok(render(v, as_json))
}

/// One JSON object, or a plain-text listing of the same content.
pub fn render(v: Value, as_json: bool) -> String {
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
