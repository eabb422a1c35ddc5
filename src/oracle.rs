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

use crate::exact::{self, ExactTrajectory};
use crate::scalar::point;
use crate::tape::finite;
use crate::{Error, FlowOptions, Model};
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
        .ok_or_else(|| Error::uncertified("energy enclosure not finite"))
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
pub fn check_trajectory(
    model: &Model,
    h: f64,
    q: &[Vec<f64>],
    opts: &CheckOptions,
) -> Result<Verdict, Error> {
    let n = model.n;
    if q.len() < 2 {
        return Err(Error::input("a trajectory needs at least q_0 and q_1"));
    }
    if let Some(k) = q.iter().position(|qk| qk.len() != n) {
        return Err(Error::input(format!(
            "q_{k} has {} components, scene `{}` needs {n}",
            q[k].len(),
            model.name()
        )));
    }
    if q.iter().flatten().any(|x| !x.is_finite()) {
        return Err(Error::input("non-finite number in the trajectory"));
    }
    let pts = |v: &[f64]| v.iter().map(|x| point(*x)).collect::<Vec<_>>();
    let ex = exact::trajectory(model, &pts(&q[0]), &pts(&q[1]), h, q.len() - 1, &opts.flow)?;
    let distance: Vec<Interval> = q.iter().zip(&ex.q).map(|(a, b)| distance(a, b)).collect();
    let max_distance = distance.iter().fold(point(0.0), |m, d| m.max(*d));
    let (mut defect, mut energy_error) = (Vec::new(), Vec::new());
    if opts.pairs {
        let e0 = energy(model, &ex.q[0], &ex.v[0])?;
        for k in 0..q.len() - 1 {
            let r = exact::retract(model, &pts(&q[k]), &pts(&q[k + 1]), h, &opts.flow)?;
            energy_error.push(energy(model, &pts(&q[k]), &r.v0)? - e0);
            defect.push(r.s);
        }
    }
    if !finite(max_distance) {
        return Err(Error::uncertified("distance enclosure not finite"));
    }
    Ok(Verdict {
        distance,
        max_distance,
        defect,
        energy_error,
        exact: ex,
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
