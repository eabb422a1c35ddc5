//! Queries and answers as JSON values (contract.md, commands 1-5): the one place where a
//! request is validated and turned into a library call. The command line and the batch
//! protocol both go through [`Query`] and [`Session::answer`]. No printing here.

use crate::exact;
pub use crate::oracle::{Steps, Tolerances};
use crate::scalar::point;
use crate::scene::{Description, Scene, SceneFile};
use crate::schemes::{NewtonOptions, Scheme, SchemeKind, Trajectory};
use crate::{AnyScene, Error, FlowOptions, FlowStats, Model};
use inari::Interval;
use serde_json::{json, Map, Value};
use std::collections::HashMap;
use std::rc::Rc;

/// A scene by name with its parameters, or a user's scene definition (a scene file or an
/// inline JSON object, spec chapter 10) with the parameters that override its defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSpec {
    pub name: String,
    pub params: Vec<(String, f64)>,
    /// `Some` for a user's scene (then `name` is its name, for messages only).
    pub definition: Option<std::sync::Arc<SceneFile>>,
}

impl SceneSpec {
    /// A built-in scene by name.
    pub fn named(name: &str, params: Vec<(String, f64)>) -> SceneSpec {
        SceneSpec {
            name: name.to_string(),
            params,
            definition: None,
        }
    }

    /// A user's scene.
    pub fn defined(definition: SceneFile, params: Vec<(String, f64)>) -> SceneSpec {
        SceneSpec {
            name: definition.name(),
            params,
            definition: Some(std::sync::Arc::new(definition)),
        }
    }
}

/// One request (contract commands 1-4, and the `lagrangian` extension).
#[derive(Clone, Debug, PartialEq)]
pub enum Query {
    Flow {
        scene: SceneSpec,
        q: Vec<f64>,
        u: Vec<f64>,
        /// One time (`t`) or many (`times`, dense output: spec eq. (5.16), contract E11).
        t: At,
        order: usize,
        /// Also the derivative D(q, u)(t) / D(q, u)(0) (`flow --jacobian`).
        jacobian: bool,
    },
    Retract(Pair),
    Step(Pair),
    Lagrangian(Pair),
    Integrate {
        pair: Pair,
        scheme: SchemeKind,
        steps: usize,
    },
    /// A certified verdict on a whole trajectory `q_0 .. q_N` of step `h`, or at times
    /// `t_0 < .. < t_N` (contract E12) (the `check` command's, as a batch query).
    Check {
        scene: SceneSpec,
        steps: Steps,
        q: Vec<Vec<f64>>,
        /// Tolerance on `max_k |q_k - q^e_k|_inf`: the answer says `passed` (proved within),
        /// or fails (proved beyond) or is refused as undecided.
        tol: Option<f64>,
        /// Tolerance on `max_k |s_k|_inf`, the pairs' defects (contract E13): decided as
        /// `tol`, and both must pass.
        defect_tol: Option<f64>,
        /// Also the per-pair defects and energies (default true).
        pairs: bool,
    },
}

/// The times of a `flow` query.
#[derive(Clone, Debug, PartialEq)]
pub enum At {
    /// `t`: the state at this time.
    One(f64),
    /// `times`: the states at these increasing times, from one integration.
    Many(Vec<f64>),
}

/// The arguments shared by the commands on a pair of configurations.
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    pub scene: SceneSpec,
    pub q0: Vec<f64>,
    pub q1: Vec<f64>,
    pub h: f64,
}

/// Largest accepted `steps` for `integrate`.
pub const MAX_STEPS: usize = 10_000_000;

/// Models and schemes already compiled, by scene and parameters: a batch of queries on the
/// same scene records its tapes once.
#[derive(Default)]
pub struct Session {
    models: HashMap<String, Rc<Model>>,
    schemes: HashMap<(String, bool), Rc<Scheme>>,
    /// Settings of the validated integrator for every query (a fuzzer lowers `max_steps`).
    pub flow: FlowOptions,
    /// Refuse `integrate` queries with more steps than this (0: the contract's maximum).
    pub max_integrate_steps: usize,
    /// Time budget in seconds of every query that names none (`batch --deadline`); `None`:
    /// [`default_deadline`] of the query's command.
    pub deadline: Option<f64>,
}

