//! Tools for people who test their own nonholonomic integrators against the oracle
//! ([spec/11-testing.md](crate::spec::testing)): a [`Stepper`] trait for a user's one-step map, and
//! the certified local error of a stepper on a ladder of step sizes with the observed order
//! between consecutive rungs as an interval.
//!
//! ```
//! # use dalembert::{AnyScene, Model, FlowOptions};
//! # use dalembert::schemes::{Scheme, SchemeKind};
//! # use dalembert::testing::local_order;
//! let model = Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap();
//! let mut dla = Scheme::new(&model, SchemeKind::Dla);
//! let hs = [0.2, 0.1, 0.05, 0.025];
//! let ladder = local_order(&model, &mut dla, &[0.0, 0.0, 0.3], &[0.8, 0.5], &hs, &FlowOptions::default()).unwrap();
//! // every rung's error is a certified interval; so is the order between rungs
//! assert!(ladder.orders[2].inf() > 2.5); // proved: the local error shrinks faster than h^2.5 here
//! ```

#[cfg(feature = "fuzzing")]
#[cfg_attr(docsrs, doc(cfg(feature = "fuzzing")))]
pub mod fuzz;
#[cfg(feature = "quickcheck")]
#[cfg_attr(docsrs, doc(cfg(feature = "quickcheck")))]
pub mod quickcheck_inputs;
#[cfg(feature = "proptest")]
#[cfg_attr(docsrs, doc(cfg(feature = "proptest")))]
pub mod strategies;

use crate::oracle::{check_step, check_trajectory, CheckOptions};
use crate::scalar::{point, Scalar};
use crate::schemes::{NewtonOptions, Scheme};
use crate::{flow, Error, FlowOptions, Interval, Model};
use inari::Interval as Inari;

/// A user's one-step map of a two-step (variational) integrator: `q_{k+1}` from
/// `(q_{k-1}, q_k)` and the step `h`, written into the caller's buffer, or the stepper's
/// own failure.
///
/// ```
/// use dalembert::testing::{check_stepper, Stepper};
/// use dalembert::{AnyScene, FlowOptions, Model};
/// /// The straight-line two-step map q_{k+1} = 2 q_k - q_{k-1}; it never fails.
/// struct Straight;
/// impl Stepper for Straight {
///     type Error = std::convert::Infallible;
///     fn step(&mut self, q_prev: &[f64], q: &[f64], _h: f64, q_next: &mut [f64])
///         -> Result<(), Self::Error> {
///         for ((x, a), b) in q_next.iter_mut().zip(q_prev).zip(q) {
///             *x = 2.0 * b - a;
///         }
///         Ok(())
///     }
/// }
/// let model = Model::new(&AnyScene::new("particle", &[])?)?;
/// let (q0, q1) = ([0.0; 3], [0.1, 0.1, 0.0]);
/// let v = check_stepper(&model, &mut Straight, &q0, &q1, 0.125, 3, &FlowOptions::default())?;
/// assert_eq!(v.q.len(), 4);
/// # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
/// ```
pub trait Stepper {
    /// The stepper's own failure: any type that prints (`String`, an error type,
    /// [`std::convert::Infallible`]); its `Display` text goes into the
    /// [`Error::Input`] of kind
    /// [`InputKind::Stepper`](crate::InputKind::Stepper) that names the step. The same bound
    /// as `testing::fuzz::NewtonSolver::Error` (feature `fuzzing`).
    type Error: std::fmt::Display + std::fmt::Debug;
    /// Write `q_{k+1}` into `q_next` (as many numbers as `q` has) from `q_prev = q_{k-1}`,
    /// `q = q_k` and the step `h`; `Err` with the stepper's own failure. `q_next` holds
    /// NaN on entry: a component left unwritten is refused as not finite.
    fn step(
        &mut self,
        q_prev: &[f64],
        q: &[f64],
        h: f64,
        q_next: &mut [f64],
    ) -> Result<(), Self::Error>;
    /// The integrator's own starting step: write `q_1` into `q1` from a state `(q_0, v_0)`
    /// (v_0 the velocity in coordinates), when it has one; `None` (the default): start from
    /// the exact motion.
    fn start(
        &mut self,
        _q0: &[f64],
        _v0: &[f64],
        _h: f64,
        _q1: &mut [f64],
    ) -> Option<Result<(), Self::Error>> {
        None
    }
}

