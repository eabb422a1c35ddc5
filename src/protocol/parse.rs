//! The strict readers: numbers and vectors of the flags, JSON texts (no repeated key, every
//! number finite), batch queries (`Query::from_json`), and the lines of a batch stream.

use super::{At, Pair, Query, SceneSpec, Steps, MAX_STEPS};
use crate::scene::SceneFile;
use crate::{Error, InputKind};
use serde_json::{Map, Value};

/// Longest batch line read, in bytes (without its newline): 1 MiB. A longer line is not
/// kept in memory; it gets an error answer and the stream goes on.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// A line of a batch stream.
#[derive(Clone, Debug, PartialEq)]
pub enum Line {
    /// The bytes of the line, without its `\n`.
    Text(Vec<u8>),
    /// A line longer than the limit, and how long it was.
    TooLong {
        /// The line's length in bytes, without its `\n`.
        bytes: u64,
    },
}

/// Lines of bytes from a reader, each at most `limit` bytes kept: a longer line is skipped
/// to its end without being held (memory stays `limit` plus the reader's buffer).
#[derive(Debug)]
pub struct LineReader<R> {
    inner: R,
    limit: usize,
}

impl<R: std::io::BufRead> LineReader<R> {
    /// Lines of `inner`, at most `limit` bytes of each kept.
    pub fn new(inner: R, limit: usize) -> Self {
        LineReader { inner, limit }
    }

    /// The reader underneath (to see what it holds already read).
    pub fn get_ref(&self) -> &R {
        &self.inner
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

/// A decimal literal read as the nearest f64 (Rust's parser is correctly rounded);
/// non-finite values and anything but a plain decimal literal are input errors.
pub fn parse_num(name: &str, s: &str) -> Result<f64, Error> {
    let t = s.trim();
    let ok_chars = !t.is_empty()
        && t.chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'));
    let x: f64 = if ok_chars { t.parse().ok() } else { None }
        .ok_or_else(|| Error::input_key(name, format!("{name}: `{s}` is not a decimal number")))?;
    finite(InputKind::Key(name.to_string()), name, x)
}

fn finite(kind: InputKind, name: &str, x: f64) -> Result<f64, Error> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::input_at(
            kind,
            format!("{name}: not a finite number"),
        ))
    }
}

/// A comma-separated vector without spaces.
pub fn parse_vec(name: &str, s: &str) -> Result<Vec<f64>, Error> {
    s.split(',').map(|x| parse_num(name, x)).collect()
}

/// `name=value`.
pub fn parse_param(s: &str) -> Result<(String, f64), Error> {
    let (k, v) = s.split_once('=').ok_or_else(|| {
        Error::input_key("param", format!("param: expected name=value, got `{s}`"))
    })?;
    Ok((k.to_string(), parse_num("param", v)?))
}

/// `--steps`: an integer in `0..=MAX_STEPS`.
pub fn parse_steps(s: &str) -> Result<usize, Error> {
    match s.trim().parse::<usize>() {
        Ok(n) if n <= MAX_STEPS => Ok(n),
        _ => Err(Error::input_key(
            "steps",
            format!("steps: expected an integer in 0..={MAX_STEPS}, got `{s}`"),
        )),
    }
}

/// `--order`: a Taylor order, an integer in `2..=60` ([spec (5.8)](crate::spec::enclosure)).
pub fn parse_order(s: &str) -> Result<usize, Error> {
    match s.trim().parse::<usize>() {
        Ok(p) if (2..=60).contains(&p) => Ok(p),
        _ => Err(Error::input_key(
            "order",
            format!("order: expected an integer in 2..=60, got `{s}`"),
        )),
    }
}

/// The most significand bits a query may ask for (`--precision`, the `precision` key).
pub const MAX_PRECISION: u32 = 4096;

/// `--precision`: significand bits, an integer in `53..=MAX_PRECISION`
/// ([spec/12-precision.md](crate::spec::precision), contract E18).
pub fn parse_precision(s: &str) -> Result<u32, Error> {
    match s.trim().parse::<u32>() {
        Ok(p) if (53..=MAX_PRECISION).contains(&p) => Ok(p),
        _ => Err(Error::input_key(
            "precision",
            format!("precision: expected a number of bits in 53..={MAX_PRECISION}, got `{s}`"),
        )),
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
        Err(Error::input_key(
            name,
            format!("{name}: a budget in seconds must be > 0 (got {x})"),
        ))
    }
}

