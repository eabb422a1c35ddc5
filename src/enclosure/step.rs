//! One step of the method ([spec eqs. (5.3)-(5.6)](crate::spec::enclosure), (5.9)-(5.12)): the a priori enclosure, the
//! Taylor polynomial and its remainder, the derivative factor and Lohner's update.

use super::ival::{rounded_to_f64, Ival};
use super::linalg::{self, IMat};
use super::options::{Basis, FlowOptions};
use super::set::*;
use super::system::System;
use crate::tape::{Coef, Coeffs, Rows};
use inari::Interval;
use nalgebra::DMatrix;

pub(super) enum StepFail {
    /// The a priori enclosure was not proved for this h: try a smaller one.
    Shrink,
    /// The remainder (5.5) was wider than its tolerance, by this factor (at least; from
    /// one slice when the others were skipped): try a smaller step (5.8).
    TooWide(f64),
    /// Nothing more can be proved from here.
    Fatal(String),
}

/// Number of time slices over which the remainder's coefficient is enclosed ([spec (5.5)](crate::spec::enclosure)).
pub(super) const SLICES: usize = 8;

/// How a try's remainder (5.5) is held to the tolerance ([spec (5.8)](crate::spec::enclosure)).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Tolerance {
    /// Accepted whatever its width (a fixed step (5.13), or after 12 tries).
    Loose,
    /// Rejected when wider than the tolerance, after slicing (5.5) if that is needed.
    Strict,
    /// Rejected when wider than the tolerance before slicing: the steps of a short rest
    /// (5.8) (d), where a shorter try costs less than the slices.
    Unsliced,
}

/// Largest accepted width of the Lagrange remainder, relative to the state's size, in
/// units of the rounding level [`Ival::eps`].
pub(super) const REMAINDER_TOL: f64 = 1.0;

/// Horner's scheme in intervals, for the components `cols` of every row at once: entry `i`
/// encloses `sum_k c_k[cols.start + i] t^k` for every `t` in `h` and every choice of
/// coefficients in the enclosures, with `c_k` the rows and then `top` if given (fused
/// multiply-adds, each outward rounded: [spec (1.4)](crate::spec::scalars)).
pub(super) fn horner<I: Ival>(
    rows: Rows<'_, I>,
    cols: std::ops::Range<usize>,
    top: Option<&[I]>,
    h: I,
) -> Vec<I> {
    let rows: Vec<&[I]> = rows
        .iter()
        .chain(top)
        .map(|r| &r[cols.clone()])
        .collect();
    I::horner(&rows, h)
}

/// What one step hands on.
pub(super) struct StepOut<I: Ival> {
    pub(super) set: LohnerSet<I>,
    /// For C^1 output: the step's derivative factor `[J]`, `[B'^{-1}][J B]` and
    /// `[B'^{-1}]` ([spec eq. (5.15)](crate::spec::enclosure)).
    pub(super) jac: Option<(IMat<I>, IMat<I>, IMat<I>)>,
    /// The basis `B'` that a reorganisation (5.10') replaced by `I`, if any.
    pub(super) rebased: Option<DMatrix<f64>>,
    /// The remainder's width relative to its tolerance (5.8).
    pub(super) ratio: f64,
    /// For the product form (5.10'''): the step's `[J]` and the enclosure of `x(h; m) - m'`
    /// (`None` for the image of a point set, which starts afresh).
    pub(super) link: Option<(DMatrix<f64>, Vec<I>)>,
}

/// The a priori enclosure (5.4) of the centre's trajectory proved by a rejected try of a
/// step: the box `y` holds the trajectory over `[0, span]`, so over every shorter span too,
/// and `ty` are the coefficients over it up to `order + 1` ([spec (5.4')](crate::spec::enclosure)).
pub(super) struct Prior<I> {
    span: f64,
    order: usize,
    y: Vec<I>,
    ty: Coeffs<I>,
}