/// The crate's DLA and MLA schemes are steppers (Newton with its default options); a
/// failure is Newton's, typed.
impl Stepper for Scheme {
    type Error = crate::newton::NewtonFailure;
    fn step(
        &mut self,
        q_prev: &[f64],
        q: &[f64],
        h: f64,
        q_next: &mut [f64],
    ) -> Result<(), Self::Error> {
        let (x, _, _) = Scheme::step(self, q_prev, q, h, &NewtonOptions::default())?;
        q_next.copy_from_slice(&x);
        Ok(())
    }
}

/// `stepper`'s failure at the step that asked for `q_{k+1}` (`k = None`: not a step of a
/// run), as an input error of kind [`InputKind::Stepper`](crate::InputKind::Stepper).
fn stepper_failed(k: Option<usize>, message: String) -> Error {
    Error::input_at(crate::InputKind::Stepper { step: k }, message)
}

/// The certified local errors of a stepper on a ladder of step sizes ([spec eq. (11.1)](crate::spec::testing)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Ladder {
    /// The step sizes, as given.
    pub h: Vec<f64>,
    /// `error[i] ∋ |q2 - q^e_2|_inf` at `h[i]`: the stepper's `q2` from the pair
    /// `(q0, q1_i)`, `q1_i` a float point of the exact motion at `h[i]`, against the exact
    /// discrete flow from the same pair.
    pub error: Vec<Interval>,
    /// `orders[i] ∋ ln(e_i / e_{i+1}) / ln(h_i / h_{i+1})` (eq. (11.2)): the observed order
    /// between rungs i and i + 1 of the true errors; `[-inf, +inf]` where an error's
    /// enclosure reaches 0.
    pub orders: Vec<Interval>,
}

/// Run `stepper` once from `(q0, q1)` for each `h` of `hs` (distinct, decreasing, > 0), where
/// `q1` is the midpoint of the certified flow from `(q0, u0)` at time h (a float pair next to
/// M_h^{e,nh}), and enclose its local error against the exact discrete flow from that pair.
///
/// # Containment
/// `error[i]` contains the distance from the stepper's `q2` to `q(2 h_i)` of the exact
/// discrete flow from its pair ([spec Theorem 8.1](crate::spec::oracle)), and `orders[i]` contains the quotient of
/// logarithms (11.2) of the true errors (interval arithmetic, outward rounded). A stepper
/// failure is an `Error::Input` naming the rung; an oracle that cannot conclude,
/// `Error::Uncertified`.
pub fn local_order<St: Stepper + ?Sized>(
    model: &Model,
    stepper: &mut St,
    q0: &[f64],
    u0: &[f64],
    hs: &[f64],
    opts: &FlowOptions,
) -> Result<Ladder, Error> {
    local_errors(model, stepper, q0, u0, hs, opts, |h, q1, q2| {
        Ok(check_step(model, h, q0, q1, q2, opts)?.distance)
    })
}