/// The budget in seconds of a single-step query (`retract`, `step`, `lagrangian`, and each
/// pair that `check` certifies) when none is given: such a query answers in milliseconds on
/// ordinary input, so this only stops a pathological one.
pub const STEP_DEADLINE: f64 = 5.0;

/// The documented default budget of a query, in seconds: [`STEP_DEADLINE`] for the
/// single-step queries, none for `flow` (bounded by `FlowOptions::max_steps`) and
/// `integrate` (bounded by its `steps`).
pub fn default_deadline(q: &Query) -> Option<f64> {
    match q {
        Query::Retract(_) | Query::Step(_) | Query::Lagrangian(_) => Some(STEP_DEADLINE),
        Query::Check { q, .. } => Some(STEP_DEADLINE * q.len().max(1) as f64),
        Query::Flow { .. } | Query::Integrate { .. } => None,
    }
}

/// The instant `seconds` from now; `None` (no limit) when that is past what the clock holds.
pub fn deadline_in(seconds: f64) -> Option<std::time::Instant> {
    let d = std::time::Duration::try_from_secs_f64(seconds).ok()?;
    std::time::Instant::now().checked_add(d)
}

/// The earlier of two deadlines (`None` is no limit).
fn earlier(
    a: Option<std::time::Instant>,
    b: Option<std::time::Instant>,
) -> Option<std::time::Instant> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    }
}

/// One row of an `integrate` answer (see [`Session::integrate_each`]).
pub use crate::schemes::Row;

fn scene_key(s: &SceneSpec) -> String {
    let mut k = match &s.definition {
        None => s.name.clone(),
        Some(d) => format!("file:{}", d.key()),
    };
    for (p, v) in &s.params {
        k.push_str(&format!("|{p}={:x}", v.to_bits()));
    }
    k
}

impl Session {
    pub fn model(&mut self, s: &SceneSpec) -> Result<Rc<Model>, Error> {
        let key = scene_key(s);
        if let Some(m) = self.models.get(&key) {
            return Ok(m.clone());
        }
        let m = Rc::new(match &s.definition {
            None => Model::new(&AnyScene::new(&s.name, &s.params)?)?,
            Some(d) => Model::new(&SceneFile::clone(d).with_params(&s.params)?)?,
        });
        self.models.insert(key, m.clone());
        Ok(m)
    }

    fn scheme(&mut self, s: &SceneSpec, kind: SchemeKind) -> Result<Rc<Scheme>, Error> {
        let key = (scene_key(s), kind == SchemeKind::Mla);
        if let Some(sc) = self.schemes.get(&key) {
            return Ok(sc.clone());
        }
        let model = self.model(s)?;
        let sc = Rc::new(Scheme::new(&model, kind));
        self.schemes.insert(key, sc.clone());
        Ok(sc)
    }

    /// Answer a query with the JSON object its command prints with `--json`, within the
    /// session's budget ([`Session::deadline`], else [`default_deadline`]).
    pub fn answer(&mut self, q: &Query) -> Result<Value, Error> {
        self.answer_within(q, None)
    }

