//! Elementary functions of [`MpInterval`] at any precision: sqrt, exp, ln, sin, cos, tan,
//! atan, sinh, cosh, tanh, asinh and the constant pi: [spec (12.2.3)-(12.2.5)](crate::spec::precision).
//!
//! Every kernel is evaluated in the interval arithmetic of [`MpInterval`] at a working
//! precision of the requested one plus guard bits: the argument reduction (with pi and ln 2
//! themselves computed in interval arithmetic, cached per precision), then a truncated Taylor
//! series to which an interval `[-R, R]` bounding its remainder is added. So every kernel
//! value encloses the exact function value by construction; the guard bits only make it
//! tight. The result is then rounded outward to the requested precision. Interval arguments
//! go through monotonicity and periodicity (12.2.5).
//!
//! The intervals built from two ends known to be ordered (`[max, +inf]`, `[-1, 1]`, ...) fall
//! back to the whole line should the constructor ever refuse them: never reached, and the whole
//! line would still be an enclosure, so no path here panics.

use super::mp::{MpInterval, MIN_PREC};
use super::mp_float::{Mp, Round};
use std::sync::{Mutex, OnceLock};

/// Guard bits of the kernels over the requested precision.
const GUARD: u32 = 40;

/// Beyond `2^REDUCTION_LIMIT` in magnitude sin, cos and tan give up the reduction modulo
/// pi/2 (it would need more than `REDUCTION_LIMIT` bits of pi): `[-1, 1]`, the whole line.
const REDUCTION_LIMIT: i64 = 1 << 20;

fn c(x: f64, w: u32) -> MpInterval {
    MpInterval::from_f64(x, w)
}

fn int(n: i64, w: u32) -> MpInterval {
    MpInterval::point(&Mp::from_i64(n), w)
}

/// `x + [-r, r]`.
fn widen(x: &MpInterval, r: &Mp) -> MpInterval {
    let w = x.prec();
    let lo = x.inf().sub(r, w, Round::Down);
    let hi = x.sup().add(r, w, Round::Up);
    match (lo, hi) {
        (Some(lo), Some(hi)) => MpInterval::new(&lo, &hi, w).unwrap_or(MpInterval::entire(w)),
        _ => MpInterval::entire(w),
    }
}

/// `2^e` as an exact `Mp`.
fn pow2(e: i64) -> Mp {
    Mp::from_i64(1).ldexp(e, Round::Near)
}

/// Whether every point of `x` is at most `2^e` in magnitude.
fn mag_le_pow2(x: &MpInterval, e: i64) -> bool {
    x.mag() <= pow2(e)
}

/// atan(t) for `|t| <= 1/2`: `sum (-1)^n t^(2n+1)/(2n+1)` plus `[-R, R]` with
/// `R = |t|^(2N+3)/(2N+3)` (12.2.4).
fn atan_series(t: &MpInterval, w: u32) -> MpInterval {
    let t2 = t.sqr();
    let mut pw = *t;
    let mut sum = *t;
    let tiny = pow2(-(w as i64) - 8);
    let mut n: i64 = 0;
    loop {
        n += 1;
        pw = pw.mul_ref(&t2);
        let term = pw.div_u64((2 * n + 1) as u64);
        if term.mag() <= tiny.mul(&t.mag(), w, Round::Down) || n > 100_000 {
            // the remainder after the terms up to n - 1 is at most |this term|
            return widen(&sum, &term.mag());
        }
        sum = if n % 2 == 1 {
            sum.sub_ref(&term)
        } else {
            sum.add_ref(&term)
        };
    }
}

/// atanh(z) for `|z| <= 1/2`: `sum z^(2n+1)/(2n+1)` plus `[-R, R]`, `R = 2 |z|^(2N+3)/(2N+3)`
/// (the tail is at most its first term over `1 - z^2 >= 3/4`) (12.2.4).
fn atanh_series(z: &MpInterval, w: u32) -> MpInterval {
    let z2 = z.sqr();
    let mut pw = *z;
    let mut sum = *z;
    let tiny = pow2(-(w as i64) - 8);
    let mut n: i64 = 0;
    loop {
        n += 1;
        pw = pw.mul_ref(&z2);
        let term = pw.div_u64((2 * n + 1) as u64);
        if term.mag() <= tiny.mul(&z.mag(), w, Round::Down) || n > 100_000 {
            return widen(&sum, &term.mag().ldexp(1, Round::Up));
        }
        sum = sum.add_ref(&term);
    }
}

struct Consts {
    prec: u32,
    pi: MpInterval,
    ln2: MpInterval,
}

static CONSTS: OnceLock<Mutex<Vec<Consts>>> = OnceLock::new();