/// One step of the method ([spec eqs. (5.3)-(5.6)](crate::spec::enclosure), (5.9)-(5.12)). `prior` carries the a
/// priori box of a rejected try to the next try of the same step (5.4').
#[allow(clippy::too_many_arguments)]
pub(super) fn lohner_step<I: Ival>(
    sys: &System,
    set: &LohnerSet<I>,
    c: Rows<'_, I>,
    h: I,
    p: usize,
    tol: Tolerance,
    c1_mode: super::control::C1,
    opts: &FlowOptions,
    high: bool,
    jac_order: &mut usize,
    prior: &mut Option<Prior<I>>,
) -> Result<StepOut<I>, StepFail> {
    use super::control::C1;
    let (c1, precise) = (c1_mode != C1::No, c1_mode == C1::Precise);
    let boxes64 = opts.box_series_in_f64;
    // the level the state is held to (12.0.10)
    let level = opts.level::<I>();
    let d = set.m.len();
    let fatal = |s: &str| StepFail::Fatal(s.to_string());
    if !set.r.iter().chain(&set.r0).all(|r| r.contains(0.0)) {
        return Err(fatal("internal invariant broken: 0 not in r"));
    }
    let scale = set.m.iter().fold(1.0f64, |a, x| a.max(I::pt_f64(*x).abs()));
    // (5.3) the Taylor polynomial at the centre (coefficients `c`)
    let phi = horner(c, 0..d, None, h);
    if tol != Tolerance::Loose && phi.iter().any(|x| x.wid() > scale * (16.0 * level)) {
        return Err(StepFail::Shrink);
    }
    let point_set = set.r.iter().chain(&set.r0).all(|r| r.is_exact_zero());
    // The hull, joined with the centre: the mean-value segments of (5.6b) run from `m`,
    // which the parallelepiped holds (0 in [r0], [r]) but its intersection with the box of
    // (5.12) need not
    let xbox: Vec<I> = set
        .hull()
        .iter()
        .zip(&set.m)
        .map(|(x, c)| x.convex_hull(I::pt(*c)))
        .collect();
    // `[X] - m`
    let spread = relative(&xbox, &set.m);
    // the size of x0 - m over the set
    let extent = xbox
        .iter()
        .zip(&set.m)
        .fold(0.0f64, |a, (x, c)| a.max((*x - I::pt(*c)).mag()));
    // z encloses x(h; m); x(h; x0) lies in z + J (x0 - m) for every x0 in the set.
    // (5.4)-(5.5) for the trajectory from the centre alone; the a priori box of an earlier
    // try of this step over a longer span serves this one (5.4'), else a new one
    let (y, ty) = match prior.take() {
        Some(pr) if pr.order == p && h.sup() <= pr.span => (pr.y, pr.ty),
        _ => a_priori(&sys.field, c, h, p, 0.0, boxes64, F64_SHARE * scale * level)?,
    };
    let (rem, ratio) = match remainder_over(sys, c, &y, &ty, h, p, scale * level, tol, boxes64) {
        Err(fail @ StepFail::TooWide(_)) => {
            *prior = Some(Prior {
                span: h.sup(),
                order: p,
                y,
                ty,
            });
            return Err(fail);
        }
        other => other?,
    };
    let z: Vec<I> = phi.iter().zip(&rem).map(|(a, b)| *a + *b).collect();
    if !z.iter().all(|x| x.is_finite()) {
        return Err(StepFail::Shrink);
    }
    // (5.10'') F(m) at a higher precision, where its width at this one costs the step's
    // error more than FINER_AT of the state's rounding level
    let coarse = c
        .iter()
        .nth(1)
        .is_some_and(|c1| c1[..d].iter().any(|x| x.wid() * h.sup() > FINER_AT * scale * level));
    let finer = coarse.then(|| I::field_finer(&sys.field, &set.m)).flatten();
    if point_set && !c1 {
        // a point set needs no Jacobian (J B r = 0 for r = 0)
        let image = point_image(set, z.clone());
        // (5.10''') its error for the product form: `x(h; m) - m_1` (`m_1 = mid(z)`, the
        // image's centre) from the increment, through the centre `m'` of (5.10''), and from z
        let (m_inc, _, err) = recentre(&set.m, c, h, &rem, &z, finer.as_deref());
        let err: Vec<I> = (0..d)
            .map(|i| {
                let by_z = z[i] - I::pt(image.m[i]);
                let by_incr = err[i] + (I::pt(m_inc[i]) - I::pt(image.m[i]));
                let both = by_z.intersection(by_incr);
                if both.is_empty() {
                    by_z
                } else {
                    both
                }
            })
            .collect();
        return Ok(StepOut {
            set: image,
            jac: None,
            rebased: None,
            ratio,
            link: Some((DMatrix::zeros(d, d), err)),
        });
    }
    // (5.6) the flow's Jacobian at the lowest order (from `jac_order` on) whose remainder
    // is negligible there; otherwise (5.6'') over the whole set.
    // A loose derivative (12.0.9) holds the step's factor to its own level
    let eps = match c1_mode {
        C1::Loose(eps) => eps.max(level),
        _ => level,
    };
    // [J] in f64 where (5.6''') passes; the linear part below then runs in f64 (5.10'''')
    let jac64 = match c1_mode {
        C1::Cheap | C1::Precise => None,
        C1::No | C1::Loose(_) => step_jacobian_in_f64(sys, &xbox, h, p, scale, extent, eps, jac_order),
    };
    let jac = match &jac64 {
        Some(j) => Some(exact_in(j)),
        None => step_jacobian(sys, &xbox, h, p, scale, extent, eps, precise, high, jac_order),
    };
    let (rem, jac, ratio) = match jac {
        Some(jac) => (rem, jac, ratio),
        None => box_enclosure(sys, &xbox, h, p, scale, tol, c1)?,
    };
    let z: Vec<I> = phi.iter().zip(&rem).map(|(a, b)| *a + *b).collect();
    let (m_new, zc, err) = recentre(&set.m, c, h, &rem, &z, finer.as_deref());
    let parts = Parts {
        zc,
        r0: set.r0.clone(),
        r: set.r.clone(),
        dx: spread.clone(),
        sub: set.sub.as_ref().map(|sb| {
            let hull = set.hull_of(&sb.r0, &sb.r, &sb.boxed);
            (sb.r0.clone(), sb.r.clone(), relative(&hull, &set.m))
        }),
    };
    let lin = match &jac64 {
        Some(j) => linear_part(j, &set.b, &set.c, opts.basis, &parts.map(rounded_to_f64)).map_exact(),
        None => linear_part(&jac, &set.b, &set.c, opts.basis, &parts),
    };
    if !z.iter().all(|x| x.is_finite()) || !lin.finite {
        return Err(StepFail::Shrink);
    }
    let unbounded = |r: &[I]| !r.iter().all(|x| x.is_finite());
    if unbounded(&lin.r) || lin.sub.as_ref().is_some_and(|(r, _)| unbounded(r)) {
        return Err(fatal("enclosure became unbounded"));
    }
    // The box method beside the parallelepiped: x(h) in z + [J] ([X] - m) (spec eq. (5.12)).
    let image_box = |jdx: &[I]| -> Vec<I> { z.iter().zip(jdx).map(|(a, b)| *a + *b).collect() };
    let sub = set.sub.as_ref().zip(lin.sub.as_ref()).map(|(sb, (r, jdx))| SubSet {
        r0: sb.r0.clone(),
        r: r.clone(),
        boxed: image_box(jdx),
    });
    let (b_inv, ba) = (lin.b_inv, lin.ba);
    let mut set = LohnerSet {
        m: m_new,
        c: lin.c_new,
        r0: set.r0.clone(),
        b: lin.b_new,
        r: lin.r,
        boxed: image_box(&lin.jdx),
        sub,
    };
    // (5.10') once the errors outgrow the propagated part, they are folded into it
    let diam = |r: &[I]| r.iter().fold(0.0f64, |a, x| a.max(x.wid()));
    let rebased = if opts.reorganise && diam(&set.r) > REORGANISE * diam(&set.r0) {
        let b = set.reorganise(&b_inv);
        if unbounded(&set.r0) || set.sub.as_ref().is_some_and(|sb| unbounded(&sb.r0)) {
            return Err(fatal("enclosure became unbounded"));
        }
        Some(b)
    } else {
        None
    };
    // (5.10''') the step as the product form reads it: `mid([J])` and the error
    // `[e] + ([J] - mid([J])) ([X] - m)`
    let (jm, off) = linalg::split(&jac);
    let err: Vec<I> = err
        .iter()
        .zip(linalg::mul_vec(&off, &spread))
        .map(|(a, b)| *a + b)
        .collect();
    let link = Some((jm, err));
    Ok(StepOut {
        set,
        jac: c1.then_some((jac, ba, b_inv)),
        rebased,
        ratio,
        link,
    })
}

/// The vectors the linear part of a step reads ([spec eqs. (5.9)-(5.10), (5.12)](crate::spec::enclosure)):
/// `[z - m']` joined with 0 (`zc`), the set's `[r0]`, `[r]` and `[X] - m`, and the marked
/// subset's `[r0_S]`, `[r_S]` and hull minus `m`.
struct Parts<L> {
    zc: Vec<L>,
    r0: Vec<L>,
    r: Vec<L>,
    dx: Vec<L>,
    sub: Option<(Vec<L>, Vec<L>, Vec<L>)>,
}

impl<L: Copy> Parts<L> {
    /// Every vector mapped by `f`.
    fn map<M>(&self, f: impl Fn(&[L]) -> Vec<M>) -> Parts<M> {
        Parts {
            zc: f(&self.zc),
            r0: f(&self.r0),
            r: f(&self.r),
            dx: f(&self.dx),
            sub: self.sub.as_ref().map(|(a, b, c)| (f(a), f(b), f(c))),
        }
    }
}

/// What the linear part of a step gives: `C' = mid([J] C)`, the new basis `B'`, `[B'^-1]`,
/// `[B'^-1][J B]`, the new `[r']` and `[J]([X] - m)` of the set and of its marked subset, and
/// whether `[J] B` and `[J] C` are finite.
struct Linear<L> {
    finite: bool,
    c_new: DMatrix<f64>,
    b_new: DMatrix<f64>,
    b_inv: IMat<L>,
    ba: IMat<L>,
    r: Vec<L>,
    jdx: Vec<L>,
    sub: Option<(Vec<L>, Vec<L>)>,
}

impl Linear<Interval> {
    /// The same enclosures in the interval type `I` (each f64 end is a point of `I`: exact).
    fn map_exact<I: Ival>(self) -> Linear<I> {
        Linear {
            finite: self.finite,
            c_new: self.c_new,
            b_new: self.b_new,
            b_inv: exact_in(&self.b_inv),
            ba: exact_in(&self.ba),
            r: exact_in_vec(&self.r),
            jdx: exact_in_vec(&self.jdx),
            sub: self.sub.map(|(r, jdx)| (exact_in_vec(&r), exact_in_vec(&jdx))),
        }
    }
}

