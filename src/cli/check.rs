//! `dalembert check`: read a candidate trajectory, ask the oracle, print a verdict table.

use super::integrate::io;
use super::progress::Bar;
use super::spool::Spool;
use super::SceneArgs;
use crate::oracle::{check_rows, check_rows_in, CheckOptions, RowVerdict};
use crate::precision::dd::DdInterval;
use crate::precision::wide::{self, WideInterval};
use crate::protocol::{self, CheckRows, Session, STEP_WORK};
use crate::scene::Scene;
use crate::{Error, InputKind};
use serde_json::Value;
use std::fs::File;
use std::io::{BufRead, BufReader, Write};

/// Check the trajectory in `file` and write the verdict (a table, or with `as_json` the
/// object of the batch `check` answer) to stdout. Returns whether the check passed (exit
/// 0) or proved the tolerance exceeded (exit 1); an undecided comparison is
/// `Error::Uncertified` (exit 3). CSV rows are read, checked and written one at a time
/// (through a spool, so that a refusal still leaves stdout empty), in memory independent
/// of their number; a JSON file is read whole. Without `h`, the file's times give the steps
/// (non-uniform, contract E12); `tols` are `--tol` and `--defect-tol` (E13).
#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: &SceneArgs,
    h: Option<&str>,
    file: &str,
    (deadline, work, max_steps): (Option<&str>, Option<&str>, Option<&str>),
    tols: (Option<&str>, Option<&str>),
    no_pairs: bool,
    precision: Option<&str>,
    as_json: bool,
) -> Result<bool, Error> {
    let bits = precision.map(protocol::parse_precision).transpose()?;
    let bits = bits.filter(|b| *b > 53);
    if let Some(b) = bits.filter(|b| *b > wide::MAX_BITS) {
        return Err(protocol::precise::above(b));
    }
    let spec = super::scene_spec(scene)?;
    let model = Session::default().model(&spec)?;
    let h = h.map(|h| protocol::parse_num("--h", h)).transpose()?;
    let tols = protocol::Tolerances {
        tol: tols
            .0
            .map(|t| protocol::parse_num("--tol", t))
            .transpose()?,
        defect_tol: tols
            .1
            .map(|t| protocol::parse_num("--defect-tol", t))
            .transpose()?,
    };
    tols.require_pairs(!no_pairs)?;
    let deadline = deadline
        .map(|d| protocol::parse_seconds("--deadline", d))
        .transpose()?;
    let work = work
        .map(|w| protocol::parse_work("--work", w))
        .transpose()?;
    let coordinates = model.scene.description().coordinates;
    let m = model.n - model.k;
    let (rows, count) = read_trajectory(file, &coordinates, m, h)?;
    // the budget: as given for the whole check, else STEP_WORK for each pair (contract E14)
    let mut opts = CheckOptions {
        pairs: !no_pairs,
        ..CheckOptions::default()
    };
    opts.flow.deadline = deadline.and_then(protocol::deadline_in);
    let work = match (deadline, work) {
        (None, None) => Some(STEP_WORK.saturating_mul(count.max(1) as u64)),
        (_, w) => w,
    };
    if let Some(w) = work {
        opts.flow = opts.flow.allow_work(w);
    }
    if let Some(n) = max_steps {
        opts.flow.max_taylor_steps = protocol::parse_max_steps("--max-steps", n)?;
    }
    let mut bar = Bar::new();
    let table = CheckRows::new(as_json);
    // one spool per part of the answer (text: the table; JSON: distance, defect, energy_error)
    let mut spools: Vec<Spool> = (0..table.parts())
        .map(|i| Spool::new(&format!("check{i}")))
        .collect::<Result<_, _>>()?;
    let sink = |row: RowVerdict| {
        bar.update("check", (row.k + 1) as f64, count as f64);
        let pair = row
            .pair
            .as_ref()
            .map(|p| (p.defect.as_slice(), p.energy_error));
        table
            .row(&mut spools, row.k, row.distance, pair)
            .map_err(io)
    };
    let rows: Box<dyn Iterator<Item = Result<Row, Error>>> = match h {
        Some(_) => Box::new(rows.map(|r| r.map(|(_, q)| (None, q)))),
        None => {
            let untimed = move || {
                Error::input(format!(
                    "--trajectory `{file}`: without --h the rows need their times (a CSV \
                     column `t`, or a JSON key \"t\"); or give --h"
                ))
            };
            Box::new(rows.map(move |r| r.and_then(|(t, q)| Ok((Some(t.ok_or_else(untimed)?), q)))))
        }
    };
    // the bits computed with (contract E21): f64 intervals, double-double up to 106, else
    // exactly `bits`; the figures are f64 intervals at every precision
    let (max_distance, max_defect, used) = match bits {
        None => {
            let s = check_rows(&model, h, rows, &opts, sink)?;
            (s.max_distance, s.max_defect, None)
        }
        Some(54..=106) => {
            let s = check_rows_in::<DdInterval>(&model, h, rows, &opts, sink)?;
            (s.max_distance, s.max_defect, Some(106))
        }
        Some(b) => wide::with_bits(b, || {
            let s = check_rows_in::<WideInterval>(&model, h, rows, &opts, sink)?;
            Ok::<_, Error>((s.max_distance, s.max_defect, Some(b)))
        })?,
    };
    bar.clear();
    let passed = tols.passes(max_distance, max_defect)?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    table
        .finish(
            &mut out,
            max_distance,
            max_defect,
            &tols,
            passed,
            used,
            |i, w| spools[i].copy_to(w),
        )
        .and_then(|()| out.flush())
        .map_err(io)?;
    Ok(passed)
}