/// Enclosures of pi and ln 2 at (at least) `w` bits, computed once per precision (rounded
/// up to a multiple of 64) and kept (12.2.3).
fn consts(w: u32) -> (MpInterval, MpInterval) {
    let key = w.div_ceil(64) * 64;
    let cache = CONSTS.get_or_init(|| Mutex::new(Vec::new()));
    if let Ok(v) = cache.lock() {
        if let Some(k) = v.iter().find(|k| k.prec == key) {
            return (k.pi.with_prec(w), k.ln2.with_prec(w));
        }
    }
    let wk = key + 32;
    // Machin: pi = 16 atan(1/5) - 4 atan(1/239)
    let a = atan_series(&c(1.0, wk).div_ref(&c(5.0, wk)), wk);
    let b = atan_series(&c(1.0, wk).div_ref(&c(239.0, wk)), wk);
    let pi = a.ldexp(4).sub_ref(&b.ldexp(2)).with_prec(key);
    // ln 2 = 2 atanh(1/3)
    let ln2 = atanh_series(&c(1.0, wk).div_ref(&c(3.0, wk)), wk)
        .ldexp(1)
        .with_prec(key);
    if let Ok(mut v) = cache.lock() {
        if v.len() < 64 {
            v.push(Consts { prec: key, pi, ln2 });
        }
    }
    (pi.with_prec(w), ln2.with_prec(w))
}

fn pi_w(w: u32) -> MpInterval {
    consts(w).0
}

fn ln2_w(w: u32) -> MpInterval {
    consts(w).1
}

/// exp over a narrow interval `x` with finite ends (12.2.4).
fn exp_kernel(x: &MpInterval, w: u32) -> MpInterval {
    if x.is_exact_zero() {
        return c(1.0, w);
    }
    // beyond 2^44 in magnitude exp leaves the exponent range (|exp| >= 2^(1.44 2^44))
    if x.inf().top() > 44 && x.inf().is_positive() {
        return MpInterval::new(&Mp::max_value(w), &Mp::infinity(false), w)
            .unwrap_or_else(|| MpInterval::entire(w));
    }
    if x.sup().top() > 44 && x.sup().is_negative() {
        return MpInterval::new(&Mp::zero(), &Mp::min_positive(), w)
            .unwrap_or_else(|| MpInterval::entire(w));
    }
    if x.inf().top() > 44 || x.sup().top() > 44 {
        let lo = exp_kernel(&MpInterval::point(x.inf(), w), w);
        let hi = exp_kernel(&MpInterval::point(x.sup(), w), w);
        return lo.hull(&hi);
    }
    // x = k ln 2 + r, k the nearest integer to mid(x) / ln 2 (any k is correct; this one
    // makes |r| small)
    let k = (x.mid().to_f64(Round::Near) / core::f64::consts::LN_2).round() as i64;
    let w2 = w + 64;
    let r = x
        .with_prec(w2)
        .sub_ref(&int(k, w2).mul_ref(&ln2_w(w2)))
        .with_prec(w + 16);
    // t = r / 2^j with |t| <= 2^-10, exp(r) = exp(t)^(2^j)
    let j = (r.mag().top() + 10).max(0);
    let t = r.ldexp(-j);
    let wt = w + 16;
    let mut sum = c(1.0, wt);
    let mut term = c(1.0, wt);
    let tiny = pow2(-(wt as i64) - 8);
    let mut n: i64 = 0;
    loop {
        n += 1;
        term = term.mul_ref(&t).div_u64((n) as u64);
        if term.mag() <= tiny || n > 100_000 {
            // tail after the terms up to n - 1: at most |t|^n/n! (1 + |t| + |t|^2 + ...)
            // <= 2 |t|^n / n! for |t| <= 1/2, and |term| bounds |t|^n / n! from above
            sum = widen(&sum, &term.mag().ldexp(1, Round::Up));
            break;
        }
        sum = sum.add_ref(&term);
    }
    for _ in 0..j {
        sum = sum.sqr();
    }
    sum.ldexp(k).with_prec(w)
}

/// ln over a narrow interval `x` of positive finite ends (12.2.4).
fn ln_kernel(x: &MpInterval, w: u32) -> MpInterval {
    if x.sup().is_infinite() {
        let lo = ln_kernel(&MpInterval::point(x.inf(), w), w);
        return MpInterval::new(lo.inf(), &Mp::infinity(false), w)
            .unwrap_or_else(|| MpInterval::entire(w));
    }
    let one = Mp::from_i64(1);
    if *x.inf() == one && *x.sup() == one {
        return c(0.0, w);
    }
    // x = y 2^e with y near [3/4, 3/2]
    let m = x.mid();
    let mut e = m.top() - 1;
    if m.ldexp(-e, Round::Near) > Mp::from_i64(3).ldexp(-1, Round::Near) {
        e += 1;
    }
    let w2 = w + 16;
    let y = x.with_prec(w2 + 48).ldexp(-e);
    let one_i = c(1.0, w2 + 48);
    let z = y.sub_ref(&one_i).div_ref(&y.add_ref(&one_i)).with_prec(w2);
    if !mag_le_pow2(&z, -1) {
        // not narrow: split at the ends (ln is increasing)
        let lo = ln_kernel(&MpInterval::point(x.inf(), w), w);
        let hi = ln_kernel(&MpInterval::point(x.sup(), w), w);
        return lo.hull(&hi);
    }
    let ln_y = atanh_series(&z, w2).ldexp(1);
    let w3 = w + 64;
    ln_y.with_prec(w3)
        .add_ref(&int(e, w3).mul_ref(&ln2_w(w3)))
        .with_prec(w)
}

