//! `dalembert check`: read a candidate trajectory, ask the oracle, print a verdict table.

use super::SceneArgs;
use dalembert::oracle::{check_trajectory, CheckOptions};
use dalembert::protocol::{self, Session, STEP_DEADLINE};
use dalembert::scene::Scene;
use dalembert::Error;
use inari::Interval;
use serde_json::Value;
use std::io::BufRead;

/// Returns the text to print and whether the check passed (exit 0) or proved the tolerance
/// exceeded (exit 1); an undecided comparison is `Error::Uncertified` (exit 3).
pub fn run(
    scene: &SceneArgs,
    h: &str,
    file: &str,
    deadline: Option<&str>,
    tol: Option<&str>,
    no_pairs: bool,
    as_json: bool,
) -> Result<(String, bool), Error> {
    let spec = super::scene_spec(scene)?;
    let model = Session::default().model(&spec)?;
    let h = protocol::parse_num("--h", h)?;
    let tol = tol.map(|t| protocol::parse_num("--tol", t)).transpose()?;
    let deadline = deadline
        .map(|d| protocol::parse_seconds("--deadline", d))
        .transpose()?;
    let coordinates = model.scene.description().coordinates;
    let m = model.n - model.k;
    let q = read_trajectory(file, &coordinates, m, h)?;
    // the budget: as given for the whole check, else STEP_DEADLINE for each pair
    let budget = deadline.unwrap_or(STEP_DEADLINE * q.len().max(1) as f64);
    let mut opts = CheckOptions {
        pairs: !no_pairs,
        ..CheckOptions::default()
    };
    opts.flow.deadline = protocol::deadline_in(budget);
    let v = check_trajectory(&model, h, &q, &opts)?;
    let passed = protocol::tolerance_verdict(&v, tol)?;
    let out = if as_json {
        protocol::verdict(&v, passed).to_string()
    } else {
        table(
            &v.distance,
            &v.defect,
            &v.energy_error,
            v.max_distance,
            passed,
            tol,
        )
    };
    Ok((out, passed))
}

