//! Fuzzing a user's Newton solver against the oracle (feature `fuzzing`; [spec eq. (11.7)](crate::spec::testing)).
//!
//! A user's solver computes one step `q2` of a two-step integrator from `(q0, q1, h)` and says
//! whether its Newton iteration converged. [`fuzz_solver`] decodes arbitrary bytes into such
//! an input for a [`Model`] ([`SolverInput::decode`]: configurations in a box, steps in a
//! range, pairs on and near `M_h^{e,nh}`, and extremes), calls the solver, and panics (the
//! way a cargo-fuzz target reports a finding) exactly when
//!
//! * an `Ok` answer does not have `n` components, or
//! * an answer claimed converged holds a NaN or an infinity, or
//! * an answer claimed converged is **proved** farther than the stated tolerance from the
//!   exact discrete step `q^e_2 = q(2h)` of the pair: the oracle certified the step (with a
//!   small budget) and the lower end of the enclosure of `|q2 - q^e_2|_inf` exceeds the
//!   tolerance.
//!
//! (A stated tolerance that is NaN or negative panics too, as a fault of the fuzz target, and
//! so does an internal fault of the oracle, saying that it is a bug of dalembert.)
//! A failure of the solver (`Err`), an answer not claimed converged, and a step the oracle
//! cannot certify within its budget are outcomes ([`FuzzOutcome`]), never findings. A panic
//! of the solver itself propagates unchanged: libFuzzer records it with its input. A hung
//! solver is caught by libFuzzer's `-timeout`; the harness's own work is bounded
//! ([`FuzzOptions`]: a step count for every certified flow, a deadline for the oracle's).
//!
//! ```
//! use dalembert::schemes::{Scheme, SchemeKind};
//! use dalembert::testing::fuzz::{fuzz_solver, FuzzOutcome, SolverAnswer, SolverInput};
//! use dalembert::{AnyScene, Model};
//! let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
//! let dla = Scheme::new(&model, SchemeKind::Dla);
//! // the user's solver: a closure (q0, q1, h) -> Result<SolverAnswer, E>
//! let solver = |q0: &[f64], q1: &[f64], h: f64| {
//!     dla.step(q0, q1, h, &Default::default())
//!         .map(|(q2, _, _)| SolverAnswer { q2, converged: true })
//! };
//! // the accuracy it claims against the exact discrete flow: DLA's local error is O(h^3)
//! let tol = |i: &SolverInput| i.tolerance(1e-9, 2.0, 3);
//! let outcome = fuzz_solver(&model, &solver, tol, b"any bytes at all"); // panics on a finding
//! if let FuzzOutcome::Certified { distance, tol } = outcome {
//!     assert!(distance.inf() <= tol); // not proved outside the tolerance
//! }
//! ```

use super::{pair_point, Stepper};
use crate::oracle::check_step;
use crate::schemes::{NewtonFailure, NewtonOptions, Scheme};
use crate::Interval;
use crate::{Error, FlowOptions, Model};
pub use arbitrary::Unstructured;
use std::fmt;
use std::path::Path;
use std::time::{Duration, Instant};

/// What a solver returns: the next configuration and whether its iteration converged.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverAnswer {
    /// The solver's next configuration (n numbers are expected).
    pub q2: Vec<f64>,
    /// `true` claims that `q2` is within the stated tolerance of the exact discrete step;
    /// `false` hands back a last iterate and claims nothing about it.
    pub converged: bool,
}

/// A user's Newton solver for one step of a two-step integrator.
///
/// Implemented for every closure `Fn(&[f64], &[f64], f64) -> Result<SolverAnswer, E>`, for
/// the crate's DLA/MLA schemes ([`Scheme`], converged whenever Newton succeeds) and, through
/// [`Claimed`], for every [`Stepper`]. [`Stepper`] itself is not enough here: it has no way
/// to say "not converged", which is what a Newton solver's caller relies on.
pub trait NewtonSolver {
    /// The solver's own failure: any type that prints (`String`, an error type), the same
    /// bound as [`Stepper::Error`]; its `Debug` text is kept in the outcome.
    type Error: std::fmt::Display + std::fmt::Debug;
    /// `q2` from the pair `(q0, q1)` and the step `h`, with the claim `converged`; or the
    /// solver's own failure.
    fn solve(&self, q0: &[f64], q1: &[f64], h: f64) -> Result<SolverAnswer, Self::Error>;
}