/// atan over a narrow interval with finite ends, all of one sign (12.2.4).
fn atan_kernel(x: &MpInterval, w: u32) -> MpInterval {
    if x.is_exact_zero() {
        return c(0.0, w);
    }
    if x.sup().is_negative() {
        return atan_kernel(&x.neg(), w).neg();
    }
    let w2 = w + 16;
    let one = c(1.0, w2);
    let xx = x.with_prec(w2);
    let big = *x.inf() > Mp::from_i64(1);
    // |x| > 1: atan x = pi/2 - atan(1/x)
    let mut u = if big { one.div_ref(&xx) } else { xx };
    // three halvings: atan u = 2 atan(u / (1 + sqrt(1 + u^2))), |u| <= 1 -> <= tan(pi/32)
    for _ in 0..3 {
        u = u.div_ref(&one.add_ref(&one.add_ref(&u.sqr()).sqrt()));
    }
    let a = atan_series(&u, w2).ldexp(3);
    let r = if big {
        pi_w(w2).ldexp(-1).sub_ref(&a)
    } else {
        a
    };
    r.with_prec(w)
}

/// sin and cos of a narrow interval with finite ends (12.2.4); a value not asked for
/// (`want_sin`, `want_cos`) is returned as `[-1, 1]` without its series.
fn sin_cos_kernel(
    x: &MpInterval,
    w: u32,
    want_sin: bool,
    want_cos: bool,
) -> (MpInterval, MpInterval) {
    if x.is_exact_zero() {
        return (c(0.0, w), c(1.0, w));
    }
    let w2 = w + 16;
    let raw_top = x.mag().top();
    let top = raw_top.max(0);
    let (k, r) = if raw_top <= -1 {
        // |x| < 1/2: no reduction (k = 0)
        (Mp::zero(), x.with_prec(w2))
    } else {
        // x = k pi/2 + r; pi is taken with top(x) + w + 64 bits, more if the subtraction
        // cancels (x close to a multiple of pi/2)
        let mut extra: i64 = 64;
        loop {
            let wr = (w as i64 + top + extra).min(u32::MAX as i64 / 2) as u32;
            let half_pi = pi_w(wr).ldexp(-1);
            let q = x.with_prec(wr).div_ref(&half_pi);
            let k = q
                .mid()
                .add(&Mp::from_i64(1).ldexp(-1, Round::Near), wr, Round::Near);
            let k = k.map(|v| v.floor()).unwrap_or_else(Mp::zero);
            let r = x
                .with_prec(wr)
                .sub_ref(&MpInterval::point(&k, wr).mul_ref(&half_pi));
            // bits lost to cancellation: top(x) - top(r)
            let lost = top - r.mag().top();
            if lost + 8 <= extra || extra > 4 * (w as i64 + top) {
                break (k, r.with_prec(w2));
            }
            extra = lost + 72;
        }
    };
    let q = k.integer_mod4();
    // sin x is +-sin r for even q, +-cos r for odd q; cos x the other way round
    let need_sin_r = (want_sin && q % 2 == 0) || (want_cos && q % 2 == 1);
    let need_cos_r = (want_sin && q % 2 == 1) || (want_cos && q % 2 == 0);
    let unit = MpInterval::from_f64_pair(-1.0, 1.0, w).unwrap_or_else(|| MpInterval::entire(w));
    let r2 = r.sqr();
    let tiny = pow2(-(w2 as i64) - 8);
    // sin r = sum (-1)^n r^(2n+1)/(2n+1)!, |remainder| <= |r|^(2N+3)/(2N+3)! (Lagrange)
    let s = if need_sin_r {
        let mut s = r;
        let mut term = r;
        let mut n: i64 = 0;
        loop {
            n += 1;
            term = term.mul_ref(&r2).div_u64(((2 * n) * (2 * n + 1)) as u64);
            if term.mag() <= tiny.mul(&r.mag(), w2, Round::Down) || n > 100_000 {
                break widen(&s, &term.mag());
            }
            s = if n % 2 == 1 {
                s.sub_ref(&term)
            } else {
                s.add_ref(&term)
            };
        }
    } else {
        unit
    };
    // cos r = sum (-1)^n r^(2n)/(2n)!, |remainder| <= |r|^(2N+2)/(2N+2)!
    let co = if need_cos_r {
        let mut co = c(1.0, w2);
        let mut term = c(1.0, w2);
        let mut n: i64 = 0;
        loop {
            n += 1;
            term = term.mul_ref(&r2).div_u64(((2 * n - 1) * (2 * n)) as u64);
            if term.mag() <= tiny || n > 100_000 {
                break widen(&co, &term.mag());
            }
            co = if n % 2 == 1 {
                co.sub_ref(&term)
            } else {
                co.add_ref(&term)
            };
        }
    } else {
        unit
    };
    let (s, co) = match q {
        0 => (s, co),
        1 => (co, s.neg()),
        2 => (s.neg(), co.neg()),
        _ => (co.neg(), s),
    };
    (
        s.with_prec(w).intersection(&unit),
        co.with_prec(w).intersection(&unit),
    )
}

