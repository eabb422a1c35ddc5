//! Rigorous interval elementary functions built on a correctly rounded libm ([spec (1.3)](crate::spec::scalars)):
//! sin, cos, tan, exp, ln, atan, sinh, cosh, tanh, asinh; sqrt is inari's own (exact
//! rounding, no libm).
//!
//! Each point value comes from CORE-MATH (the `core-math` crate), whose binary64 functions
//! are correctly rounded: the returned double `r` is a neighbour of the exact value `y`, so
//! `next_down(r) < y < next_up(r)` ([spec eq. (1.3.1)](crate::spec::scalars)); that one-ulp outward step is the
//! only rounding argument used here. Interval bounds then follow from monotone pieces; the
//! extrema of sin and cos, and the poles of tan, are located by comparing the argument with
//! multiples of pi/2 through inari's enclosure `Interval::FRAC_PI_2` (exact interval
//! division, no MPFR). Where that comparison cannot be made exactly in f64 (non-degenerate
//! arguments beyond 2^52) the answer is the whole range `[-1, 1]` (tan: the whole line).
//!
//! Conventions are inari's: the empty interval maps to itself; `ln` is restricted to its
//! natural domain (`ln([-1, 4]) = [-inf, ln 4]`, `ln([-2, 0]) = EMPTY`); an endpoint that
//! overflows is infinite (`exp([1000, 1000]) = [f64::MAX, +inf]`), so `finite()` refuses it.
//!
//! # Containment
//! For every function `f` here and every interval `x`, `f(x)` contains `f(t)` for every real
//! `t` in `x` where `f` is defined ([spec (1.3)](crate::spec::scalars)); the point values at the exact special
//! arguments (`sin 0 = 0`, `cos 0 = 1`, `exp 0 = 1`, `ln 1 = 0`, ...) are exact.

use core_math as cm;
use inari::Interval;

/// The smallest double above `x` (`x` itself for +inf and NaN; `-f64::MAX` for -inf).
#[inline]
fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    if x > 0.0 {
        f64::from_bits(b + 1)
    } else {
        f64::from_bits(b - 1)
    }
}

/// The largest double below `x`.
#[inline]
fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// `[lo, hi]`; the whole line if the pair is not an interval (never reached by the
/// functions below, whose bounds are ordered; the fallback is sound in any case).
#[inline]
fn make(lo: f64, hi: f64) -> Interval {
    Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
}

/// Lower bound of `f(x)` from the correctly rounded value (eq. (1.3.1)).
#[inline]
fn rd(f: fn(f64) -> f64, x: f64) -> f64 {
    next_down(f(x))
}

/// Upper bound of `f(x)` from the correctly rounded value (eq. (1.3.1)).
#[inline]
fn ru(f: fn(f64) -> f64, x: f64) -> f64 {
    next_up(f(x))
}

/// Beyond this magnitude a non-degenerate argument of sin, cos, tan is not reduced: the
/// integers near `x / (pi/2)` are then no longer all doubles (eq. (1.3.4)).
const REDUCTION_LIMIT: f64 = 4503599627370496.0; // 2^52

const UNIT: (f64, f64) = (-1.0, 1.0);

/// The integers `j` such that `j pi/2` may lie in `[a, b]`: a superset `[j0, j1]` computed
/// with an enclosure of pi/2 (eq. (1.3.3)). Requires finite `|a|, |b| <= 2^52`.
#[inline]
fn half_pi_multiples(x: Interval) -> (f64, f64) {
    let t = x / Interval::FRAC_PI_2;
    (t.inf().ceil(), t.sup().floor())
}

