//! `dalembert batch` talked to line by line: a client that sends lines and waits gets every
//! answer to what it sent (however the lines arrive: one per write, two in one write, a
//! blank line after one, a line in two writes), and the bytes it reads are those of one
//! `batch` run on the whole input at once.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use crate::common::run_binary;

/// A hang guard only (no assertion here is about time).
const HANG: Duration = Duration::from_secs(120);

fn query(id: usize) -> String {
    format!(
        r#"{{"id":{id},"cmd":"step","scene":"particle","q0":[0.1,0.2,0.3],"q1":[0.5,0.6,0.55],"h":0.{id}}}"#
    )
}

#[test]
fn each_answer_arrives_before_the_next_line_is_sent() {
    // (bytes written at once, the ids answered by then)
    let writes: Vec<(String, Vec<usize>)> = vec![
        (format!("{}\n", query(1)), vec![1]),
        (format!("{}\n\n", query(2)), vec![2]),
        (format!("{}\n{}\n", query(3), query(4)), vec![3, 4]),
        (query(5)[..30].to_string(), vec![]),
        (format!("{}\n", &query(5)[30..]), vec![5]),
        ("not json\n".to_string(), vec![0]),
        (format!("{}\n", query(6)), vec![6]),
    ];
    let all: String = writes.iter().map(|(w, _)| w.as_str()).collect();
    for jobs in ["1", "2"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_dalembert"))
            .args(["batch", "--jobs", jobs])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let stdout = BufReader::new(child.stdout.take().unwrap());
        let (tx, rx) = mpsc::channel();
        let reader = std::thread::spawn(move || {
            for line in stdout.lines() {
                if tx.send(line.unwrap()).is_err() {
                    return;
                }
            }
        });
        let mut read = String::new();
        for (bytes, ids) in &writes {
            stdin.write_all(bytes.as_bytes()).unwrap();
            stdin.flush().unwrap();
            for id in ids {
                let line = rx.recv_timeout(HANG).expect("an answer to what was sent");
                let answer: serde_json::Value = serde_json::from_str(&line).unwrap();
                let want = if *id == 0 {
                    serde_json::Value::Null
                } else {
                    (*id).into()
                };
                assert_eq!(answer["id"], want, "jobs {jobs}: {line}");
                read += &line;
                read.push('\n');
            }
        }
        drop(stdin);
        assert!(child.wait().unwrap().success());
        reader.join().unwrap();
        assert!(rx.try_recv().is_err(), "no answer beyond the lines sent");
        let once = run_binary(vec!["batch".into()], all.as_bytes(), HANG);
        assert_eq!(read, once.stdout, "jobs {jobs}");
    }
}