/// sinh over a narrow interval with finite ends of one sign (12.2.4).
fn sinh_kernel(x: &MpInterval, w: u32) -> MpInterval {
    if x.is_exact_zero() {
        return c(0.0, w);
    }
    if x.sup().is_negative() {
        return sinh_kernel(&x.neg(), w).neg();
    }
    let w2 = w + 16;
    if mag_le_pow2(x, -1) {
        // sum x^(2n+1)/(2n+1)!, remainder <= cosh(x) |x|^(2N+3)/(2N+3)! <= 2 |next term|
        let x = x.with_prec(w2);
        let x2 = x.sqr();
        let tiny = pow2(-(w2 as i64) - 8);
        let mut s = x;
        let mut term = x;
        let mut n: i64 = 0;
        loop {
            n += 1;
            term = term.mul_ref(&x2).div_u64(((2 * n) * (2 * n + 1)) as u64);
            if term.mag() <= tiny.mul(&x.mag(), w2, Round::Down) || n > 100_000 {
                return widen(&s, &term.mag().ldexp(1, Round::Up)).with_prec(w);
            }
            s = s.add_ref(&term);
        }
    }
    // (e^x - e^-x) / 2, x >= 1/2: e^x >= 1.6, no harmful cancellation
    let e = exp_kernel(&x.with_prec(w2), w2);
    e.sub_ref(&e.recip()).ldexp(-1).with_prec(w)
}

/// cosh over a narrow interval with finite ends of one sign (12.2.4).
fn cosh_kernel(x: &MpInterval, w: u32) -> MpInterval {
    let w2 = w + 16;
    let x = if x.sup().is_negative() { x.neg() } else { *x };
    let e = exp_kernel(&x.with_prec(w2), w2);
    let one = c(1.0, w);
    e.add_ref(&e.recip()).ldexp(-1).with_prec(w).intersection(
        &MpInterval::new(one.inf(), &Mp::infinity(false), w)
            .unwrap_or_else(|| MpInterval::entire(w)),
    )
}

/// tanh over a narrow interval with finite ends of one sign (12.2.4).
fn tanh_kernel(x: &MpInterval, w: u32) -> MpInterval {
    if x.is_exact_zero() {
        return c(0.0, w);
    }
    if x.sup().is_negative() {
        return tanh_kernel(&x.neg(), w).neg();
    }
    let w2 = w + 16;
    let r = if mag_le_pow2(x, -1) {
        sinh_kernel(x, w2).div_ref(&cosh_kernel(x, w2))
    } else {
        // 1 - 2 / (e^(2x) + 1)
        let e = exp_kernel(&x.with_prec(w2).ldexp(1), w2);
        let two = c(2.0, w2);
        c(1.0, w2).sub_ref(&two.div_ref(&e.add_ref(&c(1.0, w2))))
    };
    r.with_prec(w).intersection(
        &MpInterval::from_f64_pair(-1.0, 1.0, w).unwrap_or_else(|| MpInterval::entire(w)),
    )
}

/// asinh over a narrow interval with finite ends of one sign (12.2.4).
fn asinh_kernel(x: &MpInterval, w: u32) -> MpInterval {
    if x.is_exact_zero() {
        return c(0.0, w);
    }
    if x.sup().is_negative() {
        return asinh_kernel(&x.neg(), w).neg();
    }
    let w2 = w + 16;
    let xx = x.with_prec(w2);
    if mag_le_pow2(x, -1) {
        // sum (-1)^n a_n x^(2n+1)/(2n+1), a_n = (2n)!/(4^n n!^2): alternating with
        // decreasing terms for |x| < 1, so the remainder is at most the first omitted term
        let x2 = xx.sqr();
        let tiny = pow2(-(w2 as i64) - 8);
        let mut s = xx;
        let mut p = xx; // a_n x^(2n+1)
        let mut n: i64 = 0;
        loop {
            n += 1;
            p = p
                .mul_ref(&x2)
                .mul_ref(&int(2 * n - 1, w2))
                .div_u64((2 * n) as u64);
            let term = p.div_u64((2 * n + 1) as u64);
            if term.mag() <= tiny.mul(&xx.mag(), w2, Round::Down) || n > 100_000 {
                return widen(&s, &term.mag()).with_prec(w);
            }
            s = if n % 2 == 1 {
                s.sub_ref(&term)
            } else {
                s.add_ref(&term)
            };
        }
    }
    if x.inf().top() > super::mp_float::EXP_LIMIT / 4 {
        // x^2 would leave the exponent range: asinh x = ln(2x) + [0, 1/(4 x^2)], and
        // 1/(4 x^2) < 2^-(2^39) is below 2^-(w + 10)
        let l = ln_kernel(&xx.ldexp(1), w2);
        let hi = l.sup().add(&pow2(-(w2 as i64) - 10), w2, Round::Up);
        return match hi {
            Some(hi) => MpInterval::new(l.inf(), &hi, w).unwrap_or(MpInterval::entire(w)),
            None => MpInterval::entire(w),
        };
    }
    // ln(x + sqrt(x^2 + 1)), x >= 1/2
    let one = c(1.0, w2);
    let t = xx.add_ref(&xx.sqr().add_ref(&one).sqrt());
    let lo = ln_kernel(&MpInterval::point(t.inf(), w2), w2);
    let hi = ln_kernel(&MpInterval::point(t.sup(), w2), w2);
    lo.hull(&hi).with_prec(w)
}

