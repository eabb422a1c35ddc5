//! The oracle: certified verdicts on candidate discrete trajectories produced by any float
//! integrator ([spec/08-oracle.md](crate::spec::oracle)). Small enough to use from a property test:
//!
//! ```
//! # use dalembert::{AnyScene, Model, oracle};
//! let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
//! let q: Vec<Vec<f64>> = vec![vec![0.0; 3], vec![0.4, 0.4, 0.08], vec![0.76, 0.8, 0.29]];
//! let v = oracle::check_trajectory(&model, 0.5, &q, &oracle::CheckOptions::default()).unwrap();
//! assert!(v.max_distance.sup() < 1e-2); // proved: every q_k is within 1e-2 of the exact flow
//! ```

use crate::enclosure::Ival;
use crate::exact::{self, ExactFlow, ExactTrajectory, Iterate, IterateIn};
use crate::scalar::point;
use crate::tape::finite;
use crate::{Error, FlowOptions, InputKind, Interval, Model, Reason};
use inari::Interval as Inari;

/// What to compute besides the distances: `CheckOptions::default()` and the `with_*`
/// setters.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct CheckOptions {
    /// Also certify, for every consecutive pair, its defect w.r.t. M_h^{e,nh} and the energy
    /// of the exact trajectory through it (one retraction per pair).
    pub pairs: bool,
    /// Settings of every validated flow and retraction the check runs (order, step budget,
    /// deadline).
    pub flow: FlowOptions,
}

impl CheckOptions {
    /// With or without the pair figures ([`CheckOptions::pairs`]).
    pub fn with_pairs(mut self, on: bool) -> Self {
        self.pairs = on;
        self
    }
    /// With the settings `flow` of every validated flow and retraction.
    pub fn with_flow(mut self, flow: FlowOptions) -> Self {
        self.flow = flow;
        self
    }
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            pairs: true,
            flow: FlowOptions::default(),
        }
    }
}

/// Certified figures about a candidate trajectory `q_0 .. q_N` ([spec Theorem 8.1](crate::spec::oracle)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Verdict {
    /// `distance[k] ∋ |q_k - q^e_k|_inf`, `q^e` the exact discrete flow from `(q_0, q_1)`.
    pub distance: Vec<Interval>,
    /// The hull of the distances: `max_k |q_k - q^e_k|_inf` lies in it.
    pub max_distance: Interval,
    /// `defect[k] ∋ s` of the pair `(q_k, q_{k+1})` (empty unless `pairs`).
    pub defect: Vec<Vec<Interval>>,
    /// `∋ max_k |s_k|_inf` over the pairs' defects (`None` without pair figures).
    pub max_defect: Option<Interval>,
    /// `energy_error[k] ∋ E_L(q_k, R^{e-}(q_k, q_{k+1})) - E_L(q_0, R^{e-}(q_0, q_1))`
    /// (empty unless `pairs`).
    pub energy_error: Vec<Interval>,
    /// The exact discrete trajectory the candidate was compared with.
    pub exact: ExactTrajectory,
}

/// `|a - B|_inf` over the box `B`: an interval containing `max_i |a_i - b_i|` for every
/// `b in B`.
pub fn distance(a: &[f64], b: &[Interval]) -> Interval {
    a.iter()
        .zip(b)
        .map(|(x, y)| (point(*x) - Inari::from(*y)).abs())
        .fold(point(0.0), |m, d| m.max(d))
        .into()
}

/// `E_L(q, v)` enclosed over the boxes (the energy of the exact trajectory through `(q, v)`).
/// In any interval type `I`.
pub(crate) fn energy<I: Ival>(model: &Model, q: &[I], v: &[I]) -> Result<I, Error> {
    let x: Vec<I> = q.iter().chain(v).copied().collect();
    model
        .energy_tape()
        .eval_checked(&x)
        .map(|e| e[0])
        .ok_or_else(|| Error::refused(Reason::Unbounded, "energy enclosure not finite"))
}

