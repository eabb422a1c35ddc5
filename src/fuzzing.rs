//! The checks behind the cargo-fuzz targets (`fuzz/fuzz_targets/`), kept in the library so
//! that `cargo test` replays the committed corpus on the stable toolchain
//! (`tests/fuzz_corpus.rs`). Each function decodes arbitrary bytes and panics exactly when
//! the invariant written above it is broken ([spec/08-oracle.md](crate::spec::oracle), "Fuzzing").
//!
//! The `panic!`, `expect` and `assert!` calls in this module are those invariants: a panic is
//! how a fuzz target reports a finding, so each is reachable only through a bug of the crate
//! (an answer that is not JSON, a number changed on the way, an `Error::Internal`). Reading
//! the batch bytes goes through an in-memory slice, whose reads cannot fail. The module is
//! behind the `fuzzing` feature; nothing else in `src/` panics outside its tests.

use crate::enclosure::{flow_set, LohnerSet};
use crate::protocol::{At, BatchAnswer, Line, LineReader, Pair, Query, SceneSpec, Session, Steps};
use crate::scalar::point;
use crate::scene::{Knife, KnifeEps, Particle};
use crate::schemes::{step_residual, NewtonOptions, Scheme, SchemeKind};
use crate::tape::finite;
use crate::{exact, AnyScene, Error, FlowOptions, Model};
use arbitrary::{Arbitrary, Unstructured};
use serde_json::Value;
use std::cell::RefCell;

/// The certified targets' budget: 8 validated steps a flow (the retraction's Newton: 32
/// float steps in all) and [`FUZZ_WORK`] Taylor terms a call, so that a hard input is refused ([`crate::Reason::Budget`]) at the
/// cost of a few ordinary ones. With the simplified tapes
/// ([spec (2.13)](crate::spec::taylor)) the corpus's certified shares are the same as with 16. Steps, not time: a
/// run replays the same on every machine.
/// The certified targets' work limit per call ([spec (5.8''')](crate::spec::enclosure)): 2 million Taylor terms, about
/// 7 ms, above every answered input of the committed corpora (the costliest retraction there
/// does 1.8 million).
const FUZZ_WORK: u64 = 2_000_000;

fn budget() -> FlowOptions {
    FlowOptions {
        max_taylor_steps: 8,
        ..FlowOptions::default()
    }
    .allow_work(FUZZ_WORK)
}

/// What the inputs of a fuzz target came to, for the corpus replay's shares
/// (`tests/fuzz_corpus.rs`): every check function returns its input's tally (a line of
/// `batch_line` or a query of `scenes_step` each count once).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Answered: a certified answer that passed its re-check, or (float scheme targets) a
    /// step whose residual was checked, or (scene files) a scene read and compiled.
    pub answered: usize,
    /// Refused because the budget was spent ([`crate::Reason::Budget`]).
    pub budget: usize,
    /// Refused for a stated reason that is not the budget (a failed proof, an unbounded
    /// enclosure, undefined data, a Newton failure of a float scheme).
    pub refused: usize,
    /// Input refused (exit 2), or bytes that decode to no input.
    pub input: usize,
}

impl Tally {
    fn one(e: &Error) -> Tally {
        match e {
            Error::Input(_) => Tally::input(),
            e if e.is_budget() => Tally {
                budget: 1,
                ..Tally::default()
            },
            _ => Tally {
                refused: 1,
                ..Tally::default()
            },
        }
    }
    fn answered() -> Tally {
        Tally {
            answered: 1,
            ..Tally::default()
        }
    }
    fn input() -> Tally {
        Tally {
            input: 1,
            ..Tally::default()
        }
    }
    /// Add another tally to this one.
    pub fn add(&mut self, o: Tally) {
        self.answered += o.answered;
        self.budget += o.budget;
        self.refused += o.refused;
        self.input += o.input;
    }
    /// The number of inputs counted.
    pub fn total(&self) -> usize {
        self.answered + self.budget + self.refused + self.input
    }
}

impl std::fmt::Display for Tally {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let pc = |x: usize| 100.0 * x as f64 / self.total().max(1) as f64;
        write!(
            f,
            "answered {:.0}%, refused by the budget {:.0}%, refused for a stated reason {:.0}%, input refused {:.0}%",
            pc(self.answered),
            pc(self.budget),
            pc(self.refused),
            pc(self.input)
        )
    }
}

const EPS: [f64; 5] = [0.1, 0.5, -0.3, 0.9, 0.99];

/// The scenes added after the first three targets' corpora were made, fuzzed by
/// [`scenes_step`] (the older targets keep their decoding, so their corpora stay valid).
const NEW_SCENES: [&str; 4] = [
    "rolling-disk",
    "sleigh",
    "contact-oscillator",
    "contact-oscillator-nr",
];
const FIRST_NEW: usize = 2 + EPS.len();

thread_local! {
    static MODELS: RefCell<Vec<Option<(Model, Scheme, Scheme)>>> =
        RefCell::new((0..FIRST_NEW + NEW_SCENES.len()).map(|_| None).collect());
}

