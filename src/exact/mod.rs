//! The exact discrete objects of the paper, certified ([spec/06-exact-discrete.md](crate::spec::exact_discrete)):
//! the nonholonomic exponential map, the exact retractions R^{e-}, R^{e+} and the defect of
//! membership in M_h^{e,nh} (Krawczyk), the exact discrete flow and Legendre transforms.

mod krawczyk;

use crate::enclosure::linalg::{self, IMat};
use crate::enclosure::{
    float_flow_counted, float_flow_tail_counted, flow_set, flow_set_c1, flow_set_span, FlowOptions,
    Ival, LohnerSet,
};
use crate::interval::{unwrap, wrap, wrap_rows};
use crate::model::Model;
use crate::newton::{self, NewtonFailure, NewtonOptions, NewtonOutcome};
use crate::Interval;
use crate::{Error, Reason};
use inari::Interval as Inari;
use nalgebra::{DMatrix, DVector};

pub use krawczyk::krawczyk;

/// The nonholonomic exponential map with its derivative ([spec eq. (6.1)](crate::spec::exact_discrete)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Exponential {
    /// `q(h)` for every initial condition in the input boxes.
    pub q1: Vec<Interval>,
    /// `qd(h)`.
    pub v1: Vec<Interval>,
    /// `D q(h) / D u0`, n x (n - k), over the whole input box.
    pub dq_du: Vec<Vec<Interval>>,
    /// The state set at time h (to carry a trajectory further); not serialized.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub set: LohnerSet,
}

/// `exp_h(q0, u0) = (q0, q(h))` and `D_{u0} q(h)`.
///
/// # Containment
/// For every `q0` in the box `q0` and `u0` in the box `u0`, the exact `q(h)` and `qd(h)` of the
/// trajectory with `q(0) = q0`, `qd(0) = E(q0)^T u0` lie in `q1`, `v1`, and
/// `D q(h)/D u0 (q0, u0)` lies in `dq_du` ([spec Theorem 5.2](crate::spec::enclosure)). `Error::Uncertified` otherwise.
pub fn exponential(
    model: &Model,
    q0: &[Interval],
    u0: &[Interval],
    h: f64,
    opts: &FlowOptions,
) -> Result<Exponential, Error> {
    let n = model.n;
    let x0: Vec<Inari> = q0.iter().chain(u0).map(|x| Inari::from(*x)).collect();
    let (set, jac, _) = flow_set_c1(&model.dynamics, LohnerSet::from_box(&x0), h, opts)?;
    let hull = set.hull();
    let v1 = set_velocity(model, &set)?;
    let dq_du = jac
        .rows()
        .take(n)
        .map(|row| wrap(row[n..].to_vec()))
        .collect();
    Ok(Exponential {
        q1: wrap(hull[..n].to_vec()),
        v1: wrap(v1),
        dq_du,
        set,
    })
}

fn velocity<I: Ival>(model: &Model, x: &[I]) -> Result<Vec<I>, Error> {
    model
        .velocity
        .eval_checked(x)
        .ok_or_else(|| Error::refused(Reason::Unbounded, "velocity enclosure is not finite"))
}

/// Velocities over a state set, by the centred form ([spec eq. (5.12)](crate::spec::enclosure)).
fn set_velocity<I: Ival>(model: &Model, set: &LohnerSet<I>) -> Result<Vec<I>, Error> {
    set.image(&model.velocity_jac)
        .ok_or_else(|| Error::refused(Reason::Unbounded, "velocity enclosure is not finite"))
}

/// `N(q) = mu(q)^T`, n x k, enclosed over a box ([spec eq. (6.2)](crate::spec::exact_discrete)).
pub fn normal_matrix(model: &Model, q: &[Interval]) -> Result<Vec<Vec<Interval>>, Error> {
    Ok(wrap_rows(normal_rows(model, &unwrap(q))?))
}

/// [`normal_matrix`] in the computation's intervals.
fn normal_rows<I: Ival>(model: &Model, q: &[I]) -> Result<Vec<Vec<I>>, Error> {
    let (n, k) = (model.n, model.k);
    let mu = model
        .constraints
        .eval_checked(q)
        .ok_or_else(|| Error::refused(Reason::Unbounded, "constraint covectors not finite"))?;
    Ok((0..n)
        .map(|i| (0..k).map(|a| mu[a * n + i]).collect())
        .collect())
}

/// The exact retraction at a pair ([spec eqs. (6.2)-(6.4)](crate::spec::exact_discrete)).
///
/// Computed in the interval type `I` (inari's, 53 bits, unless [`retract_in`] chose
/// another): the fields are `I`'s answer intervals ([`Ival::Public`]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(serialize = "I::Public: serde::Serialize"))
)]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Retraction<I: Ival = Inari> {
    /// Quasi-velocities at Q0: `R^{e-}` in the basis of D.
    pub u0: Vec<I::Public>,
    /// The defect s in R^k: (Q0, Q1) is in M_h^{e,nh} iff s = 0.
    pub s: Vec<I::Public>,
    /// `v0 = E(Q0)^T u0 = R^{e-}_{h,nh}(Q0, Q1)`.
    pub v0: Vec<I::Public>,
    /// `v1 = qd(h) = R^{e+}_{h,nh}`.
    pub v1: Vec<I::Public>,
    /// `q(h) = Q1 + N(Q1) s`, the point of M_h^{e,nh} over Q0 nearest Q1 along N.
    pub q1: Vec<I::Public>,
    /// The state set at time h (carries the trajectory on); not serialized.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub set: LohnerSet<I>,
}

/// As answers' intervals.
fn public<I: Ival>(x: Vec<I>) -> Vec<I::Public> {
    x.into_iter().map(I::public).collect()
}

/// From answers' intervals.
fn private<I: Ival>(x: &[I::Public]) -> Vec<I> {
    x.iter().map(|p| I::from_public(p.clone())).collect()
}