    /// As [`Session::answer`], within `seconds` when given (a query's own `deadline`).
    /// Past the budget: `Error::over_budget` (exit 3), never a partial answer.
    pub fn answer_within(&mut self, q: &Query, seconds: Option<f64>) -> Result<Value, Error> {
        let budget = seconds.or(self.deadline).or_else(|| default_deadline(q));
        let mut opts = self.flow.clone();
        opts.deadline = earlier(opts.deadline, budget.and_then(deadline_in));
        match q {
            Query::Flow {
                scene,
                q,
                u,
                t,
                order,
                jacobian,
            } => {
                let model = self.model(scene)?;
                let o = FlowOptions {
                    order: *order,
                    ..opts
                };
                let t = match t {
                    At::One(t) => *t,
                    At::Many(times) => {
                        if *jacobian {
                            return Err(Error::input(
                                "`jacobian` is given only at one time `t`, not with `times`",
                            ));
                        }
                        let at = crate::flow::flow_at(&model, q, u, times, &o)?;
                        let total = at.last().map(|e| stats(&e.stats));
                        let at: Vec<Value> = times
                            .iter()
                            .zip(&at)
                            .map(|(t, e)| {
                                json!({
                                    "t": t,
                                    "q": intervals(&e.q),
                                    "v": intervals(&e.v),
                                    "u": intervals(&e.u),
                                })
                            })
                            .collect();
                        return Ok(json!({"at": at, "stats": total}));
                    }
                };
                let (e, jac) = if *jacobian {
                    let (e, j) = crate::flow::flow_c1(&model, q, u, t, &o)?;
                    (e, Some(j))
                } else {
                    (crate::flow(&model, q, u, t, &o)?, None)
                };
                let mut a = json!({
                    "q": intervals(&e.q),
                    "v": intervals(&e.v),
                    "u": intervals(&e.u),
                    "stats": stats(&e.stats),
                });
                if let Some(j) = jac {
                    a["jacobian"] = Value::Array(j.iter().map(|row| intervals(row)).collect());
                }
                Ok(a)
            }
            Query::Retract(p) => {
                let model = self.model(&p.scene)?;
                let r = exact::retract(&model, &points(&p.q0), &points(&p.q1), p.h, &opts)?;
                Ok(json!({
                    "u0": intervals(&r.u0),
                    "v0": intervals(&r.v0),
                    "v1": intervals(&r.v1),
                    "defect": intervals(&r.s),
                    "member": if r.possibly_member() { "possible" } else { "no" },
                    "q1": intervals(&r.q1),
                }))
            }
            Query::Step(p) => {
                let model = self.model(&p.scene)?;
                let s = exact::step(&model, &points(&p.q0), &points(&p.q1), p.h, &opts)?;
                Ok(json!({
                    "q1": intervals(&s.q1),
                    "q2": intervals(&s.q2),
                    "p_minus": intervals(&s.p_minus),
                    "p_plus": intervals(&s.p_plus),
                }))
            }
            Query::Lagrangian(p) => {
                let model = self.model(&p.scene)?;
                let (r, l) =
                    exact::discrete_lagrangian(&model, &points(&p.q0), &points(&p.q1), p.h, &opts)?;
                Ok(json!({"l": interval(l), "defect": intervals(&r.s)}))
            }
            Query::Check {
                scene,
                steps,
                q,
                tol,
                defect_tol,
                pairs,
            } => {
                let model = self.model(scene)?;
                let tols = Tolerances {
                    tol: *tol,
                    defect_tol: *defect_tol,
                };
                tols.check(*pairs)?;
                let o = crate::oracle::CheckOptions {
                    pairs: *pairs,
                    flow: opts,
                };
                let v = crate::oracle::check_steps(&model, steps, q, &o)?;
                let passed = tols.decide(v.max_distance, v.max_defect)?;
                Ok(verdict(&v, passed))
            }
            Query::Integrate {
                pair,
                scheme,
                steps,
            } => {
                if self.max_integrate_steps > 0 && *steps > self.max_integrate_steps {
                    return Err(Error::input(format!(
                        "steps: at most {} in this session",
                        self.max_integrate_steps
                    )));
                }
                let model = self.model(&pair.scene)?;
                for q in [&pair.q0, &pair.q1] {
                    if q.len() == model.n && q.iter().all(|x| x.is_finite()) {
                        model.check_at(&points(q))?;
                    }
                }
                let sc = self.scheme(&pair.scene, *scheme)?;
                let mut tr = Trajectory {
                    q: Vec::new(),
                    p: Vec::new(),
                    energy: Vec::new(),
                    iterations: Vec::new(),
                    max_residual: 0.0,
                };
                tr.max_residual = sc.integrate_each(
                    &pair.q0,
                    &pair.q1,
                    pair.h,
                    *steps,
                    &NewtonOptions::default(),
                    |r: Row| -> Result<(), Error> {
                        Error::check_deadline(opts.deadline)?;
                        tr.q.push(r.q.to_vec());
                        tr.p.extend(r.p.map(<[f64]>::to_vec));
                        tr.energy.extend(r.energy);
                        tr.iterations.extend(r.iterations);
                        Ok(())
                    },
                )?;
                Ok(trajectory(&tr))
            }
        }
    }