fn scene_of(i: usize) -> Result<AnyScene, Error> {
    Ok(match i {
        0 => AnyScene::Particle(Particle),
        1 => AnyScene::Knife(Knife),
        j if j < FIRST_NEW => AnyScene::KnifeEps(KnifeEps { eps: EPS[j - 2] }),
        j => AnyScene::new(NEW_SCENES[j - FIRST_NEW], &[])?,
    })
}

/// `f` on the (cached) model and schemes of scene `i`; `None` when the scene cannot be
/// built (not expected: every registered scene builds with its defaults, as
/// `scene::tests::every_scene_is_consistent_with_its_description` checks).
fn with_model<R>(i: usize, f: impl FnOnce(&Model, &Scheme, &Scheme) -> R) -> Option<R> {
    MODELS.with(|m| {
        let mut m = m.borrow_mut();
        let slot = &mut m[i];
        let (model, dla, mla) = match slot {
            Some(entry) => &*entry,
            None => {
                let model = Model::new(&scene_of(i).ok()?).ok()?;
                let dla = Scheme::new(&model, SchemeKind::Dla);
                let mla = Scheme::new(&model, SchemeKind::Mla);
                &*slot.insert((model, dla, mla))
            }
        };
        Some(f(model, dla, mla))
    })
}

/// An f64 that is usually ordinary and sometimes extreme.
fn num(u: &mut Unstructured) -> arbitrary::Result<f64> {
    Ok(match u.int_in_range(0u8..=7)? {
        0 => f64::arbitrary(u)?,
        1 => u
            .choose(&[
                0.0,
                -0.0,
                1e-300,
                -1e-300,
                1e150,
                -1e150,
                1e308,
                std::f64::consts::FRAC_PI_2,
            ])?
            .to_owned(),
        _ => i16::arbitrary(u)? as f64 / 1024.0,
    })
}

fn vec3(u: &mut Unstructured) -> arbitrary::Result<Vec<f64>> {
    (0..3).map(|_| num(u)).collect()
}

/// A pair `(q0, q1, h)` for the certified targets, mostly where integrators work. A first
/// byte chooses: 10 in 16 near M_h^{e,nh} (q0 in [-4, 4]^n, u0 in [-2, 2]^m, h = 2^-e (1 + f)
/// with e in 2..=12, f in [0, 1): 2.4e-4 <= h < 0.5, and q1 the float flow of (q0, u0) over h, moved along the
/// first constraint normal by 0 or by 2^-k, k in 8..=52); 3 in 16 an Euler pair
/// q1 = q0 + h E(q0)^T u0; 3 in 16 anything at all ([`num`]: extremes included).
fn pair(u: &mut Unstructured, model: &Model) -> arbitrary::Result<(Vec<f64>, Vec<f64>, f64)> {
    let (n, m) = (model.n, model.n - model.k);
    let choice = u.int_in_range(0u8..=15)?;
    if choice >= 13 {
        let v = |u: &mut Unstructured| (0..n).map(|_| num(u)).collect::<arbitrary::Result<_>>();
        return Ok((v(u)?, v(u)?, num(u)?));
    }
    let small = |u: &mut Unstructured, r: f64| -> arbitrary::Result<f64> {
        Ok(f64::from(i16::arbitrary(u)?) / 32768.0 * r)
    };
    let q0: Vec<f64> = (0..n)
        .map(|_| small(u, 4.0))
        .collect::<arbitrary::Result<_>>()?;
    let u0: Vec<f64> = (0..m)
        .map(|_| small(u, 2.0))
        .collect::<arbitrary::Result<_>>()?;
    let e = u.int_in_range(2i32..=12)?;
    let h = 2f64.powi(-e) * (1.0 + small(u, 1.0)?.abs());
    let x0: Vec<f64> = q0.iter().chain(&u0).copied().collect();
    let v0 = model.velocity.eval::<f64>(&x0);
    let euler: Vec<f64> = q0.iter().zip(&v0).map(|(q, v)| q + h * v).collect();
    if choice >= 10 {
        return Ok((q0, euler, h));
    }
    let shift = match u.int_in_range(0i32..=48)? {
        k if k < 8 => 0.0,
        k => 2f64.powi(-k) * if bool::arbitrary(u)? { 1.0 } else { -1.0 },
    };
    let flown = crate::enclosure::float_flow_counted(&model.dynamics, &x0, h, &budget());
    let Some((x, _)) = flown.filter(|(x, _)| x.iter().all(|v| v.is_finite())) else {
        return Ok((q0, euler, h));
    };
    let mut q1 = x[..n].to_vec();
    if shift != 0.0 {
        // a zero normal leaves q1 on the flow
        let _ = crate::testing::shift_off(model, &mut q1, shift);
    }
    Ok((q0, q1, h))
}

