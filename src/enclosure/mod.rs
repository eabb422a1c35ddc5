//! The validated integrator: interval Taylor series + a priori enclosure (Picard-Lindelof
//! in the high-order form of Corliss and Rihm) + Lohner's QR control of the wrapping effect
//! (spec/05-enclosure.md, eqs. (5.1)-(5.10)).

pub mod linalg;

use crate::model::{Model, System};
use crate::scalar::{iv, point};
use crate::tape::{finite, Coef};
use crate::Error;
use inari::Interval;
use linalg::IMat;
use nalgebra::DMatrix;

/// A set `{ m + B r : r in [r] } ∩ boxed` (Lohner's parallelepiped and a box, both
/// enclosures of the same states; spec eq. (5.1)): `m` and `B` are exact f64 data, `[r]` an
/// interval vector that contains 0.
#[derive(Clone, Debug)]
pub struct LohnerSet {
    pub m: Vec<f64>,
    pub b: DMatrix<f64>,
    pub r: Vec<Interval>,
    pub boxed: Vec<Interval>,
}

impl LohnerSet {
    /// The single point `x` (exact f64 values).
    pub fn point(x: &[f64]) -> Self {
        LohnerSet {
            m: x.to_vec(),
            b: DMatrix::identity(x.len(), x.len()),
            r: vec![point(0.0); x.len()],
            boxed: x.iter().map(|v| point(*v)).collect(),
        }
    }
    /// A box, as centre plus radius.
    pub fn from_box(x: &[Interval]) -> Self {
        let m: Vec<f64> = x.iter().map(|v| v.mid()).collect();
        let r = x.iter().zip(&m).map(|(v, c)| *v - point(*c)).collect();
        LohnerSet {
            m,
            b: DMatrix::identity(x.len(), x.len()),
            r,
            boxed: x.to_vec(),
        }
    }
    /// An interval box containing the set (spec eq. (5.2)): the parallelepiped's hull
    /// intersected with the box (both contain the set, so the intersection is not empty).
    pub fn hull(&self) -> Vec<Interval> {
        let br = linalg::mul_vec(&linalg::imat(&self.b), &self.r);
        self.m
            .iter()
            .zip(br)
            .zip(&self.boxed)
            .map(|((c, x), bx)| {
                let p = point(*c) + x;
                let both = p.intersection(*bx);
                if both.is_empty() {
                    p
                } else {
                    both
                }
            })
            .collect()
    }

    /// An enclosure of `{ G(x) : x in the set }` by the centred form
    /// `G(m) + (DG([X]) B) [r]`, intersected with `G([X])` (spec eq. (5.12)); `g_jac` is the
    /// tape of `(G, DG)` (`G` then `DG` row-major). `None` if an evaluation is not proved.
    pub fn image(&self, g_jac: &crate::tape::Tape) -> Option<Vec<Interval>> {
        let d = self.m.len();
        let k = g_jac.n_outputs() / (d + 1);
        let at_m = g_jac.eval_checked(&self.m.iter().map(|x| point(*x)).collect::<Vec<_>>())?;
        let over = g_jac.eval_checked(&self.hull())?;
        let dg: IMat = (0..k)
            .map(|i| over[k + i * d..k + (i + 1) * d].to_vec())
            .collect();
        let lin = linalg::mul_vec(&linalg::mul(&dg, &linalg::imat(&self.b)), &self.r);
        let out: Vec<Interval> = (0..k)
            .map(|i| {
                let c = at_m[i] + lin[i];
                let both = c.intersection(over[i]);
                if both.is_empty() {
                    c
                } else {
                    both
                }
            })
            .collect();
        out.iter().all(|x| finite(*x)).then_some(out)
    }
}

/// Settings of the validated integrator. `order = 0` chooses automatically.
#[derive(Clone, Debug)]
pub struct FlowOptions {
    pub order: usize,
    /// Refuse (exit 3) rather than take more steps than this.
    pub max_steps: usize,
    /// `0` (default): step sizes chosen by spec eq. (5.8). `> 0`: every step tries this size
    /// (rounded down to three significant bits) without the width tolerances of (5.8); a
    /// step whose a priori enclosure fails is retried smaller as in (5.8) (spec eq. (5.13)).
    pub step: f64,
    /// Told the fraction of the time span done after each accepted step (for a progress
    /// display; it sees nothing else and cannot change the result).
    pub progress: Option<Progress>,
}