/// The ladder of one-step errors: for each `h`, the stepper's `q2` from the pair `(q0, q1)`
/// of [`start`], and `error_of(h, q1, q2)` its certified error.
fn local_errors<St: Stepper + ?Sized>(
    model: &Model,
    stepper: &mut St,
    q0: &[f64],
    u0: &[f64],
    hs: &[f64],
    opts: &FlowOptions,
    mut error_of: impl FnMut(f64, &[f64], &[f64]) -> Result<Interval, Error>,
) -> Result<Ladder, Error> {
    check_ladder(hs)?;
    let mut error = Vec::with_capacity(hs.len());
    let mut q2 = vec![f64::NAN; q0.len()];
    for &h in hs {
        let q1 = start(model, q0, u0, h, opts)?;
        q2.fill(f64::NAN);
        stepper
            .step(q0, &q1, h, &mut q2)
            .map_err(|e| stepper_failed(Some(1), format!("the stepper failed at h = {h}: {e}")))?;
        error.push(error_of(h, &q1, &q2)?);
    }
    Ok(ladder(hs, error))
}

/// [`local_order`] with the exact discrete flow computed in the interval type `I` (e.g.
/// [`crate::precision::dd::DdInterval`], 106 bits; [spec/12-precision.md](crate::spec::precision)): the certified
/// local errors stay narrow down to about `2^-100 |q|` where the f64 ones stop at about
/// `2^-50 |q|`, so the orders of a scheme are certified at smaller steps. `error[i]` encloses
/// `|q2 - q^e_2|_inf`, `q^e_2` the exact step's `q(2h)` ([`crate::exact::step_in`]) from the
/// same pair as [`local_order`]'s.
///
/// # Containment
/// As [`local_order`], whatever `I` ([spec Theorem 6.2](crate::spec::exact_discrete), (12.0.2)).
pub fn local_order_in<I: crate::Ival, St: Stepper + ?Sized>(
    model: &Model,
    stepper: &mut St,
    q0: &[f64],
    u0: &[f64],
    hs: &[f64],
    opts: &FlowOptions,
) -> Result<Ladder, Error> {
    local_errors(model, stepper, q0, u0, hs, opts, |h, q1, q2| {
        if let Some(x) = q2.iter().find(|x| !x.is_finite()) {
            return Err(stepper_failed(
                Some(1),
                format!("the stepper's q2 has the non-finite component {x} at h = {h}"),
            ));
        }
        let exact = crate::exact::step_in::<I>(model, q0, q1, h, opts)?;
        let d: Vec<I> = exact
            .q2
            .iter()
            .zip(q2)
            .map(|(e, x)| I::cst(*x) - I::from_public(e.clone()))
            .collect();
        // |q2 - q^e_2|_inf lies between the largest lower bound and the largest upper bound
        // of the components' magnitudes
        let lo = d.iter().fold(0.0f64, |a, x| a.max(x.mig()));
        let hi = d.iter().fold(0.0f64, |a, x| a.max(x.mag()));
        Interval::try_new(lo, hi).ok_or_else(|| {
            Error::refused(crate::Reason::Unbounded, "the local error is not finite")
        })
    })
}

/// The certified global error of a stepper over `[0, t_end]` on a ladder of step sizes
/// ([spec eq. (11.3)](crate::spec::testing)): for each `h`, `N = t_end / h` steps (an integer, else an input error)
/// from `(q0, q1)`, `q1` as in [`local_order`]; `error[i]` encloses
/// `max_k |q_k - q^e_k|_inf` against the exact discrete flow from that pair, and `orders`
/// the observed orders between rungs (11.2).
///
/// # Containment
/// As [`local_order`], with Theorem 8.1 over N steps (`oracle::check_trajectory`).
pub fn global_order<St: Stepper + ?Sized>(
    model: &Model,
    stepper: &mut St,
    q0: &[f64],
    u0: &[f64],
    t_end: f64,
    hs: &[f64],
    opts: &FlowOptions,
) -> Result<Ladder, Error> {
    check_ladder(hs)?;
    let mut error = Vec::with_capacity(hs.len());
    for &h in hs {
        let steps = t_end / h;
        if !(steps >= 1.0 && steps.fract() == 0.0 && steps <= 1e6) {
            return Err(Error::input(format!(
                "t_end / h must be a whole number of steps in 1..=1e6 (h = {h})"
            )));
        }
        let q1 = start(model, q0, u0, h, opts)?;
        let q = run_flat(stepper, q0, &q1, h, steps as usize, |k, e| {
            format!("the stepper failed at h = {h}, step {}: {e}", k + 1)
        })?;
        let o = CheckOptions {
            pairs: false,
            flow: opts.clone(),
        };
        let rows: Vec<&[f64]> = q.chunks(q0.len()).collect();
        error.push(check_trajectory(model, h, &rows, &o)?.max_distance);
    }
    Ok(ladder(hs, error))
}