/// Invariant: a scheme step or projection on arbitrary scenes, states and steps never
/// panics or hangs, and either fails with a named Newton failure or returns finite numbers
/// that satisfy the discrete equations to a residual consistent with the one reported.
pub fn newton_step(data: &[u8]) -> Tally {
    let mut u = Unstructured::new(data);
    let Ok((scene, mla, qm, qk, h)) = (|| -> arbitrary::Result<_> {
        Ok((
            u.int_in_range(0..=1 + EPS.len())?,
            bool::arbitrary(&mut u)?,
            vec3(&mut u)?,
            vec3(&mut u)?,
            num(&mut u)?.abs(),
        ))
    })() else {
        return Tally::input();
    };
    newton_invariant(scene, mla, &qm, &qk, h)
}

fn newton_invariant(scene: usize, mla: bool, qm: &[f64], qk: &[f64], h: f64) -> Tally {
    with_model(scene, |model, dla, mla_s| {
        let s = if mla { mla_s } else { dla };
        let opts = NewtonOptions::default();
        if let Ok(tr) = s.integrate(qm, qk, h, 2, &opts) {
            assert!(
                tr.q.iter().flatten().all(|x| x.is_finite()),
                "non-finite state"
            );
            assert!(tr.max_residual.is_finite());
        }
        if !(h.is_finite() && h > 0.0) || qm.iter().chain(qk).any(|x| !x.is_finite()) {
            return Tally::input();
        }
        let stepped = s.step(qm, qk, h, &opts);
        // a named Newton failure of the float scheme: refused for a stated reason
        let tally = match &stepped {
            Ok(_) => Tally::answered(),
            Err(_) => Tally {
                refused: 1,
                ..Tally::default()
            },
        };
        if let Ok((next, _, reported)) = stepped {
            assert!(next.iter().all(|x| x.is_finite()), "non-finite step");
            let kind = if mla {
                SchemeKind::Mla
            } else {
                SchemeKind::Dla
            };
            // The exact residual at the returned point, enclosed in intervals through the
            // generic evaluation (not the scheme's simplified tapes, spec (2.13)): its proved
            // lower bound must not exceed what was reported, up to rounding of the report.
            let pts = |v: &[f64]| v.iter().map(|x| point(*x)).collect::<Vec<_>>();
            let r = step_residual::<_, inari::Interval>(
                &*model.scene,
                kind,
                &pts(qm),
                &pts(qk),
                &pts(&next),
                &point(h),
            );
            let proved = r
                .iter()
                .filter(|x| !x.is_empty())
                .fold(0.0f64, |a, x| a.max(x.mig()));
            // the rounding of the residual's terms, as the interval evaluation carries it
            // (near overflow the terms are ~1e307 and one ulp of them is ~1e291)
            let rounding = r
                .iter()
                .filter(|x| !x.is_empty())
                .fold(0.0f64, |a, x| a.max(x.wid()));
            assert!(
                proved
                    <= 4.0 * reported + 4.0 * rounding + 1e-9 * (1.0 + scale(&next, qk, h)),
                "residual at least {proved:e} against reported {reported:e} (rounding {rounding:e})"
            );
        }
        tally
    })
    .unwrap_or_else(Tally::input)
}

fn scale(a: &[f64], b: &[f64], h: f64) -> f64 {
    let m = a.iter().chain(b).fold(0.0f64, |m, x| m.max(x.abs()));
    (m * m / h.min(1.0)).min(1e300)
}

/// Invariant: the certified retraction on arbitrary pairs never panics, and a success
/// passes the oracle's own re-check: finite intervals, and the flow from the `u0` box
/// encloses a `q(h)` that meets the returned `q1` box (two enclosures of one point).
pub fn retraction(data: &[u8]) -> Tally {
    let mut u = Unstructured::new(data);
    let Ok(scene) = u.int_in_range(0..=1 + EPS.len()) else {
        return Tally::input();
    };
    let Some(Ok((q0, q1, h))) = with_model(scene, |model, _, _| pair(&mut u, model)) else {
        return Tally::input();
    };
    retraction_invariant(scene, &q0, &q1, h)
}

fn retraction_invariant(scene: usize, q0: &[f64], q1: &[f64], h: f64) -> Tally {
    with_model(scene, |model, _, _| {
        let pts = |v: &[f64]| v.iter().map(|x| point(*x)).collect::<Vec<_>>();
        let answer = |v: &[f64]| crate::interval::wrap(pts(v));
        match exact::retract(model, &answer(q0), &answer(q1), h, &budget()) {
            Err(Error::Internal(m)) => panic!("internal fault: {m}"),
            Err(e) => Tally::one(&e),
            Ok(r) => {
                let all =
                    r.u0.iter()
                        .chain(&r.s)
                        .chain(&r.v0)
                        .chain(&r.v1)
                        .chain(&r.q1);
                assert!(
                    all.clone().all(|x| finite((*x).into())),
                    "non-finite success"
                );
                let x0: Vec<_> = pts(q0)
                    .into_iter()
                    .chain(r.u0.iter().map(|x| inari::Interval::from(*x)))
                    .collect();
                if let Ok((set, _)) =
                    flow_set(&model.dynamics, LohnerSet::from_box(&x0), h, &budget())
                {
                    let hull = set.hull();
                    for i in 0..model.n {
                        assert!(
                            !hull[i].intersection(r.q1[i].into()).is_empty(),
                            "re-check failed: q(h) enclosures disjoint in component {i}"
                        );
                    }
                }
                Tally::answered()
            }
        }
    })
    .unwrap_or_else(Tally::input)
}

