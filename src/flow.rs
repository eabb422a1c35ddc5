//! The validated flow of a mechanical system ([spec/05-enclosure.md](crate::spec::enclosure), Theorem 5.1, eq.
//! (5.16)): a `Model`'s reduced equations carried by the generic validated integrator of
//! the generic validated ODE layer (`enclosure`, [spec chapter 5](crate::spec::enclosure)), from a state `(q, u)` given as exact f64, with the checks every
//! query makes (dimensions, finite numbers, the scene at `q`, [spec (3.17)](crate::spec::scenes)).

use crate::enclosure::{
    flow_set_jacobian_explained, flow_set_span_memo, too_many, FlowOptions, FlowStats, Ival,
    LohnerSet, Memo,
};
use crate::interval::{wrap, wrap_rows};
use crate::model::Model;
use crate::progress::Progress;
use crate::scalar::point;
use crate::{Error, InputKind, Interval, Limit, Reason};

/// The certified state at time t: intervals of [`Interval`] (53 bits) by default, or of
/// another interval type ([`flow_at_in`], [spec/12-precision.md](crate::spec::precision)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct FlowEnclosure<I = Interval> {
    /// Contains the exact configuration `q(t)` (n intervals).
    pub q: Vec<I>,
    /// Contains the exact quasi-velocities `u(t)` in the scene's basis of D (n - k intervals).
    pub u: Vec<I>,
    /// Contains the exact velocity `qd(t) = E(q(t))^T u(t)` (n intervals, [spec eq. (4.2)](crate::spec::dynamics)).
    pub v: Vec<I>,
    /// What the integrator did between 0 and `t`.
    pub stats: FlowStats,
}

