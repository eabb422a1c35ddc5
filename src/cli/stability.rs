//! `dalembert stability`: the table of `crate::report::stability` as Markdown or JSON.

use crate::report::stability::{Certified, Row, Solve};
use serde_json::{json, Value};

use super::render::number;

fn vector(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| number(*x)).collect();
    items.join(", ")
}

fn scene(r: &Row) -> String {
    let params: Vec<String> = r
        .case
        .params
        .iter()
        .map(|(k, v)| format!("{k}={}", number(*v)))
        .collect();
    if params.is_empty() {
        r.case.scene.clone()
    } else {
        format!("{} {}", r.case.scene, params.join(" "))
    }
}

fn certified_text(c: &Certified) -> String {
    match c {
        Certified::Answered { width, relative } => {
            format!("answered, width {width:.1e} (relative {relative:.1e})")
        }
        Certified::Refused { code, reason } => format!("exit {code}: {reason}"),
    }
}

fn solve_text(s: &Solve) -> String {
    match s {
        Solve::Converged { iterations } => {
            let its: Vec<String> = iterations.iter().map(|i| i.to_string()).collect();
            format!("converged, {} it.", its.join(" + "))
        }
        Solve::Failed { step, failure } => format!("failed at step {step}: {failure}"),
    }
}

/// The Markdown table.
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::from(
        "| scene | extreme | h | q0 | q1 | certified step | DLA Newton | MLA Newton | time |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} s |\n",
            scene(r),
            r.case.family,
            number(r.case.h),
            vector(&r.case.q0),
            vector(&r.case.q1),
            certified_text(&r.certified).replace('|', "/"),
            solve_text(&r.dla),
            solve_text(&r.mla),
            r.seconds
        ));
    }
    out.trim_end().to_string()
}

fn solve_json(s: &Solve) -> Value {
    match s {
        Solve::Converged { iterations } => json!({"converged": true, "iterations": iterations}),
        Solve::Failed { step, failure } => {
            json!({"converged": false, "step": step, "failure": failure})
        }
    }
}

/// One JSON object `{"rows": [...]}`.
pub fn json(rows: &[Row]) -> String {
    let rows: Vec<Value> = rows
        .iter()
        .map(|r| {
            let params: serde_json::Map<String, Value> = r
                .case
                .params
                .iter()
                .map(|(k, v)| (k.clone(), json!(v)))
                .collect();
            let certified = match &r.certified {
                Certified::Answered { width, relative } => {
                    json!({"answered": true, "width": width, "relative_width": relative})
                }
                Certified::Refused { code, reason } => {
                    json!({"answered": false, "code": code, "reason": reason})
                }
            };
            json!({
                "scene": r.case.scene,
                "params": params,
                "extreme": r.case.family,
                "h": r.case.h,
                "q0": r.case.q0,
                "q1": r.case.q1,
                "certified": certified,
                "dla": solve_json(&r.dla),
                "mla": solve_json(&r.mla),
                "seconds": r.seconds,
            })
        })
        .collect();
    json!({ "rows": rows }).to_string()
}

/// Run the table (with a progress bar on a terminal) and render it.
pub fn run(as_json: bool) -> Result<String, crate::Error> {
    let bar = super::progress::SharedBar::new();
    let rows = crate::report::stability::table(&bar.progress())?;
    bar.clear();
    Ok(if as_json {
        json(&rows)
    } else {
        markdown(&rows)
    })
}
