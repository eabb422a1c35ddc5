//! The answers and all their renderings: one typed [`Answer`] per command, rendered as the
//! JSON object of `--json` and of the batch protocol ([`Answer::to_json`]) and as the text
//! or CSV the commands print without `--json` ([`Answer::to_text`]); the row-by-row forms of
//! `integrate` and `check` are in `rows.rs` beside this file, and the whole answers render
//! through them.

pub use super::rows::{interval, intervals};
use super::rows::{CheckRows, IntegrateRows};
use super::Tolerances;
use crate::exact::{ExactStep, Retraction};
use crate::oracle::Verdict;
use crate::scene::Description;
use crate::schemes::{Row, Trajectory};
use crate::{DecimalInterval, Error, FlowEnclosure, FlowStats, Interval};
use serde::Serialize;
use serde_json::{json, Value};
use std::io::Write;

/// The answer of one command, as the library computed it (contract commands 1-4, the
/// `lagrangian` and `check` queries, and the `scenes` listing).
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    /// `flow` at one time `t`; with `jacobian`, also D(q, u)(t) / D(q, u)(0).
    Flow {
        /// The certified state at `t` ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves)).
        enclosure: FlowEnclosure,
        /// Contains `D(q, u)(t) / D(q, u)(0)`, rows and columns q then u ([spec Theorem 5.3](crate::spec::enclosure));
        /// `None` unless asked for.
        jacobian: Option<Vec<Vec<Interval>>>,
    },
    /// `flow` at each of `times` (dense output), from one integration.
    FlowAt {
        /// The times asked for, increasing.
        times: Vec<f64>,
        /// The certified state at each of `times`, in order ([spec Theorem 5.4](crate::spec::enclosure)).
        enclosures: Vec<FlowEnclosure>,
    },
    /// `flow` at one time computed with more than 53 bits (contract E18): the same keys,
    /// each end a decimal string rounded outward, and the `precision` used.
    FlowWide {
        /// The significand bits the answer was computed with (at least those asked for).
        precision: u32,
        /// The certified state at `t` ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves)).
        enclosure: FlowEnclosure<DecimalInterval>,
        /// Contains `D(q, u)(t) / D(q, u)(0)` when asked for.
        jacobian: Option<Vec<Vec<DecimalInterval>>>,
    },
    /// `flow` at each of `times` computed with more than 53 bits (contract E18).
    FlowAtWide {
        /// The significand bits the answer was computed with.
        precision: u32,
        /// The times asked for, increasing.
        times: Vec<f64>,
        /// The certified state at each of `times`, in order.
        enclosures: Vec<FlowEnclosure<DecimalInterval>>,
    },
    /// `retract` computed with more than 53 bits (contract E18): the keys of `retract`, each
    /// end a decimal string rounded outward.
    RetractWide {
        /// The significand bits the answer was computed with.
        precision: u32,
        /// `R^{e-}` in the basis of D.
        u0: Vec<DecimalInterval>,
        /// `v0 = E(Q0)^T u0`.
        v0: Vec<DecimalInterval>,
        /// `v1 = qd(h)`.
        v1: Vec<DecimalInterval>,
        /// The defect `s`.
        s: Vec<DecimalInterval>,
        /// `q(h) = Q1 + N(Q1) s`.
        q1: Vec<DecimalInterval>,
        /// `false` when the defect is proved non-zero (the pair is off M_h^{e,nh}).
        possibly_member: bool,
    },
    /// `step` computed with more than 53 bits (contract E18).
    StepWide {
        /// The significand bits the answer was computed with.
        precision: u32,
        /// `q(h)`.
        q1: Vec<DecimalInterval>,
        /// `q(2h)`.
        q2: Vec<DecimalInterval>,
        /// `F^-_{h,nh} l`.
        p_minus: Vec<DecimalInterval>,
        /// `F^+_{h,nh} l`.
        p_plus: Vec<DecimalInterval>,
    },
    /// `lagrangian` computed with more than 53 bits (contract E18).
    LagrangianWide {
        /// The significand bits the answer was computed with.
        precision: u32,
        /// Contains the action.
        l: DecimalInterval,
        /// The retraction's defect `s`.
        s: Vec<DecimalInterval>,
    },
    /// `order` with the local ladder's exact steps computed with more than 53 bits
    /// (contract E18): the keys of `order` plus `precision`.
    OrderWide {
        /// The significand bits of the local ladder's exact steps.
        precision: u32,
        /// The errors and orders.
        order: super::order::OrderAnswer,
    },
    /// `retract`: the exact retractions and the defect of the pair.
    Retract(Retraction),
    /// `step`: one step of the exact discrete flow with the Legendre transforms.
    Step(ExactStep),
    /// `lagrangian`: the exact discrete Lagrangian and the retraction it integrates along.
    Lagrangian {
        /// Contains the action `int_0^h L(q, qd) dt` ([spec eqs. (6.7)-(6.8)](crate::spec::exact_discrete)).
        l: Interval,
        /// The retraction of the pair, whose trajectory the action is taken along.
        retraction: Retraction,
    },
    /// `check`: the verdict, the tolerances it was decided on, and the decision.
    Check {
        /// The certified figures ([spec Theorem 8.1](crate::spec::oracle)).
        verdict: Verdict,
        /// The tolerances given (none, one or both).
        tolerances: Tolerances,
        /// `true` when every given tolerance is proved met (or none is given), `false` when
        /// one is proved exceeded ([spec (8.3)](crate::spec::oracle), (8.5)).
        passed: bool,
    },
    /// `check` computed at `precision` bits (batch `precision`, contract E28): the figures
    /// of [`Answer::Check`]'s verdict, each rounded outward to an f64 interval.
    CheckWide {
        /// The bits used (106 for 54..=106).
        precision: u32,
        /// `∋ |q_k - q^e_k|_inf` for each row.
        distance: Vec<Interval>,
        /// `∋ max_k |q_k - q^e_k|_inf`.
        max_distance: Interval,
        /// Each pair's defect `s_k` (with pair figures).
        defect: Vec<Vec<Interval>>,
        /// `∋ max_k |s_k|_inf` (with pair figures).
        max_defect: Option<Interval>,
        /// Each pair's energy error (with pair figures).
        energy_error: Vec<Interval>,
        /// The tolerances given (none, one or both).
        tolerances: Tolerances,
        /// As [`Answer::Check`]'s.
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
                enclosure,
                jacobian,
            } => value(FlowView {
                enclosure,
                jacobian: jacobian.as_ref(),
                precision: None,
            }),
            Answer::FlowAt { times, enclosures } => value(flow_at_view(times, enclosures, None)),
            Answer::FlowWide {
                precision,
                enclosure,
                jacobian,
            } => value(FlowView {
                enclosure,
                jacobian: jacobian.as_ref(),
                precision: Some(*precision),
            }),
            Answer::FlowAtWide {
                precision,
                times,
                enclosures,
            } => value(flow_at_view(times, enclosures, Some(*precision))),
            Answer::Retract(r) => value(RetractView {
                u0: &r.u0,
                v0: &r.v0,
                v1: &r.v1,
                defect: &r.s,
                member: member(r.possibly_member()),
                q1: &r.q1,
                precision: None,
            }),
            Answer::Step(s) => value(StepView {
                q1: &s.q1,
                q2: &s.q2,
                p_minus: &s.p_minus,
                p_plus: &s.p_plus,
                precision: None,
            }),
            Answer::Lagrangian { l, retraction } => value(LagrangianView {
                l,
                defect: &retraction.s,
                precision: None,
            }),
            Answer::RetractWide {
                precision,
                u0,
                v0,
                v1,
                s,
                q1,
                possibly_member,
            } => value(RetractView {
                u0,
                v0,
                v1,
                defect: s,
                member: member(*possibly_member),
                q1,
                precision: Some(*precision),
            }),
            Answer::StepWide {
                precision,
                q1,
                q2,
                p_minus,
                p_plus,
            } => value(StepView {
                q1,
                q2,
                p_minus,
                p_plus,
                precision: Some(*precision),
            }),
            Answer::LagrangianWide { precision, l, s } => value(LagrangianView {
                l,
                defect: s,
                precision: Some(*precision),
            }),
            Answer::Check {
                verdict: v, passed, ..
            } => verdict(v, *passed),
            Answer::CheckWide {
                precision,
                distance,
                max_distance,
                defect,
                max_defect,
                energy_error,
                passed,
                ..
            } => {
                let mut v = value(CheckView {
                    distance,
                    max_distance: *max_distance,
                    defect,
                    energy_error,
                    passed: *passed,
                    max_defect: *max_defect,
                });
                v["precision"] = (*precision).into();
                v
            }
            Answer::Integrate(t) => trajectory(t),
            Answer::Scenes(list) => {
                let list: Vec<Value> = list.iter().map(description).collect();
                json!({ "scenes": list })
            }
            Answer::Order(o) => o.to_json(),
            Answer::OrderWide { precision, order } => {
                let mut v = order.to_json();
                v["precision"] = (*precision).into();
                v
            }
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
                        None,
                        |i, w| w.write_all(&parts[i]),
                    )
                })
            }
            Answer::CheckWide {
                precision,
                distance,
                max_distance,
                defect,
                max_defect,
                energy_error,
                tolerances,
                passed,
            } => {
                let rows = CheckRows::new(false);
                let mut parts = vec![Vec::new(); rows.parts()];
                written(|w| {
                    for (k, d) in distance.iter().enumerate() {
                        let pair = defect.get(k).zip(energy_error.get(k));
                        rows.row(&mut parts, k, *d, pair.map(|(s, e)| (s.as_slice(), *e)))?;
                    }
                    rows.finish(
                        w,
                        *max_distance,
                        *max_defect,
                        tolerances,
                        *passed,
                        Some(*precision),
                        |i, w| w.write_all(&parts[i]),
                    )
                })
            }
            Answer::Scenes(_) => scenes_text(&self.to_json()),
            Answer::Order(o) => o.to_text(),
            Answer::OrderWide { precision, order } => format!(
                "{}\n(the local errors computed with {precision} bits)",
                order.to_text()
            ),
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

