//! The oracle: certified verdicts on candidate discrete trajectories produced by any float
//! integrator (spec/08-oracle.md). Small enough to use from a property test:
//!
//! ```no_run
//! # use dalembert::{AnyScene, Model, oracle};
//! let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
//! let q: Vec<Vec<f64>> = vec![vec![0.0; 3], vec![0.4, 0.4, 0.08], vec![0.76, 0.8, 0.29]];
//! let v = oracle::check_trajectory(&model, 0.5, &q, &oracle::CheckOptions::default()).unwrap();
//! assert!(v.max_distance.sup() < 1e-2); // proved: every q_k is within 1e-2 of the exact flow
//! ```

use crate::exact::{self, ExactFlow, ExactTrajectory, Iterate};
use crate::scalar::point;
use crate::tape::finite;
use crate::{Error, FlowOptions, Model, Reason};
use inari::Interval;

/// What to compute besides the distances.
#[derive(Clone, Debug)]
pub struct CheckOptions {
    /// Also certify, for every consecutive pair, its defect w.r.t. M_h^{e,nh} and the energy
    /// of the exact trajectory through it (one retraction per pair).
    pub pairs: bool,
    pub flow: FlowOptions,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            pairs: true,
            flow: FlowOptions::default(),
        }
    }
}

/// Certified figures about a candidate trajectory `q_0 .. q_N` (spec Theorem 8.1).
#[derive(Clone, Debug)]
pub struct Verdict {
    /// `distance[k] ∋ |q_k - q^e_k|_inf`, `q^e` the exact discrete flow from `(q_0, q_1)`.
    pub distance: Vec<Interval>,
    /// The hull of the distances: `max_k |q_k - q^e_k|_inf` lies in it.
    pub max_distance: Interval,
    /// `defect[k] ∋ s` of the pair `(q_k, q_{k+1})` (empty unless `pairs`).
    pub defect: Vec<Vec<Interval>>,
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
        .map(|(x, y)| (point(*x) - *y).abs())
        .fold(point(0.0), |m, d| m.max(d))
}

/// `E_L(q, v)` enclosed over the boxes (the energy of the exact trajectory through `(q, v)`).
pub(crate) fn energy(model: &Model, q: &[Interval], v: &[Interval]) -> Result<Interval, Error> {
    let x: Vec<Interval> = q.iter().chain(v).copied().collect();
    model
        .energy
        .eval_checked(&x)
        .map(|e| e[0])
        .ok_or_else(|| Error::refused(Reason::Unbounded, "energy enclosure not finite"))
}