    /// An `integrate` query row by row in constant memory: `row` gets q_k, p_k and the
    /// energy for k = 0..=steps in order, as soon as each is known; returns the largest
    /// Newton residual. Within `seconds` when given, else the session's budget; past it, or
    /// when `row` fails, the integration stops with that error.
    pub fn integrate_each(
        &mut self,
        pair: &Pair,
        scheme: SchemeKind,
        steps: usize,
        seconds: Option<f64>,
        mut row: impl FnMut(Row) -> Result<(), Error>,
    ) -> Result<f64, Error> {
        if self.max_integrate_steps > 0 && steps > self.max_integrate_steps {
            return Err(Error::input(format!(
                "steps: at most {} in this session",
                self.max_integrate_steps
            )));
        }
        let deadline = earlier(
            self.flow.deadline,
            seconds.or(self.deadline).and_then(deadline_in),
        );
        let sc = self.scheme(&pair.scene, scheme)?;
        sc.integrate_each(
            &pair.q0,
            &pair.q1,
            pair.h,
            steps,
            &NewtonOptions::default(),
            |r: Row| {
                Error::check_deadline(deadline)?;
                row(r)
            },
        )
    }

    /// One line of the batch protocol (contract command 5): `None` for a blank line, else
    /// the answer line `{"id": .., "ok": ..}` or `{"id": .., "error": {"code", "message"}}`.
    pub fn batch_line(&mut self, line: &str) -> Option<String> {
        self.batch_answer(0, &Line::Text(line.as_bytes().to_vec()))
            .map(|a| a.text)
    }

    /// Line `line_no` (1-based; 0: unknown) of a batch stream as read by [`LineReader`]:
    /// `None` for a blank line, else exactly one answer line. A line that is not UTF-8, not
    /// JSON or too long gets an error object with `"id": null` naming the line number.
    pub fn batch_answer(&mut self, line_no: usize, line: &Line) -> Option<BatchAnswer> {
        let at = if line_no > 0 {
            format!("line {line_no}: ")
        } else {
            String::new()
        };
        let mut answered = None;
        let (id, result) = match line {
            Line::TooLong { bytes } => (
                Value::Null,
                Err(Error::input(format!(
                    "{at}longer than {MAX_LINE_BYTES} bytes ({bytes} bytes); not read"
                ))),
            ),
            Line::Text(bytes) => match std::str::from_utf8(bytes) {
                Err(e) => (
                    Value::Null,
                    Err(Error::input(format!(
                        "{at}not valid UTF-8 (byte {})",
                        e.valid_up_to() + 1
                    ))),
                ),
                Ok(text) if text.trim().is_empty() => return None,
                Ok(text) => match parse_json(text) {
                    Err(e) => {
                        // JSON that is only refused for a repeated key still has its id
                        let id = serde_json::from_str::<Value>(text)
                            .ok()
                            .and_then(|v| v.get("id").cloned())
                            .unwrap_or(Value::Null);
                        let what = if id.is_null() { "not JSON" } else { "refused" };
                        (
                            id,
                            Err(Error::input(format!("{at}{what}: {}", e.message()))),
                        )
                    }
                    Ok(v) => {
                        let id = v.get("id").cloned().unwrap_or(Value::Null);
                        let r = Query::from_json(&v).and_then(|q| {
                            let a = self.answer_within(&q, deadline_from_json(&v)?)?;
                            answered = Some(q);
                            Ok(a)
                        });
                        (id, r)
                    }
                },
            },
        };
        let out = match result {
            Ok(ok) => json!({"id": id, "ok": ok}),
            Err(e) => json!({"id": id, "error": error_object(&e)}),
        };
        Some(BatchAnswer {
            text: out.to_string(),
            answered,
        })
    }
}

/// An answer line of the batch protocol, and the query it answered when it is `ok` (so
/// that a test can compare it with the line: the numbers used are the numbers given).
#[derive(Clone, Debug)]
pub struct BatchAnswer {
    pub text: String,
    pub answered: Option<Query>,
}

/// Longest batch line read, in bytes (without its newline): 1 MiB. A longer line is not
/// kept in memory; it gets an error answer and the stream goes on.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// A line of a batch stream.
#[derive(Clone, Debug, PartialEq)]
pub enum Line {
    /// The bytes of the line, without its `\n`.
    Text(Vec<u8>),
    /// A line longer than the limit, and how long it was.
    TooLong { bytes: u64 },
}

/// Lines of bytes from a reader, each at most `limit` bytes kept: a longer line is skipped
/// to its end without being held (memory stays `limit` plus the reader's buffer).
pub struct LineReader<R> {
    inner: R,
    limit: usize,
}

impl<R: std::io::BufRead> LineReader<R> {
    pub fn new(inner: R, limit: usize) -> Self {
        LineReader { inner, limit }
    }