/// (5.9)-(5.10), (5.12) The linear part of a step in the interval type `L`, from the step's
/// `[J]` and the set's bases `B`, `C`. The propagated part: `C' = mid([J] C)`, its excess
/// `[J] C - C'` joins the errors. The error part: the new basis `mid([J] B)` itself or its
/// orthogonal factor (`basis`), and
/// `r' = [B'^-1][J B] r + [B'^-1] ((z - m') + ([J] C - C') r0)`. Lohner's column sorting (by
/// `||A_j|| wid(r_j)`) was measured to be worse here: on the particle at t = 600 it gave widths
/// 1.7e-7 against 5.2e-11 unsorted (spec section 5.5).
fn linear_part<L: Ival>(
    jac: &IMat<L>,
    b: &DMatrix<f64>,
    c: &DMatrix<f64>,
    basis: Basis,
    x: &Parts<L>,
) -> Linear<L> {
    let a = linalg::mul(jac, &linalg::imat(b));
    let jc = linalg::mul(jac, &linalg::imat(c));
    let finite = linalg::all_finite(&a) && linalg::all_finite(&jc);
    let (c_new, dc) = linalg::split(&jc);
    let (b_new, b_inv) = choose_basis(linalg::mid(&a), basis);
    let ba = linalg::mul(&b_inv, &a);
    let image_r = |r0: &[L], r: &[L]| -> Vec<L> {
        let y: Vec<L> = x.zc.iter().zip(linalg::mul_vec(&dc, r0)).map(|(a, b)| *a + b).collect();
        let shift = linalg::mul_vec(&b_inv, &y);
        let part = linalg::mul_vec(&ba, r);
        part.iter().zip(&shift).map(|(a, b)| *a + *b).collect()
    };
    Linear {
        finite,
        r: image_r(&x.r0, &x.r),
        jdx: linalg::mul_vec(jac, &x.dx),
        sub: x.sub.as_ref().map(|(r0, r, dx)| (image_r(r0, r), linalg::mul_vec(jac, dx))),
        c_new,
        b_new,
        b_inv,
        ba,
    }
}

/// f64 intervals as intervals of `I`: exact, an f64 end being a point of every precision.
fn exact_in_vec<I: Ival>(v: &[Interval]) -> Vec<I> {
    v.iter().map(|x| I::iv(x.inf(), x.sup())).collect()
}

/// [`exact_in_vec`] for a matrix.
fn exact_in<I: Ival>(m: &IMat<Interval>) -> IMat<I> {
    let rows = m.nrows();
    let cols = m.entries().len().checked_div(rows).unwrap_or(0);
    IMat::from_flat(rows, cols, exact_in_vec(m.entries()))
}

/// (5.10'') The share of the state's rounding level above which the field at the centre
/// is evaluated at a higher precision ([`Ival::field_finer`]).
pub(super) const FINER_AT: f64 = 0.125;

/// (5.10') The errors are folded into the propagated part once their widest component is
/// this many times the propagated part's.
pub(super) const REORGANISE: f64 = 10.0;

/// (5.10'') The next centre `m'` and `[z - m']`, the step's new error, from the increment
/// of the centre's Taylor polynomial: with `c` the coefficients at `m` (`c_0 = m`, exact),
/// `x(h; m) - m' = (m - m') + sum_{k>=1} c_k h^k + [R]`, where `m - m'` is a difference of
/// two close floats (exact, or outward rounded) and the increment is a fraction of the
/// state (its rounding a fraction of the state's ulp). `m' = m + mid(incr + [R])` rounded
/// to the nearest point; the result is intersected with `z - m'` (both enclose the same
/// values) and joined with 0 (so that `m'` is in the set: `0 in [r]`). Evaluating the
/// polynomial as a whole (`z = phi(m) + [R]`, `m' = mid(z)`) costs 2 to 4 ulps a step
/// instead of about one. Also returns, for the product form (5.10'''), the enclosure of
/// `x(h; m) - m'` before the join, from the increment with `c_1 = F(m)` intersected with
/// `c1` when that is given (a finer enclosure of `F(m)`; `m'` and `[z - m']` do not use it,
/// so that the set and the steps are the same with it or without).
pub(super) fn recentre<I: Ival>(
    m: &[I::Pt],
    c: Rows<'_, I>,
    h: I,
    rem: &[I],
    z: &[I],
    c1: Option<&[I]>,
) -> (Vec<I::Pt>, Vec<I>, Vec<I>) {
    let d = m.len();
    let mut tail: Vec<&[I]> = c.iter().skip(1).map(|r| &r[..d]).collect();
    // `x(h; m) - m` enclosed, from the rows `tail`
    let step_of = |tail: &[&[I]]| -> Vec<I> {
        let incr: Vec<I> = if tail.is_empty() {
            vec![I::zero(); d]
        } else {
            I::horner(tail, h).iter().map(|s| *s * h).collect()
        };
        incr.iter().zip(rem).map(|(a, b)| *a + *b).collect()
    };
    let step = step_of(&tail);
    let m_new: Vec<I::Pt> = (0..d)
        .map(|i| (I::pt(m[i]) + I::pt(step[i].mid_pt())).mid_pt())
        .collect();
    // `x(h; m) - m'` from `step` and from z
    let error = |step: &[I]| -> Vec<I> {
        (0..d)
            .map(|i| {
                let by_incr = (I::pt(m[i]) - I::pt(m_new[i])) + step[i];
                let by_z = z[i] - I::pt(m_new[i]);
                meet(by_incr, by_z)
            })
            .collect()
    };
    let err = error(&step);
    let zc = err.iter().map(|e| e.convex_hull(I::zero())).collect();
    // the first coefficient F(m) from a finer evaluation, where there is one: both enclose it
    let first: Option<Vec<I>> =
        c1.zip(tail.first()).map(|(f, c)| c.iter().zip(f).map(|(a, b)| meet(*b, *a)).collect());
    let err = match &first {
        Some(f) => {
            tail[0] = f;
            let fine = error(&step_of(&tail));
            fine.iter().zip(&err).map(|(a, b)| meet(*a, *b)).collect()
        }
        None => err,
    };
    (m_new, zc, err)
}

/// `a ∩ b` for two enclosures of the same value; `b` should they not meet (only if the
/// arithmetic were wrong: each contains the value).
fn meet<I: Ival>(a: I, b: I) -> I {
    let x = a.intersection(b);
    if x.is_empty() {
        b
    } else {
        x
    }
}

