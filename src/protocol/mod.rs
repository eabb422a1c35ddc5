//! Queries and answers (contract.md, commands 1-5): the one place where a request is
//! validated and turned into a library call, and the one place where an answer is
//! rendered. The command line and the batch protocol both go through [`Query`] and
//! [`Session::answer`], which returns a typed [`Answer`]; its JSON, text and CSV forms are
//! rendered in `answer.rs` and, row by row for the streaming commands, `rows.rs`. No
//! printing here. By subject: this file holds the queries, the session and the budgets;
//! `parse.rs` the strict readers of flags, JSON and batch lines.

mod answer;
pub mod order;
mod parse;
pub(crate) mod precise;
mod rows;

pub use answer::{
    description, error_object, exit_code, interval, intervals, scenes, stats, trajectory, verdict,
    Answer,
};
pub use parse::{
    check_keys, deadline_from_json, json_number, json_numbers, max_steps_from_json, parse_json,
    parse_max_steps, parse_num, parse_order, parse_param, parse_precision, parse_seconds,
    parse_steps, parse_vec, parse_work, query_keys, scene_spec_from_json, work_from_json, Line,
    LineReader, MAX_LINE_BYTES, MAX_PRECISION, MAX_STEP_LIMIT,
};
pub use rows::{CheckRows, IntegrateRows};

use crate::exact;
pub use crate::oracle::{Steps, Tolerances};
use crate::scalar::point;
use crate::scene::{Scene, SceneFile};
use crate::schemes::{NewtonOptions, Scheme, SchemeKind, Trajectory};
use crate::{AnyScene, Error, FlowOptions, Interval, Model};
use serde_json::{json, Value};
use std::collections::HashMap;
use std::rc::Rc;