impl Retraction {
    /// False when the defect enclosure excludes 0: (Q0, Q1) is proved off M_h^{e,nh}.
    pub fn possibly_member(&self) -> bool {
        self.s.iter().all(|x| x.contains(0.0))
    }
}

/// Solve `q(h; Q0, u0) = Q1 + N(Q1) s` for `(u0, s)` ([spec eq. (6.2)](crate::spec::exact_discrete)).
///
/// # Containment
/// For every `Q0`, `Q1` in the input boxes there is exactly one solution `(u0, s)` in a box
/// that was proved to contain it (Krawczyk, [spec Theorem 6.1](crate::spec::exact_discrete)), and it lies in
/// `(u0, s)`; `v0`, `v1`, `q1` enclose `R^{e-}`, `R^{e+}` and `q(h)` of that solution.
/// `Error::Uncertified` when Newton does not converge, the Jacobian is singular, or the
/// Krawczyk test fails (e.g. h too large for uniqueness); nothing unproved is returned.
///
/// # Example
/// ```
/// use dalembert::exact::retract;
/// use dalembert::{AnyScene, FlowOptions, Interval, Model};
/// let model = Model::new(&AnyScene::new("particle", &[])?)?;
/// let pts = |v: &[f64]| v.iter().map(|&x| Interval::point(x)).collect::<Vec<_>>();
/// let (q0, q1) = (pts(&[0.0, 0.0, 0.0]), pts(&[0.4, 0.4, 0.0]));
/// let r = retract(&model, &q0, &q1, 0.5, &FlowOptions::default())?;
/// // the defect s excludes 0: (Q0, Q1) is proved off M_h^{e,nh} (here s is about 0.073)
/// assert!(!r.possibly_member() && r.s[0].inf() > 0.07);
/// // N(Q1) = (-y1, 0, 1) leaves y alone, and y(h) = u0_2 h: u0_2 = 0.4 / 0.5
/// assert!(r.u0[1].contains(0.8) && r.q1[1].contains(0.4));
/// # Ok::<(), dalembert::Error>(())
/// ```
pub fn retract(
    model: &Model,
    q0: &[Interval],
    q1: &[Interval],
    h: f64,
    opts: &FlowOptions,
) -> Result<Retraction, Error> {
    retract_box_in(model, &unwrap(q0), &unwrap(q1), h, opts)
}

/// [`retract`] at the exact f64 points `q0`, `q1`, computed in the interval type `I` (e.g.
/// [`crate::precision::dd::DdInterval`], about 106 bits; [spec/12-precision.md](crate::spec::precision)): the same
/// Newton guess, Krawczyk test and flows, at `I`'s precision.
///
/// # Containment
/// As [`retract`], whatever `I` ([spec Theorem 6.1](crate::spec::exact_discrete)).
pub fn retract_in<I: Ival>(
    model: &Model,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    opts: &FlowOptions,
) -> Result<Retraction<I>, Error> {
    retract_box_in(model, &points::<I>(q0), &points::<I>(q1), h, opts)
}

/// The exact f64 values as degenerate intervals of `I`.
fn points<I: Ival>(x: &[f64]) -> Vec<I> {
    x.iter().map(|v| I::cst(*v)).collect()
}

