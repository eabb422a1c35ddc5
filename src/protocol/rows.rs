//! The answers of `integrate` and `check` written row by row, as the rows are known, in
//! memory independent of their number: each row goes to one or more parts (the CSV or the
//! table; for JSON one part per array of the object), and `finish` writes the whole answer
//! with every part copied in its place. Where the parts are kept (the command line spools
//! them to temporary files) is the caller's business. The bytes are those of
//! [`super::Answer::to_text`] or [`super::Answer::to_json`] of the same answer, and a
//! newline.

use super::Tolerances;
use crate::schemes::Row;
use crate::Interval;
use serde_json::Value;
use std::io::{self, Write};

// The rows are the lower layer: `answer.rs` renders whole answers with them and re-exports
// these two, and nothing here imports from `answer.rs`.

/// `[lo, hi]`; serde_json prints f64 in shortest round-trip form.
pub fn interval(x: Interval) -> Value {
    serde_json::to_value(x).unwrap_or(Value::Null)
}

/// The intervals as a JSON array of `[lo, hi]`.
pub fn intervals(x: &[Interval]) -> Value {
    serde_json::to_value(x).unwrap_or(Value::Null)
}

/// One f64 as serde_json prints it (shortest round-trip form), as the JSON answers do.
fn num(w: &mut impl Write, x: f64) -> io::Result<()> {
    serde_json::to_writer(&mut *w, &x).map_err(io::Error::other)
}

/// `[x,..]` with [`num`].
fn list(w: &mut impl Write, xs: &[f64]) -> io::Result<()> {
    w.write_all(b"[")?;
    for (i, x) in xs.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        num(w, *x)?;
    }
    w.write_all(b"]")
}

/// The `integrate` answer row by row: the CSV `k,q0..,p0..,energy` (one part), or the
/// object of contract command 4 (four parts: the arrays `q`, `p`, `energy`,
/// `newton_iterations`).
#[derive(Debug)]
pub struct IntegrateRows {
    json: bool,
    /// The number of coordinates (the CSV header's `q` columns).
    n: usize,
    /// Whether each JSON part is still empty.
    first: [bool; 4],
}

impl IntegrateRows {
    /// The rows of an `integrate` answer for a scene of `n` coordinates: the object of
    /// contract command 4 when `json`, else the CSV.
    pub fn new(json: bool, n: usize) -> Self {
        IntegrateRows {
            json,
            n,
            first: [true; 4],
        }
    }

    /// How many parts [`IntegrateRows::row`] writes to.
    pub fn parts(&self) -> usize {
        if self.json {
            4
        } else {
            1
        }
    }

    /// Row `r.k` (rows come in order from 0), appended to its parts.
    pub fn row(&mut self, parts: &mut [impl Write], r: &Row) -> io::Result<()> {
        if !self.json {
            return csv_row(&mut parts[0], r, self.n);
        }
        let first = &mut self.first;
        let mut sep = |i: usize, w: &mut dyn Write| -> io::Result<()> {
            if !std::mem::replace(&mut first[i], false) {
                w.write_all(b",")?;
            }
            Ok(())
        };
        sep(0, &mut parts[0])?;
        list(&mut parts[0], r.q)?;
        if let Some(p) = r.p {
            sep(1, &mut parts[1])?;
            list(&mut parts[1], p)?;
        }
        if let Some(e) = r.energy {
            sep(2, &mut parts[2])?;
            num(&mut parts[2], e)?;
        }
        if let Some(it) = r.iterations {
            sep(3, &mut parts[3])?;
            write!(parts[3], "{it}")?;
        }
        Ok(())
    }

    /// The whole answer into `w` once every row is written: `part(i, w)` appends part `i`.
    pub fn finish<W: Write>(
        &self,
        w: &mut W,
        max_residual: f64,
        mut part: impl FnMut(usize, &mut W) -> io::Result<()>,
    ) -> io::Result<()> {
        if !self.json {
            return part(0, w);
        }
        // the keys in serde_json's order, as in the batch answer (`trajectory`)
        w.write_all(b"{\"energy\":[")?;
        part(2, w)?;
        w.write_all(b"],\"max_residual\":")?;
        num(w, max_residual)?;
        w.write_all(b",\"newton_iterations\":[")?;
        part(3, w)?;
        w.write_all(b"],\"p\":[")?;
        part(1, w)?;
        w.write_all(b"],\"q\":[")?;
        part(0, w)?;
        w.write_all(b"]}\n")
    }
}