impl<F, E> NewtonSolver for F
where
    F: Fn(&[f64], &[f64], f64) -> Result<SolverAnswer, E>,
    E: std::fmt::Display + std::fmt::Debug,
{
    type Error = E;
    fn solve(&self, q0: &[f64], q1: &[f64], h: f64) -> Result<SolverAnswer, E> {
        self(q0, q1, h)
    }
}

/// DLA or MLA with Newton's default options: an answer is claimed converged exactly when
/// Newton reports convergence; its named failures are the solver's failures.
impl NewtonSolver for Scheme {
    type Error = NewtonFailure;
    fn solve(&self, q0: &[f64], q1: &[f64], h: f64) -> Result<SolverAnswer, NewtonFailure> {
        self.step(q0, q1, h, &NewtonOptions::default())
            .map(|(q2, _, _)| SolverAnswer {
                q2,
                converged: true,
            })
    }
}

/// A [`Stepper`] as a solver: every `Ok` answer is claimed converged. The stepper takes
/// `&mut self` and a solver `&self`: it is held in a `RefCell`.
#[derive(Debug)]
pub struct Claimed<S>(std::cell::RefCell<S>);

impl<S> Claimed<S> {
    /// `stepper` as a solver.
    pub fn new(stepper: S) -> Self {
        Claimed(std::cell::RefCell::new(stepper))
    }
    /// The stepper back.
    pub fn into_inner(self) -> S {
        self.0.into_inner()
    }
}

impl<S: Stepper> NewtonSolver for Claimed<S> {
    type Error = S::Error;
    fn solve(&self, q0: &[f64], q1: &[f64], h: f64) -> Result<SolverAnswer, S::Error> {
        let mut q2 = vec![f64::NAN; q1.len()];
        self.0.borrow_mut().step(q0, q1, h, &mut q2)?;
        Ok(SolverAnswer {
            q2,
            converged: true,
        })
    }
}

/// How the pair `(q0, q1)` of an input was made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PairKind {
    /// `q1 = mid(flow(q0, u0, h).q)`: on `M_h^{e,nh}` up to the certified flow's width and
    /// rounding (the pair builder of [spec eq. (11.6)](crate::spec::testing)).
    OnManifold,
    /// An on-manifold `q1` moved by `distance` along the unit first constraint normal.
    Near {
        /// The signed distance moved.
        distance: f64,
    },
    /// `q1 = q0 + h E(q0)^T u0` ([spec eq. (9.5)](crate::spec::report)), off `M_h^{e,nh}` by `O(h^2 |u0|^2)`:
    /// where the certified flow refused, or chosen as such.
    Euler,
}

/// One decoded input: the pair, the step, and how they were made.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverInput {
    /// The first configuration (n finite numbers).
    pub q0: Vec<f64>,
    /// The second configuration, made as `kind` says (n finite numbers).
    pub q1: Vec<f64>,
    /// The step, finite and `> 0`.
    pub h: f64,
    /// The quasi-velocities the pair was made from.
    pub u0: Vec<f64>,
    /// How `q1` was made.
    pub kind: PairKind,
}

impl SolverInput {
    /// The length scale of one step, `h + |q1 - q0|_inf`: a scheme of order p has a local
    /// error of order `scale^(p+1)` (times the scene's curvature and forces).
    pub fn scale(&self) -> f64 {
        self.h + max_abs(self.q1.iter().zip(&self.q0).map(|(a, b)| a - b))
    }

    /// `max(1, |q0|_inf, |q1|_inf)`, for a tolerance relative to the configurations.
    pub fn magnitude(&self) -> f64 {
        max_abs(self.q0.iter().chain(&self.q1).copied()).max(1.0)
    }