/// A work budget ([`crate::work_done`] terms, [spec (5.8''')](crate::spec::enclosure)): an integer >= 1 (`--work`).
pub fn parse_work(name: &str, s: &str) -> Result<u64, Error> {
    match s.trim().parse::<u64>() {
        Ok(w) if w >= 1 => Ok(w),
        _ => Err(Error::input(format!(
            "{name}: a work budget must be an integer in 1..={} (got `{s}`)",
            u64::MAX
        ))),
    }
}

/// The largest step limit accepted (`--max-steps`, the `max_steps` key): 10^9 accepted
/// steps, far beyond what any deadline or work budget lets a flow take.
pub const MAX_STEP_LIMIT: usize = 1_000_000_000;

/// `--max-steps`: the step limit of the validated flows (contract E24), an integer in
/// `1..=MAX_STEP_LIMIT`.
pub fn parse_max_steps(name: &str, s: &str) -> Result<usize, Error> {
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_STEP_LIMIT).contains(&n) => Ok(n),
        _ => Err(Error::input_key(
            name.trim_start_matches('-'),
            format!("{name}: a step limit must be an integer in 1..={MAX_STEP_LIMIT} (got `{s}`)"),
        )),
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
        .ok_or_else(|| Error::input_key(k, format!("missing key `{k}`")))
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
    number_at(InputKind::Key(what.to_string()), what, v)
}

/// [`json_number`], its refusal of kind `at`.
fn number_at(at: InputKind, what: &str, v: &Value) -> Result<f64, Error> {
    match v {
        Value::Number(n) => finite(at, what, n.as_f64().unwrap_or(f64::NAN)),
        other => Err(Error::input_at(
            at,
            format!("{what}: expected a number, got {}", kind(other)),
        )),
    }
}

/// A JSON array of numbers, every element read by [`json_number`]: none dropped,
/// padded or converted; the refusal names the element.
pub fn json_numbers(what: &str, v: &Value) -> Result<Vec<f64>, Error> {
    numbers_at(what, what, v)
}

/// [`json_numbers`] for the list under the key `key`: a refusal of the list is of kind
/// [`InputKind::Key`], of one element [`InputKind::Element`].
fn numbers_at(key: &str, what: &str, v: &Value) -> Result<Vec<f64>, Error> {
    let list = InputKind::Key(key.to_string());
    numbers_with(list, what, v, |index| InputKind::Element {
        key: key.to_string(),
        index,
    })
}

/// A JSON array of numbers: refused as `list` when it is not an array, an element `i` as
/// `element(i)`.
fn numbers_with(
    list: InputKind,
    what: &str,
    v: &Value,
    element: impl Fn(usize) -> InputKind,
) -> Result<Vec<f64>, Error> {
    v.as_array()
        .ok_or_else(|| {
            Error::input_at(
                list,
                format!("{what}: expected an array of numbers, got {}", kind(v)),
            )
        })?
        .iter()
        .enumerate()
        .map(|(i, x)| number_at(element(i), &format!("{what}[{i}]"), x))
        .collect()
}

fn json_num(o: &Map<String, Value>, k: &str) -> Result<f64, Error> {
    number_at(
        InputKind::Key(k.to_string()),
        &format!("`{k}`"),
        field(o, k)?,
    )
}

fn json_vec(o: &Map<String, Value>, k: &str) -> Result<Vec<f64>, Error> {
    numbers_at(k, &format!("`{k}`"), field(o, k)?)
}

fn json_uint(o: &Map<String, Value>, k: &str, lo: u64, hi: u64) -> Result<u64, Error> {
    field(o, k)?
        .as_u64()
        .filter(|n| (lo..=hi).contains(n))
        .ok_or_else(|| Error::input_key(k, format!("`{k}` must be an integer in {lo}..={hi}")))
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
        return Err(Error::input_key(
            k,
            format!(
                "unknown key `{k}`{hint} (the keys of {whose}: {})",
                known.join(", ")
            ),
        ));
    }
    Ok(())
}

