//! `dalembert integrate`: the scheme's rows written as they come, in memory independent of
//! the number of steps. They are spooled to an unnamed temporary file and copied to stdout
//! only when the whole trajectory is done, so that a refusal (exit 2 or 3, e.g. past
//! `--deadline`) still leaves stdout empty (contract.md) and no partial answer is printed
//! as whole.

use super::progress::Bar;
use super::spool::Spool;
use crate::protocol::{Pair, Row, Session};
use crate::schemes::SchemeKind;
use crate::Error;
use std::io::{BufWriter, Write};

pub(super) fn io(e: std::io::Error) -> Error {
    Error::input(format!("writing the output: {e}"))
}

/// One f64 as serde_json prints it (shortest round-trip form), as the JSON answers do.
pub(super) fn num(w: &mut impl Write, x: f64) -> std::io::Result<()> {
    serde_json::to_writer(&mut *w, &x).map_err(std::io::Error::other)
}

fn list(w: &mut impl Write, xs: &[f64]) -> std::io::Result<()> {
    w.write_all(b"[")?;
    for (i, x) in xs.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        num(w, *x)?;
    }
    w.write_all(b"]")
}

/// Run the integration and write its answer (CSV `k,q..,p..,energy`, or with `as_json`
/// the object of contract command 4) to stdout; nothing is written on an error.
pub fn run(
    pair: &Pair,
    scheme: SchemeKind,
    steps: usize,
    deadline: Option<f64>,
    as_json: bool,
) -> Result<(), Error> {
    let mut session = Session::default();
    let mut bar = Bar::new();
    // CSV: one spool. JSON: q, p, energy and the Newton iterations each in its own
    // spool, joined at the end into {"energy","max_residual","newton_iterations","p","q"}.
    let mut spools: Vec<Spool> = (0..if as_json { 4 } else { 1 })
        .map(|i| Spool::new(&i.to_string()))
        .collect::<Result<_, _>>()?;
    let mut first = [true; 4];
    let max_residual = session.integrate_each(pair, scheme, steps, deadline, |r: Row| {
        bar.update("integrate", r.k as f64, steps as f64);
        if as_json {
            write_json_row(&mut spools, &mut first, &r).map_err(io)
        } else {
            write_csv_row(&mut spools[0].out, &r, pair.q0.len()).map_err(io)
        }
    })?;
    bar.clear();
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let w = &mut out;
    let done = (|| -> std::io::Result<()> {
        if as_json {
            w.write_all(b"{\"energy\":[")?;
            spools[2].copy_to(w)?;
            w.write_all(b"],\"max_residual\":")?;
            num(w, max_residual)?;
            w.write_all(b",\"newton_iterations\":[")?;
            spools[3].copy_to(w)?;
            w.write_all(b"],\"p\":[")?;
            spools[1].copy_to(w)?;
            w.write_all(b"],\"q\":[")?;
            spools[0].copy_to(w)?;
            w.write_all(b"]}\n")?;
        } else {
            spools[0].copy_to(w)?;
        }
        w.flush()
    })();
    done.map_err(io)
}

fn write_csv_row(w: &mut impl Write, r: &Row, n: usize) -> std::io::Result<()> {
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

fn write_json_row(spools: &mut [Spool], first: &mut [bool; 4], r: &Row) -> std::io::Result<()> {
    let mut sep = |i: usize, s: &mut Spool| -> std::io::Result<()> {
        if !std::mem::replace(&mut first[i], false) {
            s.out.write_all(b",")?;
        }
        Ok(())
    };
    sep(0, &mut spools[0])?;
    list(&mut spools[0].out, r.q)?;
    if let Some(p) = r.p {
        sep(1, &mut spools[1])?;
        list(&mut spools[1].out, p)?;
    }
    if let Some(e) = r.energy {
        sep(2, &mut spools[2])?;
        num(&mut spools[2].out, e)?;
    }
    if let Some(it) = r.iterations {
        sep(3, &mut spools[3])?;
        write!(spools[3].out, "{it}")?;
    }
    Ok(())
}