    /// A tolerance of the usual form for a scheme of order `order` started on or near
    /// `M_h^{e,nh}`:
    /// `rel * magnitude + local * scale^(order + 1) + 4 |distance|` on [`PairKind::OnManifold`]
    /// and [`PairKind::Near`] pairs; infinite (no claim, not checked) on [`PairKind::Euler`]
    /// pairs, whose distance to `M_h^{e,nh}` is not known in advance.
    pub fn tolerance(&self, rel: f64, local: f64, order: i32) -> f64 {
        let off = match self.kind {
            PairKind::OnManifold => 0.0,
            PairKind::Near { distance } => 4.0 * distance.abs(),
            PairKind::Euler => return f64::INFINITY,
        };
        rel * self.magnitude() + local * self.scale().powi(order + 1) + off
    }

    /// Decode an input for `model` from arbitrary bytes. Total: any bytes (none included)
    /// give an input, with finite numbers, `n` components and `h > 0`; never panics.
    ///
    /// Ordinary inputs (about half): `q0` uniform in `[-q_bound, q_bound]^n`, `u0` in
    /// `[-u_bound, u_bound]^(n-k)`, `h` in `[h_min, h_max]`, `q1` from the certified flow.
    /// The rest: pairs near `M_h^{e,nh}` (distances `1e-12` to `0.05`, both sides), Euler
    /// pairs, and with `extremes` also tiny and large steps (`1e-8` to `2`), configurations
    /// up to `1e6 q_bound` and quasi-velocities up to `100 u_bound`.
    pub fn decode(model: &Model, opts: &FuzzOptions, u: &mut Unstructured) -> SolverInput {
        let space = &opts.space;
        let (n, m) = (model.n, model.n - model.k);
        let unit = |u: &mut Unstructured| -> f64 {
            // uniform in [-1, 1] from 32 bits (0 when the bytes have run out)
            let x = u.arbitrary::<u32>().unwrap_or(1 << 31);
            (x as f64 / u32::MAX as f64) * 2.0 - 1.0
        };
        let choice = u.int_in_range(0u8..=15).unwrap_or(0);
        let mut q0: Vec<f64> = (0..n).map(|_| space.q_bound * unit(u)).collect();
        let mut u0: Vec<f64> = (0..m).map(|_| space.u_bound * unit(u)).collect();
        let t = (unit(u) + 1.0) / 2.0;
        let mut h = space.h_min + (space.h_max - space.h_min) * t;
        let pick = |u: &mut Unstructured, xs: &[f64]| *u.choose(xs).unwrap_or(&xs[0]);
        let distance = pick(u, &[1e-12, -1e-9, 1e-6, -1e-4, 1e-3, -1e-2, 0.05]);
        let extreme_h = pick(u, &[1e-8, 1e-6, 1e-3, 1.0, 2.0]);
        let big = pick(u, &[10.0, 1e2, 1e3, 1e6]);
        let fast = pick(u, &[10.0, 100.0]);
        let choice = if space.extremes { choice } else { choice % 11 };
        let mut kind = match choice {
            0..=7 | 11..=13 => PairKind::OnManifold,
            8 | 9 | 14 => PairKind::Near { distance },
            _ => PairKind::Euler,
        };
        match choice {
            11 | 14 | 15 => h = extreme_h,
            12 => q0.iter_mut().for_each(|x| *x *= big),
            13 => u0.iter_mut().for_each(|x| *x *= fast),
            _ => {}
        }
        if !(h.is_finite() && h > 0.0) {
            h = 0.1; // only if the user's range is not finite: keep the decoding total
        }
        if q0.iter().chain(&u0).any(|x| !x.is_finite()) {
            q0 = vec![0.0; n];
            u0 = vec![0.0; m];
        }
        let flow_q1 = match kind {
            PairKind::OnManifold => pair_point(model, &q0, &u0, h, 0.0, &opts.flow(false)),
            PairKind::Near { distance } => {
                pair_point(model, &q0, &u0, h, distance, &opts.flow(false))
            }
            PairKind::Euler => None,
        };
        let q1 = match flow_q1 {
            Some(q1) if q1.iter().all(|x| x.is_finite()) => q1,
            _ => {
                kind = PairKind::Euler;
                let x: Vec<f64> = q0.iter().chain(&u0).copied().collect();
                let v0 = model.velocity.eval::<f64>(&x);
                let q1: Vec<f64> = q0.iter().zip(&v0).map(|(q, v)| q + h * v).collect();
                if q1.len() == n && q1.iter().all(|x| x.is_finite()) {
                    q1
                } else {
                    u0 = vec![0.0; m];
                    q0.clone()
                }
            }
        };
        SolverInput {
            q0,
            q1,
            h,
            u0,
            kind,
        }
    }
}

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Where inputs are drawn (see [`SolverInput::decode`]): `InputSpace::default()` and the
/// `with_*` setters.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct InputSpace {
    /// Ordinary configurations lie in `[-q_bound, q_bound]^n`. Default 1.
    pub q_bound: f64,
    /// Ordinary quasi-velocities lie in `[-u_bound, u_bound]^(n-k)`. Default 1.
    pub u_bound: f64,
    /// Ordinary steps lie in `[h_min, h_max]`. Default `[0.01, 0.5]`.
    pub h_min: f64,
    /// Upper end of the ordinary steps' range. Default 0.5.
    pub h_max: f64,
    /// Also tiny and large steps, large configurations and velocities. Default true.
    pub extremes: bool,
}

