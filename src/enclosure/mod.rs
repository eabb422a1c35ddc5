//! The validated integrator: interval Taylor series + a priori enclosure (Picard-Lindelof
//! in the high-order form of Corliss and Rihm) + Lohner's QR control of the wrapping effect
//! (spec/05-enclosure.md, eqs. (5.1)-(5.10)).

pub mod linalg;
mod system;

pub use system::System;

use crate::scalar::{iv, point};
use crate::tape::{finite, Coef};
use crate::{Error, Reason};
use inari::Interval;
use linalg::IMat;
use nalgebra::DMatrix;

/// A set `{ m + B r : r in [r] } ∩ boxed` (Lohner's parallelepiped and a box, both
/// enclosures of the same states; spec eq. (5.1)): `m` and `B` are exact f64 data, `[r]` an
/// interval vector that contains 0.
#[derive(Clone)]
pub struct LohnerSet {
    pub m: Vec<f64>,
    pub b: DMatrix<f64>,
    pub r: Vec<Interval>,
    pub boxed: Vec<Interval>,
    /// A marked subset `{ m + B r : r in sub.r } ∩ sub.boxed` carried along with the same
    /// centre, basis and Jacobians (spec eq. (5.14)): e.g. the image of the initial centre,
    /// which the Krawczyk test needs beside the image of the whole box.
    pub sub: Option<SubSet>,
}

crate::readable::readable_debug!(LohnerSet {
    m: dbg,
    b: dbg,
    r: iv,
    boxed: iv,
    sub: dbg
});

/// The marked subset of a [`LohnerSet`]: its own `[r]` (inside the set's) and box.
#[derive(Clone)]
pub struct SubSet {
    pub r: Vec<Interval>,
    pub boxed: Vec<Interval>,
}

crate::readable::readable_debug!(SubSet { r: iv, boxed: iv });

/// `x - m` in intervals.
fn relative(x: &[Interval], m: &[f64]) -> Vec<Interval> {
    x.iter().zip(m).map(|(v, c)| *v - point(*c)).collect()
}