    /// The next line, `None` at the end of the input.
    pub fn next_line(&mut self) -> std::io::Result<Option<Line>> {
        let mut buf = Vec::new();
        let (mut total, mut over, mut any) = (0u64, false, false);
        loop {
            let avail = match self.inner.fill_buf() {
                Ok(b) => b,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if avail.is_empty() {
                break;
            }
            any = true;
            let (chunk, used, end) = match avail.iter().position(|b| *b == b'\n') {
                Some(i) => (&avail[..i], i + 1, true),
                None => (avail, avail.len(), false),
            };
            total += chunk.len() as u64;
            if !over && buf.len() + chunk.len() > self.limit {
                over = true;
                buf = Vec::new();
            }
            if !over {
                buf.extend_from_slice(chunk);
            }
            self.inner.consume(used);
            if end {
                break;
            }
        }
        Ok(match (any, over) {
            (false, _) => None,
            (true, true) => Some(Line::TooLong { bytes: total }),
            (true, false) => Some(Line::Text(buf)),
        })
    }
}

/// Every scene the crate knows, as the scene files describe them (the `scenes` command):
/// `{"scenes": [{"name", "summary", "coordinates", "velocities", "n", "k", "parameters":
/// [{"name", "default", "description"}], "lagrangian", "mu", "basis", "invariants"}]}`.
/// The strings are formulas for people and for implementations that pose the same problems.
pub fn scenes() -> Value {
    let list: Vec<Value> = crate::scene::SCENES
        .iter()
        .map(|s| description(&s.description()))
        .collect();
    json!({ "scenes": list })
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

fn points(v: &[f64]) -> Vec<Interval> {
    v.iter().map(|x| point(*x)).collect()
}

/// `[lo, hi]`; serde_json prints f64 in shortest round-trip form.
pub fn interval(x: Interval) -> Value {
    json!([x.inf(), x.sup()])
}

pub fn intervals(x: &[Interval]) -> Value {
    Value::Array(x.iter().map(|v| interval(*v)).collect())
}

pub fn stats(s: &FlowStats) -> Value {
    json!({"order": s.order, "steps": s.steps, "rejected": s.rejected, "h_min": s.h_min, "h_max": s.h_max})
}

/// Whether a verdict passes the tolerance (spec (8.3)): `true` when `max_distance <= tol`
/// is proved (or no tolerance is given), `false` when `max_distance > tol` is proved; a
/// distance enclosure straddling `tol` decides nothing and is refused (exit 3).
pub fn tolerance_verdict(v: &crate::oracle::Verdict, tol: Option<f64>) -> Result<bool, Error> {
    tolerance_decision(v.max_distance, tol)
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

/// [`tolerance_verdict`] on the certified maximum distance alone.
pub fn tolerance_decision(max_distance: Interval, tol: Option<f64>) -> Result<bool, Error> {
    Tolerances {
        tol,
        defect_tol: None,
    }
    .decide(max_distance, None)
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

/// A decimal literal read as the nearest f64 (Rust's parser is correctly rounded);
/// non-finite values and anything but a plain decimal literal are input errors.
pub fn parse_num(name: &str, s: &str) -> Result<f64, Error> {
    let t = s.trim();
    let ok_chars = !t.is_empty()
        && t.chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'));
    let x: f64 = if ok_chars { t.parse().ok() } else { None }
        .ok_or_else(|| Error::input(format!("{name}: `{s}` is not a decimal number")))?;
    finite(name, x)
}

fn finite(name: &str, x: f64) -> Result<f64, Error> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::input(format!("{name}: not a finite number")))
    }
}

/// A comma-separated vector without spaces.
pub fn parse_vec(name: &str, s: &str) -> Result<Vec<f64>, Error> {
    s.split(',').map(|x| parse_num(name, x)).collect()
}

/// `name=value`.
pub fn parse_param(s: &str) -> Result<(String, f64), Error> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| Error::input(format!("param: expected name=value, got `{s}`")))?;
    Ok((k.to_string(), parse_num("param", v)?))
}

pub fn parse_steps(s: &str) -> Result<usize, Error> {
    match s.trim().parse::<usize>() {
        Ok(n) if n <= MAX_STEPS => Ok(n),
        _ => Err(Error::input(format!(
            "steps: expected an integer in 0..={MAX_STEPS}, got `{s}`"
        ))),
    }
}

pub fn parse_order(s: &str) -> Result<usize, Error> {
    match s.trim().parse::<usize>() {
        Ok(p) if (2..=60).contains(&p) => Ok(p),
        _ => Err(Error::input(format!(
            "order: expected an integer in 2..=60, got `{s}`"
        ))),
    }
}