/// Check a candidate trajectory `q_0 .. q_N` against the exact discrete flow from
/// `(q_0, q_1)`: with a uniform step `h` (`steps` an `f64` or [`Steps::Uniform`]), or at
/// times `t_0 < t_1 < .. < t_N`, one per row ([`Steps::Times`], a `Vec<f64>` or `&[f64]`;
/// non-uniform steps, [spec eq. (8.4)](crate::spec::oracle)). The rows are anything that is a slice of f64
/// (`Vec<f64>`, `[f64; n]`, `&[f64]`).
///
/// # Containment
/// If `Ok(v)`: for every k, `|q_k - q^e_k|_inf ∈ v.distance[k]`, where `q^e_k = q(t_k - t_0)`
/// (`t_k = k h` for a uniform step) on the trajectory from `q_0` with `u_0` the unique
/// solution of [spec eq. (6.2)](crate::spec::exact_discrete) for `(q_0, q_1)` with `h_0 = t_1 - t_0` in the Krawczyk box
/// (the exact discrete flow through `(q_0, q_1 + N(q_1) s)`); so `v.max_distance.sup() <= e`
/// proves "every iterate is within e of the exact discrete flow". The pair figures of
/// `(q_k, q_{k+1})`, with `h_k = t_{k+1} - t_k`, are proved likewise (Theorems 6.1, 6.2).
/// `Error::Input` for malformed candidates (also: times not finite and strictly
/// increasing, not one per row, or a step `h_k` that a retraction needs that is not a
/// float: `t_{k+1} - t_k` is exact in f64 whenever `t_{k+1} <= 2 t_k`, by Sterbenz's
/// lemma), `Error::Uncertified` when the oracle itself cannot conclude. The rows of
/// [`check_rows`], collected.
///
/// # Example
/// ```
/// use dalembert::oracle::{check_trajectory, CheckOptions};
/// use dalembert::schemes::{NewtonOptions, Scheme, SchemeKind};
/// use dalembert::{AnyScene, Model};
/// let model = Model::new(&AnyScene::new("particle", &[])?)?;
/// // a candidate: eight steps of DLA
/// let h = 0.125;
/// let dla = Scheme::new(&model, SchemeKind::Dla);
/// let candidate = dla.integrate(&[0.0; 3], &[0.1, 0.1, 0.005], h, 8, &NewtonOptions::default())?;
/// let v = check_trajectory(&model, h, &candidate.q, &CheckOptions::default())?;
/// // proved: every q_k is within 1e-3 of the exact discrete flow from (q_0, q_1)
/// assert!(v.max_distance.sup() < 1e-3);
/// // and every pair's defect w.r.t. M_h^{e,nh}, |s_k|_inf, is below 1e-4
/// assert!(v.max_defect.is_some_and(|d| d.sup() < 1e-4));
/// // the same candidate at its times t_k = k h: the same verdict
/// let times: Vec<f64> = (0..=8).map(|k| k as f64 * h).collect();
/// let w = check_trajectory(&model, times, &candidate.q, &CheckOptions::default())?;
/// assert_eq!(w.max_distance, v.max_distance);
/// # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
/// ```
pub fn check_trajectory<R: AsRef<[f64]>>(
    model: &Model,
    steps: impl Into<Steps>,
    q: &[R],
    opts: &CheckOptions,
) -> Result<Verdict, Error> {
    match steps.into() {
        Steps::Uniform(h) => collect(q, |rows, sink| {
            check_rows(
                model,
                Some(h),
                rows.map(|r| r.map(|q| (None, q))),
                opts,
                sink,
            )
        }),
        Steps::Times(times) => {
            if times.len() != q.len() {
                return Err(Error::input_at(
                    InputKind::Times,
                    format!(
                        "{} times for {} rows: give one time per row",
                        times.len(),
                        q.len()
                    ),
                ));
            }
            collect(q, |rows, sink| {
                let rows = times
                    .iter()
                    .zip(rows)
                    .map(|(t, r)| r.map(|r| (Some(*t), r)));
                check_rows(model, None, rows, opts, sink)
            })
        }
    }
}

/// The steps of a candidate trajectory: uniform of size `h`, or at the given times. An
/// `f64` converts to `Uniform`, a list of times to `Times`.
#[derive(Clone, Debug, PartialEq)]
pub enum Steps {
    /// The same step `h > 0` between all consecutive rows.
    Uniform(f64),
    /// `t_0 < t_1 < .. < t_N`, one per row ([spec eq. (8.4)](crate::spec::oracle)).
    Times(Vec<f64>),
}

