//! The work limit (spec (5.8''')): the work counter replays the same, a limit at least the
//! work a call needs changes nothing in its answer, and a smaller one is the typed budget
//! refusal, never a partial answer.

use crate::common::model;
use dalembert::protocol::{Query, Session};
use dalembert::Interval;
use dalembert::{exact, flow, work_done, Error, FlowOptions, Reason};
use serde_json::{json, Value};

fn bits(v: &[Interval]) -> Vec<(u64, u64)> {
    v.iter()
        .map(|x| (x.inf().to_bits(), x.sup().to_bits()))
        .collect()
}

fn with_limit(extra: Option<u64>) -> FlowOptions {
    FlowOptions::default().with_work_limit(extra.map(|w| work_done() + w))
}

fn is_work_refusal(e: &Error) -> bool {
    matches!(e, Error::Uncertified(r) if r.reason == Reason::Budget)
        && e.message().contains("not certified within the budget")
        && e.message().contains("work limit")
}

#[test]
fn the_flows_work_replays_and_a_limit_decides_only_whether_it_answers() {
    let m = model("knife", &[]);
    let run = |opts: &FlowOptions| flow(&m, &[0.0; 3], &[0.8, 0.8], 50.0, opts);
    let w0 = work_done();
    let plain = run(&FlowOptions::default()).unwrap();
    let need = work_done() - w0;
    let w1 = work_done();
    run(&FlowOptions::default()).unwrap();
    assert_eq!(work_done() - w1, need, "the same flow, the same work");
    assert!(need > 0);
    // exactly the work it needs: the same enclosure, bit for bit
    let limited = run(&with_limit(Some(need))).unwrap();
    assert_eq!(bits(&limited.q), bits(&plain.q));
    assert_eq!(bits(&limited.u), bits(&plain.u));
    // half of it: refused, with the time reached, and nothing returned
    match run(&with_limit(Some(need / 2))) {
        Err(e @ Error::Uncertified(_)) => {
            assert!(is_work_refusal(&e), "{e}");
            let Error::Uncertified(r) = &e else {
                unreachable!()
            };
            assert!(r.reached.is_some_and(|t| t > 0.0 && t < 50.0), "{r:?}");
        }
        other => panic!("expected the work refusal, got {other:?}"),
    }
    // no work at all
    assert!(is_work_refusal(&run(&with_limit(Some(0))).unwrap_err()));
}

#[test]
fn a_retraction_within_its_work_is_the_same_and_below_it_is_refused() {
    let m = model("knife", &[]);
    let pts = |v: &[f64]| {
        v.iter()
            .map(|x| Interval::try_new(*x, *x).unwrap())
            .collect::<Vec<_>>()
    };
    let (q0, q1, h) = (pts(&[0.0, 0.0, 0.0]), pts(&[0.1, 0.02, 0.1]), 0.125);
    let w0 = work_done();
    let plain = exact::retract(&m, &q0, &q1, h, &FlowOptions::default()).unwrap();
    let need = work_done() - w0;
    let limited = exact::retract(&m, &q0, &q1, h, &with_limit(Some(need))).unwrap();
    assert_eq!(bits(&limited.u0), bits(&plain.u0));
    assert_eq!(bits(&limited.q1), bits(&plain.q1));
    for w in [0, need / 10, need / 2] {
        let e = exact::retract(&m, &q0, &q1, h, &with_limit(Some(w))).unwrap_err();
        assert!(
            is_work_refusal(&e) || e.reason() == Some(Reason::Budget),
            "{e}"
        );
    }
}

#[test]
fn a_sessions_work_is_per_query() {
    let line = json!({"id": 7, "cmd": "step", "scene": "particle",
                      "q0": [0.0, 0.0, 0.0], "q1": [0.1, 0.1, 0.0], "h": 0.1});
    let q = Query::from_json(&line).unwrap();
    let mut free = Session::default();
    let plain = free.answer(&q).unwrap().to_json();
    let w0 = work_done();
    free.answer(&q).unwrap();
    let need = work_done() - w0;
    // every query gets the same allowance: ten in a row all answer as without a limit
    let mut s = Session::default();
    s.work = Some(need);
    for _ in 0..10 {
        assert_eq!(s.answer(&q).unwrap().to_json(), plain);
    }
    // too little: the batch error object, code 3, reason budget
    let mut s = Session::default();
    s.work = Some(need / 4);
    let a: Value = serde_json::from_str(&s.batch_line(&line.to_string()).unwrap()).unwrap();
    assert_eq!(a["id"], 7);
    assert_eq!(a["error"]["code"], 3);
    assert_eq!(a["error"]["reason"], "budget");
}

/// Spec (5.8) (d): in a rest of a span that takes at most three steps the remainder is held
/// to the tolerance without slices (5.5), so a short flow costs a few series per step. On
/// the particle over h = 0.5 (three steps: the pole of its field at y = +-i caps them near
/// 0.22) the flow costs at most 60 000 Taylor terms (5.8''') from every start below, and the
/// exact step (retraction, q(2h), momenta) at most 180 000. Before (d) they cost
/// 75 000-128 000 and 200 000-346 000: two steps near 0.22, each with eight slices.
#[test]
fn a_short_flow_takes_unsliced_steps_within_its_work() {
    let m = model("particle", &[]);
    let opts = FlowOptions::default();
    let point = |v: &[f64]| {
        v.iter()
            .map(|x| Interval::try_new(*x, *x).unwrap())
            .collect::<Vec<_>>()
    };
    let mut over = Vec::new();
    for y0 in [-2.0, -1.0, -0.5, -0.32, 0.0, 0.3, 1.0, 2.0] {
        let w0 = work_done();
        let e = flow(&m, &[0.0, y0, 0.0], &[0.8, 0.8], 0.5, &opts).unwrap();
        let w_flow = work_done() - w0;
        let s = e.stats;
        let w1 = work_done();
        let q0 = point(&[0.0, y0, 0.0]);
        let q1 = point(&[0.4, y0 + 0.4, 0.1]);
        exact::step(&m, &q0, &q1, 0.5, &opts).unwrap();
        let w_step = work_done() - w1;
        if w_flow > 60_000 || w_step > 180_000 || s.steps > 3 {
            over.push(format!(
                "y0 = {y0}: flow {w_flow} terms ({} steps, {} rejected, h {}..{}), step {w_step}",
                s.steps, s.rejected, s.h_min, s.h_max
            ));
        }
    }
    assert!(over.is_empty(), "{}", over.join("\n"));
}
