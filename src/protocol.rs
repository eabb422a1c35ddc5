//! Queries and answers as JSON values (contract.md, commands 1-5): the one place where a
//! request is validated and turned into a library call. The command line and the batch
//! protocol both go through [`Query`] and [`Session::answer`]. No printing here.

use crate::exact;
use crate::integrator::{NewtonOptions, Scheme, SchemeKind, Trajectory};
use crate::scalar::point;
use crate::scene::{Description, Scene, SceneFile};
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
        t: f64,
        order: usize,
    },
    Retract(Pair),
    Step(Pair),
    Lagrangian(Pair),
    Integrate {
        pair: Pair,
        scheme: SchemeKind,
        steps: usize,
    },
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
}

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

    /// Answer a query with the JSON object its command prints with `--json`.
    pub fn answer(&mut self, q: &Query) -> Result<Value, Error> {
        let opts = self.flow.clone();
        match q {
            Query::Flow {
                scene,
                q,
                u,
                t,
                order,
            } => {
                let model = self.model(scene)?;
                let o = FlowOptions {
                    order: *order,
                    ..opts
                };
                let e = crate::flow(&model, q, u, *t, &o)?;
                Ok(json!({
                    "q": intervals(&e.q),
                    "v": intervals(&e.v),
                    "u": intervals(&e.u),
                    "stats": stats(&e.stats),
                }))
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
                let tr = sc.integrate(
                    &pair.q0,
                    &pair.q1,
                    pair.h,
                    *steps,
                    &NewtonOptions::default(),
                )?;
                Ok(trajectory(&tr))
            }
        }
    }

    /// One line of the batch protocol (contract command 5): `None` for a blank line, else
    /// the answer line `{"id": .., "ok": ..}` or `{"id": .., "error": {"code", "message"}}`.
    pub fn batch_line(&mut self, line: &str) -> Option<String> {
        if line.trim().is_empty() {
            return None;
        }
        let (id, result) = match serde_json::from_str::<Value>(line) {
            Err(e) => (Value::Null, Err(Error::input(format!("not JSON: {e}")))),
            Ok(v) => {
                let id = v.get("id").cloned().unwrap_or(Value::Null);
                (id, Query::from_json(&v).and_then(|q| self.answer(&q)))
            }
        };
        let out = match result {
            Ok(ok) => json!({"id": id, "ok": ok}),
            Err(e) => json!({"id": id, "error": {"code": e.code(), "message": e.message()}}),
        };
        Some(out.to_string())
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

fn field<'a>(o: &'a Map<String, Value>, k: &str) -> Result<&'a Value, Error> {
    o.get(k)
        .ok_or_else(|| Error::input(format!("missing field `{k}`")))
}

fn json_num(o: &Map<String, Value>, k: &str) -> Result<f64, Error> {
    let x = field(o, k)?
        .as_f64()
        .ok_or_else(|| Error::input(format!("`{k}` must be a number")))?;
    finite(k, x)
}

fn json_vec(o: &Map<String, Value>, k: &str) -> Result<Vec<f64>, Error> {
    field(o, k)?
        .as_array()
        .ok_or_else(|| Error::input(format!("`{k}` must be an array of numbers")))?
        .iter()
        .map(|x| {
            x.as_f64()
                .ok_or_else(|| Error::input(format!("`{k}` must be an array of numbers")))
                .and_then(|x| finite(k, x))
        })
        .collect()
}

/// The `scene` and `params` keys of a query: a scene name, or a JSON object defining the
/// scene with the keys of a scene file (spec chapter 10).
fn scene_spec_from_json(o: &Map<String, Value>) -> Result<SceneSpec, Error> {
    let mut params = Vec::new();
    if let Some(p) = o.get("params") {
        let p = p
            .as_object()
            .ok_or_else(|| Error::input("`params` must be an object"))?;
        for (k, _) in p {
            params.push((k.clone(), json_num(p, k)?));
        }
    }
    match field(o, "scene")? {
        Value::String(name) => Ok(SceneSpec::named(name, params)),
        v @ Value::Object(_) => Ok(SceneSpec::defined(
            SceneFile::from_json(v).map_err(|e| Error::input(format!("scene: {}", e.message())))?,
            params,
        )),
        _ => Err(Error::input(
            "`scene` must be a scene name or an object defining a scene",
        )),
    }
}

impl Query {
    /// A batch query object (contract command 5): the flags' names as keys.
    pub fn from_json(v: &Value) -> Result<Query, Error> {
        let o = v
            .as_object()
            .ok_or_else(|| Error::input("a query must be a JSON object"))?;
        let cmd = field(o, "cmd")?
            .as_str()
            .ok_or_else(|| Error::input("`cmd` must be a string"))?;
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
                t: json_num(o, "t")?,
                order: match o.get("order") {
                    None => 0,
                    Some(v) => parse_order(&v.to_string())?,
                },
            }),
            "retract" => Ok(Query::Retract(pair(scene)?)),
            "step" => Ok(Query::Step(pair(scene)?)),
            "lagrangian" => Ok(Query::Lagrangian(pair(scene)?)),
            "integrate" => {
                let scheme = field(o, "scheme")?
                    .as_str()
                    .ok_or_else(|| Error::input("`scheme` must be a string"))?
                    .parse()?;
                let steps = field(o, "steps")?
                    .as_u64()
                    .filter(|n| *n as usize <= MAX_STEPS)
                    .ok_or_else(|| {
                        Error::input(format!("`steps` must be an integer in 0..={MAX_STEPS}"))
                    })? as usize;
                Ok(Query::Integrate {
                    pair: pair(scene)?,
                    scheme,
                    steps,
                })
            }
            other => Err(Error::input(format!(
                "unknown cmd `{other}` (known: flow, retract, step, integrate, lagrangian)"
            ))),
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
