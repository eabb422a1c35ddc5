//! Double-double numbers and intervals (about 106 bits): the point type [`Dd`] (an
//! unevaluated sum `hi + lo` of two doubles) and the interval type [`DdInterval`] whose every
//! operation rounds outward ([spec (12.1)](crate::spec::precision)).
//!
//! The point operations are the classical error-free-transformation algorithms of Joldes,
//! Muller and Popescu (2017); they are approximations, used for centres and Newton guesses.
//! The interval operations compute such an approximation `h + l` together with a rigorous
//! f64 bound `e` of its error (every f64 operation of the bound is followed by `next_up`, so
//! the bound is an upper bound whatever the rounding did), and return
//! `[h + down(l - e), h + up(l + e)]` renormalised exactly ([spec (12.1.3)](crate::spec::precision)).
//!
//! # Containment
//! For every operation `op` and intervals `x, y`, `op(x, y)` contains `op(s, t)` for all reals
//! `s` in `x`, `t` in `y` where `op` is defined ([spec (12.1.4)](crate::spec::precision)).

use super::dd_big::Big;
use core::cmp::Ordering;
use core::fmt;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// `u = 2^-53`, the unit roundoff of binary64.
const U: f64 = 1.0 / 9007199254740992.0;
/// `2^-1074`, the smallest positive subnormal: a bound of the underflow error of one product.
const ETA: f64 = f64::from_bits(1);
/// `2^1023`: a lower bound of every overflowing result ([spec (12.1.3)](crate::spec::precision)).
const TWO_1023: f64 = f64::from_bits(2046 << 52);

/// An upper bound of `x` when `x` is the rounded-to-nearest value of a real `y >= 0`: the next
/// double up is `>= y` ([spec (12.1.2)](crate::spec::precision)). Only for `x >= +0` (the bounds
/// here are sums and products of absolute values): then the next double up is the next bit
/// pattern; `+inf` and NaN give NaN, which every later finiteness check refuses.
#[inline(always)]
fn up(x: f64) -> f64 {
    debug_assert!(
        x.is_nan() || x.to_bits() >> 63 == 0,
        "up() of a negative number"
    );
    f64::from_bits(x.to_bits().wrapping_add(1))
}

/// TwoSum (Knuth): `s + t == a + b` exactly, `s = fl(a + b)`, for finite `a, b` with a finite sum.
#[inline(always)]
pub(super) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let t = (a - (s - bb)) + (b - bb);
    (s, t)
}

/// Fast2Sum (Dekker): exact when the exponent of `a` is at least that of `b` (or `a == 0`).
#[inline(always)]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let t = b - (s - a);
    (s, t)
}

/// FMA-based TwoProd: `p + e == a * b` exactly unless the product underflows (then the error
/// of `e` is at most `2^-1075`).
#[inline(always)]
pub(super) fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let e = a.mul_add(b, -p);
    (p, e)
}

/// A double-double number: the exact real `hi + lo`, normalised so that `hi = fl(hi + lo)`
/// (hence `|lo| <= ulp(hi)/2`). Infinite values have `lo == 0`. The arithmetic is approximate
/// (relative errors of a few `2^-106`, [spec (12.1.1)](crate::spec::precision)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Dd {
    hi: f64,
    lo: f64,
}

impl Dd {
    /// 0.
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    /// 1.
    pub const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };
    /// `+inf` (an end of an unbounded interval, not a real).
    pub const INFINITY: Dd = Dd {
        hi: f64::INFINITY,
        lo: 0.0,
    };
    /// `-inf`.
    pub const NEG_INFINITY: Dd = Dd {
        hi: f64::NEG_INFINITY,
        lo: 0.0,
    };
    /// `f64::MAX`.
    pub const MAX: Dd = Dd {
        hi: f64::MAX,
        lo: 0.0,
    };

    /// The exact double `x` (`-0.0` becomes `+0.0`).
    #[inline]
    pub fn from_f64(x: f64) -> Dd {
        Dd {
            hi: x + 0.0,
            lo: 0.0,
        }
    }

    /// The pair `(hi, lo)` as given; the caller guarantees `hi == fl(hi + lo)`.
    pub(super) const fn from_parts(hi: f64, lo: f64) -> Dd {
        Dd { hi, lo }
    }

    /// The exact sum `hi + lo` of two finite doubles, renormalised (TwoSum, exact).
    #[inline]
    pub fn new(hi: f64, lo: f64) -> Dd {
        let (s, t) = two_sum(hi, lo);
        if s.is_finite() {
            Dd {
                hi: s + 0.0,
                lo: t + 0.0,
            }
        } else {
            Dd { hi: s, lo: 0.0 }
        }
    }

    /// The leading double (the value rounded to nearest).
    #[inline]
    pub fn hi(self) -> f64 {
        self.hi
    }

    /// The trailing double.
    #[inline]
    pub fn lo(self) -> f64 {
        self.lo
    }

    /// The value rounded to nearest.
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.hi
    }

    /// The largest double `<=` the value.
    #[inline]
    pub fn to_f64_down(self) -> f64 {
        if self.lo < 0.0 {
            self.hi.next_down()
        } else {
            self.hi
        }
    }

    /// The smallest double `>=` the value.
    #[inline]
    pub fn to_f64_up(self) -> f64 {
        if self.lo > 0.0 {
            self.hi.next_up()
        } else {
            self.hi
        }
    }

    /// Not infinite and not NaN.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite()
    }

    /// NaN (only from a NaN given to [`Dd::new`] or [`Dd::from_f64`]).
    pub fn is_nan(self) -> bool {
        self.hi.is_nan()
    }

    /// `|x|` (exact).
    #[inline]
    pub fn abs(self) -> Dd {
        if self.hi < 0.0 {
            -self
        } else {
            self
        }
    }

    /// `2^k * self` for `|k| <= 1000`, exact unless it leaves the normal range.
    #[inline]
    pub fn scale_pow2(self, k: i32) -> Dd {
        let p = pow2(k);
        Dd::new(self.hi * p, self.lo * p)
    }

    /// `2^k * self` for `0 <= k <= 1100` and `|self| < 2^-800`: exact (scaling up loses no bit).
    #[inline]
    fn scale_pow2_up(self, k: i32) -> Dd {
        let k1 = k / 2;
        let (p1, p2) = (pow2(k1), pow2(k - k1));
        Dd::new(self.hi * p1 * p2, self.lo * p1 * p2)
    }

    /// `self * a + b`, two rounded double-double operations.
    #[inline]
    pub fn mul_add(self, a: Dd, b: Dd) -> Dd {
        self * a + b
    }

    /// Square root (0 for negative input), relative error about `2^-104`
    /// ([spec (12.1.1)](crate::spec::precision)).
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 || !self.hi.is_finite() {
            return if self.hi == f64::INFINITY {
                self
            } else {
                Dd::ZERO
            };
        }
        let s = self.hi.sqrt();
        let r = (-s).mul_add(s, self.hi) + self.lo;
        let c = r / (2.0 * s);
        let (h, l) = fast_two_sum(s, c);
        Dd { hi: h, lo: l }
    }

    fn is_zero(self) -> bool {
        self.hi == 0.0
    }
}

