//! Scene files ([spec/10-scene-files.md](crate::spec::scene_files)): a system posed as a TOML file or as an inline JSON
//! object with the same keys, read into a checked [`SceneFile`] that is a [`Scene`] like any
//! other (its expressions are evaluated over any scalar by walking their parsed trees).
//!
//! Every refusal is an input error of one line saying what and where.

use super::expr::{self, is_identifier, is_reserved, shown, Expr, Names, Sym};
use super::{derived_basis, identity, Description, Mat, Scene};
use crate::model::MAX_DIM;
use crate::scalar::Scalar;
use crate::Error;
use std::path::Path;

/// The keys of a scene, in the order they are checked and listed.
pub const KEYS: &[&str] = &[
    "name",
    "coordinates",
    "quasi_velocities",
    "parameters",
    "mass",
    "potential",
    "one_form",
    "constraints",
    "basis",
    "free",
];

/// The name of a scene read from an inline JSON object without `name`.
pub const INLINE_NAME: &str = "inline";

/// The largest magnitude of an integer written as a TOML or JSON integer (beyond it an
/// integer is not always an f64).
const MAX_EXACT_INT: i128 = 1 << 53;

/// The most constraints a derived basis takes: Cramer's rule with determinants expanded by
/// cofactors costs about k! k^2 (n - k) operations to record.
pub const MAX_DERIVED_K: usize = 6;

/// One expression: the text as written (whitespace runs shown as one space) and its tree.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    text: String,
    expr: Expr,
}

#[derive(Clone, Debug, PartialEq)]
enum BasisSpec {
    Given(Vec<Vec<Entry>>),
    /// The free coordinates of the derived basis ([spec eq. (3.15)](crate::spec::scenes)).
    Free(Vec<usize>),
}

/// A scene read from a TOML file or an inline JSON object, checked: names, sizes and every
/// expression. [`crate::Model::new`] then records it on tapes and checks its structure.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFile {
    name: String,
    coordinates: Vec<String>,
    velocities: Vec<String>,
    params: Vec<(String, f64)>,
    param_names: Vec<String>,
    mass: Option<Vec<Vec<Entry>>>,
    potential: Option<Entry>,
    one_form: Option<Vec<Entry>>,
    constraints: Vec<Vec<Entry>>,
    basis: BasisSpec,
}

/// A TOML or JSON value, reduced to what the format distinguishes (so both readers share
/// one checker and give the same errors).
enum Val {
    Str(String),
    Int(i128),
    Float(f64),
    Bool,
    Arr(Vec<Val>),
    Obj(Vec<(String, Val)>),
    /// Anything else (a date-time, null, or a value nested deeper than the format goes).
    Other(&'static str),
}

/// Deeper than any value of the format (scene, matrix, row, entry).
const MAX_NESTING: usize = 4;

impl Val {
    fn kind(&self) -> &'static str {
        match self {
            Val::Str(_) => "a string",
            Val::Int(_) => "an integer",
            Val::Float(_) => "a float",
            Val::Bool => "a boolean",
            Val::Arr(_) => "an array",
            Val::Obj(_) => "a table",
            Val::Other(k) => k,
        }
    }

    fn from_toml(v: &toml::Value, depth: usize) -> Val {
        use toml::Value as T;
        if depth > MAX_NESTING {
            return Val::Other("a nested value");
        }
        match v {
            T::String(s) => Val::Str(s.clone()),
            T::Integer(i) => Val::Int(*i as i128),
            T::Float(f) => Val::Float(*f),
            T::Boolean(_) => Val::Bool,
            T::Datetime(_) => Val::Other("a date-time"),
            T::Array(a) => Val::Arr(a.iter().map(|x| Val::from_toml(x, depth + 1)).collect()),
            T::Table(t) => Val::Obj(
                t.iter()
                    .map(|(k, x)| (k.clone(), Val::from_toml(x, depth + 1)))
                    .collect(),
            ),
        }
    }