/// [`retract_in`] for every pair in the boxes `q0`, `q1` of `I`'s precision (e.g. decimals read
/// as exact decimals, [spec (12.0.5)](crate::spec::precision)); what every retraction runs.
///
/// # Containment
/// As [`retract`], for every `(Q0, Q1)` in the boxes.
pub fn retract_box_in<I: Ival>(
    model: &Model,
    q0: &[I],
    q1: &[I],
    h: f64,
    opts: &FlowOptions,
) -> Result<Retraction<I>, Error> {
    check_pair(model, q0, q1, h)?;
    let (n, k) = (model.n, model.k);
    let m = n - k;
    let nq1 = IMat::from_rows(&normal_rows(model, q1)?);
    let guess = newton_guess(model, q0, q1, h, opts);
    // past the deadline or the work limit the Newton guess stops early: say so rather
    // than why it stopped
    opts.check_budget()?;
    let (guess, jac, residual) = guess?;
    let c = jac
        .try_inverse()
        .ok_or_else(|| Error::uncertified("singular Jacobian of the shooting map"))?;
    let z_pt = refine_centre(model, q0, q1, &nq1, h, opts, &c, &guess);
    // The state set at time h from the last Krawczyk box (it contains the answer's).
    let last_set = std::cell::RefCell::new(None);
    let x0_of = |u: &[I]| q0.iter().chain(u).copied().collect::<Vec<_>>();
    // (12.0.9) at double-double, the boxes' derivatives in f64 and a second, recentred test
    let loose = double_double::<I>();
    // The validated flows of all Krawczyk boxes share KRAWCZYK_WORK * max_taylor_steps steps, so
    // that a hard pair costs a bounded amount of work whatever the inflations do.
    let work = std::cell::Cell::new(0usize);
    let work_budget = KRAWCZYK_WORK * opts.max_taylor_steps;
    // One C^1 flow of the box X = (Q0, U) with the point (Q0, u~) of the centre z~ marked
    // (spec eq. (6.3)): G(z~; Q0, Q1) = q(h; Q0, u~) - Q1 - N(Q1) s~ from the marked
    // subset, DG = [D_u q(h) | -N(Q1)] over the box, and the set at h.
    let shoot = |zt: &[I::Pt], u: &[I], first: bool| -> Result<Shot<I>, Error> {
        let left = work_budget.saturating_sub(work.get());
        if left == 0 {
            return Err(Error::over_limit(
                crate::Limit::RetractionWork,
                format!(
                    "the Krawczyk boxes' flows spent their work budget ({work_budget} \
                     validated steps, {KRAWCZYK_WORK} FlowOptions::max_taylor_steps)"
                ),
            ));
        }
        // no reorganisation (5.10'): the set at h keeps the initial box's coordinates in
        // its propagated part, so that it can be restricted to K(X) below (spec (6.4'))
        let capped = FlowOptions {
            max_taylor_steps: left.min(opts.max_taylor_steps),
            reorganise: false,
            box_series_in_f64: loose,
            level: (loose && first).then_some(LOOSE_LEVEL),
            ..opts.clone()
        };
        let centre: Vec<I::Pt> = q0
            .iter()
            .map(|x| x.mid_pt())
            .chain(zt[..m].iter().copied())
            .collect();
        let at: Vec<I> = zt.iter().map(|x| I::pt(*x)).collect();
        let set = LohnerSet::with_subset(&centre, &x0_of(u), &x0_of(&at[..m]));
        // the derivative held to the level the flow holds its state to (12.0.9), (12.0.10)
        let flown = if loose {
            crate::enclosure::flow_set_c1_loose(
                &model.dynamics,
                set,
                h,
                &capped,
                capped.level::<I>(),
            )
        } else {
            flow_set_c1(&model.dynamics, set, h, &capped)
        };
        // a failed flow is charged all the steps it was allowed
        work.set(
            work.get()
                + flown
                    .as_ref()
                    .map_or(capped.max_taylor_steps, |f| f.2.steps),
        );
        let (set, jac, _) = flown?;
        let qh = set.sub_hull().ok_or_else(|| {
            Error::internal_at(crate::Invariant::Missing, "the marked point was lost")
        })?;
        let ns = linalg::mul_vec(&nq1, &at[m..]);
        let g = (0..n).map(|i| qh[i] - q1[i] - ns[i]).collect();
        let dg = (0..n)
            .map(|i| {
                jac[i][n..]
                    .iter()
                    .copied()
                    .chain(nq1[i].iter().map(|x| -*x))
                    .collect()
            })
            .collect();
        Ok((g, dg, set))
    };
    let gd = |z: &[I]| -> Result<(Vec<I>, Vec<Vec<I>>), Error> {
        let (g, dg, set) = shoot(&z_pt, &z[..m], true)?;
        *last_set.borrow_mut() = Some((z_pt.clone(), set));
        Ok((g, dg))
    };
    // first radius: twice the float Newton correction still left at the guess, and what
    // the rounding of G(z~) (a few ulps of q(h)) moves K(X) by through C: a first box
    // without it is too small for the defect s whenever s is near 0 (the particle's pair
    // of the README took two box flows)
    let ulps = DVector::from_iterator(n, q1.iter().map(|x| 4.0 * f64::EPSILON * x.mag()));
    let rad = (&c * residual).abs() * 2.0 + c.abs() * ulps;
    let rad: Vec<f64> = rad.iter().copied().collect();
    let scale = guess[..m].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut z = krawczyk(&z_pt, &c, &rad, scale, gd)?;
    if loose {
        // (12.0.9) the test again around the midpoint of K(X), over K(X) itself
        let mid: Vec<I::Pt> = z.iter().map(|x| x.mid_pt()).collect();
        let (g, dg, set) = shoot(&mid, &z[..m], false)?;
        z = krawczyk::recentred(&mid, &c, &g, &dg, z)?;
        *last_set.borrow_mut() = Some((mid, set));
    }
    let (u0, s) = (z[..m].to_vec(), z[m..].to_vec());
    let v0 = velocity(model, &x0_of(&u0))?;
    let (centre, mut set) = last_set.into_inner().ok_or_else(|| {
        Error::internal_at(
            crate::Invariant::Missing,
            "no state set from the Krawczyk box",
        )
    })?;
    set.sub = None;
    // (6.4') The set at h is the flow of the whole box X; the solution's u0 lies in
    // K(X) ⊂ X. Without reorganisations the states from x0 = centre + a lie in
    // m + C a + B [r] (spec (5.10')), so the propagated part may be restricted to
    // a in K(X) - centre (with 0, which the set's invariant keeps); (12.0.9) at
    // double-double, around the midpoint of u0 instead of the box's centre.
    let moved = if loose {
        let mid: Vec<I::Pt> = u0.iter().map(|x| x.mid_pt()).collect();
        let mut shift = vec![I::zero(); n + m];
        let mut r0 = set.r0.clone();
        for i in 0..m {
            shift[n + i] = I::pt(mid[i]) - I::pt(centre[i]);
            r0[n + i] = (u0[i] - I::pt(mid[i])).convex_hull(I::zero());
        }
        set.moved(&shift, r0)
    } else {
        None
    };
    match moved {
        Some(moved) => set = moved,
        None => {
            for (i, u) in u0.iter().enumerate() {
                let a = (*u - I::pt(centre[i])).convex_hull(I::zero());
                set.r0[n + i] = set.r0[n + i].intersection(a);
            }
        }
    }
    // (6.4'') Above 106 bits the float centre is about 2^-53 from u0, which the restriction
    // keeps in the set's width; the set at h is then the flow of the box (Q0, u0) itself,
    // centred in it (one flow more, and an enclosure of the same states). At 106 bits the
    // set was moved instead (12.0.9).
    if I::eps() < f64::EPSILON && !loose {
        set = flow_set(&model.dynamics, LohnerSet::from_box(&x0_of(&u0)), h, opts)?.0;
    }
    let hull = set.hull();
    let v1 = set_velocity(model, &set)?;
    // q(h) is enclosed twice: by the flow and by Q1 + N(Q1) s (spec eq. (6.4)).
    let ns = linalg::mul_vec(&nq1, &s);
    let q_at_h = intersect(
        &hull[..n],
        &(0..n).map(|i| q1[i] + ns[i]).collect::<Vec<_>>(),
    )?;
    Ok(Retraction {
        u0: public(u0),
        s: public(s),
        v0: public(v0),
        v1: public(v1),
        q1: public(q_at_h),
        set,
    })
}

/// Whether `I` is double-double (106 bits), where the retraction runs (12.0.9).
fn double_double<I: Ival>() -> bool {
    I::eps() < f64::EPSILON && I::eps() >= f64::EPSILON * f64::EPSILON
}