/// One exact step computed two ways (`wide` with more bits than `narrow`): an internal fault
/// panics; when both are answered, `check(k, a, b)` on each pair of components (q1, q2, the
/// momenta, the defect, in that order).
fn both_steps<A: crate::enclosure::Ival, B: crate::enclosure::Ival>(
    wide: Result<exact::ExactStep<A>, Error>,
    narrow: Result<exact::ExactStep<B>, Error>,
    mut check: impl FnMut(usize, &A::Public, &B::Public),
) -> Tally {
    match (wide, narrow) {
        (Err(Error::Internal(m)), _) | (_, Err(Error::Internal(m))) => {
            panic!("internal fault: {m}")
        }
        (Ok(w), Ok(n)) => {
            let w_all = w.q1.iter().chain(&w.q2).chain(&w.p_minus).chain(&w.p_plus);
            let n_all = n.q1.iter().chain(&n.q2).chain(&n.p_minus).chain(&n.p_plus);
            let w_all = w_all.chain(&w.retraction.s);
            let n_all = n_all.chain(&n.retraction.s);
            for (k, (a, b)) in w_all.zip(n_all).enumerate() {
                check(k, a, b);
            }
            Tally::answered()
        }
        (Err(e), _) | (_, Err(e)) => Tally::one(&e),
    }
}

/// Invariant: the exact step at 106 bits and at 53 bits on the same pair (read as
/// [`retraction`] reads it) never panic; when both are answered, every component of the two
/// (q1, q2, the momenta, the defect) meets (both contain the exact value: spec (12.0.2)) and
/// the 106-bit one is no wider than the 53-bit one, up to `2^-100` of the component's size (a
/// point answer at 53 bits may be a tiny interval at 106, whose ends print outward).
pub fn precision_step(data: &[u8]) -> Tally {
    let mut u = Unstructured::new(data);
    let Ok(scene) = u.int_in_range(0..=1 + EPS.len()) else {
        return Tally::input();
    };
    let Some(Ok((q0, q1, h))) = with_model(scene, |model, _, _| pair(&mut u, model)) else {
        return Tally::input();
    };
    with_model(scene, |model, _, _| {
        use crate::precision::dd::DdInterval;
        let pts = |v: &[f64]| crate::interval::wrap(v.iter().map(|x| point(*x)).collect());
        let wide = exact::step_in::<DdInterval>(model, &q0, &q1, h, &budget());
        let narrow = exact::step(model, &pts(&q0), &pts(&q1), h, &budget());
        both_steps(wide, narrow, |k, a, b| {
            let b = DdInterval::from_f64_pair(b.inf(), b.sup()).expect("an interval");
            assert!(!a.disjoint(b), "component {k}: {a} and {b} are disjoint");
            let slack = f64::powi(2.0, -100) * b.mag_up().max(1.0);
            assert!(
                a.wid_up() <= b.wid_up() + slack,
                "component {k}: {a} is wider than {b}"
            );
        })
    })
    .unwrap_or_else(Tally::input)
}

/// Invariant: the exact step at 256 bits ([`WideInterval`](crate::precision::wide::WideInterval))
/// and at 106 bits (double-double) on the same pair (read as [`retraction`] reads it) never
/// panic; when both are answered, every component of the two (q1, q2, the momenta, the
/// defect) meets, each end compared exactly as the decimals both print rounded outward (both
/// contain the exact value: spec (12.0.2)), and the 256-bit one is no wider than the 106-bit
/// one, up to `2^-90` of the component's size.
pub fn precision_wide_step(data: &[u8]) -> Tally {
    let mut u = Unstructured::new(data);
    let Ok(scene) = u.int_in_range(0..=1 + EPS.len()) else {
        return Tally::input();
    };
    let Some(Ok((q0, q1, h))) = with_model(scene, |model, _, _| pair(&mut u, model)) else {
        return Tally::input();
    };
    with_model(scene, |model, _, _| {
        use crate::precision::dd::DdInterval;
        use crate::precision::mp::MpInterval;
        use crate::precision::wide::{self, WideInterval};
        use crate::OutwardDecimal;
        let read = |x: &dyn OutwardDecimal| {
            let d = x.decimal();
            let lo = MpInterval::from_decimal(&d.0, 1024).expect("a decimal");
            let hi = MpInterval::from_decimal(&d.1, 1024).expect("a decimal");
            lo.hull(&hi)
        };
        let wide = wide::with_bits(256, || {
            exact::step_in::<WideInterval>(model, &q0, &q1, h, &budget())
        });
        let narrow = exact::step_in::<DdInterval>(model, &q0, &q1, h, &budget());
        both_steps(wide, narrow, |k, a, b| {
            let (ma, mb) = (read(a), read(b));
            assert!(
                !ma.disjoint(&mb),
                "component {k}: {ma} and {mb} are disjoint"
            );
            let slack = f64::powi(2.0, -90) * b.mag_up().max(1.0);
            assert!(
                a.wid_up() <= b.wid_up() + slack,
                "component {k}: {ma} is wider than {mb}"
            );
        })
    })
    .unwrap_or_else(Tally::input)
}