/// A scene by name with its parameters, or a user's scene definition (a scene file or an
/// inline JSON object, [spec chapter 10](crate::spec::scene_files)) with the parameters that override its defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSpec {
    /// The built-in scene's name, or a user's scene's name (then for messages only).
    pub name: String,
    /// Parameter values `(name, value)` that override the scene's defaults.
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
    /// `flow` (contract command 1): the state at `t` from `q(0) = q`, `qd(0) = E(q)^T u`
    /// ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves)).
    Flow {
        /// The scene.
        scene: SceneSpec,
        /// The initial configuration (n numbers).
        q: Vec<f64>,
        /// The initial quasi-velocities (n - k numbers).
        u: Vec<f64>,
        /// One time (`t`) or many (`times`, dense output: [spec eq. (5.16)](crate::spec::enclosure), contract E11).
        t: At,
        /// The Taylor order: 2 to 60, or 0 (not given) for the automatic choice ([spec (5.8)](crate::spec::enclosure)).
        order: usize,
        /// Also the derivative D(q, u)(t) / D(q, u)(0) (`flow --jacobian`).
        jacobian: bool,
    },
    /// `flow`, `retract`, `step` or `lagrangian` computed with `precision > 53` significand
    /// bits ([spec/12-precision.md](crate::spec::precision), contract E18): the answer's ends are decimal strings
    /// rounded outward. Other queries are refused at a precision above 53.
    Precise {
        /// The significand bits asked for (at least; the answer says those used).
        precision: u32,
        /// The query.
        query: Box<Query>,
        /// With `--exact-decimals` (contract E22): the decimal texts of the query's vectors
        /// (flow: `q`, `u`; retract, step, lagrangian: `q0`, `q1`), read as exact decimals
        /// enclosed at the precision; `None`: the query's f64 values, as everywhere else.
        decimals: Option<Vec<Vec<String>>>,
    },
    /// `retract` (contract command 2): the exact retraction at the pair ([spec eqs.
    /// (6.2)-(6.4)](crate::spec::exact_discrete)).
    Retract(Pair),
    /// `step` (contract command 3): one step of the exact discrete flow with the Legendre
    /// transforms ([spec Theorem 6.2](crate::spec::exact_discrete)).
    Step(Pair),
    /// `lagrangian`: the exact discrete Lagrangian of the pair ([spec eqs. (6.7)-(6.8)](crate::spec::exact_discrete)).
    Lagrangian(Pair),
    /// `integrate` (contract command 4): the float sequence `q_0 .. q_N` of DLA or MLA.
    Integrate {
        /// The scene, `q0`, `q1` (moved onto M_h^d by the scheme, [spec eq. (7.3)](crate::spec::schemes)) and `h`.
        pair: Pair,
        /// DLA or MLA.
        scheme: SchemeKind,
        /// The number `N` of steps, at most [`MAX_STEPS`].
        steps: usize,
    },
    /// A certified verdict on a whole trajectory `q_0 .. q_N` of step `h`, or at times
    /// `t_0 < .. < t_N` (contract E12) (the `check` command's, as a batch query).
    Check {
        /// The scene.
        scene: SceneSpec,
        /// The step `h` of the rows, or their times.
        steps: Steps,
        /// The candidate `q_0 .. q_N`, one configuration per row.
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
    /// `order` (contract E15): the certified local and global order of DLA or MLA ([spec
    /// chapter 11](crate::spec::testing)).
    Order {
        /// The scene.
        scene: SceneSpec,
        /// DLA or MLA.
        scheme: SchemeKind,
        /// The initial configuration (n numbers).
        q: Vec<f64>,
        /// The initial quasi-velocities (n - k numbers).
        u: Vec<f64>,
        /// The largest step of the local ladder, `0 < h <= 1`.
        h: f64,
        /// The rungs of the local ladder, 2 to 12.
        rungs: usize,
    },
    /// `scenes` (contract E27): the description of one scene as compiled (a name or a
    /// user's definition, with its parameters), or of every built-in scene (`None`).
    Scenes {
        /// The scene, or `None` for every built-in one.
        scene: Option<SceneSpec>,
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
    /// The scene.
    pub scene: SceneSpec,
    /// The first configuration `Q0` (n numbers).
    pub q0: Vec<f64>,
    /// The second configuration `Q1` (n numbers).
    pub q1: Vec<f64>,
    /// The step `h` between them.
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
    /// Settings of the validated integrator for every query (a fuzzer lowers `max_taylor_steps`).
    pub flow: FlowOptions,
    /// Refuse `integrate` queries with more steps than this (0: the contract's maximum).
    pub max_integrate_steps: usize,
    /// Time budget in seconds of every query that names no budget (`batch --deadline`).
    pub deadline: Option<f64>,
    /// Work allowed to every query that names no budget ([`crate::work_done`] terms, [spec
    /// (5.8''')](crate::spec::enclosure)), on top of `flow.work_limit` (`batch --work`; the fuzz target
    /// `batch_line` sets it). When neither this nor [`Session::deadline`] is set, a query
    /// without a budget of its own gets [`default_work`]. Unlike a deadline a work limit
    /// replays the same on every machine.
    pub work: Option<u64>,
    /// The step limit of every query that names none (`batch --max-steps`, contract E24):
    /// replaces `flow.max_taylor_steps` when given.
    pub max_steps: Option<usize>,
    /// The stops of a `flow` with `times` proved before its refusal (contract E25), left by
    /// the last query answered; taken by the batch protocol's error object.
    certified: Option<Answer>,
}

/// A summary: the scenes compiled so far (by key) and the settings.
impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut scenes: Vec<&String> = self.models.keys().collect();
        scenes.sort();
        f.debug_struct("Session")
            .field("scenes", &scenes)
            .field("flow", &self.flow)
            .field("max_integrate_steps", &self.max_integrate_steps)
            .field("deadline", &self.deadline)
            .field("work", &self.work)
            .field("max_steps", &self.max_steps)
            .finish_non_exhaustive()
    }
}

/// The budget in seconds of a single-step query before budgets were counted in work: such
/// a query answers in milliseconds on ordinary input. Kept for callers that want a
/// wall-clock backstop of that size; no query gets it by default any more.
pub const STEP_DEADLINE: f64 = 5.0;

/// The default work budget ([`crate::work_done`] terms, [spec (5.8''')](crate::spec::enclosure)) of a single-step
/// query (`retract`, `step`, `lagrangian`, and each pair that `check` certifies) that names
/// no budget: far above what any ordinary query takes (contract E14 says how it was sized),
/// so it only stops a pathological one, and stops it at the same point on every machine.
pub const STEP_WORK: u64 = 1_000_000_000;