/// A CSV row of `integrate`, after the header at row 0.
fn csv_row(w: &mut impl Write, r: &Row, n: usize) -> io::Result<()> {
    if r.k == 0 {
        w.write_all(b"k")?;
        (0..n).try_for_each(|i| write!(w, ",q{i}"))?;
        if let Some(p) = r.p {
            (0..p.len()).try_for_each(|a| write!(w, ",p{a}"))?;
            w.write_all(b",energy")?;
        }
        w.write_all(b"\n")?;
    }
    write!(w, "{}", r.k)?;
    for x in r.q.iter().chain(r.p.into_iter().flatten()).chain(&r.energy) {
        w.write_all(b",")?;
        num(w, *x)?;
    }
    w.write_all(b"\n")
}

/// The `check` answer row by row: the verdict table (one part), or the object of the batch
/// `check` answer (three parts: the arrays `distance`, `defect`, `energy_error`).
#[derive(Debug)]
pub struct CheckRows {
    json: bool,
}

impl CheckRows {
    /// The rows of a `check` answer: the batch object when `json`, else the verdict table.
    pub fn new(json: bool) -> Self {
        CheckRows { json }
    }

    /// How many parts [`CheckRows::row`] writes to.
    pub fn parts(&self) -> usize {
        if self.json {
            3
        } else {
            1
        }
    }

    /// Row `k` (rows come in order from 0): its distance, and the defect and energy error
    /// of the pair `(q_k, q_k+1)` when known.
    pub fn row(
        &self,
        parts: &mut [impl Write],
        k: usize,
        distance: Interval,
        pair: Option<(&[Interval], Interval)>,
    ) -> io::Result<()> {
        if !self.json {
            let (def, en) = match pair {
                Some((defect, energy_error)) => (
                    defect
                        .iter()
                        .map(|x| short(*x))
                        .collect::<Vec<_>>()
                        .join(" "),
                    short(energy_error),
                ),
                None => (String::new(), String::new()),
            };
            return writeln!(
                parts[0],
                "{k:>6} {:>24.3e} {def:>24} {en:>24}",
                distance.sup()
            );
        }
        let sep = if k > 0 { "," } else { "" };
        write!(parts[0], "{sep}{}", interval(distance))?;
        if let Some((defect, energy_error)) = pair {
            write!(parts[1], "{sep}{}", intervals(defect))?;
            write!(parts[2], "{sep}{}", interval(energy_error))?;
        }
        Ok(())
    }

    /// The whole answer into `w` once every row is written: `part(i, w)` appends part `i`.
    /// The text is the table's header, its rows and the summary line (the largest
    /// distance and defect, the tolerances given and the decision).
    #[allow(clippy::too_many_arguments)]
    pub fn finish<W: Write>(
        &self,
        w: &mut W,
        max_distance: Interval,
        max_defect: Option<Interval>,
        tolerances: &Tolerances,
        passed: bool,
        precision: Option<u32>,
        mut part: impl FnMut(usize, &mut W) -> io::Result<()>,
    ) -> io::Result<()> {
        if self.json {
            // the keys in serde_json's order, as in the batch answer (`verdict`)
            w.write_all(b"{\"defect\":[")?;
            part(1, w)?;
            w.write_all(b"],\"distance\":[")?;
            part(0, w)?;
            w.write_all(b"],\"energy_error\":[")?;
            part(2, w)?;
            w.write_all(b"]")?;
            if let Some(m) = max_defect {
                write!(w, ",\"max_defect\":{}", interval(m))?;
            }
            write!(
                w,
                ",\"max_distance\":{},\"passed\":{passed}",
                interval(max_distance)
            )?;
            if let Some(bits) = precision {
                write!(w, ",\"precision\":{bits}")?;
            }
            w.write_all(b"}")?;
        } else {
            writeln!(
                w,
                "{:>6} {:>24} {:>24} {:>24}",
                "k", "|q_k - q^e_k| <=", "defect(q_k,q_k+1) in", "energy error in"
            )?;
            part(0, w)?;
            write!(w, "max distance <= {:.3e}", max_distance.sup())?;
            if let Some(m) = max_defect {
                write!(w, "; max defect <= {:.3e}", m.sup())?;
            }
            let word = if passed { "PASS" } else { "FAIL (proved)" };
            if let Some(t) = tolerances.tol {
                write!(w, "; tolerance {t:e}")?;
            }
            if let Some(t) = tolerances.defect_tol {
                write!(w, "; defect tolerance {t:e}")?;
            }
            if tolerances.tol.is_some() || tolerances.defect_tol.is_some() {
                write!(w, ": {word}")?;
            }
            if let Some(bits) = precision {
                write!(w, " (computed with {bits} bits)")?;
            }
        }
        writeln!(w)
    }
}