/// The JSON value of an answer or a part of one, from its serde form. The objects are
/// serde_json's maps, whose keys are kept sorted: the answers print their keys in that
/// order whatever the order of the fields.
pub(crate) fn value(x: impl Serialize) -> Value {
    // cannot fail: the answers are numbers, strings, arrays and structs, no map with keys
    // that are not strings
    serde_json::to_value(x).unwrap_or(Value::Null)
}

/// The object `stats` of a flow answer: `order`, `steps`, `rejected`, `h_min`, `h_max`.
pub fn stats(s: &FlowStats) -> Value {
    value(s)
}

/// The exit status of the command line for an error, which is also the batch error object's
/// `code` (contract): 2 for a malformed request ([`Error::Input`]), 3 for everything that
/// certifies nothing (a refusal, an internal fault). A command-line convention, kept out of
/// the library's error type.
pub fn exit_code(e: &Error) -> i32 {
    match e {
        Error::Input(_) => 2,
        Error::Uncertified(_) | Error::Internal(_) => 3,
    }
}

/// The batch error object (contract, E10): `code` and `message`; for a refusal also its
/// `reason` (`budget`, `no_proof`, `unbounded`, `undefined`) and, when a flow was under
/// way, `reached` (the time up to which it was proved); `reason` `internal` for a fault of
/// the crate.
pub fn error_object(e: &Error) -> Value {
    let mut o = json!({"code": exit_code(e), "message": e.message()});
    match e {
        Error::Uncertified(r) => {
            o["reason"] = json!(r.reason.name());
            o["cause"] = json!(r.cause.name());
            if let Some(t) = r.reached {
                o["reached"] = json!(t);
            }
        }
        Error::Internal(_) => {
            o["reason"] = json!("internal");
            o["cause"] = json!("internal");
        }
        Error::Input(_) => {}
    }
    o
}

