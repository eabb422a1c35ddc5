//! `dalembert batch [--jobs N]` (contract command 5): JSON lines in, JSON lines out, in
//! order. Each worker keeps its own `Session` (compiled scenes); answers are printed as
//! soon as all earlier lines are answered, and flushed, so a client may talk line by line.

use dalembert::protocol::Session;
use dalembert::Error;
use std::collections::BTreeMap;
use std::io::{BufRead, Write};
use std::sync::{mpsc, Arc, Mutex};

pub fn run(jobs: &str) -> Result<(), Error> {
    let jobs: usize = match jobs.trim().parse() {
        Ok(j) if (1..=256).contains(&j) => j,
        _ => {
            return Err(Error::input(format!(
                "--jobs: expected an integer in 1..=256, got `{jobs}`"
            )))
        }
    };
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    if jobs == 1 {
        let mut session = Session::default();
        let mut out = stdout.lock();
        for line in stdin.lock().lines() {
            let line = line.map_err(|e| Error::input(format!("reading stdin: {e}")))?;
            if let Some(answer) = session.batch_line(&line) {
                writeln!(out, "{answer}")
                    .and_then(|_| out.flush())
                    .map_err(broken_pipe)?;
            }
        }
        return Ok(());
    }
    let (work_tx, work_rx) = mpsc::channel::<(usize, String)>();
    let work_rx = Arc::new(Mutex::new(work_rx));
    let (done_tx, done_rx) = mpsc::channel::<(usize, Option<String>)>();
    let workers: Vec<_> = (0..jobs)
        .map(|_| {
            let rx = Arc::clone(&work_rx);
            let tx = done_tx.clone();
            std::thread::spawn(move || {
                let mut session = Session::default();
                loop {
                    let next = match rx.lock() {
                        Ok(guard) => guard.recv(),
                        Err(_) => return,
                    };
                    let Ok((i, line)) = next else { return };
                    if tx.send((i, session.batch_line(&line))).is_err() {
                        return;
                    }
                }
            })
        })
        .collect();
    drop(done_tx);
    let printer = std::thread::spawn(move || -> Result<(), Error> {
        let mut pending: BTreeMap<usize, Option<String>> = BTreeMap::new();
        let mut next = 0usize;
        let mut out = stdout.lock();
        for (i, answer) in done_rx {
            pending.insert(i, answer);
            while let Some(a) = pending.remove(&next) {
                if let Some(a) = a {
                    writeln!(out, "{a}")
                        .and_then(|_| out.flush())
                        .map_err(broken_pipe)?;
                }
                next += 1;
            }
        }
        Ok(())
    });
    for (i, line) in stdin.lock().lines().enumerate() {
        let line = line.map_err(|e| Error::input(format!("reading stdin: {e}")))?;
        if work_tx.send((i, line)).is_err() {
            break;
        }
    }
    drop(work_tx);
    for w in workers {
        let _ = w.join();
    }
    match printer.join() {
        Ok(r) => r,
        Err(_) => Err(Error::uncertified("internal error in the batch printer")),
    }
}

fn broken_pipe(e: std::io::Error) -> Error {
    Error::input(format!("writing stdout: {e}"))
}