fn check_ladder(hs: &[f64]) -> Result<(), Error> {
    if hs.len() < 2 || hs.windows(2).any(|w| !(w[0] > w[1] && w[1] > 0.0)) {
        return Err(Error::input(
            "the ladder needs at least two step sizes, decreasing and > 0",
        ));
    }
    Ok(())
}

/// The float point of the exact motion from `(q0, u0)` at time h (the midpoint of its
/// certified enclosure).
fn start(
    model: &Model,
    q0: &[f64],
    u0: &[f64],
    h: f64,
    opts: &FlowOptions,
) -> Result<Vec<f64>, Error> {
    Ok(flow(model, q0, u0, h, opts)?
        .q
        .iter()
        .map(|x| x.mid())
        .collect())
}

fn ladder(hs: &[f64], error: Vec<Interval>) -> Ladder {
    let orders = error
        .windows(2)
        .zip(hs.windows(2))
        .map(|(e, h)| observed_order(e[0], e[1], h[0], h[1]))
        .collect();
    Ladder {
        h: hs.to_vec(),
        error,
        orders,
    }
}

/// Certified verdicts on a stepper's run ([spec eq. (11.4)](crate::spec::testing)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct StepperVerdict {
    /// The stepper's iterates `q_0 .. q_N` (`q_0`, `q_1` as given or started).
    pub q: Vec<Vec<f64>>,
    /// Against the exact discrete flow from `(q_0, q_1)`: distances, defects of every pair,
    /// energy errors (`oracle::Verdict`).
    pub discrete: crate::oracle::Verdict,
    /// `continuous[k] ∋ |q_k - q(t_k)|_inf` against the exact motion from `(q_0, u_0)` at
    /// `t_k = k h`; empty when the run was started from a pair.
    pub continuous: Vec<Interval>,
}

impl StepperVerdict {
    /// Whether the run passes the tolerance `tol` on the distance to the exact discrete
    /// flow and `defect_tol` on its pairs' defects (`discrete.max_defect`), decided as the
    /// `check` command decides ([spec (8.3)](crate::spec::oracle), (8.5)): `Ok(false)` when one is proved
    /// exceeded, `Error::Uncertified` when undecided.
    pub fn passes(&self, tol: Option<f64>, defect_tol: Option<f64>) -> Result<bool, Error> {
        crate::oracle::Tolerances { tol, defect_tol }
            .passes(self.discrete.max_distance, self.discrete.max_defect)
    }
}

/// Run `stepper` for `steps` steps from `(q0, q1)` and check the run against the exact
/// discrete flow from that pair ([spec eq. (11.4)](crate::spec::testing)).
///
/// # Containment
/// As `oracle::check_trajectory` (Theorem 8.1). A stepper failure is an `Error::Input`
/// naming the step.
pub fn check_stepper<St: Stepper + ?Sized>(
    model: &Model,
    stepper: &mut St,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    steps: usize,
    opts: &FlowOptions,
) -> Result<StepperVerdict, Error> {
    let q = run(stepper, q0, q1, h, steps)?;
    let o = CheckOptions {
        pairs: true,
        flow: opts.clone(),
    };
    Ok(StepperVerdict {
        discrete: check_trajectory(model, h, &q, &o)?,
        q,
        continuous: Vec::new(),
    })
}