/// The `check` answer: `{"distance", "max_distance", "defect", "energy_error", "passed"}`.
/// With pair figures also `"max_defect"` (contract E13).
pub fn verdict(v: &crate::oracle::Verdict, passed: bool) -> Value {
    value(CheckView {
        distance: &v.distance,
        max_distance: v.max_distance,
        defect: &v.defect,
        energy_error: &v.energy_error,
        passed,
        max_defect: v.max_defect,
    })
}

/// The `integrate` answer, with the Legendre transforms, energy and Newton figures: the
/// serde form of [`Trajectory`] (`q`, `p`, `energy`, `newton_iterations`, `max_residual`).
pub fn trajectory(t: &Trajectory) -> Value {
    value(t)
}

// The answers whose protocol object is not the serde form of the library's type: some keys
// renamed, dropped or computed. The keys print sorted (see [`value`]).

/// `flow` at one time: the enclosure's `q`, `u`, `v`, `stats`, and `jacobian` when asked.
#[derive(Serialize)]
struct FlowView<'a, I> {
    #[serde(flatten)]
    enclosure: &'a FlowEnclosure<I>,
    #[serde(skip_serializing_if = "Option::is_none")]
    jacobian: Option<&'a Vec<Vec<I>>>,
    /// Only above 53 bits (contract E18).
    #[serde(skip_serializing_if = "Option::is_none")]
    precision: Option<u32>,
}