/// Sine or cosine (eq. (1.3.4)): `f` is the correctly rounded point function, `f0` its exact
/// value at 0, `peak` the residue of `j` mod 4 where `f(j pi/2) = 1` (sin: 1, cos: 0); at
/// residue `peak + 2` it is -1.
fn sin_cos(x: Interval, f: fn(f64) -> f64, f0: f64, peak: f64) -> Interval {
    if x.is_empty() {
        return x;
    }
    let (a, b) = (x.inf(), x.sup());
    if !(a.is_finite() && b.is_finite()) {
        return make(UNIT.0, UNIT.1);
    }
    let lo_at = |t: f64| if t == 0.0 { f0 } else { rd(f, t) };
    let hi_at = |t: f64| if t == 0.0 { f0 } else { ru(f, t) };
    if a == b {
        return make(lo_at(a).max(-1.0), hi_at(a).min(1.0));
    }
    if a < -REDUCTION_LIMIT || b > REDUCTION_LIMIT {
        return make(UNIT.0, UNIT.1);
    }
    let (j0, j1) = half_pi_multiples(x);
    if j1 - j0 >= 3.0 {
        // four consecutive integers: both extrema are inside
        return make(UNIT.0, UNIT.1);
    }
    let mut lo = lo_at(a).min(lo_at(b));
    let mut hi = hi_at(a).max(hi_at(b));
    let trough = (peak + 2.0) % 4.0;
    let mut j = j0;
    while j <= j1 {
        let r = j.rem_euclid(4.0);
        if r == peak {
            hi = 1.0;
        } else if r == trough {
            lo = -1.0;
        }
        j += 1.0;
    }
    make(lo.max(-1.0), hi.min(1.0))
}

/// Interval sine ([spec eq. (1.3.4)](crate::spec::scalars)).
pub fn sin(x: Interval) -> Interval {
    sin_cos(x, cm::sin, 0.0, 1.0)
}

/// Interval cosine ([spec eq. (1.3.4)](crate::spec::scalars)).
pub fn cos(x: Interval) -> Interval {
    sin_cos(x, cm::cos, 1.0, 0.0)
}

/// Interval tangent ([spec eq. (1.3.5)](crate::spec::scalars)): the whole line when a pole `(2k+1) pi/2` may lie in
/// the argument, otherwise the increasing branch between its endpoints.
pub fn tan(x: Interval) -> Interval {
    if x.is_empty() {
        return x;
    }
    let (a, b) = (x.inf(), x.sup());
    if !(a.is_finite() && b.is_finite()) {
        return Interval::ENTIRE;
    }
    let lo_at = |t: f64| if t == 0.0 { 0.0 } else { rd(cm::tan, t) };
    let hi_at = |t: f64| if t == 0.0 { 0.0 } else { ru(cm::tan, t) };
    if a == b {
        return make(lo_at(a), hi_at(a));
    }
    if a < -REDUCTION_LIMIT || b > REDUCTION_LIMIT {
        return Interval::ENTIRE;
    }
    let (j0, j1) = half_pi_multiples(x);
    // a pole is an odd multiple of pi/2: any two consecutive integers hold an odd one
    if j1 > j0 || (j1 == j0 && j0.rem_euclid(2.0) == 1.0) {
        return Interval::ENTIRE;
    }
    make(lo_at(a), hi_at(b))
}

/// Increasing `f` with `f(0) = 0` and the sign of its argument (atan, sinh, tanh), its range
/// within `[-m, m]` (eq. (1.3.2)).
fn odd_increasing(x: Interval, f: fn(f64) -> f64, m: f64) -> Interval {
    if x.is_empty() {
        return x;
    }
    let (a, b) = (x.inf(), x.sup());
    let mut lo = rd(f, a).max(-m);
    let mut hi = ru(f, b).min(m);
    if a >= 0.0 {
        lo = lo.max(0.0);
    }
    if b <= 0.0 {
        hi = hi.min(0.0);
    }
    make(lo, hi)
}

/// Interval arctangent ([spec eq. (1.3.2)](crate::spec::scalars)).
pub fn atan(x: Interval) -> Interval {
    odd_increasing(x, cm::atan, f64::INFINITY)
}

/// Interval hyperbolic sine ([spec eq. (1.3.2)](crate::spec::scalars)).
pub fn sinh(x: Interval) -> Interval {
    odd_increasing(x, cm::sinh, f64::INFINITY)
}

/// Interval inverse hyperbolic sine ([spec eq. (1.3.2)](crate::spec::scalars)).
pub fn asinh(x: Interval) -> Interval {
    odd_increasing(x, cm::asinh, f64::INFINITY)
}

/// Interval hyperbolic tangent ([spec eq. (1.3.2)](crate::spec::scalars)); within `[-1, 1]`.
pub fn tanh(x: Interval) -> Interval {
    odd_increasing(x, cm::tanh, 1.0)
}