/// `[lo,hi]` with three significant digits, for the table.
fn short(x: Interval) -> String {
    format!("[{:.2e},{:.2e}]", x.inf(), x.sup())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::oracle::{check_rows, CheckOptions, Steps};
    use crate::protocol::{Answer, Pair, Query, SceneSpec, Session};
    use crate::schemes::SchemeKind;

    fn pair() -> Pair {
        Pair {
            scene: SceneSpec::named("particle", vec![]),
            q0: vec![0.0, 0.0, 0.0],
            q1: vec![0.4, 0.4, 0.0],
            h: 0.5,
        }
    }

    /// The streamed form of `integrate` (what the command prints) is the whole answer's
    /// rendering, in both formats, with and without steps.
    #[test]
    fn integrate_rows_render_the_whole_answer() {
        for steps in [0, 6] {
            let mut s = Session::default();
            let whole = s
                .answer(&Query::Integrate {
                    pair: pair(),
                    scheme: SchemeKind::Mla,
                    steps,
                })
                .unwrap();
            for json in [false, true] {
                let mut rows = IntegrateRows::new(json, 3);
                let mut parts = vec![Vec::new(); rows.parts()];
                let max_residual = s
                    .integrate_each(&pair(), SchemeKind::Mla, steps, None, |r| {
                        rows.row(&mut parts, &r)
                            .map_err(|e| crate::Error::input(e.to_string()))
                    })
                    .unwrap();
                let mut out = Vec::new();
                rows.finish(&mut out, max_residual, |i, w| w.write_all(&parts[i]))
                    .unwrap();
                assert_eq!(String::from_utf8(out).unwrap(), whole.render(json) + "\n");
            }
        }
    }

    /// The streamed form of `check` is the whole answer's rendering: the batch object and
    /// the table with its summary line, with and without the pairs' figures.
    #[test]
    fn check_rows_render_the_whole_answer() {
        let Answer::Integrate(t) = Session::default()
            .answer(&Query::Integrate {
                pair: pair(),
                scheme: SchemeKind::Dla,
                steps: 4,
            })
            .unwrap()
        else {
            panic!("not an integrate answer")
        };
        let model = Session::default()
            .model(&SceneSpec::named("particle", vec![]))
            .unwrap();
        for pairs in [true, false] {
            let tol = Some(1e-3);
            let whole = Session::default()
                .answer(&Query::Check {
                    scene: SceneSpec::named("particle", vec![]),
                    steps: Steps::Uniform(0.5),
                    q: t.q.clone(),
                    tol,
                    defect_tol: None,
                    pairs,
                })
                .unwrap();
            let Answer::Check { passed, .. } = whole else {
                panic!("not a check answer")
            };
            for json in [false, true] {
                let table = CheckRows::new(json);
                let mut parts = vec![Vec::new(); table.parts()];
                let opts = CheckOptions {
                    pairs,
                    ..CheckOptions::default()
                };
                let rows = t.q.iter().cloned().map(|q| Ok((None, q)));
                let summary = check_rows(&model, Some(0.5), rows, &opts, |r| {
                    let pair = r
                        .pair
                        .as_ref()
                        .map(|p| (p.defect.as_slice(), p.energy_error));
                    table
                        .row(&mut parts, r.k, r.distance, pair)
                        .map_err(|e| crate::Error::input(e.to_string()))
                })
                .unwrap();
                let tolerances = Tolerances {
                    tol,
                    defect_tol: None,
                };
                let mut out = Vec::new();
                table
                    .finish(
                        &mut out,
                        summary.max_distance,
                        summary.max_defect,
                        &tolerances,
                        passed,
                        None,
                        |i, w| w.write_all(&parts[i]),
                    )
                    .unwrap();
                assert_eq!(String::from_utf8(out).unwrap(), whole.render(json) + "\n");
            }
        }
    }
}
