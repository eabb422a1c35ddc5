//! The work budget (contract E14, spec (5.8''')): `--work N`, the `"work"` key and
//! `batch --work N` refuse a query once it has done N Taylor terms (exit 3, reason
//! `budget`), the same on every run; the default budget of a single-step query is
//! `STEP_WORK` terms, not a wall-clock time, so a batch file answers byte for byte the same
//! on an idle machine and with both cores busy; a query that names a `deadline` runs within
//! that deadline alone, as before.

use dalembert::protocol::{default_work, Budget, Query, Session, STEP_WORK};
use serde_json::Value;
use std::ffi::OsString;
use std::process::{Child, Command};
use std::time::Duration;

use crate::common::{run_binary, Run};

/// A hang guard only: far above any run below.
const HANG: Duration = Duration::from_secs(300);

fn run(args: &[&str], stdin: &[u8]) -> Run {
    run_binary(args.iter().map(OsString::from).collect(), stdin, HANG)
}

fn answers(r: &Run) -> Vec<Value> {
    assert_eq!(r.code, 0, "{r:?}");
    r.stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

const STEP: &str =
    r#"{"id":1,"cmd":"step","scene":"particle","q0":[0.1,0.2,0.3],"q1":[0.5,0.6,0.55],"h":0.3"#;

#[test]
fn a_small_work_is_refused_with_reason_budget_every_time() {
    let line = format!("{STEP},\"work\":1000}}\n");
    for _ in 0..3 {
        let a = answers(&run(&["batch"], line.as_bytes()));
        assert_eq!(a.len(), 1);
        assert_eq!(a[0]["id"], 1);
        assert_eq!(a[0]["error"]["code"], 3, "{}", a[0]);
        assert_eq!(a[0]["error"]["reason"], "budget", "{}", a[0]);
        let m = a[0]["error"]["message"].as_str().unwrap();
        assert!(m.starts_with("not certified within the budget"), "{m}");
    }
    // the same query within a large work, or the default, is answered, and identically
    let big = answers(&run(
        &["batch"],
        format!("{STEP},\"work\":1000000000}}\n").as_bytes(),
    ));
    let default = answers(&run(&["batch"], format!("{STEP}}}\n").as_bytes()));
    assert!(big[0]["ok"]["q2"].is_array(), "{}", big[0]);
    assert_eq!(big, default);
}

#[test]
fn batch_work_is_the_budget_of_every_query_without_one() {
    let lines = format!(
        "{STEP}}}\n{}\n",
        STEP.replace("\"id\":1", "\"id\":2") + ",\"work\":1000000000}"
    );
    let a = answers(&run(&["batch", "--work", "1000"], lines.as_bytes()));
    assert_eq!(a[0]["error"]["reason"], "budget", "{}", a[0]);
    assert!(a[1]["ok"].is_object(), "{}", a[1]);
    // a query's own deadline replaces the default work, not a work the session names
    let line = format!("{STEP},\"deadline\":1000}}\n");
    let a = answers(&run(&["batch", "--work", "1000"], line.as_bytes()));
    assert_eq!(a[0]["error"]["reason"], "budget", "{}", a[0]);
    let a = answers(&run(&["batch"], line.as_bytes()));
    assert!(a[0]["ok"].is_object(), "{}", a[0]);
}

#[test]
fn work_flags_refuse_and_answer_on_every_command_that_takes_a_budget() {
    let pair = [
        "--scene",
        "particle",
        "--q0",
        "0.1,0.2,0.3",
        "--q1",
        "0.5,0.6,0.55",
        "--h",
        "0.3",
    ];
    for cmd in ["retract", "step", "lagrangian"] {
        let mut a = vec![cmd];
        a.extend(pair);
        a.extend(["--work", "1000"]);
        let r = run(&a, b"");
        assert_eq!(r.code, 3, "{cmd}: {r:?}");
        assert!(r.stdout.is_empty());
        assert!(
            r.stderr.contains("not certified within the budget"),
            "{r:?}"
        );
        a.pop();
        a.push("1000000000");
        assert_eq!(run(&a, b"").code, 0, "{cmd}");
    }
    let flow = [
        "flow", "--scene", "knife", "--q", "0,0,0", "--u", "1,0.5", "--t", "3",
    ];
    let mut a = flow.to_vec();
    a.extend(["--work", "10"]);
    let r = run(&a, b"");
    assert_eq!(r.code, 3, "{r:?}");
    assert_eq!(run(&flow, b"").code, 0);
    // check: the work is for the whole check
    let dir = std::env::temp_dir().join(format!("work_budget_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let traj = dir.join("line.json");
    std::fs::write(&traj, "[[0,0.5,0],[0.125,0.5,0.0625],[0.25,0.5,0.125]]").unwrap();
    let traj = traj.to_str().unwrap();
    let check = [
        "check",
        "--scene",
        "particle",
        "--h",
        "0.125",
        "--trajectory",
        traj,
    ];
    let mut a = check.to_vec();
    a.extend(["--work", "1000"]);
    let r = run(&a, b"");
    assert_eq!(r.code, 3, "{r:?}");
    assert_eq!(run(&check, b"").code, 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_work_must_be_a_positive_integer() {
    for bad in ["0", "-1", "1.5", "1e6", "x", ""] {
        let mut a = vec![
            "step",
            "--scene",
            "particle",
            "--q0",
            "0,0,0",
            "--q1",
            "0.1,0.1,0",
        ];
        a.extend(["--h", "0.1", "--work", bad]);
        let r = run(&a, b"");
        assert_eq!(r.code, 2, "{bad}: {r:?}");
        assert!(r.stderr.contains("--work"), "{r:?}");
        let r = run(&["batch", "--work", bad], b"");
        assert_eq!(r.code, 2, "{bad}: {r:?}");
    }
    for bad in ["0", "-1", "1.5", "1e6", "\"10\"", "null", "true"] {
        let line = format!("{STEP},\"work\":{bad}}}\n");
        let a = answers(&run(&["batch"], line.as_bytes()));
        assert_eq!(a[0]["id"], 1);
        assert_eq!(a[0]["error"]["code"], 2, "{bad}: {}", a[0]);
        assert!(a[0]["error"]["message"]
            .as_str()
            .unwrap()
            .contains("`work`"));
    }
}

#[test]
fn the_default_budget_is_work_unless_a_budget_is_named() {
    let q = Query::from_json(&serde_json::from_str(&format!("{STEP}}}")).unwrap()).unwrap();
    let s = Session::default();
    let none = Budget::default();
    assert_eq!(
        s.budget_of(&q, none),
        Budget {
            deadline: None,
            work: Some(STEP_WORK),
            ..Budget::default()
        }
    );
    assert_eq!(default_work(&q), Some(STEP_WORK));
    let d = Budget {
        deadline: Some(2.0),
        work: None,
        ..Budget::default()
    };
    assert_eq!(s.budget_of(&q, d), d);
    let w = Budget {
        deadline: None,
        work: Some(5),
        ..Budget::default()
    };
    assert_eq!(s.budget_of(&q, w), w);
    let mut s = Session::default();
    s.deadline = Some(3.0);
    assert_eq!(
        s.budget_of(&q, none),
        Budget {
            deadline: Some(3.0),
            work: None,
            ..Budget::default()
        }
    );
    let mut s = Session::default();
    s.work = Some(7);
    assert_eq!(
        s.budget_of(&q, none),
        Budget {
            deadline: None,
            work: Some(7),
            ..Budget::default()
        }
    );
    // a check: STEP_WORK per row; flow and integrate: none (their step counts bound them)
    let check = r#"{"cmd":"check","scene":"particle","h":0.1,"q":[[0,0,0],[0.1,0,0],[0.2,0,0]]}"#;
    let check = Query::from_json(&serde_json::from_str(check).unwrap()).unwrap();
    assert_eq!(default_work(&check), Some(3 * STEP_WORK));
    let flow = r#"{"cmd":"flow","scene":"knife","q":[0,0,0],"u":[1,1],"t":1}"#;
    let flow = Query::from_json(&serde_json::from_str(flow).unwrap()).unwrap();
    assert_eq!(default_work(&flow), None);
}

/// A deterministic mix of 1,000 queries: particle, knife, sleigh and rolling-disk steps,
/// retractions and Lagrangians at random pairs, flows, checks, refusals of input, and
/// queries with a `work` near what they need (answered or refused by the work alone).
fn thousand_queries() -> String {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut out = String::new();
    for i in 0..1000 {
        let mut r = || 2.0 * next() - 1.0;
        let (q0, v) = ([r(), r(), r()], [r(), r(), r()]);
        let h = [0.0625, 0.125, 0.25, 0.5][i % 4];
        let q1: Vec<f64> = q0.iter().zip(&v).map(|(a, b)| a + h * b).collect();
        let cmd = ["step", "retract", "lagrangian"][i % 3];
        let line = match i % 10 {
            0..=3 => format!(
                r#"{{"id":{i},"cmd":"{cmd}","scene":"particle","q0":{q0:?},"q1":{q1:?},"h":{h}}}"#
            ),
            4 | 5 => format!(
                r#"{{"id":{i},"cmd":"{cmd}","scene":"knife","q0":{q0:?},"q1":{q1:?},"h":{h}}}"#
            ),
            6 => format!(
                r#"{{"id":{i},"cmd":"{cmd}","scene":"sleigh","q0":{q0:?},"q1":{q1:?},"h":{h}}}"#
            ),
            7 => format!(
                r#"{{"id":{i},"cmd":"flow","scene":"knife","q":{q0:?},"u":[{},{}],"t":{}}}"#,
                v[0],
                v[1],
                4.0 * h
            ),
            8 => format!(
                r#"{{"id":{i},"cmd":"step","scene":"particle","q0":{q0:?},"q1":{q1:?},"h":{h},"work":{}}}"#,
                20_000 + (next() * 200_000.0) as u64
            ),
            _ => match i % 30 {
                9 => format!(r#"{{"id":{i},"cmd":"step","scene":"particle","q0":[0,0]}}"#),
                19 => format!(
                    r#"{{"id":{i},"cmd":"check","scene":"particle","h":0.125,"q":[[0,0.5,0],[0.125,0.5,0.0625],[0.25,0.5,0.125]]}}"#
                ),
                _ => format!(
                    r#"{{"id":{i},"cmd":"retract","scene":"contact-oscillator","q0":{q0:?},"q1":{q1:?},"h":{h}}}"#
                ),
            },
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// Two processes that keep both cores busy for at most `seconds` (killed when dropped).
struct Busy(Vec<Child>);

impl Busy {
    fn start(seconds: u32) -> Busy {
        let spin = format!(
            "end=$(( $(date +%s) + {seconds} )); while [ $(date +%s) -lt $end ]; do :; done"
        );
        Busy(
            (0..2)
                .map(|_| Command::new("sh").args(["-c", &spin]).spawn().expect("sh"))
                .collect(),
        )
    }
}

impl Drop for Busy {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

#[test]
fn a_thousand_query_batch_answers_byte_for_byte_the_same_idle_and_loaded() {
    let input = thousand_queries();
    let idle = run(&["batch"], input.as_bytes());
    let a = answers(&idle);
    assert_eq!(a.len(), 1000);
    let count = |f: &dyn Fn(&Value) -> bool| a.iter().filter(|v| f(v)).count();
    let ok = count(&|v| v["ok"].is_object());
    let budget = count(&|v| v["error"]["reason"] == "budget");
    let input_errors = count(&|v| v["error"]["code"] == 2);
    // most are answered; the small works refuse some and answer others; every kind occurs
    assert!(ok > 800, "{ok} answered");
    assert!(
        (5..100).contains(&budget),
        "{budget} refused for the budget"
    );
    assert!(input_errors >= 30, "{input_errors} input errors");
    let loaded = {
        let _busy = Busy::start(60);
        run(&["batch", "--jobs", "2"], input.as_bytes())
    };
    assert_eq!(loaded.code, 0);
    assert!(
        idle.stdout == loaded.stdout,
        "the loaded run answered differently"
    );
}