    fn from_json(v: &serde_json::Value, depth: usize) -> Val {
        use serde_json::Value as J;
        if depth > MAX_NESTING {
            return Val::Other("a nested value");
        }
        match v {
            J::String(s) => Val::Str(s.clone()),
            J::Number(n) => {
                if let Some(i) = n.as_i64() {
                    Val::Int(i as i128)
                } else if let Some(u) = n.as_u64() {
                    Val::Int(u as i128)
                } else {
                    // serde_json reads a decimal as the nearest f64 (float_roundtrip)
                    Val::Float(n.as_f64().unwrap_or(f64::NAN))
                }
            }
            J::Bool(_) => Val::Bool,
            J::Null => Val::Other("null"),
            J::Array(a) => Val::Arr(a.iter().map(|x| Val::from_json(x, depth + 1)).collect()),
            J::Object(o) => Val::Obj(
                o.iter()
                    .map(|(k, x)| (k.clone(), Val::from_json(x, depth + 1)))
                    .collect(),
            ),
        }
    }
}

/// A number of the format (a parameter value or a plain-number expression): finite, and an
/// integer at most 2^53 in magnitude.
fn number(v: &Val, place: &str) -> Result<f64, String> {
    match v {
        Val::Int(i) if i.abs() <= MAX_EXACT_INT => Ok(*i as f64),
        Val::Int(i) => Err(format!(
            "{place}: the integer {i} is beyond 2^53 in magnitude, so not exactly an f64 \
             (write it as a decimal, read as the nearest f64)"
        )),
        Val::Float(f) if f.is_finite() => Ok(*f),
        Val::Float(f) => Err(format!("{place}: the number {f} is not finite")),
        other => Err(format!(
            "{place}: expected a number, found {}",
            other.kind()
        )),
    }
}