/// As [`check_stepper`], started from a state: `q1` is the stepper's own start
/// ([`Stepper::start`] from `(q0, v0)`, `v0 = E(q0)^T u0`) or, without one, the float point
/// of the exact motion from `(q0, u0)` at time h (as in (11.1)); the run is also checked
/// against that motion at every `t_k = k h`, so that a scheme whose start is first order
/// shows it ([spec eq. (11.5)](crate::spec::testing)).
///
/// # Containment
/// `continuous[k]` contains `|q_k - q(t_k)|_inf` for the exact motion from `(q0, u0)`
/// (Theorem 5.1); the rest as [`check_stepper`].
pub fn check_stepper_from_state<St: Stepper + ?Sized>(
    model: &Model,
    stepper: &mut St,
    q0: &[f64],
    u0: &[f64],
    h: f64,
    steps: usize,
    opts: &FlowOptions,
) -> Result<StepperVerdict, Error> {
    crate::flow::check_state(model, q0, u0)?;
    let x: Vec<f64> = q0.iter().chain(u0).copied().collect();
    let v0 = model.velocity.eval(&x);
    let mut q1 = vec![f64::NAN; q0.len()];
    match stepper.start(q0, &v0, h, &mut q1) {
        None => q1 = start(model, q0, u0, h, opts)?,
        Some(r) => {
            r.map_err(|e| stepper_failed(Some(0), format!("the stepper's start failed: {e}")))?
        }
    }
    let mut v = check_stepper(model, stepper, q0, &q1, h, steps, opts)?;
    let mut continuous = vec![Interval::point(0.0)];
    for (k, qk) in v.q.iter().enumerate().skip(1) {
        let e = flow(model, q0, u0, k as f64 * h, opts)?;
        continuous.push(crate::oracle::distance(qk, &e.q));
    }
    v.continuous = continuous;
    Ok(v)
}

fn run<St: Stepper + ?Sized>(
    stepper: &mut St,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    steps: usize,
) -> Result<Vec<Vec<f64>>, Error> {
    if steps == 0 || steps > 1_000_000 {
        return Err(Error::input_key("steps", "steps must be in 1..=1000000"));
    }
    let q = run_flat(stepper, q0, q1, h, steps, |k, e| {
        format!("the stepper failed at step {k} (h = {h}): {e}")
    })?;
    Ok(q.chunks(q0.len()).map(<[f64]>::to_vec).collect())
}

/// `q_0, q_1` and `steps - 1` steps of `stepper`, row after row in one buffer of
/// `(steps + 1) n` numbers that the stepper writes into: no allocation per step. A failure
/// of step k (the one that gives `q_{k+1}`) is refused with `failed(k, e)`; so is an answer
/// that is not `n` finite numbers.
fn run_flat<St: Stepper + ?Sized>(
    stepper: &mut St,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    steps: usize,
    failed: impl Fn(usize, &St::Error) -> String,
) -> Result<Vec<f64>, Error> {
    let n = q0.len();
    if q1.len() != n {
        return Err(Error::input_at(
            crate::InputKind::Dimension {
                what: "q1".into(),
                got: q1.len(),
                expected: n,
            },
            format!("q1 has {} components, q0 has {n}", q1.len()),
        ));
    }
    let mut q = vec![f64::NAN; (steps + 1) * n];
    q[..n].copy_from_slice(q0);
    q[n..2 * n].copy_from_slice(q1);
    for k in 1..steps {
        let (done, rest) = q.split_at_mut((k + 1) * n);
        let next = &mut rest[..n];
        stepper
            .step(&done[(k - 1) * n..k * n], &done[k * n..], h, next)
            .map_err(|e| stepper_failed(Some(k), failed(k, &e)))?;
        if next.iter().any(|x| !x.is_finite()) {
            return Err(stepper_failed(
                Some(k),
                format!("the stepper returned {next:?} at step {k}: not {n} finite numbers"),
            ));
        }
    }
    Ok(q)
}