/// Enclosure of the exact nonholonomic state at time `t` from `q(0) = q`,
/// `qd(0) = sum_a u_a e_a(q)`.
///
/// # Containment
/// For the exact f64 inputs, the returned `q`, `u`, `v` contain the exact `q(t)`, the
/// quasi-velocities `u(t)` and `qd(t) = E(q(t))^T u(t)` of the trajectory ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves));
/// the trajectory is proved to exist between 0 and `t`. A negative `t` flows backward ([spec
/// (5.17)](crate::spec::enclosure)). Fails with `Error::Input` for malformed input and `Error::Uncertified` when a
/// step cannot be proved: singular data near the state reached ([`Reason::Undefined`],
/// naming them, [spec (5.18)](crate::spec::enclosure)), blow-up, too many steps ([`Reason::Budget`]); never with a
/// box that was not proved.
///
/// # Example
/// ```
/// use dalembert::{flow, AnyScene, FlowOptions, Model};
/// let model = Model::new(&AnyScene::new("particle", &[])?)?;
/// // q(0) = 0, qd(0) = 0.8 e_1(0) + 0.8 e_2(0); on the particle y(t) = 0.8 t exactly
/// let e = flow(&model, &[0.0, 0.0, 0.0], &[0.8, 0.8], 2.0, &FlowOptions::default())?;
/// assert!(e.q[1].contains(1.6) && e.u[1].contains(0.8));
/// assert!(e.q.iter().chain(&e.v).all(|x| x.wid() < 1e-12));
/// # Ok::<(), dalembert::Error>(())
/// ```
pub fn flow(
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Result<FlowEnclosure, Error> {
    let mut at = flow_at(model, q, u, &[t], opts)?;
    at.pop()
        .ok_or_else(|| Error::internal_at(crate::Invariant::Missing, "flow_at answered no time"))
}

/// Dense output: enclosures of the exact nonholonomic state at each of the increasing
/// times `t_1 < t_2 < ...` from `q(0) = q`, `qd(0) = sum_a u_a e_a(q)`, in one
/// validated integration each way: the set at `t_i >= 0` is carried on to `t_{i+1}` over
/// the span `t_{i+1} - t_i`, enclosed by outward rounding ([spec eq. (5.16)](crate::spec::enclosure)); the times
/// below 0 are reached the same way by the time-reversed field from 0 down, nearest
/// first ([spec (5.17)](crate::spec::enclosure)). Each answer's `stats` count the steps from 0 to its time. [`flow`]
/// is the one-time case.
///
/// # Containment
/// For the exact f64 inputs, the `i`-th enclosure contains the exact `q(t_i)`, `u(t_i)`,
/// `qd(t_i)` ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves), eqs. (5.16), (5.17)); the trajectory is proved to exist on
/// `[min(0, t_1), max(0, t_last)]`. `Error::Input` for malformed input (no times, a time
/// not finite, times not strictly increasing); `Error::Uncertified` as [`flow`].
pub fn flow_at(
    model: &Model,
    q: &[f64],
    u: &[f64],
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure>, Error> {
    let at = flow_at_in::<inari::Interval>(model, q, u, times, opts)?;
    Ok(at.into_iter().map(answer).collect())
}

/// The enclosure in the answers' intervals.
fn answer(e: FlowEnclosure<inari::Interval>) -> FlowEnclosure {
    FlowEnclosure {
        q: wrap(e.q),
        u: wrap(e.u),
        v: wrap(e.v),
        stats: e.stats,
    }
}

/// [`flow_at`] computed in the interval type `I` (e.g. [`crate::precision::dd::DdInterval`],
/// about 106 bits): the same method, steps and proofs ([spec/12-precision.md](crate::spec::precision)), with
/// the rounding level, the Taylor order and the tolerances of `I`'s precision.
///
/// # Containment
/// As [`flow_at`]: for the exact f64 inputs, the `i`-th enclosure contains the exact
/// `q(t_i)`, `u(t_i)`, `qd(t_i)` ([spec Theorem 5.1](crate::spec::enclosure#theorem-51-what-flow-proves)), whatever `I`, since every
/// operation of `I` encloses its real result ([`Ival`]).
pub fn flow_at_in<I: Ival>(
    model: &Model,
    q: &[f64],
    u: &[f64],
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure<I>>, Error> {
    flow_at_certified_in(model, q, u, times, opts).map_err(|r| r.error)
}

/// A dense flow refused at some stop: the stops certified before the refusal, each with
/// its time (contract E25), and the refusal.
#[derive(Clone, Debug)]
pub struct Refused<I = Interval> {
    /// The stops proved before the refusal, in the order of the times given: `(t, the
    /// enclosure at t)`, as [`flow_at_in`] would answer them (empty when none).
    pub at: Vec<(f64, FlowEnclosure<I>)>,
    /// Why the rest was not answered.
    pub error: Error,
}

/// A refusal before any stop was proved.
impl<I> From<Error> for Refused<I> {
    fn from(error: Error) -> Refused<I> {
        Refused {
            at: Vec::new(),
            error,
        }
    }
}

/// [`flow_at_in`], keeping on a refusal the stops proved before it ([`Refused`]).
///
/// # Containment
/// As [`flow_at_in`], for the answer and for every stop of a refusal's `at`: each is the
/// same enclosure [`flow_at_in`] computes for that time when it answers, proved before the
/// refusal (a later failure does not undo an earlier proof: each leg starts from the set
/// proved at the stop before it, [spec eq. (5.16)](crate::spec::enclosure)).
pub fn flow_at_certified_in<I: Ival>(
    model: &Model,
    q: &[f64],
    u: &[f64],
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure<I>>, Refused<I>> {
    let t = first_time(times)?;
    let x = flow_query(model, q, u, t)?;
    flow_from(model, &LohnerSet::<I>::point(&x), times, opts)
}

/// [`flow_at_certified_in`] in the answers' intervals (f64).
pub fn flow_at_certified(
    model: &Model,
    q: &[f64],
    u: &[f64],
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure>, Refused> {
    flow_at_certified_in::<inari::Interval>(model, q, u, times, opts)
        .map(|at| at.into_iter().map(answer).collect())
        .map_err(|r| Refused {
            at: r.at.into_iter().map(|(t, e)| (t, answer(e))).collect(),
            error: r.error,
        })
}

/// [`flow_at_in`] from every state in the boxes `q`, `u` (of `I`'s precision: e.g. decimals
/// read as exact decimals and enclosed, [spec (12.0.5)](crate::spec::precision)). The scene is checked on the
/// boxes ([spec eq. (3.17)](crate::spec::scenes)).
///
/// # Containment
/// As [`flow_at_in`], for every initial state in the boxes: the `i`-th enclosure contains
/// `q(t_i)`, `u(t_i)`, `qd(t_i)` of the flow from each of them.
pub fn flow_boxes_in<I: Ival>(
    model: &Model,
    q: &[I],
    u: &[I],
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure<I>>, Error> {
    flow_boxes_certified_in(model, q, u, times, opts).map_err(|r| r.error)
}

/// [`flow_boxes_in`], keeping on a refusal the stops proved before it ([`Refused`]).
///
/// # Containment
/// As [`flow_boxes_in`] and [`flow_at_certified_in`].
pub fn flow_boxes_certified_in<I: Ival>(
    model: &Model,
    q: &[I],
    u: &[I],
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure<I>>, Refused<I>> {
    let start = boxes_start(model, q, u, times)?;
    flow_from(model, &start, times, opts)
}

/// The initial set of [`flow_boxes_in`], after its checks: the query's (at the boxes'
/// midpoints), finite boxes, and the scene on the boxes ([spec eq. (3.17)](crate::spec::scenes)).
fn boxes_start<I: Ival>(
    model: &Model,
    q: &[I],
    u: &[I],
    times: &[f64],
) -> Result<LohnerSet<I>, Error> {
    let mid = |x: &[I]| x.iter().map(|v| v.mid()).collect::<Vec<f64>>();
    let t = first_time(times)?;
    flow_query(model, &mid(q), &mid(u), t)?;
    if !q.iter().chain(u).all(|x| x.is_finite()) {
        return Err(Error::input_at(
            InputKind::Number("state".into()),
            "a component of the state is not a finite interval",
        ));
    }
    model.check_at(
        &q.iter()
            .map(|x| crate::scalar::iv(x.inf(), x.sup()))
            .collect::<Vec<_>>(),
    )?;
    let x: Vec<I> = q.iter().chain(u).copied().collect();
    Ok(LohnerSet::from_box(&x))
}

fn first_time(times: &[f64]) -> Result<f64, Error> {
    times
        .first()
        .copied()
        .ok_or_else(|| Error::input_at(InputKind::Times, "no time given: at least one is needed"))
}

/// The flow of the checked initial set `start` to each of `times` (backward for those below 0).
fn flow_from<I: Ival>(
    model: &Model,
    start: &LohnerSet<I>,
    times: &[f64],
    opts: &FlowOptions,
) -> Result<Vec<FlowEnclosure<I>>, Refused<I>> {
    for (i, w) in times.windows(2).enumerate() {
        if !w[1].is_finite() || w[1] <= w[0] {
            return Err(Refused::from(Error::input_at(
                InputKind::Times,
                format!(
                    "times must be finite and strictly increasing (t_{} = {}, t_{} = {})",
                    i + 1,
                    w[0],
                    i + 2,
                    w[1]
                ),
            )));
        }
    }
    // times below 0 backward (by the reversed field, nearest first), the others forward
    let split = times.partition_point(|t| *t < 0.0);
    let back: Vec<f64> = times[..split].iter().rev().map(|t| -t).collect();
    let mut out = Vec::with_capacity(times.len());
    let mut steps = 0;
    // a refusal keeps the stops proved before it, with their times (contract E25)
    let refused = |done: Vec<FlowEnclosure<I>>, at: &[f64], error| Refused {
        at: at.iter().copied().zip(done).collect(),
        error,
    };
    if !back.is_empty() {
        let (mut e, s) = carry::<I>(model, model.reversed(), -1.0, start.clone(), &back, opts)
            .map_err(|(mut done, error)| {
                let at: Vec<f64> = times[..split].iter().rev().copied().collect();
                let mut r = refused(std::mem::take(&mut done), &at, error);
                r.at.reverse();
                r
            })?;
        e.reverse();
        out.extend(e);
        steps = s;
    }
    if split < times.len() {
        let rest = FlowOptions {
            max_taylor_steps: opts.max_taylor_steps.saturating_sub(steps),
            ..opts.clone()
        };
        let forward = carry::<I>(
            model,
            &model.dynamics,
            1.0,
            start.clone(),
            &times[split..],
            &rest,
        );
        match forward {
            Ok((e, _)) => out.extend(e),
            Err((done, error)) => {
                out.extend(done);
                return Err(refused(out, times, error));
            }
        }
    }
    Ok(out)
}

/// What [`carry`] hands back: the enclosures at the times and the steps taken, or on a
/// refusal the enclosures proved before it and the refusal.
type Carried<I> = Result<(Vec<FlowEnclosure<I>>, usize), (Vec<FlowEnclosure<I>>, Error)>;

/// The enclosures at the increasing times `times >= 0` of the flow of `sys` from the set
/// `set`: the model's field (`sign` 1) or the reversed one (`sign` -1, the times then measured
/// backward: a refusal's `reached` and message carry the sign). Also the steps taken.
fn carry<I: Ival>(
    model: &Model,
    sys: &crate::enclosure::System,
    sign: f64,
    mut set: LohnerSet<I>,
    times: &[f64],
    opts: &FlowOptions,
) -> Carried<I> {
    let last = *times.last().ok_or_else(|| {
        (
            Vec::new(),
            Error::input("no time given: at least one is needed"),
        )
    })?;
    let mut total = FlowStats::default();
    let mut out = Vec::with_capacity(times.len());
    let mut from = 0.0;
    // the step rule's memory and the steps' product form, carried from one stop to the next
    let mut memo = Memo::default();
    for &t in times {
        // the progress of a leg, as a fraction of the whole span [0, t_last]
        let leg = FlowOptions {
            progress: if opts.progress.is_silent() {
                Progress::default()
            } else {
                let p = opts.progress.clone();
                Progress::new(move |what, done, total| {
                    let f = if total > 0.0 { done / total } else { 1.0 };
                    p.tell(what, from + f * (t - from), last)
                })
            },
            max_taylor_steps: opts.max_taylor_steps.saturating_sub(total.steps),
            ..opts.clone()
        };
        // why the steps collapsed, if the scene's data say so; the leg's start (its centre)
        // for the float motion that tells a box grown too wide from the motion's own failure
        let start: Vec<f64> = set.m.iter().map(|x| I::pt_f64(*x)).collect();
        let motion = Motion::new(sys, &start, t - from);
        let explain = |x: &[inari::Interval], h: f64, done: f64, spent: Option<&Error>| {
            let at = sign * (point(from) + point(done)).inf();
            why_stopped(model, x, (h, at), &motion, spent)
        };
        // the exact span t - from, enclosed (exact when Sterbenz's lemma applies)
        let span = I::cst(t) - I::cst(from);
        let flown =
            flow_set_span_memo(sys, set, span, &leg, &mut memo, Some(&explain)).map_err(|e| {
                match &e {
                    // proved up to `from` and then up to `reached` into the leg
                    Error::Uncertified(r) => {
                        let reached = (point(from) + point(r.reached.unwrap_or(0.0))).inf();
                        // the step limit is the whole integration's: say so with its end
                        let e = if r.limit == Some(Limit::TaylorSteps) {
                            let whole = too_many(opts.max_taylor_steps, sign * last);
                            if r.message.ends_with(OUTGROWN) {
                                whole.with_cause(r.cause).with_more(OUTGROWN)
                            } else {
                                whole
                            }
                        } else {
                            e
                        };
                        e.reached(sign * reached)
                    }
                    _ => e,
                }
            });
        let (next, stats) = match flown {
            Ok(x) => x,
            Err(e) => return Err((out, e)),
        };
        set = next;
        total = FlowStats {
            order: stats.order,
            steps: total.steps + stats.steps,
            rejected: total.rejected + stats.rejected,
            h_min: if out.is_empty() || total.steps == 0 {
                stats.h_min
            } else if stats.steps == 0 {
                total.h_min
            } else {
                total.h_min.min(stats.h_min)
            },
            h_max: total.h_max.max(stats.h_max),
        };
        match finish(model, &set, total.clone()) {
            Ok(e) => out.push(e),
            Err(e) => return Err((out, e.reached(sign * t))),
        }
        from = t;
    }
    Ok((out, total.steps))
}

/// Why a flow of `sys` from `start` over `span` (a leg of a flow of `model`) stopped in the
/// box `x` at the time `at` with steps of size `h` (the [`Explain`](crate::enclosure::Explain)
/// of its flows): the scene's data failing near the state (E17, [`explained`], with the cause
/// `width` when the box had grown too wide, [`widened`]), else, when the flow stopped with the
/// refusal `spent`, that refusal with the cause `width` when a float solution is regular
/// ([`outgrown`]). `spent` is the step limit's, or (reason `no_proof`) the sign of a box grown
/// wider than [`WIDEST`](crate::model::WIDEST) with collapsed steps ([spec
/// (5.18'')](crate::spec::enclosure)): that one is refused, cause `width`, when the box's
/// configuration is that wide and a float solution is regular up to the time asked; `None`
/// otherwise (the flow goes on: a box wide in its velocities alone, or a motion that may
/// itself fail, is left to the data's checks).
fn why_stopped(
    model: &Model,
    x: &[inari::Interval],
    (h, at): (f64, f64),
    motion: &Motion<'_>,
    spent: Option<&Error>,
) -> Option<Error> {
    if spent.is_some_and(|e| e.reason() == Some(Reason::NoProof)) {
        let (name, w) = widest(model, x)?;
        if !motion.regular() {
            return None;
        }
        return Some(
            Error::refused(
                Reason::NoProof,
                format!(
                    "the enclosure grew too wide at t = {at}: {name} has width {w:e} (steps of \
                     {h:e}); its steps had collapsed and a float solution is regular up to the \
                     time asked: a higher precision (--precision 106) may answer"
                ),
            )
            .with_cause(crate::Cause::Width),
        );
    }
    explained(model, x, h, at)
        .map(|e| widened(model, x, motion, e))
        .or_else(|| spent.and_then(|e| outgrown(motion, e)))
}

/// The float motion of a leg, from the centre `start` of its initial set over `span`: whether
/// it is regular is what tells a box grown too wide from the motion's own failure (it only
/// words a refusal: nothing proved depends on it).
struct Motion<'a> {
    sys: &'a crate::enclosure::System,
    start: &'a [f64],
    span: f64,
    regular: std::cell::OnceCell<bool>,
}

impl<'a> Motion<'a> {
    fn new(sys: &'a crate::enclosure::System, start: &'a [f64], span: f64) -> Motion<'a> {
        let regular = std::cell::OnceCell::new();
        Motion {
            sys,
            start,
            span,
            regular,
        }
    }

    /// Whether the float motion of `sys` from `start` is carried over the whole `span`, with
    /// finite values and within the step limit (computed once).
    fn regular(&self) -> bool {
        *self.regular.get_or_init(|| {
            let opts = FlowOptions::default();
            crate::enclosure::float_flow_counted(self.sys, self.start, self.span, &opts).is_some()
        })
    }
}

/// Whether some coordinate `q_i` of the box `x` (whose first `n` components are the
/// configuration) is wider than `2^-6 (1 + |q_i|)` (or not a number).
fn too_wide(model: &Model, x: &[inari::Interval]) -> bool {
    widest(model, x).is_some()
}

/// The name and width of the first coordinate `q_i` of the box `x` wider than
/// `2^-6 (1 + |q_i|)` (or not a number), if any.
fn widest<'a>(model: &'a Model, x: &[inari::Interval]) -> Option<(&'a str, f64)> {
    x.iter()
        .take(model.n)
        .zip(model.coordinates())
        .find(|(q, _)| q.wid().is_nan() || q.wid() > crate::model::WIDEST * (1.0 + q.mag()))
        .map(|(q, name)| (name.as_str(), q.wid()))
}

/// The refusal `e` of the scene's data on the box `x` reached by a leg from `start` (the
/// centre of its initial set) over the time `span`, with the cause `width` when the box grew
/// too wide while the motion stays where the data hold ([spec (5.18')](crate::spec::enclosure)):
/// some coordinate of the box is wider than `2^-6 (1 + |q_i|)` (the widest box
/// [`Model::explain_stop`] trusts its checks on), and the float motion of `sys` from `start`
/// (not rigorous: it only words the refusal) is carried over the whole `span`, with finite
/// values and within the step limit. Otherwise the cause stays the data's.
fn widened(model: &Model, x: &[inari::Interval], motion: &Motion<'_>, e: Error) -> Error {
    if !too_wide(model, x) || !motion.regular() {
        return e;
    }
    e.with_cause(crate::Cause::Width).with_more(
        "; the enclosure grew too wide before the motion came near where the scene fails (a \
         float solution is regular up to the time asked): a higher precision (--precision \
         106) may answer",
    )
}

/// The step budget's refusal `e` of a leg from `start` over the time `span` whose steps
/// collapsed while the scene's data hold near the state, with the cause `width` when the
/// float motion of `sys` from `start` (not rigorous: it only words the refusal) is carried
/// over the whole `span`, with finite values and within the step limit: the enclosure grew
/// too fast for any step, not the motion ([spec (5.18')](crate::spec::enclosure)). `None`
/// otherwise (the refusal stays the budget's, cause `steps`). The reason stays `budget`
/// (contract E17: no cause was found near the state).
fn outgrown(motion: &Motion<'_>, e: &Error) -> Option<Error> {
    if !motion.regular() {
        return None;
    }
    Some(
        e.clone()
            .with_cause(crate::Cause::Width)
            .with_more(OUTGROWN),
    )
}

/// The end of the message of [`outgrown`]'s refusal.
const OUTGROWN: &str = "; its steps collapsed while the scene's data hold near the state and a \
                        float solution is regular up to the time asked: the enclosure grew too \
                        fast for any step, and a higher precision (--precision 106) may answer";

/// The refusal of a flow stopped at time `at` in the state box `x` with steps of size `h`
/// (0: none taken), when the scene's data say why ([spec (5.18)](crate::spec::enclosure)).
fn explained(model: &Model, x: &[inari::Interval], h: f64, at: f64) -> Option<Error> {
    let (cause, why) = model.explain_stop(x, h)?;
    // (+ 0.0: a start backward is at t = 0, not -0)
    let at = at + 0.0;
    let steps = if h > 0.0 {
        format!("steps of {h:e}")
    } else {
        "no step taken".to_string()
    };
    Some(
        Error::refused(
            Reason::Undefined,
            format!("the flow cannot be carried on at t = {at} ({steps}): {why}"),
        )
        .with_cause(cause),
    )
}

/// The initial state `x = (q, u)` of a flow query, after the checks every flow makes: the
/// state (dimensions, finite numbers), the scene at `q` ([spec eq. (3.17)](crate::spec::scenes)), and `t` finite
/// (of either sign: a negative time flows backward, [spec (5.17)](crate::spec::enclosure)).
fn flow_query(model: &Model, q: &[f64], u: &[f64], t: f64) -> Result<Vec<f64>, Error> {
    check_state(model, q, u)?;
    model.check_at(
        &q.iter()
            .map(|x| crate::scalar::point(*x))
            .collect::<Vec<_>>(),
    )?;
    if !t.is_finite() {
        return Err(Error::input_at(
            InputKind::Number("t".into()),
            format!("time must be finite and >= 0 (got {t})"),
        ));
    }
    Ok(q.iter().chain(u).copied().collect())
}

/// Validate dimensions and finiteness of a state.
pub fn check_state(model: &Model, q: &[f64], u: &[f64]) -> Result<(), Error> {
    let (n, m) = (model.n, model.n - model.k);
    if q.len() != n {
        let at = InputKind::Dimension {
            what: "q".into(),
            got: q.len(),
            expected: n,
        };
        return Err(Error::input_at(
            at,
            format!(
                "q has {} components, scene `{}` needs {n}",
                q.len(),
                model.name()
            ),
        ));
    }
    if u.len() != m {
        let at = InputKind::Dimension {
            what: "u".into(),
            got: u.len(),
            expected: m,
        };
        return Err(Error::input_at(
            at,
            format!(
                "u has {} components, scene `{}` needs {m}",
                u.len(),
                model.name()
            ),
        ));
    }
    if let Some(x) = q.iter().chain(u).find(|x| !x.is_finite()) {
        return Err(Error::input_at(
            InputKind::Number("state".into()),
            format!("non-finite number {x} in the state"),
        ));
    }
    Ok(())
}

fn finish<I: Ival>(
    model: &Model,
    set: &LohnerSet<I>,
    stats: FlowStats,
) -> Result<FlowEnclosure<I>, Error> {
    let x = set.hull();
    let v = set
        .image(&model.velocity_jac)
        .ok_or_else(|| Error::refused(Reason::Unbounded, "velocity enclosure is not finite"))?;
    Ok(FlowEnclosure {
        q: x[..model.n].to_vec(),
        u: x[model.n..].to_vec(),
        v,
        stats,
    })
}

/// The state and the derivative `D (q, u)(t) / D (q, u)(0)` ((n+m) x (n+m) intervals,
/// rows and columns in the order q then u) of the trajectory from the exact f64 `(q, u)`.
///
/// # Containment
/// Theorem 5.1 for the state, and the true derivative lies in the returned matrix ([spec
/// Theorem 5.3](crate::spec::enclosure)); a negative `t` flows backward ([spec (5.17)](crate::spec::enclosure)). Fails as [`flow`] does.
pub fn flow_c1(
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Result<(FlowEnclosure, Vec<Vec<Interval>>), Error> {
    let (e, jac) = flow_c1_in::<inari::Interval>(model, q, u, t, opts)?;
    Ok((answer(e), wrap_rows(jac)))
}

/// [`flow_c1`] computed in the interval type `I` (as [`flow_at_in`]).
///
/// # Containment
/// As [`flow_c1`], whatever `I` ([spec/12-precision.md](crate::spec::precision)).
pub fn flow_c1_in<I: Ival>(
    model: &Model,
    q: &[f64],
    u: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Result<(FlowEnclosure<I>, Vec<Vec<I>>), Error> {
    let x0 = flow_query(model, q, u, t)?;
    // backward: the reversed field over |t| (spec (5.17)), whose derivative is that of the
    // flow over t
    let (sys, sign) = if t < 0.0 {
        (model.reversed(), -1.0)
    } else {
        (&model.dynamics, 1.0)
    };
    let motion = Motion::new(sys, &x0, t.abs());
    let explain = |x: &[inari::Interval], h: f64, done: f64, spent: Option<&Error>| {
        why_stopped(model, x, (h, sign * done), &motion, spent)
    };
    let (set, jac, stats) = flow_set_jacobian_explained(
        sys,
        LohnerSet::<I>::point(&x0),
        t.abs(),
        opts,
        Some(&explain),
    )
    .map_err(|e| match e {
        Error::Uncertified(ref r) if sign < 0.0 => {
            let reached = -r.reached.unwrap_or(0.0);
            // the step limit's message with the time asked for
            let e = if r.limit == Some(Limit::TaylorSteps) {
                too_many(opts.max_taylor_steps, t)
            } else {
                e
            };
            e.reached(reached)
        }
        e => e,
    })?;
    Ok((finish(model, &set, stats)?, jac.to_rows()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::AnyScene;

    #[test]
    fn answers_debug_print_intervals_as_endpoints() {
        let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
        let e = flow(&model, &[0.0; 3], &[0.8, 0.8], 1.0, &FlowOptions::default()).unwrap();
        let text = format!("{e:?}");
        assert!(!text.contains("m128") && !text.contains("rep"), "{text}");
        // the first component printed as its two exact endpoints
        let x = e.q[0];
        assert!(
            text.starts_with(&format!(
                "FlowEnclosure {{ q: [[{:?}, {:?}]",
                x.inf(),
                x.sup()
            )),
            "{text}"
        );
    }

    #[test]
    fn progress_is_told_a_rising_fraction_ending_at_one_and_changes_nothing() {
        use std::sync::{Arc, Mutex};
        let model = Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap();
        let seen = Arc::new(Mutex::new(Vec::new()));
        let s2 = seen.clone();
        let opts = FlowOptions {
            progress: Progress::new(move |what, done, total| {
                assert_eq!((what, total), ("flow", 5.0));
                s2.lock().unwrap().push(done / total)
            }),
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
    fn an_overflowing_point_step_is_refused_also_with_fixed_steps() {
        // x + u1 t overflows: the image of the point is not finite. With fixed steps the
        // width tolerances of (5.8) are off, so only the finiteness check stands between
        // this and an answer with an infinite endpoint.
        let model = Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap();
        for fixed_h in [None, Some(1.0)] {
            let opts = FlowOptions {
                fixed_h,
                ..FlowOptions::default()
            };
            let r = flow(&model, &[f64::MAX, 0.0, 0.0], &[1e300, 0.0], 1.0, &opts);
            match r {
                Err(Error::Uncertified(_)) => {}
                Ok(e) => panic!("answered with {:?}", e.q),
                Err(e) => panic!("{e}"),
            }
        }
    }

    #[test]
    fn particle_with_zero_y_speed_moves_on_a_line() {
        let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
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