/// A row of a candidate trajectory: `(t_k if given, q_k)`.
type Row = (Option<f64>, Vec<f64>);

/// The rows of a candidate trajectory, read as they are needed.
type Rows = Box<dyn Iterator<Item = Result<Row, Error>>>;

/// The candidate in `file`: JSON `{"q": [[..]..]}` (as `integrate --json` prints it) or
/// `[[..]..]`, or CSV; and the number of rows (for the default budget and the progress
/// bar: CSV lines are counted in a first pass). Strict (README, "Input rules"): every
/// number finite, every row the scene's length, no key or column that is not known, the
/// refusal naming file, line and column.
fn read_trajectory(
    file: &str,
    coordinates: &[String],
    m: usize,
    h: Option<f64>,
) -> Result<(Rows, usize), Error> {
    let cannot =
        |e: std::io::Error| Error::input(format!("--trajectory: cannot read `{file}`: {e}"));
    let open = || -> Result<BufReader<File>, Error> {
        Ok(BufReader::new(File::open(file).map_err(cannot)?))
    };
    let mut r = open()?;
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
            let rows = json_trajectory(file, &text, coordinates.len(), h)?;
            let count = rows.len();
            Ok((Box::new(rows.into_iter().map(Ok)), count))
        }
        Some(_) => {
            // lines that are not blank, less the header if any: an upper bound is enough
            let mut count = 0;
            let mut lines = open()?.split(b'\n');
            for line in &mut lines {
                let line = line.map_err(cannot)?;
                count += usize::from(line.iter().any(|b| !b.is_ascii_whitespace()));
            }
            let rows = CsvRows {
                file: file.to_string(),
                lines: open()?.lines(),
                coordinates: coordinates.to_vec(),
                m,
                h,
                columns: None,
                blank_since: None,
                no: 0,
                k: 0,
                done: false,
            };
            Ok((Box::new(rows), count))
        }
    }
}

/// The keys of `integrate --json` output: `q` is read, the others are that command's own
/// figures and are ignored.
/// `t` (contract E12) gives the rows' times.
const TRAJECTORY_KEYS: [&str; 6] = ["q", "t", "p", "energy", "newton_iterations", "max_residual"];