/// What one flow of a Krawczyk box gives: `[G]` at the marked centre, `[DG]` over the box
/// (rows), and the set at `h`.
type Shot<I> = (Vec<I>, Vec<Vec<I>>, LohnerSet<I>);

/// (12.0.9) The level `2^-64` the first Krawczyk box's derivative is held to at
/// double-double: its `K(X)` comes out about that wide, and the second test narrows it.
const LOOSE_LEVEL: f64 = 1.0 / 18_446_744_073_709_551_616.0;

/// Most Newton steps of [`refine_centre`].
const CENTRE_STEPS: usize = 8;

/// The centre `z~` of the Krawczyk box at `I`'s precision ([spec (12.0.7)](crate::spec::precision)): the float
/// guess itself up to 106 bits; above, the float guess moved by Newton steps
/// `z <- mid(z - C [G](z))` with `[G](z) = q(h; Q0, u) - Q1 - N(Q1) s` from a validated flow
/// of the point `(Q0, u)` at `I`'s precision. A float guess is about `2^-52 |z|` from the
/// zero, and `K(X)` keeps `|I - C DG|` times that distance, about `2^-104 |z|`: enough at
/// 106 bits, not beyond. Each step shrinks the distance by about `|I - C DG|` (C is a float
/// inverse); they stop once the correction is below `eps / 2^-52` of `max |z|`, after
/// [`CENTRE_STEPS`], or at a flow that fails (then the last centre serves). A choice only:
/// the Krawczyk test decides, whatever the centre.
#[allow(clippy::too_many_arguments)]
fn refine_centre<I: Ival>(
    model: &Model,
    q0: &[I],
    q1: &[I],
    nq1: &IMat<I>,
    h: f64,
    opts: &FlowOptions,
    c: &DMatrix<f64>,
    guess: &[f64],
) -> Vec<I::Pt> {
    let mut z: Vec<I::Pt> = guess.iter().map(|x| I::pt_of(*x)).collect();
    if I::eps() >= f64::EPSILON * f64::EPSILON {
        return z;
    }
    let (n, m) = (model.n, model.n - model.k);
    let ci = linalg::imat::<I>(c);
    let scale = guess.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let goal = I::eps() / f64::EPSILON * scale;
    for _ in 0..CENTRE_STEPS {
        let zi: Vec<I> = z.iter().map(|p| I::pt(*p)).collect();
        let x0: Vec<I> = q0.iter().chain(&zi[..m]).copied().collect();
        let Ok((set, _)) = flow_set(&model.dynamics, LohnerSet::from_box(&x0), h, opts) else {
            break;
        };
        let qh = set.hull();
        let ns = linalg::mul_vec(nq1, &zi[m..]);
        let g: Vec<I> = (0..n).map(|i| qh[i] - q1[i] - ns[i]).collect();
        let corr = linalg::mul_vec(&ci, &g);
        if !corr.iter().all(|x| x.is_finite()) {
            break;
        }
        let size = corr.iter().fold(0.0f64, |a, x| a.max(x.mag()));
        z = (0..n).map(|i| (zi[i] - corr[i]).mid_pt()).collect();
        if size <= goal {
            break;
        }
    }
    z
}

/// Two enclosures of one object must intersect ([spec 0.4](crate::spec::overview#04-self-checks-vnode-lp-and-capd-style)); their intersection encloses it.
pub fn intersect_checked(a: &[Interval], b: &[Interval]) -> Result<Vec<Interval>, Error> {
    Ok(wrap(intersect(&unwrap(a), &unwrap(b))?))
}

/// [`intersect_checked`] in the computation's intervals.
fn intersect<I: Ival>(a: &[I], b: &[I]) -> Result<Vec<I>, Error> {
    let r: Vec<I> = a.iter().zip(b).map(|(x, y)| x.intersection(*y)).collect();
    if r.iter().any(|x| x.is_empty()) {
        // both enclose the same exact value: disjoint only through a fault of the crate
        return Err(Error::internal_at(
            crate::Invariant::DisjointEnclosures,
            "self-check failed: two enclosures of the same quantity are disjoint",
        ));
    }
    Ok(r)
}

fn check_pair<I: Ival>(model: &Model, q0: &[I], q1: &[I], h: f64) -> Result<(), Error> {
    let n = model.n;
    if q0.len() != n || q1.len() != n {
        return Err(Error::input(format!(
            "q0 and q1 need {n} components for scene `{}`",
            model.name()
        )));
    }
    if !q0.iter().chain(q1).all(|x| x.is_finite()) {
        return Err(Error::input("non-finite number in q0 or q1"));
    }
    if !h.is_finite() || h <= 0.0 {
        return Err(Error::input(format!("h must be finite and > 0 (got {h})")));
    }
    let f64s = |x: &[I]| {
        x.iter()
            .map(|v| crate::scalar::iv(v.inf(), v.sup()))
            .collect::<Vec<_>>()
    };
    model.check_at(&f64s(q0))?;
    model.check_at(&f64s(q1))
}

/// The float Newton's point, the float Jacobian of G there and the float residual G.
type NewtonGuess = (Vec<f64>, DMatrix<f64>, DVector<f64>);

/// Work bound of the retraction's float Newton, in multiples of `FlowOptions::max_taylor_steps`.
const NEWTON_WORK: usize = 4;

/// Work bound of the validated flows of all Krawczyk boxes of one retraction, in multiples
/// of `FlowOptions::max_taylor_steps` ([spec (6.3)](crate::spec::exact_discrete)).
const KRAWCZYK_WORK: usize = 3;

