//! The public types a Rust user programs against (issue 36): errors that compose and carry a
//! typed kind, a stepper that writes into the caller's buffer, options built with setters,
//! trajectories given as rows of any slice of f64. The kinds asserted here are the parts of
//! each request that are at fault by construction (a key that is wrong, a row that is short).

use dalembert::oracle::{check_trajectory, CheckOptions, Steps};
use dalembert::protocol::{exit_code, Query};
use dalembert::schemes::{NewtonFailure, NewtonOptions, Scheme, SchemeError, SchemeKind};
use dalembert::testing::{check_stepper, Stepper};
use dalembert::{
    flow, flow::flow_at, AnyScene, Error, FlowOptions, InputKind, Limit, Model, Reason,
};

type BoxError = Box<dyn std::error::Error + Send + Sync>;

fn model(name: &str) -> Model {
    Model::new(&AnyScene::new(name, &[]).unwrap()).unwrap()
}

fn query(text: &str) -> Result<Query, Error> {
    Query::from_json(&serde_json::from_str(text).unwrap())
}

/// Every public error type goes through `?` into a boxed `Error + Send + Sync`.
#[test]
fn every_error_type_converts_with_question_mark() {
    fn scheme_error() -> Result<(), BoxError> {
        Err(SchemeError::NonFinite { step: 2 })?
    }
    fn newton_failure() -> Result<(), BoxError> {
        Err(NewtonFailure::Diverged)?
    }
    fn library_error() -> Result<(), BoxError> {
        AnyScene::new("no-such-scene", &[])?;
        Ok(())
    }
    let e = scheme_error().unwrap_err();
    assert_eq!(
        e.to_string(),
        "momentum or energy not finite at step 2 (overflow)"
    );
    assert_eq!(
        newton_failure().unwrap_err().to_string(),
        "divergence (line search found no decrease)"
    );
    let e = library_error().unwrap_err();
    let e = e.downcast_ref::<Error>().expect("a dalembert::Error");
    assert_eq!(
        e.input_kind(),
        Some(&InputKind::Scene("no-such-scene".into()))
    );
    // a scheme's Newton failure is its source
    let nested = SchemeError::Newton {
        step: 3,
        failure: NewtonFailure::SingularJacobian,
    };
    let source = std::error::Error::source(&nested).expect("a source");
    assert_eq!(source.to_string(), "singular Jacobian");
}

