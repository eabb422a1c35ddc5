//! The command-line contract of `dalembert flow` (exit statuses, option syntax, JSON,
//! numbers), tested on the built binary.

use dalembert::{flow, AnyScene, FlowEnclosure, FlowOptions, Model};
use serde_json::Value;
use std::time::Duration;

use crate::common::{run_binary, Run};

/// No run of the binary in this file may take longer than this (a hang is a failure).
const TIME_LIMIT: Duration = Duration::from_secs(30);

fn run(args: &[&str]) -> Run {
    run_binary(args.iter().map(Into::into).collect(), b"", TIME_LIMIT)
}

/// A successful `flow --json`: exit 0, exactly one JSON object on stdout, with "q" and "v"
/// lists of valid intervals [lo, hi] (finite, lo <= hi).
fn answer(args: &[&str]) -> (Run, Value) {
    let r = run(args);
    assert_eq!(r.code, 0, "dalembert {args:?}: {r:?}");
    let v: Value = serde_json::from_str(&r.stdout)
        .unwrap_or_else(|e| panic!("stdout of {args:?} is not one JSON value ({e}): {r:?}"));
    assert!(
        v.is_object(),
        "stdout of {args:?} is not an object: {}",
        r.stdout
    );
    assert_eq!(
        r.stdout.trim_end().lines().count(),
        1,
        "one JSON object, one line: {}",
        r.stdout
    );
    for key in ["q", "v"] {
        let list = v[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key} missing in {}", r.stdout));
        assert!(!list.is_empty());
        for pair in list {
            let p = pair.as_array().expect("interval is a list");
            assert_eq!(p.len(), 2, "interval {pair} is not [lo, hi]");
            let (lo, hi) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
            assert!(
                lo.is_finite() && hi.is_finite() && lo <= hi,
                "bad interval {pair}"
            );
        }
    }
    (r, v)
}

/// A refusal: the given exit status, nothing on stdout, exactly one line `error: ...` on
/// stderr.
fn refused(args: &[&str], code: i32) -> Run {
    let r = run(args);
    assert_eq!(r.code, code, "dalembert {args:?}: {r:?}");
    assert!(r.stdout.is_empty(), "stdout must be empty: {args:?}: {r:?}");
    assert!(
        r.stderr.starts_with("error:"),
        "stderr must start with `error:`: {args:?}: {r:?}"
    );
    assert_eq!(
        r.stderr.lines().count(),
        1,
        "stderr must be exactly one line: {args:?}: {r:?}"
    );
    r
}

fn flow_args<'a>(
    scene: &'a str,
    params: &[&'a str],
    q: &'a str,
    u: &'a str,
    t: &'a str,
) -> Vec<&'a str> {
    let mut a = vec!["flow", "--scene", scene];
    for p in params {
        a.push("--param");
        a.push(p);
    }
    a.extend(["--q", q, "--u", u, "--t", t, "--json"]);
    a
}

// ---------------------------------------------------------------------------------------
// A minimal JSON reader that keeps numbers as their text, so that they can be read with
// Rust's correctly rounded `str::parse::<f64>` (serde_json's default float parsing is not
// guaranteed to be correctly rounded).

#[derive(Debug, Clone)]
enum J {
    Num(String),
    Str(String),
    Arr(Vec<J>),
    Obj(Vec<(String, J)>),
    Lit,
}

struct Reader<'a> {
    s: &'a [u8],
    i: usize,
}