/// Interval exponential ([spec eq. (1.3.2)](crate::spec::scalars)): increasing, positive, `>= 1` exactly on `x >= 0`.
pub fn exp(x: Interval) -> Interval {
    if x.is_empty() {
        return x;
    }
    let (a, b) = (x.inf(), x.sup());
    let mut lo = rd(cm::exp, a).max(0.0);
    let mut hi = ru(cm::exp, b);
    if a >= 0.0 {
        lo = lo.max(1.0);
    }
    if b <= 0.0 {
        hi = hi.min(1.0);
    }
    make(lo, hi)
}

/// Interval natural logarithm ([spec eq. (1.3.2)](crate::spec::scalars)), restricted to `(0, +inf)` as inari does:
/// the part of `x` at or below 0 is dropped, a lower end at or below 0 gives `-inf`, and an
/// interval with no positive point gives EMPTY. The tape checks positivity itself before
/// calling it ([spec eq. (2.10)](crate::spec::taylor)).
pub fn ln(x: Interval) -> Interval {
    if x.is_empty() {
        return x;
    }
    let (a, b) = (x.inf(), x.sup());
    if b <= 0.0 {
        return Interval::EMPTY;
    }
    let mut lo = if a <= 0.0 {
        f64::NEG_INFINITY
    } else {
        rd(cm::log, a)
    };
    let mut hi = ru(cm::log, b);
    if a >= 1.0 {
        lo = lo.max(0.0);
    }
    if b <= 1.0 {
        hi = hi.min(0.0);
    }
    make(lo, hi)
}

/// Interval hyperbolic cosine ([spec eq. (1.3.2)](crate::spec::scalars)): decreasing on `x <= 0`, increasing on
/// `x >= 0`, minimum 1 at 0.
pub fn cosh(x: Interval) -> Interval {
    if x.is_empty() {
        return x;
    }
    let (a, b) = (x.inf(), x.sup());
    let hi_at = |t: f64| if t == 0.0 { 1.0 } else { ru(cm::cosh, t) };
    let (lo, hi) = if b <= 0.0 {
        (rd(cm::cosh, b), hi_at(a))
    } else if a >= 0.0 {
        (rd(cm::cosh, a), hi_at(b))
    } else {
        (1.0, hi_at((-a).max(b)))
    };
    make(lo.max(1.0), hi)
}

/// An enclosure of pi (inari's constant: the tightest pair of doubles around it).
pub fn pi() -> Interval {
    Interval::PI
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(a: f64, b: f64) -> Interval {
        Interval::try_from((a, b)).unwrap()
    }

    #[test]
    fn neighbours() {
        assert_eq!(next_up(0.0), f64::from_bits(1));
        assert_eq!(next_up(-0.0), f64::from_bits(1));
        assert_eq!(next_down(0.0), -f64::from_bits(1));
        assert_eq!(next_up(1.0), 1.0 + f64::EPSILON);
        assert_eq!(next_down(1.0), 1.0 - f64::EPSILON / 2.0);
        assert_eq!(next_up(f64::MAX), f64::INFINITY);
        assert_eq!(next_down(f64::INFINITY), f64::MAX);
        assert_eq!(next_up(f64::NEG_INFINITY), -f64::MAX);
        assert_eq!(next_down(f64::NEG_INFINITY), f64::NEG_INFINITY);
        assert_eq!(next_up(-f64::from_bits(1)), -0.0);
    }

    #[test]
    fn exact_special_values() {
        let z = iv(0.0, 0.0);
        assert_eq!(sin(z), z);
        assert_eq!(tan(z), z);
        assert_eq!(atan(z), z);
        assert_eq!(sinh(z), z);
        assert_eq!(tanh(z), z);
        let one = iv(1.0, 1.0);
        assert_eq!(cos(z), one);
        assert_eq!(exp(z), one);
        assert_eq!(cosh(z), one);
        assert_eq!(ln(one), z);
    }

    #[test]
    fn conventions() {
        assert!(sin(Interval::EMPTY).is_empty());
        assert!(ln(iv(-2.0, 0.0)).is_empty());
        assert_eq!(ln(iv(-1.0, 1.0)).inf(), f64::NEG_INFINITY);
        assert_eq!(exp(iv(1000.0, 1000.0)), iv(f64::MAX, f64::INFINITY));
        assert_eq!(sin(Interval::ENTIRE), iv(-1.0, 1.0));
        assert_eq!(tan(iv(1.0, 2.0)), Interval::ENTIRE);
        assert_eq!(cos(iv(-0.5, 0.5)).sup(), 1.0);
        assert_eq!(sin(iv(1.0, 2.0)).sup(), 1.0);
    }
}