/// `[f(a).lo, f(b).hi]` for an increasing `f` evaluated by `kern` at the (finite) ends, with
/// the limits at infinite ends given.
fn increasing(
    x: &MpInterval,
    kern: fn(&MpInterval, u32) -> MpInterval,
    at_minus_inf: Mp,
    at_plus_inf: Mp,
) -> MpInterval {
    let p = x.prec();
    if x.is_empty() {
        return *x;
    }
    let w = p + GUARD;
    if x.inf() == x.sup() {
        // a point: one kernel call gives both ends
        return kern(&MpInterval::point(x.inf(), w), w).with_prec(p);
    }
    let lo = if x.inf().is_infinite() {
        at_minus_inf
    } else {
        *kern(&MpInterval::point(x.inf(), w), w).inf()
    };
    let hi = if x.sup().is_infinite() {
        at_plus_inf
    } else {
        *kern(&MpInterval::point(x.sup(), w), w).sup()
    };
    MpInterval::new(&lo, &hi, p).unwrap_or(MpInterval::entire(p))
}

/// Cuts `y` to the bounds that hold on the reals: `[lo, hi]` (either may be infinite).
fn cut(y: MpInterval, lo: f64, hi: f64) -> MpInterval {
    let p = y.prec();
    let b = MpInterval::new(
        &Mp::from_f64(lo).unwrap_or(Mp::infinity(true)),
        &Mp::from_f64(hi).unwrap_or(Mp::infinity(false)),
        p,
    )
    .unwrap_or(MpInterval::entire(p));
    y.intersection(&b)
}

/// For an odd increasing function (atan, sinh, tanh, asinh): the sign of the argument.
fn same_sign(x: &MpInterval, y: MpInterval) -> MpInterval {
    if !x.inf().is_negative() {
        cut(y, 0.0, f64::INFINITY)
    } else if !x.sup().is_positive() {
        cut(y, f64::NEG_INFINITY, 0.0)
    } else {
        y
    }
}

/// The integers `j` that may have `j pi/2` in `x` (finite, non-degenerate): `[ceil(inf T),
/// floor(sup T)]` for an enclosure `T` of `x / (pi/2)`, or `None` when more than 4 (12.2.5).
fn multiples_of_half_pi(x: &MpInterval) -> Option<Vec<u32>> {
    let top = x.mag().top().max(0);
    let w = (x.prec() as i64 + top + 64).min(u32::MAX as i64 / 2) as u32;
    let t = x.with_prec(w).div_ref(&pi_w(w).ldexp(-1));
    let j0 = t.inf().ceil();
    let j1 = t.sup().floor();
    let count = j1.sub(&j0, 64, Round::Up)?;
    if count > Mp::from_i64(3) {
        return None;
    }
    let mut out = Vec::new();
    let mut j = j0;
    while j <= j1 {
        out.push(j.integer_mod4());
        j = j.add(&Mp::from_i64(1), w.max(64) + 64, Round::Near)?;
    }
    Some(out)
}

impl MpInterval {
    /// An enclosure of pi at `prec` bits (Machin's formula in interval arithmetic, 12.2.3).
    pub fn pi(prec: u32) -> MpInterval {
        let prec = prec.max(MIN_PREC);
        pi_w(prec + GUARD).with_prec(prec)
    }

    /// An enclosure of ln 2 at `prec` bits (12.2.3).
    pub fn ln2(prec: u32) -> MpInterval {
        let prec = prec.max(MIN_PREC);
        ln2_w(prec + GUARD).with_prec(prec)
    }

    /// Square root, rounded outward; the part of the argument below 0 is dropped
    /// (`sqrt([-1, 4]) = [0, 2]`, empty if `x < 0` everywhere) (12.2.5).
    pub fn sqrt(&self) -> MpInterval {
        let p = self.prec();
        if self.is_empty() || self.sup().is_negative() {
            return MpInterval::empty(p);
        }
        let lo = (*self.inf()).max(Mp::zero());
        let lo = lo.sqrt(p, Round::Down).unwrap_or_else(Mp::zero);
        let hi = self.sup().sqrt(p, Round::Up).unwrap_or(Mp::infinity(false));
        MpInterval::new(&lo, &hi, p).unwrap_or(MpInterval::entire(p))
    }