/// The edit distance between two short strings (for "did you mean").
fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().take(64).collect();
    let b: Vec<char> = b.chars().take(64).collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur.push(sub.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The known key closest to `key`, if it is a near miss.
fn near_miss(key: &str) -> Option<&'static str> {
    let norm = |s: &str| s.to_ascii_lowercase().replace('-', "_");
    KEYS.iter()
        .map(|k| {
            let d = if norm(key) == *k {
                0
            } else {
                distance(&norm(key), k)
            };
            (d, *k)
        })
        .filter(|(d, k)| *d <= 2.max(k.len() / 4))
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Whitespace runs as one space, trimmed.
fn normalised(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// What the reader has resolved so far: the names an expression may use.
struct Ctx {
    coordinates: Vec<String>,
    parameters: Vec<String>,
}

impl Ctx {
    fn names(&self) -> Names<'_> {
        Names {
            coordinates: &self.coordinates,
            parameters: &self.parameters,
        }
    }

    fn entry(&self, v: &Val, place: &str) -> Result<Entry, String> {
        match v {
            Val::Str(s) => {
                let e = expr::parse(s, &self.names()).map_err(|e| match e.at {
                    Some(at) => format!(
                        "{place}: {} at character {at} of `{}`",
                        e.what,
                        shown(s, 80)
                    ),
                    None => format!("{place}: {} in `{}`", e.what, shown(s, 80)),
                })?;
                Ok(Entry {
                    text: normalised(s),
                    expr: e,
                })
            }
            Val::Int(_) | Val::Float(_) => {
                let x = number(v, place)?;
                let lit = Expr::Num(x.abs());
                Ok(Entry {
                    text: format!("{x}"),
                    expr: if x.is_sign_negative() {
                        Expr::Neg(Box::new(lit))
                    } else {
                        lit
                    },
                })
            }
            other => Err(format!(
                "{place}: expected an expression (a string or a number), found {}",
                other.kind()
            )),
        }
    }

    fn row(&self, v: &Val, place: &str, cols: usize) -> Result<Vec<Entry>, String> {
        let Val::Arr(a) = v else {
            return Err(format!(
                "{place}: expected an array of {cols} expressions, found {}",
                v.kind()
            ));
        };
        if a.len() != cols {
            return Err(format!(
                "{place}: {} entries, expected {cols} (one per coordinate)",
                a.len()
            ));
        }
        a.iter()
            .enumerate()
            .map(|(j, x)| self.entry(x, &format!("{place}[{}]", j + 1)))
            .collect()
    }

    /// A matrix of `cols` columns; `rows` checked by the caller when it is not known yet.
    fn matrix(
        &self,
        v: &Val,
        key: &str,
        rows: Option<usize>,
        cols: usize,
        what_rows: &str,
    ) -> Result<Vec<Vec<Entry>>, String> {
        let Val::Arr(a) = v else {
            return Err(format!(
                "{key}: expected an array of rows, found {}",
                v.kind()
            ));
        };
        if let Some(r) = rows {
            if a.len() != r {
                return Err(format!(
                    "{key}: {} rows, expected {r} ({what_rows})",
                    a.len()
                ));
            }
        }
        a.iter()
            .enumerate()
            .map(|(i, row)| {
                let place = format!("{key}[{}]", i + 1);
                if !matches!(row, Val::Arr(_)) {
                    return Err(format!(
                        "{place}: expected a row (an array of {cols} expressions), found {} \
                         (a matrix is an array of rows: [[...], [...]])",
                        row.kind()
                    ));
                }
                self.row(row, &place, cols)
            })
            .collect()
    }
}

/// A list of distinct identifiers usable as names.
fn names(v: &Val, key: &str, taken: &[(&str, &[String])]) -> Result<Vec<String>, String> {
    let Val::Arr(a) = v else {
        return Err(format!(
            "{key}: expected an array of names, found {}",
            v.kind()
        ));
    };
    let mut out: Vec<String> = Vec::new();
    for (i, x) in a.iter().enumerate() {
        let place = format!("{key}[{}]", i + 1);
        let Val::Str(s) = x else {
            return Err(format!(
                "{place}: expected a name (a string), found {}",
                x.kind()
            ));
        };
        identifier(s, &place)?;
        if out.contains(s) {
            return Err(format!("{place}: duplicate name `{s}`"));
        }
        for (what, list) in taken {
            if list.contains(s) {
                return Err(format!("{place}: `{s}` is already a name of the {what}"));
            }
        }
        out.push(s.clone());
    }
    Ok(out)
}

fn identifier(s: &str, place: &str) -> Result<(), String> {
    if !is_identifier(s) {
        return Err(format!(
            "{place}: `{}` is not a name ([A-Za-z_][A-Za-z0-9_]*)",
            shown(s, 40)
        ));
    }
    if is_reserved(s) {
        return Err(format!(
            "{place}: `{s}` is reserved (a function of the expressions, or pi)"
        ));
    }
    Ok(())
}

fn scene_name(s: &str, place: &str) -> Result<String, String> {
    if s.trim().is_empty() {
        return Err(format!("{place}: the name is empty"));
    }
    if s.chars().any(char::is_control) {
        return Err(format!(
            "{place}: the name `{}` has control characters",
            shown(s, 40)
        ));
    }
    if s.chars().count() > 200 {
        return Err(format!("{place}: the name is longer than 200 characters"));
    }
    Ok(s.to_string())
}

/// The checked scene from the top-level value.
fn build(top: &Val, default_name: &str) -> Result<SceneFile, String> {
    let Val::Obj(kv) = top else {
        return Err(format!(
            "a scene is a table (object) of keys, found {}",
            top.kind()
        ));
    };
    for (k, _) in kv {
        if !KEYS.contains(&k.as_str()) {
            let hint = near_miss(k)
                .map(|m| format!("did you mean `{m}`? "))
                .unwrap_or_default();
            return Err(format!(
                "unknown key `{}` ({hint}known: {})",
                shown(k, 40),
                KEYS.join(", ")
            ));
        }
    }
    let get = |k: &str| kv.iter().find(|(x, _)| x == k).map(|(_, v)| v);
    misplaced_in_parameters(get("parameters"), &get)?;

    let name = match get("name") {
        Some(Val::Str(s)) => scene_name(s, "name")?,
        Some(v) => return Err(format!("name: expected a string, found {}", v.kind())),
        None => {
            let d: String = shown(default_name, 200);
            if d.trim().is_empty() {
                "scene".to_string()
            } else {
                d
            }
        }
    };

    let coordinates = match get("coordinates") {
        Some(v) => names(v, "coordinates", &[])?,
        None => {
            return Err(
                "missing key `coordinates` (the names of q's components, e.g. [\"x\", \"y\"])"
                    .into(),
            )
        }
    };
    let n = coordinates.len();
    if n == 0 || n > MAX_DIM {
        return Err(format!("coordinates: {n} names (1 to {MAX_DIM} allowed)"));
    }

    let mut params = Vec::new();
    if let Some(v) = get("parameters") {
        let Val::Obj(p) = v else {
            return Err(format!(
                "parameters: expected a table of name = number, found {}",
                v.kind()
            ));
        };
        for (k, x) in p {
            let place = format!("parameters.{}", shown(k, 40));
            identifier(k, &place)?;
            if coordinates.contains(k) {
                return Err(format!("{place}: `{k}` is already a coordinate"));
            }
            params.push((k.clone(), number(x, &place)?));
        }
    }
    let ctx = Ctx {
        coordinates: coordinates.clone(),
        parameters: params.iter().map(|(k, _)| k.clone()).collect(),
    };

    let constraints = match get("constraints") {
        Some(v) => ctx.matrix(v, "constraints", None, n, "")?,
        None => {
            return Err(format!(
                "missing key `constraints` (k rows of {n} expressions: the covectors mu^a)"
            ))
        }
    };
    let k = constraints.len();
    if k == 0 || k >= n {
        return Err(format!(
            "constraints: {k} rows for {n} coordinates (1 to n - 1 = {} allowed)",
            n - 1
        ));
    }
    let m = n - k;

    let velocities = match get("quasi_velocities") {
        Some(v) => {
            let vs = names(v, "quasi_velocities", &[])?;
            if vs.len() != m {
                return Err(format!(
                    "quasi_velocities: {} names, expected n - k = {m}",
                    vs.len()
                ));
            }
            vs
        }
        None => (1..=m).map(|a| format!("u{a}")).collect(),
    };

    let mass = get("mass")
        .map(|v| ctx.matrix(v, "mass", Some(n), n, "n x n"))
        .transpose()?;
    let potential = get("potential")
        .map(|v| ctx.entry(v, "potential"))
        .transpose()?;
    let one_form = get("one_form")
        .map(|v| ctx.row(v, "one_form", n))
        .transpose()?;

    let basis = match (get("basis"), get("free")) {
        (Some(_), Some(_)) => {
            return Err(
                "both `basis` and `free` are given: give the basis, or the free coordinates \
                 of the derived basis, not both"
                    .into(),
            )
        }
        (Some(v), None) => {
            BasisSpec::Given(ctx.matrix(v, "basis", Some(m), n, "n - k, one per quasi-velocity")?)
        }
        (None, Some(v)) => {
            if k > MAX_DERIVED_K {
                return Err(format!(
                    "free: a derived basis takes at most {MAX_DERIVED_K} constraints (the \
                     determinants of its pivot block are expanded by cofactors), this scene \
                     has {k}: give `basis` instead"
                ));
            }
            let Val::Arr(a) = v else {
                return Err(format!(
                    "free: expected an array of coordinate names, found {}",
                    v.kind()
                ));
            };
            if a.len() != m {
                return Err(format!(
                    "free: {} names, expected n - k = {m} coordinates",
                    a.len()
                ));
            }
            let mut idx = Vec::new();
            for (i, x) in a.iter().enumerate() {
                let place = format!("free[{}]", i + 1);
                let Val::Str(s) = x else {
                    return Err(format!(
                        "{place}: expected a coordinate name, found {}",
                        x.kind()
                    ));
                };
                let Some(j) = coordinates.iter().position(|c| c == s) else {
                    return Err(format!(
                        "{place}: unknown coordinate `{}` (known: {})",
                        shown(s, 40),
                        coordinates.join(", ")
                    ));
                };
                if idx.contains(&j) {
                    return Err(format!("{place}: coordinate `{s}` repeated"));
                }
                idx.push(j);
            }
            BasisSpec::Free(idx)
        }
        (None, None) => {
            return Err(format!(
                "missing key `free` (the n - k = {m} coordinates whose velocities are the \
                 quasi-velocities) or `basis` ({m} rows of {n} expressions)"
            ))
        }
    };

    if let BasisSpec::Free(free) = &basis {
        velocities_in_order(&velocities, free, &coordinates)?;
    }

    Ok(SceneFile {
        name,
        coordinates,
        velocities,
        param_names: ctx.parameters,
        params,
        mass,
        potential,
        one_form,
        constraints,
        basis,
    })
}

/// (10.1) A scene key found inside the `parameters` table and not at the top: in TOML every
/// key written after a `[parameters]` header belongs to that table. Named as such when it
/// cannot be a parameter (a required or naming key, or a value that is not a number); a
/// number under `mass`, `potential` or `one_form` stays a parameter of that name.
fn misplaced_in_parameters<'a>(
    params: Option<&'a Val>,
    top: &dyn Fn(&str) -> Option<&'a Val>,
) -> Result<(), String> {
    let Some(Val::Obj(p)) = params else {
        return Ok(());
    };
    // in the order of KEYS: the first a reader of the file looks for is named first
    let found = KEYS.iter().filter_map(|k| p.iter().find(|(x, _)| x == k));
    for (k, v) in found {
        let scene_key = k != "parameters";
        let never_a_parameter = matches!(
            k.as_str(),
            "name" | "coordinates" | "quasi_velocities" | "constraints" | "basis" | "free"
        );
        if scene_key
            && top(k).is_none()
            && (never_a_parameter || !matches!(v, Val::Int(_) | Val::Float(_)))
        {
            return Err(format!(
                "`{k}` appears after [parameters], so TOML reads it as a parameter: move it \
                 above the [parameters] header (every key after a table header belongs to \
                 that table), or write the parameters inline: parameters = {{ ... }}"
            ));
        }
    }
    Ok(())
}