fn table(
    dist: &[Interval],
    defect: &[Vec<Interval>],
    energy: &[Interval],
    max: Interval,
    passed: bool,
    tol: Option<f64>,
) -> String {
    let mut s = format!(
        "{:>6} {:>24} {:>24} {:>24}\n",
        "k", "|q_k - q^e_k| <=", "defect(q_k,q_k+1) in", "energy error in"
    );
    for (k, d) in dist.iter().enumerate() {
        let def = defect
            .get(k)
            .map(|s| {
                s.iter()
                    .map(|x| format!("[{:.2e},{:.2e}]", x.inf(), x.sup()))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .unwrap_or_default();
        let en = energy
            .get(k)
            .map(|e| format!("[{:.2e},{:.2e}]", e.inf(), e.sup()))
            .unwrap_or_default();
        s.push_str(&format!("{k:>6} {:>24.3e} {def:>24} {en:>24}\n", d.sup()));
    }
    s.push_str(&format!("max distance <= {:.3e}", max.sup()));
    if let Some(t) = tol {
        s.push_str(&format!(
            "; tolerance {t:e}: {}",
            if passed { "PASS" } else { "FAIL (proved)" }
        ));
    }
    s
}

/// The candidate in `file`: JSON `{"q": [[..]..]}` (as `integrate --json` prints it) or
/// `[[..]..]`, or CSV. Strict (README, "Input rules"): every number finite, every row the
/// scene's length, no key or column that is not known, the refusal naming file, line and
/// column.
fn read_trajectory(
    file: &str,
    coordinates: &[String],
    m: usize,
    h: f64,
) -> Result<Vec<Vec<f64>>, Error> {
    let cannot =
        |e: std::io::Error| Error::input(format!("--trajectory: cannot read `{file}`: {e}"));
    let f = std::fs::File::open(file).map_err(cannot)?;
    let mut r = std::io::BufReader::new(f);
    // JSON or CSV: the first byte that is not white space decides
    let first = loop {
        let buf = r.fill_buf().map_err(cannot)?;
        match buf.iter().position(|b| !b.is_ascii_whitespace()) {
            Some(i) => break Some(buf[i]),
            None if buf.is_empty() => break None,
            None => {
                let len = buf.len();
                r.consume(len);
            }
        }
    };
    match first {
        None => Err(Error::input(format!(
            "--trajectory `{file}`: the file is empty"
        ))),
        Some(b'{') | Some(b'[') => {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut r, &mut text)
                .map_err(|e| Error::input(format!("--trajectory `{file}`: {e}")))?;
            json_trajectory(file, &text, coordinates.len())
        }
        Some(_) => csv_trajectory(file, r, coordinates, m, h),
    }
}

/// The keys of `integrate --json` output: `q` is read, the others are that command's own
/// figures and are ignored.
const TRAJECTORY_KEYS: [&str; 5] = ["q", "p", "energy", "newton_iterations", "max_residual"];

fn json_trajectory(file: &str, text: &str, n: usize) -> Result<Vec<Vec<f64>>, Error> {
    let at = format!("--trajectory `{file}`");
    let v = protocol::parse_json(text)
        .map_err(|e| Error::input(format!("{at}: not JSON: {}", e.message())))?;
    let rows = match &v {
        Value::Object(o) => {
            protocol::check_keys(o, &TRAJECTORY_KEYS, "a trajectory")
                .map_err(|e| Error::input(format!("{at}: {}", e.message())))?;
            o.get("q")
                .ok_or_else(|| Error::input(format!("{at}: missing key `q`")))?
        }
        other => other,
    };
    let rows = rows
        .as_array()
        .ok_or_else(|| Error::input(format!("{at}: `q` must be an array of configurations")))?;
    rows.iter()
        .enumerate()
        .map(|(k, r)| {
            let q = protocol::json_numbers(&format!("{at}: q[{k}]"), r)?;
            if q.len() == n {
                Ok(q)
            } else {
                Err(Error::input(format!(
                    "{at}: q[{k}] has {} numbers, the scene has {n} coordinates",
                    q.len()
                )))
            }
        })
        .collect()
}

/// What a CSV column holds.
#[derive(Clone, Copy, PartialEq)]
enum Column {
    Coordinate(usize),
    K,
    T,
    /// `p0..`, `energy`: `integrate`'s own figures, read as numbers and not used.
    Ignored,
}

fn csv_trajectory(
    file: &str,
    r: impl BufRead,
    coordinates: &[String],
    m: usize,
    h: f64,
) -> Result<Vec<Vec<f64>>, Error> {
    let n = coordinates.len();
    let at = |line: usize| format!("--trajectory `{file}` line {line}");
    let mut columns: Option<Vec<(Column, String)>> = None;
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut blank_since: Option<usize> = None;
    for (i, line) in r.lines().enumerate() {
        let no = i + 1;
        let line = line.map_err(|e| Error::input(format!("{}: {e}", at(no))))?;
        let line = line.strip_suffix('\r').unwrap_or(&line);
        if line.trim().is_empty() {
            blank_since.get_or_insert(no);
            continue;
        }
        if let Some(b) = blank_since {
            return Err(Error::input(format!(
                "{}: an empty line in the middle of the data; remove it",
                at(b)
            )));
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        if columns.is_none() {
            // a first line with a cell that is not a number is the header
            if cells.iter().any(|c| protocol::parse_num("", c).is_err()) {
                let cols = header_columns(&cells, coordinates, m)
                    .map_err(|e| Error::input(format!("{}: {}", at(no), e.message())))?;
                columns = Some(cols);
                continue;
            }
            columns = Some(
                (0..n)
                    .map(|i| (Column::Coordinate(i), coordinates[i].clone()))
                    .collect(),
            );
        }
        let cols = columns.as_deref().unwrap_or_default();
        if cells.len() != cols.len() {
            return Err(Error::input(format!(
                "{}: {} cells, expected {} ({}){}",
                at(no),
                cells.len(),
                cols.len(),
                cols.iter()
                    .map(|c| c.1.as_str())
                    .collect::<Vec<_>>()
                    .join(","),
                if rows.is_empty() && cols.len() == n {
                    "; without a header line the columns are the coordinates in order"
                } else {
                    ""
                }
            )));
        }
        let k = rows.len();
        let mut q = vec![f64::NAN; n];
        for (c, (cell, (what, name))) in cells.iter().zip(cols).enumerate() {
            let x = protocol::parse_num(&format!("{}, column {} (`{name}`)", at(no), c + 1), cell)?;
            match what {
                Column::Coordinate(i) => q[*i] = x,
                Column::K if x != k as f64 => {
                    return Err(Error::input(format!(
                        "{}: k = {x}, but this is row {k} of the data (rows must be q_0, q_1, .. in order)",
                        at(no)
                    )))
                }
                Column::T if (x - k as f64 * h).abs() > 1e-6 * (k as f64 * h).abs().max(h) => {
                    return Err(Error::input(format!(
                        "{}: t = {x}, but k h = {} for row {k} with --h {h}",
                        at(no),
                        k as f64 * h
                    )))
                }
                _ => {}
            }
        }
        rows.push(q);
    }
    Ok(rows)
}

/// The role of each header cell; every coordinate once (by its name or as `q0`..).
fn header_columns(
    cells: &[&str],
    coordinates: &[String],
    m: usize,
) -> Result<Vec<(Column, String)>, Error> {
    let n = coordinates.len();
    let mut cols: Vec<(Column, String)> = Vec::new();
    for (c, name) in cells.iter().enumerate() {
        let by_q = name
            .strip_prefix('q')
            .and_then(|i| i.parse::<usize>().ok())
            .filter(|i| *i < n && name[1..] == i.to_string());
        let col = if let Some(i) = coordinates.iter().position(|x| x == name) {
            Column::Coordinate(i)
        } else if let Some(i) = by_q {
            Column::Coordinate(i)
        } else if *name == "k" {
            Column::K
        } else if *name == "t" {
            Column::T
        } else if *name == "energy"
            || name
                .strip_prefix('p')
                .and_then(|a| a.parse::<usize>().ok())
                .is_some_and(|a| a < m && name[1..] == a.to_string())
        {
            Column::Ignored
        } else {
            return Err(Error::input(format!(
                "column {}: unknown column `{name}` (known: {}, or q0..q{}; k, t; p0..p{}, energy)",
                c + 1,
                coordinates.join(", "),
                n - 1,
                m.saturating_sub(1)
            )));
        };
        if let Some((_, prev)) = cols
            .iter()
            .find(|(k, _)| *k == col && col != Column::Ignored)
        {
            return Err(Error::input(format!(
                "column {}: `{name}` is the same column as `{prev}`",
                c + 1
            )));
        }
        if cols.iter().any(|(_, p)| p == name) {
            return Err(Error::input(format!(
                "column {}: `{name}` appears twice",
                c + 1
            )));
        }
        cols.push((col, name.to_string()));
    }
    let missing: Vec<&str> = (0..n)
        .filter(|i| !cols.iter().any(|(c, _)| *c == Column::Coordinate(*i)))
        .map(|i| coordinates[i].as_str())
        .collect();
    if !missing.is_empty() {
        return Err(Error::input(format!(
            "the header has no column for {}",
            missing.join(", ")
        )));
    }
    Ok(cols)
}
