//! The command line of the exact discrete objects (contract.md commands 2 and 3, and the
//! `lagrangian` extension): JSON shape, interval well-formedness, closed forms, exit codes.

use crate::common::*;
use dalembert::scalar::iv;
use dalembert::{exact, AnyScene, FlowOptions, Model};
use serde_json::Value;
use std::process::Command;

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str]) -> Out {
    let o = Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .args(args)
        .output()
        .expect("run dalembert");
    Out {
        code: o.status.code().expect("exit status"),
        stdout: String::from_utf8(o.stdout).unwrap(),
        stderr: String::from_utf8(o.stderr).unwrap(),
    }
}

fn fmt_vec(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:?}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// A `--json` answer: the parsed object (structure) and its text (numbers).
///
/// serde_json's default float parser is not correctly rounded (it may return a neighbour of
/// the printed f64), so interval endpoints are read from the text with `str::parse::<f64>`,
/// which is; the contract promises that the printed form parses back to the identical f64.
struct Answer {
    v: Value,
    text: String,
}

impl Answer {
    fn parse(text: &str) -> Answer {
        let v: Value = serde_json::from_str(text).expect("valid JSON");
        assert!(v.is_object(), "one JSON object: {text}");
        Answer {
            v,
            text: text.to_string(),
        }
    }