/// Check a candidate trajectory of step `h` against the exact discrete flow.
///
/// # Containment
/// If `Ok(v)`: for every k, `|q_k - q^e_k|_inf ∈ v.distance[k]`, where `q^e_k = q(kh)` on the
/// trajectory from `q_0` with `u_0` the unique solution of spec eq. (6.2) for `(q_0, q_1)` in
/// the Krawczyk box (the exact discrete flow through `(q_0, q_1 + N(q_1) s)`); so
/// `v.max_distance.sup() <= e` proves "every iterate is within e of the exact discrete
/// flow". The pair figures are proved likewise (Theorems 6.1, 6.2). `Error::Input` for
/// malformed candidates, `Error::Uncertified` when the oracle itself cannot conclude.
/// The rows of [`check_each`], collected.
pub fn check_trajectory(
    model: &Model,
    h: f64,
    q: &[Vec<f64>],
    opts: &CheckOptions,
) -> Result<Verdict, Error> {
    let mut distance = Vec::with_capacity(q.len());
    let (mut defect, mut energy_error) = (Vec::new(), Vec::new());
    let (mut eq, mut ev, mut ep) = (Vec::new(), Vec::new(), Vec::new());
    let summary = check_each(model, h, q.iter().map(|r| Ok(r.clone())), opts, |row| {
        distance.push(row.distance);
        if let Some(pair) = row.pair {
            defect.push(pair.defect);
            energy_error.push(pair.energy_error);
        }
        eq.push(row.exact.q);
        ev.push(row.exact.v);
        ep.push(row.exact.p);
        Ok(())
    })?;
    Ok(Verdict {
        distance,
        max_distance: summary.max_distance,
        defect,
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
#[derive(Clone, Debug)]
pub struct PairVerdict {
    /// `∋ s` of the pair, its defect w.r.t. M_h^{e,nh}.
    pub defect: Vec<Interval>,
    /// `∋ E_L(q_k, R^{e-}(q_k, q_{k+1})) - E_L(q_0, R^{e-}(q_0, q_1))`.
    pub energy_error: Interval,
}

/// Certified figures about one row `q_k` of a candidate trajectory (spec Theorem 8.1).
#[derive(Clone, Debug)]
pub struct RowVerdict {
    pub k: usize,
    /// `∋ |q_k - q^e_k|_inf`.
    pub distance: Interval,
    /// The pair `(q_k, q_{k+1})`: `None` on the last row and unless `CheckOptions::pairs`.
    pub pair: Option<PairVerdict>,
    /// The iterate `q^e_k` of the exact discrete flow that `q_k` was compared with.
    pub exact: Iterate,
}

/// What [`check_each`] returns once every row is checked.
#[derive(Clone, Debug)]
pub struct CheckSummary {
    /// The number of rows `N + 1`.
    pub rows: usize,
    /// `∋ max_k |q_k - q^e_k|_inf`.
    pub max_distance: Interval,
    /// The retraction of `(q_0, q_1)` the exact discrete flow starts from.
    pub retraction: crate::exact::Retraction,
}

/// [`check_trajectory`] one row at a time, in memory independent of the number of rows:
/// `rows` is read as needed, and `sink` is given each row's verdict as soon as it is
/// proved (row k once `q_{k+1}` is read, for its pair figures). An error from `rows` or
/// `sink` stops the check and is returned as it is.
///
/// # Containment
/// As [`check_trajectory`], row by row.
pub fn check_each(
    model: &Model,
    h: f64,
    rows: impl IntoIterator<Item = Result<Vec<f64>, Error>>,
    opts: &CheckOptions,
    mut sink: impl FnMut(RowVerdict) -> Result<(), Error>,
) -> Result<CheckSummary, Error> {
    let n = model.n;
    let mut rows = rows.into_iter().enumerate().map(|(k, row)| {
        let row = row?;
        if row.len() != n {
            return Err(Error::input(format!(
                "q_{k} has {} components, scene `{}` needs {n}",
                row.len(),
                model.name()
            )));
        }
        if row.iter().any(|x| !x.is_finite()) {
            return Err(Error::input(format!(
                "non-finite number in the trajectory (q_{k})"
            )));
        }
        Ok(row)
    });
    let too_short = || Error::input("a trajectory needs at least q_0 and q_1");
    let q0 = rows.next().ok_or_else(too_short)??;
    let q1 = rows.next().ok_or_else(too_short)??;
    let pts = |v: &[f64]| v.iter().map(|x| point(*x)).collect::<Vec<_>>();
    let mut flow = ExactFlow::start(model, &pts(&q0), &pts(&q1), h, &opts.flow)?;
    let mut max_distance = point(0.0);
    // Row k against the iterate k of the exact discrete flow.
    let mut compare = |flow: &mut ExactFlow, q: &[f64]| -> Result<(Interval, Iterate), Error> {
        let exact = flow.next_iterate()?;
        let d = distance(q, &exact.q);
        if !finite(d) {
            return Err(Error::refused(
                Reason::Unbounded,
                "distance enclosure not finite",
            ));
        }
        max_distance = max_distance.max(d);
        Ok((d, exact))
    };
    let first = compare(&mut flow, &q0)?;
    let e0 = if opts.pairs {
        Some(energy(model, &first.1.q, &first.1.v)?)
    } else {
        None
    };
    // The row waiting for its successor: its floats, distance and exact iterate.
    let mut pending = (q0, first.0, first.1);
    let mut count = 1;
    for next in std::iter::once(Ok(q1)).chain(rows) {
        let next = next?;
        let (qk, d, exact) = pending;
        let pair = match e0 {
            None => None,
            Some(e0) => {
                // (q_0, q_1) was retracted to start the flow: the same computation
                let r = if exact.k == 0 {
                    flow.retraction.clone()
                } else {
                    exact::retract(model, &pts(&qk), &pts(&next), h, &opts.flow)?
                };
                Some(PairVerdict {
                    energy_error: energy(model, &pts(&qk), &r.v0)? - e0,
                    defect: r.s,
                })
            }
        };
        sink(RowVerdict {
            k: exact.k,
            distance: d,
            pair,
            exact,
        })?;
        let (d, exact) = compare(&mut flow, &next)?;
        pending = (next, d, exact);
        count += 1;
    }
    let (_, d, exact) = pending;
    sink(RowVerdict {
        k: exact.k,
        distance: d,
        pair: None,
        exact,
    })?;
    Ok(CheckSummary {
        rows: count,
        max_distance,
        retraction: flow.retraction,
    })
}

/// Certified figures about one step `(q0, q1, q2)` of a candidate scheme.
#[derive(Clone, Debug)]
pub struct StepVerdict {
    /// `∋ |q2 - q^e_2|_inf`, `q^e_2 = q(2h)` of the exact discrete flow from `(q0, q1)`.
    pub distance: Interval,
    /// `∋ s` of `(q0, q1)`.
    pub defect: Vec<Interval>,
}

/// Check one step against the exact discrete flow (spec Theorem 8.1 with N = 2).
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
    let v = check_trajectory(model, h, &[q0.to_vec(), q1.to_vec(), q2.to_vec()], &o)?;
    Ok(StepVerdict {
        distance: v.distance[2],
        defect: v.exact.retraction.s.clone(),
    })
}