/// A time budget in seconds: a finite number > 0 (`--deadline`, the `deadline` key).
pub fn parse_seconds(name: &str, s: &str) -> Result<f64, Error> {
    check_seconds(name, parse_num(name, s)?)
}

fn check_seconds(name: &str, x: f64) -> Result<f64, Error> {
    if x > 0.0 && x.is_finite() {
        Ok(x)
    } else {
        Err(Error::input(format!(
            "{name}: a budget in seconds must be > 0 (got {x})"
        )))
    }
}

/// A JSON text, read strictly: a key repeated in an object is refused (serde_json would
/// keep the last one silently), numbers are the nearest f64 (`float_roundtrip`), and a
/// number out of the f64 range is refused.
pub fn parse_json(text: &str) -> Result<Value, Error> {
    let mut de = serde_json::Deserializer::from_str(text);
    let v = serde::Deserialize::deserialize(&mut de)
        .and_then(|Strict(v)| de.end().map(|()| v))
        .map_err(|e| {
            // one line of JSON: its column is the position that matters
            let m = e.to_string();
            Error::input(if text.contains('\n') {
                m
            } else {
                m.replace(" at line 1 column ", " at column ")
            })
        })?;
    Ok(v)
}

/// A JSON value whose objects have no repeated key.
struct Strict(Value);

impl<'de> serde::Deserialize<'de> for Strict {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(StrictVisitor).map(Strict)
    }
}

struct StrictVisitor;

impl<'de> serde::de::Visitor<'de> for StrictVisitor {
    type Value = Value;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, b: bool) -> Result<Value, E> {
        Ok(Value::Bool(b))
    }
    fn visit_i64<E>(self, x: i64) -> Result<Value, E> {
        Ok(Value::from(x))
    }
    fn visit_u64<E>(self, x: u64) -> Result<Value, E> {
        Ok(Value::from(x))
    }
    fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<Value, E> {
        serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| E::custom("number out of range"))
    }
    fn visit_str<E>(self, s: &str) -> Result<Value, E> {
        Ok(Value::String(s.to_string()))
    }
    fn visit_string<E>(self, s: String) -> Result<Value, E> {
        Ok(Value::String(s))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut v = Vec::new();
        while let Some(Strict(x)) = seq.next_element()? {
            v.push(x);
        }
        Ok(Value::Array(v))
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut m = Map::new();
        while let Some(k) = map.next_key::<String>()? {
            if m.contains_key(&k) {
                return Err(serde::de::Error::custom(format!(
                    "key `{k}` appears twice in one object"
                )));
            }
            let Strict(v) = map.next_value()?;
            m.insert(k, v);
        }
        Ok(Value::Object(m))
    }
}

fn field<'a>(o: &'a Map<String, Value>, k: &str) -> Result<&'a Value, Error> {
    o.get(k)
        .ok_or_else(|| Error::input(format!("missing key `{k}`")))
}

/// What a JSON value is, for messages.
fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// A JSON number as the f64 it denotes, finite; `what` names it in the message. Strings
/// (even "0.1"), null and booleans are refused: numbers are JSON numbers.
pub fn json_number(what: &str, v: &Value) -> Result<f64, Error> {
    match v {
        Value::Number(n) => finite(what, n.as_f64().unwrap_or(f64::NAN)),
        other => Err(Error::input(format!(
            "{what}: expected a number, got {}",
            kind(other)
        ))),
    }
}

/// A JSON array of numbers, every element read by [`json_number`]: none dropped,
/// padded or converted; the refusal names the element.
pub fn json_numbers(what: &str, v: &Value) -> Result<Vec<f64>, Error> {
    v.as_array()
        .ok_or_else(|| {
            Error::input(format!(
                "{what}: expected an array of numbers, got {}",
                kind(v)
            ))
        })?
        .iter()
        .enumerate()
        .map(|(i, x)| json_number(&format!("{what}[{i}]"), x))
        .collect()
}

fn json_num(o: &Map<String, Value>, k: &str) -> Result<f64, Error> {
    json_number(&format!("`{k}`"), field(o, k)?)
}

fn json_vec(o: &Map<String, Value>, k: &str) -> Result<Vec<f64>, Error> {
    json_numbers(&format!("`{k}`"), field(o, k)?)
}