impl Reader<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn value(&mut self) -> J {
        self.ws();
        match self.s[self.i] {
            b'{' => {
                self.i += 1;
                let mut m = Vec::new();
                self.ws();
                if self.s[self.i] == b'}' {
                    self.i += 1;
                    return J::Obj(m);
                }
                loop {
                    self.ws();
                    let J::Str(k) = self.value() else {
                        panic!("object key is not a string")
                    };
                    self.ws();
                    assert_eq!(self.s[self.i], b':');
                    self.i += 1;
                    m.push((k, self.value()));
                    self.ws();
                    let c = self.s[self.i];
                    self.i += 1;
                    if c == b'}' {
                        return J::Obj(m);
                    }
                    assert_eq!(c, b',');
                }
            }
            b'[' => {
                self.i += 1;
                let mut a = Vec::new();
                self.ws();
                if self.s[self.i] == b']' {
                    self.i += 1;
                    return J::Arr(a);
                }
                loop {
                    a.push(self.value());
                    self.ws();
                    let c = self.s[self.i];
                    self.i += 1;
                    if c == b']' {
                        return J::Arr(a);
                    }
                    assert_eq!(c, b',');
                }
            }
            b'"' => {
                self.i += 1;
                let start = self.i;
                while self.s[self.i] != b'"' {
                    if self.s[self.i] == b'\\' {
                        self.i += 1;
                    }
                    self.i += 1;
                }
                self.i += 1;
                J::Str(String::from_utf8(self.s[start..self.i - 1].to_vec()).unwrap())
            }
            c if c == b'-' || c.is_ascii_digit() => {
                let start = self.i;
                while self.i < self.s.len()
                    && matches!(
                        self.s[self.i],
                        b'0'..=b'9' | b'-' | b'+' | b'.' | b'e' | b'E'
                    )
                {
                    self.i += 1;
                }
                J::Num(String::from_utf8(self.s[start..self.i].to_vec()).unwrap())
            }
            _ => {
                let start = self.i;
                while self.i < self.s.len() && self.s[self.i].is_ascii_alphabetic() {
                    self.i += 1;
                }
                let word = &self.s[start..self.i];
                assert!(
                    matches!(word, b"true" | b"false" | b"null"),
                    "not JSON at byte {start}"
                );
                J::Lit
            }
        }
    }
}

fn read_json(s: &str) -> J {
    let mut r = Reader {
        s: s.as_bytes(),
        i: 0,
    };
    let v = r.value();
    r.ws();
    assert_eq!(r.i, s.len(), "trailing text after the JSON value");
    v
}

fn field<'a>(j: &'a J, key: &str) -> Option<&'a J> {
    match j {
        J::Obj(m) => m.iter().find(|(k, _)| k == key).map(|(_, v)| v),
        _ => None,
    }
}

/// The intervals of `key` as the exact text of their endpoints.
fn interval_texts(j: &J, key: &str) -> Vec<(String, String)> {
    let Some(J::Arr(list)) = field(j, key) else {
        panic!("no list `{key}`")
    };
    list.iter()
        .map(|p| match p {
            J::Arr(ends) if ends.len() == 2 => match (&ends[0], &ends[1]) {
                (J::Num(a), J::Num(b)) => (a.clone(), b.clone()),
                _ => panic!("interval endpoints are not numbers: {p:?}"),
            },
            _ => panic!("not an interval: {p:?}"),
        })
        .collect()
}

/// The significant digits of a decimal literal (no sign, no leading/trailing zeros).
fn significant_digits(s: &str) -> String {
    let mantissa = s.split(['e', 'E']).next().unwrap();
    let digits: String = mantissa.chars().filter(|c| c.is_ascii_digit()).collect();
    let t = digits.trim_start_matches('0').trim_end_matches('0');
    if t.is_empty() {
        "0".to_string()
    } else {
        t.to_string()
    }
}

/// Parse an endpoint exactly and check that its text is a shortest round-trip form.
fn exact_f64(s: &str) -> f64 {
    let x: f64 = s
        .parse()
        .unwrap_or_else(|e| panic!("`{s}` is not a number: {e}"));
    assert!(x.is_finite(), "`{s}` is not finite");
    // Rust's `{:e}` prints the shortest digit string that reads back as x.
    let shortest = significant_digits(&format!("{x:e}"));
    assert_eq!(
        significant_digits(s).len(),
        shortest.len(),
        "`{s}` is not a shortest round-trip form of {x:e}"
    );
    x
}

fn exact_intervals(j: &J, key: &str) -> Vec<(f64, f64)> {
    interval_texts(j, key)
        .iter()
        .map(|(a, b)| (exact_f64(a), exact_f64(b)))
        .collect()
}

fn library(scene: &str, params: &[(&str, f64)], q: &[f64], u: &[f64], t: f64) -> FlowEnclosure {
    let model = Model::new(&AnyScene::new(scene, params).unwrap()).unwrap();
    flow(&model, q, u, t, &FlowOptions::default()).unwrap()
}

fn same_bits(cli: &[(f64, f64)], lib: &[dalembert::Interval], what: &str) {
    assert_eq!(cli.len(), lib.len(), "{what}: dimension");
    for (i, ((lo, hi), x)) in cli.iter().zip(lib).enumerate() {
        assert_eq!(
            (lo.to_bits(), hi.to_bits()),
            (x.inf().to_bits(), x.sup().to_bits()),
            "{what}[{i}]: CLI [{lo:e}, {hi:e}] vs library [{:e}, {:e}]",
            x.inf(),
            x.sup()
        );
    }
}