impl Default for InputSpace {
    fn default() -> Self {
        InputSpace {
            q_bound: 1.0,
            u_bound: 1.0,
            h_min: 0.01,
            h_max: 0.5,
            extremes: true,
        }
    }
}

impl InputSpace {
    /// With ordinary configurations in `[-b, b]^n`.
    pub fn with_q_bound(mut self, b: f64) -> Self {
        self.q_bound = b;
        self
    }
    /// With ordinary quasi-velocities in `[-b, b]^(n-k)`.
    pub fn with_u_bound(mut self, b: f64) -> Self {
        self.u_bound = b;
        self
    }
    /// With ordinary steps in `[lo, hi]`.
    pub fn with_h_range(mut self, lo: f64, hi: f64) -> Self {
        (self.h_min, self.h_max) = (lo, hi);
        self
    }
    /// With or without the extreme inputs.
    pub fn with_extremes(mut self, on: bool) -> Self {
        self.extremes = on;
        self
    }
}

/// The inputs and the oracle's budget: `FuzzOptions::default()` and the `with_*` setters.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct FuzzOptions {
    /// Where the inputs are drawn.
    pub space: InputSpace,
    /// Accepted Taylor steps of every certified flow (the pair builder's and the oracle's,
    /// [`FlowOptions::max_taylor_steps`]). Default 400.
    pub max_taylor_steps: usize,
    /// Time allowed to the oracle's check of one answer. Default 50 ms. The deadline makes
    /// a refusal depend on the machine's load, never a finding. The pair builder has no
    /// deadline (only `max_taylor_steps`), so that decoding does not depend on time: the same bytes
    /// are the same input on every machine.
    pub budget: Duration,
    /// Arithmetic work allowed to the pair builder and, separately, to the oracle's check
    /// ([`crate::work_done`] terms, [spec (5.8''')](crate::spec::enclosure)). Default 20 million: about 50 ms here,
    /// 20 times the costliest input of the example corpus. Unlike the deadline it refuses
    /// the same input on every machine.
    pub max_work: u64,
}

impl Default for FuzzOptions {
    fn default() -> Self {
        FuzzOptions {
            space: InputSpace::default(),
            max_taylor_steps: 400,
            budget: Duration::from_millis(50),
            max_work: 20_000_000,
        }
    }
}

