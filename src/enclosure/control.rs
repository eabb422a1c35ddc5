//! Step and order control ([spec eqs. (5.7)](crate::spec::enclosure), (5.8) (a)-(d), (5.8'), (5.8'')): the loop that
//! carries a set over a span of time, choosing each step before trying it and the last
//! step's order.

use super::chain::{self, Link, Memo};
use super::ival::{rounded_to_f64, Ival};
use super::linalg::{self, IMat};
use super::options::{FlowOptions, FlowStats};
use super::set::*;
use super::step::*;
use super::system::System;
use crate::tape::Rows;
use crate::{Error, Reason};

/// What a flow computes besides the set.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum C1 {
    No,
    /// The derivative, each step's factor as cheap as the state allows (5.6).
    Cheap,
    /// The derivative as an enclosure only: each step's factor held to the test (5.6) at
    /// this level instead of the state's precision, in f64 where (5.6''') passes at it.
    Loose(f64),
    /// The derivative, each step's factor to the rounding level (5.6).
    Precise,
}

/// What [`flow_set_general`] hands back: the set at the end, the derivative when asked
/// for, and the statistics.
pub(super) type Flown<I> = (LohnerSet<I>, Option<IMat<I>>, FlowStats);

/// Carry `set` over every span of time in `total` (a point for a float time). `memo`: the
/// last accepted step that was not the final one, and its remainder's width relative to the
/// tolerance (5.8), read at the start and left for a continuation.
/// `explain`, when given, is asked why the flow cannot go on when its steps collapse (see
/// [`Explain`]); its answer replaces the step budget's or the step-size underflow's refusal.
pub(super) fn flow_set_general<I: Ival>(
    sys: &System,
    mut set: LohnerSet<I>,
    total: I,
    opts: &FlowOptions,
    c1_mode: C1,
    memo: &mut Memo<I>,
    explain: Option<Explain<'_>>,
) -> Result<Flown<I>, Error> {
    let t = total.sup();
    let precise = c1_mode == C1::Precise;
    let mut total_jac: Option<JacobianSet<I>> = None;
    let level = opts.level::<I>();
    let short_order = opts.order_at_level::<I>(I::short_order());
    let mut p = opts.given_order().unwrap_or(opts.order_at_level::<I>(I::order()));
    // (5.8) (e) whether the order of a short span is still to be chosen (at the first step)
    let mut choose_order = opts.given_order().is_none() && opts.given_h().is_none();
    let mut stats = FlowStats {
        order: p,
        steps: 0,
        rejected: 0,
        h_min: f64::INFINITY,
        h_max: 0.0,
    };
    // Time done so far, exactly enclosed (spec eq. (5.7)).
    let mut done = I::zero();
    // The end is reached by the step marked last (whose span is `total - done`), not by a
    // rounded sum of steps that only touches `t`.
    let mut reached = t <= 0.0;
    // Index in JAC_ORDERS of the variational order to try first (5.6).
    let mut jac_order = 0;
    // (5.8) (c): the step of the last first try rejected just above the tolerance, and the
    // steps accepted since
    let mut ceiling: Option<(f64, i32)> = None;
    // The refusal of a flow stopped at `done` with steps of size `h`: `explain`'s cause when
    // it names one, else `fallback`. A stop by the step budget is explained only when the
    // steps have collapsed (64 times below the largest one taken): a flow that is merely
    // long is refused for its budget.
    let stop = |fallback: Error, set: &LohnerSet<I>, h: f64, done: I, stats: &FlowStats| {
        let collapsed = h * 64.0 < stats.h_max;
        let budget = fallback.reason() == Some(Reason::Budget);
        // the budget's refusal, handed to `explain` when the steps collapsed on the way to it
        let spent = (collapsed && budget).then_some(&fallback);
        let cause = explain
            .filter(|_| collapsed || !budget)
            .and_then(|f| f(&rounded_to_f64(&set.hull()), h, done.inf(), spent));
        cause.unwrap_or(fallback).reached(done.inf())
    };
    // the last accepted step (0 before the first)
    let mut last_h = 0.0;
    // the steps since the last image of a point set, for the product form (5.10'''):
    // those of the flow this one continues, if it starts where that one ended
    let mut links: Vec<Link<I>> = if memo.end == set.m {
        // the set carried on is the one the steps made, its box not narrowed (5.10''')
        if let Some(b) = memo.boxed.take() {
            set.boxed = b;
        }
        std::mem::take(&mut memo.links)
    } else {
        Vec::new()
    };
    while !reached {
        // the work is the steps taken and tried: rejected tries count too (a hard start can
        // reject dozens of tries per step)
        if stats.steps >= opts.max_taylor_steps || stats.steps + stats.rejected >= 2 * opts.max_taylor_steps {
            return Err(stop(too_many(opts.max_taylor_steps, t), &set, last_h, done, &stats));
        }
        opts.check_budget().map_err(|e| e.reached(done.inf()))?;
        let rem = (total - done).intersection(I::iv(0.0, f64::MAX));
        // (5.3) Taylor coefficients at the centre, for every try of this step.
        let centre: Vec<I> = set.m.iter().map(|x| I::pt(*x)).collect();
        let m_f64: Vec<f64> = set.m.iter().map(|x| I::pt_f64(*x)).collect();
        // the step of the rule (5.8) (a)-(c) at order `p`, from the coefficients' midpoints
        // (choices only)
        // the caps on that step: the step the last one predicts, and the ceiling (5.8) (c)
        let (memo_step, ceiling_now) = (memo.step, ceiling);
        let cap = |p: usize| {
            let predicted = memo_step.map_or(f64::INFINITY, |(h0, ratio)| h0 * rescale(ratio, p, 1.5));
            let ceiling = ceiling_now.map_or(f64::INFINITY, |(hc, k)| {
                hc * 0.97 * (1.0 + CEILING_GROWTH).powi(k)
            });
            predicted.min(ceiling)
        };
        let rule_at = |mid: Rows<'_, f64>, p: usize| {
            round_step_fine(step_size(mid.first(p + 1), p, &m_f64, level).min(cap(p)))
        };
        // (5.8) (e) A span that takes two or three steps at order `p` from its start is
        // taken at SHORT_ORDER: fewer, longer steps where the span sets their number. The
        // series goes on from order p to SHORT_ORDER when it does.
        let short = |c: Rows<'_, I>| {
            let h = rule_at(c.map(|x| x.mid()).rows(), p);
            short_span(rem.inf(), rem.sup(), h)
        };
        let fixed = opts.given_h().is_some();
        let mut series = sys.field.ode_series(&centre, if choose_order { short_order } else { p });
        let undefined = || Error::refused(Reason::Undefined, "vector field not defined at the state");
        // (5.8') A last step that a lower order also reaches in one step takes that order
        // (the work of a Taylor series grows like the square of its order): a short flow,
        // such as a retraction's over a small h, costs a fraction of order p. The series is
        // grown through the lower orders first and stops at the first that reaches the end
        // of the span, so that the orders above it are not computed. Only where the caps
        // of the rule (5.8) let a step reach that end; should its remainder not meet the
        // tolerance, the step is tried again at order p.
        let mut low = None;
        if !fixed && opts.given_order().is_none() && round_step_fine(cap(p)) >= rem.inf() {
            for q in I::low_orders().iter().copied().filter(|&q| q < p) {
                if !series.grow(q) {
                    break;
                }
                let mid = series.rows().map(|x| x.mid());
                if step_size(mid.rows(), q, &m_f64, level) >= rem.sup() {
                    low = Some(q);
                    break;
                }
            }
        }
        let (mut h, mut last, short_rest, mut p_step) = match low {
            Some(q) => (rem.inf(), true, within_short_rest(rem.sup(), rem.inf()), q),
            None => {
                // the series to order p, and on to SHORT_ORDER when the span is short (5.8) (e)
                if !series.grow(p) {
                    return Err(stop(undefined(), &set, last_h, done, &stats));
                }
                if choose_order {
                    let more = short_order;
                    if more > p && short(series.rows()) {
                        // past p a failure leaves the series at p
                        series.grow(more);
                    }
                    choose_order = false;
                    p = series.order();
                    stats.order = p;
                }
                // A fixed step (spec eq. (5.13)) or the rule of (5.8), from the coefficients'
                // midpoints (choices only).
                let h = if fixed {
                    round_step(opts.given_h().unwrap_or(0.0))
                } else {
                    rule_at(series.rows().map(|x| x.mid()).rows(), p)
                }
                .min(rem.inf());
                // (5.8) (d) In a rest of the span that takes at most SHORT_REST steps of
                // this size, the remainder is held to the tolerance without slices (5.5).
                let short_rest = !fixed && within_short_rest(rem.sup(), h);
                (h, h >= rem.inf(), short_rest, p)
            }
        };
        // (5.6) the precise ladder's orders above the state's, only while the derivative
        // carried so far is narrower than HIGH_UNTIL of its size
        let high = precise
            && total_jac.as_ref().is_none_or(|acc| {
                let hull = acc.hull(&set.b);
                let size = hull.entries().iter().fold(1.0f64, |a, x| a.max(x.mag()));
                let wide = hull.entries().iter().fold(0.0f64, |a, x| a.max(x.wid()));
                wide <= HIGH_UNTIL * size
            });
        let mut tries = 0;
        // the a priori box of a rejected try, for the next try of this step (5.4')
        let mut prior = None;
        loop {
            if tries > 0 {
                opts.check_budget().map_err(|e| e.reached(done.inf()))?;
            }
            let hi = if last { rem } else { I::cst(h) };
            let tol = match (fixed || tries >= 12, short_rest) {
                (true, _) => Tolerance::Loose,
                (false, true) => Tolerance::Unsliced,
                (false, false) => Tolerance::Strict,
            };
            let step = lohner_step(
                sys,
                &set,
                series.rows().first(p_step + 1),
                hi,
                p_step,
                tol,
                c1_mode,
                opts,
                high,
                &mut jac_order,
                &mut prior,
            );
            match step {
                Ok(out) => {
                    if let Some((j, ba, b_inv)) = &out.jac {
                        let mut next = match total_jac.take() {
                            Some(acc) => acc.step(j, ba, b_inv),
                            None => JacobianSet::first(j, b_inv),
                        };
                        if let Some(b) = &out.rebased {
                            next = next.rebase(b);
                        }
                        if !linalg::all_finite(&next.r) {
                            return Err(Error::refused(
                                Reason::Unbounded,
                                "derivative enclosure became unbounded",
                            )
                            .reached(done.inf()));
                        }
                        total_jac = Some(next);
                    }
                    // from a point, the steps before do not matter
                    if set.r.iter().chain(&set.r0).all(|r| r.is_exact_zero()) {
                        links.clear();
                    }
                    match out.link {
                        Some((jac, err)) => links.push(Link {
                            c: set.c,
                            r0: set.r0,
                            b: set.b,
                            r: set.r,
                            jac,
                            err,
                        }),
                        None => links.clear(),
                    }
                    set = out.set;
                    // the final step, cut to the end, says little about the next
                    if !last {
                        memo.step = Some((hi.sup(), out.ratio));
                    }
                    done = if last { total } else { done + hi };
                    reached = last;
                    stats.steps += 1;
                    if let Some((_, k)) = &mut ceiling {
                        *k = k.saturating_add(1);
                    }
                    stats.h_min = stats.h_min.min(hi.inf());
                    stats.h_max = stats.h_max.max(hi.sup());
                    last_h = hi.sup();
                    opts.progress
                        .tell("flow", if last { t } else { done.sup().min(t) }, t);
                    // (5.18'') a box grown past the widest the scene's checks look at, its
                    // steps collapsed: refused at once when `explain` names a cause
                    if !last && hi.sup() * 64.0 < stats.h_max {
                        if let Some(e) = hopeless(&set, hi.sup(), done, explain) {
                            return Err(e);
                        }
                    }
                    // refuse early when the steps now taken would not reach t in time
                    let left = (t - done.sup()) / hi.sup();
                    if !last && stats.steps as f64 + left > 4.0 * opts.max_taylor_steps as f64 {
                        return Err(stop(too_many(opts.max_taylor_steps, t), &set, last_h, done, &stats));
                    }
                    break;
                }
                Err(StepFail::Fatal(why)) => {
                    return Err(stop(Error::uncertified(why), &set, h, done, &stats))
                }
                Err(StepFail::Shrink | StepFail::TooWide(_)) if p_step < p => {
                    // the lower order did not do: the same step at order p
                    if !series.grow(p) {
                        return Err(stop(undefined(), &set, last_h, done, &stats));
                    }
                    choose_order = false;
                    p_step = p;
                    stats.rejected += 1;
                }
                Err(fail @ (StepFail::Shrink | StepFail::TooWide(_))) => {
                    if tries == 0 && !last && matches!(fail, StepFail::TooWide(r) if r <= 4.0) {
                        ceiling = Some((hi.sup(), 0));
                    }
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
                    if stats.steps + stats.rejected >= 2 * opts.max_taylor_steps {
                        return Err(stop(too_many(opts.max_taylor_steps, t), &set, h, done, &stats));
                    }
                    if tries > 60 || h.is_nan() || h <= 0.0 || h < t * 1e-14 {
                        let e = Error::uncertified(format!(
                            "no a priori enclosure could be proved near t = {} (step size underflow)",
                            done.sup()
                        ));
                        return Err(stop(e, &set, h, done, &stats));
                    }
                }
            }
        }
    }
    if stats.steps == 0 {
        stats.h_min = 0.0;
    }
    // (5.10''') the final box narrowed by the steps' errors in product form
    memo.boxed = Some(set.boxed.clone());
    chain::narrow(&mut set, &links, 4 * stats.steps);
    memo.end = set.m.clone();
    memo.links = links;
    // No answer with an infinite endpoint (contract, Numbers): every consumer of a flow
    // reads the set through its hull.
    if !set.hull().iter().all(|x| x.is_finite()) {
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

/// (5.6) The relative width of the derivative carried so far up to which the precise
/// ladder goes above the state's order.
const HIGH_UNTIL: f64 = 1e-11;

/// Asked why a flow cannot go on, with the state's hull at the stop, the size of the steps
/// there, the time done and, when the steps collapsed on the way to the step budget, that
/// budget's refusal: a refusal naming the cause (the system's data not proved regular near
/// the state, say), or `None` when it sees none. It only words the refusal: what is proved
/// does not depend on it.
pub(crate) type Explain<'a> =
    &'a dyn Fn(&[inari::Interval], f64, f64, Option<&Error>) -> Option<Error>;

/// The widest box, relative to `1 + |x_i|` in each coordinate, whose refusals are worded by
/// the scene's data ([spec (5.18)](crate::spec::enclosure)); a flow whose steps collapsed
/// stops once its box is wider ([spec (5.18'')](crate::spec::enclosure)).
pub(crate) const WIDEST: f64 = 1.0 / 64.0;

/// The refusal of a flow whose box, after a step of size `h` that ended at `done`, is wider
/// than [`WIDEST`] in some coordinate: what `explain` says of it, handed the refusal `the
/// enclosure grew too wide` (reason `no_proof`) as it is handed the step limit's
/// ([spec (5.18'')](crate::spec::enclosure)). `None` (the flow goes on) when the box is not
/// that wide, or `explain` names no cause. Asked after each step once the steps collapsed, so
/// `explain` keeps what it computes once per flow.
fn hopeless<I: Ival>(
    set: &LohnerSet<I>,
    h: f64,
    done: I,
    explain: Option<Explain<'_>>,
) -> Option<Error> {
    let explain = explain?;
    let x = rounded_to_f64(&set.hull());
    if x.iter().all(|x| x.wid() <= WIDEST * (1.0 + x.mag())) {
        return None;
    }
    let e = Error::refused(Reason::NoProof, "the enclosure grew too wide");
    explain(&x, h, done.inf(), Some(&e)).map(|e| e.reached(done.inf()))
}


/// (5.8) (d): in a rest of the span that takes at most this many steps, the steps are not
/// sliced.
pub(super) const SHORT_REST: f64 = 3.0;


/// (5.8) (d): whether a rest of length `rest` takes at most SHORT_REST steps of size `h`.
pub(super) fn within_short_rest(rest: f64, h: f64) -> bool {
    (rest / h).ceil() <= SHORT_REST
}

/// (5.8) (e): whether a span `[lo, hi]` long takes two or three (at most SHORT_REST) steps
/// of size `h`: more than one, and no more than a short rest.
pub(super) fn short_span(lo: f64, hi: f64, h: f64) -> bool {
    h < lo && within_short_rest(hi, h)
}


/// The remainder's width, relative to REMAINDER_TOL, that the step rule (5.8) aims at: the
/// remainder varies along a trajectory (about 20 times on the knife between steps of the
/// same size), and aiming at 0.15 keeps the rejections under 5%.
pub(super) const REMAINDER_TARGET: f64 = 0.15;

/// (5.8) (c): how fast the ceiling left by a rejected first try lifts, per accepted step.
const CEILING_GROWTH: f64 = 0.002;

pub(crate) fn too_many(max: usize, t: f64) -> Error {
    Error::over_limit(
        crate::Limit::TaylorSteps,
        format!("more than {max} steps would be needed to reach t = {t}"),
    )
}

/// Round a positive step down to three significant bits (`{1, 1.25, 1.5, 1.75} * 2^e`), so
/// that sums of steps stay exact in f64 for long ([spec eq. (5.7)](crate::spec::enclosure)).
pub(super) fn round_step(h: f64) -> f64 {
    if h.is_nan() || h <= 0.0 || !h.is_finite() {
        return h;
    }
    let base = 2f64.powf(h.log2().floor());
    let quarters = (h / base * 4.0).floor().clamp(4.0, 7.0);
    base * quarters / 4.0
}

/// Round a positive step down to five significant bits (`{16, ..., 31} / 16 * 2^e`): sums of
/// steps stay exact in f64 for long ([spec eq. (5.7)](crate::spec::enclosure)), and the step rule (5.8) can follow
/// the remainder's steep growth with h (about h^(p+2)) more closely than with three bits.
pub(super) fn round_step_fine(h: f64) -> f64 {
    if h.is_nan() || h <= 0.0 || !h.is_finite() {
        return h;
    }
    let base = 2f64.powf(h.log2().floor());
    let sixteenths = (h / base * 16.0).floor().clamp(16.0, 31.0);
    base * sixteenths / 16.0
}

/// The factor by which to multiply a step whose remainder was `ratio` times its tolerance
/// so that the next one is about REMAINDER_TARGET times the tolerance ([spec eq. (5.8)](crate::spec::enclosure)): the remainder grows
/// like `h^(p+2)` (`h^(p+1)` and the width of the slices of the a priori box, about `h`).
/// At most `max`, at least 1/4.
pub(super) fn rescale(ratio: f64, p: usize, max: f64) -> f64 {
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

/// The step-size rule of [spec eq. (5.8)](crate::spec::enclosure) from float Taylor coefficients at the state `x`.
/// `eps` is the rounding level of the precision ([`Ival::eps`]).
pub(super) fn step_size(c: Rows<'_, f64>, p: usize, x: &[f64], eps: f64) -> f64 {
    round_step(step_bound(c, p, x, eps).min(f64::MAX))
}

/// The bound of the rule (5.8) before rounding.
fn step_bound(c: Rows<'_, f64>, p: usize, x: &[f64], eps: f64) -> f64 {
    let scale = x.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    let tol = scale * eps * 0.25;
    let mut h = f64::INFINITY;
    // `min(h, bound^(1/i))`, the root taken only when it can lower h. The minimum does not
    // depend on the order of the terms: the highest coefficients, whose bounds are the
    // smallest when the series converges, come first, and most roots are then skipped.
    let lower = |h: f64, bound: f64, i: usize| {
        if root_at_least(bound, i, h) {
            h
        } else {
            h.min(bound.powf(1.0 / i as f64))
        }
    };
    for (i, ci) in c.iter().enumerate().skip(1).rev() {
        let norm = ci.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if norm > 0.0 {
            // the last two terms below the rounding level ...
            if i + 1 >= p {
                h = lower(h, tol / norm, i);
            }
            // ... and no term larger than the state (no cancellation in the sum)
            h = lower(h, scale / norm, i);
        }
    }
    h
}

/// Whether `bound.powf(1 / i)` is sure to be at least `h`, so that `h.min(..)` is `h`:
/// `bound >= h^i (1 + 2^-40)` with `h^i` from `powi` a normal number. The margin, about
/// `2^-40 / i` after the root, exceeds what the roundings of `h^i` (at most `i` of an ulp),
/// of `1 / i` (an ulp, times `|ln bound| / i <= 710 / i`) and of `powf` (an ulp) can take
/// off. Only saves work: `false` leaves the decision to `powf`.
fn root_at_least(bound: f64, i: usize, h: f64) -> bool {
    if !h.is_finite() || i > 64 {
        return false;
    }
    let hi = h.powi(i as i32);
    hi.is_normal() && bound >= hi * (1.0 + f64::powi(2.0, -40))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tape::Coeffs;

    /// The rule (5.8) as the spec writes it, before rounding: every root taken, lowest
    /// coefficient first.
    fn bound_by_definition(c: &[Vec<f64>], p: usize, x: &[f64]) -> f64 {
        let scale = x.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        let tol = scale * f64::EPSILON * 0.25;
        let mut h = f64::INFINITY;
        for (i, ci) in c.iter().enumerate().skip(1) {
            let norm = ci.iter().map(|v| v.abs()).fold(0.0, f64::max);
            if norm > 0.0 {
                h = h.min((scale / norm).powf(1.0 / i as f64));
                if i + 1 >= p {
                    h = h.min((tol / norm).powf(1.0 / i as f64));
                }
            }
        }
        h
    }

    #[test]
    fn the_step_rule_skips_only_roots_that_cannot_lower_the_step() {
        // xorshift, fixed seed. Coefficients decaying like r^-k, with magnitudes from 1e-300
        // to 1e300 and noise from 0.5 to 1.5, or nearly tied roots (where a skip decided
        // without its margin would change the minimum); some exactly 0.
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut finite = 0;
        for case in 0..20_000 {
            let p = 2 + (next() * 40.0) as usize;
            let d = 1 + (next() * 5.0) as usize;
            let r = 10f64.powf(next() * 8.0 - 4.0);
            let x: Vec<f64> = (0..d)
                .map(|_| (next() - 0.5) * 10f64.powf(next() * 8.0))
                .collect();
            let scale = x.iter().fold(1.0f64, |a, v| a.max(v.abs()));
            // odd cases: |c_k| = scale r^-k (1 + 1e-9 noise) below the two last, which are
            // 0, so that every root is r within 1e-9: near ties
            let tie = case % 2 == 1;
            let big = if tie {
                scale
            } else {
                10f64.powf(next() * 600.0 - 300.0)
            };
            let spread = if tie { 1e-9 } else { 1.0 };
            let c: Vec<Vec<f64>> = (0..=p)
                .map(|k| {
                    (0..d)
                        .map(|_| {
                            if next() < 0.1 || (tie && k + 1 >= p) {
                                return 0.0;
                            }
                            let v = big * r.powi(-(k as i32)) * (1.0 + spread * (next() - 0.5));
                            if next() < 0.5 {
                                v
                            } else {
                                -v
                            }
                        })
                        .collect()
                })
                .collect();
            let flat = Coeffs::from_rows(d, c.iter().map(|r| &r[..]));
            let fast = step_bound(flat.rows(), p, &x, f64::EPSILON);
            let slow = bound_by_definition(&c, p, &x);
            assert_eq!(fast.to_bits(), slow.to_bits(), "case {case}: {fast} != {slow}");
            assert_eq!(step_size(flat.rows(), p, &x, f64::EPSILON), round_step(slow.min(f64::MAX)));
            finite += usize::from(fast.is_finite());
        }
        assert!(finite > 10_000);
    }
}