fn fmt_vec(x: &[f64]) -> String {
    x.iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(",")
}

// ---------------------------------------------------------------------------------------

#[test]
fn json_answer_is_well_formed() {
    for (scene, q, u) in [
        ("knife-eps", "0,0,0", "0.8,0.8"),
        ("knife", "0.3,-1.2,0.9", "1.1,-0.6"),
        ("particle", "0,0,0", "0.8,0.8"),
    ] {
        for t in ["0", "0.5", "3"] {
            let (r, v) = answer(&flow_args(scene, &[], q, u, t));
            assert_eq!(v["q"].as_array().unwrap().len(), 3);
            assert_eq!(v["v"].as_array().unwrap().len(), 3);
            // and the numbers are shortest round-trip forms
            let j = read_json(&r.stdout);
            for key in ["q", "v"] {
                for (lo, hi) in exact_intervals(&j, key) {
                    assert!(lo <= hi);
                }
            }
        }
    }
}

#[test]
fn both_option_syntaxes_agree() {
    let cases: [(&str, &[&str], &str, &str, &str); 4] = [
        ("knife-eps", &["eps=-0.3"], "-1,2,-3", "-0.5,0.9", "1.5"),
        ("knife-eps", &[], "0,0,0", "0.8,0.8", "1"),
        ("knife", &[], "-0.25,-0,1e-3", "-1.5,-2", "0.75"),
        ("particle", &[], "-1,-2,-3", "-0.8,-0.8", "2"),
    ];
    for (scene, params, q, u, t) in cases {
        let spaced = answer(&flow_args(scene, params, q, u, t)).0.stdout;
        let mut eq: Vec<String> = vec!["flow".into(), format!("--scene={scene}")];
        for p in params {
            eq.push(format!("--param={p}"));
        }
        eq.extend([format!("--q={q}"), format!("--u={u}"), format!("--t={t}")]);
        eq.push("--json".into());
        let eq_refs: Vec<&str> = eq.iter().map(|s| s.as_str()).collect();
        let joined = answer(&eq_refs).0.stdout;
        assert_eq!(spaced, joined, "{eq:?}");
        // mixed syntaxes and another order of the options
        let mut mixed: Vec<String> = vec![
            "flow".into(),
            format!("--t={t}"),
            "--json".into(),
            "--u".into(),
            u.into(),
        ];
        for p in params {
            mixed.push("--param".into());
            mixed.push(p.to_string());
        }
        mixed.extend([format!("--q={q}"), "--scene".into(), scene.into()]);
        let mixed_refs: Vec<&str> = mixed.iter().map(|s| s.as_str()).collect();
        assert_eq!(spaced, answer(&mixed_refs).0.stdout, "{mixed:?}");
    }
}

#[test]
fn hyphen_values_are_values_not_options() {
    // `--t -1` must be read as the time -1 (a backward flow, contract E15), exactly as
    // `--t=-1`, not as an unknown option `-1`.
    let (_, a) = answer(&flow_args("knife", &[], "0,0,0", "0.8,0.8", "-1"));
    let (_, b) = answer(&[
        "flow",
        "--scene=knife",
        "--q=0,0,0",
        "--u=0.8,0.8",
        "--t=-1",
        "--json",
    ]);
    assert_eq!(a, b);
    // and `--t -inf` as the time -inf, refused as not finite
    let a = refused(&flow_args("knife", &[], "0,0,0", "0.8,0.8", "-inf"), 2);
    let b = refused(
        &[
            "flow",
            "--scene=knife",
            "--q=0,0,0",
            "--u=0.8,0.8",
            "--t=-inf",
            "--json",
        ],
        2,
    );
    assert_eq!(a.stderr, b.stderr);
    // A negative-looking value gives the same answer in both spellings.
    let (_, v1) = answer(&flow_args("knife", &[], "-0.5,-0.5,-0.5", "-0.5,0.9", "1"));
    let (_, v2) = answer(&[
        "flow",
        "--scene",
        "knife",
        "--q=-0.5,-0.5,-0.5",
        "--u=-0.5,0.9",
        "--t",
        "1",
        "--json",
    ]);
    assert_eq!(v1, v2);
}