fn json_uint(o: &Map<String, Value>, k: &str, lo: u64, hi: u64) -> Result<u64, Error> {
    field(o, k)?
        .as_u64()
        .filter(|n| (lo..=hi).contains(n))
        .ok_or_else(|| Error::input(format!("`{k}` must be an integer in {lo}..={hi}")))
}

/// Edit distance, for "did you mean".
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != b[j]))
                .min(row[j] + 1)
                .min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Refuse a key not in `known`, naming it, the nearest known key and all of them.
pub fn check_keys(o: &Map<String, Value>, known: &[&str], whose: &str) -> Result<(), Error> {
    for k in o.keys() {
        if known.contains(&k.as_str()) {
            continue;
        }
        let near = known
            .iter()
            .map(|c| (distance(k, c), *c))
            .filter(|(d, c)| *d <= 2.max(c.len() / 3))
            .min();
        let hint = near.map_or(String::new(), |(_, c)| format!("; did you mean `{c}`?"));
        return Err(Error::input(format!(
            "unknown key `{k}`{hint} (the keys of {whose}: {})",
            known.join(", ")
        )));
    }
    Ok(())
}

/// The scene of a batch query: its `"scene"` and `"params"` keys (the one place where a
/// JSON query's scene is read). `"scene"` is a scene name, or an object defining the scene
/// with the keys of a scene file (spec chapter 10); `"params"` is an object of numbers; a
/// parameter the scene does not have is refused when the scene is built.
pub fn scene_spec_from_json(o: &Map<String, Value>) -> Result<SceneSpec, Error> {
    let mut params = Vec::new();
    if let Some(p) = o.get("params") {
        let p = p.as_object().ok_or_else(|| {
            Error::input(format!(
                "`params` must be an object of numbers, got {}",
                kind(p)
            ))
        })?;
        for (k, v) in p {
            params.push((k.clone(), json_number(&format!("`params.{k}`"), v)?));
        }
    }
    match field(o, "scene")? {
        Value::String(name) => Ok(SceneSpec::named(name, params)),
        v @ Value::Object(_) => Ok(SceneSpec::defined(
            SceneFile::from_json(v)
                .map_err(|e| Error::input(format!("`scene`: {}", e.message())))?,
            params,
        )),
        other => Err(Error::input(format!(
            "`scene` must be a scene name (a string) or an object defining a scene, got {}",
            kind(other)
        ))),
    }
}

/// The keys every query may have.
const COMMON_KEYS: [&str; 5] = ["id", "cmd", "scene", "params", "deadline"];

/// The keys of a query of command `cmd` (`None` for an unknown command).
pub fn query_keys(cmd: &str) -> Option<Vec<&'static str>> {
    let own: &[&str] = match cmd {
        "flow" => &["q", "u", "t", "times", "order", "jacobian"],
        "retract" | "step" | "lagrangian" => &["q0", "q1", "h"],
        "integrate" => &["q0", "q1", "h", "scheme", "steps"],
        "check" => &["h", "t", "q", "tol", "defect_tol", "pairs"],
        _ => return None,
    };
    Some(COMMON_KEYS.iter().chain(own).copied().collect())
}

/// The `deadline` key of a batch query (seconds, > 0), if any.
pub fn deadline_from_json(v: &Value) -> Result<Option<f64>, Error> {
    match v.get("deadline") {
        None => Ok(None),
        Some(d) => check_seconds("`deadline`", json_number("`deadline`", d)?).map(Some),
    }
}

