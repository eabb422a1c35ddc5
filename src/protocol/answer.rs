//! The answers and all their renderings: one typed [`Answer`] per command, rendered as the
//! JSON object of `--json` and of the batch protocol ([`Answer::to_json`]) and as the text
//! or CSV the commands print without `--json` ([`Answer::to_text`]); the row-by-row forms of
//! `integrate` and `check` are in `rows.rs` beside this file, and the whole answers render
//! through them.

use super::rows::{CheckRows, IntegrateRows};
use super::Tolerances;
use crate::exact::{ExactStep, Retraction};
use crate::oracle::Verdict;
use crate::scene::Description;
use crate::schemes::{Row, Trajectory};
use crate::{Error, FlowEnclosure, FlowStats};
use inari::Interval;
use serde_json::{json, Value};
use std::io::Write;

/// The answer of one command, as the library computed it (contract commands 1-4, the
/// `lagrangian` and `check` queries, and the `scenes` listing).
#[derive(Clone, Debug)]
pub enum Answer {
    /// `flow` at one time `t`; with `jacobian`, also D(q, u)(t) / D(q, u)(0).
    Flow {
        /// The certified state at `t` (spec Theorem 5.1).
        enclosure: FlowEnclosure,
        /// Contains `D(q, u)(t) / D(q, u)(0)`, rows and columns q then u (spec Theorem 5.3);
        /// `None` unless asked for.
        jacobian: Option<Vec<Vec<Interval>>>,
    },
    /// `flow` at each of `times` (dense output), from one integration.
    FlowAt {
        /// The times asked for, increasing.
        times: Vec<f64>,
        /// The certified state at each of `times`, in order (spec Theorem 5.4).
        enclosures: Vec<FlowEnclosure>,
    },
    /// `retract`: the exact retractions and the defect of the pair.
    Retract(Retraction),
    /// `step`: one step of the exact discrete flow with the Legendre transforms.
    Step(ExactStep),
    /// `lagrangian`: the exact discrete Lagrangian and the retraction it integrates along.
    Lagrangian {
        /// Contains the action `int_0^h L(q, qd) dt` (spec eqs. (6.7)-(6.8)).
        l: Interval,
        /// The retraction of the pair, whose trajectory the action is taken along.
        retraction: Retraction,
    },
    /// `check`: the verdict, the tolerances it was decided on, and the decision.
    Check {
        /// The certified figures (spec Theorem 8.1).
        verdict: Verdict,
        /// The tolerances given (none, one or both).
        tolerances: Tolerances,
        /// `true` when every given tolerance is proved met (or none is given), `false` when
        /// one is proved exceeded (spec (8.3), (8.5)).
        passed: bool,
    },
    /// `integrate`: the float trajectory of a scheme.
    Integrate(Trajectory),
    /// `scenes`: the descriptions of the scenes listed.
    Scenes(Vec<Description>),
    /// `order`: the certified errors and orders of a scheme (contract E15).
    Order(super::order::OrderAnswer),
}