impl FuzzOptions {
    /// With the inputs drawn from `space`.
    pub fn with_space(mut self, space: InputSpace) -> Self {
        self.space = space;
        self
    }
    /// With at most `n` accepted Taylor steps per certified flow.
    pub fn with_max_taylor_steps(mut self, n: usize) -> Self {
        self.max_taylor_steps = n;
        self
    }
    /// With the time `budget` for the oracle's check of one answer.
    pub fn with_budget(mut self, budget: Duration) -> Self {
        self.budget = budget;
        self
    }
    /// With the arithmetic work `w` allowed to the pair builder and to the oracle's check.
    pub fn with_max_work(mut self, w: u64) -> Self {
        self.max_work = w;
        self
    }

    fn flow(&self, deadline: bool) -> FlowOptions {
        FlowOptions {
            max_taylor_steps: self.max_taylor_steps,
            deadline: if deadline {
                Instant::now().checked_add(self.budget)
            } else {
                None
            },
            ..FlowOptions::default()
        }
        .allow_work(self.max_work)
    }
}

/// What one input came to when it was not a finding.
#[derive(Clone, Debug, PartialEq)]
pub enum FuzzOutcome {
    /// Claimed converged, and the oracle certified the step: `distance` encloses
    /// `|q2 - q^e_2|_inf` and its lower end is within `tol` (its upper end may not be: the
    /// enclosure's width is not held against the solver).
    Certified {
        /// Contains `|q2 - q^e_2|_inf` ([spec Theorem 8.1](crate::spec::oracle) with N = 2).
        distance: Interval,
        /// The tolerance stated for this input.
        tol: f64,
    },
    /// Claimed converged; the oracle could not certify the step within its budget (its
    /// typed refusal). Not a finding.
    Refused(Error),
    /// Claimed converged, finite, but the tolerance is infinite: nothing to compare.
    Unchecked,
    /// An answer not claimed converged (its numbers are not checked beyond their count).
    NotConverged,
    /// The solver's typed failure (its `Debug` text).
    SolverFailed(String),
}

/// Decode `data` ([`SolverInput::decode`], default [`FuzzOptions`]), run `solver` and check
/// its answer against the oracle ([spec eq. (11.7)](crate::spec::testing)); panics on a finding (module docs).
/// `tol` states the accuracy the solver claims, for each input, of a converged answer
/// against the exact discrete step (`|q2 - q^e_2|_inf`; see [`SolverInput::tolerance`]);
/// it must not be NaN or negative (that is a finding against the fuzz target).
pub fn fuzz_solver<S: NewtonSolver + ?Sized>(
    model: &Model,
    solver: &S,
    tol: impl Fn(&SolverInput) -> f64,
    data: &[u8],
) -> FuzzOutcome {
    fuzz_solver_with(model, solver, tol, &FuzzOptions::default(), data)
}

/// [`fuzz_solver`] with chosen inputs and budget.
pub fn fuzz_solver_with<S: NewtonSolver + ?Sized>(
    model: &Model,
    solver: &S,
    tol: impl Fn(&SolverInput) -> f64,
    opts: &FuzzOptions,
    data: &[u8],
) -> FuzzOutcome {
    let input = SolverInput::decode(model, opts, &mut Unstructured::new(data));
    check_answer(model, solver, &tol, opts, &input)
}