/// A float Newton iteration for (u0, s), started from the least-squares velocity
/// `E(Q0)^T u ~ (Q1 - Q0)/h`, s = 0, on a float Taylor integration of the flow and its
/// variational equation in u0. It only chooses the centre of the Krawczyk box and the
/// matrix C; returns the point, the float Jacobian of G there and the float residual G.
fn newton_guess<I: Ival>(
    model: &Model,
    q0: &[I],
    q1: &[I],
    h: f64,
    opts: &FlowOptions,
) -> Result<NewtonGuess, Error> {
    let (n, k) = (model.n, model.k);
    let m = n - k;
    let mid = |x: &[I]| x.iter().map(|v| v.mid()).collect::<Vec<f64>>();
    let (a, b) = (mid(q0), mid(q1));
    let not_converged =
        || Error::uncertified("Newton iteration for the retraction did not converge");
    // E(Q0) rows from the velocity tape: v = E^T u is linear in u.
    let basis: Vec<Vec<f64>> = (0..m)
        .map(|j| {
            let x: Vec<f64> = a
                .iter()
                .copied()
                .chain((0..m).map(|i| if i == j { 1.0 } else { 0.0 }))
                .collect();
            model.velocity.eval::<f64>(&x)
        })
        .collect();
    let e = DMatrix::from_fn(m, n, |i, j| basis[i][j]);
    let rhs = DVector::from_fn(n, |i, _| (b[i] - a[i]) / h);
    let u = (&e * e.transpose())
        .lu()
        .solve(&(&e * rhs))
        .ok_or_else(|| Error::refused(Reason::Undefined, "basis of D is degenerate at q0"))?;
    let mu = model.constraints.eval::<f64>(&b);
    // The total number of float Taylor steps over all evaluations is bounded by
    // NEWTON_WORK * max_taylor_steps, so that no input makes the retraction slow (a fuzz finding:
    // a far sleigh pair took 13 s in 180 evaluations of up to max_taylor_steps steps each).
    let work = std::cell::Cell::new(0usize);
    let budget = NEWTON_WORK * opts.max_taylor_steps;
    // Work left for one more float integration, or None when the budget is spent.
    let capped = || -> Option<FlowOptions> {
        opts.check_budget().ok()?;
        let left = budget.checked_sub(work.get()).filter(|l| *l > 0)?;
        Some(FlowOptions {
            max_taylor_steps: left.min(opts.max_taylor_steps),
            ..opts.clone()
        })
    };
    let x0_of = |z: &DVector<f64>| -> Vec<f64> {
        a.iter().copied().chain(z.iter().take(m).copied()).collect()
    };
    let g_of = |x: &[f64], z: &DVector<f64>| {
        DVector::from_fn(n, |i, _| {
            x[i] - b[i] - (0..k).map(|c| mu[c * n + i] * z[m + c]).sum::<f64>()
        })
    };
    // Charge the steps of one float integration to the budget (all of it on failure).
    let spend = |steps: Option<usize>| work.set(steps.map_or(budget, |s| work.get() + s));
    // G(z) and DG(z) by the flow and its variational equation in u0
    let shoot = |z: &DVector<f64>| -> Option<(DVector<f64>, DMatrix<f64>)> {
        let flown = float_flow_tail_counted(&model.dynamics, &x0_of(z), h, &capped()?);
        spend(flown.as_ref().map(|f| f.2));
        let (x, jx, _) = flown?;
        let j = DMatrix::from_fn(n, n, |i, c| {
            if c < m {
                jx[(i, c)]
            } else {
                -mu[(c - m) * n + i]
            }
        });
        Some((g_of(&x, z), j))
    };
    // G(z) alone, by the flow of the state
    let residual = |z: &DVector<f64>| -> Option<DVector<f64>> {
        let flown = float_flow_counted(&model.dynamics, &x0_of(z), h, &capped()?);
        spend(flown.as_ref().map(|f| f.1));
        Some(g_of(&flown?.0, z))
    };
    let mut z = DVector::from_fn(n, |i, _| if i < m { u[i] } else { 0.0 });
    let nan = || {
        (
            DVector::from_element(n, f64::NAN),
            DMatrix::from_element(n, n, f64::NAN),
        )
    };
    // Converged at the noise level of the float flow; a stalled iteration still gives a
    // usable centre: the Krawczyk test, not Newton, decides (spec Theorem 6.1).
    let noise = b.iter().chain(&a).fold(1.0f64, |m, x| m.max(x.abs())) * 16.0 * f64::EPSILON;
    // Each evaluation is a whole float integration: bound the work (at most 20 iterations
    // of at most 9 evaluations), so that no input makes the retraction slow.
    let nopts = NewtonOptions {
        tol: noise,
        max_iter: 20,
        max_backtracks: 8,
    };
    // Fast path: one Newton step from the guess, checked by the flow of the state alone
    // (a third of the work of a shot with the Jacobian). When the shooting map is nearly
    // linear near the guess (for the particle it is linear in (u0, s)), this is the whole
    // iteration, and DG at the guess serves for C.
    let first = shoot(&z);
    if let Some((g0, j0)) = &first {
        if let Some(dz) = j0.clone().lu().solve(&(-g0)) {
            let z1 = &z + dz;
            if let Some(g1) = residual(&z1).filter(|g| g.amax() <= noise) {
                return Ok((z1.iter().copied().collect(), j0.clone(), g1));
            }
        }
    }
    // Otherwise the damped Newton iteration (spec eq. (7.6)) from the guess. The last
    // evaluation is kept: Newton ends at a point it has evaluated, whose Jacobian is the
    // one wanted.
    let last = std::cell::RefCell::new(Some((z.clone(), first)));
    let remembered_shoot = |z: &DVector<f64>| {
        let r = match last.borrow_mut().take() {
            Some((at, r)) if at == *z => r,
            _ => shoot(z),
        };
        *last.borrow_mut() = Some((z.clone(), r.clone()));
        r
    };
    let outcome = newton::solve(&mut z, |z| remembered_shoot(z).unwrap_or_else(nan), &nopts);
    let answer = match outcome {
        NewtonOutcome::Converged { .. }
        | NewtonOutcome::Failed(NewtonFailure::Diverged | NewtonFailure::IterationLimit)
            if z.iter().all(|x| x.is_finite()) =>
        {
            remembered_shoot(&z)
                .ok_or_else(not_converged)
                .map(|(g, j)| (z.iter().copied().collect(), j, g))
        }
        NewtonOutcome::Failed(NewtonFailure::SingularJacobian) => {
            Err(Error::uncertified("singular Jacobian of the shooting map"))
        }
        NewtonOutcome::Failed(f) => Err(Error::uncertified(format!(
            "Newton iteration for the retraction failed: {f}"
        ))),
        NewtonOutcome::Converged { .. } => Err(not_converged()),
    };
    // a failure once the work budget is spent is the budget's, not the proof's
    answer.map_err(|e| {
        if work.get() >= budget {
            Error::over_limit(
                crate::Limit::RetractionWork,
                format!(
                    "the retraction's Newton iteration spent its work budget ({budget} float \
                     Taylor steps, 4 FlowOptions::max_taylor_steps): {}",
                    e.message()
                ),
            )
        } else {
            e
        }
    })
}