impl Answer {
    /// The JSON object the command prints with `--json`, and the `ok` of a batch answer.
    pub fn to_json(&self) -> Value {
        match self {
            Answer::Flow {
                enclosure: e,
                jacobian,
            } => {
                let mut a = json!({
                    "q": intervals(&e.q),
                    "v": intervals(&e.v),
                    "u": intervals(&e.u),
                    "stats": stats(&e.stats),
                });
                if let Some(j) = jacobian {
                    a["jacobian"] = Value::Array(j.iter().map(|row| intervals(row)).collect());
                }
                a
            }
            Answer::FlowAt { times, enclosures } => {
                let total = enclosures.last().map(|e| stats(&e.stats));
                let at: Vec<Value> = times
                    .iter()
                    .zip(enclosures)
                    .map(|(t, e)| {
                        json!({
                            "t": t,
                            "q": intervals(&e.q),
                            "v": intervals(&e.v),
                            "u": intervals(&e.u),
                        })
                    })
                    .collect();
                json!({"at": at, "stats": total})
            }
            Answer::Retract(r) => json!({
                "u0": intervals(&r.u0),
                "v0": intervals(&r.v0),
                "v1": intervals(&r.v1),
                "defect": intervals(&r.s),
                "member": if r.possibly_member() { "possible" } else { "no" },
                "q1": intervals(&r.q1),
            }),
            Answer::Step(s) => json!({
                "q1": intervals(&s.q1),
                "q2": intervals(&s.q2),
                "p_minus": intervals(&s.p_minus),
                "p_plus": intervals(&s.p_plus),
            }),
            Answer::Lagrangian { l, retraction } => {
                json!({"l": interval(*l), "defect": intervals(&retraction.s)})
            }
            Answer::Check {
                verdict: v, passed, ..
            } => verdict(v, *passed),
            Answer::Integrate(t) => trajectory(t),
            Answer::Scenes(list) => {
                let list: Vec<Value> = list.iter().map(description).collect();
                json!({ "scenes": list })
            }
            Answer::Order(o) => o.to_json(),
        }
    }

    /// What the command prints: the JSON object with `--json` (`json`), else the text.
    pub fn render(&self, json: bool) -> String {
        if json {
            self.to_json().to_string()
        } else {
            self.to_text()
        }
    }

    /// What the command prints without `--json` (without the final newline): for `flow`,
    /// `retract`, `step` and `lagrangian` one `key: value` line per key of the JSON object
    /// (the stops of `flow --times` a block each); for `integrate` the CSV
    /// `k,q0..,p0..,energy`; for `check` the verdict table and its summary line; for
    /// `scenes` the listing.
    pub fn to_text(&self) -> String {
        match self {
            Answer::Integrate(t) => {
                let mut rows = IntegrateRows::new(false, t.q.first().map_or(0, Vec::len));
                let mut parts = vec![Vec::new(); rows.parts()];
                written(|w| {
                    for r in trajectory_rows(t) {
                        rows.row(&mut parts, &r)?;
                    }
                    rows.finish(w, t.max_residual, |i, w| w.write_all(&parts[i]))
                })
            }
            Answer::Check {
                verdict: v,
                tolerances,
                passed,
            } => {
                let rows = CheckRows::new(false);
                let mut parts = vec![Vec::new(); rows.parts()];
                written(|w| {
                    for (k, d) in v.distance.iter().enumerate() {
                        let pair = v.defect.get(k).zip(v.energy_error.get(k));
                        rows.row(&mut parts, k, *d, pair.map(|(s, e)| (s.as_slice(), *e)))?;
                    }
                    rows.finish(
                        w,
                        v.max_distance,
                        v.max_defect,
                        tolerances,
                        *passed,
                        |i, w| w.write_all(&parts[i]),
                    )
                })
            }
            Answer::Scenes(_) => scenes_text(&self.to_json()),
            Answer::Order(o) => o.to_text(),
            _ => human(&self.to_json()),
        }
    }
}

/// The rows of a whole trajectory as [`crate::schemes::Scheme::integrate_each`] gives
/// them: `p` and the energy where known, the Newton iterations from row 1 on.
fn trajectory_rows(t: &Trajectory) -> impl Iterator<Item = Row<'_>> {
    t.q.iter().enumerate().map(|(k, q)| Row {
        k,
        q,
        p: t.p.get(k).map(Vec::as_slice),
        energy: t.energy.get(k).copied(),
        iterations: k.checked_sub(1).and_then(|i| t.iterations.get(i)).copied(),
    })
}