/// `2^k` for `-1074 <= k <= 1023` (exact).
#[inline]
pub(super) fn pow2(k: i32) -> f64 {
    if k >= -1022 {
        f64::from_bits(((k + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (k + 1074))
    }
}

impl PartialEq for Dd {
    fn eq(&self, o: &Dd) -> bool {
        self.hi == o.hi && self.lo == o.lo
    }
}

impl PartialOrd for Dd {
    /// Exact comparison of the values: `hi` is the rounding to nearest of the value, which is
    /// monotone, so the pairs compare lexicographically.
    fn partial_cmp(&self, o: &Dd) -> Option<Ordering> {
        match self.hi.partial_cmp(&o.hi)? {
            Ordering::Equal => self.lo.partial_cmp(&o.lo),
            c => Some(c),
        }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Dd {
        Dd::from_f64(x)
    }
}

impl Neg for Dd {
    type Output = Dd;
    #[inline]
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi + 0.0,
            lo: -self.lo + 0.0,
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    /// AccurateDWPlusDW (JMP 2017, Algorithm 6): relative error at most `3u^2 + 13u^3`.
    #[inline]
    fn add(self, o: Dd) -> Dd {
        let (sh, sl) = two_sum(self.hi, o.hi);
        let (th, tl) = two_sum(self.lo, o.lo);
        let c = sl + th;
        let (vh, vl) = fast_two_sum(sh, c);
        let w = tl + vl;
        let (h, l) = fast_two_sum(vh, w);
        if h.is_finite() {
            Dd { hi: h, lo: l }
        } else {
            Dd {
                hi: self.hi + o.hi,
                lo: 0.0,
            }
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    #[inline]
    fn sub(self, o: Dd) -> Dd {
        self + (-o)
    }
}

impl Mul for Dd {
    type Output = Dd;
    /// DWTimesDW3 (JMP 2017, Algorithm 12, FMA): relative error at most `4u^2`.
    #[inline]
    fn mul(self, o: Dd) -> Dd {
        let (ch, cl1) = two_prod(self.hi, o.hi);
        let tl0 = self.lo * o.lo;
        let tl1 = self.hi.mul_add(o.lo, tl0);
        let cl2 = self.lo.mul_add(o.hi, tl1);
        let cl3 = cl1 + cl2;
        let (h, l) = fast_two_sum(ch, cl3);
        if h.is_finite() {
            Dd { hi: h, lo: l }
        } else {
            Dd { hi: ch, lo: 0.0 }
        }
    }
}

impl Div for Dd {
    type Output = Dd;
    /// DWDivDW2 (JMP 2017, Algorithm 17): relative error at most `15u^2 + 56u^3`.
    #[inline]
    fn div(self, o: Dd) -> Dd {
        let th = self.hi / o.hi;
        if !th.is_finite() || th == 0.0 {
            return Dd::from_f64(th);
        }
        // DWTimesFP1 (Algorithm 7): r = o * th.
        let (ch, cl1) = two_prod(o.hi, th);
        let cl2 = o.lo * th;
        let (t1h, t1l) = fast_two_sum(ch, cl2);
        let t2 = t1l + cl1;
        let (rh, rl) = fast_two_sum(t1h, t2);
        let pih = self.hi - rh;
        let dl = self.lo - rl;
        let d = pih + dl;
        let tl = d / o.hi;
        let (h, l) = fast_two_sum(th, tl);
        Dd { hi: h, lo: l }
    }
}

/// An interval `[lo, hi]` of reals with double-double ends, outward rounded: every operation
/// returns a superset of the exact range ([spec (12.1.4)](crate::spec::precision)). The
/// empty interval is `[+inf, -inf]`; a lower end is never `+inf` and an upper end never
/// `-inf` otherwise, and no end is NaN.
#[derive(Clone, Copy, PartialEq)]
pub struct DdInterval {
    pub(super) lo: Dd,
    pub(super) hi: Dd,
}

/// Lower end `h + l` from doubles with `h + l` exactly its value (TwoSum, exact); a sum that
/// overflows is `>= 2^1023` in magnitude, so `f64::MAX` (positive) or `-inf` (negative) bounds it
/// from below.
#[inline(always)]
fn end_down(h: f64, l: f64) -> Dd {
    let (s, t) = two_sum(h, l);
    if s.is_finite() {
        Dd {
            hi: s + 0.0,
            lo: t + 0.0,
        }
    } else if s > 0.0 {
        Dd::MAX
    } else {
        Dd::NEG_INFINITY
    }
}

/// Upper end, as [`end_down`].
#[inline(always)]
fn end_up(h: f64, l: f64) -> Dd {
    let (s, t) = two_sum(h, l);
    if s.is_finite() {
        Dd {
            hi: s + 0.0,
            lo: t + 0.0,
        }
    } else if s < 0.0 {
        -Dd::MAX
    } else {
        Dd::INFINITY
    }
}

/// The interval `[h + l - e, h + l + e]` rounded outward, given `|exact - (h + l)| <= e`
/// ([spec (12.1.3)](crate::spec::precision)). A non-finite `h` means the exact value overflowed
/// with the sign of `h` (its magnitude is then at least `2^1023`, (12.1.3)); any other
/// non-finite input gives the whole line.
#[inline(always)]
fn enclose(h: f64, l: f64, e: f64) -> DdInterval {
    if !h.is_finite() {
        return overflow(h);
    }
    let ld = -next_up_fast(e - l);
    let lu = next_up_fast(l + e);
    if !(ld.is_finite() && lu.is_finite()) {
        return DdInterval::ENTIRE;
    }
    DdInterval {
        lo: end_down(h, ld),
        hi: end_up(h, lu),
    }
}

/// The next double above `x` for finite `x` (branch-free: `-0.0` is first mapped to `+0.0`,
/// then the bit pattern moves one step away from or toward zero); `+inf` and NaN give NaN,
/// which the callers refuse.
#[inline(always)]
fn next_up_fast(x: f64) -> f64 {
    let y = x + 0.0;
    let b = y.to_bits();
    let step = if y >= 0.0 { 1u64 } else { u64::MAX };
    f64::from_bits(b.wrapping_add(step))
}

/// The enclosure of a real known to be at least `2^1023` in magnitude with the sign of `h`.
#[inline(never)]
fn overflow(h: f64) -> DdInterval {
    if h == f64::INFINITY {
        DdInterval {
            lo: Dd::from_f64(TWO_1023),
            hi: Dd::INFINITY,
        }
    } else if h == f64::NEG_INFINITY {
        DdInterval {
            lo: Dd::NEG_INFINITY,
            hi: Dd::from_f64(-TWO_1023),
        }
    } else {
        DdInterval::ENTIRE
    }
}

/// `(h, l, e)` with `|x + y - (h + l)| <= e` for finite `x, y`; `e = 0` when `h + l` is exact
/// and `(h, l)` normalised; `h` infinite when the leading sum overflows
/// ([spec (12.1.5)](crate::spec::precision)).
#[inline(always)]
fn add_core(x: Dd, y: Dd) -> (f64, f64, f64) {
    let (s, t) = two_sum(x.hi, y.hi);
    if !s.is_finite() {
        // fl(x_h + y_h) overflowed: |x + y| >= (1 - u) f64::MAX > 2^1023 (12.1.3).
        return (s, 0.0, 0.0);
    }
    let (u, v) = two_sum(x.lo, y.lo);
    let (w, we) = two_sum(t, u);
    let (zh, zl) = two_sum(s, w);
    // x + y == zh + zl + we + v exactly.
    if we == 0.0 && v == 0.0 {
        return (zh + 0.0, zl + 0.0, 0.0);
    }
    let r = we + v;
    let l = zl + r;
    let e = up(U * up(r.abs() + l.abs()));
    (zh, l, e)
}

/// The enclosure of `x + y` for finite `x, y` ([spec (12.1.5)](crate::spec::precision)).
#[inline(always)]
fn add_pt(x: Dd, y: Dd) -> DdInterval {
    let (h, l, e) = add_core(x, y);
    if e == 0.0 && h.is_finite() {
        let d = Dd { hi: h, lo: l };
        return DdInterval { lo: d, hi: d };
    }
    enclose(h, l, e)
}

/// `(h, l, e)` with `|x y - (h + l)| <= e` for finite `x, y`; `e = 0` when exact
/// ([spec (12.1.6)](crate::spec::precision)).
#[inline(always)]
fn mul_core(x: Dd, y: Dd) -> (f64, f64, f64) {
    if x.hi == 0.0 || y.hi == 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let (ch, cl1) = two_prod(x.hi, y.hi);
    if x.lo == 0.0 && y.lo == 0.0 && ch.is_finite() && ch.abs() >= EXACT_PRODUCT {
        // A product of two doubles, no underflow: ch + cl1 is exact (TwoProd).
        return (ch + 0.0, cl1 + 0.0, 0.0);
    }
    let tl0 = x.lo * y.lo;
    let tl1 = x.hi.mul_add(y.lo, tl0);
    let cl2 = x.lo.mul_add(y.hi, tl1);
    let cl3 = cl1 + cl2;
    let s = up(up(up(tl0.abs() + tl1.abs()) + cl2.abs()) + cl3.abs());
    let e = up(up(U * s) + 4.0 * ETA);
    (ch, cl3, e)
}

/// The enclosure of `x * y` for finite `x, y` ([spec (12.1.6)](crate::spec::precision)).
#[inline(always)]
fn mul_pt(x: Dd, y: Dd) -> DdInterval {
    let (h, l, e) = mul_core(x, y);
    if e == 0.0 && h.is_finite() {
        let d = Dd { hi: h, lo: l };
        return DdInterval { lo: d, hi: d };
    }
    enclose(h, l, e)
}

/// An upper bound of `a + b` for `a, b >= 0` (exact when one is 0).
#[inline(always)]
fn add_up(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        b
    } else if b == 0.0 {
        a
    } else {
        up(a + b)
    }
}

/// An upper bound of `a b` for `a, b >= 0` (exactly 0 when one is 0).
#[inline(always)]
fn mul_up(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        0.0
    } else {
        up(a * b)
    }
}

/// A ball `c +- r`: a double-double centre and an f64 radius, standing for every real within
/// `r` of `c` ([spec (12.1.19)](crate::spec::precision)). The elementary functions evaluate
/// their series in balls: one error-free product or sum per operation instead of one per end.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ball {
    c: Dd,
    r: f64,
}

impl Ball {
    /// A ball containing the interval (finite, non-empty; otherwise the radius is infinite).
    pub(super) fn from_interval(x: DdInterval) -> Ball {
        if x.is_empty() || !x.is_finite() {
            return Ball {
                c: Dd::ZERO,
                r: f64::INFINITY,
            };
        }
        if x.is_point() {
            return Ball { c: x.lo, r: 0.0 };
        }
        let c = x.mid();
        let r = add_pt(x.hi, -c)
            .hi
            .to_f64_up()
            .max(add_pt(c, -x.lo).hi.to_f64_up());
        Ball { c, r }
    }

    /// The interval of the ball, rounded outward (12.1.3).
    pub(super) fn to_interval(self) -> DdInterval {
        if !(self.r.is_finite() && self.c.hi.is_finite()) {
            return DdInterval::ENTIRE;
        }
        if self.r == 0.0 {
            return DdInterval {
                lo: self.c,
                hi: self.c,
            };
        }
        enclose(self.c.hi, self.c.lo, self.r)
    }

    /// The centre `h + l` renormalised exactly, the radius enlarged by `e`.
    #[inline(always)]
    fn make(h: f64, l: f64, r: f64) -> Ball {
        let (a, b) = two_sum(h, l);
        if a.is_finite() && r.is_finite() {
            Ball {
                c: Dd {
                    hi: a + 0.0,
                    lo: b + 0.0,
                },
                r,
            }
        } else {
            Ball {
                c: Dd::ZERO,
                r: f64::INFINITY,
            }
        }
    }

    /// An upper bound of `|c|`.
    #[inline(always)]
    fn mag_c(self) -> f64 {
        add_up(self.c.hi.abs(), self.c.lo.abs())
    }

    #[inline(always)]
    pub(super) fn add(self, o: Ball) -> Ball {
        let (h, l, e) = add_core(self.c, o.c);
        Ball::make(h, l, add_up(add_up(self.r, o.r), e))
    }

    /// `|ab - c_a c_b| <= |c_a| r_b + |c_b| r_a + r_a r_b`, plus the rounding of `c_a c_b`.
    #[inline(always)]
    pub(super) fn mul(self, o: Ball) -> Ball {
        let (h, l, e) = mul_core(self.c, o.c);
        let r = if self.r == 0.0 && o.r == 0.0 {
            e
        } else {
            let cross = add_up(mul_up(self.mag_c(), o.r), mul_up(o.mag_c(), self.r));
            add_up(add_up(cross, mul_up(self.r, o.r)), e)
        };
        Ball::make(h, l, r)
    }

    /// The ball enlarged by `rho >= 0`.
    #[inline(always)]
    pub(super) fn widen(self, rho: f64) -> Ball {
        Ball {
            c: self.c,
            r: add_up(self.r, rho),
        }
    }

    #[inline(always)]
    pub(super) fn neg(self) -> Ball {
        Ball {
            c: -self.c,
            r: self.r,
        }
    }
}

/// `x = +0` stays 0, a positive `x` moves one double up: for `x = fl(y)` with `y >= 0` an
/// upper bound of `y` (12.1.2(a)) when `x = 0` only for `y = 0` (as for sums of non-negative
/// doubles); `+inf` and NaN give NaN. Branch-free, on the bits.
#[inline(always)]
fn up0(x: f64) -> f64 {
    let b = x.to_bits();
    f64::from_bits(b + u64::from(b != 0))
}

/// `u (1 + 2^-50)`: at least `u (1 + u)^3`, the factor of the rounding bound of a radius
/// ([spec (12.1.21)](crate::spec::precision)).
const U_RAD: f64 = U * (1.0 + 1.0 / 1125899906842624.0);

/// `1 + 2^-40`: at least `(1 + u)^k` for `k <= 2^12`, the factor that bounds the rounding of
/// a sum of at most `2^12` non-negative terms each rounded at most `2^12` times
/// ([spec (12.1.21)](crate::spec::precision)).
const GROW: f64 = 1.0 + 1.0 / 1099511627776.0;

/// The longest sum [`dot_fused`] takes (longer ones take the chain of interval operations).
const DOT_MAX: u32 = 1024;

/// A centre `c1 + c2` (two doubles, not necessarily normalised), `m = |fl(c1 + c2)|` and a
/// radius `r`: every real of `x` lies within `r` of `c1 + c2`, and `|c1 + c2| <= (1 + u) m`
/// ([spec (12.1.21)](crate::spec::precision)). A point has radius 0; an empty or unbounded
/// interval has a NaN radius.
#[inline(always)]
fn centre_radius(x: DdInterval) -> (f64, f64, f64, f64) {
    let (lo, hi) = (x.lo, x.hi);
    // The width hi - lo = dh + dl up to the roundings of dh, dl and sw.
    let dh = hi.hi - lo.hi;
    let dl = hi.lo - lo.lo;
    let sw = dh + dl;
    let h = 0.5 * sw;
    let c1 = lo.hi;
    let c2 = lo.lo + h;
    // sw - h is exact; it is h unless the halving rounded (subnormal).
    let hm = h.abs().max((sw - h).abs());
    let s = ((dh.abs() + dl.abs()) + sw.abs()) + c2.abs();
    // s = 0: dh, dl, sw and c2 are exact (they are 0), so hm is the radius.
    let r = if s == 0.0 {
        hm
    } else {
        up(s.mul_add(U_RAD, hm))
    };
    let r = if lo.hi.is_finite() && hi.hi.is_finite() {
        r
    } else {
        f64::NAN
    };
    (c1, c2, (c1 + c2).abs(), r)
}

/// The running sums of [`dot_fused`]: the centre `s + l` of the sum so far, `g` (a sum of
/// magnitudes that bounds the rounding errors of the centre), `r` (the sum of the radii of the
/// products).
struct DotSums {
    s: f64,
    l: f64,
    g: f64,
    r: f64,
}

impl DotSums {
    /// Adds `x y` ([spec (12.1.21)](crate::spec::precision)).
    #[inline(always)]
    fn term(&mut self, x: DdInterval, y: DdInterval) {
        let (a1, a2, ma, ra) = centre_radius(x);
        let (b1, b2, mb, rb) = centre_radius(y);
        // The centres' product: DWTimesDW3 without its last renormalisation.
        let (p, e) = two_prod(a1, b1);
        let t0 = a2 * b2;
        let t1 = a1.mul_add(b2, t0);
        let k = a2.mul_add(b1, t1);
        let (s, t) = two_sum(self.s, p);
        let v1 = e + k;
        let v2 = t + v1;
        let l = self.l + v2;
        self.s = s;
        self.l = l;
        self.g += ((t0.abs() + t1.abs()) + (k.abs() + v1.abs())) + (v2.abs() + l.abs());
        self.r += ma.mul_add(rb, mb.mul_add(ra, ra * rb));
    }
}

/// The sum of `x_j y_j` over the pairs, computed as one sum of the centres' products in
/// double-double with a bound of its rounding errors, and one f64 radius
/// ([spec (12.1.21)](crate::spec::precision)); `None` when an input is empty or unbounded, an
/// intermediate is not finite, or there are more than [`DOT_MAX`] pairs.
#[inline(always)]
fn dot_fused(pairs: impl Iterator<Item = (DdInterval, DdInterval)>) -> Option<DdInterval> {
    let mut z = DotSums {
        s: 0.0,
        l: 0.0,
        g: 0.0,
        r: 0.0,
    };
    let mut n = 0u32;
    for (x, y) in pairs {
        if n == DOT_MAX {
            return None;
        }
        z.term(x, y);
        n += 1;
    }
    // |sum - (s + l)| <= up(up(g GROW) u) + up(r GROW) + 4 n eta; 4 n eta exactly from the
    // bits (a subnormal is its multiple of eta; no arithmetic on subnormals, which is slow).
    // g = 0: the six magnitudes of every term are 0, so are their rounding errors.
    let eg = if z.g == 0.0 {
        0.0
    } else {
        up(U * up(z.g * GROW))
    };
    let er = up0(z.r * GROW);
    let rad = up0(up0(eg + er) + f64::from_bits(4 * u64::from(n)));
    if !(z.s.is_finite() && z.l.is_finite() && rad.is_finite()) {
        return None;
    }
    Some(enclose(z.s, z.l, rad))
}

impl DdInterval {
    /// `acc + sum_j x_j y_j` (`acc - ...` when `neg`) over the pairs, the sum enclosed at once
    /// in midpoint-radius form ([spec (12.1.21)](crate::spec::precision)) and added to `acc`.
    /// An empty or unbounded input, an overflow, or more than 1024 pairs take the chain of
    /// interval operations `acc + x_0 y_0 + ...` instead, each rounded outward (12.1.4).
    #[inline]
    pub fn dot_acc<I>(acc: DdInterval, neg: bool, pairs: I) -> DdInterval
    where
        I: Iterator<Item = (DdInterval, DdInterval)> + Clone,
    {
        match dot_fused(pairs.clone()) {
            Some(s) => {
                if neg {
                    acc - s
                } else {
                    acc + s
                }
            }
            None => dot_chain(acc, neg, pairs),
        }
    }
}

/// The chain `acc +- x_0 y_0 +- x_1 y_1 ...` of outward-rounded operations (12.1.4).
#[inline(never)]
fn dot_chain(
    acc: DdInterval,
    neg: bool,
    pairs: impl Iterator<Item = (DdInterval, DdInterval)>,
) -> DdInterval {
    pairs.fold(
        acc,
        |s, (x, y)| if neg { s - x * y } else { x.mul_add(y, s) },
    )
}

/// `2^-969`: a product of two doubles at least this large has an exact FMA error term (its
/// error is a multiple of `2^-1073`).
const EXACT_PRODUCT: f64 = f64::from_bits(54 << 52);

/// `[a, b] / [c, d]` in f64 with outward rounding (`c, d` of one strict sign, all finite).
#[inline]
fn div_f64_iv(a: f64, b: f64, c: f64, d: f64) -> (f64, f64) {
    let q = [a / c, a / d, b / c, b / d];
    let lo = q.iter().copied().fold(f64::INFINITY, f64::min).next_down();
    let hi = q
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max)
        .next_up();
    (lo, hi)
}

/// The enclosure of `x / y` for finite `x` and finite non-zero `y` through the exact residual
/// `x / y = q + (x - q y) / y` ([spec (12.1.7)](crate::spec::precision)).
#[inline]
fn div_pt(x: Dd, y: Dd) -> DdInterval {
    if x.is_zero() {
        return DdInterval::ZERO;
    }
    if x.hi.abs() < SMALL || y.hi.abs() < SMALL {
        // Scale tiny operands up (exact) so that the residual stays far above the subnormal
        // range: x / y = (x 2^kx) / (y 2^ky) 2^(ky - kx).
        let kx = if x.hi.abs() < SMALL {
            -exponent(x.hi)
        } else {
            0
        };
        let ky = if y.hi.abs() < SMALL {
            -exponent(y.hi)
        } else {
            0
        };
        return div_pt_normal(x.scale_pow2_up(kx), y.scale_pow2_up(ky)).scale_pow2(ky - kx);
    }
    div_pt_normal(x, y)
}

/// Below this magnitude an operand of a division or square root is first scaled up: `2^-900`.
const SMALL: f64 = f64::from_bits(123 << 52);

/// The exponent `k` of a finite non-zero double: `2^k <= |x| < 2^(k+1)`.
#[inline]
fn exponent(x: f64) -> i32 {
    let b = x.to_bits() & 0x7fff_ffff_ffff_ffff;
    let e = (b >> 52) as i32;
    if e == 0 {
        63 - b.leading_zeros() as i32 - 1074
    } else {
        e - 1023
    }
}

#[inline]
fn div_pt_normal(x: Dd, y: Dd) -> DdInterval {
    let q = x / y;
    if !q.hi.is_finite() {
        return overflow(q.hi);
    }
    if x.lo == 0.0 && y.lo == 0.0 && q.lo == 0.0 && two_prod(q.hi, y.hi) == (x.hi, 0.0) {
        // q y == x exactly (|x| >= 2^-900 here, so the FMA error term is exact).
        return DdInterval { lo: q, hi: q };
    }
    let r = add_pt_iv(x, mul_pt(q, y));
    let (rl, rh) = (r.lo.to_f64_down(), r.hi.to_f64_up());
    if !(rl.is_finite() && rh.is_finite()) {
        return DdInterval::ENTIRE;
    }
    let (dl, dh) = div_f64_iv(rl, rh, y.to_f64_down(), y.to_f64_up());
    DdInterval::point(q)
        + DdInterval {
            lo: Dd::from_f64(dl),
            hi: Dd::from_f64(dh),
        }
}

/// `x - p` for a point `x` and an interval `p` with finite ends.
#[inline(always)]
fn add_pt_iv(x: Dd, p: DdInterval) -> DdInterval {
    if p.lo == p.hi {
        return add_pt(x, -p.lo);
    }
    DdInterval {
        lo: add_pt(x, -p.hi).lo,
        hi: add_pt(x, -p.lo).hi,
    }
}

/// The enclosure of `sqrt(x)` for finite `x > 0` via the residual: `sqrt(x) = q + r / (sqrt(x) + q)`
/// with `r = x - q^2` ([spec (12.1.8)](crate::spec::precision)).
fn sqrt_pt(x: Dd) -> DdInterval {
    if x.hi < SMALL {
        // sqrt(x) = sqrt(x 2^2k) 2^-k, the scaling up exact.
        let k = -exponent(x.hi) / 2;
        return sqrt_pt_normal(x.scale_pow2_up(2 * k)).scale_pow2(-k);
    }
    sqrt_pt_normal(x)
}

fn sqrt_pt_normal(x: Dd) -> DdInterval {
    let q = x.sqrt();
    if x.lo == 0.0 && q.lo == 0.0 && two_prod(q.hi, q.hi) == (x.hi, 0.0) {
        // q^2 == x exactly (x >= 2^-900, so the FMA error term is exact).
        return DdInterval { lo: q, hi: q };
    }
    let r = add_pt_iv(x, mul_pt(q, q));
    let (rl, rh) = (r.lo.to_f64_down(), r.hi.to_f64_up());
    let qd = q.to_f64_down();
    let qu = q.to_f64_up();
    let m = up(up(rl.abs().max(rh.abs())) / qd);
    let dl = (2.0 * qd - m).next_down();
    let dh = (2.0 * qu + m).next_up();
    if !(rl.is_finite() && rh.is_finite() && dl > 0.0 && dh.is_finite()) {
        // Not reached for finite positive x (the residual is tiny); the bound stays sound.
        return DdInterval {
            lo: Dd::ZERO,
            hi: Dd::from_f64(up(x.to_f64_up().sqrt())),
        }
        .hull(DdInterval::point(q));
    }
    let (dl, dh) = div_f64_iv(rl, rh, dl, dh);
    DdInterval::point(q)
        + DdInterval {
            lo: Dd::from_f64(dl),
            hi: Dd::from_f64(dh),
        }
}

impl DdInterval {
    /// The empty set.
    pub const EMPTY: DdInterval = DdInterval {
        lo: Dd::INFINITY,
        hi: Dd::NEG_INFINITY,
    };
    /// The whole real line.
    pub const ENTIRE: DdInterval = DdInterval {
        lo: Dd::NEG_INFINITY,
        hi: Dd::INFINITY,
    };
    /// `[0, 0]`.
    pub const ZERO: DdInterval = DdInterval {
        lo: Dd::ZERO,
        hi: Dd::ZERO,
    };
    /// `[1, 1]`.
    pub const ONE: DdInterval = DdInterval {
        lo: Dd::ONE,
        hi: Dd::ONE,
    };

    /// The degenerate interval `[x, x]` of an exact double; empty for NaN, the whole line for
    /// an infinity (an infinity is not a real number).
    #[inline]
    pub fn from_f64(x: f64) -> DdInterval {
        if x.is_finite() {
            let d = Dd::from_f64(x);
            DdInterval { lo: d, hi: d }
        } else if x.is_nan() {
            DdInterval::EMPTY
        } else {
            DdInterval::ENTIRE
        }
    }

    /// The degenerate interval `[p, p]` (empty for NaN, the whole line for an infinity).
    #[inline]
    pub fn point(p: Dd) -> DdInterval {
        if p.hi.is_finite() {
            DdInterval { lo: p, hi: p }
        } else if p.hi.is_nan() {
            DdInterval::EMPTY
        } else {
            DdInterval::ENTIRE
        }
    }

    /// `[lo, hi]` when `lo <= hi`, `lo < +inf` and `hi > -inf` (no NaN); `None` otherwise.
    pub fn new(lo: Dd, hi: Dd) -> Option<DdInterval> {
        let lo = Dd::new(lo.hi, lo.lo);
        let hi = Dd::new(hi.hi, hi.lo);
        if lo <= hi && lo.hi < f64::INFINITY && hi.hi > f64::NEG_INFINITY {
            Some(DdInterval { lo, hi })
        } else {
            None
        }
    }

    /// `[lo, hi]` of two doubles, as [`DdInterval::new`].
    pub fn from_f64_pair(lo: f64, hi: f64) -> Option<DdInterval> {
        DdInterval::new(Dd::from_f64(lo), Dd::from_f64(hi))
    }

    /// The empty set.
    pub fn empty() -> DdInterval {
        DdInterval::EMPTY
    }

    /// The whole real line.
    pub fn entire() -> DdInterval {
        DdInterval::ENTIRE
    }

    /// The lower end, exact (`+inf` when empty).
    #[inline]
    pub fn inf(self) -> Dd {
        self.lo
    }

    /// The upper end, exact (`-inf` when empty).
    #[inline]
    pub fn sup(self) -> Dd {
        self.hi
    }

    /// The lower end rounded down to a double.
    #[inline]
    pub fn inf_f64(self) -> f64 {
        self.lo.to_f64_down()
    }

    /// The upper end rounded up to a double.
    #[inline]
    pub fn sup_f64(self) -> f64 {
        self.hi.to_f64_up()
    }

    /// A point of the interval near its midpoint: 0 for the whole line, the finite end of a
    /// half-bounded interval, NaN for the empty interval.
    pub fn mid(self) -> Dd {
        if self.is_empty() {
            return Dd {
                hi: f64::NAN,
                lo: 0.0,
            };
        }
        match (self.lo.is_finite(), self.hi.is_finite()) {
            (false, false) => Dd::ZERO,
            (false, true) => self.hi,
            (true, false) => self.lo,
            (true, true) => {
                let m = self.lo.scale_pow2(-1) + self.hi.scale_pow2(-1);
                if m < self.lo {
                    self.lo
                } else if m > self.hi {
                    self.hi
                } else {
                    m
                }
            }
        }
    }

    /// An upper bound of the width (NaN for the empty interval, as inari).
    pub fn wid_up(self) -> f64 {
        if self.is_empty() {
            return f64::NAN;
        }
        if !self.is_finite() {
            return f64::INFINITY;
        }
        add_pt(self.hi, -self.lo).hi.to_f64_up()
    }

    /// An upper bound of `max |x|` (NaN when empty).
    pub fn mag_up(self) -> f64 {
        if self.is_empty() {
            return f64::NAN;
        }
        self.lo.abs().to_f64_up().max(self.hi.abs().to_f64_up())
    }

    /// A lower bound of `min |x|` (NaN when empty).
    pub fn mig_down(self) -> f64 {
        if self.is_empty() {
            return f64::NAN;
        }
        if self.lo.hi >= 0.0 {
            self.lo.to_f64_down()
        } else if self.hi.hi <= 0.0 {
            (-self.hi).to_f64_down()
        } else {
            0.0
        }
    }

    /// The empty set.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.lo.hi == f64::INFINITY
    }

    /// Non-empty with both ends finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.lo.hi.is_finite() && self.hi.hi.is_finite()
    }

    /// A point (both ends equal).
    #[inline]
    pub fn is_point(self) -> bool {
        self.lo == self.hi
    }

    /// Exactly `[0, 0]`.
    pub fn is_exact_zero(self) -> bool {
        self.lo.hi == 0.0 && self.hi.hi == 0.0
    }

    /// `p` lies in the interval (exact comparison).
    pub fn contains(self, p: Dd) -> bool {
        self.lo <= p && p <= self.hi
    }

    /// The double `x` lies in the interval.
    pub fn contains_f64(self, x: f64) -> bool {
        self.contains(Dd::from_f64(x))
    }

    /// `self ⊆ o` (the empty set is a subset of every interval).
    pub fn subset(self, o: DdInterval) -> bool {
        self.is_empty() || (o.lo <= self.lo && self.hi <= o.hi)
    }

    /// `self` lies in the interior of `o` (an infinite end of `o` counts as strictly outside).
    pub fn interior(self, o: DdInterval) -> bool {
        self.is_empty()
            || ((o.lo < self.lo || o.lo.hi == f64::NEG_INFINITY)
                && (self.hi < o.hi || o.hi.hi == f64::INFINITY))
    }

    /// No common point.
    pub fn disjoint(self, o: DdInterval) -> bool {
        self.is_empty() || o.is_empty() || self.hi < o.lo || o.hi < self.lo
    }

    /// The smallest interval containing both.
    pub fn hull(self, o: DdInterval) -> DdInterval {
        if self.is_empty() {
            return o;
        }
        if o.is_empty() {
            return self;
        }
        DdInterval {
            lo: dmin(self.lo, o.lo),
            hi: dmax(self.hi, o.hi),
        }
    }

    /// The common part (exact).
    pub fn intersection(self, o: DdInterval) -> DdInterval {
        let lo = dmax(self.lo, o.lo);
        let hi = dmin(self.hi, o.hi);
        if self.is_empty() || o.is_empty() || lo > hi {
            DdInterval::EMPTY
        } else {
            DdInterval { lo, hi }
        }
    }

    /// `{|x|}` (exact).
    pub fn abs(self) -> DdInterval {
        if self.is_empty() || self.lo.hi >= 0.0 {
            self
        } else if self.hi.hi <= 0.0 {
            -self
        } else {
            DdInterval {
                lo: Dd::ZERO,
                hi: dmax(-self.lo, self.hi),
            }
        }
    }

    /// `x^2` (tighter than `x * x` when `x` contains 0).
    pub fn sqr(self) -> DdInterval {
        let a = self.abs();
        if a.is_empty() {
            return a;
        }
        let lo = mul_end(a.lo, a.lo).lo;
        let hi = mul_end(a.hi, a.hi).hi;
        DdInterval { lo, hi }
    }

    /// `x^n` for every integer `n` (`x^0 = [1, 1]` for non-empty `x`; negative powers through
    /// [`DdInterval::recip`]).
    pub fn powi(self, n: i32) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        if n < 0 {
            return self.powu(n.unsigned_abs()).recip();
        }
        self.powu(n as u32)
    }

    fn powu(self, n: u32) -> DdInterval {
        if n == 0 {
            return DdInterval::ONE;
        }
        if n.is_multiple_of(2) {
            return pow_nonneg(self.abs(), n);
        }
        let end = |p: Dd| -> DdInterval {
            if !p.is_finite() {
                DdInterval { lo: p, hi: p }
            } else if p.hi >= 0.0 {
                pow_nonneg(DdInterval::point(p), n)
            } else {
                -pow_nonneg(DdInterval::point(-p), n)
            }
        };
        DdInterval {
            lo: end(self.lo).lo,
            hi: end(self.hi).hi,
        }
    }

    /// `1 / x` (the whole line when `x` contains 0 and is not `[0, 0]`; empty for `[0, 0]`).
    pub fn recip(self) -> DdInterval {
        DdInterval::ONE / self
    }

    /// `self * a + b` (two outward-rounded operations).
    pub fn mul_add(self, a: DdInterval, b: DdInterval) -> DdInterval {
        self * a + b
    }

    /// Square root over the non-negative part (`sqrt([-1, 4]) = [0, 2]`; empty when `x < 0`).
    pub fn sqrt(self) -> DdInterval {
        if self.is_empty() || self.hi.hi < 0.0 {
            return DdInterval::EMPTY;
        }
        let lo = if self.lo.hi <= 0.0 {
            Dd::ZERO
        } else {
            sqrt_pt(self.lo).lo
        };
        let hi = if self.hi.is_zero() {
            Dd::ZERO
        } else if !self.hi.is_finite() {
            Dd::INFINITY
        } else {
            sqrt_pt(self.hi).hi
        };
        DdInterval { lo, hi }
    }

    /// `2^k * self`, outward rounded (exact unless it leaves the normal range).
    pub fn scale_pow2(self, k: i32) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let down = |x: f64| mul2(x, k, true);
        let upf = |x: f64| mul2(x, k, false);
        let lo = if self.lo.is_finite() {
            end_down(down(self.lo.hi), down(self.lo.lo))
        } else {
            self.lo
        };
        let hi = if self.hi.is_finite() {
            end_up(upf(self.hi.hi), upf(self.hi.lo))
        } else {
            self.hi
        };
        DdInterval { lo, hi }
    }
}

