//! `dalembert batch [--jobs N] [--deadline S] [--work W]` (contract command 5): JSON lines in, JSON
//! lines out, in order. Input is read as bytes, line by line, each line at most
//! `protocol::MAX_LINE_BYTES` kept: a line that is not UTF-8, not JSON or too long gets an
//! error answer and the stream goes on. Each worker keeps its own `Session` (compiled
//! scenes); answers are printed as soon as all earlier lines are answered, and flushed at
//! the latest when the next line has not arrived yet, so a client may talk line by line.

use crate::protocol::{self, Line, LineReader, Session, MAX_LINE_BYTES};
use crate::Error;
use std::collections::BTreeMap;
use std::io::{BufReader, BufWriter, Write};
use std::sync::{mpsc, Arc, Mutex};

pub fn run(
    jobs: &str,
    deadline: Option<&str>,
    work: Option<&str>,
    max_steps: Option<&str>,
) -> Result<(), Error> {
    let jobs: usize = match jobs.trim().parse() {
        Ok(j) if (1..=256).contains(&j) => j,
        _ => {
            return Err(Error::input(format!(
                "--jobs: expected an integer in 1..=256, got `{jobs}`"
            )))
        }
    };
    let deadline = deadline
        .map(|d| protocol::parse_seconds("--deadline", d))
        .transpose()?;
    let work = work
        .map(|w| protocol::parse_work("--work", w))
        .transpose()?;
    let max_steps = max_steps
        .map(|n| protocol::parse_max_steps("--max-steps", n))
        .transpose()?;
    let session = move || {
        let mut s = Session::default();
        s.deadline = deadline;
        s.work = work;
        s.max_steps = max_steps;
        s
    };
    let stdin = std::io::stdin();
    let read = |e: std::io::Error| Error::input(format!("reading stdin: {e}"));
    let stdout = std::io::stdout();
    if jobs == 1 {
        let mut session = session();
        // Answers are flushed when no whole line is left in the input buffer (before reading
        // could wait): a client waiting for an answer has it, and one that sends many lines at
        // once gets their answers in a few large writes instead of one write each.
        let mut lines = LineReader::new(
            BufReader::with_capacity(1 << 16, stdin.lock()),
            MAX_LINE_BYTES,
        );
        let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
        let mut no = 0;
        while let Some(line) = lines.next_line().map_err(read)? {
            no += 1;
            if let Some(answer) = session.batch_answer(no, &line) {
                if !write_line(&mut out, &answer.text)? {
                    return Ok(());
                }
            }
            if !lines.get_ref().buffer().contains(&b'\n') && !flush(&mut out)? {
                return Ok(());
            }
        }
        return flush(&mut out).map(|_| ());
    }
    let mut lines = LineReader::new(stdin.lock(), MAX_LINE_BYTES);
    let (work_tx, work_rx) = mpsc::channel::<(usize, Line)>();
    let work_rx = Arc::new(Mutex::new(work_rx));
    let (done_tx, done_rx) = mpsc::channel::<(usize, Option<String>)>();
    let workers: Vec<_> = (0..jobs)
        .map(|_| {
            let rx = Arc::clone(&work_rx);
            let tx = done_tx.clone();
            std::thread::spawn(move || {
                let mut session = session();
                loop {
                    let next = match rx.lock() {
                        Ok(guard) => guard.recv(),
                        Err(_) => return,
                    };
                    let Ok((i, line)) = next else { return };
                    let answer = session.batch_answer(i + 1, &line).map(|a| a.text);
                    if tx.send((i, answer)).is_err() {
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
                    if !(write_line(&mut out, &a)? && flush(&mut out)?) {
                        return Ok(());
                    }
                }
                next += 1;
            }
        }
        Ok(())
    });
    let mut i = 0;
    let mut failed = None;
    loop {
        match lines.next_line() {
            Ok(Some(line)) => {
                if work_tx.send((i, line)).is_err() {
                    break;
                }
                i += 1;
            }
            Ok(None) => break,
            Err(e) => {
                failed = Some(read(e));
                break;
            }
        }
    }
    drop(work_tx);
    for w in workers {
        let _ = w.join();
    }
    let printed = match printer.join() {
        Ok(r) => r,
        Err(_) => Err(Error::internal_at(
            crate::Invariant::Output,
            "the batch printer stopped",
        )),
    };
    printed.and(failed.map_or(Ok(()), Err))
}

/// Write one answer line. `Ok(false)` when the reader has closed the pipe
/// (`dalembert batch < q | head -1`): nobody is left to answer, so the stream ends quietly.
fn write_line(out: &mut impl Write, text: &str) -> Result<bool, Error> {
    written(writeln!(out, "{text}"))
}

/// Flush the answers written; `Ok(false)` on a closed pipe, as in `write_line`.
fn flush(out: &mut impl Write) -> Result<bool, Error> {
    written(out.flush())
}

fn written(result: std::io::Result<()>) -> Result<bool, Error> {
    match result {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(false),
        Err(e) => Err(Error::uncertified(format!("writing stdout: {e}"))),
    }
}