/// The scene of a batch query: its `"scene"` and `"params"` keys (the one place where a
/// JSON query's scene is read). `"scene"` is a scene name, or an object defining the scene
/// with the keys of a scene file ([spec chapter 10](crate::spec::scene_files)); `"params"` is an object of numbers; a
/// parameter the scene does not have is refused when the scene is built.
pub fn scene_spec_from_json(o: &Map<String, Value>) -> Result<SceneSpec, Error> {
    let mut params = Vec::new();
    if let Some(p) = o.get("params") {
        let p = p.as_object().ok_or_else(|| {
            Error::input_key(
                "params",
                format!("`params` must be an object of numbers, got {}", kind(p)),
            )
        })?;
        for (k, v) in p {
            let at = InputKind::Parameter(k.clone());
            params.push((k.clone(), number_at(at, &format!("`params.{k}`"), v)?));
        }
    }
    match field(o, "scene")? {
        Value::String(name) => Ok(SceneSpec::named(name, params)),
        v @ Value::Object(_) => Ok(SceneSpec::defined(
            SceneFile::from_json(v)
                .map_err(|e| Error::input_key("scene", format!("`scene`: {}", e.message())))?,
            params,
        )),
        other => Err(Error::input_key(
            "scene",
            format!(
                "`scene` must be a scene name (a string) or an object defining a scene, got {}",
                kind(other)
            ),
        )),
    }
}

/// The keys every query may have.
const COMMON_KEYS: [&str; 6] = ["id", "cmd", "scene", "params", "deadline", "work"];