/// Run `solver` on one given input and check its answer as [`fuzz_solver`] does (for
/// replaying an input by hand, or a property test with its own inputs).
pub fn check_answer<S: NewtonSolver + ?Sized>(
    model: &Model,
    solver: &S,
    tol: &dyn Fn(&SolverInput) -> f64,
    opts: &FuzzOptions,
    input: &SolverInput,
) -> FuzzOutcome {
    let SolverInput { q0, q1, h, .. } = input;
    let answer = match solver.solve(q0, q1, *h) {
        Err(e) => return FuzzOutcome::SolverFailed(format!("{e:?}")),
        Ok(a) => a,
    };
    let n = model.n;
    assert!(
        answer.q2.len() == n,
        "finding: the solver returned {} components, scene `{}` has {n}; input {input:?}",
        answer.q2.len(),
        model.name()
    );
    if !answer.converged {
        return FuzzOutcome::NotConverged;
    }
    assert!(
        answer.q2.iter().all(|x| x.is_finite()),
        "finding: an answer claimed converged is not finite: q2 = {:?}; input {input:?}",
        answer.q2
    );
    let tol = tol(input);
    assert!(
        tol >= 0.0,
        "finding: the stated tolerance is {tol} (NaN or negative); input {input:?}"
    );
    if tol == f64::INFINITY {
        return FuzzOutcome::Unchecked;
    }
    match check_step(model, *h, q0, q1, &answer.q2, &opts.flow(true)) {
        Ok(v) => {
            // the oracle refuses a distance enclosure that is not finite, and tol is not NaN
            assert!(
                v.distance.inf() <= tol,
                "finding: an answer claimed converged is proved farther from the exact \
                 discrete step than the stated tolerance: |q2 - q^e_2|_inf >= {:e} > tol = \
                 {tol:e} (enclosure [{:e}, {:e}]); q2 = {:?}; input {input:?}",
                v.distance.inf(),
                v.distance.inf(),
                v.distance.sup(),
                answer.q2
            );
            FuzzOutcome::Certified {
                distance: v.distance,
                tol,
            }
        }
        Err(Error::Internal(m)) => panic!(
            "internal fault of dalembert's oracle (a bug of dalembert, not of the solver): \
             {m}; input {input:?}"
        ),
        Err(e) => FuzzOutcome::Refused(e),
    }
}

/// Counts of outcomes over a set of inputs (for a replay test to print and bound).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Inputs with [`FuzzOutcome::Certified`].
    pub certified: usize,
    /// Inputs with [`FuzzOutcome::Refused`].
    pub refused: usize,
    /// Inputs with [`FuzzOutcome::Unchecked`].
    pub unchecked: usize,
    /// Inputs with [`FuzzOutcome::NotConverged`].
    pub not_converged: usize,
    /// Inputs with [`FuzzOutcome::SolverFailed`].
    pub solver_failed: usize,
}

impl Tally {
    /// Count one outcome.
    pub fn add(&mut self, outcome: &FuzzOutcome) {
        *match outcome {
            FuzzOutcome::Certified { .. } => &mut self.certified,
            FuzzOutcome::Refused(_) => &mut self.refused,
            FuzzOutcome::Unchecked => &mut self.unchecked,
            FuzzOutcome::NotConverged => &mut self.not_converged,
            FuzzOutcome::SolverFailed(_) => &mut self.solver_failed,
        } += 1;
    }
    /// The number of outcomes counted.
    pub fn total(&self) -> usize {
        self.certified + self.refused + self.unchecked + self.not_converged + self.solver_failed
    }
}

impl fmt::Display for Tally {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let pct = |k: usize| 100.0 * k as f64 / self.total().max(1) as f64;
        write!(
            f,
            "{} inputs: {} certified ({:.0}%), {} refused by the oracle ({:.0}%), {} unchecked, \
             {} not converged, {} solver failures ({:.0}%)",
            self.total(),
            self.certified,
            pct(self.certified),
            self.refused,
            pct(self.refused),
            self.unchecked,
            self.not_converged,
            self.solver_failed,
            pct(self.solver_failed)
        )
    }
}

/// Replay every file of `dir` (in name order) through `check` (typically a closure around
/// [`fuzz_solver`]) and count the outcomes: the stable-toolchain replay of a fuzz corpus.
/// A finding panics as in the fuzz target, after naming the file on stderr. An unreadable
/// directory or file is an `Err`.
pub fn replay_dir(dir: &Path, check: impl Fn(&[u8]) -> FuzzOutcome) -> std::io::Result<Tally> {
    let mut files: Vec<_> = std::fs::read_dir(dir)?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()?;
    files.sort();
    let mut tally = Tally::default();
    for f in files.iter().filter(|f| f.is_file()) {
        let data = std::fs::read(f)?;
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| check(&data))) {
            Ok(outcome) => tally.add(&outcome),
            Err(finding) => {
                eprintln!("finding on input {}", f.display());
                std::panic::resume_unwind(finding)
            }
        }
    }
    Ok(tally)
}