#[test]
fn invalid_input_exits_2() {
    let ok_q = "0,0,0";
    let ok_u = "0.8,0.8";
    let mut cases: Vec<Vec<&str>> = vec![
        // unknown scene
        flow_args("nope", &[], ok_q, ok_u, "1"),
        flow_args("Knife", &[], ok_q, ok_u, "1"),
        flow_args("", &[], ok_q, ok_u, "1"),
        // unknown parameter / parameter on a scene without parameters
        flow_args("knife-eps", &["foo=1"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=0.2", "foo=1"], ok_q, ok_u, "1"),
        flow_args("particle", &["eps=0.1"], ok_q, ok_u, "1"),
        flow_args("particle", &["foo=1"], ok_q, ok_u, "1"),
        flow_args("knife", &["eps=0.1"], ok_q, ok_u, "1"),
        // malformed or out-of-range parameters
        flow_args("knife-eps", &["eps"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=nan"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=inf"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=1e999"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=abc"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=1"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=-1"], ok_q, ok_u, "1"),
        flow_args("knife-eps", &["eps=1.5"], ok_q, ok_u, "1"),
        // wrong dimension
        flow_args("knife", &[], "0,0", ok_u, "1"),
        flow_args("knife", &[], "0,0,0,0", ok_u, "1"),
        flow_args("knife", &[], ok_q, "0.8", "1"),
        flow_args("knife", &[], ok_q, "0.8,0.8,0.8", "1"),
        flow_args("particle", &[], "0", ok_u, "1"),
        flow_args("knife-eps", &[], ok_q, "0.8,0.8,0", "1"),
        // non-finite numbers
        flow_args("knife", &[], "0,0,nan", ok_u, "1"),
        flow_args("knife", &[], "0,0,NaN", ok_u, "1"),
        flow_args("knife", &[], "inf,0,0", ok_u, "1"),
        flow_args("knife", &[], "0,-inf,0", ok_u, "1"),
        flow_args("knife", &[], "0,0,infinity", ok_u, "1"),
        flow_args("knife", &[], "1e999,0,0", ok_u, "1"),
        flow_args("knife", &[], ok_q, "-1e999,0", "1"),
        flow_args("knife", &[], ok_q, ok_u, "nan"),
        flow_args("knife", &[], ok_q, ok_u, "inf"),
        flow_args("knife", &[], ok_q, ok_u, "1e999"),
        // negative time not finite (a finite one flows backward, contract E15)
        flow_args("knife", &[], ok_q, ok_u, "-inf"),
        flow_args("knife", &[], ok_q, ok_u, "-1e999"),
        flow_args("knife-eps", &[], ok_q, ok_u, "-nan"),
        // unparsable numbers
        flow_args("knife", &[], ok_q, ok_u, "abc"),
        flow_args("knife", &[], ok_q, ok_u, ""),
        flow_args("knife", &[], ok_q, ok_u, "1..2"),
        flow_args("knife", &[], ok_q, ok_u, "1e"),
        flow_args("knife", &[], ok_q, ok_u, "0x10"),
        flow_args("knife", &[], ok_q, ok_u, "1,5"),
        flow_args("knife", &[], ok_q, ok_u, "1/2"),
        flow_args("knife", &[], "0,,0", ok_u, "1"),
        flow_args("knife", &[], "0,0,0,", ok_u, "1"),
        flow_args("knife", &[], "0;0;0", ok_u, "1"),
        flow_args("knife", &[], ok_q, "0.8,x", "1"),
        flow_args("knife", &[], ok_q, "[0.8,0.8]", "1"),
    ];
    // missing options, unknown options, stray arguments
    cases.push(vec![
        "flow", "--scene", "knife", "--q", ok_q, "--u", ok_u, "--json",
    ]);
    cases.push(vec![
        "flow", "--scene", "knife", "--q", ok_q, "--t", "1", "--json",
    ]);
    cases.push(vec!["flow", "--q", ok_q, "--u", ok_u, "--t", "1", "--json"]);
    cases.push(vec![
        "flow", "--scene", "knife", "--q", ok_q, "--u", ok_u, "--t", "1", "--json", "--bogus",
    ]);
    cases.push(vec![
        "flow", "--scene", "knife", "--q", ok_q, "--u", ok_u, "--t", "1", "--json", "stray",
    ]);
    cases.push(vec!["nosuchcommand"]);
    for args in &cases {
        refused(args, 2);
    }
}

#[test]
fn parameters_change_the_answer() {
    let (q, u, t) = ("0,0,0", "0.8,0.8", "1");
    let default = answer(&flow_args("knife-eps", &[], q, u, t)).1;
    let explicit = answer(&flow_args("knife-eps", &["eps=0.1"], q, u, t)).1;
    assert_eq!(default, explicit, "the default eps is 0.1");
    let other = answer(&flow_args("knife-eps", &["eps=0.2"], q, u, t)).1;
    assert_ne!(default, other, "--param eps=0.2 must change the answer");
    // the change is real: the x enclosures for eps = 0.1 and eps = 0.2 are disjoint
    let x = |v: &Value| {
        let p = v["q"][0].as_array().unwrap();
        (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
    };
    let (a, b) = (x(&default), x(&other));
    assert!(a.1 < b.0 || b.1 < a.0, "{a:?} vs {b:?}");
    // the parameter is the same as the library's
    let j = read_json(
        &answer(&flow_args("knife-eps", &["eps=0.2"], q, u, t))
            .0
            .stdout,
    );
    let lib = library("knife-eps", &[("eps", 0.2)], &[0.0; 3], &[0.8, 0.8], 1.0);
    same_bits(&exact_intervals(&j, "q"), &lib.q, "q");
    // a repeated --param is accepted (the contract says it may repeat)
    answer(&flow_args("knife-eps", &["eps=0.3", "eps=0.2"], q, u, t));
    // eps = 0 on knife-eps answers the knife's question: the enclosures intersect
    let k = answer(&flow_args("knife", &[], q, u, t)).1;
    let k0 = answer(&flow_args("knife-eps", &["eps=0"], q, u, t)).1;
    for key in ["q", "v"] {
        for (a, b) in k[key]
            .as_array()
            .unwrap()
            .iter()
            .zip(k0[key].as_array().unwrap())
        {
            let (a0, a1) = (a[0].as_f64().unwrap(), a[1].as_f64().unwrap());
            let (b0, b1) = (b[0].as_f64().unwrap(), b[1].as_f64().unwrap());
            assert!(a0 <= b1 && b0 <= a1, "{key}: {a} vs {b}");
        }
    }
}

/// scene, parameters, q, u, t
type Case = (
    &'static str,
    &'static [(&'static str, f64)],
    [f64; 3],
    [f64; 2],
    f64,
);

#[test]
fn cli_equals_library_bitwise() {
    let cases: [Case; 6] = [
        ("knife-eps", &[], [0.0, 0.0, 0.0], [0.8, 0.8], 1.0),
        (
            "knife-eps",
            &[("eps", -0.3)],
            [0.3, -1.2, 0.9],
            [1.1, -0.6],
            2.5,
        ),
        (
            "knife-eps",
            &[("eps", 0.9)],
            [-2.0, 0.5, 2.5],
            [-0.7, 1.3],
            0.5,
        ),
        ("knife", &[], [0.1, 0.2, 0.3], [0.4, 0.5], 3.0),
        ("particle", &[], [0.0, 0.0, 0.0], [0.8, 0.8], 7.0),
        ("particle", &[], [1e-3, -2.5, 1e3], [-0.125, 3.0], 0.0),
    ];
    for (scene, params, q, u, t) in cases {
        let ps: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v:?}")).collect();
        let ps_refs: Vec<&str> = ps.iter().map(|s| s.as_str()).collect();
        let (qs, us, ts) = (fmt_vec(&q), fmt_vec(&u), format!("{t:?}"));
        let (r, _) = answer(&flow_args(scene, &ps_refs, &qs, &us, &ts));
        let j = read_json(&r.stdout);
        let lib = library(scene, params, &q, &u, t);
        same_bits(&exact_intervals(&j, "q"), &lib.q, "q");
        same_bits(&exact_intervals(&j, "v"), &lib.v, "v");
        if field(&j, "u").is_some() {
            same_bits(&exact_intervals(&j, "u"), &lib.u, "u");
        }
    }
}

