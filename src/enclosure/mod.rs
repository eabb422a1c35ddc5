//! The validated integrator: interval Taylor series + a priori enclosure (Picard-Lindelof
//! in the high-order form of Corliss and Rihm) + Lohner's QR control of the wrapping effect
//! ([spec/05-enclosure.md](crate::spec::enclosure), eqs. (5.1)-(5.10)).

mod chain;
mod control;
mod float;
mod ival;
pub mod linalg;
mod options;
mod orders;
mod set;
mod show;
mod step;
mod system;

pub use float::{float_flow_counted, float_flow_tail_counted};
pub use ival::Ival;
pub use options::{Basis, FlowOptions, FlowStats};
// the default order is named here for the internals feature
#[allow(unused_imports)]
pub use orders::DEFAULT_ORDER;
// the marked subset is a field of the set (named here for the internals feature)
#[allow(unused_imports)]
pub use set::{LohnerSet, SubSet};
pub use system::System;

use crate::Error;
pub(crate) use chain::Memo;
pub(crate) use control::{too_many, Explain, WIDEST};
use control::{flow_set_general, C1};
use linalg::IMat;

/// Carry a set through time `t` ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves)): the returned set contains the exact
/// state at time t of every solution starting in `set`.
pub fn flow_set<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    t: f64,
    opts: &FlowOptions,
) -> Result<(LohnerSet<I>, FlowStats), Error> {
    flow_set_span(sys, set, I::cst(t), opts)
}

/// As [`flow_set`] over a span of time known by an enclosure `span` (`span.inf() >= 0`):
/// the returned set contains the exact state at time `d` of every solution starting in
/// `set`, for every `d` in `span` (the last step is an interval step, [spec eq. (5.7)](crate::spec::enclosure)). A
/// difference of float times `t_1 - t_0` is carried this way ([spec eq. (5.16)](crate::spec::enclosure)).
pub fn flow_set_span<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    span: I,
    opts: &FlowOptions,
) -> Result<(LohnerSet<I>, FlowStats), Error> {
    flow_set_span_memo(sys, set, span, opts, &mut Memo::default(), None)
}

/// [`flow_set_span`] with the step rule's memory (5.8) taken from and left in `memo`, so
/// that a flow continued from a stop (5.16) chooses its first step as if it had not
/// stopped. Only a choice of step sizes: what is proved is [`flow_set_span`]'s.
pub(crate) fn flow_set_span_memo<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    span: I,
    opts: &FlowOptions,
    memo: &mut Memo<I>,
    explain: Option<Explain<'_>>,
) -> Result<(LohnerSet<I>, FlowStats), Error> {
    if span.is_empty() || span.inf() < 0.0 || !span.sup().is_finite() {
        return Err(Error::input(format!(
            "a span of time must be finite and >= 0 (got [{}, {}])",
            span.inf(),
            span.sup()
        )));
    }
    let (set, _, stats) = flow_set_general(sys, set, span, opts, C1::No, memo, explain)?;
    Ok((set, stats))
}

/// As [`flow_set`], and also an interval matrix containing the derivative `D x(t) / D x(0)`
/// at every initial point of `set` ([spec Theorem 5.2](crate::spec::enclosure)).
pub fn flow_set_c1<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    t: f64,
    opts: &FlowOptions,
) -> Result<(LohnerSet<I>, IMat<I>, FlowStats), Error> {
    let (set, jac, stats) =
        flow_set_general(sys, set, I::cst(t), opts, C1::Cheap, &mut Memo::default(), None)?;
    let d = set.m.len();
    Ok((set, jac.unwrap_or_else(|| linalg::identity(d)), stats))
}

/// As [`flow_set_c1`], each step's Jacobian held to the test of (5.6) at the level `eps`
/// (at least the set's precision) instead of the set's precision, and computed in f64
/// where (5.6''') passes at that level ([spec (12.0.9)](crate::spec::precision)): the
/// derivative and the set are enclosures all the same, the derivative's width f64's
/// rounding or more, and the set's own width allowed the level `eps`.
pub(crate) fn flow_set_c1_loose<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    t: f64,
    opts: &FlowOptions,
    eps: f64,
) -> Result<(LohnerSet<I>, IMat<I>, FlowStats), Error> {
    let (set, jac, stats) =
        flow_set_general(sys, set, I::cst(t), opts, C1::Loose(eps), &mut Memo::default(), None)?;
    let d = set.m.len();
    Ok((set, jac.unwrap_or_else(|| linalg::identity(d)), stats))
}

/// As [`flow_set_c1`] with each step's Jacobian enclosed to the rounding level (its
/// variational order raised until its remainder is below 1 ulp of its size, [spec eq.
/// (5.6)](crate::spec::enclosure)): slower, but the derivative stays narrow over long times ([spec Theorem 5.3](crate::spec::enclosure)).
// used through the `internals` feature (and its tests); the crate's own flows go through
// `flow_set_jacobian_explained`
#[cfg_attr(not(feature = "internals"), allow(dead_code))]
pub fn flow_set_jacobian<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    t: f64,
    opts: &FlowOptions,
) -> Result<(LohnerSet<I>, IMat<I>, FlowStats), Error> {
    flow_set_jacobian_explained(sys, set, t, opts, None)
}

/// [`flow_set_jacobian`] with a refusal's cause asked of `explain` (see [`Explain`]).
pub(crate) fn flow_set_jacobian_explained<I: Ival>(
    sys: &System,
    set: LohnerSet<I>,
    t: f64,
    opts: &FlowOptions,
    explain: Option<Explain<'_>>,
) -> Result<(LohnerSet<I>, IMat<I>, FlowStats), Error> {
    let (set, jac, stats) =
        flow_set_general(sys, set, I::cst(t), opts, C1::Precise, &mut Memo::default(), explain)?;
    let d = set.m.len();
    Ok((set, jac.unwrap_or_else(|| linalg::identity(d)), stats))
}
