//! The answers print, compare and serialize (spec (1.5)): answers built by hand with known
//! intervals serialize to the JSON objects of spec/contract.md written out by hand; the
//! printed ends of an interval read back to the same f64 in order; two answers of the same
//! query are `==` and answers of different queries are not.
//!
//! The answers are built by hand through their fields: the crate's own tests build the
//! library with the `internals` feature, under which the answer structs are not
//! `#[non_exhaustive]`.

use crate::common::SplitMix64;
use dalembert::enclosure::LohnerSet;
use dalembert::exact::{ExactStep, ExactTrajectory, Retraction};
use dalembert::oracle::{Tolerances, Verdict};
use dalembert::protocol::Answer;
use dalembert::schemes::Trajectory;
use dalembert::testing::Ladder;
use dalembert::{flow, AnyScene, FlowEnclosure, FlowOptions, FlowStats, Interval, Model};

fn iv(lo: f64, hi: f64) -> Interval {
    Interval::try_new(lo, hi).unwrap()
}

fn stats() -> FlowStats {
    FlowStats {
        order: 22,
        steps: 3,
        rejected: 1,
        h_min: 0.25,
        h_max: 0.5,
    }
}

fn enclosure() -> FlowEnclosure {
    FlowEnclosure {
        q: vec![iv(0.1, 0.30000000000000004), iv(-2.5, -2.0)],
        u: vec![iv(1.0, 1.0)],
        v: vec![iv(-1e-7, 1e300), iv(0.0, 0.5)],
        stats: stats(),
    }
}

/// A retraction of two coordinates and one constraint (its set is not serialized).
fn retraction(defect: Interval) -> Retraction {
    Retraction {
        u0: vec![iv(0.75, 0.8125)],
        s: vec![defect],
        v0: vec![iv(0.75, 0.8125), iv(-0.5, 0.5)],
        v1: vec![iv(1.5, 2.0), iv(3.0, 3.0)],
        q1: vec![iv(-1.0, 1.0), iv(2.0, 2.5)],
        set: LohnerSet::point(&[0.0, 1.0, 2.0]),
    }
}

fn json(a: &Answer) -> String {
    a.to_json().to_string()
}