/// Invariant: on the newer scenes (two constraints, a mass matrix depending on q, a
/// one-form in L), the invariants of [`newton_step`] and, when asked, of [`retraction`].
pub fn scenes_step(data: &[u8]) -> Tally {
    let mut u = Unstructured::new(data);
    let Ok((scene, mla, retract)) = (|| -> arbitrary::Result<_> {
        Ok((
            FIRST_NEW + u.int_in_range(0..=NEW_SCENES.len() - 1)?,
            bool::arbitrary(&mut u)?,
            bool::arbitrary(&mut u)?,
        ))
    })() else {
        return Tally::input();
    };
    let Some(Ok((qm, qk, h))) = with_model(scene, |model, _, _| pair(&mut u, model)) else {
        return Tally::input();
    };
    let mut tally = newton_invariant(scene, mla, &qm, &qk, h.abs());
    if retract {
        tally.add(retraction_invariant(scene, &qm, &qk, h));
    }
    tally
}

/// Invariant: any bytes given to the batch protocol, read as a stream of lines (each kept
/// up to a limit, here 1 KiB so that the long-line path is reached): exactly one answer per
/// line that is not blank, each a JSON object echoing an id with exactly one of `ok` /
/// `error` (code 2 or 3); every interval in an `ok` answer is finite with lo <= hi; and an
/// answered query used exactly the numbers given: every key of the line is one its command
/// reads, and each number the query used is bit for bit the one in the line. Never a panic.
pub fn batch_line(data: &[u8]) -> Tally {
    let mut session = Session::default();
    session.flow = FlowOptions {
        work_limit: None,
        ..budget()
    };
    // the work limit is per query, like the deadline
    session.work = Some(FUZZ_WORK);
    session.max_integrate_steps = 1000;
    let mut reader = LineReader::new(data, 1024);
    let (mut lines, mut answers, mut blank) = (0, 0, 0);
    let mut tally = Tally::default();
    while let Some(line) = reader.next_line().expect("reading bytes cannot fail") {
        lines += 1;
        let is_blank = matches!(&line, Line::Text(b)
            if std::str::from_utf8(b).is_ok_and(|t| t.trim().is_empty()));
        blank += usize::from(is_blank);
        let Some(answer) = session.batch_answer(lines, &line) else {
            assert!(is_blank, "no answer to a line that is not blank");
            continue;
        };
        answers += 1;
        tally.add(check_answer(&line, &answer));
    }
    assert_eq!(
        answers + blank,
        lines,
        "one answer per line that is not blank"
    );
    let expected = if data.is_empty() {
        0
    } else {
        data.split(|b| *b == b'\n').count() - usize::from(data.ends_with(b"\n"))
    };
    assert_eq!(lines, expected, "every line read");
    tally
}

fn check_answer(line: &Line, answer: &BatchAnswer) -> Tally {
    let out = &answer.text;
    assert!(!out.contains('\n'));
    let v: Value = serde_json::from_str(out).expect("answer is JSON");
    assert!(v.get("id").is_some());
    match (v.get("ok"), v.get("error")) {
        (Some(ok), None) => {
            check_numbers(ok, ok.get("newton_iterations").is_none());
            let Line::Text(bytes) = line else {
                panic!("a line too long was answered")
            };
            let given: Value = serde_json::from_slice(bytes).expect("an answered line is JSON");
            assert_eq!(v["id"], given.get("id").cloned().unwrap_or(Value::Null));
            let q = answer
                .answered
                .as_ref()
                .expect("an ok answer names its query");
            used_exactly(&given, q);
            Tally::answered()
        }
        (None, Some(e)) => {
            let code = e["code"].as_i64();
            assert!(code == Some(2) || code == Some(3), "bad code {e}");
            assert!(e["message"].is_string());
            assert!(answer.answered.is_none());
            assert_ne!(e["reason"], "internal", "internal fault: {e}");
            // a refusal has one documented cause (contract E23); code 2 objects none
            if code == Some(3) {
                let cause = e["cause"].as_str().unwrap_or("");
                assert!(
                    crate::Cause::ALL.iter().any(|c| c.name() == cause),
                    "cause `{cause}` not documented: {e}"
                );
            } else {
                assert!(
                    e.get("cause").is_none(),
                    "a code-2 object with a cause: {e}"
                );
            }
            match (code, e["reason"].as_str()) {
                (Some(2), _) => Tally::input(),
                (_, Some("budget")) => Tally {
                    budget: 1,
                    ..Tally::default()
                },
                _ => Tally {
                    refused: 1,
                    ..Tally::default()
                },
            }
        }
        _ => panic!("answer needs exactly one of ok/error: {out}"),
    }
}