/// The exact discrete flow and Legendre transforms at a pair ([spec eqs. (6.5)-(6.7)](crate::spec::exact_discrete)).
///
/// Computed in the interval type `I` as [`Retraction`] is.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(serialize = "I::Public: serde::Serialize"))
)]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct ExactStep<I: Ival = Inari> {
    /// The retraction of `(Q0, Q1)` the step starts from ([spec eqs. (6.2)-(6.4)](crate::spec::exact_discrete)).
    pub retraction: Retraction<I>,
    /// `q(h)`, the point of M_h^{e,nh}.
    pub q1: Vec<I::Public>,
    /// `q(2h)`: the exact discrete flow maps (q0, q1) to (q1, q2).
    pub q2: Vec<I::Public>,
    /// `F^-_{h,nh} l = (<FL(v0), e_a(Q0)>)_a`.
    pub p_minus: Vec<I::Public>,
    /// `F^+_{h,nh} l = (<FL(v1), e_a(q1)>)_a`.
    pub p_plus: Vec<I::Public>,
}

/// One step of the exact discrete flow, with the Legendre transforms.
///
/// # Containment
/// For every `(Q0, Q1)` in the boxes, with `(u0, s)` the unique solution of [spec eq. (6.2)](crate::spec::exact_discrete)
/// in the Krawczyk box: `q1 ∋ q(h)`, `q2 ∋ q(2h)`, `p_minus ∋ F^- l`, `p_plus ∋ F^+ l`
/// ([spec Theorem 6.2](crate::spec::exact_discrete)).
///
/// # Example
/// ```
/// use dalembert::exact::step;
/// use dalembert::{AnyScene, FlowOptions, Interval, Model};
/// let model = Model::new(&AnyScene::new("particle", &[])?)?;
/// let pts = |v: &[f64]| v.iter().map(|&x| Interval::point(x)).collect::<Vec<_>>();
/// let (q0, q1) = (pts(&[0.0, 0.0, 0.0]), pts(&[0.4, 0.4, 0.08]));
/// let s = step(&model, &q0, &q1, 0.5, &FlowOptions::default())?;
/// // on the particle y(t) = u_2 t and p_2 = yd = u_2 = 0.8 on the whole trajectory
/// assert!(s.q2[1].contains(0.8));
/// assert!(s.p_minus[1].contains(0.8) && s.p_plus[1].contains(0.8));
/// assert!(s.q2.iter().all(|x| x.wid() < 1e-12));
/// # Ok::<(), dalembert::Error>(())
/// ```
pub fn step(
    model: &Model,
    q0: &[Interval],
    q1: &[Interval],
    h: f64,
    opts: &FlowOptions,
) -> Result<ExactStep, Error> {
    step_box_in(model, &unwrap(q0), &unwrap(q1), h, opts)
}

/// [`step`] at the exact f64 points `q0`, `q1`, computed in the interval type `I` (as
/// [`retract_in`]).
///
/// # Containment
/// As [`step`], whatever `I` ([spec Theorem 6.2](crate::spec::exact_discrete)).
pub fn step_in<I: Ival>(
    model: &Model,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    opts: &FlowOptions,
) -> Result<ExactStep<I>, Error> {
    step_box_in(model, &points::<I>(q0), &points::<I>(q1), h, opts)
}

/// [`step_in`] for every pair in the boxes `q0`, `q1` (as [`retract_box_in`]).
///
/// # Containment
/// As [`step`], for every `(Q0, Q1)` in the boxes.
pub fn step_box_in<I: Ival>(
    model: &Model,
    q0: &[I],
    q1: &[I],
    h: f64,
    opts: &FlowOptions,
) -> Result<ExactStep<I>, Error> {
    let n = model.n;
    let r = retract_box_in(model, q0, q1, h, opts)?;
    let p_minus = momentum_in(model, q0, &private::<I>(&r.v0))?;
    let p_plus = momentum_in(model, &private::<I>(&r.q1), &private::<I>(&r.v1))?;
    let second = FlowOptions {
        box_series_in_f64: double_double::<I>(),
        ..opts.clone()
    };
    let (set2, _) = flow_set(&model.dynamics, r.set.clone(), h, &second)?;
    let q2 = public(set2.hull()[..n].to_vec());
    Ok(ExactStep {
        q1: r.q1.clone(),
        q2,
        p_minus: public(p_minus),
        p_plus: public(p_plus),
        retraction: r,
    })
}

/// `p_a = <M(q) v + A(q), e_a(q)>` over boxes ([spec eq. (4.8)](crate::spec::dynamics); `A = 0` unless the scene has
/// a one-form).
pub fn momentum(model: &Model, q: &[Interval], v: &[Interval]) -> Result<Vec<Interval>, Error> {
    Ok(wrap(momentum_in(model, &unwrap(q), &unwrap(v))?))
}