/// The coordinate whose velocity the quasi-velocity name `v` reads as (`xd`, `x_d`,
/// `xdot`, `x_dot`, `dx`, `d_x` for a coordinate `x`), if any.
fn velocity_of(v: &str, coordinates: &[String]) -> Option<usize> {
    coordinates.iter().position(|c| {
        ["d", "_d", "dot", "_dot"]
            .iter()
            .any(|s| v.strip_suffix(s) == Some(c.as_str()))
            || ["d", "d_"]
                .iter()
                .any(|s| v.strip_prefix(s) == Some(c.as_str()))
    })
}

/// (10.1) With a derived basis the a-th quasi-velocity IS the velocity of the a-th free
/// coordinate: a name that reads as another coordinate's velocity is refused, with the
/// names in the order of `free`.
fn velocities_in_order(
    velocities: &[String],
    free: &[usize],
    coordinates: &[String],
) -> Result<(), String> {
    let wrong = velocities
        .iter()
        .zip(free)
        .enumerate()
        .find_map(|(a, (v, &f))| match velocity_of(v, coordinates) {
            Some(c) if c != f && !coordinates.contains(v) => Some((a, v, c, f)),
            _ => None,
        });
    let Some((a, v, c, f)) = wrong else {
        return Ok(());
    };
    // the names given, reordered so that each coordinate's velocity is at its free place
    let expected: Vec<String> = free
        .iter()
        .enumerate()
        .map(|(b, &fb)| {
            let own = velocities
                .iter()
                .find(|w| velocity_of(w, coordinates) == Some(fb))
                .unwrap_or(&velocities[b]);
            format!("\"{own}\"")
        })
        .collect();
    let free_names: Vec<String> = free
        .iter()
        .map(|&i| format!("\"{}\"", coordinates[i]))
        .collect();
    Err(format!(
        "quasi_velocities[{}] = `{v}` reads as the velocity of `{}`, but with free = [{}] \
         quasi-velocity {} is the velocity of `{}` (a derived basis takes the free \
         coordinates' velocities in the order of `free`): write quasi_velocities = [{}]",
        a + 1,
        coordinates[c],
        free_names.join(", "),
        a + 1,
        coordinates[f],
        expected.join(", ")
    ))
}