/// Decimal literals are read as the nearest f64: literals with the same nearest f64 give
/// the same answer, and at t = 0 the answer contains exactly that f64 (and not its
/// neighbours, which a wrongly rounding reader would produce).
#[test]
fn numbers_are_read_as_the_nearest_f64() {
    let same = [
        [
            "0.1",
            "0.1000000000000000055511151231257827021181583404541015625",
            "0.10000000000000000001",
        ],
        [
            "1",
            "1.0000000000000000000000001",
            "0.99999999999999999999999",
        ],
        ["0.3", "+0.3", "3e-1"],
        ["-0.5", "-.5", "-5E-1"],
        ["5", "5.", "5.000"],
    ];
    for group in same {
        let outs: Vec<String> = group
            .iter()
            .map(|x| {
                let u = format!("{x},0.8");
                answer(&flow_args("knife-eps", &[], "0,0,0", &u, "1"))
                    .0
                    .stdout
            })
            .collect();
        for (lit, o) in group.iter().zip(&outs) {
            assert_eq!(o, &outs[0], "`{lit}` and `{}` differ", group[0]);
        }
    }
    // literals whose nearest f64 a careless reader gets wrong
    let literals = [
        ("9007199254740993", 9007199254740992.0),
        (
            "2.2250738585072011e-308",
            f64::from_bits(0x000F_FFFF_FFFF_FFFF),
        ),
        ("2.2250738585072012e-308", f64::MIN_POSITIVE),
        ("1e-320", f64::from_bits(2024)),
        ("0.30000000000000004", 0.30000000000000004),
        (
            "1.00000000000000011102230246251565404236316680908203125",
            1.0,
        ),
        (
            "1.00000000000000011102230246251565404236316680908203126",
            1.0000000000000002,
        ),
        ("-0.000001", -1e-6),
        ("123456789012345678901234567890", 1.2345678901234568e29),
    ];
    for (lit, want) in literals {
        let q = format!("{lit},0,0");
        let (r, _) = answer(&flow_args("particle", &[], &q, "0,0", "0"));
        let x = exact_intervals(&read_json(&r.stdout), "q")[0];
        assert!(
            x.0 <= want && want <= x.1,
            "`{lit}` must be read as {want:e}; t = 0 answer is [{:e}, {:e}]",
            x.0,
            x.1
        );
        let (below, above) = (next_down(want), next_up(want));
        assert!(
            !(x.0 <= below && above <= x.1),
            "t = 0 answer for `{lit}` is too wide to tell the neighbours apart: [{:e}, {:e}]",
            x.0,
            x.1
        );
    }
}