/// `x * 2^k` rounded down (`down`) or up: exact when the product is normal or
/// zero from zero; otherwise one outward step, since the product is rounded to nearest
/// ([spec (12.1.2)](crate::spec::precision)).
#[inline]
fn mul2(x: f64, k: i32, down: bool) -> f64 {
    let mut y = x;
    let mut k = k;
    while k != 0 && y != 0.0 && y.is_finite() {
        // Each step is a directed bound and multiplying by 2^step > 0 is monotone.
        let step = k.clamp(-1000, 1000);
        y = mul2_step(y, step, down);
        k -= step;
    }
    y
}

/// One step of [`mul2`], `|k| <= 1000`.
#[inline]
fn mul2_step(x: f64, k: i32, down: bool) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let y = x * pow2(k);
    if y.is_finite() && y.abs() >= f64::MIN_POSITIVE {
        y
    } else if y.is_finite() {
        if down {
            y.next_down()
        } else {
            y.next_up()
        }
    } else if down {
        if y > 0.0 {
            f64::MAX
        } else {
            f64::NEG_INFINITY
        }
    } else if y > 0.0 {
        f64::INFINITY
    } else {
        -f64::MAX
    }
}

/// `x^n` for `x >= 0` (binary powering; every product is outward rounded and the factors are
/// non-negative, so the result encloses the range).
fn pow_nonneg(x: DdInterval, mut n: u32) -> DdInterval {
    let mut base = x;
    let mut acc = DdInterval::ONE;
    while n > 0 {
        if n & 1 == 1 {
            acc = acc * base;
        }
        n >>= 1;
        if n > 0 {
            base = base.sqr();
        }
    }
    acc
}