fn flow_at_view<'a, I>(
    times: &[f64],
    enclosures: &'a [FlowEnclosure<I>],
    precision: Option<u32>,
) -> FlowAtView<'a, I> {
    FlowAtView {
        at: times
            .iter()
            .zip(enclosures)
            .map(|(t, e)| Stop {
                t: *t,
                q: &e.q,
                v: &e.v,
                u: &e.u,
            })
            .collect(),
        stats: enclosures.last().map(|e| &e.stats),
        precision,
    }
}

/// `flow` at many times: a stop each (without its stats), and the stats of the whole
/// integration (`null` when there is no stop).
#[derive(Serialize)]
struct FlowAtView<'a, I> {
    at: Vec<Stop<'a, I>>,
    stats: Option<&'a FlowStats>,
    /// Only above 53 bits (contract E18).
    #[serde(skip_serializing_if = "Option::is_none")]
    precision: Option<u32>,
}

/// One stop of `flow --times`.
#[derive(Serialize)]
struct Stop<'a, I> {
    t: f64,
    q: &'a [I],
    v: &'a [I],
    u: &'a [I],
}

/// `retract`: the retraction with its defect `s` as `defect`, and whether the pair may be
/// a member of M_h^{e,nh}.
#[derive(Serialize)]
struct RetractView<'a, P> {
    u0: &'a [P],
    v0: &'a [P],
    v1: &'a [P],
    defect: &'a [P],
    member: &'static str,
    q1: &'a [P],
    /// Only above 53 bits (contract E18).
    #[serde(skip_serializing_if = "Option::is_none")]
    precision: Option<u32>,
}

/// The `member` key of `retract`.
fn member(possibly: bool) -> &'static str {
    if possibly {
        "possible"
    } else {
        "no"
    }
}

/// `step`: the step without its retraction.
#[derive(Serialize)]
struct StepView<'a, P> {
    q1: &'a [P],
    q2: &'a [P],
    p_minus: &'a [P],
    p_plus: &'a [P],
    /// Only above 53 bits (contract E18).
    #[serde(skip_serializing_if = "Option::is_none")]
    precision: Option<u32>,
}

/// `lagrangian`: the action and the retraction's defect.
#[derive(Serialize)]
struct LagrangianView<'a, P> {
    l: &'a P,
    defect: &'a [P],
    /// Only above 53 bits (contract E18).
    #[serde(skip_serializing_if = "Option::is_none")]
    precision: Option<u32>,
}

/// `check`: the verdict without the exact trajectory, with the decision; `max_defect` only
/// with pair figures.
#[derive(Serialize)]
struct CheckView<'a> {
    distance: &'a [Interval],
    max_distance: Interval,
    defect: &'a [Vec<Interval>],
    energy_error: &'a [Interval],
    passed: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_defect: Option<Interval>,
}