/// `{ln(a / b) / ln(ha / hb) : a in ea, b in eb}` enclosed ([spec eq. (11.2)](crate::spec::testing)), ha > hb > 0;
/// the whole line when `ea` or `eb` reaches 0.
pub fn observed_order(ea: Interval, eb: Interval, ha: f64, hb: f64) -> Interval {
    let r = (point(ha) / point(hb)).ln();
    let usable = ea.inf() > 0.0 && eb.inf() > 0.0 && r.inf() > 0.0;
    if usable {
        ((Inari::from(ea) / Inari::from(eb)).ln() / r).into()
    } else {
        Interval::ENTIRE
    }
}

/// A start pair for a scheme, with what the oracle proved about it.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Pair {
    /// The first configuration `q0`.
    pub q0: Vec<f64>,
    /// The quasi-velocities the pair was made from.
    pub u0: Vec<f64>,
    /// The second configuration: `mid(flow(q0, u0, h).q)`, possibly moved a chosen distance
    /// off `M_h^{e,nh}` along the first constraint normal ([spec eq. (11.6)](crate::spec::testing)).
    pub q1: Vec<f64>,
    /// The step `h > 0` of the pair.
    pub h: f64,
    /// Encloses the defect s of `(q0, q1)` with respect to `M_h^{e,nh}` ([spec eq. (6.2)](crate::spec::exact_discrete)).
    pub defect: Vec<Interval>,
}

#[cfg(any(feature = "proptest", feature = "quickcheck"))]
pub(crate) fn points(v: &[f64]) -> Vec<Inari> {
    v.iter().map(|x| point(*x)).collect()
}

#[cfg(any(feature = "proptest", feature = "quickcheck"))]
pub(crate) fn exact_pair(
    model: &Model,
    q0: Vec<f64>,
    u0: Vec<f64>,
    h: f64,
    distance: f64,
) -> Option<Pair> {
    let opts = FlowOptions::default();
    let q1 = pair_point(model, &q0, &u0, h, distance, &opts)?;
    let pts = |v: &[f64]| crate::interval::wrap(points(v));
    let r = crate::exact::retract(model, &pts(&q0), &pts(&q1), h, &opts).ok()?;
    Some(Pair {
        q0,
        u0,
        q1,
        h,
        defect: r.s,
    })
}

/// The second point of the pair builder: `q1 = mid(flow(q0, u0, h).q)`, then moved by
/// `distance` along the unit first constraint normal at that point; `None` when the flow
/// refuses (within `opts`) or the normal is zero or not finite.
#[cfg(any(feature = "proptest", feature = "quickcheck", feature = "fuzzing"))]
pub(crate) fn pair_point(
    model: &Model,
    q0: &[f64],
    u0: &[f64],
    h: f64,
    distance: f64,
    opts: &FlowOptions,
) -> Option<Vec<f64>> {
    let mut q1: Vec<f64> = flow(model, q0, u0, h, opts)
        .ok()?
        .q
        .iter()
        .map(|x| x.mid())
        .collect();
    if distance != 0.0 {
        shift_off(model, &mut q1, distance)?;
    }
    Some(q1)
}

/// Move `q` by `distance` along the unit normal of the first constraint at `q` (a float
/// choice of a point off `M_h^{e,nh}`; the oracle certifies where it lands). `None` when
/// that normal is 0 or not finite (`q` is then unchanged).
#[cfg(any(feature = "proptest", feature = "quickcheck", feature = "fuzzing"))]
pub(crate) fn shift_off(model: &Model, q: &mut [f64], distance: f64) -> Option<()> {
    let mu = model.constraints.eval::<f64>(q);
    let normal = &mu[..model.n];
    let len = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    for (x, nx) in q.iter_mut().zip(normal) {
        *x += distance * nx / len;
    }
    Some(())
}