#[inline(always)]
fn dmin(a: Dd, b: Dd) -> Dd {
    if b < a {
        b
    } else {
        a
    }
}

#[inline(always)]
fn dmax(a: Dd, b: Dd) -> Dd {
    if b > a {
        b
    } else {
        a
    }
}

impl Neg for DdInterval {
    type Output = DdInterval;
    #[inline]
    fn neg(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        DdInterval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Add for DdInterval {
    type Output = DdInterval;
    /// [spec (12.1.5)](crate::spec::precision).
    #[inline]
    fn add(self, o: DdInterval) -> DdInterval {
        if self.is_empty() || o.is_empty() {
            return DdInterval::EMPTY;
        }
        if self.is_point() && o.is_point() && self.lo.is_finite() && o.lo.is_finite() {
            return add_pt(self.lo, o.lo);
        }
        let lo = if self.lo.hi == f64::NEG_INFINITY || o.lo.hi == f64::NEG_INFINITY {
            Dd::NEG_INFINITY
        } else {
            add_pt(self.lo, o.lo).lo
        };
        let hi = if self.hi.hi == f64::INFINITY || o.hi.hi == f64::INFINITY {
            Dd::INFINITY
        } else {
            add_pt(self.hi, o.hi).hi
        };
        DdInterval { lo, hi }
    }
}

impl Sub for DdInterval {
    type Output = DdInterval;
    #[inline]
    fn sub(self, o: DdInterval) -> DdInterval {
        self + (-o)
    }
}

/// The enclosure of the product of two ends (the infinite ones as limits, `0 * inf = 0`).
#[inline(always)]
fn mul_end(x: Dd, y: Dd) -> DdInterval {
    if x.is_zero() || y.is_zero() {
        return DdInterval::ZERO;
    }
    if x.is_finite() && y.is_finite() {
        return mul_pt(x, y);
    }
    let s = if (x.hi > 0.0) == (y.hi > 0.0) {
        Dd::INFINITY
    } else {
        Dd::NEG_INFINITY
    };
    DdInterval { lo: s, hi: s }
}

impl Mul for DdInterval {
    type Output = DdInterval;
    /// [spec (12.1.6)](crate::spec::precision).
    #[inline]
    fn mul(self, o: DdInterval) -> DdInterval {
        if self.is_empty() || o.is_empty() {
            return DdInterval::EMPTY;
        }
        let (a, b, c, d) = (self.lo, self.hi, o.lo, o.hi);
        if self.is_point() && o.is_point() {
            return mul_end(a, c);
        }
        if a.hi >= 0.0 && c.hi >= 0.0 {
            DdInterval {
                lo: mul_end(a, c).lo,
                hi: mul_end(b, d).hi,
            }
        } else if b.hi <= 0.0 && d.hi <= 0.0 {
            DdInterval {
                lo: mul_end(b, d).lo,
                hi: mul_end(a, c).hi,
            }
        } else if a.hi >= 0.0 && d.hi <= 0.0 {
            DdInterval {
                lo: mul_end(b, c).lo,
                hi: mul_end(a, d).hi,
            }
        } else if b.hi <= 0.0 && c.hi >= 0.0 {
            DdInterval {
                lo: mul_end(a, d).lo,
                hi: mul_end(b, c).hi,
            }
        } else {
            let p = [mul_end(a, c), mul_end(a, d), mul_end(b, c), mul_end(b, d)];
            let lo = p.iter().map(|i| i.lo).fold(Dd::INFINITY, dmin);
            let hi = p.iter().map(|i| i.hi).fold(Dd::NEG_INFINITY, dmax);
            DdInterval { lo, hi }
        }
    }
}

/// The enclosure of the quotient of two ends (`y` non-zero; the infinite ones as limits).
#[inline(always)]
fn div_end(x: Dd, y: Dd) -> DdInterval {
    if x.is_finite() && y.is_finite() {
        return div_pt(x, y);
    }
    if !y.is_finite() {
        // x finite here (an infinite x only meets a finite y in the cases of `div`).
        return DdInterval::ZERO;
    }
    let s = if (x.hi > 0.0) == (y.hi > 0.0) {
        Dd::INFINITY
    } else {
        Dd::NEG_INFINITY
    };
    DdInterval { lo: s, hi: s }
}

impl Div for DdInterval {
    type Output = DdInterval;
    /// [spec (12.1.7)](crate::spec::precision). A divisor with 0 as an end gives a half-line
    /// when the dividend does not contain 0 (`[1, 2] / [0, 4] = [1/4, +inf]`), the whole line
    /// otherwise or when 0 is inside the divisor; the divisor `[0, 0]` gives the empty set.
    #[inline]
    fn div(self, o: DdInterval) -> DdInterval {
        if self.is_empty() || o.is_empty() || o.is_exact_zero() {
            return DdInterval::EMPTY;
        }
        let (a, b, c, d) = (self.lo, self.hi, o.lo, o.hi);
        if c.hi > 0.0 {
            if self.is_point() && o.is_point() {
                return div_end(a, c);
            }
            let lo = div_end(a, if a.hi >= 0.0 { d } else { c }).lo;
            let hi = div_end(b, if b.hi >= 0.0 { c } else { d }).hi;
            DdInterval { lo, hi }
        } else if d.hi < 0.0 {
            if self.is_point() && o.is_point() {
                return div_end(a, c);
            }
            let lo = div_end(b, if b.hi >= 0.0 { d } else { c }).lo;
            let hi = div_end(a, if a.hi >= 0.0 { c } else { d }).hi;
            DdInterval { lo, hi }
        } else if a.hi > 0.0 || b.hi < 0.0 {
            // The divisor has 0 as an end (a half-line) or inside (the whole line), the
            // dividend does not contain 0: as IEEE 1788 and inari.
            let (pos, neg) = (a.hi > 0.0, b.hi < 0.0);
            if d.hi == 0.0 && c.hi < 0.0 {
                // y in [c, 0): x / y runs to +inf (x < 0) or -inf (x > 0) as y -> 0.
                if neg {
                    DdInterval {
                        lo: div_end(b, c).lo,
                        hi: Dd::INFINITY,
                    }
                } else {
                    DdInterval {
                        lo: Dd::NEG_INFINITY,
                        hi: div_end(a, c).hi,
                    }
                }
            } else if c.hi == 0.0 && d.hi > 0.0 {
                if pos {
                    DdInterval {
                        lo: div_end(a, d).lo,
                        hi: Dd::INFINITY,
                    }
                } else {
                    DdInterval {
                        lo: Dd::NEG_INFINITY,
                        hi: div_end(b, d).hi,
                    }
                }
            } else {
                DdInterval::ENTIRE
            }
        } else {
            DdInterval::ENTIRE
        }
    }
}

impl From<f64> for DdInterval {
    fn from(x: f64) -> DdInterval {
        DdInterval::from_f64(x)
    }
}

// ---------------------------------------------------------------------------------------------
// Exact decimal conversions ([spec (12.1.9)](crate::spec::precision)).

/// A finite non-zero double as `(negative, m, e)` with `|x| = m * 2^e` exactly.
fn decompose(x: f64) -> (bool, u64, i64) {
    let bits = x.to_bits();
    let neg = bits >> 63 == 1;
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = bits & ((1u64 << 52) - 1);
    if exp == 0 {
        (neg, frac, -1074)
    } else {
        (neg, frac | (1u64 << 52), exp - 1075)
    }
}

/// A finite double-double as `(negative, Q, e)` with `value = ±Q * 2^e` exactly (`Q = 0` for 0).
pub(super) fn dd_to_big(x: Dd) -> (bool, Big, i64) {
    if x.hi == 0.0 {
        return (false, Big::zero(), 0);
    }
    let (nh, mh, eh) = decompose(x.hi);
    if x.lo == 0.0 {
        return (nh, Big::from_u64(mh), eh);
    }
    let (nl, ml, el) = decompose(x.lo);
    let e = eh.min(el);
    let h = Big::from_u64(mh).shl((eh - e) as u64);
    let l = Big::from_u64(ml).shl((el - e) as u64);
    // |lo| < |hi|, so the magnitude is |hi| ± |lo| with the sign of hi.
    let q = if nh == nl { h.add(&l) } else { h.sub(&l) };
    (nh, q, e)
}

/// The bounds of a real of sign `neg` whose magnitude lies in `[Q, Q + s] * 2^e` (`s` is 0
/// or 1), rounded outward to at most 106 significant bits ([spec (12.1.9)](crate::spec::precision)).
pub(super) fn big_to_interval(neg: bool, q: &Big, e: i64, s: bool) -> DdInterval {
    let (mlo, mhi) = big_mag_bounds(q, e, s);
    if neg {
        DdInterval { lo: -mhi, hi: -mlo }
    } else {
        DdInterval { lo: mlo, hi: mhi }
    }
}

/// Lower and upper double-double bounds of a magnitude in `[Q, Q + s] * 2^e`.
fn big_mag_bounds(q: &Big, e: i64, s: bool) -> (Dd, Dd) {
    if q.is_zero() {
        if !s {
            return (Dd::ZERO, Dd::ZERO);
        }
        let up = if e < -1074 {
            Dd::from_f64(pow2(-1074))
        } else if e > 1023 {
            Dd::INFINITY
        } else {
            Dd::from_f64(pow2(e as i32))
        };
        return (Dd::ZERO, up);
    }
    let t = q.bit_len() as i64 - 1 + e; // 2^t <= Q 2^e < 2^(t+1)
    if t >= 1024 {
        return (Dd::MAX, Dd::INFINITY);
    }
    if t < -1075 {
        return (Dd::ZERO, Dd::from_f64(pow2(-1074)));
    }
    let g = (t - 105).max(-1074);
    let (n, inexact) = if g >= e {
        let sh = (g - e) as u64;
        (q.shr(sh), q.any_low_bits(sh) || s)
    } else {
        // Q < 2^106 here: no shift, exact.
        let sh = (e - g) as u64;
        (q.shl(sh), s)
    };
    let n_lo = n.clone();
    let lower = small_big_to_dd(&n_lo, g as i32);
    let upper = if inexact {
        let mut n1 = n;
        n1.mul_small_add(1, 1);
        small_big_to_dd(&n1, g as i32)
    } else {
        lower
    };
    (lower, upper)
}

/// `N * 2^g` exactly, for `N <= 2^106` and `-1074 <= g`, `N 2^g <= 2^1024` (then `+inf`).
fn small_big_to_dd(n: &Big, g: i32) -> Dd {
    let hi_part = n.shr(53);
    let lo_part = n.low_bits(53);
    let h = hi_part.low_u64() as f64; // < 2^53 + 1 and a power of two when equal: exact
    let l = lo_part.low_u64() as f64;
    let hp = h * pow2_wide(g + 53);
    let lp = l * pow2(g);
    if !hp.is_finite() {
        return Dd::INFINITY;
    }
    Dd::new(hp, lp)
}

/// `2^k` for `-1074 <= k <= 1100` (infinite above 1023).
fn pow2_wide(k: i32) -> f64 {
    if k > 1023 {
        f64::INFINITY
    } else {
        pow2(k)
    }
}

/// The significant digits of a decimal read exactly; the rest only bound the value.
const MAX_DECIMAL_DIGITS: usize = 800;

/// `10^k` splits as `5^k 2^k`: the exact value of a decimal `±D * 10^k`, bounded outward.
fn decimal_to_interval(neg: bool, d: &Big, k: i64) -> DdInterval {
    if d.is_zero() {
        return DdInterval::ZERO;
    }
    let digits = d.to_decimal().len() as i64;
    // Far outside the double range: avoid huge exact powers.
    if digits + k > 400 {
        let m = DdInterval {
            lo: Dd::MAX,
            hi: Dd::INFINITY,
        };
        return if neg { -m } else { m };
    }
    if digits + k < -400 {
        let m = DdInterval {
            lo: Dd::ZERO,
            hi: Dd::from_f64(pow2(-1074)),
        };
        return if neg { -m } else { m };
    }
    if k >= 0 {
        let mut q = d.clone();
        for _ in 0..k {
            q.mul_small_add(10, 0);
        }
        return big_to_interval(neg, &q, 0, false);
    }
    let m = (-k) as u64;
    let p5 = Big::pow5(m);
    let shift = (p5.bit_len() as i64 - d.bit_len() as i64 + 110).max(0) as u64;
    let (q, inexact) = d.shl(shift).div_floor(&p5);
    big_to_interval(neg, &q, -(shift as i64) - m as i64, inexact)
}

impl DdInterval {
    /// The tightest or a near-tightest interval containing the exact value of a decimal string
    /// `[+-]digits[.digits][(e|E)[+-]digits]` (at most one ulp of 106 bits on each side);
    /// `None` if the string is not such a decimal. ([spec (12.1.9)](crate::spec::precision))
    pub fn from_decimal(s: &str) -> Option<DdInterval> {
        let s = s.trim();
        let (neg, rest) = match s.as_bytes().first()? {
            b'-' => (true, &s[1..]),
            b'+' => (false, &s[1..]),
            _ => (false, s),
        };
        let (mant, exp) = match rest.find(['e', 'E']) {
            Some(i) => (&rest[..i], Some(&rest[i + 1..])),
            None => (rest, None),
        };
        let (ip, fp) = match mant.find('.') {
            Some(i) => (&mant[..i], &mant[i + 1..]),
            None => (mant, ""),
        };
        if ip.is_empty() && fp.is_empty() {
            return None;
        }
        if !ip.bytes().chain(fp.bytes()).all(|c| c.is_ascii_digit()) {
            return None;
        }
        let mut k: i64 = match exp {
            None => 0,
            Some(e) => {
                let (en, ed) = match e.as_bytes().first()? {
                    b'-' => (true, &e[1..]),
                    b'+' => (false, &e[1..]),
                    _ => (false, e),
                };
                if ed.is_empty() || !ed.bytes().all(|c| c.is_ascii_digit()) {
                    return None;
                }
                // Saturate: beyond ±10^9 every non-zero value over- or underflows anyway.
                let v = ed
                    .bytes()
                    .fold(0i64, |a, c| (a * 10 + (c - b'0') as i64).min(1_000_000_000));
                if en {
                    -v
                } else {
                    v
                }
            }
        };
        k = k.saturating_sub(fp.len() as i64);
        let digits: Vec<u8> = ip
            .bytes()
            .chain(fp.bytes())
            .skip_while(|&c| c == b'0')
            .collect();
        // Beyond 800 significant digits (every double-double has fewer) the value lies in
        // [D, D + 1] 10^k' with D the
        // first 800 digits: bounded by the two ends, so that a long input stays cheap.
        let (kept, dropped) = digits.split_at(digits.len().min(MAX_DECIMAL_DIGITS));
        let mut d = Big::zero();
        for &c in kept {
            d.mul_small_add(10, (c - b'0') as u32);
        }
        let k = k.saturating_add(dropped.len() as i64);
        if dropped.iter().all(|&c| c == b'0') {
            return Some(decimal_to_interval(neg, &d, k));
        }
        let mut d1 = d.clone();
        d1.mul_small_add(1, 1);
        Some(decimal_to_interval(neg, &d, k).hull(decimal_to_interval(neg, &d1, k)))
    }

    /// The lower end as a decimal with `digits` significant digits, rounded down.
    pub fn inf_decimal(self, digits: usize) -> String {
        dd_to_decimal(self.lo, digits, false)
    }

    /// The upper end as a decimal with `digits` significant digits, rounded up.
    pub fn sup_decimal(self, digits: usize) -> String {
        dd_to_decimal(self.hi, digits, true)
    }
}

/// `x` as `d.ddd…e±X` with `digits` (at least 1) significant digits, rounded up (`up`) or down;
/// exact arithmetic on the dyadic value ([spec (12.1.9)](crate::spec::precision)).
pub fn dd_to_decimal(x: Dd, digits: usize, up_dir: bool) -> String {
    let digits = digits.max(1);
    if x.hi.is_nan() {
        return "NaN".to_string();
    }
    if x.hi == f64::INFINITY {
        return "inf".to_string();
    }
    if x.hi == f64::NEG_INFINITY {
        return "-inf".to_string();
    }
    let (neg, q, e) = dd_to_big(x);
    if q.is_zero() {
        return "0".to_string();
    }
    // value = A * 10^de exactly.
    let (a, de) = if e >= 0 {
        (q.shl(e as u64), 0i64)
    } else {
        (q.mul(&Big::pow5((-e) as u64)), e)
    };
    let s = a.to_decimal();
    let n = s.len();
    let (mut kept, dropped_nonzero) = if n > digits {
        (
            s.as_bytes()[..digits].to_vec(),
            s[digits..].bytes().any(|c| c != b'0'),
        )
    } else {
        (s.as_bytes().to_vec(), false)
    };
    // Decimal exponent of the first kept digit.
    let mut exp10 = n as i64 - 1 + de;
    // Magnitude rounded up when the direction points away from zero.
    let away = up_dir != neg;
    if dropped_nonzero && away {
        let mut i = kept.len();
        loop {
            if i == 0 {
                kept.insert(0, b'1');
                kept.pop();
                exp10 += 1;
                break;
            }
            i -= 1;
            if kept[i] == b'9' {
                kept[i] = b'0';
            } else {
                kept[i] += 1;
                break;
            }
        }
    }
    while kept.len() > 1 && kept.last() == Some(&b'0') {
        kept.pop();
    }
    let mut out = String::new();
    if neg {
        out.push('-');
    }
    out.push(kept[0] as char);
    if kept.len() > 1 {
        out.push('.');
        out.push_str(core::str::from_utf8(&kept[1..]).unwrap_or("0"));
    }
    if exp10 != 0 {
        out.push_str(&format!("e{exp10}"));
    }
    out
}

/// The number of significant digits that carries 106 bits: `ceil(106 log10 2) + 2`.
pub const DISPLAY_DIGITS: usize = 34;

impl fmt::Display for DdInterval {
    /// `[lo, hi]`, each end rounded outward to 34 significant digits; `[empty]` when empty.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            return write!(f, "[empty]");
        }
        write!(
            f,
            "[{}, {}]",
            self.inf_decimal(DISPLAY_DIGITS),
            self.sup_decimal(DISPLAY_DIGITS)
        )
    }
}

