//! Answers computed with more than 53 bits ([spec/12-precision.md](crate::spec::precision), contract E18): the
//! query's precision picks the interval type, the generic functions ([`crate::flow::flow_at_in`],
//! [`crate::exact::retract_in`], ...) compute in it, and the ends are printed as decimals
//! rounded outward ([`crate::OutwardDecimal`]).

use super::{Answer, At, Query, SceneSpec};
use crate::enclosure::{FlowOptions, Ival};
use crate::exact::{discrete_lagrangian_in, retract_in, step_in};
use crate::flow::{flow_at_in, flow_c1_in, FlowEnclosure};
use crate::model::Model;
use crate::precision::dd::DdInterval;
use crate::precision::wide::{self, WideInterval};
use crate::{DecimalInterval, Error, OutwardDecimal};

/// The scene of a query that reads `precision`; an input error for the others.
pub(super) fn scene(query: &Query) -> Result<&SceneSpec, Error> {
    match query {
        Query::Flow { scene, .. } | Query::Order { scene, .. } => Ok(scene),
        Query::Retract(p) | Query::Step(p) | Query::Lagrangian(p) => Ok(&p.scene),
        _ => Err(not_read()),
    }
}

fn not_read() -> Error {
    Error::input_key(
        "precision",
        "`precision` is read by flow, retract, step, lagrangian and order only",
    )
}

/// The answer to `query` (flow, retract, step, lagrangian or order) at `bits > 53` significand bits:
/// double-double intervals up to 106 bits, [`WideInterval`]s at exactly `bits` up to 512.
pub(crate) fn answer(
    bits: u32,
    model: &Model,
    query: &Query,
    opts: &FlowOptions,
) -> Result<Answer, Error> {
    match bits {
        54..=106 => answer_in::<DdInterval>(106, model, query, opts),
        wide::MIN_BITS..=wide::MAX_BITS => {
            wide::with_bits(bits, || answer_in::<WideInterval>(bits, model, query, opts))
        }
        _ => Err(above(bits)),
    }
}

/// The input error of a precision above what this build computes with.
pub(crate) fn above(bits: u32) -> Error {
    Error::input_key(
        "precision",
        format!(
            "precision: {bits} bits is above the {} this build computes with",
            wide::MAX_BITS
        ),
    )
}

fn answer_in<I>(
    bits: u32,
    model: &Model,
    query: &Query,
    opts: &FlowOptions,
) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
    I::Public: OutwardDecimal,
{
    match query {
        Query::Flow {
            q,
            u,
            t,
            order,
            jacobian,
            ..
        } => {
            let o = FlowOptions {
                order: (*order > 0).then_some(*order),
                ..opts.clone()
            };
            flow_in::<I>(bits, model, q, u, t, *jacobian, &o)
        }
        Query::Retract(p) => {
            let r = retract_in::<I>(model, &p.q0, &p.q1, p.h, opts)?;
            Ok(Answer::RetractWide {
                precision: bits,
                possibly_member: r.s.iter().all(|x| I::from_public(x.clone()).contains(0.0)),
                u0: decimals(&r.u0),
                v0: decimals(&r.v0),
                v1: decimals(&r.v1),
                s: decimals(&r.s),
                q1: decimals(&r.q1),
            })
        }
        Query::Step(p) => {
            let s = step_in::<I>(model, &p.q0, &p.q1, p.h, opts)?;
            Ok(Answer::StepWide {
                precision: bits,
                q1: decimals(&s.q1),
                q2: decimals(&s.q2),
                p_minus: decimals(&s.p_minus),
                p_plus: decimals(&s.p_plus),
            })
        }
        Query::Lagrangian(p) => {
            let (r, l) = discrete_lagrangian_in::<I>(model, &p.q0, &p.q1, p.h, opts)?;
            Ok(Answer::LagrangianWide {
                precision: bits,
                l: l.decimal(),
                s: decimals(&r.s),
            })
        }
        Query::Order {
            scheme,
            q,
            u,
            h,
            rungs,
            ..
        } => {
            let mut s = crate::schemes::Scheme::new(model, *scheme);
            let a = super::order::answer(model, &mut s, q, u, *h, *rungs, opts, Some(bits))?;
            Ok(Answer::OrderWide {
                precision: bits,
                order: a,
            })
        }
        _ => Err(not_read()),
    }
}

fn flow_in<I>(
    bits: u32,
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: &At,
    jacobian: bool,
    opts: &FlowOptions,
) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
{
    let dec = |e: FlowEnclosure<I>| FlowEnclosure {
        q: decimals(&e.q),
        u: decimals(&e.u),
        v: decimals(&e.v),
        stats: e.stats,
    };
    match t {
        At::Many(times) => {
            if jacobian {
                return Err(Error::input_key(
                    "jacobian",
                    "`jacobian` is given only at one time `t`, not with `times`",
                ));
            }
            let enclosures = flow_at_in::<I>(model, q, u, times, opts)?;
            Ok(Answer::FlowAtWide {
                precision: bits,
                times: times.clone(),
                enclosures: enclosures.into_iter().map(dec).collect(),
            })
        }
        At::One(t) => {
            let (enclosure, jacobian) = if jacobian {
                let (e, j) = flow_c1_in::<I>(model, q, u, *t, opts)?;
                (e, Some(j.iter().map(|r| decimals(r)).collect()))
            } else {
                let mut e = flow_at_in::<I>(model, q, u, &[*t], opts)?;
                let e = e.pop().ok_or_else(|| {
                    Error::internal_at(crate::Invariant::Missing, "flow_at_in answered no time")
                })?;
                (e, None)
            };
            Ok(Answer::FlowWide {
                precision: bits,
                enclosure: dec(enclosure),
                jacobian,
            })
        }
    }
}

fn decimals<P: OutwardDecimal>(x: &[P]) -> Vec<DecimalInterval> {
    x.iter().map(|v| v.decimal()).collect()
}