    /// The numbers of the value of `key`, read exactly from the text.
    fn numbers(&self, key: &str) -> Vec<f64> {
        let pat = format!("\"{key}\":");
        let start = self.text.find(&pat).unwrap_or_else(|| panic!("no `{key}`")) + pat.len();
        let rest = &self.text[start..];
        let mut depth = 0;
        let mut end = rest.len();
        for (i, ch) in rest.char_indices() {
            match ch {
                '[' => depth += 1,
                ']' => {
                    depth -= 1;
                    if depth == 0 {
                        end = i + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        rest[..end]
            .split(['[', ']', ','])
            .filter(|t| !t.trim().is_empty())
            .map(|t| t.trim().parse::<f64>().expect("a JSON number"))
            .collect()
    }

    /// A contract interval vector: `[[lo, hi], ...]`, finite, lo <= hi.
    fn boxes(&self, key: &str, len: usize) -> Vec<I> {
        let a = self.v[key]
            .as_array()
            .unwrap_or_else(|| panic!("missing `{key}` in {}", self.text));
        assert_eq!(
            a.len(),
            len,
            "`{key}` has {} entries in {}",
            a.len(),
            self.text
        );
        for x in a {
            let x = x.as_array().expect("an interval is an array");
            assert!(
                x.len() == 2 && x.iter().all(|y| y.is_number()),
                "{}",
                self.text
            );
        }
        let nums = self.numbers(key);
        assert_eq!(nums.len(), 2 * len);
        nums.chunks(2).map(|p| interval(p[0], p[1])).collect()
    }

    fn interval(&self, key: &str) -> I {
        let a = self.v[key].as_array().expect("an interval is an array");
        assert!(
            a.len() == 2 && a.iter().all(|y| y.is_number()),
            "{}",
            self.text
        );
        let nums = self.numbers(key);
        interval(nums[0], nums[1])
    }
}

fn interval(lo: f64, hi: f64) -> I {
    assert!(
        lo.is_finite() && hi.is_finite() && lo <= hi,
        "bad interval [{lo}, {hi}]"
    );
    iv(lo, hi)
}

/// `dalembert CMD --scene S --q0 .. --q1 .. --h .. --json` with f64 inputs printed in
/// shortest round-trip form (read back as the identical f64).
fn pair_cmd(cmd: &str, scene: &str, q0: &[f64], q1: &[f64], h: f64) -> Answer {
    let (a, b, c) = (fmt_vec(q0), fmt_vec(q1), format!("{h:?}"));
    let args = [
        cmd, "--scene", scene, "--q0", &a, "--q1", &b, "--h", &c, "--json",
    ];
    let o = run(&args);
    assert_eq!(o.code, 0, "{args:?}: stderr {}", o.stderr);
    assert!(o.stderr.is_empty(), "{args:?}: stderr {}", o.stderr);
    assert_eq!(o.stdout.lines().count(), 1, "one JSON object on one line");
    Answer::parse(&o.stdout)
}

fn particle_pairs() -> Vec<([f64; 3], [f64; 3], f64)> {
    let m = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
    let q0 = [0.25, -0.75, 1.0];
    let on = mids(
        &dalembert::flow(&m, &q0, &[1.1, 0.6], 0.5, &FlowOptions::default())
            .unwrap()
            .q,
    );
    vec![
        (q0, [on[0], on[1], on[2]], 0.5),
        (q0, [on[0], on[1], on[2] + 0.125], 0.5),
        ([0.0, 0.5, 0.0], [1.0, 0.7, 0.3], 0.1),
        ([0.0, 2.0, -1.0], [0.5, 2.0, 0.5], 1.0),
    ]
}

#[test]
fn retract_json_shape_and_closed_form() {
    for (q0, q1, h) in particle_pairs() {
        let v = pair_cmd("retract", "particle", &q0, &q1, h);
        let c = format!("q0={q0:?} q1={q1:?} h={h:?}");
        let u0 = v.boxes("u0", 2);
        let v0 = v.boxes("v0", 3);
        v.boxes("v1", 3);
        let s = v.boxes("defect", 1);
        let member = v.v["member"].as_str().expect("member is a string");
        assert!(member == "no" || member == "possible", "{member}");
        assert_eq!(
            member == "possible",
            s[0].contains(0.0),
            "member vs defect at {c}"
        );
        let cf = particle_retraction(&q0, &q1, h);
        assert!(
            !s[0].disjoint(cf.s),
            "SOUNDNESS: defect {s:?} vs {:?} at {c}",
            cf.s
        );
        assert!(
            overlap(&u0, &cf.u0),
            "SOUNDNESS: u0 {u0:?} vs {:?} at {c}",
            cf.u0
        );
        let v0c = [cf.u0[0], cf.u0[1], pt(q0[1]) * cf.u0[0]];
        assert!(overlap(&v0, &v0c), "SOUNDNESS: v0 {v0:?} vs {v0c:?} at {c}");
        // v0 = E(Q0)^T u0 lies in D exactly: zd0 = y0 xd0 must be consistent
        assert!(!v0[2].disjoint(pt(q0[1]) * v0[0]));
        if cf.s.mig() > 0.0 {
            assert_eq!(member, "no", "proved off M but member = {member} at {c}");
        }
    }
    // knife: closed form of the retraction
    for (q0, q1, h) in [
        ([0.0, 0.0, 0.0], [0.3, 0.1, 0.2], 0.5),
        ([1.0, -2.0, 0.7], [1.5, -1.5, 0.2], 1.0),
    ] {
        let v = pair_cmd("retract", "knife", &q0, &q1, h);
        let cf = knife_retraction(&q0, &q1, h);
        let u0 = v.boxes("u0", 2);
        let s = v.boxes("defect", 1);
        assert!(
            overlap(&u0, &cf.u0),
            "SOUNDNESS: knife u0 {u0:?} vs {:?}",
            cf.u0
        );
        assert!(
            !s[0].disjoint(cf.s),
            "SOUNDNESS: knife defect {s:?} vs {:?}",
            cf.s
        );
        assert_eq!(v.v["member"], "no");
    }
}

#[test]
fn step_json_shape_and_closed_form() {
    for (q0, q1, h) in particle_pairs() {
        let v = pair_cmd("step", "particle", &q0, &q1, h);
        let c = format!("q0={q0:?} q1={q1:?} h={h:?}");
        let cf = particle_retraction(&q0, &q1, h);
        let sq1b = v.boxes("q1", 3);
        let q2 = v.boxes("q2", 3);
        let pm = v.boxes("p_minus", 2);
        let pp = v.boxes("p_plus", 2);
        assert!(
            overlap(&sq1b, &cf.q1),
            "SOUNDNESS: q1 {sq1b:?} vs {:?} at {c}",
            cf.q1
        );
        let q2c = particle_q(&pts(&q0), &cf.u0, 2.0 * h);
        assert!(overlap(&q2, &q2c), "SOUNDNESS: q2 {q2:?} vs {q2c:?} at {c}");
        assert!(
            overlap(&pm, &cf.p_minus),
            "SOUNDNESS: p- {pm:?} vs {:?} at {c}",
            cf.p_minus
        );
        assert!(
            overlap(&pp, &cf.p_plus),
            "SOUNDNESS: p+ {pp:?} vs {:?} at {c}",
            cf.p_plus
        );
    }
    let (q0, q1, h) = ([0.0, 0.0, 0.0], [0.3, 0.1, 0.2], 0.5);
    let v = pair_cmd("step", "knife", &q0, &q1, h);
    let cf = knife_retraction(&q0, &q1, h);
    let (q2c, _) = knife_q(&pts(&q0), &cf.u0, 2.0 * h);
    assert!(overlap(&v.boxes("q1", 3), &cf.q1));
    assert!(overlap(&v.boxes("q2", 3), &q2c));
    assert!(overlap(&v.boxes("p_minus", 2), &cf.p_minus));
    assert!(overlap(&v.boxes("p_plus", 2), &cf.p_plus));
}

#[test]
fn lagrangian_json_closed_form() {
    for (q0, q1, h) in particle_pairs() {
        let v = pair_cmd("lagrangian", "particle", &q0, &q1, h);
        let l = v.interval("l");
        let s = v.boxes("defect", 1);
        let cf = particle_retraction(&q0, &q1, h);
        assert!(!l.disjoint(cf.l), "SOUNDNESS: l {l:?} vs {:?}", cf.l);
        assert!(!s[0].disjoint(cf.s));
    }
    // straight line y = 0: l = (x1 - x0)^2 / (2h), whatever z1 is (N(Q1) = (0, 0, 1));
    // z1 = 0 would be an exact member, refused by the known Krawczyk bug (exact_discrete.rs)
    let v = pair_cmd(
        "lagrangian",
        "particle",
        &[0.0, 0.0, 0.0],
        &[3.0, 0.0, 0.5],
        2.0,
    );
    assert!(v.interval("l").contains(2.25));
    assert!(v.boxes("defect", 1)[0].contains(-0.5));
}

/// The command line is a thin front: its intervals are the library's, bit for bit, and
/// decimal inputs are read as the nearest f64.
#[test]
fn cli_equals_library() {
    let (a, b, h) = ("0.1,-0.3,0.7", "0.45,0.2,1.1", "0.3");
    let parse = |s: &str| -> Vec<f64> { s.split(',').map(|x| x.parse().unwrap()).collect() };
    let (q0, q1, hf) = (parse(a), parse(b), h.parse::<f64>().unwrap());
    for scene in ["particle", "knife"] {
        let m = Model::new(&AnyScene::new(scene, &[]).unwrap()).unwrap();
        let o = FlowOptions::default();
        let r = exact::retract(&m, &args(&q0), &args(&q1), hf, &o).unwrap();
        let out = run(&[
            "retract", "--scene", scene, "--q0", a, "--q1", b, "--h", h, "--json",
        ]);
        assert_eq!(out.code, 0, "{}", out.stderr);
        let v = Answer::parse(&out.stdout);
        for (key, lib) in [
            ("u0", &r.u0),
            ("v0", &r.v0),
            ("v1", &r.v1),
            ("defect", &r.s),
        ] {
            let cli = v.boxes(key, lib.len());
            for (x, y) in cli.iter().zip(lib.iter()) {
                assert_eq!(
                    (x.inf().to_bits(), x.sup().to_bits()),
                    (y.inf().to_bits(), y.sup().to_bits()),
                    "{scene} {key}: {x:?} vs {y:?}"
                );
            }
        }
        let st = exact::step(&m, &args(&q0), &args(&q1), hf, &o).unwrap();
        let out = run(&[
            "step", "--scene", scene, "--q0", a, "--q1", b, "--h", h, "--json",
        ]);
        let v = Answer::parse(&out.stdout);
        for (key, lib) in [
            ("q1", &st.q1),
            ("q2", &st.q2),
            ("p_minus", &st.p_minus),
            ("p_plus", &st.p_plus),
        ] {
            let cli = v.boxes(key, lib.len());
            for (x, y) in cli.iter().zip(lib.iter()) {
                assert_eq!((x.inf(), x.sup()), (y.inf(), y.sup()), "{scene} {key}");
            }
        }
    }
}

/// `--name value` and `--name=value` are the same, also for values starting with '-'.
#[test]
fn option_syntax_forms() {
    let a = run(&[
        "retract",
        "--scene",
        "particle",
        "--q0",
        "-0.5,0.25,-1",
        "--q1",
        "0.5,-0.25,-1.5",
        "--h",
        "0.5",
        "--json",
    ]);
    let b = run(&[
        "retract",
        "--scene=particle",
        "--q0=-0.5,0.25,-1",
        "--q1=0.5,-0.25,-1.5",
        "--h=0.5",
        "--json",
    ]);
    assert_eq!(a.code, 0, "{}", a.stderr);
    assert_eq!(a.stdout, b.stdout);
    assert_eq!(a.code, b.code);
}

/// knife-eps with eps = 0 poses the knife's exact problem: the answers must overlap.
#[test]
fn knife_eps_zero_is_the_knife() {
    let (q0, q1, h) = ([0.0, 0.0, 0.3], [0.4, 0.2, 0.5], 0.5);
    let k = pair_cmd("step", "knife", &q0, &q1, h);
    let (a, b, c) = (fmt_vec(&q0), fmt_vec(&q1), format!("{h:?}"));
    let o = run(&[
        "step",
        "--scene",
        "knife-eps",
        "--param",
        "eps=0",
        "--q0",
        &a,
        "--q1",
        &b,
        "--h",
        &c,
        "--json",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let e = Answer::parse(&o.stdout);
    for (key, n) in [("q1", 3), ("q2", 3), ("p_minus", 2), ("p_plus", 2)] {
        assert!(overlap(&k.boxes(key, n), &e.boxes(key, n)), "{key}");
    }
}

fn assert_error(args: &[&str], code: i32) {
    let o = run(args);
    assert_eq!(
        o.code, code,
        "{args:?}: stdout {:?} stderr {:?}",
        o.stdout, o.stderr
    );
    assert!(o.stdout.is_empty(), "{args:?}: stdout {:?}", o.stdout);
    let lines: Vec<&str> = o.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: stderr {:?}", o.stderr);
    assert!(lines[0].starts_with("error:"), "{args:?}: {:?}", lines[0]);
}

#[test]
fn invalid_input_exits_2() {
    for cmd in ["retract", "step", "lagrangian"] {
        for h in ["0", "-1", "-0", "nan", "inf", "1e999", "abc", ""] {
            assert_error(
                &[
                    cmd, "--scene", "particle", "--q0", "0,0,0", "--q1", "1,1,1", "--h", h,
                    "--json",
                ],
                2,
            );
        }
        for (q0, q1) in [
            ("0,0", "1,1,1"),
            ("0,0,0", "1,1,1,1"),
            ("0,0,0", "1,,1"),
            ("0,0,nan", "1,1,1"),
        ] {
            assert_error(
                &[
                    cmd, "--scene", "knife", "--q0", q0, "--q1", q1, "--h", "0.5", "--json",
                ],
                2,
            );
        }
        assert_error(
            &[
                cmd, "--scene", "wheel", "--q0", "0,0,0", "--q1", "1,1,1", "--h", "0.5", "--json",
            ],
            2,
        );
        assert_error(
            &[
                cmd, "--scene", "knife", "--param", "mass=2", "--q0", "0,0,0", "--q1", "1,1,1",
                "--h", "0.5", "--json",
            ],
            2,
        );
        assert_error(&[cmd, "--scene", "particle", "--q0", "0,0,0", "--json"], 2);
    }
}

#[test]
fn unprovable_exits_3() {
    // the knife turned by pi in one step (no certified retraction: see exact_discrete.rs)
    for cmd in ["retract", "step", "lagrangian"] {
        assert_error(
            &[
                cmd,
                "--scene",
                "knife",
                "--q0",
                "0,0,0",
                "--q1",
                "1,0,3.141592653589793",
                "--h",
                "1",
                "--json",
            ],
            3,
        );
    }
}

/// Regression: exact members of M_h^{e,nh} whose solution has zero components were once
/// refused with exit 3 (Krawczyk radii of zero components could not grow).
#[test]
fn exact_member_is_answered() {
    for (q0, q1, h) in [
        ([0.0, 2.0, -1.0], [0.5, 2.0, 0.0], 1.0),
        ([0.0, 0.0, 0.0], [3.0, 0.0, 0.0], 2.0),
    ] {
        let v = pair_cmd("retract", "particle", &q0, &q1, h);
        assert_eq!(v.v["member"], "possible");
    }
}