impl fmt::Debug for DdInterval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl fmt::Display for Dd {
    /// The value rounded toward zero to 34 significant digits.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", dd_to_decimal(*self, DISPLAY_DIGITS, self.hi < 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(x: f64) -> DdInterval {
        DdInterval::from_f64(x)
    }

    fn no_nan(x: DdInterval) -> bool {
        !x.lo.hi.is_nan() && !x.lo.lo.is_nan() && !x.hi.hi.is_nan() && !x.hi.lo.is_nan()
    }

    #[test]
    fn closed_forms() {
        assert!((iv(3.0) * iv(7.0)).contains_f64(21.0));
        assert!((iv(1.0) / iv(3.0) * iv(3.0)).contains_f64(1.0));
        assert!(iv(2.0).sqrt().sqr().contains_f64(2.0));
        assert!(iv(4.0).sqrt().contains_f64(2.0));
        assert!((DdInterval::from_decimal("0.1").unwrap() * iv(10.0)).contains_f64(1.0));
        assert!(!DdInterval::from_decimal("0.1").unwrap().contains_f64(0.1)); // 0.1 is not a double
        let third = iv(1.0) / iv(3.0);
        assert!(third.wid_up() < 2.0 * 4.93e-32);
        // (1 + 2^-30)^2 = (1 + 2^-29) + 2^-60 exactly: contained, and far from 1 + 2^-29.
        let x = DdInterval::from_f64(1.0 + pow2(-30));
        let s = x.sqr();
        assert!(s.contains(Dd::new(1.0 + pow2(-29), pow2(-60))));
        assert!(s.is_point());
        assert!(!s.contains(Dd::new(1.0 + pow2(-29), 0.0)));
        let y = DdInterval::point(Dd::new(1.0, pow2(-60))).sqr(); // 1 + 2^-59 + 2^-120
        assert!(y.contains(Dd::new(1.0, pow2(-59))) && !y.contains(Dd::new(1.0, pow2(-60))));
        assert!(iv(-1.5).powi(5).contains_f64(-7.59375));
        assert!(iv(2.0).powi(-3).contains_f64(0.125));
        assert!(iv(-2.0)
            .powi(i32::MIN)
            .subset(DdInterval::from_f64_pair(0.0, pow2(-1000)).unwrap()));
    }

    #[test]
    fn interval_cases() {
        let a = DdInterval::from_f64_pair(-2.0, 3.0).unwrap();
        let b = DdInterval::from_f64_pair(-5.0, 4.0).unwrap();
        let p = a * b;
        assert!(p.contains_f64(-15.0) && p.contains_f64(12.0) && p.contains_f64(10.0));
        assert!(p.subset(DdInterval::from_f64_pair(-15.000001, 12.000001).unwrap()));
        assert!(a.sqr().inf() == Dd::ZERO && a.sqr().contains_f64(9.0));
        let q = DdInterval::from_f64_pair(1.0, 2.0).unwrap()
            / DdInterval::from_f64_pair(-4.0, -2.0).unwrap();
        assert!(q.contains_f64(-1.0) && q.contains_f64(-0.25));
        assert!((iv(1.0) / DdInterval::from_f64_pair(-1.0, 1.0).unwrap()) == DdInterval::ENTIRE);
        assert!((iv(1.0) / iv(0.0)).is_empty());
        let h = DdInterval::from_f64_pair(1.0, 2.0).unwrap()
            / DdInterval::from_f64_pair(0.0, 4.0).unwrap();
        assert!(h.inf() == Dd::from_f64(0.25) && h.sup() == Dd::INFINITY);
        let h = DdInterval::from_f64_pair(1.0, 2.0).unwrap()
            / DdInterval::from_f64_pair(-4.0, 0.0).unwrap();
        assert!(h.inf() == Dd::NEG_INFINITY && h.sup() == Dd::from_f64(-0.25));
        let h = DdInterval::from_f64_pair(-2.0, -1.0).unwrap()
            / DdInterval::from_f64_pair(-4.0, 0.0).unwrap();
        assert!(h.inf() == Dd::from_f64(0.25) && h.sup() == Dd::INFINITY);
        let h = DdInterval::from_f64_pair(-2.0, -1.0).unwrap()
            / DdInterval::from_f64_pair(0.0, 4.0).unwrap();
        assert!(h.inf() == Dd::NEG_INFINITY && h.sup() == Dd::from_f64(-0.25));
        let h = DdInterval::from_f64_pair(-2.0, 1.0).unwrap()
            / DdInterval::from_f64_pair(0.0, 4.0).unwrap();
        assert!(h == DdInterval::ENTIRE);
        assert_eq!(
            DdInterval::from_f64_pair(-1.0, 4.0).unwrap().sqrt().sup(),
            Dd::from_f64(2.0)
        );
        assert_eq!(
            DdInterval::from_f64_pair(-1.0, 4.0).unwrap().sqrt().inf(),
            Dd::ZERO
        );
        assert!(DdInterval::from_f64_pair(-2.0, -1.0)
            .unwrap()
            .sqrt()
            .is_empty());
        assert!(a.hull(b).contains_f64(-5.0) && a.intersection(b).contains_f64(3.0));
        assert!(iv(1.0).intersection(iv(2.0)).is_empty());
        assert!(iv(1.0).interior(a) && !a.interior(a) && iv(1.0).subset(a) && iv(7.0).disjoint(a));
        assert!(DdInterval::new(Dd::from_f64(2.0), Dd::from_f64(1.0)).is_none());
        assert!(DdInterval::new(Dd::INFINITY, Dd::INFINITY).is_none());
        assert_eq!(a.mag_up(), 3.0);
        assert_eq!(a.mig_down(), 0.0);
        assert_eq!(b.wid_up(), 9.0);
        assert!(a.contains(a.mid()) && DdInterval::ENTIRE.mid() == Dd::ZERO);
    }

    #[test]
    fn special_values_never_nan() {
        let specials = [
            DdInterval::EMPTY,
            DdInterval::ENTIRE,
            DdInterval::ZERO,
            DdInterval::from_f64_pair(f64::MAX, f64::MAX).unwrap(),
            DdInterval::from_f64_pair(-f64::MAX, 1.0).unwrap(),
            DdInterval::new(Dd::NEG_INFINITY, Dd::ZERO).unwrap(),
            DdInterval::new(Dd::ONE, Dd::INFINITY).unwrap(),
            DdInterval::from_f64_pair(5e-324, 1e-300).unwrap(),
            DdInterval::from_f64_pair(-1.0, 1.0).unwrap(),
        ];
        for &x in &specials {
            for &y in &specials {
                for r in [
                    x + y,
                    x - y,
                    x * y,
                    x / y,
                    x.sqr(),
                    x.sqrt(),
                    x.powi(3),
                    x.powi(-2),
                    x.abs(),
                    x.mul_add(y, x),
                ] {
                    assert!(no_nan(r), "{x:?} {y:?} -> {r:?}");
                    assert!(
                        r.is_empty()
                            || (r.lo <= r.hi
                                && r.lo.hi < f64::INFINITY
                                && r.hi.hi > f64::NEG_INFINITY)
                    );
                }
            }
        }
        let big = iv(1e300) * iv(1e300);
        assert!(big.sup() == Dd::INFINITY && big.inf().hi() >= TWO_1023);
        assert!((iv(f64::MAX) + iv(f64::MAX)).sup() == Dd::INFINITY);
        assert!(DdInterval::from_f64(f64::NAN).is_empty());
        assert!(DdInterval::from_f64(f64::INFINITY) == DdInterval::ENTIRE);
        assert!((DdInterval::EMPTY + iv(1.0)).is_empty());
        assert!((DdInterval::ENTIRE * DdInterval::ZERO).is_exact_zero());
    }

    #[test]
    fn next_up_fast_is_next_up() {
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            5e-324,
            -5e-324,
            f64::MAX / 2.0,
            -f64::MAX,
            1e-310,
            -2.5,
        ] {
            assert_eq!(next_up_fast(x), x.next_up(), "{x}");
        }
        assert!(next_up_fast(f64::MAX).is_infinite() && next_up_fast(f64::INFINITY).is_nan());
    }

    #[test]
    fn decimal_parsing() {
        for bad in ["", ".", "1e", "abc", "1.2.3", "--1", "1e+", "0x10", "1 2"] {
            assert!(DdInterval::from_decimal(bad).is_none(), "{bad}");
        }
        assert!(DdInterval::from_decimal("1.5").unwrap() == iv(1.5));
        assert!(DdInterval::from_decimal("-.5e1").unwrap() == iv(-5.0));
        assert!(
            DdInterval::from_decimal("+12345678901234567890123456789012")
                .unwrap()
                .is_point()
        );
        assert!(DdInterval::from_decimal("1e400").unwrap().sup() == Dd::INFINITY);
        assert!(DdInterval::from_decimal("1e400").unwrap().inf() == Dd::MAX);
        assert!(DdInterval::from_decimal("-1e-400")
            .unwrap()
            .contains(Dd::ZERO));
        assert!(
            DdInterval::from_decimal("1e-999999999999")
                .unwrap()
                .sup()
                .hi()
                == pow2(-1074)
        );
        let x = DdInterval::from_decimal("0.1").unwrap();
        assert!(x.wid_up() <= 2.0 * 1.0e-1 * 1.3e-32);
        // 2^-1074 exactly, written out.
        let tiny = DdInterval::from_decimal("4.940656458412465441765687928682213723650598026143247644255856825006755072702087518652998363616359923797965646954457177309266567103559397963987747960107818781263007131903114045278458171678489821036887186360569987307230500063874091535649843873124733972731696151400317153853980741262385655911710266585566867681870395603106249319452715914924553293054565444011274801297099995419319894090804165633245247571478690147267801593552386115501348035264934720193790268107107491703332226844753335720832431936092382893458368060106011506169809753078342277318329247904982524730776375927247874656084778203734469699533647017972677717585125660551199131504891101451037862738167250955837389733598993664809941164205702637090279242767544565229087538682506419718265533447265625e-324").unwrap();
        assert!(tiny.is_point() && tiny.inf().hi() == pow2(-1074));
        // Long inputs: bounded by their first 800 digits, and cheap.
        let long = format!("0.{}", "3".repeat(100_000));
        let third = DdInterval::from_decimal(&long).unwrap();
        assert!(third.inf_f64() > 0.3333 && third.sup_f64() < 0.33334 && third.wid_up() < 1e-31);
        let big = format!("{}e-100000", "7".repeat(100_000));
        let sevens = DdInterval::from_decimal(&big).unwrap();
        assert!(sevens.inf_f64() > 0.7777 && sevens.sup_f64() < 0.7778 && sevens.wid_up() < 1e-31);
    }

    /// The exact value of a finite double-double times `2^1100` (an integer).
    fn exact(x: Dd) -> num_bigint::BigInt {
        use num_bigint::BigInt;
        let one = |v: f64| -> BigInt {
            if v == 0.0 {
                return BigInt::from(0);
            }
            let (neg, m, e) = decompose(v);
            let b = BigInt::from(m) << ((e + 1100) as usize);
            if neg {
                -b
            } else {
                b
            }
        };
        one(x.hi) + one(x.lo)
    }

    /// (12.1.21) The fused dot product against exact integer arithmetic: for random and
    /// adversarial intervals (points, thin and wide intervals, cancellation, huge and tiny
    /// magnitudes down to the subnormals, zeros), `acc +- sum x_j y_j` contains the exact range
    /// `acc +- [sum_j min corners, sum_j max corners]` (each term ranges independently over its
    /// interval product), and is not much wider than it; empty, unbounded and overflowing
    /// inputs take the chain of interval operations.
    #[test]
    fn fused_dot_contains_the_exact_range() {
        use num_bigint::BigInt;
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            // splitmix64
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        };
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        // A random double-double of magnitude about 2^k, or 0.
        let mut dd = |k: i32, unit: &mut dyn FnMut() -> f64| -> Dd {
            if unit() < 0.05 {
                return Dd::ZERO;
            }
            let sign = if unit() < 0.5 { -1.0 } else { 1.0 };
            let hi = sign * (1.0 + unit()) * pow2(k.clamp(-1074, 1022));
            let lo = (unit() - 0.5) * hi * pow2(-53);
            Dd::new(hi, if unit() < 0.3 { 0.0 } else { lo })
        };
        let iv = |unit: &mut dyn FnMut() -> f64,
                  dd: &mut dyn FnMut(i32, &mut dyn FnMut() -> f64) -> Dd|
         -> DdInterval {
            let scale = match (unit() * 10.0) as u32 {
                0 => 500 - (unit() * 100.0) as i32,  // huge
                1 => -1000 - (unit() * 74.0) as i32, // tiny, down to the subnormals
                2 => -600,
                _ => (unit() * 120.0) as i32 - 60,
            };
            let c = dd(scale, unit);
            let w = match (unit() * 6.0) as u32 {
                0 | 1 => return DdInterval::point(c),
                2 => dd(scale - 100 - (unit() * 10.0) as i32, unit).abs(),
                3 => dd(scale - 55, unit).abs(),
                4 => dd(scale - 20, unit).abs(),
                _ => dd(scale + 1, unit).abs(), // wide, may straddle 0
            };
            let lo = c - w;
            let hi = c + w.scale_pow2(-1);
            if lo <= hi {
                DdInterval::new(lo, hi).unwrap()
            } else {
                DdInterval::point(c)
            }
        };
        let exact_range = |acc: DdInterval, neg: bool, xs: &[DdInterval], ys: &[DdInterval]| {
            let sh = 1100usize;
            let (mut lo, mut hi) = (exact(acc.lo) << sh, exact(acc.hi) << sh);
            for (x, y) in xs.iter().zip(ys) {
                let c: Vec<BigInt> = [(x.lo, y.lo), (x.lo, y.hi), (x.hi, y.lo), (x.hi, y.hi)]
                    .iter()
                    .map(|&(a, b)| exact(a) * exact(b))
                    .collect();
                let (mn, mx) = (
                    c.iter().min().unwrap().clone(),
                    c.iter().max().unwrap().clone(),
                );
                if neg {
                    lo -= mx;
                    hi -= mn;
                } else {
                    lo += mn;
                    hi += mx;
                }
            }
            (lo, hi)
        };
        let mut fast = 0;
        for case in 0..1500 {
            let n = 1 + (unit() * 40.0) as usize;
            let mut xs: Vec<DdInterval> = (0..n).map(|_| iv(&mut unit, &mut dd)).collect();
            let mut ys: Vec<DdInterval> = (0..n).map(|_| iv(&mut unit, &mut dd)).collect();
            if case % 3 == 1 && n >= 2 {
                // cancellation: the second product undoes the first up to a tiny remainder
                xs[1] = -xs[0];
                ys[1] = ys[0] + DdInterval::from_f64(pow2(-70)) * ys[0];
            }
            if case % 7 == 3 {
                // unbounded, empty or overflowing inputs
                let j = (unit() * n as f64) as usize;
                xs[j] = match case % 4 {
                    0 => DdInterval::ENTIRE,
                    1 => DdInterval::new(Dd::ONE, Dd::INFINITY).unwrap(),
                    2 => DdInterval::from_f64_pair(1e300, 1e301).unwrap(),
                    _ => DdInterval::EMPTY,
                };
                ys[j] = DdInterval::from_f64_pair(1e10, 1e300).unwrap();
            }
            let acc = iv(&mut unit, &mut dd);
            let neg = unit() < 0.5;
            let got = DdInterval::dot_acc(acc, neg, xs.iter().copied().zip(ys.iter().copied()));
            let chain = dot_chain(acc, neg, xs.iter().copied().zip(ys.iter().copied()));
            assert!(no_nan(got), "case {case}");
            if dot_fused(xs.iter().copied().zip(ys.iter().copied())).is_none() {
                assert!(got == chain, "case {case}: the fallback is the chain");
                continue;
            }
            fast += 1;
            let (lo, hi) = exact_range(acc, neg, &xs, &ys);
            let sh = 1100usize;
            assert!(
                (exact(got.lo) << sh) <= lo && hi <= (exact(got.hi) << sh),
                "case {case}: {got:?} misses the exact range"
            );
            // Not much wider than the exact range: at most 1.5 times it (the balls of wide
            // factors) plus a few 2^-100 of the magnitudes, when those are far from the
            // subnormals.
            let mag: f64 = xs
                .iter()
                .zip(&ys)
                .map(|(x, y)| x.mag_up() * y.mag_up())
                .sum::<f64>()
                + acc.mag_up();
            let ew = {
                // a lower estimate of (hi - lo) 2^-2200 (within a factor 2), for a loose check
                let bits = (&hi - &lo).bits() as i32;
                if bits == 0 {
                    0.0
                } else {
                    pow2((bits - 2201).clamp(-1074, 1023))
                }
            };
            if mag.is_finite() && mag > 1e-250 {
                assert!(
                    got.wid_up() <= 3.0 * ew + mag * pow2(-96),
                    "case {case}: {got:?} too wide ({} against {ew}, magnitude {mag})",
                    got.wid_up()
                );
            }
        }
        assert!(fast > 1000, "{fast} cases took the fused sum");
    }
}