    /// `e^x` (12.2.4, 12.2.5).
    pub fn exp(&self) -> MpInterval {
        let y = cut(
            increasing(self, exp_kernel, Mp::zero(), Mp::infinity(false)),
            0.0,
            f64::INFINITY,
        );
        if !self.inf().is_negative() {
            cut(y, 1.0, f64::INFINITY)
        } else if !self.sup().is_positive() {
            cut(y, 0.0, 1.0)
        } else {
            y
        }
    }

    /// Natural logarithm; the part of the argument at or below 0 is dropped: an argument
    /// reaching 0 or below gives `-inf` as lower end, one with no positive point is empty
    /// (12.2.5).
    pub fn ln(&self) -> MpInterval {
        let p = self.prec();
        if self.is_empty() || !self.sup().is_positive() {
            return MpInterval::empty(p);
        }
        if !self.inf().is_positive() {
            let hi = if self.sup().is_infinite() {
                Mp::infinity(false)
            } else {
                let w = p + GUARD;
                *ln_kernel(&MpInterval::point(self.sup(), w), w).sup()
            };
            return MpInterval::new(&Mp::infinity(true), &hi, p)
                .unwrap_or_else(|| MpInterval::entire(p));
        }
        let y = increasing(self, ln_kernel, Mp::infinity(true), Mp::infinity(false));
        let one = Mp::from_i64(1);
        if *self.inf() >= one {
            cut(y, 0.0, f64::INFINITY)
        } else if *self.sup() <= one {
            cut(y, f64::NEG_INFINITY, 0.0)
        } else {
            y
        }
    }

    /// Arctangent (12.2.4, 12.2.5).
    pub fn atan(&self) -> MpInterval {
        let p = self.prec();
        let half_pi = MpInterval::pi(p + GUARD).ldexp(-1);
        let y = increasing(self, atan_kernel, half_pi.sup().neg(), *half_pi.sup());
        same_sign(self, y)
    }

    /// Hyperbolic sine (12.2.4, 12.2.5).
    pub fn sinh(&self) -> MpInterval {
        same_sign(
            self,
            increasing(self, sinh_kernel, Mp::infinity(true), Mp::infinity(false)),
        )
    }

    /// Hyperbolic tangent (12.2.4, 12.2.5).
    pub fn tanh(&self) -> MpInterval {
        same_sign(
            self,
            increasing(self, tanh_kernel, Mp::from_i64(-1), Mp::from_i64(1)),
        )
    }

    /// Inverse hyperbolic sine (12.2.4, 12.2.5).
    pub fn asinh(&self) -> MpInterval {
        same_sign(
            self,
            increasing(self, asinh_kernel, Mp::infinity(true), Mp::infinity(false)),
        )
    }

    /// Hyperbolic cosine: decreasing on `x <= 0`, increasing on `x >= 0`, 1 at 0 (12.2.5).
    pub fn cosh(&self) -> MpInterval {
        let p = self.prec();
        if self.is_empty() {
            return *self;
        }
        let w = p + GUARD;
        let at = |v: &Mp| -> MpInterval {
            if v.is_infinite() {
                MpInterval::new(&Mp::max_value(p), &Mp::infinity(false), w)
                    .unwrap_or_else(|| MpInterval::entire(w))
            } else {
                cosh_kernel(&MpInterval::point(v, w), w)
            }
        };
        let (lo, hi) = if !self.inf().is_negative() {
            (*at(self.inf()).inf(), *at(self.sup()).sup())
        } else if !self.sup().is_positive() {
            (*at(self.sup()).inf(), *at(self.inf()).sup())
        } else {
            let m = self.inf().abs().max(self.sup().abs());
            (Mp::from_i64(1), *at(&m).sup())
        };
        MpInterval::new(&lo, &hi, p).unwrap_or(MpInterval::entire(p))
    }

    /// Sine: the hull of the values at the ends and of the extrema `±1` at the multiples of
    /// pi/2 that may lie inside (12.2.5).
    pub fn sin(&self) -> MpInterval {
        self.sin_cos_range(true)
    }

    /// Cosine, as [`MpInterval::sin`] (12.2.5).
    pub fn cos(&self) -> MpInterval {
        self.sin_cos_range(false)
    }

