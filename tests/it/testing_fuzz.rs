//! The Newton-solver fuzz harness (`dalembert::testing::fuzz`, spec eq. (11.7)) on fixed
//! pseudo-random byte strings: the crate's DLA passes it with most steps certified; wrong,
//! non-finite and mis-sized answers claimed converged are caught; failures are not findings.
//! Also the template of `examples/fuzz_newton/` (its solver and its replay test).

use crate::common::model;
use dalembert::schemes::{Scheme, SchemeKind};
use dalembert::testing::fuzz::{
    check_answer, fuzz_solver, fuzz_solver_with, Claimed, FuzzOptions, FuzzOutcome, InputSpace,
    PairKind, SolverAnswer, SolverInput, Tally, Unstructured,
};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use crate::my_solver;

/// `count` byte strings of `len` bytes from a xorshift generator (deterministic).
fn inputs(seed: u64, count: usize, len: usize) -> Vec<Vec<u8>> {
    let mut s = seed;
    (0..count)
        .map(|_| {
            (0..len)
                .map(|_| {
                    s ^= s << 13;
                    s ^= s >> 7;
                    s ^= s << 17;
                    (s >> 24) as u8
                })
                .collect()
        })
        .collect()
}

fn dla_tolerance(i: &SolverInput) -> f64 {
    i.tolerance(1e-9, 2.0, 3)
}

thread_local! {
    static EXPECTING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Run `f`, which is expected to panic with a finding: `Err(message)` if it panicked, with
/// the panic kept off stderr (only on this thread, only here; other panics print as usual).
fn finding<R>(f: impl FnOnce() -> R) -> Result<R, String> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !EXPECTING.with(|e| e.get()) {
                default(info)
            }
        }));
    });
    EXPECTING.with(|e| e.set(true));
    let r = catch_unwind(AssertUnwindSafe(f));
    EXPECTING.with(|e| e.set(false));
    r.map_err(|p| {
        p.downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default()
    })
}

#[test]
fn dla_passes_the_harness_with_most_steps_certified() {
    for (scene, count) in [("particle", 300), ("knife", 60)] {
        let model = model(scene, &[]);
        let dla = Scheme::new(&model, SchemeKind::Dla);
        let mut tally = Tally::default();
        let t = Instant::now();
        for data in inputs(0x9E37_79B9_7F4A_7C15, count, 64) {
            tally.add(&fuzz_solver(&model, &dla, dla_tolerance, &data));
        }
        let per_call = t.elapsed() / count as u32;
        println!("DLA on {scene}: {tally}; {per_call:?} per input");
        assert_eq!(tally.total(), count);
        assert!(
            2 * tally.certified >= count,
            "{scene}: fewer than half certified: {tally}"
        );
    }
}

#[test]
fn decoding_is_total_and_deterministic() {
    let model = model("knife", &[]);
    let opts = FuzzOptions::default();
    let mut kinds = [0usize; 3];
    let mut extreme = 0;
    for i in 0..200 {
        // lengths 0..200: short strings run out of bytes
        let data: Vec<u8> = inputs(i as u64 + 1, 1, i)[0].clone();
        assert!(data.len() == i);
        let a = SolverInput::decode(&model, &opts, &mut Unstructured::new(&data));
        let b = SolverInput::decode(&model, &opts, &mut Unstructured::new(&data));
        assert_eq!(a, b, "the same bytes decode to the same input");
        assert_eq!((a.q0.len(), a.q1.len(), a.u0.len()), (3, 3, 2));
        assert!(a.h > 0.0 && a.h.is_finite());
        assert!(a.q0.iter().chain(&a.q1).chain(&a.u0).all(|x| x.is_finite()));
        kinds[match a.kind {
            PairKind::OnManifold => 0,
            PairKind::Near { .. } => 1,
            PairKind::Euler => 2,
        }] += 1;
        extreme += usize::from(a.h < 0.01 || a.h > 0.5 || a.q0.iter().any(|x| x.abs() > 1.0));
    }
    assert!(
        kinds.iter().all(|&k| k > 0),
        "every kind of pair drawn: {kinds:?}"
    );
    assert!(extreme > 0, "extremes drawn");
    // every byte value in the first position, and no bytes at all
    for b in 0..=255u8 {
        let a = SolverInput::decode(&model, &opts, &mut Unstructured::new(&[b]));
        assert!(a.h > 0.0 && a.q1.iter().all(|x| x.is_finite()));
    }
}