/// The rows `(t_k if given, q_k)` of a JSON trajectory; with `h`, a time must be `k h`.
fn json_trajectory(file: &str, text: &str, n: usize, h: Option<f64>) -> Result<Vec<Row>, Error> {
    let at = format!("--trajectory `{file}`");
    let v = protocol::parse_json(text)
        .map_err(|e| Error::input(format!("{at}: not JSON: {}", e.message())))?;
    let mut times = None;
    let rows = match &v {
        Value::Object(o) => {
            protocol::check_keys(o, &TRAJECTORY_KEYS, "a trajectory")
                .map_err(|e| Error::input(format!("{at}: {}", e.message())))?;
            if let Some(t) = o.get("t") {
                times = Some(protocol::json_numbers(&format!("{at}: `t`"), t)?);
            }
            o.get("q")
                .ok_or_else(|| Error::input(format!("{at}: missing key `q`")))?
        }
        other => other,
    };
    let rows = rows
        .as_array()
        .ok_or_else(|| Error::input(format!("{at}: `q` must be an array of configurations")))?;
    if let Some(t) = &times {
        if t.len() != rows.len() {
            return Err(Error::input(format!(
                "{at}: {} times in `t` for {} rows in `q`",
                t.len(),
                rows.len()
            )));
        }
    }
    rows.iter()
        .enumerate()
        .map(|(k, r)| {
            let row = |column| InputKind::Row { row: k, column };
            let q = protocol::json_numbers(&format!("{at}: q[{k}]"), r).map_err(|e| {
                let column = e.input_kind().and_then(|kind| match kind {
                    InputKind::Element { index, .. } => Some(*index),
                    _ => None,
                });
                e.of_kind(row(column))
            })?;
            let t = times.as_ref().map(|t| t[k]);
            if let (Some(t), Some(h)) = (t, h) {
                time_is_kh(t, k, h)
                    .map_err(|e| Error::input_at(InputKind::Times, format!("{at}: {e}")))?;
            }
            if q.len() == n {
                Ok((t, q))
            } else {
                Err(Error::input_at(
                    row(None),
                    format!(
                        "{at}: q[{k}] has {} numbers, the scene has {n} coordinates",
                        q.len()
                    ),
                ))
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

/// The CSV rows of `file`, one per call; the first error ends them.
struct CsvRows {
    file: String,
    lines: std::io::Lines<BufReader<File>>,
    coordinates: Vec<String>,
    m: usize,
    h: Option<f64>,
    columns: Option<Vec<(Column, String)>>,
    blank_since: Option<usize>,
    /// The line number last read.
    no: usize,
    /// The row index of the next row.
    k: usize,
    done: bool,
}

impl Iterator for CsvRows {
    type Item = Result<Row, Error>;
    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let row = self.row().transpose();
        if !matches!(row, Some(Ok(_))) {
            self.done = true;
        }
        row
    }
}

impl CsvRows {
    fn at(&self) -> String {
        format!("--trajectory `{}` line {}", self.file, self.no)
    }

    /// The next row, `None` at the end of the file.
    fn row(&mut self) -> Result<Option<Row>, Error> {
        let n = self.coordinates.len();
        loop {
            let Some(line) = self.lines.next() else {
                return Ok(None);
            };
            self.no += 1;
            let line = line.map_err(|e| Error::input(format!("{}: {e}", self.at())))?;
            let line = line.strip_suffix('\r').unwrap_or(&line);
            if line.trim().is_empty() {
                self.blank_since.get_or_insert(self.no);
                continue;
            }
            if let Some(b) = self.blank_since {
                self.no = b;
                return Err(Error::input(format!(
                    "{}: an empty line in the middle of the data; remove it",
                    self.at()
                )));
            }
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if self.columns.is_none() {
                // a first line with a cell that is not a number is the header
                if cells.iter().any(|c| protocol::parse_num("", c).is_err()) {
                    let cols = header_columns(&cells, &self.coordinates, self.m)
                        .map_err(|e| Error::input(format!("{}: {}", self.at(), e.message())))?;
                    self.columns = Some(cols);
                    continue;
                }
                self.columns = Some(
                    (0..n)
                        .map(|i| (Column::Coordinate(i), self.coordinates[i].clone()))
                        .collect(),
                );
            }
            let cols = self.columns.as_deref().unwrap_or_default();
            if cells.len() != cols.len() {
                let at = InputKind::Row {
                    row: self.k,
                    column: None,
                };
                return Err(Error::input_at(
                    at,
                    format!(
                        "{}: {} cells, expected {} ({}){}",
                        self.at(),
                        cells.len(),
                        cols.len(),
                        cols.iter()
                            .map(|c| c.1.as_str())
                            .collect::<Vec<_>>()
                            .join(","),
                        if self.k == 0 && cols.len() == n {
                            "; without a header line the columns are the coordinates in order"
                        } else {
                            ""
                        }
                    ),
                ));
            }
            let (k, h) = (self.k, self.h);
            let mut q = vec![f64::NAN; n];
            let mut time = None;
            for (c, (cell, (what, name))) in cells.iter().zip(cols).enumerate() {
                let x = protocol::parse_num(
                    &format!("{}, column {} (`{name}`)", self.at(), c + 1),
                    cell,
                )
                .map_err(|e| {
                    e.of_kind(InputKind::Row {
                        row: k,
                        column: Some(c),
                    })
                })?;
                match what {
                    Column::Coordinate(i) => q[*i] = x,
                    Column::K if x != k as f64 => {
                        return Err(Error::input_at(InputKind::Row { row: k, column: Some(c) }, format!(
                            "{}: k = {x}, but this is row {k} of the data (rows must be q_0, q_1, .. in order)",
                            self.at()
                        )))
                    }
                    Column::T => {
                        if let Some(h) = h {
                            time_is_kh(x, k, h).map_err(|e| {
                                Error::input_at(InputKind::Times, format!("{}: {e}", self.at()))
                            })?;
                        }
                        time = Some(x);
                    }
                    _ => {}
                }
            }
            self.k += 1;
            return Ok(Some((time, q)));
        }
    }
}

/// With `--h`, the time of row `k` must be `k h` (to 1e-6 relative).
fn time_is_kh(t: f64, k: usize, h: f64) -> Result<(), String> {
    if (t - k as f64 * h).abs() > 1e-6 * (k as f64 * h).abs().max(h) {
        return Err(format!(
            "t = {t}, but k h = {} for row {k} with --h {h}",
            k as f64 * h
        ));
    }
    Ok(())
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