impl From<f64> for Steps {
    fn from(h: f64) -> Steps {
        Steps::Uniform(h)
    }
}

impl From<Vec<f64>> for Steps {
    fn from(t: Vec<f64>) -> Steps {
        Steps::Times(t)
    }
}

impl From<&Vec<f64>> for Steps {
    fn from(t: &Vec<f64>) -> Steps {
        Steps::Times(t.clone())
    }
}

impl From<&[f64]> for Steps {
    fn from(t: &[f64]) -> Steps {
        Steps::Times(t.to_vec())
    }
}

impl From<&Steps> for Steps {
    fn from(s: &Steps) -> Steps {
        s.clone()
    }
}

type Sink<'a> = &'a mut dyn FnMut(RowVerdict) -> Result<(), Error>;
type RowIter<'a> = Box<dyn Iterator<Item = Result<Vec<f64>, Error>> + 'a>;

/// The rows of a streaming check, collected into a [`Verdict`].
fn collect<'q, R: AsRef<[f64]>>(
    q: &'q [R],
    check: impl FnOnce(RowIter<'q>, Sink) -> Result<CheckSummary, Error>,
) -> Result<Verdict, Error> {
    let mut distance = Vec::with_capacity(q.len());
    let (mut defect, mut energy_error) = (Vec::new(), Vec::new());
    let (mut eq, mut ev, mut ep) = (Vec::new(), Vec::new(), Vec::new());
    let mut sink = |row: RowVerdict| {
        distance.push(row.distance);
        if let Some(pair) = row.pair {
            defect.push(pair.defect);
            energy_error.push(pair.energy_error);
        }
        eq.push(row.exact.q);
        ev.push(row.exact.v);
        ep.push(row.exact.p);
        Ok(())
    };
    let summary = check(
        Box::new(q.iter().map(|r| Ok(r.as_ref().to_vec()))),
        &mut sink,
    )?;
    let max_defect = summary.max_defect;
    Ok(Verdict {
        distance,
        max_distance: summary.max_distance,
        defect,
        max_defect,
        energy_error,
        exact: ExactTrajectory {
            retraction: summary.retraction,
            q: eq,
            v: ev,
            p: ep,
        },
    })
}

/// Certified figures about the pair `(q_k, q_{k+1})` (Theorems 6.1, 6.2).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct PairVerdict {
    /// `∋ s` of the pair, its defect w.r.t. M_h^{e,nh}.
    pub defect: Vec<Interval>,
    /// `∋ E_L(q_k, R^{e-}(q_k, q_{k+1})) - E_L(q_0, R^{e-}(q_0, q_1))`.
    pub energy_error: Interval,
}

/// Certified figures about one row `q_k` of a candidate trajectory ([spec Theorem 8.1](crate::spec::oracle)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct RowVerdict {
    /// The row's index `k`.
    pub k: usize,
    /// `∋ |q_k - q^e_k|_inf`.
    pub distance: Interval,
    /// The pair `(q_k, q_{k+1})`: `None` on the last row and unless `CheckOptions::pairs`.
    pub pair: Option<PairVerdict>,
    /// The iterate `q^e_k` of the exact discrete flow that `q_k` was compared with.
    pub exact: Iterate,
}

/// What [`check_rows`] returns once every row is checked.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(serialize = "I::Public: serde::Serialize"))
)]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct CheckSummary<I: Ival = Inari> {
    /// The number of rows `N + 1`.
    pub rows: usize,
    /// `∋ max_k |q_k - q^e_k|_inf`.
    pub max_distance: Interval,
    /// The retraction of `(q_0, q_1)` the exact discrete flow starts from (in the
    /// computation's intervals).
    pub retraction: crate::exact::Retraction<I>,
    /// `∋ max_k |s_k|_inf` over the pairs' defects (`None` without pair figures).
    pub max_defect: Option<Interval>,
}