/// Small steps, no extremes: DLA's stated tolerance is then below 1e-4 on every pair built
/// on M_h^{e,nh} or within 2.5e-5 of it, so an error of 1e-3 must be proved there.
fn small_steps() -> FuzzOptions {
    FuzzOptions::default().with_space(
        InputSpace::default()
            .with_h_range(0.001, 0.01)
            .with_extremes(false),
    )
}

#[test]
fn a_wrong_answer_claimed_converged_is_caught() {
    let model = model("particle", &[]);
    let dla = Scheme::new(&model, SchemeKind::Dla);
    // DLA's answer moved by 1e-3 in every component, claimed converged
    let wrong = |q0: &[f64], q1: &[f64], h: f64| {
        dla.step(q0, q1, h, &Default::default())
            .map(|(q2, _, _)| SolverAnswer {
                q2: q2.iter().map(|x| x + 1e-3).collect(),
                converged: true,
            })
    };
    let opts = small_steps();
    let (mut caught, mut passed) = (0, Tally::default());
    for data in inputs(11, 40, 64) {
        let input = SolverInput::decode(&model, &opts, &mut Unstructured::new(&data));
        let tol = dla_tolerance(&input);
        match finding(|| fuzz_solver_with(&model, &wrong, dla_tolerance, &opts, &data)) {
            Err(m) => {
                assert!(
                    m.starts_with("finding: an answer claimed converged is proved farther"),
                    "{m}"
                );
                assert!(tol < 1e-4);
                caught += 1;
            }
            Ok(o) => {
                // only what the harness may not judge: no claim, a claim too loose to be
                // refuted by 1e-3 (a pair put far from M_h^{e,nh}), or no certificate
                assert!(
                    match o {
                        FuzzOutcome::Unchecked | FuzzOutcome::Refused(_) => true,
                        FuzzOutcome::Certified { tol, .. } => tol >= 1e-4,
                        _ => false,
                    },
                    "{o:?} on {input:?}"
                );
                passed.add(&o);
            }
        }
    }
    println!("wrong solver: {caught} of 40 caught; not judged: {passed}");
    assert!(caught >= 20, "caught {caught} of 40");
    // the same inputs with DLA itself: no finding
    for data in inputs(11, 40, 64) {
        fuzz_solver_with(&model, &dla, dla_tolerance, &opts, &data);
    }
}

#[test]
fn non_finite_or_missized_answers_claimed_converged_are_caught() {
    let model = model("particle", &[]);
    let nan = |_: &[f64], _: &[f64], _: f64| {
        Ok::<_, String>(SolverAnswer {
            q2: vec![0.0, f64::NAN, 1.0],
            converged: true,
        })
    };
    let inf = |q0: &[f64], _: &[f64], _: f64| {
        Ok::<_, String>(SolverAnswer {
            q2: q0.iter().map(|_| f64::INFINITY).collect(),
            converged: true,
        })
    };
    let short = |_: &[f64], q1: &[f64], _: f64| {
        Ok::<_, String>(SolverAnswer {
            q2: q1[..2].to_vec(),
            converged: false,
        })
    };
    for data in inputs(5, 20, 48) {
        for (solver, what) in [
            (
                &nan as &dyn Fn(&[f64], &[f64], f64) -> Result<SolverAnswer, String>,
                "not finite",
            ),
            (&inf, "not finite"),
            (&short, "returned 2 components"),
        ] {
            let m = finding(|| fuzz_solver(&model, &solver, dla_tolerance, &data))
                .expect_err("a finding");
            assert!(m.starts_with("finding:") && m.contains(what), "{m}");
        }
    }
}