/// [`momentum`] in the computation's intervals.
fn momentum_in<I: Ival>(model: &Model, q: &[I], v: &[I]) -> Result<Vec<I>, Error> {
    let x: Vec<I> = q.iter().chain(v).copied().collect();
    model
        .momentum_tape()
        .eval_checked(&x)
        .ok_or_else(|| Error::refused(Reason::Unbounded, "momentum enclosure not finite"))
}

/// The exact discrete trajectory `q_0 .. q_N` from `(Q0, Q1)` ([spec eq. (6.6)](crate::spec::exact_discrete)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct ExactTrajectory {
    /// The retraction of `(Q0, Q1)`: its `u0` box fixes the trajectory ([spec eq. (6.2)](crate::spec::exact_discrete)).
    pub retraction: Retraction,
    /// `q_k ∋ q(k h)`, k = 0..=N.
    pub q: Vec<Vec<Interval>>,
    /// `v_k ∋ qd(k h)`.
    pub v: Vec<Vec<Interval>>,
    /// `p_k ∋ <FL(qd(kh)), e_a(q(kh))>`: both F^+ of the pair ending at k and F^- of the
    /// pair starting at k (momentum matching, paper eq. (momemtummatch)).
    pub p: Vec<Vec<Interval>>,
}

/// Iterate the exact discrete flow N - 1 times from `(Q0, Q1)`.
///
/// The exact discrete flow reproduces the continuous flow (paper eq. (exactflow)): the
/// iterates are `q_k = q(kh)` of the one trajectory through `Q0` with `u0 = R^{e-}(Q0, Q1)`.
/// The certificate is carried as that trajectory's Lohner set, so correlations between
/// consecutive iterates are kept and widths grow like the flow's, not like a box iteration's.
/// Collects [`ExactFlow`]'s iterates.
///
/// # Containment
/// `q[k] ∋ q(kh)`, `v[k] ∋ qd(kh)`, `p[k] ∋` the D*-momentum at `kh`, for the trajectory
/// of the unique solution of (6.2) in the Krawczyk box ([spec Theorem 6.3](crate::spec::exact_discrete)).
pub fn trajectory(
    model: &Model,
    q0: &[Interval],
    q1: &[Interval],
    h: f64,
    steps: usize,
    opts: &FlowOptions,
) -> Result<ExactTrajectory, Error> {
    let mut flow = ExactFlow::start(model, q0, q1, h, opts)?;
    let (mut q, mut v, mut p) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..=steps {
        let it = flow.next_iterate()?;
        q.push(it.q);
        v.push(it.v);
        p.push(it.p);
    }
    Ok(ExactTrajectory {
        retraction: flow.retraction,
        q,
        v,
        p,
    })
}

/// One iterate of the exact discrete flow: `q ∋ q(kh)`, `v ∋ qd(kh)`, `p ∋` the
/// D*-momentum at `kh` (as the rows of [`ExactTrajectory`]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Iterate {
    /// The index `k` of the iterate (0 for `Q0`).
    pub k: usize,
    /// Contains `q(kh)` (with non-uniform steps, `q(t_k - t_0)`); for `k = 1`, the
    /// intersection of the flow's box with `Q1 + N(Q1) s` ([spec eq. (6.4)](crate::spec::exact_discrete)).
    pub q: Vec<Interval>,
    /// Contains `qd(kh)`; for `k = 0`, `R^{e-}(Q0, Q1)` of the retraction.
    pub v: Vec<Interval>,
    /// Contains the D*-momentum `(<FL(qd(kh)), e_a(q(kh))>)_a` ([spec eq. (4.8)](crate::spec::dynamics)).
    pub p: Vec<Interval>,
}

/// The exact discrete flow from `(Q0, Q1)` one iterate at a time, in memory independent of
/// the number of iterates ([spec eq. (6.6)](crate::spec::exact_discrete)): the state is the trajectory's Lohner set at
/// the last iterate. [`trajectory`] and the oracle's streaming check
/// ([`crate::oracle::check_rows`]) are built on it.
///
/// # Containment
/// As [`trajectory`]: the `k`-th call of [`ExactFlow::next_iterate`] (from 0) encloses
/// `q(kh)`, `qd(kh)` and the momentum there, for the trajectory of the unique solution of
/// (6.2) in the Krawczyk box.
pub struct ExactFlow<'m, I: Ival = Inari> {
    model: &'m Model,
    h: f64,
    opts: FlowOptions,
    set: LohnerSet<I>,
    k: usize,
    q0: Vec<I>,
    /// The retraction of `(Q0, Q1)` the trajectory starts from.
    pub retraction: Retraction<I>,
}

/// A summary: the scene, the step, the next iterate's index and the retraction.
impl<I: Ival> std::fmt::Debug for ExactFlow<'_, I> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExactFlow")
            .field("scene", &self.model.name())
            .field("h", &self.h)
            .field("k", &self.k)
            .field("retraction", &self.retraction)
            .finish_non_exhaustive()
    }
}

/// An iterate of [`ExactFlow`] in the computation's intervals (as [`Iterate`]).
#[derive(Clone, Debug, PartialEq)]
pub struct IterateIn<I: Ival> {
    /// The index `k` of the iterate (0 for `Q0`).
    pub k: usize,
    /// Contains `q(kh)` (as [`Iterate::q`]).
    pub q: Vec<I>,
    /// Contains `qd(kh)` (as [`Iterate::v`]).
    pub v: Vec<I>,
    /// Contains the D*-momentum (as [`Iterate::p`]).
    pub p: Vec<I>,
}

impl<'m> ExactFlow<'m> {
    /// Retract `(Q0, Q1)` ([spec eq. (6.2)](crate::spec::exact_discrete)); nothing is flown yet.
    pub fn start(
        model: &'m Model,
        q0: &[Interval],
        q1: &[Interval],
        h: f64,
        opts: &FlowOptions,
    ) -> Result<Self, Error> {
        ExactFlow::start_box(model, unwrap(q0), &unwrap(q1), h, opts)
    }