    fn sin_cos_range(&self, sin: bool) -> MpInterval {
        let p = self.prec();
        let unit = MpInterval::from_f64_pair(-1.0, 1.0, p).unwrap_or_else(|| MpInterval::entire(p));
        if self.is_empty() {
            return *self;
        }
        if !self.is_finite() || self.mag().top() > REDUCTION_LIMIT {
            return unit;
        }
        let w = p + GUARD;
        let at = |v: &Mp| {
            let (s, c) = sin_cos_kernel(&MpInterval::point(v, w), w, sin, !sin);
            if sin {
                s
            } else {
                c
            }
        };
        if self.inf() == self.sup() {
            return at(self.inf()).with_prec(p);
        }
        let Some(js) = multiples_of_half_pi(self) else {
            return unit;
        };
        let mut r = at(self.inf()).hull(&at(self.sup()));
        for j in js {
            // sin has its maximum at j = 1 (mod 4), minimum at 3; cos at 0 and 2
            let v = match (sin, j) {
                (true, 1) | (false, 0) => 1.0,
                (true, 3) | (false, 2) => -1.0,
                _ => continue,
            };
            r = r.hull(&c(v, w));
        }
        r.with_prec(p).intersection(&unit)
    }

    /// `(sin x, cos x)` with one argument reduction for a point `x` (as [`MpInterval::sin`]
    /// and [`MpInterval::cos`] otherwise) (12.2.4, 12.2.5).
    pub fn sin_cos(&self) -> (MpInterval, MpInterval) {
        let p = self.prec();
        if self.is_empty() || self.inf() != self.sup() || self.mag().top() > REDUCTION_LIMIT {
            return (self.sin(), self.cos());
        }
        let w = p + GUARD;
        let (s, c) = sin_cos_kernel(&MpInterval::point(self.inf(), w), w, true, true);
        (s.with_prec(p), c.with_prec(p))
    }

