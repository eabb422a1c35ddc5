//! Running the built binary from an integration test: arguments as OS strings, bytes on
//! stdin, stdout and stderr drained on threads (a large output cannot block the child), and
//! a hang guard. Shared by the command-line tests (through `crate::common`).

#![allow(dead_code)]

use std::ffi::OsString;
use std::io::{Read, Write};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Output of one run of the binary.
#[derive(Debug)]
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Run `dalembert args` with `stdin`; a run longer than `limit` is killed and fails the test
/// (a hang guard: no assertion of these tests is about time).
pub fn run_binary(args: Vec<OsString>, stdin: &[u8], limit: Duration) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .args(&args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn dalembert");
    let mut inp = child.stdin.take().unwrap();
    let data = stdin.to_vec();
    let t_in = std::thread::spawn(move || {
        let _ = inp.write_all(&data);
    });
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut s = Vec::new();
        out.read_to_end(&mut s).map(|_| s)
    });
    let t_err = std::thread::spawn(move || {
        let mut s = Vec::new();
        err.read_to_end(&mut s).map(|_| s)
    });
    let start = Instant::now();
    let status = loop {
        if let Some(st) = child.try_wait().expect("wait") {
            break st;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("dalembert {args:?} did not finish within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let _ = t_in.join();
    let stdout = String::from_utf8(t_out.join().unwrap().unwrap()).expect("stdout is UTF-8");
    let stderr = String::from_utf8(t_err.join().unwrap().unwrap()).expect("stderr is UTF-8");
    let code = status
        .code()
        .unwrap_or_else(|| panic!("dalembert {args:?} was killed by a signal: {status:?}"));
    Run {
        code,
        stdout,
        stderr,
    }
}

/// The binary run with `args` (no stdin), its whole output.
pub fn run_args(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .args(args)
        .output()
        .unwrap()
}

/// The binary run with the words of `line` as its arguments (no stdin), its whole output.
pub fn run_line(line: &str) -> std::process::Output {
    run_args(&line.split_whitespace().collect::<Vec<_>>())
}

/// `dalembert batch` fed `input`; it must exit 0; its answers parsed, one per line.
pub fn batch_answers(input: &str) -> Vec<serde_json::Value> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .arg("batch")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}