/// `t_{k+1} - t_k` as a float, when it is one: a retraction's step ([spec eq. (8.4)](crate::spec::oracle)).
fn exact_step(k: usize, t0: f64, t1: f64) -> Result<f64, Error> {
    let d = point(t1) - point(t0);
    if d.inf() == d.sup() && d.inf() > 0.0 {
        Ok(d.inf())
    } else {
        Err(Error::input_at(
            InputKind::Times,
            format!(
                "t_{} - t_{k} = {t1} - {t0} is not a float: the retraction of the pair needs an \
             exact step (it is exact when t_{} <= 2 t_{k}, e.g. for t_k = k h)",
                k + 1,
                k + 1
            ),
        ))
    }
}

/// [`check_trajectory`] one row at a time, in memory independent of the number of rows:
/// `rows` (`(t_k, q_k)`) is read as needed, and `sink` is given each row's verdict as soon
/// as it is proved (row k once `q_{k+1}` is read, for its pair figures). With `h =
/// Some(h)` the steps are uniform and the rows' times are not read (give `None`); with `h =
/// None` every row carries its time `Some(t_k)` (non-uniform steps, [spec eq. (8.4)](crate::spec::oracle)), and a
/// row without one is an input error. An error from `rows` or `sink` stops the check and
/// is returned as it is.
///
/// # Containment
/// As [`check_trajectory`], row by row.
pub fn check_rows(
    model: &Model,
    h: Option<f64>,
    rows: impl IntoIterator<Item = Result<(Option<f64>, Vec<f64>), Error>>,
    opts: &CheckOptions,
    sink: impl FnMut(RowVerdict) -> Result<(), Error>,
) -> Result<CheckSummary, Error> {
    check_rows_in::<Inari>(model, h, rows, opts, sink)
}

/// The smallest f64 interval containing `x` (the same interval for inari's).
fn outward<I: Ival>(x: &I) -> Inari {
    crate::scalar::iv(x.inf(), x.sup())
}