impl Query {
    /// A batch query object (contract command 5): the flags' names as keys. Strict: every
    /// key must be one its command reads (a near miss is named), every number a finite JSON
    /// number, every vector an array of them.
    pub fn from_json(v: &Value) -> Result<Query, Error> {
        let o = v
            .as_object()
            .ok_or_else(|| Error::input("a query must be a JSON object"))?;
        let cmd = match field(o, "cmd")? {
            Value::String(c) => c.as_str(),
            other => {
                return Err(Error::input(format!(
                    "`cmd` must be a string, got {}",
                    kind(other)
                )))
            }
        };
        let keys = query_keys(cmd).ok_or_else(|| {
            Error::input(format!(
                "unknown cmd `{cmd}` (known: flow, retract, step, integrate, lagrangian, check)"
            ))
        })?;
        check_keys(o, &keys, &format!("a `{cmd}` query"))?;
        deadline_from_json(v)?;
        let scene = scene_spec_from_json(o)?;
        let pair = |scene: SceneSpec| -> Result<Pair, Error> {
            Ok(Pair {
                scene,
                q0: json_vec(o, "q0")?,
                q1: json_vec(o, "q1")?,
                h: json_num(o, "h")?,
            })
        };
        match cmd {
            "flow" => Ok(Query::Flow {
                scene,
                q: json_vec(o, "q")?,
                u: json_vec(o, "u")?,
                t: match (o.get("t"), o.get("times")) {
                    (Some(_), None) => At::One(json_num(o, "t")?),
                    (None, Some(_)) => At::Many(json_vec(o, "times")?),
                    _ => return Err(Error::input("give exactly one of `t` and `times`")),
                },
                order: match o.get("order") {
                    None => 0,
                    Some(_) => json_uint(o, "order", 2, 60)? as usize,
                },
                jacobian: match o.get("jacobian") {
                    None => false,
                    Some(Value::Bool(b)) => *b,
                    Some(other) => {
                        return Err(Error::input(format!(
                            "`jacobian` must be true or false, got {}",
                            kind(other)
                        )))
                    }
                },
            }),
            "retract" => Ok(Query::Retract(pair(scene)?)),
            "step" => Ok(Query::Step(pair(scene)?)),
            "lagrangian" => Ok(Query::Lagrangian(pair(scene)?)),
            "check" => {
                let rows = match field(o, "q")? {
                    Value::Array(rows) => rows,
                    other => {
                        return Err(Error::input(format!(
                            "`q` must be an array of rows (arrays of numbers), got {}",
                            kind(other)
                        )))
                    }
                };
                let q = rows
                    .iter()
                    .enumerate()
                    .map(|(k, r)| json_numbers(&format!("`q`[{k}]"), r))
                    .collect::<Result<Vec<_>, _>>()?;
                let pairs = match o.get("pairs") {
                    None => true,
                    Some(Value::Bool(b)) => *b,
                    Some(other) => {
                        return Err(Error::input(format!(
                            "`pairs` must be true or false, got {}",
                            kind(other)
                        )))
                    }
                };
                let steps = match (o.get("h"), o.get("t")) {
                    (Some(_), None) => Steps::Uniform(json_num(o, "h")?),
                    (None, Some(_)) => Steps::Times(json_vec(o, "t")?),
                    _ => return Err(Error::input("give exactly one of `h` and `t`")),
                };
                Ok(Query::Check {
                    scene,
                    steps,
                    q,
                    tol: o.get("tol").map(|_| json_num(o, "tol")).transpose()?,
                    defect_tol: o
                        .get("defect_tol")
                        .map(|_| json_num(o, "defect_tol"))
                        .transpose()?,
                    pairs,
                })
            }
            _ => {
                let scheme = match field(o, "scheme")? {
                    Value::String(s) => s.parse()?,
                    other => {
                        return Err(Error::input(format!(
                            "`scheme` must be a string, got {}",
                            kind(other)
                        )))
                    }
                };
                let steps = json_uint(o, "steps", 0, MAX_STEPS as u64)? as usize;
                Ok(Query::Integrate {
                    pair: pair(scene)?,
                    scheme,
                    steps,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_lines_get_error_objects_and_ids_are_echoed() {
        let mut s = Session::default();
        assert_eq!(s.batch_line("   "), None);
        let a: Value = serde_json::from_str(&s.batch_line("{nope").unwrap()).unwrap();
        assert_eq!(a["id"], Value::Null);
        assert_eq!(a["error"]["code"], 2);
        let a: Value = serde_json::from_str(
            &s.batch_line(r#"{"id": [7], "cmd": "fly", "scene": "particle"}"#)
                .unwrap(),
        )
        .unwrap();
        assert_eq!(a["id"], json!([7]));
        assert_eq!(a["error"]["code"], 2);
        let a: Value = serde_json::from_str(
            &s.batch_line(r#"{"id": 1, "cmd": "flow", "scene": "particle", "q": [0,0,0], "u": [0.8,0.8], "t": 0.5}"#)
                .unwrap(),
        )
        .unwrap();
        assert_eq!(a["id"], 1);
        assert!(a["ok"]["q"][0][0].as_f64().unwrap() <= a["ok"]["q"][0][1].as_f64().unwrap());
    }
}
