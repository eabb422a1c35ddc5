//! Answers computed with more than 53 bits ([spec/12-precision.md](crate::spec::precision), contract E18): the
//! query's precision picks the interval type, the generic flow ([`crate::flow::flow_at_in`])
//! computes in it, and the ends are printed as decimals rounded outward
//! ([`crate::OutwardDecimal`]).

use crate::enclosure::{FlowOptions, Ival};
use crate::flow::{flow_at_in, flow_c1_in, FlowEnclosure};
use crate::model::Model;
use crate::protocol::{Answer, At};
use crate::{DecimalInterval, Error, OutwardDecimal};

/// The `flow` answer at `bits > 53` significand bits: double-double intervals up to 106
/// bits, arbitrary precision beyond.
pub(crate) fn flow_answer(
    bits: u32,
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: &At,
    jacobian: bool,
    opts: &FlowOptions,
) -> Result<Answer, Error> {
    match bits {
        54..=106 => {
            flow_in::<crate::precision::dd::DdInterval>(106, model, q, u, t, jacobian, opts)
        }
        _ => Err(Error::input_key(
            "precision",
            format!("precision: {bits} bits is above the 106 this build computes with"),
        )),
    }
}

fn flow_in<I: Ival + OutwardDecimal>(
    bits: u32,
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: &At,
    jacobian: bool,
    opts: &FlowOptions,
) -> Result<Answer, Error> {
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

fn decimals<I: OutwardDecimal>(x: &[I]) -> Vec<DecimalInterval> {
    x.iter().map(|v| v.decimal()).collect()
}