/// The query answered is the line, read independently here: the same command, scene,
/// parameters and numbers (bit for bit), and no key in the line that the command ignores.
fn used_exactly(given: &Value, q: &Query) {
    let o = given.as_object().expect("an answered line is an object");
    // a `precision` above 53 wraps the query; at most 53 leaves it as it is (contract E18)
    let asked = o.get("precision").map(|p| p.as_u64().expect("an integer"));
    if !matches!(q, Query::Precise { .. }) {
        assert!(asked.is_none_or(|p| p <= 53));
    }
    let bits = |k: &str| -> u64 { o[k].as_f64().expect("a number").to_bits() };
    let vec_bits = |k: &str, used: &[f64]| {
        let line: Vec<u64> = o[k]
            .as_array()
            .expect("an array")
            .iter()
            .map(|x| x.as_f64().expect("a number").to_bits())
            .collect();
        let used: Vec<u64> = used.iter().map(|x| x.to_bits()).collect();
        assert_eq!(
            line, used,
            "`{k}`: the numbers used are not the numbers given"
        );
    };
    let scene_of = |s: &SceneSpec| {
        match &s.definition {
            None => assert_eq!(o["scene"].as_str(), Some(s.name.as_str())),
            // a scene defined in the line (contract E26): the one read from it
            Some(def) => {
                let read =
                    crate::scene::SceneFile::from_json(&o["scene"]).expect("the line's scene");
                assert_eq!(read.key(), def.key(), "the scene used is not the one given");
            }
        }
        let mut line: Vec<(String, u64)> = o
            .get("params")
            .and_then(Value::as_object)
            .map(|p| {
                p.iter()
                    .map(|(k, x)| (k.clone(), x.as_f64().expect("a number").to_bits()))
                    .collect()
            })
            .unwrap_or_default();
        let mut used: Vec<(String, u64)> = s
            .params
            .iter()
            .map(|(k, x)| (k.clone(), x.to_bits()))
            .collect();
        line.sort();
        used.sort();
        assert_eq!(line, used, "the parameters used are not the ones given");
    };
    let pair = |p: &Pair| {
        scene_of(&p.scene);
        vec_bits("q0", &p.q0);
        vec_bits("q1", &p.q1);
        assert_eq!(bits("h"), p.h.to_bits());
    };
    let (cmd, keys) = match q {
        Query::Flow {
            scene,
            q,
            u,
            t,
            order,
            jacobian,
        } => {
            assert_eq!(
                o.get("jacobian").and_then(Value::as_bool).unwrap_or(false),
                *jacobian
            );
            scene_of(scene);
            vec_bits("q", q);
            vec_bits("u", u);
            match t {
                At::One(t) => assert_eq!(bits("t"), t.to_bits()),
                At::Many(t) => vec_bits("times", t),
            }
            assert_eq!(
                o.get("order").and_then(Value::as_u64).unwrap_or(0),
                *order as u64
            );
            (
                "flow",
                ["q", "u", "t", "times", "order", "jacobian", "precision"].as_slice(),
            )
        }
        Query::Retract(p) => {
            pair(p);
            ("retract", ["q0", "q1", "h", "precision"].as_slice())
        }
        Query::Step(p) => {
            pair(p);
            ("step", ["q0", "q1", "h", "precision"].as_slice())
        }
        Query::Lagrangian(p) => {
            pair(p);
            ("lagrangian", ["q0", "q1", "h", "precision"].as_slice())
        }
        Query::Integrate {
            pair: p,
            scheme,
            steps,
        } => {
            pair(p);
            assert_eq!(o["steps"].as_u64(), Some(*steps as u64));
            let named: SchemeKind = o["scheme"]
                .as_str()
                .expect("a string")
                .parse()
                .expect("a scheme");
            assert_eq!(named, *scheme);
            ("integrate", ["q0", "q1", "h", "scheme", "steps"].as_slice())
        }
        Query::Check {
            scene,
            steps,
            q,
            tol,
            defect_tol,
            pairs,
        } => {
            scene_of(scene);
            match steps {
                Steps::Uniform(h) => assert_eq!(bits("h"), h.to_bits()),
                Steps::Times(t) => vec_bits("t", t),
            }
            assert_eq!(
                o.get("defect_tol").map(|_| bits("defect_tol")),
                defect_tol.map(f64::to_bits)
            );
            let rows = o["q"].as_array().expect("rows");
            assert_eq!(rows.len(), q.len(), "rows dropped or added");
            for (row, given) in q.iter().zip(rows) {
                let given: Vec<u64> = given
                    .as_array()
                    .expect("a row")
                    .iter()
                    .map(|x| x.as_f64().expect("a number").to_bits())
                    .collect();
                let used: Vec<u64> = row.iter().map(|x| x.to_bits()).collect();
                assert_eq!(given, used, "a row of `q` was not used as given");
            }
            assert_eq!(o.get("tol").map(|_| bits("tol")), tol.map(f64::to_bits));
            assert_eq!(
                o.get("pairs").and_then(Value::as_bool).unwrap_or(true),
                *pairs
            );
            (
                "check",
                ["h", "t", "q", "tol", "defect_tol", "pairs", "precision"].as_slice(),
            )
        }
        Query::Order {
            scene,
            scheme,
            q,
            u,
            h,
            rungs,
        } => {
            scene_of(scene);
            vec_bits("q", q);
            vec_bits("u", u);
            if o.get("h").is_some() {
                assert_eq!(bits("h"), h.to_bits());
            }
            if let Some(r) = o.get("rungs") {
                assert_eq!(r.as_u64(), Some(*rungs as u64));
            }
            let named: SchemeKind = o["scheme"]
                .as_str()
                .expect("a string")
                .parse()
                .expect("a scheme");
            assert_eq!(named, *scheme);
            (
                "order",
                ["scheme", "q", "u", "h", "rungs", "precision"].as_slice(),
            )
        }
        Query::Scenes { scene } => {
            if let Some(s) = scene {
                scene_of(s);
            }
            ("scenes", [].as_slice())
        }
        Query::Precise {
            precision, query, ..
        } => {
            assert_eq!(asked, Some(u64::from(*precision)));
            assert!(*precision > 53);
            // the query inside, checked against the line without the key it consumed
            let mut inner = given.clone();
            if let Some(o) = inner.as_object_mut() {
                o.remove("precision");
            }
            return used_exactly(&inner, query);
        }
    };
    assert_eq!(o["cmd"].as_str(), Some(cmd));
    for k in o.keys() {
        assert!(
            [
                "id",
                "cmd",
                "scene",
                "params",
                "deadline",
                "work",
                "max_steps"
            ]
            .contains(&k.as_str())
                || keys.contains(&k.as_str()),
            "key `{k}` of the line was ignored by `{cmd}`"
        );
    }
}