#[test]
fn failures_and_unconverged_answers_are_not_findings() {
    let model = model("particle", &[]);
    let fails = |_: &[f64], _: &[f64], _: f64| Err::<SolverAnswer, _>("singular Jacobian");
    // a last iterate handed back, not claimed converged: its NaN is not a finding
    let gave_up = |_: &[f64], _: &[f64], _: f64| {
        Ok::<_, std::convert::Infallible>(SolverAnswer {
            q2: vec![f64::NAN; 3],
            converged: false,
        })
    };
    for data in inputs(3, 30, 48) {
        assert_eq!(
            fuzz_solver(&model, &fails, dla_tolerance, &data),
            FuzzOutcome::SolverFailed("\"singular Jacobian\"".into())
        );
        assert_eq!(
            fuzz_solver(&model, &gave_up, dla_tolerance, &data),
            FuzzOutcome::NotConverged
        );
    }
}

#[test]
fn a_stepper_claimed_converged_is_a_solver() {
    let model = model("particle", &[]);
    let dla = Claimed::new(Scheme::new(&model, SchemeKind::Dla));
    let mut tally = Tally::default();
    for data in inputs(29, 20, 64) {
        tally.add(&fuzz_solver(&model, &dla, dla_tolerance, &data));
    }
    assert_eq!(
        tally.not_converged, 0,
        "a stepper's answers are claimed converged"
    );
    assert!(tally.certified > 0, "{tally}");
}

#[test]
fn a_nan_tolerance_is_a_finding_and_an_infinite_one_claims_nothing() {
    let model = model("particle", &[]);
    let dla = Scheme::new(&model, SchemeKind::Dla);
    let input = SolverInput {
        q0: vec![0.0; 3],
        q1: vec![0.04, 0.04, 0.0],
        h: 0.05,
        u0: vec![0.8, 0.8],
        kind: PairKind::Euler,
    };
    let opts = FuzzOptions::default();
    let nan = |_: &SolverInput| f64::NAN;
    let m = finding(|| check_answer(&model, &dla, &nan, &opts, &input)).expect_err("a finding");
    assert!(m.contains("stated tolerance is NaN"), "{m}");
    let o = check_answer(
        &model,
        &dla,
        &|i: &SolverInput| dla_tolerance(i),
        &opts,
        &input,
    );
    assert_eq!(o, FuzzOutcome::Unchecked);
    // with a finite claim the same Euler pair is checked, and DLA is within 1e-3 of it
    let o = check_answer(&model, &dla, &|_: &SolverInput| 1e-3, &opts, &input);
    match o {
        FuzzOutcome::Certified { distance, tol } => {
            assert_eq!(tol, 1e-3);
            assert!(distance.inf() <= 1e-3);
        }
        o => panic!("expected a certified step: {o:?}"),
    }
}

#[test]
fn the_template_fuzz_target_is_the_docs_block_and_uses_the_template_solver() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let target =
        std::fs::read_to_string(root.join("examples/fuzz_newton/fuzz_targets/my_solver.rs"))
            .unwrap();
    let docs = std::fs::read_to_string(root.join("docs/testing.md")).unwrap();
    assert!(
        docs.contains(&format!("```rust\n{target}```")),
        "docs/testing.md's fuzz target differs from examples/fuzz_newton/fuzz_targets/my_solver.rs"
    );
    assert!(target.contains("#[path = \"../my_solver.rs\"]"));
    assert!(target.contains("fuzz_solver(model, solver, tolerance, data)"));
    // the items the target uses, compiled here through the same file
    let (model, solver) = my_solver::setup();
    let mut tally = Tally::default();
    for data in inputs(23, 40, 64) {
        tally.add(&fuzz_solver(&model, &solver, my_solver::tolerance, &data));
    }
    println!("template solver: {tally}");
    assert!(2 * tally.certified >= tally.total(), "{tally}");
}