    /// Tangent: the whole line if a pole (odd multiple of pi/2) may lie in the argument,
    /// else increasing (12.2.5).
    pub fn tan(&self) -> MpInterval {
        let p = self.prec();
        if self.is_empty() {
            return *self;
        }
        if !self.is_finite() || self.mag().top() > REDUCTION_LIMIT {
            return MpInterval::entire(p);
        }
        let w = p + GUARD;
        let at = |v: &Mp| {
            let (s, c) = sin_cos_kernel(&MpInterval::point(v, w), w, true, true);
            s.div_ref(&c)
        };
        if self.inf() != self.sup() {
            match multiples_of_half_pi(self) {
                Some(js) if js.iter().all(|j| j % 2 == 0) => {}
                _ => return MpInterval::entire(p),
            }
        }
        let lo = at(self.inf());
        let hi = at(self.sup());
        if lo.is_empty() || hi.is_empty() {
            return MpInterval::entire(p);
        }
        MpInterval::new(lo.inf(), hi.sup(), p).unwrap_or(MpInterval::entire(p))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: u32 = 256;

    fn iv(x: f64) -> MpInterval {
        MpInterval::from_f64(x, P)
    }

    /// The width in units of `2^(top(mag) - prec)`, rounded up.
    fn ulps(x: &MpInterval) -> i64 {
        let w = x.sup().sub(x.inf(), 8192, Round::Up).unwrap();
        if w.is_zero() {
            return 0;
        }
        let u = pow2(x.mag().top() - x.prec() as i64);
        w.div(&u, 64, Round::Up)
            .unwrap()
            .ceil()
            .to_i64()
            .unwrap_or(i64::MAX)
    }

    #[test]
    fn pi_and_ln2_against_decimals() {
        // 70 digits of pi and ln 2 (closed forms known to every table), truncated and + 1e-69
        let pi_lo = "3.141592653589793238462643383279502884197169399375105820974944592307816";
        let pi_hi = "3.141592653589793238462643383279502884197169399375105820974944592307817";
        let pi = MpInterval::pi(P);
        assert!(MpInterval::from_decimal(pi_lo, 2 * P).unwrap().sup() < pi.inf());
        assert!(pi.sup() < MpInterval::from_decimal(pi_hi, 2 * P).unwrap().inf());
        assert!(ulps(&pi) <= 2, "{}", ulps(&pi));
        let l_lo = "0.6931471805599453094172321214581765680755001343602552541206800094933936";
        let l_hi = "0.6931471805599453094172321214581765680755001343602552541206800094933937";
        let l = MpInterval::ln2(P);
        assert!(MpInterval::from_decimal(l_lo, 2 * P).unwrap().sup() < l.inf());
        assert!(l.sup() < MpInterval::from_decimal(l_hi, 2 * P).unwrap().inf());
        assert!(ulps(&l) <= 2);
    }

    #[test]
    fn closed_forms() {
        // sin(pi) contains 0 and is tiny
        let s = MpInterval::pi(P).sin();
        assert!(s.contains_f64(0.0));
        assert!(s.mag_up() < 1e-74);
        // exp(ln 2) contains 2
        let e = MpInterval::ln2(P).exp();
        assert!(e.contains_f64(2.0) && e.wid_up() < 1e-74);
        // sqrt(2)^2 contains 2
        let r = iv(2.0).sqrt();
        assert!(r.sqr().contains_f64(2.0) && ulps(&r) <= 1);
        // 4 atan(1) = pi, cos(0) = 1, tan(pi/4) = 1, sinh/cosh/tanh consistency
        let a = iv(1.0).atan().ldexp(2);
        assert!(!a.disjoint(&MpInterval::pi(P)) && ulps(&a) <= 4);
        assert_eq!(iv(0.0).cos(), iv(1.0));
        let t = MpInterval::pi(P).ldexp(-2).tan();
        assert!(t.contains_f64(1.0) && t.wid_up() < 1e-74);
        let x = iv(0.75);
        let ch = x.cosh();
        let sh = x.sinh();
        assert!((ch.sqr() - sh.sqr()).contains_f64(1.0));
        assert!(!(sh / ch).disjoint(&x.tanh()));
        // asinh(sinh x) = x, ln(exp x) = x
        assert!(sh.asinh().contains_f64(0.75));
        assert!(iv(-3.5).exp().ln().contains_f64(-3.5));
        let (s, c) = iv(2.5).sin_cos();
        assert_eq!((s, c), (iv(2.5).sin(), iv(2.5).cos()));
        assert!(iv(1e-300).asinh().contains_f64(1e-300));
        assert!(iv(-0.3).sinh().asinh().contains_f64(-0.3));
        for f in [
            MpInterval::exp,
            MpInterval::ln,
            MpInterval::sin,
            MpInterval::cos,
            MpInterval::tan,
            MpInterval::atan,
            MpInterval::sinh,
            MpInterval::cosh,
            MpInterval::tanh,
            MpInterval::asinh,
        ] {
            for x in [0.3, 2.5, 1e-20, 1e5, -7.25, 1e22] {
                let y = f(&iv(x));
                assert!(y.is_empty() || !y.is_finite() || ulps(&y) <= 3, "{x}: {y}");
            }
        }
    }

    #[test]
    fn interval_arguments() {
        let x = MpInterval::from_f64_pair(1.0, 2.0, P).unwrap();
        let s = x.sin();
        // sin has its maximum 1 at pi/2 inside [1, 2]
        assert_eq!(*s.sup(), Mp::from_i64(1));
        assert!(s.inf() <= iv(1.0).sin().inf());
        let c = x.cos();
        assert!(c.contains(&iv(2.0).cos().inf().clone()) && c.sup() >= iv(1.0).cos().sup());
        assert!(!x.tan().is_finite());
        let wide = MpInterval::from_f64_pair(0.0, 7.0, P).unwrap();
        assert_eq!(wide.sin(), MpInterval::from_f64_pair(-1.0, 1.0, P).unwrap());
        let y = MpInterval::from_f64_pair(-1.0, 4.0, P).unwrap();
        assert_eq!(y.sqrt(), MpInterval::from_f64_pair(0.0, 2.0, P).unwrap());
        assert!(y.ln().inf().is_infinite());
        assert!(MpInterval::from_f64_pair(-2.0, -1.0, P)
            .unwrap()
            .ln()
            .is_empty());
        assert_eq!(*y.cosh().inf(), Mp::from_i64(1));
        assert!(MpInterval::entire(P).exp().inf().is_zero());
        assert_eq!(*MpInterval::entire(P).tanh().sup(), Mp::from_i64(1));
        assert!(MpInterval::empty(P).sin().is_empty());
        let big = iv(1e300);
        assert!(big.exp().sup().is_infinite() && big.exp().inf() >= &Mp::max_value(P));
        assert!(iv(-1e300).exp().inf().is_zero());
        assert_eq!(big.tanh().sup(), &Mp::from_i64(1));
        let s = big.sin();
        assert!(ulps(&s) <= 3, "{s}");
        // numbers far beyond the doubles: answers, no hang
        let huge = MpInterval::point(&Mp::from_i64(3).ldexp(1 << 39, Round::Near), P);
        let unit = MpInterval::from_f64_pair(-1.0, 1.0, P).unwrap();
        assert_eq!(huge.sin(), unit);
        assert!(!huge.tan().is_finite());
        assert!(huge.exp().sup().is_infinite());
        assert_eq!(huge.tanh().sup(), &Mp::from_i64(1));
        let a = huge.asinh();
        let l = huge.ln();
        assert!(a.is_finite() && l.is_finite() && a.inf() > l.sup());
        assert!(huge.atan().subset(&MpInterval::pi(P).ldexp(-1).hull(&unit)));
        assert!(huge.sqr().sup().is_infinite() && huge.sqrt().is_finite());
        let tiny = MpInterval::point(&Mp::from_i64(3).ldexp(-(1 << 39), Round::Near), P);
        assert_eq!(tiny.exp().inf(), &Mp::from_i64(1));
        assert_eq!(tiny.neg().exp().sup(), &Mp::from_i64(1));
        assert!(!tiny.sinh().inf().is_negative() && !tiny.neg().atan().sup().is_positive());
        assert!(!iv(1.0 + 1e-15).ln().inf().is_negative());
        assert!(tiny.sin().contains(tiny.inf()) || tiny.sin().sup() >= tiny.inf());
        assert!(tiny.ln().is_finite() && tiny.atan().is_finite());
        assert!(huge.to_string().starts_with("[1e"));
    }
}