/// Every number finite; with `intervals`, every pair of numbers is an interval lo <= hi
/// (a float trajectory from `integrate` has pairs that are not intervals).
fn check_numbers(v: &Value, intervals: bool) {
    match v {
        Value::Array(a) if intervals && a.len() == 2 && a.iter().all(Value::is_number) => {
            let lo = a[0].as_f64().unwrap_or(f64::NAN);
            let hi = a[1].as_f64().unwrap_or(f64::NAN);
            assert!(
                lo.is_finite() && hi.is_finite() && lo <= hi,
                "bad interval {v}"
            );
        }
        Value::Array(a) => a.iter().for_each(|x| check_numbers(x, intervals)),
        Value::Object(o) => o.values().for_each(|x| check_numbers(x, intervals)),
        Value::Number(n) => assert!(n.as_f64().is_some_and(f64::is_finite)),
        _ => {}
    }
}

/// Invariant: reading a scene never panics or hangs, and every refusal is one input-error
/// line. The first byte chooses the input: arbitrary text read as a TOML scene file
/// (`0`), as an inline JSON scene (`1`), or (`2`) a structured expression, generated from
/// the grammar and a few near misses of it, placed in a small scene. A scene that is read
/// has a stable key and a description of its sizes, and either compiles with
/// [`Model::new`] or is refused with a typed error; an expression that is read parses
/// back from its canonical text (found in the key) to the same scene.
pub fn scene_file(data: &[u8]) -> Tally {
    use crate::scene::{Scene, SceneFile};
    let Some((&mode, rest)) = data.split_first() else {
        return Tally::input();
    };
    let one_line = |e: &Error| {
        assert!(
            matches!(e, Error::Input(_)) && !e.message().contains('\n'),
            "a refusal must be one input-error line: {e:?}"
        );
        Tally::input()
    };
    let accepted = |sf: &SceneFile, compile: bool| {
        let d = sf.description();
        let (n, k) = (sf.dim(), sf.n_constraints());
        assert!(n >= 2 && k >= 1 && k < n, "sizes n = {n}, k = {k}");
        assert_eq!((d.coordinates.len(), d.constraints.len()), (n, k));
        assert_eq!((d.velocities.len(), d.basis.len()), (n - k, n - k));
        assert_eq!(sf.key(), sf.clone().key());
        if !compile {
            return Tally::answered();
        }
        match Model::new(sf) {
            Ok(m) => {
                assert_eq!((m.n, m.k), (n, k));
                let _ = m.check_at(&vec![point(0.25); n]);
                Tally::answered()
            }
            Err(Error::Internal(m)) => panic!("internal fault: {m}"),
            Err(e) => Tally::one(&e),
        }
    };
    match mode % 3 {
        0 => {
            let text = String::from_utf8_lossy(rest);
            match SceneFile::from_toml(&text, "fuzz") {
                Ok(sf) => accepted(&sf, rest.len() < 4096 && sf.dim() <= 8),
                Err(e) => one_line(&e),
            }
        }
        1 => {
            let Ok(v) = serde_json::from_slice::<Value>(rest) else {
                return Tally::input();
            };
            match SceneFile::from_json(&v) {
                Ok(sf) => accepted(&sf, rest.len() < 4096 && sf.dim() <= 8),
                Err(e) => one_line(&e),
            }
        }
        _ => {
            let mut u = Unstructured::new(rest);
            let Ok(slot) = u.int_in_range(0u8..=4) else {
                return Tally::input();
            };
            let mut expr = String::new();
            if fuzz_expr(&mut u, 0, &mut expr).is_err() {
                return Tally::input();
            }
            let scene = |e: &str| {
                let e = Value::String(e.to_string()).to_string();
                let (mut mass, mut pot, mut form, mut mu, mut basis) = (
                    "[[1, 0, 0], [0, \"c\", 0], [0, 0, 1]]".to_string(),
                    "\"x*y\"".to_string(),
                    "[0, 0, 0]".to_string(),
                    "[[\"-y\", 0, 1]]".to_string(),
                    "[[1, 0, \"y\"], [0, 1, 0]]".to_string(),
                );
                match slot {
                    0 => mass = format!("[[1, 0, 0], [0, {e}, 0], [0, 0, 1]]"),
                    1 => pot = e,
                    2 => form = format!("[0, {e}, 0]"),
                    3 => mu = format!("[[\"-y\", {e}, 1]]"),
                    _ => basis = format!("[[1, 0, \"y\"], [0, 1, {e}]]"),
                }
                format!(
                    "coordinates = [\"x\", \"y\", \"z\"]\nmass = {mass}\npotential = {pot}\n\
                     one_form = {form}\nconstraints = {mu}\nbasis = {basis}\n\
                     [parameters]\nc = 2.5\n"
                )
            };
            let sf = match SceneFile::from_toml(&scene(&expr), "fuzz") {
                Ok(sf) => sf,
                Err(e) => return one_line(&e),
            };
            let key: Value = serde_json::from_str(&sf.key()).expect("the key is JSON");
            let canonical = match slot {
                0 => &key["mass"][1][1],
                1 => &key["potential"],
                2 => &key["one_form"][1],
                3 => &key["constraints"][0][1],
                _ => &key["basis"][1][2],
            };
            let canonical = canonical.as_str().expect("a canonical expression");
            let again = SceneFile::from_toml(&scene(canonical), "fuzz")
                .expect("the canonical text of an expression is read");
            assert_eq!(again.key(), sf.key(), "canonical text {canonical}");
            let q = [point(0.3), point(-1.25), point(2.0)];
            let _ = sf.potential(&q);
            let _ = sf.mass(&[0.3, -1.25, 2.0]);
            accepted(&sf, true)
        }
    }
}