/// The bytes `write` writes into memory, as text, without its final newline (a `Vec<u8>`
/// takes every write, and the renderings write UTF-8 only).
fn written(write: impl FnOnce(&mut Vec<u8>) -> std::io::Result<()>) -> String {
    let mut out = Vec::new();
    // writing into memory cannot fail
    let _ = write(&mut out);
    if out.last() == Some(&b'\n') {
        out.pop();
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Plain-text rendering of an answer object; an array of objects (the stops of `flow
/// --times`) one object a block, indented.
fn human(v: &Value) -> String {
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

/// The `scenes` listing for people: the content of the JSON object, a block per scene.
fn scenes_text(v: &Value) -> String {
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

/// Every scene the crate knows, as the scene files describe them (the `scenes` command):
/// `{"scenes": [{"name", "summary", "coordinates", "velocities", "n", "k", "parameters":
/// [{"name", "default", "description"}], "lagrangian", "mu", "basis", "invariants"}]}`.
/// The strings are formulas for people and for implementations that pose the same problems.
pub fn scenes() -> Value {
    Answer::Scenes(
        crate::scene::SCENES
            .iter()
            .map(|s| s.description())
            .collect(),
    )
    .to_json()
}

/// One entry of [`scenes`]: a scene's description (for a user's scene, the compiled one:
/// its expressions and its derived basis as formulas).
pub fn description(s: &Description) -> Value {
    json!({
        "name": s.name,
        "summary": s.summary,
        "coordinates": s.coordinates,
        "velocities": s.velocities,
        "n": s.n,
        "k": s.k,
        "parameters": s.params.iter().map(|(name, default, description)| json!({
            "name": name,
            "default": default,
            "description": description,
        })).collect::<Vec<_>>(),
        "lagrangian": s.lagrangian,
        "mu": s.constraints,
        "basis": s.basis,
        "invariants": s.invariants,
    })
}

/// `[lo, hi]`; serde_json prints f64 in shortest round-trip form.
pub fn interval(x: Interval) -> Value {
    json!([x.inf(), x.sup()])
}

/// The intervals as a JSON array of `[lo, hi]`.
pub fn intervals(x: &[Interval]) -> Value {
    Value::Array(x.iter().map(|v| interval(*v)).collect())
}

/// The object `stats` of a flow answer: `order`, `steps`, `rejected`, `h_min`, `h_max`.
pub fn stats(s: &FlowStats) -> Value {
    json!({"order": s.order, "steps": s.steps, "rejected": s.rejected, "h_min": s.h_min, "h_max": s.h_max})
}

/// The batch error object (contract, E10): `code` and `message`; for a refusal also its
/// `reason` (`budget`, `no_proof`, `unbounded`, `undefined`) and, when a flow was under
/// way, `reached` (the time up to which it was proved); `reason` `internal` for a fault of
/// the crate.
pub fn error_object(e: &Error) -> Value {
    let mut o = json!({"code": e.code(), "message": e.message()});
    match e {
        Error::Uncertified(r) => {
            o["reason"] = json!(r.reason.name());
            if let Some(t) = r.reached {
                o["reached"] = json!(t);
            }
        }
        Error::Internal(_) => o["reason"] = json!("internal"),
        Error::Input(_) => {}
    }
    o
}

/// The `check` answer: `{"distance", "max_distance", "defect", "energy_error", "passed"}`.
/// With pair figures also `"max_defect"` (contract E13).
pub fn verdict(v: &crate::oracle::Verdict, passed: bool) -> Value {
    let mut a = json!({
        "distance": intervals(&v.distance),
        "max_distance": interval(v.max_distance),
        "defect": v.defect.iter().map(|d| intervals(d)).collect::<Vec<_>>(),
        "energy_error": intervals(&v.energy_error),
        "passed": passed,
    });
    if let Some(m) = v.max_defect {
        a["max_defect"] = interval(m);
    }
    a
}

/// The `integrate` answer, with the Legendre transforms, energy and Newton figures.
pub fn trajectory(t: &Trajectory) -> Value {
    json!({
        "q": t.q,
        "p": t.p,
        "energy": t.energy,
        "newton_iterations": t.iterations,
        "max_residual": t.max_residual,
    })
}