/// The batch protocol's refusals name the key, the element, the row and column, or the
/// parameter; the messages are the contract's.
#[test]
fn protocol_errors_carry_the_part_of_the_query() {
    let flow_q = |rest: &str| {
        query(&format!(
            r#"{{"cmd": "flow", "scene": "knife", "u": [0.8, 0.8], {rest}}}"#
        ))
        .unwrap_err()
    };
    let e = flow_q(r#""q": [0, 0, "x"], "t": 1"#);
    assert_eq!(
        e.input_kind(),
        Some(&InputKind::Element {
            key: "q".into(),
            index: 2
        })
    );
    assert_eq!(e.message(), "`q`[2]: expected a number, got a string");
    let e = flow_q(r#""q": [0, 0, 0], "t": 1, "tt": 2"#);
    assert_eq!(e.input_kind(), Some(&InputKind::Key("tt".into())));
    let e = flow_q(r#""q": [0, 0, 0]"#);
    assert_eq!(e.input_kind(), Some(&InputKind::Key("t".into())));
    let e = query(r#"{"cmd": "flow", "scene": "knife", "params": {"eps": "x"}, "q": [0, 0, 0], "u": [0, 0], "t": 1}"#)
        .unwrap_err();
    assert_eq!(e.input_kind(), Some(&InputKind::Parameter("eps".into())));
    let e =
        query(r#"{"cmd": "check", "scene": "particle", "h": 0.5, "q": [[0, 0, 0], [0, 0, null]]}"#)
            .unwrap_err();
    assert_eq!(
        e.input_kind(),
        Some(&InputKind::Row {
            row: 1,
            column: Some(2)
        })
    );
    assert_eq!(exit_code(&e), 2);
}

/// The library's own checks: dimensions, rows of a candidate, the scene's parameters.
#[test]
fn library_input_errors_carry_their_kind() {
    let m = model("knife");
    let o = FlowOptions::default();
    let e = flow(&m, &[0.0; 2], &[0.8, 0.8], 1.0, &o).unwrap_err();
    assert_eq!(
        e.input_kind(),
        Some(&InputKind::Dimension {
            what: "q".into(),
            got: 2,
            expected: 3
        })
    );
    let e = flow(&m, &[0.0; 3], &[0.8, 0.8], f64::NAN, &o).unwrap_err();
    assert_eq!(e.input_kind(), Some(&InputKind::Number("t".into())));
    let e = flow_at(&m, &[0.0; 3], &[0.8, 0.8], &[1.0, 0.5], &o).unwrap_err();
    assert_eq!(e.input_kind(), Some(&InputKind::Times));
    let p = model("particle");
    let rows = [[0.0, 0.0, 0.0], [0.4, 0.4, f64::NAN], [0.76, 0.8, 0.29]];
    let e = check_trajectory(&p, 0.5, &rows, &CheckOptions::default()).unwrap_err();
    assert_eq!(
        e.input_kind(),
        Some(&InputKind::Row {
            row: 1,
            column: Some(2)
        })
    );
    let e = AnyScene::new("knife-eps", &[("eps", f64::INFINITY)]).unwrap_err();
    assert_eq!(e.input_kind(), Some(&InputKind::Parameter("eps".into())));
    assert!(AnyScene::new("knife-eps", &[("eps", 0.2)]).is_ok());
}

/// A flow over more Taylor steps than allowed is refused as that budget, also across the
/// legs of a dense flow, and says so by its `limit`, not only in words.
#[test]
fn the_step_budget_is_a_typed_limit() {
    let m = model("knife");
    let o = FlowOptions::default().with_max_taylor_steps(3);
    for e in [
        flow(&m, &[0.0; 3], &[0.8, 0.8], 600.0, &o).unwrap_err(),
        flow_at(&m, &[0.0; 3], &[0.8, 0.8], &[0.5, 1.0, 2.0, 3.0], &o).unwrap_err(),
    ] {
        assert_eq!(e.reason(), Some(Reason::Budget), "{e}");
        assert_eq!(e.limit(), Some(Limit::TaylorSteps), "{e}");
        assert!(e.message().starts_with("more than 3 steps"), "{e}");
        assert_eq!(exit_code(&e), 3);
    }
    let past = FlowOptions::default().with_deadline(Some(std::time::Instant::now()));
    let e = flow(&m, &[0.0; 3], &[0.8, 0.8], 1.0, &past).unwrap_err();
    assert_eq!(e.limit(), Some(Limit::Deadline));
}

/// The setters give the same answers as the fields they set: a fixed step size and a given
/// order, against the automatic choice, both enclosing the particle's closed form y = 0.8 t.
#[test]
fn options_built_with_setters_answer_as_documented() {
    let m = model("particle");
    let auto = flow(&m, &[0.0; 3], &[0.8, 0.8], 2.0, &FlowOptions::default()).unwrap();
    let fixed = FlowOptions::default().with_order(12).with_fixed_h(0.25);
    let f = flow(&m, &[0.0; 3], &[0.8, 0.8], 2.0, &fixed).unwrap();
    assert_eq!(f.stats.order, 12);
    assert_eq!(f.stats.h_max, 0.25);
    assert!(auto.q[1].contains(1.6) && f.q[1].contains(1.6));
    let o = NewtonOptions::default().with_max_iter(1);
    assert_eq!(o.max_iter, 1);
}

/// A stepper that leaves its buffer unwritten gives NaN, refused as an input error naming
/// the step; one that writes it is checked as before, rows given as arrays.
#[test]
fn a_stepper_writes_into_the_callers_buffer() {
    struct Lazy;
    impl Stepper for Lazy {
        type Error = std::convert::Infallible;
        fn step(&mut self, _: &[f64], _: &[f64], _: f64, _: &mut [f64]) -> Result<(), Self::Error> {
            Ok(())
        }
    }
    let m = model("particle");
    let (q0, q1) = ([0.0; 3], [0.1, 0.1, 0.0]);
    let o = FlowOptions::default();
    let e = check_stepper(&m, &mut Lazy, &q0, &q1, 0.125, 3, &o).unwrap_err();
    assert_eq!(e.input_kind(), Some(&InputKind::Stepper { step: Some(1) }));
    let mut dla = Scheme::new(&m, SchemeKind::Dla);
    let v = check_stepper(&m, &mut dla, &q0, &q1, 0.125, 3, &o).unwrap();
    // the same run checked directly, as rows of slices and at the times k h: the same verdict
    let rows: Vec<&[f64]> = v.q.iter().map(Vec::as_slice).collect();
    let times: Vec<f64> = (0..rows.len()).map(|k| k as f64 * 0.125).collect();
    let w = check_trajectory(&m, Steps::Times(times), &rows, &CheckOptions::default()).unwrap();
    assert_eq!(w.max_distance, v.discrete.max_distance);
}