/// Line and column (1-based, columns in characters) of byte offset `at` in `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before, |i| &before[i + 1..])
        .chars()
        .count()
        + 1;
    (line, col)
}

impl SceneFile {
    /// Read a scene from TOML text; `default_name` is its name when the text has no `name`.
    pub fn from_toml(text: &str, default_name: &str) -> Result<SceneFile, Error> {
        let table: toml::Table = toml::from_str(text).map_err(|e| {
            let msg = e.message().lines().next().unwrap_or("").trim().to_string();
            let msg = shown(&msg, 200);
            Error::input(match e.span() {
                Some(s) => {
                    let (l, c) = line_col(text, s.start);
                    format!("TOML syntax error at line {l}, column {c}: {msg}")
                }
                None => format!("TOML syntax error: {msg}"),
            })
        })?;
        let top = Val::from_toml(&toml::Value::Table(table), 0);
        build(&top, default_name).map_err(Error::input)
    }

    /// Read the scene file at `path` (its name defaults to the file's stem); every message
    /// starts with the path.
    pub fn read(path: &Path) -> Result<SceneFile, Error> {
        let shown_path = shown(&path.display().to_string(), 400);
        let bytes = std::fs::read(path).map_err(|e| {
            Error::input(format!(
                "{shown_path}: cannot read the scene file: {}",
                shown(&e.to_string(), 200)
            ))
        })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            Error::input(format!(
                "{shown_path}: the scene file is not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ))
        })?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        SceneFile::from_toml(&text, &stem)
            .map_err(|e| Error::input(format!("{shown_path}: {}", e.message())))
    }

