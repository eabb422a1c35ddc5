//! `dalembert integrate`: the scheme's rows written as they come, in memory independent of
//! the number of steps. They are spooled to an unnamed temporary file and copied to stdout
//! only when the whole trajectory is done, so that a refusal (exit 2 or 3, e.g. past
//! `--deadline`) still leaves stdout empty (contract.md) and no partial answer is printed
//! as whole.

use super::progress::Bar;
use super::spool::Spool;
use crate::protocol::{Budget, IntegrateRows, Pair, Row, Session};
use crate::schemes::SchemeKind;
use crate::Error;
use std::io::{BufWriter, Write};

pub(super) fn io(e: std::io::Error) -> Error {
    Error::input(format!("writing the output: {e}"))
}

/// Run the integration and write its answer (CSV `k,q..,p..,energy`, or with `as_json`
/// the object of contract command 4, as `protocol::IntegrateRows` renders them) to stdout;
/// nothing is written on an error.
pub fn run(
    pair: &Pair,
    scheme: SchemeKind,
    steps: usize,
    budget: Budget,
    as_json: bool,
) -> Result<(), Error> {
    let mut session = Session::default();
    let mut bar = Bar::new();
    let mut rows = IntegrateRows::new(as_json, pair.q0.len());
    // one spool per part of the answer (CSV: one; JSON: q, p, energy, Newton iterations)
    let mut spools: Vec<Spool> = (0..rows.parts())
        .map(|i| Spool::new(&i.to_string()))
        .collect::<Result<_, _>>()?;
    let max_residual = session.integrate_each_with(pair, scheme, steps, budget, |r: Row| {
        bar.update("integrate", r.k as f64, steps as f64);
        rows.row(&mut spools, &r).map_err(io)
    })?;
    bar.clear();
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    rows.finish(&mut out, max_residual, |i, w| spools[i].copy_to(w))
        .and_then(|()| out.flush())
        .map_err(io)
}
