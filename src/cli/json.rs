//! Numbers in and out (contract.md, "Numbers").

use dalembert::exact::{ExactStep, Retraction};
use dalembert::integrator::Trajectory;
use dalembert::{Error, FlowStats};
use inari::Interval;
use serde_json::{json, Value};

/// A decimal literal read as the nearest f64; non-finite values are input errors.
pub fn parse_num(name: &str, s: &str) -> Result<f64, Error> {
    let t = s.trim();
    let ok_chars = !t.is_empty()
        && t.chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'));
    let x: f64 = if ok_chars { t.parse().ok() } else { None }
        .ok_or_else(|| Error::input(format!("--{name}: `{s}` is not a decimal number")))?;
    if !x.is_finite() {
        return Err(Error::input(format!(
            "--{name}: `{s}` is not a finite number"
        )));
    }
    Ok(x)
}

/// A comma-separated vector without spaces.
pub fn parse_vec(name: &str, s: &str) -> Result<Vec<f64>, Error> {
    s.split(',').map(|x| parse_num(name, x)).collect()
}

/// `name=value`.
pub fn parse_param(s: &str) -> Result<(String, f64), Error> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| Error::input(format!("--param: expected name=value, got `{s}`")))?;
    Ok((k.to_string(), parse_num("param", v)?))
}

/// The number of steps of `integrate`: an integer in 0..=10^7.
pub fn parse_steps(s: &str) -> Result<usize, Error> {
    match s.parse::<usize>() {
        Ok(n) if n <= 10_000_000 => Ok(n),
        _ => Err(Error::input(format!(
            "--steps: expected an integer in 0..=10000000, got `{s}`"
        ))),
    }
}

pub fn parse_order(s: &str) -> Result<usize, Error> {
    match s.parse::<usize>() {
        Ok(p) if (2..=60).contains(&p) => Ok(p),
        _ => Err(Error::input(format!(
            "--order: expected an integer in 2..=60, got `{s}`"
        ))),
    }
}

/// `[lo, hi]` pairs; f64 printed in shortest round-trip form by serde_json.
pub fn intervals(x: &[Interval]) -> Value {
    Value::Array(x.iter().map(|v| json!([v.inf(), v.sup()])).collect())
}

pub fn stats(s: &FlowStats) -> Value {
    json!({"order": s.order, "steps": s.steps, "rejected": s.rejected, "h_min": s.h_min, "h_max": s.h_max})
}

/// Plain-text rendering of an answer object for people.
pub fn human(v: &Value) -> String {
    let mut out = String::new();
    if let Value::Object(m) = v {
        for (k, val) in m {
            out.push_str(&format!("{k:>8}: {val}\n"));
        }
    }
    out.trim_end().to_string()
}

/// The `retract` answer (contract command 2).
pub fn retraction(r: &Retraction) -> Value {
    json!({
        "u0": intervals(&r.u0),
        "v0": intervals(&r.v0),
        "v1": intervals(&r.v1),
        "defect": intervals(&r.s),
        "member": if r.possibly_member() { "possible" } else { "no" },
        "q1": intervals(&r.q1),
    })
}

/// The `step` answer (contract command 3).
pub fn step(s: &ExactStep) -> Value {
    json!({
        "q1": intervals(&s.q1),
        "q2": intervals(&s.q2),
        "p_minus": intervals(&s.p_minus),
        "p_plus": intervals(&s.p_plus),
    })
}

/// The `integrate` answer (contract command 4), with the Legendre transforms, energy and
/// Newton figures as extra fields.
pub fn trajectory(t: &Trajectory) -> Value {
    json!({
        "q": t.q,
        "p": t.p,
        "energy": t.energy,
        "newton_iterations": t.iterations,
        "max_residual": t.max_residual,
    })
}

/// The same as CSV: `k, q..., p..., energy`.
pub fn trajectory_csv(t: &Trajectory) -> String {
    let n = t.q.first().map_or(0, |q| q.len());
    let m = t.p.first().map_or(0, |p| p.len());
    let mut out = String::from("k");
    (0..n).for_each(|i| out.push_str(&format!(",q{i}")));
    (0..m).for_each(|a| out.push_str(&format!(",p{a}")));
    out.push_str(",energy\n");
    for (k, q) in t.q.iter().enumerate() {
        out.push_str(&k.to_string());
        for x in q {
            out.push_str(&format!(",{x:?}"));
        }
        for x in t.p.get(k).into_iter().flatten() {
            out.push_str(&format!(",{x:?}"));
        }
        if let Some(e) = t.energy.get(k) {
            out.push_str(&format!(",{e:?}"));
        }
        out.push('\n');
    }
    out.trim_end().to_string()
}