fn next_up(x: f64) -> f64 {
    if x == 0.0 {
        f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

#[test]
fn no_arguments_runs_the_demo_and_help_works() {
    let r = run(&[]);
    assert_eq!(r.code, 0, "{r:?}");
    assert!(!r.stdout.trim().is_empty(), "the demo prints something");
    for info in dalembert::scene::SCENES {
        assert!(
            r.stdout.contains(info.name),
            "the demo's tour of the scenes misses {}",
            info.name
        );
    }
    for args in [&["--help"][..], &["-h"], &["flow", "--help"]] {
        let r = run(args);
        assert_eq!(r.code, 0, "{args:?}: {r:?}");
        assert!(
            !r.stdout.trim().is_empty(),
            "{args:?} prints help on stdout"
        );
    }
    let r = run(&["flow", "--help"]);
    for opt in ["--scene", "--param", "--q", "--u", "--t", "--json"] {
        assert!(r.stdout.contains(opt), "flow --help does not mention {opt}");
    }
}

/// Well-formed requests whose answer cannot be proved: exit 3, one `error:` line, nothing
/// on stdout, and promptly (every run is limited to TIME_LIMIT).
#[test]
fn uncertified_exits_3() {
    let cases = [
        // an astronomically long time
        flow_args("knife", &[], "0,0,0", "0.8,0.8", "1e300"),
        flow_args("knife-eps", &[], "0,0,0", "0.8,0.8", "1e300"),
        flow_args("particle", &[], "0,0,0", "0.8,0.8", "1e300"),
        // a state at the edge of the f64 range: x overflows along the flow
        flow_args("knife", &[], "1.7976931348623157e308,0,0", "1e300,0", "1"),
        // the basis of D nearly degenerates (D(phi) = (1 - eps)^2 at phi = 0)
        flow_args(
            "knife-eps",
            &["eps=0.999999999999"],
            "0,0,0",
            "0.8,0.8",
            "5",
        ),
    ];
    for args in &cases {
        let r = refused(args, 3);
        assert!(
            r.stderr.to_lowercase().contains("certif"),
            "{args:?}: {}",
            r.stderr
        );
    }
}