/// A progress callback (see [`FlowOptions::progress`]).
#[derive(Clone)]
pub struct Progress(pub std::sync::Arc<dyn Fn(f64) + Send + Sync>);

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Progress")
    }
}

impl Default for FlowOptions {
    fn default() -> Self {
        FlowOptions {
            order: 0,
            max_steps: 20_000,
            step: 0.0,
            progress: None,
        }
    }
}

/// What the integrator did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlowStats {
    pub order: usize,
    pub steps: usize,
    /// Steps tried and rejected (a priori enclosure or remainder not good enough).
    pub rejected: usize,
    pub h_min: f64,
    pub h_max: f64,
}

/// The certified state at time t.
#[derive(Clone, Debug)]
pub struct FlowEnclosure {
    pub q: Vec<Interval>,
    pub u: Vec<Interval>,
    pub v: Vec<Interval>,
    pub stats: FlowStats,
}

/// The order used when none is given: about -ln(2^-53)/2, where the work per unit time of
/// a Taylor method of order p at double precision is smallest (spec eq. (5.8)).
pub const DEFAULT_ORDER: usize = 20;

/// Enclosure of the exact nonholonomic state at time `t` from `q(0) = q`,
/// `qd(0) = sum_a u_a e_a(q)`.
///
/// # Containment
/// For the exact f64 inputs, the returned `q`, `u`, `v` contain the exact `q(t)`, the
/// quasi-velocities `u(t)` and `qd(t) = E(q(t))^T u(t)` of the trajectory (spec Theorem 5.1);
/// the trajectory is proved to exist on `[0, t]`. Fails with `Error::Input` for malformed
/// input and `Error::Uncertified` when a step cannot be proved (singular data, blow-up,
/// too many steps): never with a box that was not proved.
pub fn flow(
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Result<FlowEnclosure, Error> {
    check_state(model, q, u)?;
    if !t.is_finite() || t < 0.0 {
        return Err(Error::input(format!(
            "time must be finite and >= 0 (got {t})"
        )));
    }
    let x: Vec<f64> = q.iter().chain(u).copied().collect();
    let (set, stats) = flow_set(&model.dynamics, LohnerSet::point(&x), t, opts)?;
    finish(model, &set, stats)
}

/// Validate dimensions and finiteness of a state.
pub fn check_state(model: &Model, q: &[f64], u: &[f64]) -> Result<(), Error> {
    let (n, m) = (model.n, model.n - model.k);
    if q.len() != n {
        return Err(Error::input(format!(
            "q has {} components, scene `{}` needs {n}",
            q.len(),
            model.scene.name()
        )));
    }
    if u.len() != m {
        return Err(Error::input(format!(
            "u has {} components, scene `{}` needs {m}",
            u.len(),
            model.scene.name()
        )));
    }
    if let Some(x) = q.iter().chain(u).find(|x| !x.is_finite()) {
        return Err(Error::input(format!("non-finite number {x} in the state")));
    }
    Ok(())
}

fn finish(model: &Model, set: &LohnerSet, stats: FlowStats) -> Result<FlowEnclosure, Error> {
    let x = set.hull();
    let v = set
        .image(&model.velocity_jac)
        .ok_or_else(|| Error::uncertified("velocity enclosure is not finite"))?;
    Ok(FlowEnclosure {
        q: x[..model.n].to_vec(),
        u: x[model.n..].to_vec(),
        v,
        stats,
    })
}

enum StepFail {
    /// The a priori enclosure was not proved for this h: try a smaller one.
    Shrink,
    /// Nothing more can be proved from here.
    Fatal(String),
}

/// Carry a set through time `t` (spec Theorem 5.1): the returned set contains the exact
/// state at time t of every solution starting in `set`.
pub fn flow_set(
    sys: &System,
    set: LohnerSet,
    t: f64,
    opts: &FlowOptions,
) -> Result<(LohnerSet, FlowStats), Error> {
    let (set, _, stats) = flow_set_general(sys, set, t, opts, false)?;
    Ok((set, stats))
}

/// As [`flow_set`], and also an interval matrix containing the derivative `D x(t) / D x(0)`
/// at every initial point of `set` (spec Theorem 5.2).
pub fn flow_set_c1(
    sys: &System,
    set: LohnerSet,
    t: f64,
    opts: &FlowOptions,
) -> Result<(LohnerSet, IMat, FlowStats), Error> {
    let (set, jac, stats) = flow_set_general(sys, set, t, opts, true)?;
    let d = set.m.len();
    Ok((set, jac.unwrap_or_else(|| linalg::identity(d)), stats))
}

fn flow_set_general(
    sys: &System,
    mut set: LohnerSet,
    t: f64,
    opts: &FlowOptions,
    c1: bool,
) -> Result<(LohnerSet, Option<IMat>, FlowStats), Error> {
    let mut total_jac: Option<IMat> = None;
    let p = if opts.order == 0 {
        DEFAULT_ORDER
    } else {
        opts.order
    };
    let mut stats = FlowStats {
        order: p,
        steps: 0,
        rejected: 0,
        h_min: f64::INFINITY,
        h_max: 0.0,
    };
    let total = point(t);
    // Time done so far, exactly enclosed (spec eq. (5.7)).
    let mut done = point(0.0);
    // Memory of rejected steps: the estimate (5.8) is scaled by this factor.
    let mut factor = 1.0f64;
    while done.sup() < t {
        if stats.steps >= opts.max_steps {
            return Err(too_many(opts.max_steps, t));
        }
        let rem = (total - done).intersection(iv(0.0, f64::MAX));
        // A fixed step (spec eq. (5.13)) or the rule of (5.8).
        let fixed = opts.step > 0.0;
        let mut h = if fixed {
            round_step(opts.step)
        } else {
            round_step(suggest_step(sys, &set, p)? * factor)
        }
        .min(rem.inf());
        let mut last = h >= rem.inf();
        let mut tries = 0;
        loop {
            let hi = if last { rem } else { point(h) };
            match lohner_step(sys, &set, hi, p, !fixed && tries < 12, c1) {
                Ok((next, step_jac)) => {
                    set = next;
                    if let Some(j) = step_jac {
                        total_jac = Some(match total_jac {
                            None => j,
                            Some(acc) => linalg::mul(&j, &acc),
                        });
                        if !total_jac.as_ref().is_some_and(linalg::all_finite) {
                            return Err(Error::uncertified(
                                "derivative enclosure became unbounded",
                            ));
                        }
                    }
                    factor = (factor * 1.1).min(1.0);
                    done = if last { total } else { done + hi };
                    stats.steps += 1;
                    stats.h_min = stats.h_min.min(hi.inf());
                    stats.h_max = stats.h_max.max(hi.sup());
                    if let Some(p) = &opts.progress {
                        (p.0)(if last { 1.0 } else { done.sup() / t });
                    }
                    // refuse early when the steps now taken would not reach t in time
                    let left = (t - done.sup()) / hi.sup();
                    if !last && stats.steps as f64 + left > 4.0 * opts.max_steps as f64 {
                        return Err(too_many(opts.max_steps, t));
                    }
                    break;
                }
                Err(StepFail::Fatal(why)) => return Err(Error::uncertified(why)),
                Err(StepFail::Shrink) => {
                    tries += 1;
                    stats.rejected += 1;
                    factor *= 0.7;
                    h = round_step(h * 0.7);
                    last = false;
                    if tries > 60 || h.is_nan() || h <= 0.0 || h < t * 1e-14 {
                        return Err(Error::uncertified(format!(
                            "no a priori enclosure could be proved near t = {} (step size underflow)",
                            done.sup()
                        )));
                    }
                }
            }
        }
    }
    if stats.steps == 0 {
        stats.h_min = 0.0;
    }
    Ok((set, total_jac, stats))
}

/// Number of time slices over which the remainder's coefficient is enclosed (spec (5.5)).
const SLICES: usize = 8;

/// Largest accepted width of the Lagrange remainder, relative to the state's size.
const REMAINDER_TOL: f64 = f64::EPSILON;

fn too_many(max: usize, t: f64) -> Error {
    Error::uncertified(format!(
        "more than {max} steps would be needed to reach t = {t}"
    ))
}

/// Round a positive step down to three significant bits (`{1, 1.25, 1.5, 1.75} * 2^e`), so
/// that sums of steps stay exact in f64 for long (spec eq. (5.7)).
fn round_step(h: f64) -> f64 {
    if h.is_nan() || h <= 0.0 || !h.is_finite() {
        return h;
    }
    let base = 2f64.powf(h.log2().floor());
    let quarters = (h / base * 4.0).floor().clamp(4.0, 7.0);
    base * quarters / 4.0
}

/// Step size from the Taylor coefficients at the centre (spec eq. (5.8)): the last two
/// terms of the series should be below the rounding level of the state.
fn suggest_step(sys: &System, set: &LohnerSet, p: usize) -> Result<f64, Error> {
    let c = sys
        .field
        .ode_taylor::<f64>(&set.m, p)
        .ok_or_else(|| Error::uncertified("vector field not defined at the state"))?;
    Ok(step_size(&c, p, &set.m))
}

/// The step-size rule of spec eq. (5.8) from float Taylor coefficients at the state `x`.
fn step_size(c: &[Vec<f64>], p: usize, x: &[f64]) -> f64 {
    let scale = x.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    let tol = scale * f64::EPSILON * 0.25;
    let mut h = f64::INFINITY;
    for (i, ci) in c.iter().enumerate().skip(1) {
        let norm = ci.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if norm > 0.0 {
            // no term larger than the state (no cancellation in the sum) ...
            h = h.min((scale / norm).powf(1.0 / i as f64));
            // ... and the last two terms below the rounding level
            if i + 1 >= p {
                h = h.min((tol / norm).powf(1.0 / i as f64));
            }
        }
    }
    round_step(h.min(f64::MAX))
}

/// A float Taylor integration of `x' = F(x)` and of its variational equation over time `t`:
/// `(x(t), D x(t)/D x0)` approximately. Not rigorous: used only to choose points (the Newton
/// guesses of the retraction); `None` on non-finite values or too many steps.
pub fn float_flow_c1(
    sys: &System,
    x0: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, DMatrix<f64>)> {
    float_flow_c1_counted(sys, x0, t, opts).map(|(x, j, _)| (x, j))
}

/// As [`float_flow_c1`], also returning the number of Taylor steps taken (the work, for
/// callers that bound their total work).
pub fn float_flow_c1_counted(
    sys: &System,
    x0: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
    let d = x0.len();
    let p = if opts.order == 0 {
        DEFAULT_ORDER
    } else {
        opts.order
    };
    let mut x = x0.to_vec();
    let mut jac = DMatrix::<f64>::identity(d, d);
    let mut done = 0.0;
    for steps in 0..opts.max_steps {
        if done >= t {
            return Some((x, jac, steps));
        }
        let mut xv = x.clone();
        for i in 0..d {
            xv.extend((0..d).map(|j| if i == j { 1.0 } else { 0.0 }));
        }
        let c = sys.field_var.ode_taylor::<f64>(&xv, p)?;
        // The step rule (5.8) on the state AND the variational series: the Jacobian's series
        // can have a smaller radius of convergence than the state's (e.g. the particle with
        // u1 = 0: x(t) stays 0 while D x / D u1 = asinh(u2 t) / u2 is singular at t = i/u2).
        let h = step_size(&c, p, &xv).min(t - done);
        let poly = |i: usize| c.iter().rev().fold(0.0, |acc, ck| acc * h + ck[i]);
        x = (0..d).map(poly).collect();
        let v = DMatrix::from_fn(d, d, |i, j| poly(d + i * d + j));
        jac = v * jac;
        done = if h >= t - done { t } else { done + h };
        if !x.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    None
}

/// Horner's scheme in intervals: encloses `sum_i c_i t^i` for every `t` in `h` and every
/// choice of coefficients in the enclosures `c_i`.
fn horner(c: &[Interval], h: Interval) -> Interval {
    c.iter().rev().fold(point(0.0), |acc, ci| acc * h + *ci)
}

/// One step of the method (spec eqs. (5.3)-(5.6), (5.9)-(5.10)).
fn lohner_step(
    sys: &System,
    set: &LohnerSet,
    h: Interval,
    p: usize,
    strict: bool,
    c1: bool,
) -> Result<(LohnerSet, Option<IMat>), StepFail> {
    let d = set.m.len();
    let fatal = |s: &str| StepFail::Fatal(s.to_string());
    if !set.r.iter().all(|r| r.contains(0.0)) {
        return Err(fatal("internal invariant broken: 0 not in r"));
    }
    let xbox = set.hull();
    // (5.3) Taylor coefficients at the centre.
    let centre: Vec<Interval> = set.m.iter().map(|x| point(*x)).collect();
    let c = sys
        .field
        .ode_taylor(&centre, p)
        .ok_or_else(|| fatal("vector field not defined at the state"))?;
    // (5.6) coefficients of the solution and of the variational equation over the box. For
    // a point set (r = 0) without C^1 output, the box is the centre and J is not needed
    // (J B r = 0): the centre's coefficients serve, with J = 0.
    let point_set = !c1 && set.r.iter().all(|r| r.is_exact_zero());
    let cv = if point_set {
        c.iter()
            .map(|ck| {
                let mut v = ck.clone();
                v.resize(d + d * d, point(0.0));
                v
            })
            .collect()
    } else {
        let mut xv = xbox.clone();
        for i in 0..d {
            xv.extend((0..d).map(|j| point(if i == j { 1.0 } else { 0.0 })));
        }
        sys.field_var.ode_taylor(&xv, p).ok_or(StepFail::Shrink)?
    };
    // (5.4) a priori enclosure on [0, h]: Z = sum_{i<p} Tb_i [0,h]^i + T_p(Y) [0,h]^p in Y.
    let h0 = iv(0.0, h.sup());
    let coef = |k: usize, i: usize| cv[k][i];
    let guess: Vec<Interval> = (0..d)
        .map(|i| horner(&(0..=p).map(|k| coef(k, i)).collect::<Vec<_>>(), h0))
        .collect();
    let mut y = inflate(&guess);
    let mut remainder = None;
    for _ in 0..4 {
        let ty = match sys.field.ode_taylor(&y, p + 1) {
            Some(ty) => ty,
            None => return Err(StepFail::Shrink),
        };
        let z: Vec<Interval> = (0..d)
            .map(|i| {
                let mut cs: Vec<Interval> = (0..p).map(|k| coef(k, i)).collect();
                cs.push(ty[p][i]);
                horner(&cs, h0)
            })
            .collect();
        if z.iter().zip(&y).all(|(a, b)| a.subset(*b)) {
            // (5.5) Lagrange remainder T_{p+1}(x(xi)) h^{p+1} with x(xi) in Y; when that is
            // too wide, x(xi) in the enclosure of one of SLICES sub-intervals of [0, h]
            // (narrower boxes than Y: less dependency in the high-order coefficients).
            let hp = (0..=p).fold(point(1.0), |a, _| a * h);
            let scale = set.m.iter().fold(1.0f64, |a, x| a.max(x.abs()));
            let wide = ty[p + 1]
                .iter()
                .any(|t| (*t * hp).wid() > scale * REMAINDER_TOL);
            let mut hull: Option<Vec<Interval>> = None;
            for j in 0..if wide { SLICES } else { 0 } {
                let lo = h.sup() * j as f64 / SLICES as f64;
                let hi = if j + 1 == SLICES {
                    h.sup()
                } else {
                    h.sup() * (j + 1) as f64 / SLICES as f64
                };
                let tj = iv(lo, hi);
                let yj: Vec<Interval> = (0..d)
                    .map(|i| {
                        let mut cs: Vec<Interval> = (0..p).map(|k| coef(k, i)).collect();
                        cs.push(ty[p][i]);
                        horner(&cs, tj).intersection(y[i])
                    })
                    .collect();
                let tj = sys.field.ode_taylor(&yj, p + 1).ok_or(StepFail::Shrink)?;
                hull = Some(match hull {
                    None => tj[p + 1].clone(),
                    Some(hh) => hh
                        .iter()
                        .zip(&tj[p + 1])
                        .map(|(a, b)| a.convex_hull(*b))
                        .collect(),
                });
            }
            let t_rem = hull.unwrap_or_else(|| ty[p + 1].clone());
            remainder = Some(t_rem.iter().map(|t| *t * hp).collect::<Vec<_>>());
            break;
        }
        y = inflate(
            &z.iter()
                .zip(&y)
                .map(|(a, b)| a.convex_hull(*b))
                .collect::<Vec<_>>(),
        );
    }
    let remainder = remainder.ok_or(StepFail::Shrink)?;
    // (5.8) step-size control on the proved remainder, not only on the estimate.
    // (5.3) z = phi(m) + R
    let phi: Vec<Interval> = (0..d)
        .map(|i| horner(&c.iter().map(|ck| ck[i]).collect::<Vec<_>>(), h))
        .collect();
    if strict {
        let scale = set.m.iter().fold(1.0f64, |a, x| a.max(x.abs()));
        let too_wide = |x: &Interval, tol: f64| x.wid() > scale * tol;
        if remainder.iter().any(|x| too_wide(x, REMAINDER_TOL))
            || phi.iter().any(|x| too_wide(x, 16.0 * f64::EPSILON))
        {
            return Err(StepFail::Shrink);
        }
    }
    let z: Vec<Interval> = phi.iter().zip(&remainder).map(|(a, b)| *a + *b).collect();
    // (5.6) J = sum_k V_k h^k, A = J B
    let jac: IMat = (0..d)
        .map(|i| {
            (0..d)
                .map(|j| {
                    horner(
                        &cv.iter().map(|ck| ck[d + i * d + j]).collect::<Vec<_>>(),
                        h,
                    )
                })
                .collect()
        })
        .collect();
    // (5.11) the derivative of the step map over the whole set, with its own remainder.
    let step_jac = if c1 {
        let rem = variational_remainder(sys, &y, &cv, h, p)?;
        Some(
            jac.iter()
                .zip(&rem)
                .map(|(a, b)| a.iter().zip(b).map(|(x, y)| *x + *y).collect())
                .collect(),
        )
    } else {
        None
    };
    let a = linalg::mul(&jac, &linalg::imat(&set.b));
    if !z.iter().all(|x| finite(*x)) || !linalg::all_finite(&a) {
        return Err(StepFail::Shrink);
    }
    // (5.9)-(5.10) new basis from the QR factorisation of mid(A). Lohner's column sorting
    // (by ||A_j|| wid(r_j)) was measured to be worse here: on the particle at t = 600 it
    // gave widths 1.7e-7 against 5.2e-11 unsorted (spec section 5.5).
    let m_new: Vec<f64> = z.iter().map(|x| x.mid()).collect();
    let zc: Vec<Interval> = z.iter().zip(&m_new).map(|(x, c)| *x - point(*c)).collect();
    let q = linalg::mid(&a).qr().q();
    let (b_new, b_inv) = match linalg::enclose_inverse(&q, &q.transpose()) {
        Some(inv) => (q, inv),
        None => (DMatrix::identity(d, d), linalg::identity(d)),
    };
    let r_new: Vec<Interval> = {
        let ba = linalg::mul(&b_inv, &a);
        let part = linalg::mul_vec(&ba, &set.r);
        let shift = linalg::mul_vec(&b_inv, &zc);
        part.iter().zip(shift).map(|(x, y)| *x + y).collect()
    };
    if !r_new.iter().all(|x| finite(*x)) {
        return Err(fatal("enclosure became unbounded"));
    }
    // The box method beside the parallelepiped: x(h) in z + [J] ([X] - m) (spec eq. (5.6)).
    let dx: Vec<Interval> = xbox
        .iter()
        .zip(&set.m)
        .map(|(x, c)| *x - point(*c))
        .collect();
    let jdx = linalg::mul_vec(&jac, &dx);
    let boxed = z.iter().zip(jdx).map(|(a, b)| *a + b).collect();
    Ok((
        LohnerSet {
            m: m_new,
            b: b_new,
            r: r_new,
            boxed,
        },
        step_jac,
    ))
}

/// (5.11) Remainder of the variational equation over one step: with `Y` the proved a priori
/// box of the state, find `Y_V` with
/// `sum_{i<p} [V_i] [0,h]^i + V_p(Y, Y_V) [0,h]^p  in  Y_V` (V(0) = I), so that `V(t) in Y_V`
/// on `[0, h]`; then `V(h) - sum_{i<=p} V_i h^i in V_{p+1}(Y, Y_V) h^{p+1}`.
fn variational_remainder(
    sys: &System,
    y: &[Interval],
    cv: &[Vec<Interval>],
    h: Interval,
    p: usize,
) -> Result<IMat, StepFail> {
    let d = y.len();
    let h0 = iv(0.0, h.sup());
    let series = |k_max: usize, i: usize, top: Option<Interval>| {
        let mut cs: Vec<Interval> = (0..k_max).map(|k| cv[k][d + i]).collect();
        cs.extend(top);
        horner(&cs, h0)
    };
    let mut yv = inflate(
        &(0..d * d)
            .map(|i| series(p + 1, i, None))
            .collect::<Vec<_>>(),
    );
    for _ in 0..4 {
        let ext: Vec<Interval> = y.iter().chain(&yv).copied().collect();
        let tv = sys
            .field_var
            .ode_taylor(&ext, p + 1)
            .ok_or(StepFail::Shrink)?;
        let zv: Vec<Interval> = (0..d * d)
            .map(|i| series(p, i, Some(tv[p][d + i])))
            .collect();
        if zv.iter().zip(&yv).all(|(a, b)| a.subset(*b)) {
            let hp = (0..=p).fold(point(1.0), |a, _| a * h);
            return Ok((0..d)
                .map(|i| (0..d).map(|j| tv[p + 1][d + i * d + j] * hp).collect())
                .collect());
        }
        yv = inflate(
            &zv.iter()
                .zip(&yv)
                .map(|(a, b)| a.convex_hull(*b))
                .collect::<Vec<_>>(),
        );
    }
    Err(StepFail::Shrink)
}

/// A trial box for the a priori enclosure: widened by 10% of its width and a little more.
/// Any box is admissible here (the inclusion test decides), so plain floats are fine.
fn inflate(x: &[Interval]) -> Vec<Interval> {
    x.iter()
        .map(|v| {
            let w = v.wid() * 0.1 + v.mag() * 1e-15 + 1e-300;
            iv(v.inf() - w, v.sup() + w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::AnyScene;

    #[test]
    fn progress_is_told_a_rising_fraction_ending_at_one_and_changes_nothing() {
        use std::sync::{Arc, Mutex};
        let model = Model::new(AnyScene::new("knife", &[]).unwrap());
        let seen = Arc::new(Mutex::new(Vec::new()));
        let s2 = seen.clone();
        let opts = FlowOptions {
            progress: Some(Progress(Arc::new(move |f| s2.lock().unwrap().push(f)))),
            ..FlowOptions::default()
        };
        let (q, u) = ([0.0, 0.0, 0.0], [0.8, 0.8]);
        let with = flow(&model, &q, &u, 5.0, &opts).unwrap();
        let without = flow(&model, &q, &u, 5.0, &FlowOptions::default()).unwrap();
        assert_eq!(with.q, without.q);
        let seen = seen.lock().unwrap();
        assert_eq!(seen.len(), with.stats.steps);
        assert!(seen.windows(2).all(|w| w[0] <= w[1]) && seen[0] > 0.0);
        assert_eq!(*seen.last().unwrap(), 1.0);
    }

    #[test]
    fn particle_with_zero_y_speed_moves_on_a_line() {
        let model = Model::new(AnyScene::new("particle", &[]).unwrap());
        let e = flow(
            &model,
            &[0.5, 2.0, -1.0],
            &[0.25, 0.0],
            3.0,
            &FlowOptions::default(),
        )
        .unwrap();
        // nhsolution0: x = x0 + xd t, y = y0, z = z0 + y0 xd t
        assert!(e.q[0].contains(1.25) && e.q[1].contains(2.0) && e.q[2].contains(0.5));
        assert!(e.q.iter().all(|x| x.wid() < 1e-14));
    }
}