#[test]
fn a_flow_answer_built_by_hand_prints_the_contracts_object() {
    // contract command 1 with the stats (E8): the keys in serde_json's (sorted) order, a
    // zero lower end as -0.0 (inari's inf, IEEE 1788), f64 always with a point or exponent
    // (serde_json's shortest form: `1e+300`, `1e-7`)
    let a = Answer::Flow {
        enclosure: enclosure(),
        jacobian: None,
    };
    assert_eq!(
        json(&a),
        r#"{"q":[[0.1,0.30000000000000004],[-2.5,-2.0]],"stats":{"h_max":0.5,"h_min":0.25,"order":22,"rejected":1,"steps":3},"u":[[1.0,1.0]],"v":[[-1e-7,1e+300],[-0.0,0.5]]}"#
    );
    let a = Answer::Flow {
        enclosure: enclosure(),
        jacobian: Some(vec![vec![iv(1.0, 1.0), iv(-0.125, 0.125)]]),
    };
    assert!(json(&a).starts_with(r#"{"jacobian":[[[1.0,1.0],[-0.125,0.125]]],"q":"#));
    // dense output: the stops without their stats, the stats of the last stop
    let mut late = enclosure();
    late.stats.steps = 5;
    let a = Answer::FlowAt {
        times: vec![0.5, 1.0],
        enclosures: vec![enclosure(), late],
    };
    assert_eq!(
        json(&a),
        r#"{"at":[{"q":[[0.1,0.30000000000000004],[-2.5,-2.0]],"t":0.5,"u":[[1.0,1.0]],"v":[[-1e-7,1e+300],[-0.0,0.5]]},{"q":[[0.1,0.30000000000000004],[-2.5,-2.0]],"t":1.0,"u":[[1.0,1.0]],"v":[[-1e-7,1e+300],[-0.0,0.5]]}],"stats":{"h_max":0.5,"h_min":0.25,"order":22,"rejected":1,"steps":5}}"#
    );
    let a = Answer::FlowAt {
        times: vec![],
        enclosures: vec![],
    };
    assert_eq!(json(&a), r#"{"at":[],"stats":null}"#);
}

#[test]
fn the_pair_answers_built_by_hand_print_the_contracts_objects() {
    // contract command 2: `s` is `defect`, `member` is computed from it, no set
    let off = retraction(iv(0.0625, 0.125));
    assert_eq!(
        json(&Answer::Retract(off.clone())),
        r#"{"defect":[[0.0625,0.125]],"member":"no","q1":[[-1.0,1.0],[2.0,2.5]],"u0":[[0.75,0.8125]],"v0":[[0.75,0.8125],[-0.5,0.5]],"v1":[[1.5,2.0],[3.0,3.0]]}"#
    );
    let on = retraction(iv(-1e-300, 5e-324));
    assert!(json(&Answer::Retract(on.clone()))
        .starts_with(r#"{"defect":[[-1e-300,5e-324]],"member":"possible","#));
    // contract command 3: the step without its retraction
    let step = ExactStep {
        retraction: on.clone(),
        q1: vec![iv(-1.0, 1.0)],
        q2: vec![iv(4.0, 4.5)],
        p_minus: vec![iv(0.75, 0.75)],
        p_plus: vec![iv(-3.0, -2.0)],
    };
    assert_eq!(
        json(&Answer::Step(step)),
        r#"{"p_minus":[[0.75,0.75]],"p_plus":[[-3.0,-2.0]],"q1":[[-1.0,1.0]],"q2":[[4.0,4.5]]}"#
    );
    // the lagrangian extension: the action and the retraction's defect
    let a = Answer::Lagrangian {
        l: iv(0.3125, 0.375),
        retraction: off,
    };
    assert_eq!(
        json(&a),
        r#"{"defect":[[0.0625,0.125]],"l":[0.3125,0.375]}"#
    );
}

#[test]
fn a_check_and_an_integrate_answer_built_by_hand_print_the_contracts_objects() {
    let exact = ExactTrajectory {
        retraction: retraction(iv(0.0, 0.0)),
        q: vec![],
        v: vec![],
        p: vec![],
    };
    let mut verdict = Verdict {
        distance: vec![iv(0.0, 0.0), iv(0.5, 0.75)],
        max_distance: iv(0.0, 0.75),
        defect: vec![vec![iv(-0.25, 0.25)]],
        max_defect: Some(iv(0.0, 0.25)),
        energy_error: vec![iv(-1.0, 2.0)],
        exact,
    };
    let check = |v: &Verdict, passed| Answer::Check {
        verdict: v.clone(),
        tolerances: Tolerances::default(),
        passed,
    };
    // the batch `check` answer with pair figures (contract E13)
    assert_eq!(
        json(&check(&verdict, true)),
        r#"{"defect":[[[-0.25,0.25]]],"distance":[[-0.0,0.0],[0.5,0.75]],"energy_error":[[-1.0,2.0]],"max_defect":[-0.0,0.25],"max_distance":[-0.0,0.75],"passed":true}"#
    );
    // without pair figures there is no `max_defect` key (not a null)
    verdict.defect.clear();
    verdict.energy_error.clear();
    verdict.max_defect = None;
    assert_eq!(
        json(&check(&verdict, false)),
        r#"{"defect":[],"distance":[[-0.0,0.0],[0.5,0.75]],"energy_error":[],"max_distance":[-0.0,0.75],"passed":false}"#
    );
    // contract command 4: `iterations` is `newton_iterations`, counts without a point
    let t = Trajectory {
        q: vec![vec![0.0, 1.0], vec![0.5, 1.0]],
        p: vec![vec![2.0]],
        energy: vec![0.125],
        iterations: vec![3],
        max_residual: 1e-17,
    };
    let text = r#"{"energy":[0.125],"max_residual":1e-17,"newton_iterations":[3],"p":[[2.0]],"q":[[0.0,1.0],[0.5,1.0]]}"#;
    assert_eq!(json(&Answer::Integrate(t.clone())), text);
    // the library's own serde form has the same keys (in field order) and reads back
    let own = serde_json::to_string(&t).unwrap();
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(&own).unwrap(),
        serde_json::from_str::<serde_json::Value>(text).unwrap()
    );
    assert_eq!(serde_json::from_str::<Trajectory>(&own).unwrap(), t);
}

#[test]
fn the_library_serde_form_is_the_protocols_and_reads_back() {
    // a FlowEnclosure serializes as the flow answer's object (field order: q, u, v, stats)
    let e = enclosure();
    let own = serde_json::to_string(&e).unwrap();
    assert_eq!(
        own,
        r#"{"q":[[0.1,0.30000000000000004],[-2.5,-2.0]],"u":[[1.0,1.0]],"v":[[-1e-7,1e+300],[-0.0,0.5]],"stats":{"order":22,"steps":3,"rejected":1,"h_min":0.25,"h_max":0.5}}"#
    );
    assert_eq!(serde_json::from_str::<FlowEnclosure>(&own).unwrap(), e);
    // an infinite end is null in JSON and reads back in its place
    let half = iv(f64::NEG_INFINITY, 2.0);
    assert_eq!(serde_json::to_string(&half).unwrap(), "[null,2.0]");
    assert_eq!(
        serde_json::from_str::<Interval>("[null,2.0]").unwrap(),
        half
    );
    assert_eq!(
        serde_json::from_str::<Interval>("[null,null]").unwrap(),
        Interval::ENTIRE
    );
    // a pair that is no interval is refused, not turned into one
    assert!(serde_json::from_str::<Interval>("[2.0,1.0]").is_err());
    assert!(serde_json::from_str::<Interval>("[1.0]").is_err());
    // the testing kit's ladder, with an order where none is proved
    let l = Ladder {
        h: vec![0.25, 0.125],
        error: vec![iv(1e-3, 2e-3), iv(1e-4, 3e-4)],
        orders: vec![Interval::ENTIRE],
    };
    let own = serde_json::to_string(&l).unwrap();
    assert_eq!(
        own,
        r#"{"h":[0.25,0.125],"error":[[0.001,0.002],[0.0001,0.0003]],"orders":[[null,null]]}"#
    );
    assert_eq!(serde_json::from_str::<Ladder>(&own).unwrap(), l);
}

/// `[lo, hi]` as printed, split into its two ends.
fn ends(text: &str) -> (f64, f64) {
    let inner = text
        .strip_prefix('[')
        .and_then(|t| t.strip_suffix(']'))
        .unwrap_or_else(|| panic!("not [lo, hi]: {text}"));
    let (lo, hi) = inner.split_once(", ").unwrap();
    (lo.parse().unwrap(), hi.parse().unwrap())
}

#[test]
fn printed_ends_read_back_to_the_same_f64_in_order() {
    // by hand: the issue's defect below 0, which inari's own Debug printed lower end negated
    let d = iv(-1.00000000001e-6, -0.99999999999e-6);
    assert_eq!(format!("{d:?}"), "[-1.00000000001e-6, -9.9999999999e-7]");
    assert_eq!(format!("{d}"), format!("{d:?}"));
    assert_eq!(format!("{:?}", Interval::EMPTY), "[empty]");
    assert_eq!(format!("{:?}", iv(0.0, 0.0)), "[-0.0, 0.0]");
    // random doubles of every magnitude and sign (fixed seed), as pairs in order
    let mut rng = SplitMix64(0x5eed_0036);
    for _ in 0..20_000 {
        let a = f64::from_bits(rng.next_u64());
        let b = f64::from_bits(rng.next_u64());
        if !a.is_finite() || !b.is_finite() {
            continue;
        }
        let x = iv(a.min(b), a.max(b));
        for text in [format!("{x:?}"), format!("{x}")] {
            let (lo, hi) = ends(&text);
            assert!(lo <= hi, "{text}");
            assert_eq!(
                (lo.to_bits(), hi.to_bits()),
                (x.inf().to_bits(), x.sup().to_bits()),
                "{text}"
            );
        }
    }
    // a flow's answer: every interval as `[lo, hi]`, nothing of inari's representation
    let model = Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap();
    let e = flow(&model, &[0.0; 3], &[0.8, 0.8], 2.0, &FlowOptions::default()).unwrap();
    let text = format!("{e:?}");
    assert!(!text.contains("m128") && !text.contains("rep"), "{text}");
    for x in e.q.iter().chain(&e.u).chain(&e.v) {
        let (lo, hi) = ends(&format!("{x:?}"));
        assert!(lo <= hi && lo == x.inf() && hi == x.sup());
        assert!(text.contains(&format!("{x:?}")));
    }
}

#[test]
fn answers_of_the_same_query_are_equal_and_of_different_ones_not() {
    let model = Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap();
    let opts = FlowOptions::default();
    let at = |t: f64| flow(&model, &[0.0, 0.0, 0.3], &[0.8, 0.5], t, &opts).unwrap();
    let (a, b, c) = (at(1.0), at(1.0), at(1.5));
    assert_eq!(a, b);
    assert_ne!(a, c);
    // one interval changed is enough to tell them apart
    let mut d = a.clone();
    d.q[2] = d.q[2].convex_hull(Interval::point(d.q[2].sup() + 1.0));
    assert_ne!(a, d);
    // and the stats count
    let mut s = a.clone();
    s.stats.rejected += 1;
    assert_ne!(a, s);
}