    /// Read the JSON scene file at `path` with the reader `parse` of JSON texts (the
    /// protocol's strict one: no repeated key); its name defaults to the file's stem, and
    /// every message starts with the path (contract E26).
    pub fn read_json(
        path: &Path,
        parse: impl FnOnce(&str) -> Result<serde_json::Value, Error>,
    ) -> Result<SceneFile, Error> {
        let shown_path = shown(&path.display().to_string(), 400);
        let text = std::fs::read(path)
            .map_err(|e| {
                Error::input(format!(
                    "{shown_path}: cannot read the scene file: {}",
                    shown(&e.to_string(), 200)
                ))
            })
            .and_then(|b| {
                String::from_utf8(b).map_err(|e| {
                    Error::input(format!(
                        "{shown_path}: the scene file is not UTF-8 text (invalid byte at offset {})",
                        e.utf8_error().valid_up_to()
                    ))
                })
            })?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let v = parse(&text).map_err(|e| {
            Error::input(format!(
                "{shown_path}: JSON syntax error: {}",
                shown(e.message(), 200)
            ))
        })?;
        if !v.is_object() {
            return Err(Error::input(format!(
                "{shown_path}: a JSON scene file holds one object with the keys of a scene file"
            )));
        }
        SceneFile::from_json_named(&v, &stem)
            .map_err(|e| Error::input(format!("{shown_path}: {}", e.message())))
    }

    /// Read a scene from a JSON object with the keys of the file format (the batch
    /// protocol's inline scenes); its name defaults to `"inline"`.
    pub fn from_json(v: &serde_json::Value) -> Result<SceneFile, Error> {
        SceneFile::from_json_named(v, INLINE_NAME)
    }

    /// Read a scene from a JSON object with the keys of the file format; `default_name`
    /// is its name when the object has no `name` (a `.json` scene file's stem, contract
    /// E26).
    pub fn from_json_named(v: &serde_json::Value, default_name: &str) -> Result<SceneFile, Error> {
        build(&Val::from_json(v, 0), default_name).map_err(Error::input)
    }