/// Past this length `fuzz_expr` writes only leaves. Without it an expression 12 deep could
/// reach thousands of nodes: such inputs took up to 87 ms each (compiling the model's tapes
/// and their derivatives), three quarters of a grown corpus's time, and test nothing that a
/// shorter expression with the same operations does not.
const FUZZ_EXPR_LEN: usize = 120;

/// An expression of the scene-file grammar, with near misses (unknown names, refused
/// functions, stray characters, extreme numbers and exponents), at most 12 deep and about
/// [`FUZZ_EXPR_LEN`] characters long.
fn fuzz_expr(u: &mut Unstructured, depth: usize, out: &mut String) -> arbitrary::Result<()> {
    let leaf = depth >= 12 || out.len() >= FUZZ_EXPR_LEN;
    match u.int_in_range(0u8..=if leaf { 1 } else { 9 })? {
        0 => out.push_str(u.choose(&[
            "0", "1", "2", "0.5", "0.1", "1e308", "1e-320", "3.", ".25", "1e999", "7e", "00",
        ])?),
        1 => out.push_str(u.choose(&["x", "y", "z", "c", "pi", "w", "sin", "_", "x1"])?),
        2 => {
            out.push('-');
            fuzz_expr(u, depth + 1, out)?;
        }
        3..=5 => {
            out.push('(');
            fuzz_expr(u, depth + 1, out)?;
            out.push_str(u.choose(&[" + ", "-", "*", " / ", "^", ",", " "])?);
            fuzz_expr(u, depth + 1, out)?;
            out.push(')');
        }
        6 => {
            fuzz_expr(u, depth + 1, out)?;
            out.push('^');
            out.push_str(u.choose(&["2", "-3", "0.5", "-0.5", "0", "1.5", "1024", "2000", "-1"])?);
        }
        7 | 8 => {
            out.push_str(u.choose(&[
                "sin", "cos", "tan", "exp", "log", "ln", "sqrt", "atan", "sinh", "cosh", "tanh",
                "abs", "min", "atan2", "x",
            ])?);
            out.push('(');
            fuzz_expr(u, depth + 1, out)?;
            out.push(')');
        }
        _ => out.push(char::from(u8::arbitrary(u)?)),
    }
    Ok(())
}