/// The keys of a query of command `cmd` (`None` for an unknown command).
pub fn query_keys(cmd: &str) -> Option<Vec<&'static str>> {
    let own: &[&str] = match cmd {
        "flow" => &[
            "q",
            "u",
            "t",
            "times",
            "order",
            "jacobian",
            "precision",
            "max_steps",
        ],
        "retract" | "step" | "lagrangian" => &["q0", "q1", "h", "precision", "max_steps"],
        "integrate" => &["q0", "q1", "h", "scheme", "steps"],
        "check" => &[
            "h",
            "t",
            "q",
            "tol",
            "defect_tol",
            "pairs",
            "precision",
            "max_steps",
        ],
        "order" => &["scheme", "q", "u", "h", "rungs", "precision", "max_steps"],
        "scenes" => &[],
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

/// The `max_steps` key of a batch query (an integer in `1..=MAX_STEP_LIMIT`, contract
/// E24), if any.
pub fn max_steps_from_json(v: &Value) -> Result<Option<usize>, Error> {
    match v.get("max_steps") {
        None => Ok(None),
        Some(n) => match n.as_u64() {
            Some(k) if (1..=MAX_STEP_LIMIT as u64).contains(&k) => Ok(Some(k as usize)),
            _ => Err(Error::input_key(
                "max_steps",
                format!(
                    "`max_steps` must be an integer in 1..={MAX_STEP_LIMIT}, got {}",
                    match n {
                        Value::Number(x) => x.to_string(),
                        other => kind(other).to_string(),
                    }
                ),
            )),
        },
    }
}

/// The `work` key of a batch query (an integer >= 1, [`crate::work_done`] terms), if any.
pub fn work_from_json(v: &Value) -> Result<Option<u64>, Error> {
    match v.get("work") {
        None => Ok(None),
        Some(w) => match w.as_u64() {
            Some(n) if n >= 1 => Ok(Some(n)),
            _ => Err(Error::input(format!(
                "`work` must be an integer in 1..={}, got {}",
                u64::MAX,
                match w {
                    Value::Number(n) => n.to_string(),
                    other => kind(other).to_string(),
                }
            ))),
        },
    }
}

impl Query {
    /// A batch query object (contract command 5): the flags' names as keys. Strict: every
    /// key must be one its command reads (a near miss is named), every number a finite JSON
    /// number, every vector an array of them. A `precision` above 53 (flow, retract, step,
    /// lagrangian; contract E18) wraps the query in [`Query::Precise`].
    pub fn from_json(v: &Value) -> Result<Query, Error> {
        let q = Query::from_json_f64(v)?;
        match v.get("precision") {
            None => Ok(q),
            Some(_) => {
                let o = v
                    .as_object()
                    .ok_or_else(|| Error::input("a query must be a JSON object"))?;
                let bits = json_uint(o, "precision", 53, MAX_PRECISION as u64)? as u32;
                Ok(if bits > 53 {
                    Query::Precise {
                        precision: bits,
                        query: Box::new(q),
                        decimals: None,
                    }
                } else {
                    q
                })
            }
        }
    }

    fn from_json_f64(v: &Value) -> Result<Query, Error> {
        let o = v
            .as_object()
            .ok_or_else(|| Error::input("a query must be a JSON object"))?;
        let cmd = match field(o, "cmd")? {
            Value::String(c) => c.as_str(),
            other => {
                return Err(Error::input_key(
                    "cmd",
                    format!("`cmd` must be a string, got {}", kind(other)),
                ))
            }
        };
        let keys = query_keys(cmd).ok_or_else(|| {
            Error::input_key(
                "cmd",
                format!(
                    "unknown cmd `{cmd}` (known: flow, retract, step, integrate, lagrangian, check, order, scenes)"
                ),
            )
        })?;
        check_keys(o, &keys, &format!("a `{cmd}` query"))?;
        deadline_from_json(v)?;
        work_from_json(v)?;
        max_steps_from_json(v)?;
        if cmd == "scenes" {
            // every built-in scene without `scene` (contract E27)
            if o.get("scene").is_none() {
                if o.contains_key("params") {
                    return Err(Error::input_key(
                        "params",
                        "`params` goes with `scene` (the scene whose parameters they are)",
                    ));
                }
                return Ok(Query::Scenes { scene: None });
            }
            return Ok(Query::Scenes {
                scene: Some(scene_spec_from_json(o)?),
            });
        }
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
                    _ => return Err(Error::input_key("t", "give exactly one of `t` and `times`")),
                },
                order: match o.get("order") {
                    None => 0,
                    Some(_) => json_uint(o, "order", 2, 60)? as usize,
                },
                jacobian: match o.get("jacobian") {
                    None => false,
                    Some(Value::Bool(b)) => *b,
                    Some(other) => {
                        return Err(Error::input_key(
                            "jacobian",
                            format!("`jacobian` must be true or false, got {}", kind(other)),
                        ))
                    }
                },
            }),
            "order" => Ok(Query::Order {
                scene,
                scheme: match field(o, "scheme")? {
                    Value::String(s) => s.parse()?,
                    other => {
                        return Err(Error::input(format!(
                            "`scheme` must be a string, got {}",
                            kind(other)
                        )))
                    }
                },
                q: json_vec(o, "q")?,
                u: json_vec(o, "u")?,
                h: match o.get("h") {
                    None => super::order::DEFAULT_H,
                    Some(_) => super::order::check_h("`h`", json_num(o, "h")?)?,
                },
                rungs: match o.get("rungs") {
                    None => super::order::DEFAULT_RUNGS,
                    Some(_) => {
                        let r = &super::order::RUNGS;
                        json_uint(o, "rungs", *r.start() as u64, *r.end() as u64)? as usize
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
                        return Err(Error::input_key(
                            "q",
                            format!(
                                "`q` must be an array of rows (arrays of numbers), got {}",
                                kind(other)
                            ),
                        ))
                    }
                };
                let q = rows
                    .iter()
                    .enumerate()
                    .map(|(k, r)| {
                        let row = InputKind::Row {
                            row: k,
                            column: None,
                        };
                        numbers_with(row, &format!("`q`[{k}]"), r, |i| InputKind::Row {
                            row: k,
                            column: Some(i),
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                let pairs = match o.get("pairs") {
                    None => true,
                    Some(Value::Bool(b)) => *b,
                    Some(other) => {
                        return Err(Error::input_key(
                            "pairs",
                            format!("`pairs` must be true or false, got {}", kind(other)),
                        ))
                    }
                };
                let steps = match (o.get("h"), o.get("t")) {
                    (Some(_), None) => Steps::Uniform(json_num(o, "h")?),
                    (None, Some(_)) => Steps::Times(json_vec(o, "t")?),
                    _ => return Err(Error::input_key("h", "give exactly one of `h` and `t`")),
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
                        return Err(Error::input_key(
                            "scheme",
                            format!("`scheme` must be a string, got {}", kind(other)),
                        ))
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