    /// The iterate `k` (0 for `Q0`, 1 for `q(h)`, then one flow of the set by `h` each).
    pub fn next_iterate(&mut self) -> Result<Iterate, Error> {
        self.next_iterate_after(Interval::point(self.h))
    }

    /// Non-uniform steps ([spec eq. (8.4)](crate::spec::oracle)): as [`ExactFlow::next_iterate`], the set flown
    /// from the last iterate over every span of time in `dt` (the exact `t_k - t_{k-1}`
    /// enclosed) instead of `h`: the `k`-th iterate, `k >= 2`, encloses `q(t_k - t_0)` when
    /// the spans given enclose `t_2 - t_1, .., t_k - t_{k-1}` and `h = t_1 - t_0`. The
    /// iterates 0 and 1 are `Q0` and `q(h)`: `dt` is not used for them.
    pub fn next_iterate_after(&mut self, dt: Interval) -> Result<Iterate, Error> {
        let it = self.next_iterate_in(dt.into())?;
        Ok(Iterate {
            k: it.k,
            q: wrap(it.q),
            v: wrap(it.v),
            p: wrap(it.p),
        })
    }
}

impl<'m, I: Ival> ExactFlow<'m, I> {
    /// [`ExactFlow::start`] at the exact f64 points `q0`, `q1`, computed in the interval type
    /// `I` ([spec (12.0)](crate::spec::precision)).
    pub fn start_in(
        model: &'m Model,
        q0: &[f64],
        q1: &[f64],
        h: f64,
        opts: &FlowOptions,
    ) -> Result<Self, Error> {
        ExactFlow::start_box(model, points::<I>(q0), &points::<I>(q1), h, opts)
    }

    fn start_box(
        model: &'m Model,
        q0: Vec<I>,
        q1: &[I],
        h: f64,
        opts: &FlowOptions,
    ) -> Result<Self, Error> {
        let retraction = retract_box_in(model, &q0, q1, h, opts)?;
        Ok(ExactFlow {
            model,
            h,
            opts: opts.clone(),
            set: retraction.set.clone(),
            k: 0,
            q0,
            retraction,
        })
    }

    /// [`ExactFlow::next_iterate_after`] in the computation's intervals (`dt` encloses the
    /// span of time).
    pub fn next_iterate_in(&mut self, dt: I) -> Result<IterateIn<I>, Error> {
        let (model, n, k) = (self.model, self.model.n, self.k);
        let (q, v) = match k {
            0 => (self.q0.clone(), private::<I>(&self.retraction.v0)),
            _ => {
                if k > 1 {
                    // on an error the set stays as it was: a later call tries again
                    self.set = flow_set_span(&model.dynamics, self.set.clone(), dt, &self.opts)?.0;
                }
                let hull = self.set.hull();
                let q = if k == 1 {
                    intersect(&hull[..n], &private::<I>(&self.retraction.q1))?
                } else {
                    hull[..n].to_vec()
                };
                (q, set_velocity(model, &self.set)?)
            }
        };
        let p = momentum_in(model, &q, &v)?;
        self.k += 1;
        Ok(IterateIn { k, q, v, p })
    }
}

/// The exact discrete Lagrangian `l^{e,h}_{d,nh}(Q0, Q1) = int_0^h L(q(t), qd(t)) dt` along
/// the trajectory of [`retract`] (paper section 6; [spec eq. (6.8)](crate::spec::exact_discrete)).
///
/// # Containment
/// The returned interval contains the action over `[0, h]` of the trajectory from `Q0` with
/// `u0` the unique solution of (6.2) in the Krawczyk box, for every `(Q0, Q1)` in the boxes.
/// On M_h^{e,nh} (defect 0) this is the paper's exact discrete Lagrangian; off it, it is the
/// action of the trajectory from Q0 to `Q1 + N(Q1) s`.
pub fn discrete_lagrangian(
    model: &Model,
    q0: &[Interval],
    q1: &[Interval],
    h: f64,
    opts: &FlowOptions,
) -> Result<(Retraction, Interval), Error> {
    let (r, l) = discrete_lagrangian_box_in(model, &unwrap(q0), &unwrap(q1), h, opts)?;
    Ok((r, l.into()))
}

/// [`discrete_lagrangian`] at the exact f64 points `q0`, `q1`, computed in the interval type
/// `I` (as [`retract_in`]).
///
/// # Containment
/// As [`discrete_lagrangian`], whatever `I` ([spec eq. (6.8)](crate::spec::exact_discrete)).
pub fn discrete_lagrangian_in<I: Ival>(
    model: &Model,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    opts: &FlowOptions,
) -> Result<(Retraction<I>, I::Public), Error> {
    let (r, l) = discrete_lagrangian_box_in(model, &points::<I>(q0), &points::<I>(q1), h, opts)?;
    Ok((r, l.public()))
}

/// [`discrete_lagrangian_in`] for every pair in the boxes `q0`, `q1` (as [`retract_box_in`]).
///
/// # Containment
/// As [`discrete_lagrangian`], for every `(Q0, Q1)` in the boxes.
pub fn discrete_lagrangian_box_in<I: Ival>(
    model: &Model,
    q0: &[I],
    q1: &[I],
    h: f64,
    opts: &FlowOptions,
) -> Result<(Retraction<I>, I), Error> {
    let r = retract_box_in(model, q0, q1, h, opts)?;
    let x0: Vec<I> = q0
        .iter()
        .copied()
        .chain(private::<I>(&r.u0))
        .chain(std::iter::once(I::zero()))
        .collect();
    let (set, _) = flow_set(model.action_system(), LohnerSet::from_box(&x0), h, opts)?;
    let l = set.hull()[x0.len() - 1];
    if !l.is_finite() {
        return Err(Error::refused(
            Reason::Unbounded,
            "action enclosure not finite",
        ));
    }
    Ok((r, l))
}