/// The basis `B'` of the next set and an interval matrix containing its inverse ([spec eqs.
/// (5.9)-(5.10)](crate::spec::enclosure)): `mid([A])` itself for [`Basis::Parallelepiped`] (its inverse proved by
/// (5.9) from a float inverse), the orthogonal factor of its QR factorisation for
/// [`Basis::Orthogonal`] or when the parallelepiped's inverse is not proved, and `I` when
/// neither is.
pub(super) fn choose_basis<I: Ival>(am: DMatrix<f64>, basis: Basis) -> (DMatrix<f64>, IMat<I>) {
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


/// Steps taken over the whole set (5.6'') without trying (5.6a) after no order of
/// JAC_ORDERS gave the precise derivative (then the highest order is tried again).
pub(super) const SKIP: usize = 16;

/// The image of a point set (r = 0): the box z, recentred.
pub(super) fn point_image<I: Ival>(set: &LohnerSet<I>, z: Vec<I>) -> LohnerSet<I> {
    let image = LohnerSet::from_box(&z);
    if set.sub.is_some() {
        // the subset of a point is the point
        LohnerSet::with_subset(&image.m, &z, &z)
    } else {
        image
    }
}

/// (5.4)-(5.5), (5.6'') over the whole set (Lohner's original step): `[R]` in
/// `z = phi(m) + [R]`, the remainder over an a priori box of every trajectory from the hull, and
/// `[J] = D phi([X])` from the variational Taylor coefficients over the hull; for C^1
/// output, `[J]` plus the variational remainder (5.11).
#[allow(clippy::too_many_arguments)]
pub(super) fn box_enclosure<I: Ival>(
    sys: &System,
    xbox: &[I],
    h: I,
    p: usize,
    scale: f64,
    tol: Tolerance,
    c1: bool,
) -> Result<(Vec<I>, IMat<I>, f64), StepFail> {
    let d = xbox.len();
    let cv = sys
        .field_var
        .ode_taylor(&with_seed(xbox, &sys.var_cols), p)
        .ok_or(StepFail::Shrink)?;
    let b = Coeffs::from_rows(d, cv.iter());
    let (rem, y, ratio) = remainder(sys, b.rows(), h, p, scale, tol)?;
    let mut jac = variational_polynomial(cv.rows(), d, h);
    if c1 {
        let vrem = variational_remainder(sys, &y, cv.rows(), h, p)?;
        for (x, r) in jac.entries_mut().iter_mut().zip(vrem.entries()) {
            *x = *x + *r;
        }
    }
    Ok((rem, full_jacobian(&jac, &sys.var_cols), ratio))
}

/// The Picard-Lindelof test in the high-order form of Corliss and Rihm ([spec eq. (5.4)](crate::spec::enclosure)):
/// with `b` the Taylor coefficients `0..=q` at the initial set, find a box `Y` with
/// `sum_{i<q} b_i [0,h]^i + T_q(Y) [0,h]^q  in  Y`. Returns `Y` and the coefficients
/// `T_0..T_{q+1}` over `Y` (the last one for the Lagrange remainder). The first trial box
/// is the Taylor range over `[0, h]` widened by 10%; after a failed trial, the hull of `Y`
/// and `Z` widened by 10% and by `widen` times the excess of `Z` over `Y` (up to three times).
/// `boxes64` and `floor` as in [`box_taylor`].
pub(super) fn a_priori<I: Ival>(
    tape: &crate::tape::Tape,
    b: Rows<'_, I>,
    h: I,
    q: usize,
    widen: f64,
    boxes64: bool,
    floor: f64,
) -> Result<(Vec<I>, Coeffs<I>), StepFail> {
    let h0 = I::iv(0.0, h.sup());
    let dim = b.width();
    let series = |top: &[I]| horner(b.first(q), 0..dim, Some(top), h0);
    let mut y = inflate(&series(&b[q]));
    for _ in 0..4 {
        let ty = box_taylor(tape, &y, q + 1, time_scale(h), boxes64, floor).ok_or(StepFail::Shrink)?;
        let z = series(&ty[q]);
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
                I::iv(hull.inf() - w, hull.sup() + w)
            })
            .collect();
    }
    Err(StepFail::Shrink)
}

/// (5.5''') The share of an entry's magnitude under which its width is taken to hold
/// more than f64 rounding: `2^-36`.
pub(super) const F64_SHARE: f64 = 1.0 / (1u64 << 36) as f64;

/// (5.5''') The width under which an entry of an f64 series may be the noise of underflows
/// rather than the box's: `2^-1024`, `2^50` times the largest error of one operation whose
/// result underflows (`2^-1074`; sums of subnormal numbers are exact).
pub(super) const F64_FLOOR: f64 = f64::from_bits(1 << 50);

/// (5.5''') The rows an f64 series over a box grows between two looks at its last row.
pub(super) const F64_ROWS: usize = 8;

/// (5.5''') The Taylor coefficients `0..=order` of the solutions through the box `y` (an a
/// priori box, or a slice of one), read for an a priori test (row `order - 1`) and a
/// Lagrange remainder (row `order`). Where [`Ival::box_series_in_f64`], the series is first
/// computed in inari's f64 intervals from `y` rounded outward to f64 ends: it encloses the
/// same coefficients (spec (2.2) for a box containing `y`), and f64 ends are points of every
/// precision, so it is taken as it is when the rounding of f64 is a negligible share of the
/// two rows read: each of their entries is exactly 0 or wider than [`F64_SHARE`] times its
/// magnitude and than [`F64_FLOOR`] (far above the noise of underflows). Not tried for a box
/// nearly a point in every component. Otherwise (or when the f64 series is not finite) the
/// series at this precision. Where the f64 series underflows, it is tried again as that of
/// `y(s) = x(h s)` (its rows, about the remainder's size rather than `1/k!`, stay in f64's
/// range at high orders), row `k` multiplied back by an enclosure of `h^-k` at this precision.
/// An entry of a row read whose whole part in the step, its magnitude times `h^k` for row
/// `k`, is at most `floor` passes the test too, whatever its width: `floor` is `F64_SHARE`
/// times the state's rounding unit, which the step's tolerance absorbs (0 where the rows
/// are read against another tolerance).
/// A choice of evaluation only: both enclose the coefficients.
pub(super) fn box_taylor<I: Ival>(
    tape: &crate::tape::Tape,
    y: &[I],
    order: usize,
    h: f64,
    boxes64: bool,
    floor: f64,
) -> Option<Coeffs<I>> {
    if I::box_series_in_f64() || boxes64 {
        let y64 = rounded_to_f64(y);
        // a box nearly a point in every component (a very short step's): its f64 series
        // would be f64's rounding rather than the box's width, and is not tried
        if y64.iter().any(|x| x.wid() > F64_SHARE * x.mag()) {
            // the series of x itself first; the time scale only where its rows underflow
            let read = Read { span: h, floor };
            match f64_series(tape, &y64, order, 1.0, read) {
                Ok(c) => return Some(c.map(|x| I::iv(x.inf(), x.sup()))),
                Err(F64Series::Underflow) if h != 1.0 => {
                    if let Ok(c) = f64_series(tape, &y64, order, h, read) {
                        return Some(unscaled(&c, h));
                    }
                }
                Err(_) => {}
            }
        }
    }
    tape.ode_taylor(y, order)
}

/// The time scale of the f64 series of a step over `[0, h]` ((5.5'''): `h`'s upper end, an
/// f64; 1 for a span that is not positive and finite).
fn time_scale<I: Ival>(h: I) -> f64 {
    let t = h.sup();
    if t > 0.0 && t.is_finite() {
        t
    } else {
        1.0
    }
}

/// The coefficients `x_k = y_k h^-k` of an f64 series of `y(s) = x(h s)` (`h > 0` an exact
/// f64), at this precision: row `k` times an enclosure of `h^-k`.
fn unscaled<I: Ival>(c: &Coeffs<inari::Interval>, h: f64) -> Coeffs<I> {
    // h^-k by products of an enclosure of 1/h (a product costs less than a quotient); the
    // f64 ends converted exactly
    let inv = I::cst(1.0).quot(I::cst(h));
    let mut inv_k = I::cst(1.0);
    let rows: Vec<Vec<I>> = c
        .iter()
        .map(|row| {
            let out = row.iter().map(|x| I::iv(x.inf(), x.sup()) * inv_k).collect();
            inv_k = inv_k * inv;
            out
        })
        .collect();
    Coeffs::from_rows(c.rows().width(), rows.iter().map(|r| r.as_slice()))
}

/// How [`f64_series`] judges an entry of its rows: its part in a step over `[0, span]`
/// ([`box_taylor`]'s `h`), and the amount under which that part is negligible.
#[derive(Clone, Copy)]
struct Read {
    span: f64,
    floor: f64,
}

