//! The strict readers (README, "Input rules"): any accepted input round-trips to the same
//! numbers, and any mutation that drops, adds or retypes an element is refused.

use dalembert::protocol::{self, parse_json, parse_vec, Line, LineReader, Query, Session};
use proptest::prelude::*;
use serde_json::{json, Value};

/// Finite f64 of every kind: ordinary, tiny, huge, subnormal, signed zeros.
fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>().prop_filter("finite", |x| x.is_finite()),
        -10.0f64..10.0,
        Just(-0.0),
        Just(f64::MIN_POSITIVE / 3.0),
        Just(f64::MAX),
    ]
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn step_line(q0: &[f64], q1: &[f64], h: f64) -> Value {
    json!({"id": 1, "cmd": "step", "scene": "particle", "q0": q0, "q1": q1, "h": h})
}

/// The answer's error code, or 0 for an `ok`.
fn code(s: &mut Session, line: &str) -> i64 {
    let a: Value = serde_json::from_str(&s.batch_line(line).unwrap()).unwrap();
    a["error"]["code"].as_i64().unwrap_or(0)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        rng_algorithm: proptest::test_runner::RngAlgorithm::ChaCha,
        ..ProptestConfig::default()
    })]

    #[test]
    fn a_json_query_round_trips_to_the_same_numbers(
        q0 in proptest::collection::vec(finite(), 3),
        q1 in proptest::collection::vec(finite(), 3),
        h in finite(),
    ) {
        let text = step_line(&q0, &q1, h).to_string();
        let q = Query::from_json(&parse_json(&text).unwrap()).unwrap();
        let Query::Step(p) = q else { panic!("not a step") };
        prop_assert_eq!(bits(&p.q0), bits(&q0));
        prop_assert_eq!(bits(&p.q1), bits(&q1));
        prop_assert_eq!(p.h.to_bits(), h.to_bits());
    }

    #[test]
    fn a_command_line_vector_round_trips_to_the_same_numbers(
        v in proptest::collection::vec(finite(), 1..6),
    ) {
        let text: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        let back = parse_vec("--q", &text.join(",")).unwrap();
        prop_assert_eq!(bits(&back), bits(&v));
        // exponent form too
        let text: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
        let back = parse_vec("--q", &text.join(",")).unwrap();
        prop_assert_eq!(bits(&back), bits(&v));
    }

    #[test]
    fn a_vector_with_an_element_dropped_added_or_retyped_is_refused(
        q0 in proptest::collection::vec(-1.0f64..1.0, 3),
        at in 0usize..3,
        how in 0usize..7,
    ) {
        let mut s = Session::default();
        let mut line = step_line(&q0, &[0.1, 0.1, 0.0], 0.1);
        let v = line["q0"].as_array_mut().unwrap();
        match how {
            0 => { v.remove(at); }
            1 => v.insert(at, json!(0.5)),
            2 => v[at] = Value::Null,
            3 => v[at] = json!(q0[at].to_string()),
            4 => v[at] = json!(true),
            5 => v[at] = json!([q0[at]]),
            _ => v[at] = json!({"x": q0[at]}),
        }
        prop_assert_eq!(code(&mut s, &line.to_string()), 2, "{}", line);
        // and on the command line: an empty, a non-numeric or a non-finite element
        let mut cells: Vec<String> = q0.iter().map(|x| format!("{x:?}")).collect();
        cells[at] = ["", "null", "0x1", "inf", "NaN", "1e400", "1,"][how].to_string();
        prop_assert!(parse_vec("--q0", &cells.join(",")).is_err(), "{:?}", cells);
    }

    #[test]
    fn the_line_reader_gives_back_every_line_and_never_holds_a_long_one(
        lines in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..50), 0..8),
        limit in 1usize..40,
    ) {
        let mut data = Vec::new();
        for l in &lines {
            data.extend(l.iter().copied().filter(|b| *b != b'\n'));
            data.push(b'\n');
        }
        let mut r = LineReader::new(&data[..], limit);
        let mut got = Vec::new();
        while let Some(l) = r.next_line().unwrap() {
            got.push(l);
        }
        prop_assert_eq!(got.len(), lines.len());
        for (g, l) in got.iter().zip(&lines) {
            let l: Vec<u8> = l.iter().copied().filter(|b| *b != b'\n').collect();
            match g {
                Line::Text(t) => { prop_assert!(l.len() <= limit); prop_assert_eq!(t, &l); }
                Line::TooLong { bytes } => {
                    prop_assert!(l.len() > limit);
                    prop_assert_eq!(*bytes, l.len() as u64);
                }
            }
        }
    }
}

#[test]
fn a_repeated_key_is_refused_at_any_depth() {
    assert!(parse_json(r#"{"a": 1, "a": 1}"#).is_err());
    assert!(parse_json(r#"{"p": {"eps": 0.1, "eps": 0.5}}"#).is_err());
    assert!(parse_json(r#"[{"x": 1}, {"x": 2}]"#).is_ok());
    assert!(parse_json("1e400").is_err());
    assert!(parse_json("{} x").is_err());
}

#[test]
fn the_keys_of_each_command_are_read_and_a_near_miss_is_named() {
    let base = r#"{"cmd":"flow","scene":"knife-eps","q":[0,0,0],"u":[1,1],"t":0.5"#;
    for (extra, says) in [
        (r#","param":{"eps":0.5}"#, "did you mean `params`?"),
        (r#","T":0.5"#, "unknown key `T`"),
        (r#","q0":[0,0,0]"#, "unknown key `q0`"),
        (r#","deadlin":1"#, "did you mean `deadline`?"),
    ] {
        let e = Query::from_json(&parse_json(&format!("{base}{extra}}}")).unwrap()).unwrap_err();
        assert_eq!(dalembert::protocol::exit_code(&e), 2);
        assert!(e.message().contains(says), "{e}");
    }
    let ok = Query::from_json(
        &parse_json(&format!(
            r#"{base},"params":{{"eps":0.5}},"id":"x","deadline":2,"order":12}}"#
        ))
        .unwrap(),
    )
    .unwrap();
    assert!(matches!(ok, Query::Flow { order: 12, .. }));
    assert_eq!(
        protocol::deadline_from_json(&json!({"deadline": 2.5})).unwrap(),
        Some(2.5)
    );
    for bad in [json!(0), json!(-1), json!("1"), json!(null)] {
        assert!(protocol::deadline_from_json(&json!({ "deadline": bad })).is_err());
    }
}

#[test]
fn a_past_deadline_refuses_and_a_generous_one_changes_nothing() {
    let mut s = Session::default();
    let q = Query::from_json(&step_line(&[0.0, 0.0, 0.0], &[0.1, 0.1, 0.0], 0.1)).unwrap();
    let plain = s.answer(&q).unwrap().to_json();
    assert_eq!(s.answer_within(&q, Some(1e6)).unwrap().to_json(), plain);
    // a budget already spent when the work starts: the typed refusal, exit 3
    let e = s.answer_within(&q, Some(1e-9)).unwrap_err();
    assert_eq!(dalembert::protocol::exit_code(&e), 3);
    assert!(
        e.message().contains("not certified within the budget"),
        "{e}"
    );
}