    /// Whether `path` names a JSON scene file (its extension is `json`, in any case):
    /// read as JSON, anything else as TOML (contract E26).
    pub fn is_json_path(path: &Path) -> bool {
        path.extension()
            .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("json"))
    }

    /// The scene with the parameter values `given` (name, exact f64; the last one given
    /// wins); unknown names and non-finite values are input errors.
    pub fn with_params(mut self, given: &[(String, f64)]) -> Result<SceneFile, Error> {
        for (k, v) in given {
            let Some(slot) = self.params.iter_mut().find(|(p, _)| p == k) else {
                let known = if self.params.is_empty() {
                    "it declares no parameters".to_string()
                } else {
                    format!("known: {}", self.param_names.join(", "))
                };
                return Err(Error::input(format!(
                    "scene `{}` has no parameter `{}` ({known})",
                    self.name,
                    shown(k, 40)
                )));
            };
            if !v.is_finite() {
                return Err(Error::input(format!(
                    "parameter `{k}` must be finite (got {v})"
                )));
            }
            slot.1 = *v;
        }
        Ok(self)
    }

    /// The parameters with their values, in the order of the scene.
    pub fn parameters(&self) -> &[(String, f64)] {
        &self.params
    }

    /// The coordinates' names.
    pub fn coordinates(&self) -> &[String] {
        &self.coordinates
    }

    /// A canonical text of the definition and the parameter values, equal for equal
    /// scenes however they were written (TOML or JSON, spacing, a number as a string or
    /// a plain number): a key for caching compiled models.
    pub fn key(&self) -> String {
        let nm = self.names();
        let c = |e: &Entry| serde_json::Value::String(e.expr.canonical(&nm));
        let row = |r: &Vec<Entry>| serde_json::Value::Array(r.iter().map(c).collect());
        let mat = |m: &Vec<Vec<Entry>>| serde_json::Value::Array(m.iter().map(row).collect());
        let (basis, free) = match &self.basis {
            BasisSpec::Given(b) => (mat(b), serde_json::Value::Null),
            BasisSpec::Free(f) => (serde_json::Value::Null, serde_json::json!(f)),
        };
        serde_json::json!({
            "scene_file": 1,
            "name": self.name,
            "coordinates": self.coordinates,
            "quasi_velocities": self.velocities,
            "parameters": self.params.iter().map(|(k, v)| vec![k.clone(), format!("{v:?}")]).collect::<Vec<_>>(),
            "mass": self.mass.as_ref().map(mat),
            "potential": self.potential.as_ref().map(c),
            "one_form": self.one_form.as_ref().map(row),
            "constraints": mat(&self.constraints),
            "basis": basis,
            "free": free,
        })
        .to_string()
    }

    fn names(&self) -> Names<'_> {
        Names {
            coordinates: &self.coordinates,
            parameters: &self.param_names,
        }
    }

    fn values<S: Scalar>(&self) -> Vec<S> {
        self.params.iter().map(|(_, v)| S::cst(*v)).collect()
    }

    fn eval_row<S: Scalar>(row: &[Entry], q: &[S], p: &[S]) -> Vec<S> {
        row.iter().map(|e| e.expr.eval(q, p)).collect()
    }

    /// The derived basis as formulas (evaluated over strings).
    fn derived_basis_text(&self, free: &[usize]) -> Vec<Vec<String>> {
        let q: Vec<Sym> = self.coordinates.iter().map(|c| Sym::name(c)).collect();
        let p: Vec<Sym> = self.param_names.iter().map(|c| Sym::name(c)).collect();
        let mu: Mat<Sym> = self
            .constraints
            .iter()
            .map(|r| Self::eval_row(r, &q, &p))
            .collect();
        derived_basis(&mu, free, self.coordinates.len())
            .into_iter()
            .map(|r| r.into_iter().map(|s| s.text().to_string()).collect())
            .collect()
    }
}

fn tuple(v: &[String]) -> String {
    format!("({})", v.join(", "))
}

fn texts(r: &[Entry]) -> Vec<String> {
    r.iter().map(|e| e.text.clone()).collect()
}