/// (5.5''') The f64 series of [`box_taylor`] over `y64` (that of `y(s) = x(h s)` when
/// `h != 1`) when its rows read pass the test, or why not. Grown [`F64_ROWS`] rows at a time:
/// a row with a non-zero entry under [`F64_FLOOR`] whose part in the step is above
/// `read.floor` stops it (the coefficients of such a box shrink with the order, so the rows
/// read would be the noise of underflows), so that a series that is not taken costs little.
fn f64_series(
    tape: &crate::tape::Tape,
    y64: &[inari::Interval],
    order: usize,
    h: f64,
    read: Read,
) -> Result<Coeffs<inari::Interval>, F64Series> {
    // row k holds `h^k x_k`: its part in the step is its magnitude times `(span / h)^k`
    // (a choice only: rounded to nearest; an overflow is not small)
    let small = |x: &inari::Interval, k: usize| {
        read.floor > 0.0 && x.mag() * (read.span / h).powi(k as i32) <= read.floor
    };
    let negligible = |x: &inari::Interval, k: usize| {
        x.is_exact_zero()
            || (x.is_finite() && (x.wid() >= (F64_SHARE * x.mag()).max(F64_FLOOR) || small(x, k)))
    };
    let scale = (h != 1.0).then(|| crate::scalar::iv(h, h));
    let mut s = tape.ode_series_scaled(y64, order, scale);
    let mut k = 0;
    loop {
        k = (k + F64_ROWS).min(order);
        if !s.grow(k) {
            return Err(F64Series::Other);
        }
        let under = |x: &inari::Interval| !x.is_exact_zero() && x.mag() < F64_FLOOR && !small(x, k);
        if s.rows()[k].iter().any(under) {
            return Err(F64Series::Underflow);
        }
        if k == order {
            let first = order.saturating_sub(1);
            let rows = s.rows();
            let taken = (first..=order).all(|r| rows[r].iter().all(|x| negligible(x, r)));
            return if taken { Ok(s.coeffs()) } else { Err(F64Series::Other) };
        }
    }
}

/// Why an f64 series of [`box_taylor`] was not taken.
#[derive(Debug, PartialEq)]
enum F64Series {
    /// A row has an entry under [`F64_FLOOR`] (and above the floor of [`Read`]).
    Underflow,
    /// A coefficient was not proved, or a row read is not wide enough.
    Other,
}

/// (5.4)-(5.5): with `b` the Taylor coefficients at the initial set (its centre, or its
/// hull), proves that every trajectory from it exists on `[0, h]` and returns `[R]` with
/// `x(h) - phi(x0) in [R]`, and the a priori box `Y`. When `T_{p+1}(Y) h^{p+1}` is wide,
/// `x(xi)` is taken in the enclosures of SLICES sub-intervals of `[0, h]` (narrower boxes
/// than Y: less dependency in the high-order coefficients), unless `tol` is
/// [`Tolerance::Unsliced`]. Unless `tol` is [`Tolerance::Loose`], a remainder wider than
/// the tolerance rejects the step (5.8).
pub(super) fn remainder<I: Ival>(
    sys: &System,
    b: Rows<'_, I>,
    h: I,
    p: usize,
    scale: f64,
    tol: Tolerance,
) -> Result<(Vec<I>, Vec<I>, f64), StepFail> {
    let (y, ty) = a_priori(&sys.field, b, h, p, 0.0, false, F64_SHARE * scale * I::eps())?;
    let (rem, ratio) = remainder_over(sys, b, &y, &ty, h, p, scale * I::eps(), tol, false)?;
    Ok((rem, y, ratio))
}

