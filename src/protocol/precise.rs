//! Answers computed with more than 53 bits ([spec/12-precision.md](crate::spec::precision), contract E18): the
//! query's precision picks the interval type, the generic functions ([`crate::flow::flow_at_in`],
//! [`crate::exact::retract_in`], ...) compute in it, and the ends are printed as decimals
//! rounded outward ([`crate::OutwardDecimal`]).

use super::{Answer, At, Query, SceneSpec, Steps, Tolerances};
use crate::enclosure::{FlowOptions, Ival};
use crate::exact::{
    discrete_lagrangian_box_in, discrete_lagrangian_in, retract_box_in, retract_in, step_box_in,
    step_in,
};
use crate::flow::{
    flow_at_certified_in, flow_boxes_certified_in, flow_c1_in, FlowEnclosure, Refused,
};
use crate::model::Model;
use crate::oracle::{check_rows_in, CheckOptions};
use crate::precision::dd::DdInterval;
use crate::precision::wide::{self, WideInterval};
use crate::{DecimalInterval, Error, OutwardDecimal};

/// The scene of a query that reads `precision`; an input error for the others.
pub(super) fn scene(query: &Query) -> Result<&SceneSpec, Error> {
    match query {
        Query::Flow { scene, .. } | Query::Order { scene, .. } | Query::Check { scene, .. } => {
            Ok(scene)
        }
        Query::Retract(p) | Query::Step(p) | Query::Lagrangian(p) => Ok(&p.scene),
        _ => Err(not_read()),
    }
}

fn not_read() -> Error {
    Error::input_key(
        "precision",
        "`precision` is read by flow, retract, step, lagrangian, order and check only",
    )
}

/// The answer to `query` (flow, retract, step, lagrangian or order) at `bits > 53` significand bits:
/// double-double intervals up to 106 bits, [`WideInterval`]s at exactly `bits` up to 512.
pub(crate) fn answer(
    bits: u32,
    model: &Model,
    query: &Query,
    decimals: Option<&[Vec<String>]>,
    opts: &FlowOptions,
    certified: &mut Option<Answer>,
) -> Result<Answer, Error> {
    match bits {
        54..=106 => answer_in::<DdInterval>(106, model, query, decimals, opts, certified),
        wide::MIN_BITS..=wide::MAX_BITS => wide::with_bits(bits, || {
            answer_in::<WideInterval>(bits, model, query, decimals, opts, certified)
        }),
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

/// The decimal texts read as exact decimals enclosed in `I` (contract E22): one vector of
/// boxes per text vector.
fn exact_boxes<I: Ival>(decimals: &[Vec<String>]) -> Result<Vec<Vec<I>>, Error> {
    decimals
        .iter()
        .map(|v| {
            v.iter()
                .map(|s| {
                    I::from_decimal(s.trim()).ok_or_else(|| {
                        Error::input_key(
                            "exact-decimals",
                            format!("--exact-decimals: `{s}` is not a decimal number"),
                        )
                    })
                })
                .collect()
        })
        .collect()
}

/// `query` with its vectors read as exact decimals (contract E22).
fn answer_exact<I>(
    bits: u32,
    model: &Model,
    query: &Query,
    decimals: &[Vec<String>],
    opts: &FlowOptions,
    certified: &mut Option<Answer>,
) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
    I::Public: OutwardDecimal,
{
    let boxes = exact_boxes::<I>(decimals)?;
    let [a, b] = boxes.as_slice() else {
        return Err(Error::input_key(
            "exact-decimals",
            "--exact-decimals reads the two vectors of flow, retract, step and lagrangian",
        ));
    };
    match query {
        Query::Flow {
            t, order, jacobian, ..
        } => {
            let o = FlowOptions {
                order: (*order > 0).then_some(*order),
                ..opts.clone()
            };
            flow_in::<I>(bits, model, Start::Boxes(a, b), t, *jacobian, &o, certified)
        }
        Query::Retract(p) => {
            retract_answer::<I>(bits, retract_box_in::<I>(model, a, b, p.h, opts)?)
        }
        Query::Step(p) => step_answer::<I>(bits, step_box_in::<I>(model, a, b, p.h, opts)?),
        Query::Lagrangian(p) => lagrangian_answer(
            bits,
            discrete_lagrangian_box_in::<I>(model, a, b, p.h, opts)?,
        ),
        _ => Err(Error::input_key(
            "exact-decimals",
            "--exact-decimals is read by flow, retract, step and lagrangian only",
        )),
    }
}

fn retract_answer<I>(bits: u32, r: crate::exact::Retraction<I>) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
    I::Public: OutwardDecimal,
{
    Ok(Answer::RetractWide {
        precision: bits,
        possibly_member: r.s.iter().all(|x| I::from_public(x.clone()).contains(0.0)),
        u0: decimals_of(&r.u0),
        v0: decimals_of(&r.v0),
        v1: decimals_of(&r.v1),
        s: decimals_of(&r.s),
        q1: decimals_of(&r.q1),
    })
}

fn lagrangian_answer<I, L: OutwardDecimal>(
    bits: u32,
    (r, l): (crate::exact::Retraction<I>, L),
) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
    I::Public: OutwardDecimal,
{
    Ok(Answer::LagrangianWide {
        precision: bits,
        l: l.decimal(),
        s: decimals_of(&r.s),
    })
}

fn step_answer<I>(bits: u32, s: crate::exact::ExactStep<I>) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
    I::Public: OutwardDecimal,
{
    Ok(Answer::StepWide {
        precision: bits,
        q1: decimals_of(&s.q1),
        q2: decimals_of(&s.q2),
        p_minus: decimals_of(&s.p_minus),
        p_plus: decimals_of(&s.p_plus),
    })
}

fn answer_in<I>(
    bits: u32,
    model: &Model,
    query: &Query,
    decimals: Option<&[Vec<String>]>,
    opts: &FlowOptions,
    certified: &mut Option<Answer>,
) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
    I::Public: OutwardDecimal,
{
    if let Some(d) = decimals {
        return answer_exact::<I>(bits, model, query, d, opts, certified);
    }
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
            flow_in::<I>(
                bits,
                model,
                Start::Points(q, u),
                t,
                *jacobian,
                &o,
                certified,
            )
        }
        Query::Retract(p) => {
            retract_answer::<I>(bits, retract_in::<I>(model, &p.q0, &p.q1, p.h, opts)?)
        }
        Query::Step(p) => step_answer::<I>(bits, step_in::<I>(model, &p.q0, &p.q1, p.h, opts)?),
        Query::Lagrangian(p) => lagrangian_answer(
            bits,
            discrete_lagrangian_in::<I>(model, &p.q0, &p.q1, p.h, opts)?,
        ),
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
        Query::Check {
            steps,
            q,
            tol,
            defect_tol,
            pairs,
            ..
        } => check_in::<I>(bits, model, steps, q, (*tol, *defect_tol), *pairs, opts),
        _ => Err(not_read()),
    }
}