impl Scene for SceneFile {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn dim(&self) -> usize {
        self.coordinates.len()
    }
    fn n_constraints(&self) -> usize {
        self.constraints.len()
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        let p = self.values();
        self.constraints
            .iter()
            .map(|r| Self::eval_row(r, q, &p))
            .collect()
    }
    /// The given mass matrix; an entry below the diagonal written as its mirror image is
    /// the same value (so symmetry is structural, [spec 3.6](crate::spec::scenes)).
    fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        let Some(m) = &self.mass else {
            return identity(self.dim());
        };
        let p = self.values();
        let n = m.len();
        let mut out: Mat<S> = Vec::with_capacity(n);
        for i in 0..n {
            let mut row = Vec::with_capacity(n);
            for j in 0..n {
                let v = if j < i && m[i][j].expr == m[j][i].expr {
                    out[j][i].clone()
                } else {
                    m[i][j].expr.eval(q, &p)
                };
                row.push(v);
            }
            out.push(row);
        }
        out
    }
    fn potential<S: Scalar>(&self, q: &[S]) -> S {
        match &self.potential {
            Some(e) => e.expr.eval(q, &self.values()),
            None => S::zero(),
        }
    }
    fn one_form<S: Scalar>(&self, q: &[S]) -> Option<Vec<S>> {
        self.one_form
            .as_ref()
            .map(|r| Self::eval_row(r, q, &self.values()))
    }
    fn free(&self) -> Vec<usize> {
        match &self.basis {
            BasisSpec::Free(f) => f.clone(),
            BasisSpec::Given(_) => (0..self.dim() - self.n_constraints()).collect(),
        }
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        match &self.basis {
            BasisSpec::Given(b) => {
                let p = self.values();
                b.iter().map(|r| Self::eval_row(r, q, &p)).collect()
            }
            BasisSpec::Free(f) => derived_basis(&self.constraints(q), f, self.dim()),
        }
    }
    fn description(&self) -> Description {
        let (n, k) = (self.dim(), self.n_constraints());
        let mut lagrangian = "L = 1/2 qd^T M(q) qd".to_string();
        if self.one_form.is_some() {
            lagrangian.push_str(" + A(q) qd");
        }
        if self.potential.is_some() {
            lagrangian.push_str(" - V(q)");
        }
        lagrangian.push_str(&format!("; q = {}", tuple(&self.coordinates)));
        match &self.mass {
            None => lagrangian.push_str("; M = I"),
            Some(m) => {
                let rows: Vec<String> = m.iter().map(|r| tuple(&texts(r))).collect();
                lagrangian.push_str(&format!("; M = ({})", rows.join(", ")));
            }
        }
        if let Some(a) = &self.one_form {
            lagrangian.push_str(&format!("; A = {}", tuple(&texts(a))));
        }
        if let Some(v) = &self.potential {
            lagrangian.push_str(&format!("; V = {}", v.text));
        }
        let constraints = self
            .constraints
            .iter()
            .enumerate()
            .map(|(a, r)| format!("mu^{} = {}", a + 1, tuple(&texts(r))))
            .collect();
        let basis = match &self.basis {
            BasisSpec::Given(b) => b
                .iter()
                .enumerate()
                .map(|(a, r)| format!("e{} = {}", a + 1, tuple(&texts(r))))
                .collect(),
            BasisSpec::Free(f) => self
                .derived_basis_text(f)
                .iter()
                .zip(f)
                .enumerate()
                .map(|(a, (r, &i))| {
                    format!(
                        "e{} = {}   [derived: {} = the velocity of {}]",
                        a + 1,
                        tuple(r),
                        self.velocities[a],
                        self.coordinates[i]
                    )
                })
                .collect(),
        };
        Description {
            name: self.name.clone(),
            summary: format!(
                "a system posed by a scene file ({n} coordinates, {k} constraint{})",
                if k == 1 { "" } else { "s" }
            ),
            coordinates: self.coordinates.clone(),
            velocities: self.velocities.clone(),
            params: self
                .params
                .iter()
                .map(|(k, v)| (k.clone(), *v, "a parameter of the scene file".to_string()))
                .collect(),
            n,
            k,
            lagrangian,
            constraints,
            basis,
            invariants: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_count_characters() {
        assert_eq!(line_col("ab\ncé\nx", 0), (1, 1));
        assert_eq!(line_col("ab\ncé\nx", 3), (2, 1));
        assert_eq!(line_col("ab\ncé\nx", 7), (3, 1));
        assert_eq!(line_col("ab\ncé\nx", 6), (2, 3));
    }

    #[test]
    fn near_misses_are_named() {
        assert_eq!(near_miss("masss"), Some("mass"));
        assert_eq!(near_miss("Coordinates"), Some("coordinates"));
        assert_eq!(near_miss("quasi-velocities"), Some("quasi_velocities"));
        assert_eq!(near_miss("oneform"), Some("one_form"));
        assert_eq!(near_miss("zzzz"), None);
    }
}