/// [`check_rows`] computed in the interval type `I` ([spec (12.0)](crate::spec::precision)): the exact
/// discrete flow, the retractions and the energies at `I`'s precision; each figure (a
/// distance, a defect, an energy error, an exact iterate) is then rounded outward to an f64
/// interval, where a distance below the f64 ends' own rounding stays narrow (f64 intervals
/// are relative).
///
/// # Containment
/// As [`check_trajectory`], row by row.
pub fn check_rows_in<I: Ival>(
    model: &Model,
    h: Option<f64>,
    rows: impl IntoIterator<Item = Result<(Option<f64>, Vec<f64>), Error>>,
    opts: &CheckOptions,
    mut sink: impl FnMut(RowVerdict) -> Result<(), Error>,
) -> Result<CheckSummary<I>, Error> {
    let rows = rows.into_iter();
    let n = model.n;
    let mut last_t = f64::NEG_INFINITY;
    let mut rows = rows.enumerate().map(|(k, row)| {
        let (t, row) = row?;
        if row.len() != n {
            return Err(Error::input_at(
                InputKind::Row {
                    row: k,
                    column: None,
                },
                format!(
                    "q_{k} has {} components, scene `{}` needs {n}",
                    row.len(),
                    model.name()
                ),
            ));
        }
        if let Some(column) = row.iter().position(|x| !x.is_finite()) {
            return Err(Error::input_at(
                InputKind::Row {
                    row: k,
                    column: Some(column),
                },
                format!("non-finite number in the trajectory (q_{k})"),
            ));
        }
        if let Some(t) = t {
            if !t.is_finite() || t <= last_t {
                return Err(Error::input_at(
                    InputKind::Times,
                    format!("t_{k} = {t}: times must be finite and strictly increasing"),
                ));
            }
            last_t = t;
        }
        Ok((t, row))
    });
    let too_short = || {
        Error::input_at(
            InputKind::Row {
                row: 1,
                column: None,
            },
            "a trajectory needs at least q_0 and q_1",
        )
    };
    let (t0, q0) = rows.next().ok_or_else(too_short)??;
    let (t1, q1) = rows.next().ok_or_else(too_short)??;
    // the step of the pair (q_k, q_{k+1}), and the span from t_k to t_{k+1}
    let step = |k: usize, a: Option<f64>, b: Option<f64>| match (h, a, b) {
        (Some(h), _, _) => Ok(h),
        (None, Some(a), Some(b)) => exact_step(k, a, b),
        _ => Err(Error::input_at(
            InputKind::Times,
            format!(
                "q_{k} or q_{} has no time: without `h`, every row needs one",
                k + 1
            ),
        )),
    };
    let span = |a: Option<f64>, b: Option<f64>| match (h, a, b) {
        (None, Some(a), Some(b)) => I::cst(b) - I::cst(a),
        _ => I::cst(h.unwrap_or(0.0)),
    };
    let pts = |v: &[f64]| v.iter().map(|x| I::cst(*x)).collect::<Vec<_>>();
    let h0 = step(0, t0, t1)?;
    let mut flow = ExactFlow::<I>::start_in(model, &q0, &q1, h0, &opts.flow)?;
    let mut max_distance = point(0.0);
    let mut max_defect: Option<Inari> = None;
    // Row k against the iterate k of the exact discrete flow, `dt` after the iterate k-1: the
    // distance, the iterate rounded outward to f64 and the iterate itself.
    let mut compare = |flow: &mut ExactFlow<I>,
                       q: &[f64],
                       dt: I|
     -> Result<(Inari, Iterate, IterateIn<I>), Error> {
        let exact = flow.next_iterate_in(dt)?;
        // the differences in I, each rounded outward to f64, then |.|_inf as in `distance`
        let d = q
            .iter()
            .zip(&exact.q)
            .map(|(x, y)| outward(&(I::cst(*x) - *y)).abs())
            .fold(point(0.0), |m, d| m.max(d));
        if !finite(d) {
            return Err(Error::refused(
                Reason::Unbounded,
                "distance enclosure not finite",
            ));
        }
        max_distance = max_distance.max(d);
        let wide = |x: &[I]| {
            x.iter()
                .map(|v| outward(v).into())
                .collect::<Vec<Interval>>()
        };
        let rounded = Iterate {
            k: exact.k,
            q: wide(&exact.q),
            v: wide(&exact.v),
            p: wide(&exact.p),
        };
        Ok((d, rounded, exact))
    };
    let first = compare(&mut flow, &q0, I::cst(h0))?;
    let e0 = if opts.pairs {
        Some(energy(model, &first.2.q, &first.2.v)?)
    } else {
        None
    };
    let first = (first.0, first.1);
    // The row waiting for its successor: its time, floats, distance and exact iterate.
    let mut pending = (t0, q0, first.0, first.1);
    let mut count = 1;
    for next in std::iter::once(Ok((t1, q1))).chain(rows) {
        let (tn, next) = next?;
        let (tk, qk, d, exact) = pending;
        let pair = match e0 {
            None => None,
            Some(e0) => {
                // (q_0, q_1) was retracted to start the flow: the same computation
                let r = if exact.k == 0 {
                    flow.retraction.clone()
                } else {
                    let hk = step(exact.k, tk, tn)?;
                    exact::retract_in::<I>(model, &qk, &next, hk, &opts.flow)?
                };
                let s: Vec<Inari> =
                    r.s.iter()
                        .map(|x| outward(&I::from_public(x.clone())))
                        .collect();
                let size = s.iter().fold(point(0.0), |m, x| m.max(x.abs()));
                max_defect = Some(max_defect.map_or(size, |m| m.max(size)));
                let v0: Vec<I> = r.v0.iter().map(|x| I::from_public(x.clone())).collect();
                Some(PairVerdict {
                    energy_error: outward(&(energy(model, &pts(&qk), &v0)? - e0)).into(),
                    defect: s.into_iter().map(Interval::from).collect(),
                })
            }
        };
        sink(RowVerdict {
            k: exact.k,
            distance: d.into(),
            pair,
            exact,
        })?;
        let (d, exact, _) = compare(&mut flow, &next, span(tk, tn))?;
        pending = (tn, next, d, exact);
        count += 1;
    }
    let (_, _, d, exact) = pending;
    sink(RowVerdict {
        k: exact.k,
        distance: d.into(),
        pair: None,
        exact,
    })?;
    Ok(CheckSummary {
        rows: count,
        max_distance: max_distance.into(),
        retraction: flow.retraction,
        max_defect: max_defect.map(Interval::from),
    })
}