/// A batch `check` at `bits` (contract E28): the exact discrete flow, the retractions and
/// the energies computed in `I` by [`check_rows_in`], every figure rounded outward to an f64
/// interval, as `check --precision` (E21) computes them.
fn check_in<I: Ival>(
    bits: u32,
    model: &Model,
    steps: &Steps,
    q: &[Vec<f64>],
    (tol, defect_tol): (Option<f64>, Option<f64>),
    pairs: bool,
    opts: &FlowOptions,
) -> Result<Answer, Error> {
    let tolerances = Tolerances { tol, defect_tol };
    tolerances.require_pairs(pairs)?;
    let o = CheckOptions {
        pairs,
        flow: opts.clone(),
    };
    let (h, times) = match steps {
        Steps::Uniform(h) => (Some(*h), None),
        Steps::Times(t) => {
            if t.len() != q.len() {
                return Err(Error::input_at(
                    crate::InputKind::Times,
                    format!(
                        "{} times for {} rows: give one time per row",
                        t.len(),
                        q.len()
                    ),
                ));
            }
            (None, Some(t))
        }
    };
    let rows = q
        .iter()
        .enumerate()
        .map(|(k, r)| Ok::<_, Error>((times.map(|t| t[k]), r.clone())));
    let (mut distance, mut defect, mut energy_error) = (Vec::new(), Vec::new(), Vec::new());
    let summary = check_rows_in::<I>(model, h, rows, &o, |row| {
        distance.push(row.distance);
        if let Some(p) = row.pair {
            defect.push(p.defect);
            energy_error.push(p.energy_error);
        }
        Ok(())
    })?;
    let passed = tolerances.passes(summary.max_distance, summary.max_defect)?;
    Ok(Answer::CheckWide {
        precision: bits,
        distance,
        max_distance: summary.max_distance,
        defect,
        max_defect: summary.max_defect,
        energy_error,
        tolerances,
        passed,
    })
}

/// Where a flow starts: the query's f64 point `(q, u)`, or boxes (exact decimals, E22).
enum Start<'a, I> {
    Points(&'a [f64], &'a [f64]),
    Boxes(&'a [I], &'a [I]),
}

impl<I: Ival> Start<'_, I> {
    fn flow(
        &self,
        model: &Model,
        times: &[f64],
        opts: &FlowOptions,
    ) -> Result<Vec<FlowEnclosure<I>>, Refused<I>> {
        match self {
            Start::Points(q, u) => flow_at_certified_in::<I>(model, q, u, times, opts),
            Start::Boxes(q, u) => flow_boxes_certified_in::<I>(model, q, u, times, opts),
        }
    }
}

fn flow_in<I>(
    bits: u32,
    model: &Model,
    start: Start<'_, I>,
    t: &At,
    jacobian: bool,
    opts: &FlowOptions,
    certified: &mut Option<Answer>,
) -> Result<Answer, Error>
where
    I: Ival + OutwardDecimal,
{
    let dec = |e: FlowEnclosure<I>| FlowEnclosure {
        q: decimals_of(&e.q),
        u: decimals_of(&e.u),
        v: decimals_of(&e.v),
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
            let enclosures = start.flow(model, times, opts).map_err(|r| {
                // the stops proved before the refusal (contract E25)
                let (times, enclosures): (Vec<f64>, Vec<_>) =
                    r.at.into_iter().map(|(t, e)| (t, dec(e))).unzip();
                *certified = Some(Answer::FlowAtWide {
                    precision: bits,
                    times,
                    enclosures,
                });
                r.error
            })?;
            Ok(Answer::FlowAtWide {
                precision: bits,
                times: times.clone(),
                enclosures: enclosures.into_iter().map(dec).collect(),
            })
        }
        At::One(t) => {
            let (enclosure, jacobian) = if jacobian {
                let Start::Points(q, u) = start else {
                    return Err(Error::input_key(
                        "exact-decimals",
                        "--exact-decimals is not offered with --jacobian (the derivative is at a point)",
                    ));
                };
                let (e, j) = flow_c1_in::<I>(model, q, u, *t, opts)?;
                (e, Some(j.iter().map(|r| decimals_of(r)).collect()))
            } else {
                let mut e = start.flow(model, &[*t], opts).map_err(|r| r.error)?;
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

fn decimals_of<P: OutwardDecimal>(x: &[P]) -> Vec<DecimalInterval> {
    x.iter().map(|v| v.decimal()).collect()
}