/// (5.5) from an a priori box `y` of every trajectory from the initial set over `[0, h]`
/// (or over a longer span) and the coefficients `ty` over it up to `p + 1`: `[R]` and its
/// width relative to the tolerance `REMAINDER_TOL unit` (`unit`: the state's size times the
/// level it is held to, `I::eps()` or (12.0.10) a flow's own).
#[allow(clippy::too_many_arguments)]
pub(super) fn remainder_over<I: Ival>(
    sys: &System,
    b: Rows<'_, I>,
    y: &[I],
    ty: &Coeffs<I>,
    h: I,
    p: usize,
    unit: f64,
    tol: Tolerance,
    boxes64: bool,
) -> Result<(Vec<I>, f64), StepFail> {
    let strict = tol != Tolerance::Loose;
    let d = b.width();
    let hp = (0..=p).fold(I::cst(1.0), |a, _| a * h);
    // the widest component of T h^(p+1), relative to the tolerance (NaN if not finite)
    let ratio_of = |t: &[I]| {
        t.iter().fold(0.0f64, |a, t| {
            let w = (*t * hp).wid() / (REMAINDER_TOL * unit);
            if w.is_nan() || a.is_nan() {
                f64::NAN
            } else {
                a.max(w)
            }
        })
    };
    let too_wide = |t: &[I]| {
        let r = ratio_of(t);
        r.is_nan() || r > 1.0
    };
    let wide = too_wide(&ty[p + 1]);
    if wide && tol == Tolerance::Unsliced {
        return Err(StepFail::TooWide(ratio_of(&ty[p + 1])));
    }
    let mut t_rem = ty[p + 1].to_vec();
    if wide {
        for j in 0..SLICES {
            let lo = h.sup() * j as f64 / SLICES as f64;
            let hi = if j + 1 == SLICES {
                h.sup()
            } else {
                h.sup() * (j + 1) as f64 / SLICES as f64
            };
            let tj = I::iv(lo, hi);
            let yj: Vec<I> = horner(b.first(p), 0..d, Some(&ty[p]), tj)
                .iter()
                .zip(y)
                .map(|(a, b)| a.intersection(*b))
                .collect();
            let tj = box_taylor(&sys.field, &yj, p + 1, time_scale(h), boxes64, F64_SHARE * unit)
                .ok_or(StepFail::Shrink)?;
            let part = &tj[p + 1];
            // The hull over the SLICES is at least as wide as this slice: in strict mode a
            // slice already over the tolerance decides the rejection, without the others.
            if strict && too_wide(part) {
                return Err(StepFail::TooWide(ratio_of(part)));
            }
            t_rem = if j == 0 {
                part.to_vec()
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
    Ok((t_rem.iter().map(|t| *t * hp).collect(), ratio))
}

/// (5.6''') The Jacobian of a step of a C^0 flow (or of a loose C^1 flow, spec (12.0.9))
/// over a set of small extent, computed in inari's f64 intervals from the box `xbox` and the
/// span `h` rounded outward to f64 ends: [`step_jacobian`] over the larger f64 box, its orders
/// chosen by the same test at the level `eps` (the set's precision, or a loose flow's level:
/// the remainder times the set's extent below `scale eps`). Taken when the whole f64
/// enclosure (its rounding included) passes that test: every entry's width times the extent
/// times `d` at most `scale eps`. `None` at 53 bits,
/// when the extent is too large for f64's rounding to pass, or when the test fails; the
/// Jacobian is then computed at this precision. A choice of evaluation only: both enclose
/// the same Jacobian (spec (5.6)), and f64 ends are points of every precision (the caller
/// takes it into `I` exactly, [`exact_in`]).
#[allow(clippy::too_many_arguments)]
fn step_jacobian_in_f64<I: Ival>(
    sys: &System,
    xbox: &[I],
    h: I,
    p: usize,
    scale: f64,
    extent: f64,
    eps: f64,
    order: &mut usize,
) -> Option<IMat<Interval>> {
    let d = xbox.len();
    // the test, NaN failing it
    let passes = |width: f64| width * extent * d as f64 <= scale * eps;
    // f64's rounding alone, about 2^-50 of entries of size about 1, must pass it
    if I::eps() >= f64::EPSILON || !passes(F64_JAC_ROUNDING) {
        return None;
    }
    let jac = step_jacobian(sys, &rounded_to_f64(xbox), rounded_to_f64(&[h])[0], p, scale, extent, eps, false, false, order)?;
    jac.entries().iter().all(|x| passes(x.wid())).then_some(jac)
}

/// (5.6''') The width f64's rounding gives an entry of a step's Jacobian, at the least:
/// `2^-50` (the entries are near the identity's for the steps taken).
const F64_JAC_ROUNDING: f64 = 1.0 / (1u64 << 50) as f64;

/// (5.6) An interval matrix containing `D x(h; x0) / D x0` for every `x0` in the hull
/// `[X]`, from the Taylor series of order `q` of the variational equation
/// `V' = DF(x) V, V(0) = I`, with the Lagrange remainder over an a priori box of the
/// extended system `(x, V)`. The orders of [`JAC_ORDERS`] up to `p` are tried from
/// `*order` (an index, updated for the next step) on until the remainder's share of the new
/// set's width (`wid(remainder) |x0 - m| d`) is below the rounding level of the state
/// (`scale eps`: `eps` is the state's precision, which (5.6''') passes to a series in f64) and,
/// if `precise`, the remainder itself below 1 ulp of the Jacobian's size (the C^1 output
/// of [`flow_set_jacobian`]). `None` when no order does: the step is then taken over the
/// whole set (`box_enclosure`).
#[allow(clippy::too_many_arguments)]
pub(super) fn step_jacobian<I: Ival>(
    sys: &System,
    xbox: &[I],
    h: I,
    p: usize,
    scale: f64,
    extent: f64,
    eps: f64,
    precise: bool,
    high: bool,
    order: &mut usize,
) -> Option<IMat<I>> {
    let d = xbox.len();
    // The ladder of orders and the highest one tried: for the precise derivative, the
    // precise ladder to its top when the interval type has one (Theorem 5.3)
    let (orders, cap) = match I::precise_jac_orders().filter(|_| precise && high) {
        Some(o) => (o, o[o.len() - 1].max(p)),
        None => (I::jac_orders(), p.max(I::jac_orders()[0])),
    };
    // After no order qualified for the precise derivative, the next SKIP steps go straight
    // to the step over the whole set (the order index counts them down above the ladder).
    if *order >= orders.len() {
        *order -= 1;
        if *order >= orders.len() {
            return None;
        }
    }
    let seed = with_seed(xbox, &sys.var_cols);
    let c = sys.var_cols.len();
    // The a priori box of the extended system, found at the lowest order (where the Picard
    // test over boxes suffers least from the dependency in the coefficients); it holds
    // every trajectory on [0, h], so the Lagrange remainder of any order may use it. At a
    // low order the test converges slowly for components whose range is nearly a point
    // (e.g. D u1 / D u1 = 1 for the knife): widen generously.
    let q0 = orders[0];
    // the series at the seed, grown from rung to rung (the same coefficients as a series
    // computed afresh at each order, spec (2.2))
    let mut k = (*order).min(orders.len() - 1);
    let mut w = sys.field_var.ode_series(&seed, orders[k]);
    if !w.grow(q0) {
        return None;
    }
    let (y_ext, t0) = a_priori(&sys.field_var, w.rows(), h, q0, 4.0, false, 0.0).ok()?;
    // the series over the a priori box for the remainders above q0, grown likewise (made at
    // the first rung above q0); once a coefficient was not proved it is not at any higher
    // order, and the rungs above have no remainder
    let mut over: Option<crate::tape::OdeSeries<'_, I>> = None;
    // the last two (order, ratio) tried, for the orders above the state's (5.6)
    let mut tried: [Option<(usize, f64)>; 2] = [None, None];
    loop {
        let q = orders[k];
        // An order above the state's is tried only when the last two ratios, extrapolated
        // geometrically in the order, reach 1 by the top of the ladder (a choice: it saves
        // the two costliest series where they would not do)
        let hopeless = q > p.max(q0)
            && match tried {
                [Some((q1, r1)), Some((q2, r2))] => {
                    let per_order = (r2 / r1).powf(1.0 / (q2 - q1) as f64);
                    let at_top = r2 * per_order.powi((cap - q2) as i32);
                    at_top.is_nan() || at_top > 1.0
                }
                _ => false,
            };
        if q > cap || hopeless {
            if precise {
                *order = orders.len() + SKIP;
            }
            return None;
        }
        if !w.grow(q) {
            return None;
        }
        let tw = if q == q0 {
            Some(t0.rows())
        } else {
            // a series that failed once grows no more (`OdeSeries::grow`)
            let g = over.get_or_insert_with(|| sys.field_var.ode_series(&y_ext, q + 1));
            g.grow(q + 1).then(|| g.rows())
        };
        if let Some(tw) = tw {
            let hq = (0..=q).fold(I::cst(1.0), |a, _| a * h);
            let rem: Vec<I> = (0..d * c).map(|k| tw[q + 1][d + k] * hq).collect();
            let widest = rem.iter().fold(0.0f64, |a, x| a.max(x.wid()));
            let mut jac = variational_polynomial(w.rows(), d, h);
            let size = jac.entries().iter().fold(1.0f64, |a, x| a.max(x.mag()));
            // (NaN fails the tests too)
            let share = widest * extent * d as f64 / (scale * eps);
            let own = if precise {
                widest / (size * I::eps())
            } else {
                0.0
            };
            let ratio = share.max(own);
            tried = [tried[1], Some((q, ratio))];
            if ratio <= 1.0 {
                // next step: the same order, or one lower when this one had a wide margin
                // (above the state's order, one lower only with a margin of 1e-8: a
                // series tried in vain costs more there)
                let margin = if q > p { 1e-8 } else { 1e-4 };
                *order = if ratio < margin { k.saturating_sub(1) } else { k };
                for (x, r) in jac.entries_mut().iter_mut().zip(&rem) {
                    *x = *x + *r;
                }
                return Some(full_jacobian(&jac, &sys.var_cols));
            }
        }
        k += 1;
        if k == orders.len() {
            if precise {
                *order = orders.len() + SKIP;
            }
            return None;
        }
    }
}

/// `(x, W0)`: a box with the seed of the variational equation ([spec eq. (4.11)](crate::spec::dynamics)) for the
/// columns `cols` of `D x(t) / D x(0)`: `W0` is `d x cols.len()`, row-major, with
/// `W0[cols[k]][k] = 1` and 0 elsewhere.
pub(super) fn with_seed<I: Ival>(x: &[I], cols: &[usize]) -> Vec<I> {
    let mut xv = x.to_vec();
    for i in 0..x.len() {
        xv.extend(cols.iter().map(|&j| I::cst(if i == j { 1.0 } else { 0.0 })));
    }
    xv
}

/// `D x(h) / D x(0)` from its columns `cols` (`w`, d x cols.len()): every other column `j`
/// is `e_j`, exactly, since the field does not read component `j` ([spec eq. (5.6')](crate::spec::enclosure)).
pub(super) fn full_jacobian<I: Ival>(w: &IMat<I>, cols: &[usize]) -> IMat<I> {
    let d = w.nrows();
    let mut jac = linalg::identity(d);
    for i in 0..d {
        for (&j, x) in cols.iter().zip(&w[i]) {
            jac[i][j] = *x;
        }
    }
    jac
}

/// `sum_k [V_k] h^k`: the Taylor polynomial of the variational part (components `d..`,
/// d rows, row-major) of the coefficients `w` of the extended system.
pub(super) fn variational_polynomial<I: Ival>(w: Rows<'_, I>, d: usize, h: I) -> IMat<I> {
    let c = (w.width() - d) / d.max(1);
    if c == 0 {
        return IMat::from_flat(d, 0, Vec::new());
    }
    IMat::from_flat(d, c, horner(w, d..d + d * c, None, h))
}

/// (5.11) Remainder of the variational equation over one step: with `Y` the proved a priori
/// box of the state, find `Y_V` with
/// `sum_{i<p} [V_i] [0,h]^i + V_p(Y, Y_V) [0,h]^p  in  Y_V` (V(0) = I), so that `V(t) in Y_V`
/// on `[0, h]`; then `V(h) - sum_{i<=p} V_i h^i in V_{p+1}(Y, Y_V) h^{p+1}`.
pub(super) fn variational_remainder<I: Ival>(
    sys: &System,
    y: &[I],
    cv: Rows<'_, I>,
    h: I,
    p: usize,
) -> Result<IMat<I>, StepFail> {
    let (d, c) = (y.len(), sys.var_cols.len());
    let h0 = I::iv(0.0, h.sup());
    let cols = d..d + d * c;
    let mut yv = inflate(&horner(cv.first(p + 1), cols.clone(), None, h0));
    for _ in 0..4 {
        let ext: Vec<I> = y.iter().chain(&yv).copied().collect();
        let tv = box_taylor(&sys.field_var, &ext, p + 1, time_scale(h), false, 0.0).ok_or(StepFail::Shrink)?;
        let zv = horner(cv.first(p), cols.clone(), Some(&tv[p]), h0);
        if zv.iter().zip(&yv).all(|(a, b)| a.subset(*b)) {
            let hp = (0..=p).fold(I::cst(1.0), |a, _| a * h);
            return Ok(IMat::from_flat(
                d,
                c,
                tv[p + 1][d..d + d * c].iter().map(|t| *t * hp).collect(),
            ));
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
pub(super) fn inflate<I: Ival>(x: &[I]) -> Vec<I> {
    x.iter()
        .map(|v| {
            let w = v.wid() * 0.1 + v.mag() * 1e-15 + 1e-300;
            I::iv(v.inf() - w, v.sup() + w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::precision::mp::MpInterval;
    use crate::precision::wide::{with_bits, WideInterval};
    use crate::scalar::Scalar;
    use crate::tape::Tape;

    /// `x' = y, y' = -x`: the solution `x(t) = x0 cos t + y0 sin t` gives the coefficients
    /// in closed form, `x_k = (x0 cos(k pi/2) + y0 sin(k pi/2)) / k!` and
    /// `y_k = (k + 1) x_(k+1)`: over the box `[a, b] x [c, d]` each is `+-[a, b] / k!` or
    /// `+-[c, d] / k!`. Returns, for row `k` and component `i`, the sign and which interval.
    fn exact_row(k: usize, i: usize) -> (bool, usize) {
        // (negative, index of the interval: 0 for [a, b], 1 for [c, d])
        match (k % 4, i) {
            (0, 0) => (false, 0),
            (1, 0) => (false, 1),
            (2, 0) => (true, 0),
            (3, 0) => (true, 1),
            (0, _) => (false, 1),
            (1, _) => (true, 0),
            (2, _) => (true, 1),
            _ => (false, 0),
        }
    }

    /// Every coefficient of `c` (rows `0..=order`) times `k!` contains the exact range
    /// over the box (compared exactly at 1024 bits: the products are exact there), and
    /// is at most `slack` wider than it.
    fn check_exact(c: &Coeffs<WideInterval>, ends: [(&MpInterval, &MpInterval); 2], order: usize, slack: f64) {
        let mut fact = 1u64;
        for k in 0..=order {
            if k > 0 {
                fact *= k as u64;
            }
            for i in 0..2 {
                let (neg, which) = exact_row(k, i);
                let (lo, hi) = ends[which];
                let range = lo.hull(hi);
                let range = if neg { range.neg() } else { range };
                let scaled = c[k][i].to_mp().with_prec(1024).mul_ref(&MpInterval::from_f64(fact as f64, 1024));
                assert!(range.subset(&scaled), "row {k}, component {i}: {scaled} misses {range}");
                assert!(
                    scaled.wid_up() <= range.wid_up() * (1.0 + 1e-12) + slack,
                    "row {k}, component {i}: {scaled} is wider than {range}"
                );
            }
        }
    }

    /// `x' = y, y' = -x` as a system: its flow's Jacobian over `h` is the rotation
    /// `[[cos h, sin h], [-sin h, cos h]]` at every state.
    fn rotation<S: Scalar>(x: &[S]) -> Vec<S> {
        vec![x[1].clone(), -x[0].clone()]
    }

    /// (5.10'''') A 106-bit flow of the rotation `x' = y, y' = -x` from a box 2^-70 wide takes
    /// its steps' Jacobians in f64 (5.6''') and so its linear part in f64. The flow's box
    /// at t = 1 must hold the exact image of every corner of the initial box (the closed
    /// form at 256 bits, about 2^-250 wide) and be no wider than the exact image's hull
    /// plus 8 ulps of double-double at the state's size.
    #[test]
    fn a_small_sets_linear_part_in_f64_keeps_the_exact_image_of_the_box() {
        use crate::precision::dd::DdInterval;
        let sys = System::record(2, 0, rotation, rotation);
        let rad = 2f64.powi(-70);
        let (x0, y0) = (0.5, -0.25);
        let around = |c: f64| DdInterval::cst(c) + DdInterval::iv(-1.0, 1.0) * DdInterval::cst(rad);
        let start = [around(x0), around(y0)];
        let (set, stats) = crate::enclosure::flow_set(&sys, LohnerSet::from_box(&start), 1.0, &FlowOptions::default()).expect("a flow of the rotation");
        assert!(stats.steps >= 1);
        let hull = set.hull();
        with_bits(256, || {
            let w = |x: f64| WideInterval::cst(x);
            let (c, s) = (w(1.0).cos(), w(1.0).sin());
            let dd = |x: &DdInterval| WideInterval::from_mp(&MpInterval::from_dd(*x, 256));
            let mut lo = [f64::INFINITY; 2];
            let mut hi = [f64::NEG_INFINITY; 2];
            for (a, b) in [(-rad, -rad), (-rad, rad), (rad, -rad), (rad, rad)] {
                let (x, y) = (w(x0) + w(a), w(y0) + w(b));
                let image = [x * c + y * s, y * c - x * s];
                for i in 0..2 {
                    assert!(image[i].subset(&dd(&hull[i])), "component {i}: the image of a corner, {:?}, is not in {:?}", image[i], hull[i]);
                    lo[i] = lo[i].min(image[i].inf_f64());
                    hi[i] = hi[i].max(image[i].sup_f64());
                }
            }
            for i in 0..2 {
                let exact = hi[i] - lo[i];
                assert!(hull[i].wid() <= exact + 8.0 * 2f64.powi(-106), "component {i}: {:?} is wider than the image's {exact:e}", hull[i]);
            }
        });
    }

    #[test]
    fn a_small_sets_step_jacobian_in_f64_encloses_the_rotation_and_a_large_sets_is_not_tried() {
        let sys = System::record(2, 0, rotation, rotation);
        with_bits(256, || {
            let w = |x: f64| WideInterval::cst(x);
            let tiny = w(2f64.powi(-110)) * w(2f64.powi(-110));
            let around = |c: f64| w(c) + WideInterval::iv(-1.0, 1.0) * tiny;
            let xbox = [around(0.5), around(-0.25)];
            let h = w(0.125);
            let mut order = 0;
            // the extent 2^-220: f64's rounding (2^-52) times it is below 2^-255
            let jac: IMat<WideInterval> =
                exact_in(&step_jacobian_in_f64(&sys, &xbox, h, 96, 1.0, 2f64.powi(-220), 2f64.powi(-255), &mut order)
                    .expect("the f64 Jacobian is taken for a set this small"));
            // the closed form at 256 bits (about 2^-250 wide) lies inside each entry, whose
            // ends are f64 values, and each entry is as tight as f64 allows up to 2^-40
            let (c, s) = (h.cos(), h.sin());
            let exact = [[c, s], [-s, c]];
            for (i, row) in exact.iter().enumerate() {
                for (j, e) in row.iter().enumerate() {
                    let x = jac[i][j];
                    assert_eq!(WideInterval::iv(Ival::inf(&x), Ival::sup(&x)), x, "J[{i}][{j}] has an end that is no f64");
                    assert!(e.subset(&x), "J[{i}][{j}] = {x:?} misses the rotation's {e:?}");
                    assert!(x.wid() < 2f64.powi(-40), "J[{i}][{j}] = {x:?} is wide");
                }
            }
            // a set 2^-20 wide: f64's rounding alone would not pass the test at 256 bits
            let wide = [w(0.5) + WideInterval::iv(-1.0, 1.0) * w(2f64.powi(-20)), around(-0.25)];
            assert!(step_jacobian_in_f64(&sys, &wide, h, 96, 1.0, 2f64.powi(-20), 2f64.powi(-255), &mut order).is_none());
        });
        // at 53 bits it is never tried
        let xbox = [crate::scalar::iv(0.5, 0.5), crate::scalar::iv(-0.25, -0.25)];
        let mut order = 0;
        assert!(step_jacobian_in_f64(&sys, &xbox, crate::scalar::iv(0.125, 0.125), 20, 1.0, 0.0, f64::EPSILON, &mut order).is_none());
    }

    #[test]
    fn box_series_in_f64_enclose_the_closed_form_and_are_taken_only_where_their_rounding_is_negligible() {
        let tape = Tape::record(2, |x| vec![x[1], -x[0]]);
        let order = 13; // 13! < 2^53: exact as an f64
        with_bits(256, || {
            // a box of the width of an a priori box: the f64 series is taken (its ends are
            // f64 values) and it is as tight as the closed form up to f64 rounding
            let (a, b, c, d) = (0.5, 0.625, -0.25, 0.125);
            let y = [WideInterval::iv(a, b), WideInterval::iv(c, d)];
            let s = box_taylor(&tape, &y, order, 1.0, false, 0.0).expect("a series");
            for x in s.iter().flatten() {
                assert_eq!(WideInterval::iv(Ival::inf(x), Ival::sup(x)), *x, "{x:?} has an end that is no f64");
            }
            let mp = |v: f64| MpInterval::from_f64(v, 1024);
            let (ma, mb, mc, md) = (mp(a), mp(b), mp(c), mp(d));
            check_exact(&s, [(&ma, &mb), (&mc, &md)], order, 0.0);
            // the same series through the time scale h = 3 (the f64 series of y(s) = x(3 s),
            // its row k multiplied back by 3^-k at 256 bits): the same enclosure
            let y64 = [crate::scalar::iv(a, b), crate::scalar::iv(c, d)];
            let read = Read { span: 1.0, floor: 0.0 };
            let scaled = f64_series(&tape, &y64, order, 3.0, read).expect("an f64 series");
            check_exact(&unscaled(&scaled, 3.0), [(&ma, &mb), (&mc, &md)], order, 0.0);
            // at order 200 the coefficients (about 1/200!, 1e-375) fall below f64's range,
            // those of y(s) = x(8 s) (about 8^200/200!, 1e-195) do not: the f64 series is
            // taken only with the time scale
            assert_eq!(f64_series(&tape, &y64, 200, 1.0, read).err(), Some(F64Series::Underflow));
            assert!(f64_series(&tape, &y64, 200, 8.0, read).is_ok());

            // a box 2^-200 wide: f64 would round it to 2^-53, so the series is computed at
            // 256 bits (its widths are those of the box, not of f64)
            let tiny = WideInterval::cst(2f64.powi(-100)) * WideInterval::cst(2f64.powi(-100));
            let y = [WideInterval::cst(a) + WideInterval::iv(0.0, 1.0) * tiny, WideInterval::cst(c)];
            let s = box_taylor(&tape, &y, order, 1.0, false, 0.0).expect("a series");
            let hi = y[0].to_mp().with_prec(1024);
            let hi = MpInterval::point(hi.sup(), 1024);
            check_exact(&s, [(&ma, &hi), (&mc, &mc)], order, 2f64.powi(-240));
            assert!(s[order][0].wid() < 2f64.powi(-200));

            // a box below f64's range (2^-1100 to 2^-1099): an f64 series would be the noise
            // of underflows; the series is computed at 256 bits
            let lo = (0..5).fold(WideInterval::cst(2f64.powi(-100)), |a, _| a * tiny);
            let y = [lo * WideInterval::iv(1.0, 2.0), WideInterval::cst(0.0)];
            let s = box_taylor(&tape, &y, order, 1.0, false, 0.0).expect("a series");
            let (la, lb) = (y[0].to_mp().with_prec(1024), y[0].to_mp().with_prec(1024));
            let (la, lb) = (MpInterval::point(la.inf(), 1024), MpInterval::point(lb.sup(), 1024));
            let zero = mp(0.0);
            check_exact(&s, [(&la, &lb), (&zero, &zero)], order, 0.0);
        });
    }

    /// (5.5''') A component of an a priori box that is 0 over the step becomes `[-f, f]` with
    /// `f = 1e-300` (the trial box's floor, `inflate`): its coefficients fall under f64's
    /// normal range (`1e-300 / 13!`, about `1.6e-310`, at order 13), where f64's rounding is
    /// all of their width. Their part in a step of 1 is that small, so with a floor above it
    /// the f64 series is taken and encloses the closed form; with none (or one below it) the
    /// series is computed at the set's precision.
    #[test]
    fn box_series_in_f64_take_entries_under_the_normal_range_whose_part_is_below_the_floor() {
        let tape = Tape::record(2, |x| vec![x[1], -x[0]]);
        let order = 13;
        let (a, b, f) = (0.5, 0.625, 1e-300);
        with_bits(256, || {
            let y = [WideInterval::iv(a, b), WideInterval::iv(-f, f)];
            let is_f64 = |s: &Coeffs<WideInterval>| {
                s.iter()
                    .flatten()
                    .all(|x| WideInterval::iv(Ival::inf(x), Ival::sup(x)) == *x)
            };
            let mp = |v: f64| MpInterval::from_f64(v, 1024);
            for (floor, taken) in [(0.0, false), (1e-311, false), (2f64.powi(-140), true), (1e-300, true)] {
                let s = box_taylor(&tape, &y, order, 1.0, false, floor).expect("a series");
                assert_eq!(is_f64(&s), taken, "floor {floor:e}");
                check_exact(&s, [(&mp(a), &mp(b)), (&mp(-f), &mp(f))], order, 2f64.powi(-1000));
            }
            // the part of row k is its magnitude times span^k: over a span of 2^72 the same
            // entries are too large for the floor 2^-140, and stop the series unscaled
            let y64 = [crate::scalar::iv(a, b), crate::scalar::iv(-f, f)];
            let floor = 2f64.powi(-140);
            let unit = Read { span: 1.0, floor };
            assert!(f64_series(&tape, &y64, order, 1.0, unit).is_ok());
            let long = Read { span: 2f64.powi(72), floor };
            assert_eq!(f64_series(&tape, &y64, order, 1.0, long).err(), Some(F64Series::Underflow));
        });
    }
}