/// The tolerances of a `check`: on the distance (`tol`, [spec (8.3)](crate::spec::oracle)) and on the pairs'
/// defects (`defect_tol`, [spec (8.5)](crate::spec::oracle)). `Tolerances::default()` (none) and the `with_*`
/// setters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Tolerances {
    /// Tolerance on `max_k |q_k - q^e_k|_inf` ([spec (8.3)](crate::spec::oracle)); `None`: not decided.
    pub tol: Option<f64>,
    /// Tolerance on `max_k |s_k|_inf`, the pairs' defects ([spec (8.5)](crate::spec::oracle)); `None`: not decided.
    pub defect_tol: Option<f64>,
}

impl Tolerances {
    /// With the tolerance `tol` on the distance.
    pub fn with_tol(mut self, tol: f64) -> Self {
        self.tol = Some(tol);
        self
    }
    /// With the tolerance `tol` on the pairs' defects.
    pub fn with_defect_tol(mut self, tol: f64) -> Self {
        self.defect_tol = Some(tol);
        self
    }

    /// `Error::Input` for a defect tolerance without the pair figures it is decided on.
    #[cfg(feature = "cli")]
    pub(crate) fn require_pairs(&self, pairs: bool) -> Result<(), Error> {
        if self.defect_tol.is_some() && !pairs {
            return Err(Error::input(
                "a defect tolerance needs the pairs' defects: drop --no-pairs (`pairs`: false)",
            ));
        }
        Ok(())
    }

    /// Whether a check passes both tolerances ([spec (8.3)](crate::spec::oracle), (8.5)): `true` when each given
    /// one is proved met (`sup <= tol`), `false` when one is proved exceeded (`inf > tol`),
    /// else undecided and refused (`Error::Uncertified`, exit 3). `max_defect` is the
    /// enclosure of `max_k |s_k|_inf` (`None` without pair figures).
    pub fn passes(
        &self,
        max_distance: Interval,
        max_defect: Option<Interval>,
    ) -> Result<bool, Error> {
        let distance = match self.tol {
            None => Ok(true),
            Some(t) => decide_one("distance", max_distance, t),
        };
        let defect = match (self.defect_tol, max_defect) {
            (None, _) => Ok(true),
            (Some(_), None) => Err(Error::input("a defect tolerance needs the pairs' defects")),
            (Some(d), Some(m)) => decide_one("defect", m, d),
        };
        match (distance, defect) {
            (Ok(false), _) | (_, Ok(false)) => Ok(false),
            (Err(e), _) | (_, Err(e)) => Err(e),
            (Ok(true), Ok(true)) => Ok(true),
        }
    }
}

/// `sup <= tol`: true; `inf > tol`: false; else undecided (exit 3).
pub(crate) fn decide_one(what: &str, x: Interval, tol: f64) -> Result<bool, Error> {
    if x.sup() <= tol {
        Ok(true)
    } else if x.inf() > tol {
        Ok(false)
    } else {
        Err(Error::uncertified(format!(
            "undecided: the certified {what} [{:e}, {:e}] straddles the tolerance {tol:e}",
            x.inf(),
            x.sup()
        )))
    }
}

/// Certified figures about one step `(q0, q1, q2)` of a candidate scheme.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct StepVerdict {
    /// `∋ |q2 - q^e_2|_inf`, `q^e_2 = q(2h)` of the exact discrete flow from `(q0, q1)`.
    pub distance: Interval,
    /// `∋ s` of `(q0, q1)`.
    pub defect: Vec<Interval>,
}

/// Check one step against the exact discrete flow ([spec Theorem 8.1](crate::spec::oracle) with N = 2).
///
/// # Containment
/// As [`check_trajectory`]: `|q2 - q(2h)|_inf ∈ distance`, `s ∈ defect`.
pub fn check_step(
    model: &Model,
    h: f64,
    q0: &[f64],
    q1: &[f64],
    q2: &[f64],
    opts: &FlowOptions,
) -> Result<StepVerdict, Error> {
    let o = CheckOptions {
        pairs: false,
        flow: opts.clone(),
    };
    let v = check_trajectory(model, h, &[q0, q1, q2], &o)?;
    Ok(StepVerdict {
        distance: v.distance[2],
        defect: v.exact.retraction.s.clone(),
    })
}