/// The budget of one query: a wall-clock `deadline` in seconds and a `work` limit in
/// [`crate::work_done`] terms, each `None` when not given. A query's budget is the one it
/// names, else the session's; when neither names a deadline nor a work limit, it is
/// [`default_work`] (contract E14).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Budget {
    /// Seconds (> 0), or `None`.
    pub deadline: Option<f64>,
    /// Work terms (> 0), or `None`.
    pub work: Option<u64>,
    /// The step limit of the validated flows (`--max-steps`, the `max_steps` key, contract
    /// E24): at most this many accepted Taylor steps; `None`, the session's or
    /// [`crate::FlowOptions::max_taylor_steps`]'s default (20000).
    pub max_steps: Option<usize>,
}

/// The documented default budget of a query that names none, in work: [`STEP_WORK`] for
/// the single-step queries, [`STEP_WORK`] per row for `check`, none for `flow` (bounded by
/// `FlowOptions::max_taylor_steps`) and `integrate` (bounded by its `steps`).
pub fn default_work(q: &Query) -> Option<u64> {
    match q {
        Query::Retract(_) | Query::Step(_) | Query::Lagrangian(_) => Some(STEP_WORK),
        Query::Check { q, .. } => Some(STEP_WORK.saturating_mul(q.len().max(1) as u64)),
        Query::Flow { .. }
        | Query::Integrate { .. }
        | Query::Order { .. }
        | Query::Scenes { .. } => None,
        Query::Precise { query, .. } => default_work(query),
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
    /// The compiled model of a scene ([spec eq. (3.16)](crate::spec::scenes)): from the session's cache, or compiled
    /// and cached now.
    pub fn model(&mut self, s: &SceneSpec) -> Result<Rc<Model>, Error> {
        let key = scene_key(s);
        if let Some(m) = self.models.get(&key) {
            return Ok(m.clone());
        }
        let m = Rc::new(match &s.definition {
            None => Model::new(&AnyScene::new(&s.name, &borrowed(&s.params))?)?,
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

    /// Answer a query, within the session's budget ([`Session::deadline`] and
    /// [`Session::work`], else [`default_work`]). [`Answer::to_json`] is the object its
    /// command prints with `--json`, [`Answer::to_text`] what it prints without.
    pub fn answer(&mut self, q: &Query) -> Result<Answer, Error> {
        self.answer_with(q, Budget::default())
    }

    /// As [`Session::answer`], within `seconds` when given (a query's own `deadline`).
    /// Past the budget: `Error::over_budget` (exit 3), never a partial answer.
    pub fn answer_within(&mut self, q: &Query, seconds: Option<f64>) -> Result<Answer, Error> {
        self.answer_with(
            q,
            Budget {
                deadline: seconds,
                ..Budget::default()
            },
        )
    }

    /// The budget a query runs within: its own `deadline` and `work` where given, else the
    /// session's; when neither names any, [`default_work`] (contract E14).
    pub fn budget_of(&self, q: &Query, own: Budget) -> Budget {
        let b = Budget {
            deadline: own.deadline.or(self.deadline),
            work: own.work.or(self.work),
            max_steps: own.max_steps.or(self.max_steps),
        };
        if b.deadline.is_none() && b.work.is_none() {
            Budget {
                work: default_work(q),
                ..b
            }
        } else {
            b
        }
    }

    /// The validated integrator's settings within a budget: the session's, with the
    /// earlier deadline and the work allowed from now on.
    fn options(&self, b: Budget) -> FlowOptions {
        let mut opts = self.flow.clone();
        opts.deadline = earlier(opts.deadline, b.deadline.and_then(deadline_in));
        if let Some(w) = b.work {
            opts = opts.allow_work(w);
        }
        if let Some(n) = b.max_steps {
            opts.max_taylor_steps = n;
        }
        opts
    }

    /// As [`Session::answer`], within the query's own budget `own` (its `deadline` and
    /// `work` keys or flags; [`Session::budget_of`] says which applies). Past the budget:
    /// exit 3 with reason `budget`, never a partial answer.
    pub fn answer_with(&mut self, q: &Query, own: Budget) -> Result<Answer, Error> {
        self.certified = None;
        let opts = self.options(self.budget_of(q, own));
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
                    order: (*order > 0).then_some(*order),
                    ..opts
                };
                let t = match t {
                    At::One(t) => *t,
                    At::Many(times) => {
                        if *jacobian {
                            return Err(Error::input_key(
                                "jacobian",
                                "`jacobian` is given only at one time `t`, not with `times`",
                            ));
                        }
                        return match crate::flow::flow_at_certified(&model, q, u, times, &o) {
                            Ok(enclosures) => Ok(Answer::FlowAt {
                                times: times.clone(),
                                enclosures,
                            }),
                            Err(r) => {
                                // the stops proved before the refusal (contract E25)
                                let (times, enclosures) = r.at.into_iter().unzip();
                                self.certified = Some(Answer::FlowAt { times, enclosures });
                                Err(r.error)
                            }
                        };
                    }
                };
                let (enclosure, jacobian) = if *jacobian {
                    let (e, j) = crate::flow::flow_c1(&model, q, u, t, &o)?;
                    (e, Some(j))
                } else {
                    (crate::flow(&model, q, u, t, &o)?, None)
                };
                Ok(Answer::Flow {
                    enclosure,
                    jacobian,
                })
            }
            Query::Precise {
                precision,
                query,
                decimals,
            } => {
                let model = self.model(precise::scene(query)?)?;
                let mut certified = None;
                let a = precise::answer(
                    *precision,
                    &model,
                    query,
                    decimals.as_deref(),
                    &opts,
                    &mut certified,
                );
                self.certified = certified;
                a
            }
            Query::Retract(p) => {
                let model = self.model(&p.scene)?;
                let r = exact::retract(&model, &points(&p.q0), &points(&p.q1), p.h, &opts)?;
                Ok(Answer::Retract(r))
            }
            Query::Step(p) => {
                let model = self.model(&p.scene)?;
                let s = exact::step(&model, &points(&p.q0), &points(&p.q1), p.h, &opts)?;
                Ok(Answer::Step(s))
            }
            Query::Lagrangian(p) => {
                let model = self.model(&p.scene)?;
                let (retraction, l) =
                    exact::discrete_lagrangian(&model, &points(&p.q0), &points(&p.q1), p.h, &opts)?;
                Ok(Answer::Lagrangian { l, retraction })
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
                tols.require_pairs(*pairs)?;
                let o = crate::oracle::CheckOptions {
                    pairs: *pairs,
                    flow: opts,
                };
                let verdict = crate::oracle::check_trajectory(&model, steps, q, &o)?;
                let passed = tols.passes(verdict.max_distance, verdict.max_defect)?;
                Ok(Answer::Check {
                    verdict,
                    tolerances: tols,
                    passed,
                })
            }
            Query::Order {
                scene,
                scheme,
                q,
                u,
                h,
                rungs,
            } => {
                let model = self.model(scene)?;
                // a stepper of its own (the kit's steppers take `&mut self`)
                let mut s = Scheme::new(&model, *scheme);
                let a = order::answer(&model, &mut s, q, u, *h, *rungs, &opts, None)?;
                Ok(Answer::Order(a))
            }
            Query::Scenes { scene } => Ok(Answer::Scenes(match scene {
                None => crate::scene::SCENES
                    .iter()
                    .map(|s| s.description())
                    .collect(),
                Some(s) => vec![self.model(s)?.scene.description()],
            })),
            Query::Integrate {
                pair,
                scheme,
                steps,
            } => {
                let mut tr = Trajectory {
                    q: Vec::new(),
                    p: Vec::new(),
                    energy: Vec::new(),
                    iterations: Vec::new(),
                    max_residual: 0.0,
                };
                tr.max_residual =
                    self.integrate_each_with(pair, *scheme, *steps, own, |r: Row| {
                        tr.q.push(r.q.to_vec());
                        tr.p.extend(r.p.map(<[f64]>::to_vec));
                        tr.energy.extend(r.energy);
                        tr.iterations.extend(r.iterations);
                        Ok(())
                    })?;
                Ok(Answer::Integrate(tr))
            }
        }
    }

    /// An `integrate` query row by row in constant memory (the command line's `integrate`
    /// and batch's both run here): the scene is checked at `q0` and `q1` ([spec (3.17)](crate::spec::scenes)), then `row` gets q_k, p_k and the
    /// energy for k = 0..=steps in order, as soon as each is known; returns the largest
    /// Newton residual. Within `seconds` when given, else the session's budget; past it, or
    /// when `row` fails, the integration stops with that error.
    pub fn integrate_each(
        &mut self,
        pair: &Pair,
        scheme: SchemeKind,
        steps: usize,
        seconds: Option<f64>,
        row: impl FnMut(Row) -> Result<(), Error>,
    ) -> Result<f64, Error> {
        let own = Budget {
            deadline: seconds,
            ..Budget::default()
        };
        self.integrate_each_with(pair, scheme, steps, own, row)
    }

    /// As [`Session::integrate_each`], within the query's own budget `own` (an
    /// `integrate` query has no default budget: [`Session::budget_of`]), checked before
    /// each row.
    pub fn integrate_each_with(
        &mut self,
        pair: &Pair,
        scheme: SchemeKind,
        steps: usize,
        own: Budget,
        mut row: impl FnMut(Row) -> Result<(), Error>,
    ) -> Result<f64, Error> {
        if self.max_integrate_steps > 0 && steps > self.max_integrate_steps {
            return Err(Error::input_key(
                "steps",
                format!(
                    "steps: at most {} in this session",
                    self.max_integrate_steps
                ),
            ));
        }
        let budget = self.options(Budget {
            deadline: own.deadline.or(self.deadline),
            work: own.work.or(self.work),
            max_steps: None,
        });
        // the scene's structure at both start configurations (spec (3.17))
        let model = self.model(&pair.scene)?;
        for q in [&pair.q0, &pair.q1] {
            if q.len() == model.n && q.iter().all(|x| x.is_finite()) {
                model.check_at(&q.iter().map(|x| point(*x)).collect::<Vec<_>>())?;
            }
        }
        let sc = self.scheme(&pair.scene, scheme)?;
        sc.integrate_each(
            &pair.q0,
            &pair.q1,
            pair.h,
            steps,
            &NewtonOptions::default(),
            |r: Row| {
                budget.check_budget()?;
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
                            let own = Budget {
                                deadline: deadline_from_json(&v)?,
                                work: work_from_json(&v)?,
                                max_steps: max_steps_from_json(&v)?,
                            };
                            let a = self.answer_with(&q, own)?;
                            answered = Some(q);
                            Ok(a.to_json())
                        });
                        (id, r)
                    }
                },
            },
        };
        let out = match result {
            Ok(ok) => json!({"id": id, "ok": ok}),
            Err(e) => {
                let mut o = error_object(&e);
                // a `flow` with `times` refused after some stops: those stops (E25)
                if let Some(a) = self.certified.take().filter(|_| exit_code(&e) == 3) {
                    o["at"] = a.to_json()["at"].take();
                }
                json!({"id": id, "error": o})
            }
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
    /// The answer line (JSON, without a line end).
    pub text: String,
    /// The query that was answered, when the answer is `ok`; `None` for an error.
    pub answered: Option<Query>,
}

fn points(v: &[f64]) -> Vec<Interval> {
    v.iter().map(|x| Interval::point(*x)).collect()
}

/// Whether a verdict passes the tolerance ([spec (8.3)](crate::spec::oracle)): `true` when `max_distance <= tol`
/// is proved (or no tolerance is given), `false` when `max_distance > tol` is proved; a
/// distance enclosure straddling `tol` decides nothing and is refused (exit 3).
pub fn tolerance_verdict(v: &crate::oracle::Verdict, tol: Option<f64>) -> Result<bool, Error> {
    tolerance_decision(v.max_distance, tol)
}

/// [`tolerance_verdict`] on the certified maximum distance alone.
pub fn tolerance_decision(max_distance: Interval, tol: Option<f64>) -> Result<bool, Error> {
    Tolerances {
        tol,
        defect_tol: None,
    }
    .passes(max_distance, None)
}

/// Parameters with owned names, borrowed as [`AnyScene::new`] takes them.
pub(crate) fn borrowed(params: &[(String, f64)]) -> Vec<(&str, f64)> {
    params.iter().map(|(k, v)| (k.as_str(), *v)).collect()
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