impl LohnerSet {
    /// The single point `x` (exact f64 values).
    pub fn point(x: &[f64]) -> Self {
        LohnerSet {
            m: x.to_vec(),
            b: DMatrix::identity(x.len(), x.len()),
            r: vec![point(0.0); x.len()],
            boxed: x.iter().map(|v| point(*v)).collect(),
            sub: None,
        }
    }
    /// A box, as centre plus radius.
    pub fn from_box(x: &[Interval]) -> Self {
        let m: Vec<f64> = x.iter().map(|v| v.mid()).collect();
        Self::centred(&m, x)
    }
    /// The box `x` with centre `m` (a point of `x`).
    fn centred(m: &[f64], x: &[Interval]) -> Self {
        LohnerSet {
            m: m.to_vec(),
            b: DMatrix::identity(x.len(), x.len()),
            r: relative(x, m),
            boxed: x.to_vec(),
            sub: None,
        }
    }
    /// The box `x` with centre `m` (a point of `x`) and the marked subset `sub` (a box
    /// inside `x`, e.g. a single point).
    pub fn with_subset(m: &[f64], x: &[Interval], sub: &[Interval]) -> Self {
        LohnerSet {
            sub: Some(SubSet {
                r: relative(sub, m),
                boxed: sub.to_vec(),
            }),
            ..Self::centred(m, x)
        }
    }
    /// An interval box containing the set (spec eq. (5.2)): the parallelepiped's hull
    /// intersected with the box (both contain the set, so the intersection is not empty).
    pub fn hull(&self) -> Vec<Interval> {
        self.hull_of(&self.r, &self.boxed)
    }
    /// A box containing the marked subset, if there is one.
    pub fn sub_hull(&self) -> Option<Vec<Interval>> {
        self.sub.as_ref().map(|s| self.hull_of(&s.r, &s.boxed))
    }
    fn hull_of(&self, r: &[Interval], boxed: &[Interval]) -> Vec<Interval> {
        let br = linalg::mul_vec(&linalg::imat(&self.b), r);
        self.m
            .iter()
            .zip(br)
            .zip(boxed)
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
    /// Refuse with [`Error::over_budget`] (exit 3) once this instant has passed: checked
    /// before every step of the validated flow and every float flow of the retraction's
    /// Newton guess. `None`: no time limit (the step counts still bound the work).
    pub deadline: Option<std::time::Instant>,
    /// How the basis of the set is renewed at each step (spec eq. (5.10)).
    pub basis: Basis,
}

/// The basis `B'` of the next set in Lohner's update (spec eq. (5.10)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Basis {
    /// `B' = mid([J] B)`, the propagated parallelepiped (its inverse proved by (5.9); the
    /// orthogonal basis when that fails). The default: on the knife at T = 600 it is 80
    /// times narrower than the orthogonal one.
    #[default]
    Parallelepiped,
    /// `B'` = the orthogonal factor of a QR factorisation of `mid([J] B)` (Lohner's).
    Orthogonal,
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
            deadline: None,
            basis: Basis::Parallelepiped,
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

/// The order used when none is given: about -ln(2^-53)/2, where the work per unit time of
/// a Taylor method of order p at double precision is smallest (spec eq. (5.8)).
pub const DEFAULT_ORDER: usize = 20;

enum StepFail {
    /// The a priori enclosure was not proved for this h: try a smaller one.
    Shrink,
    /// The remainder (5.5) was wider than its tolerance, by this factor (at least; from
    /// one slice when the others were skipped): try a smaller step (5.8).
    TooWide(f64),
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
    flow_set_span(sys, set, point(t), opts)
}

/// As [`flow_set`] over a span of time known by an enclosure `span` (`span.inf() >= 0`):
/// the returned set contains the exact state at time `d` of every solution starting in
/// `set`, for every `d` in `span` (the last step is an interval step, spec eq. (5.7)). A
/// difference of float times `t_1 - t_0` is carried this way (spec eq. (5.16)).
pub fn flow_set_span(
    sys: &System,
    set: LohnerSet,
    span: Interval,
    opts: &FlowOptions,
) -> Result<(LohnerSet, FlowStats), Error> {
    flow_set_span_memo(sys, set, span, opts, &mut None)
}

/// [`flow_set_span`] with the step rule's memory (5.8) taken from and left in `memo`, so
/// that a flow continued from a stop (5.16) chooses its first step as if it had not
/// stopped. Only a choice of step sizes: what is proved is [`flow_set_span`]'s.
pub(crate) fn flow_set_span_memo(
    sys: &System,
    set: LohnerSet,
    span: Interval,
    opts: &FlowOptions,
    memo: &mut Option<(f64, f64)>,
) -> Result<(LohnerSet, FlowStats), Error> {
    if span.is_empty() || span.inf() < 0.0 || !span.sup().is_finite() {
        return Err(Error::input(format!(
            "a span of time must be finite and >= 0 (got [{}, {}])",
            span.inf(),
            span.sup()
        )));
    }
    let (set, _, stats) = flow_set_general(sys, set, span, opts, C1::No, memo)?;
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
    let (set, jac, stats) = flow_set_general(sys, set, point(t), opts, C1::Cheap, &mut None)?;
    let d = set.m.len();
    Ok((set, jac.unwrap_or_else(|| linalg::identity(d)), stats))
}

/// As [`flow_set_c1`] with each step's Jacobian enclosed to the rounding level (its
/// variational order raised until its remainder is below 16 ulps of its size, spec eq.
/// (5.6)): slower, but the derivative stays narrow over long times (spec Theorem 5.3).
pub fn flow_set_jacobian(
    sys: &System,
    set: LohnerSet,
    t: f64,
    opts: &FlowOptions,
) -> Result<(LohnerSet, IMat, FlowStats), Error> {
    let (set, jac, stats) = flow_set_general(sys, set, point(t), opts, C1::Precise, &mut None)?;
    let d = set.m.len();
    Ok((set, jac.unwrap_or_else(|| linalg::identity(d)), stats))
}

/// What a flow computes besides the set.
#[derive(Clone, Copy, PartialEq, Eq)]
enum C1 {
    No,
    /// The derivative, each step's factor as cheap as the state allows (5.6).
    Cheap,
    /// The derivative, each step's factor to the rounding level (5.6).
    Precise,
}

/// The derivative `D x(t) / D x(0)` carried as `C + B [R]` (spec eq. (5.15)): `C` a float
/// matrix, `B` the state set's basis, `[R]` interval columns.
struct JacobianSet {
    c: DMatrix<f64>,
    r: IMat,
}

impl JacobianSet {
    fn identity(d: usize) -> Self {
        JacobianSet {
            c: DMatrix::identity(d, d),
            r: vec![vec![point(0.0); d]; d],
        }
    }
    /// (5.15) One step: `[J]` the step's derivative factor, `ba = [B'^{-1}][J B]` and
    /// `b_inv = [B'^{-1}]` from the state's update (5.10).
    fn step(&self, jac: &IMat, ba: &IMat, b_inv: &IMat) -> Self {
        let jc = linalg::mul(jac, &linalg::imat(&self.c));
        let c = linalg::mid(&jc);
        let off: IMat = jc
            .iter()
            .enumerate()
            .map(|(i, row)| {
                row.iter()
                    .enumerate()
                    .map(|(j, x)| *x - point(c[(i, j)]))
                    .collect()
            })
            .collect();
        let r = linalg::add(&linalg::mul(ba, &self.r), &linalg::mul(b_inv, &off));
        JacobianSet { c, r }
    }
    /// `C + [B][R]` in intervals.
    fn hull(&self, b: &DMatrix<f64>) -> IMat {
        linalg::add(
            &linalg::imat(&self.c),
            &linalg::mul(&linalg::imat(b), &self.r),
        )
    }
}

/// Carry `set` over every span of time in `total` (a point for a float time). `memo`: the
/// last accepted step that was not the final one, and its remainder's width relative to the
/// tolerance (5.8), read at the start and left for a continuation.
fn flow_set_general(
    sys: &System,
    mut set: LohnerSet,
    total: Interval,
    opts: &FlowOptions,
    c1_mode: C1,
    memo: &mut Option<(f64, f64)>,
) -> Result<(LohnerSet, Option<IMat>, FlowStats), Error> {
    let t = total.sup();
    let c1 = c1_mode != C1::No;
    let precise = c1_mode == C1::Precise;
    let mut total_jac: Option<JacobianSet> = None;
    let d = set.m.len();
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
    // Time done so far, exactly enclosed (spec eq. (5.7)).
    let mut done = point(0.0);
    // The end is reached by the step marked last (whose span is `total - done`), not by a
    // rounded sum of steps that only touches `t`.
    let mut reached = t <= 0.0;
    // Index in JAC_ORDERS of the variational order to try first (5.6).
    let mut jac_order = 0;
    while !reached {
        // the work is the steps taken and tried: rejected tries count too (a hard start can
        // reject dozens of tries per step)
        if stats.steps >= opts.max_steps || stats.steps + stats.rejected >= 2 * opts.max_steps {
            return Err(too_many(opts.max_steps, t).reached(done.inf()));
        }
        Error::check_deadline(opts.deadline).map_err(|e| e.reached(done.inf()))?;
        let rem = (total - done).intersection(iv(0.0, f64::MAX));
        // (5.3) Taylor coefficients at the centre, for every try of this step.
        let centre: Vec<Interval> = set.m.iter().map(|x| point(*x)).collect();
        let c = sys.field.ode_taylor(&centre, p).ok_or_else(|| {
            Error::refused(Reason::Undefined, "vector field not defined at the state")
                .reached(done.inf())
        })?;
        // A fixed step (spec eq. (5.13)) or the rule of (5.8).
        let fixed = opts.step > 0.0;
        // the coefficients' midpoints, for the rules (5.8) and (5.8') (choices only)
        let mid: Vec<Vec<f64>> = if fixed {
            Vec::new()
        } else {
            c.iter()
                .map(|ck| ck.iter().map(|x| x.mid()).collect())
                .collect()
        };
        let mut h = if fixed {
            round_step(opts.step)
        } else {
            let rule = step_size(&mid, p, &set.m);
            let predicted = memo.map_or(rule, |(h0, ratio)| h0 * rescale(ratio, p, 1.5));
            round_step_fine(rule.min(predicted))
        }
        .min(rem.inf());
        let mut last = h >= rem.inf();
        // (5.8') A last step that a lower order also reaches in one step takes that order
        // (the work of a Taylor series grows like the square of its order): a short flow,
        // such as a retraction's over a small h, costs a fraction of order p. Should its
        // remainder not meet the tolerance, the step is tried again at order p.
        let mut p_step = p;
        if last && !fixed && opts.order == 0 {
            p_step = LOW_ORDERS
                .into_iter()
                .find(|&q| q < p && step_size(&mid[..=q], q, &set.m) >= rem.sup())
                .unwrap_or(p);
        }
        let mut tries = 0;
        loop {
            let hi = if last { rem } else { point(h) };
            let strict = !fixed && tries < 12;
            let step = lohner_step(
                sys,
                &set,
                &c[..=p_step],
                hi,
                p_step,
                strict,
                c1,
                opts.basis,
                precise,
                &mut jac_order,
            );
            match step {
                Ok(out) => {
                    if let Some((j, ba, b_inv)) = &out.jac {
                        let acc = total_jac.take().unwrap_or_else(|| JacobianSet::identity(d));
                        let next = acc.step(j, ba, b_inv);
                        if !linalg::all_finite(&next.r) {
                            return Err(Error::refused(
                                Reason::Unbounded,
                                "derivative enclosure became unbounded",
                            )
                            .reached(done.inf()));
                        }
                        total_jac = Some(next);
                    }
                    set = out.set;
                    // the final step, cut to the end, says little about the next
                    if !last {
                        *memo = Some((hi.sup(), out.ratio));
                    }
                    done = if last { total } else { done + hi };
                    reached = last;
                    stats.steps += 1;
                    stats.h_min = stats.h_min.min(hi.inf());
                    stats.h_max = stats.h_max.max(hi.sup());
                    if let Some(p) = &opts.progress {
                        (p.0)(if last { 1.0 } else { done.sup() / t });
                    }
                    // refuse early when the steps now taken would not reach t in time
                    let left = (t - done.sup()) / hi.sup();
                    if !last && stats.steps as f64 + left > 4.0 * opts.max_steps as f64 {
                        return Err(too_many(opts.max_steps, t).reached(done.inf()));
                    }
                    break;
                }
                Err(StepFail::Fatal(why)) => {
                    return Err(Error::uncertified(why).reached(done.inf()))
                }
                Err(StepFail::Shrink | StepFail::TooWide(_)) if p_step < p => {
                    // the lower order did not do: the same step at order p
                    p_step = p;
                    stats.rejected += 1;
                }
                Err(fail @ (StepFail::Shrink | StepFail::TooWide(_))) => {
                    tries += 1;
                    stats.rejected += 1;
                    // (5.8): a remainder too wide by `ratio` gives the step that should
                    // meet the target; a failed a priori enclosure, 0.7 h.
                    let cut = match fail {
                        StepFail::TooWide(ratio) => rescale(ratio, p, 0.9).min(0.9),
                        _ => 0.7,
                    };
                    h = if fixed {
                        round_step(h * cut)
                    } else {
                        round_step_fine(h * cut)
                    };
                    last = false;
                    if stats.steps + stats.rejected >= 2 * opts.max_steps {
                        return Err(too_many(opts.max_steps, t).reached(done.inf()));
                    }
                    if tries > 60 || h.is_nan() || h <= 0.0 || h < t * 1e-14 {
                        return Err(Error::uncertified(format!(
                            "no a priori enclosure could be proved near t = {} (step size underflow)",
                            done.sup()
                        ))
                        .reached(done.inf()));
                    }
                }
            }
        }
    }
    if stats.steps == 0 {
        stats.h_min = 0.0;
    }
    // No answer with an infinite endpoint (contract, Numbers): every consumer of a flow
    // reads the set through its hull.
    if !set.hull().iter().all(|x| finite(*x)) {
        return Err(Error::refused(
            Reason::Unbounded,
            "the state enclosure is not finite",
        ));
    }
    let jac = total_jac.map(|j| j.hull(&set.b));
    if jac.as_ref().is_some_and(|j| !linalg::all_finite(j)) {
        return Err(Error::refused(
            Reason::Unbounded,
            "derivative enclosure became unbounded",
        ));
    }
    Ok((set, jac, stats))
}

/// The lower orders a last step may take instead of the flow's order (spec (5.8')).
const LOW_ORDERS: [usize; 5] = [6, 8, 10, 12, 15];

/// Number of time slices over which the remainder's coefficient is enclosed (spec (5.5)).
const SLICES: usize = 8;

/// Largest accepted width of the Lagrange remainder, relative to the state's size.
const REMAINDER_TOL: f64 = f64::EPSILON;

/// The remainder's width, relative to REMAINDER_TOL, that the step rule (5.8) aims at: the
/// remainder varies along a trajectory (about 20 times on the knife between steps of the
/// same size), and aiming at 0.15 keeps the rejections under 5%.
const REMAINDER_TARGET: f64 = 0.15;

pub(crate) fn too_many(max: usize, t: f64) -> Error {
    Error::refused(
        Reason::Budget,
        format!("more than {max} steps would be needed to reach t = {t}"),
    )
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

/// Round a positive step down to five significant bits (`{16, ..., 31} / 16 * 2^e`): sums of
/// steps stay exact in f64 for long (spec eq. (5.7)), and the step rule (5.8) can follow
/// the remainder's steep growth with h (about h^(p+2)) more closely than with three bits.
fn round_step_fine(h: f64) -> f64 {
    if h.is_nan() || h <= 0.0 || !h.is_finite() {
        return h;
    }
    let base = 2f64.powf(h.log2().floor());
    let sixteenths = (h / base * 16.0).floor().clamp(16.0, 31.0);
    base * sixteenths / 16.0
}

/// The factor by which to multiply a step whose remainder was `ratio` times its tolerance
/// so that the next one is about REMAINDER_TARGET times the tolerance (spec eq. (5.8)): the remainder grows
/// like `h^(p+2)` (`h^(p+1)` and the width of the slices of the a priori box, about `h`).
/// At most `max`, at least 1/4.
fn rescale(ratio: f64, p: usize, max: f64) -> f64 {
    if ratio.is_nan() {
        return 0.25;
    }
    if ratio <= 0.0 {
        return max;
    }
    (REMAINDER_TARGET / ratio)
        .powf(1.0 / (p + 2) as f64)
        .clamp(0.25, max)
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
    let d = x0.len();
    float_flow_var(&sys.field_var, x0, DMatrix::identity(d, d), t, opts).map(|(x, j, _)| (x, j))
}

/// As [`float_flow_c1`] for the derivatives with respect to the last `sys.tail()` components
/// of `x0` only (`D x(t) / D x0[d - tail..]`, d x tail), also returning the number of Taylor
/// steps taken (the work, for callers that bound their total work).
pub fn float_flow_tail_counted(
    sys: &System,
    x0: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
    let (d, c) = (x0.len(), sys.tail());
    let w0 = DMatrix::from_fn(d, c, |i, j| if i + c == d + j { 1.0 } else { 0.0 });
    float_flow_var(&sys.field_var_tail, x0, w0, t, opts)
}

/// A float Taylor integration of `x' = F(x)` alone over time `t` (the state at `t` and the
/// number of steps taken); not rigorous, as [`float_flow_c1`].
pub fn float_flow_counted(
    sys: &System,
    x0: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, usize)> {
    let w0 = DMatrix::zeros(x0.len(), 0);
    float_flow_var(&sys.field, x0, w0, t, opts).map(|(x, _, steps)| (x, steps))
}

/// Float Taylor integration of `(x, W)' = (F(x), DF(x) W)` from `(x0, w0)`; `tape` is the
/// variational tape for `w0.ncols()` columns. W(t) = D x(t)/D x0 * w0.
fn float_flow_var(
    tape: &crate::tape::Tape,
    x0: &[f64],
    w0: DMatrix<f64>,
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
    let (d, cols) = (x0.len(), w0.ncols());
    let p = if opts.order == 0 {
        DEFAULT_ORDER
    } else {
        opts.order
    };
    let mut xw: Vec<f64> = x0.to_vec();
    xw.extend(
        (0..d)
            .flat_map(|i| (0..cols).map(move |j| (i, j)))
            .map(|(i, j)| w0[(i, j)]),
    );
    let mut done = 0.0;
    for steps in 0..opts.max_steps {
        if done >= t {
            let w = DMatrix::from_fn(d, cols, |i, j| xw[d + i * cols + j]);
            return Some((xw[..d].to_vec(), w, steps));
        }
        let c = tape.ode_taylor::<f64>(&xw, p)?;
        // The step rule (5.8) on the state AND the variational series: the Jacobian's series
        // can have a smaller radius of convergence than the state's (e.g. the particle with
        // u1 = 0: x(t) stays 0 while D x / D u1 = asinh(u2 t) / u2 is singular at t = i/u2).
        let h = step_size(&c, p, &xw).min(t - done);
        xw = (0..xw.len())
            .map(|i| c.iter().rev().fold(0.0, |acc, ck| acc * h + ck[i]))
            .collect();
        done = if h >= t - done { t } else { done + h };
        if !xw.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    None
}

/// Horner's scheme in intervals: encloses `sum_{i<n} c_i t^i` for every `t` in `h` and every
/// choice of coefficients in the enclosures `c_i = coef(i)` (fused multiply-adds, each
/// outward rounded by inari).
fn horner(n: usize, coef: impl Fn(usize) -> Interval, h: Interval) -> Interval {
    (0..n)
        .rev()
        .fold(point(0.0), |acc, i| acc.mul_add(h, coef(i)))
}

/// What one step hands on.
struct StepOut {
    set: LohnerSet,
    /// For C^1 output: the step's derivative factor `[J]`, `[B'^{-1}][J B]` and
    /// `[B'^{-1}]` (spec eq. (5.15)).
    jac: Option<(IMat, IMat, IMat)>,
    /// The remainder's width relative to its tolerance (5.8).
    ratio: f64,
}

/// One step of the method (spec eqs. (5.3)-(5.6), (5.9)-(5.12)).
#[allow(clippy::too_many_arguments)]
fn lohner_step(
    sys: &System,
    set: &LohnerSet,
    c: &[Vec<Interval>],
    h: Interval,
    p: usize,
    strict: bool,
    c1: bool,
    basis: Basis,
    precise: bool,
    jac_order: &mut usize,
) -> Result<StepOut, StepFail> {
    let d = set.m.len();
    let fatal = |s: &str| StepFail::Fatal(s.to_string());
    if !set.r.iter().all(|r| r.contains(0.0)) {
        return Err(fatal("internal invariant broken: 0 not in r"));
    }
    let scale = set.m.iter().fold(1.0f64, |a, x| a.max(x.abs()));
    // (5.3) the Taylor polynomial at the centre (coefficients `c`)
    let phi: Vec<Interval> = (0..d).map(|i| horner(c.len(), |k| c[k][i], h)).collect();
    if strict && phi.iter().any(|x| x.wid() > scale * (16.0 * f64::EPSILON)) {
        return Err(StepFail::Shrink);
    }
    let point_set = set.r.iter().all(|r| r.is_exact_zero());
    let xbox = set.hull();
    // the size of x0 - m over the set
    let extent = xbox
        .iter()
        .zip(&set.m)
        .fold(0.0f64, |a, (x, c)| a.max((*x - point(*c)).mag()));
    // z encloses x(h; m); x(h; x0) lies in z + J (x0 - m) for every x0 in the set.
    // (5.4)-(5.5) for the trajectory from the centre alone
    let (rem, _, ratio) = remainder(sys, c, h, p, scale, strict)?;
    let z: Vec<Interval> = phi.iter().zip(&rem).map(|(a, b)| *a + *b).collect();
    if !z.iter().all(|x| finite(*x)) {
        return Err(StepFail::Shrink);
    }
    if point_set && !c1 {
        // a point set needs no Jacobian (J B r = 0 for r = 0)
        return Ok(StepOut {
            set: point_image(set, z),
            jac: None,
            ratio,
        });
    }
    // (5.6) the flow's Jacobian at the lowest order (from `jac_order` on) whose remainder
    // is negligible there; otherwise (5.6'') over the whole set.
    let (z, jac, ratio) = match step_jacobian(sys, &xbox, h, p, scale, extent, precise, jac_order) {
        Some(jac) => (z, jac, ratio),
        None => box_enclosure(sys, &xbox, &phi, h, p, scale, strict, c1)?,
    };
    let a = linalg::mul(&jac, &linalg::imat(&set.b));
    if !z.iter().all(|x| finite(*x)) || !linalg::all_finite(&a) {
        return Err(StepFail::Shrink);
    }
    // (5.9)-(5.10) new basis: mid(A) itself or its orthogonal factor. Lohner's column
    // sorting (by ||A_j|| wid(r_j)) was measured to be worse here: on the particle at
    // t = 600 it gave widths 1.7e-7 against 5.2e-11 unsorted (spec section 5.5).
    let m_new: Vec<f64> = z.iter().map(|x| x.mid()).collect();
    let zc = relative(&z, &m_new);
    let (b_new, b_inv) = choose_basis(linalg::mid(&a), basis);
    let ba = linalg::mul(&b_inv, &a);
    let shift = linalg::mul_vec(&b_inv, &zc);
    let image_r = |r: &[Interval]| -> Vec<Interval> {
        let part = linalg::mul_vec(&ba, r);
        part.iter().zip(&shift).map(|(x, y)| *x + *y).collect()
    };
    // The box method beside the parallelepiped: x(h) in z + [J] ([X] - m) (spec eq. (5.12)).
    let image_box = |hull: &[Interval]| -> Vec<Interval> {
        let dx: Vec<Interval> = hull
            .iter()
            .zip(&set.m)
            .map(|(x, c)| *x - point(*c))
            .collect();
        let jdx = linalg::mul_vec(&jac, &dx);
        z.iter().zip(jdx).map(|(a, b)| *a + b).collect()
    };
    let r_new = image_r(&set.r);
    let sub = set.sub.as_ref().map(|sb| SubSet {
        r: image_r(&sb.r),
        boxed: image_box(&set.hull_of(&sb.r, &sb.boxed)),
    });
    let unbounded = |r: &[Interval]| !r.iter().all(|x| finite(*x));
    if unbounded(&r_new) || sub.as_ref().is_some_and(|sb| unbounded(&sb.r)) {
        return Err(fatal("enclosure became unbounded"));
    }
    let set = LohnerSet {
        m: m_new,
        b: b_new,
        r: r_new,
        boxed: image_box(&xbox),
        sub,
    };
    Ok(StepOut {
        set,
        jac: c1.then_some((jac, ba, b_inv)),
        ratio,
    })
}

/// The basis `B'` of the next set and an interval matrix containing its inverse (spec eqs.
/// (5.9)-(5.10)): `mid([A])` itself for [`Basis::Parallelepiped`] (its inverse proved by
/// (5.9) from a float inverse), the orthogonal factor of its QR factorisation for
/// [`Basis::Orthogonal`] or when the parallelepiped's inverse is not proved, and `I` when
/// neither is.
fn choose_basis(am: DMatrix<f64>, basis: Basis) -> (DMatrix<f64>, IMat) {
    let d = am.nrows();
    if basis == Basis::Parallelepiped {
        let inv = am
            .clone()
            .try_inverse()
            .and_then(|x| linalg::enclose_inverse(&am, &x));
        if let Some(inv) = inv {
            return (am, inv);
        }
    }
    let q = am.qr().q();
    match linalg::enclose_inverse(&q, &q.transpose()) {
        Some(inv) => (q, inv),
        None => (DMatrix::identity(d, d), linalg::identity(d)),
    }
}

/// The orders tried for the Taylor series of the variational equation (spec eq. (5.6)),
/// lowest first.
const JAC_ORDERS: [usize; 6] = [3, 5, 8, 12, 16, 20];

/// Steps taken over the whole set (5.6'') without trying (5.6a) after no order of
/// JAC_ORDERS gave the precise derivative (then the highest order is tried again).
const SKIP: usize = 16;

/// The image of a point set (r = 0): the box z, recentred.
fn point_image(set: &LohnerSet, z: Vec<Interval>) -> LohnerSet {
    let image = LohnerSet::from_box(&z);
    if set.sub.is_some() {
        // the subset of a point is the point
        LohnerSet::with_subset(&image.m, &z, &z)
    } else {
        image
    }
}

/// (5.4)-(5.5), (5.6'') over the whole set (Lohner's original step): `z = phi(m) + [R]`
/// with the remainder over an a priori box of every trajectory from the hull, and
/// `[J] = D phi([X])` from the variational Taylor coefficients over the hull; for C^1
/// output, `[J]` plus the variational remainder (5.11).
#[allow(clippy::too_many_arguments)]
fn box_enclosure(
    sys: &System,
    xbox: &[Interval],
    phi: &[Interval],
    h: Interval,
    p: usize,
    scale: f64,
    strict: bool,
    c1: bool,
) -> Result<(Vec<Interval>, IMat, f64), StepFail> {
    let d = xbox.len();
    let cv = sys
        .field_var
        .ode_taylor(&with_identity(xbox), p)
        .ok_or(StepFail::Shrink)?;
    let b: Vec<Vec<Interval>> = cv.iter().map(|ck| ck[..d].to_vec()).collect();
    let (rem, y, ratio) = remainder(sys, &b, h, p, scale, strict)?;
    let z = phi.iter().zip(&rem).map(|(a, b)| *a + *b).collect();
    let mut jac = variational_polynomial(&cv, d, h);
    if c1 {
        let vrem = variational_remainder(sys, &y, &cv, h, p)?;
        for (row, vr) in jac.iter_mut().zip(&vrem) {
            for (x, r) in row.iter_mut().zip(vr) {
                *x += *r;
            }
        }
    }
    Ok((z, jac, ratio))
}

/// The Picard-Lindelof test in the high-order form of Corliss and Rihm (spec eq. (5.4)):
/// with `b` the Taylor coefficients `0..=q` at the initial set, find a box `Y` with
/// `sum_{i<q} b_i [0,h]^i + T_q(Y) [0,h]^q  in  Y`. Returns `Y` and the coefficients
/// `T_0..T_{q+1}` over `Y` (the last one for the Lagrange remainder). The first trial box
/// is the Taylor range over `[0, h]` widened by 10%; after a failed trial, the hull of `Y`
/// and `Z` widened by 10% and by `widen` times the excess of `Z` over `Y` (up to three times).
fn a_priori(
    tape: &crate::tape::Tape,
    b: &[Vec<Interval>],
    h: Interval,
    q: usize,
    widen: f64,
) -> Result<(Vec<Interval>, Vec<Vec<Interval>>), StepFail> {
    let h0 = iv(0.0, h.sup());
    let dim = b[0].len();
    let series = |i: usize, top: Interval| horner(q + 1, |k| if k < q { b[k][i] } else { top }, h0);
    let mut y = inflate(&(0..dim).map(|i| series(i, b[q][i])).collect::<Vec<_>>());
    for _ in 0..4 {
        let ty = tape.ode_taylor(&y, q + 1).ok_or(StepFail::Shrink)?;
        let z: Vec<Interval> = (0..dim).map(|i| series(i, ty[q][i])).collect();
        if z.iter().zip(&y).all(|(a, b)| a.subset(*b)) {
            return Ok((y, ty));
        }
        // the hull of both, widened by 10% and by a multiple of the excess of Z over Y (a
        // component whose range is nearly a point grows by tiny amounts otherwise)
        y = z
            .iter()
            .zip(&y)
            .map(|(a, b)| {
                let excess = (b.inf() - a.inf()).max(a.sup() - b.sup()).max(0.0);
                let hull = a.convex_hull(*b);
                let w = hull.wid() * 0.1 + excess * widen + hull.mag() * 1e-15 + 1e-300;
                iv(hull.inf() - w, hull.sup() + w)
            })
            .collect();
    }
    Err(StepFail::Shrink)
}

/// (5.4)-(5.5): with `b` the Taylor coefficients at the initial set (its centre, or its
/// hull), proves that every trajectory from it exists on `[0, h]` and returns `[R]` with
/// `x(h) - phi(x0) in [R]`, and the a priori box `Y`. When `T_{p+1}(Y) h^{p+1}` is wide,
/// `x(xi)` is taken in the enclosures of SLICES sub-intervals of `[0, h]` (narrower boxes
/// than Y: less dependency in the high-order coefficients). In strict mode (5.8) a
/// remainder wider than the tolerance rejects the step.
fn remainder(
    sys: &System,
    b: &[Vec<Interval>],
    h: Interval,
    p: usize,
    scale: f64,
    strict: bool,
) -> Result<(Vec<Interval>, Vec<Interval>, f64), StepFail> {
    let d = b[0].len();
    let (y, ty) = a_priori(&sys.field, b, h, p, 0.0)?;
    let hp = (0..=p).fold(point(1.0), |a, _| a * h);
    // the widest component of T h^(p+1), relative to the tolerance (NaN if not finite)
    let ratio_of = |t: &[Interval]| {
        t.iter().fold(0.0f64, |a, t| {
            let w = (*t * hp).wid() / (scale * REMAINDER_TOL);
            if w.is_nan() || a.is_nan() {
                f64::NAN
            } else {
                a.max(w)
            }
        })
    };
    let too_wide = |t: &[Interval]| {
        let r = ratio_of(t);
        r.is_nan() || r > 1.0
    };
    let wide = too_wide(&ty[p + 1]);
    let mut t_rem = ty[p + 1].clone();
    if wide {
        for j in 0..SLICES {
            let lo = h.sup() * j as f64 / SLICES as f64;
            let hi = if j + 1 == SLICES {
                h.sup()
            } else {
                h.sup() * (j + 1) as f64 / SLICES as f64
            };
            let tj = iv(lo, hi);
            let yj: Vec<Interval> = (0..d)
                .map(|i| {
                    horner(p + 1, |k| if k < p { b[k][i] } else { ty[p][i] }, tj).intersection(y[i])
                })
                .collect();
            let tj = sys.field.ode_taylor(&yj, p + 1).ok_or(StepFail::Shrink)?;
            let part = &tj[p + 1];
            // The hull over the SLICES is at least as wide as this slice: in strict mode a
            // slice already over the tolerance decides the rejection, without the others.
            if strict && too_wide(part) {
                return Err(StepFail::TooWide(ratio_of(part)));
            }
            t_rem = if j == 0 {
                part.clone()
            } else {
                t_rem
                    .iter()
                    .zip(part)
                    .map(|(a, b)| a.convex_hull(*b))
                    .collect()
            };
        }
    }
    let ratio = ratio_of(&t_rem);
    if strict && too_wide(&t_rem) {
        return Err(StepFail::TooWide(ratio));
    }
    Ok((t_rem.iter().map(|t| *t * hp).collect(), y, ratio))
}

/// (5.6) An interval matrix containing `D x(h; x0) / D x0` for every `x0` in the hull
/// `[X]`, from the Taylor series of order `q` of the variational equation
/// `V' = DF(x) V, V(0) = I`, with the Lagrange remainder over an a priori box of the
/// extended system `(x, V)`. The orders of [`JAC_ORDERS`] up to `p` are tried from
/// `*order` (an index, updated for the next step) on until the remainder's share of the new
/// set's width (`wid(remainder) |x0 - m| d`) is below the rounding level of the state and,
/// if `precise`, the remainder itself below 16 ulps of the Jacobian's size (the C^1 output
/// of [`flow_set_jacobian`]). `None` when no order does: the step is then taken over the
/// whole set (`box_enclosure`).
#[allow(clippy::too_many_arguments)]
fn step_jacobian(
    sys: &System,
    xbox: &[Interval],
    h: Interval,
    p: usize,
    scale: f64,
    extent: f64,
    precise: bool,
    order: &mut usize,
) -> Option<IMat> {
    let d = xbox.len();
    // After no order qualified for the precise derivative, the next SKIP steps go straight
    // to the step over the whole set (the order index counts them down above the ladder).
    if *order >= JAC_ORDERS.len() {
        *order -= 1;
        if *order >= JAC_ORDERS.len() {
            return None;
        }
    }
    let seed = with_identity(xbox);
    // The a priori box of the extended system, found at the lowest order (where the Picard
    // test over boxes suffers least from the dependency in the coefficients); it holds
    // every trajectory on [0, h], so the Lagrange remainder of any order may use it. At a
    // low order the test converges slowly for components whose range is nearly a point
    // (e.g. D u1 / D u1 = 1 for the knife): widen generously.
    let q0 = JAC_ORDERS[0];
    let w0 = sys.field_var.ode_taylor(&seed, q0)?;
    let (y_ext, t0) = a_priori(&sys.field_var, &w0, h, q0, 4.0).ok()?;
    let mut k = (*order).min(JAC_ORDERS.len() - 1);
    loop {
        let q = JAC_ORDERS[k];
        if q > p.max(q0) {
            if precise {
                *order = JAC_ORDERS.len() + SKIP;
            }
            return None;
        }
        let (w, tw) = if q == q0 {
            (w0.clone(), Some(t0.clone()))
        } else {
            (
                sys.field_var.ode_taylor(&seed, q)?,
                sys.field_var.ode_taylor(&y_ext, q + 1),
            )
        };
        if let Some(tw) = tw {
            let hq = (0..=q).fold(point(1.0), |a, _| a * h);
            let rem: Vec<Interval> = (0..d * d).map(|k| tw[q + 1][d + k] * hq).collect();
            let widest = rem.iter().fold(0.0f64, |a, x| a.max(x.wid()));
            let mut jac = variational_polynomial(&w, d, h);
            let size = jac.iter().flatten().fold(1.0f64, |a, x| a.max(x.mag()));
            // (NaN fails the tests too)
            let share = widest * extent * d as f64 / (scale * f64::EPSILON);
            let own = if precise {
                widest / (16.0 * size * f64::EPSILON)
            } else {
                0.0
            };
            let ratio = share.max(own);
            if ratio <= 1.0 {
                // next step: the same order, or one lower when this one had a wide margin
                *order = if ratio < 1e-4 { k.saturating_sub(1) } else { k };
                for (row, r) in jac.iter_mut().zip(rem.chunks(d)) {
                    for (x, r) in row.iter_mut().zip(r) {
                        *x += *r;
                    }
                }
                return Some(jac);
            }
        }
        k += 1;
        if k == JAC_ORDERS.len() {
            if precise {
                *order = JAC_ORDERS.len() + SKIP;
            }
            return None;
        }
    }
}

/// `(x, I)`: a box with the identity seed of the variational equation (spec eq. (4.11)).
fn with_identity(x: &[Interval]) -> Vec<Interval> {
    let d = x.len();
    let mut xv = x.to_vec();
    for i in 0..d {
        xv.extend((0..d).map(|j| point(if i == j { 1.0 } else { 0.0 })));
    }
    xv
}

/// `sum_k [V_k] h^k`: the Taylor polynomial of the variational part (components `d..`,
/// row-major) of the coefficients `w` of the extended system.
fn variational_polynomial(w: &[Vec<Interval>], d: usize, h: Interval) -> IMat {
    (0..d)
        .map(|i| {
            (0..d)
                .map(|j| horner(w.len(), |k| w[k][d + i * d + j], h))
                .collect()
        })
        .collect()
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
        let n = k_max + usize::from(top.is_some());
        horner(
            n,
            |k| match top {
                Some(t) if k == k_max => t,
                _ => cv[k][d + i],
            },
            h0,
        )
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
