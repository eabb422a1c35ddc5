//! `MpInterval`: intervals whose ends are [`Mp`] numbers of a precision chosen at run time
//! (any number of bits, e.g. 113 to 4096), every operation rounded outward:
//! [spec (12.2)](crate::spec::precision).
//!
//! The ends are rounded to the interval's precision `prec` (the lower end toward minus
//! infinity, the upper toward plus infinity); a binary operation on two intervals works at the
//! larger of their precisions. The empty interval is stored as `[+inf, -inf]`; otherwise
//! `lo <= hi`, `lo < +inf`, `hi > -inf`.

use super::dd::{Dd, DdInterval};
use super::mp_float::{decimal_to_mp, parse_decimal, to_decimal};
pub use super::mp_float::{Mp, Round};
use core::fmt;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// An interval with arbitrary precision ends (see the module doc).
///
/// The layout (`repr(C)`, 64-byte aligned) puts the precision and the first 48 bytes of `lo`
/// (sign, exponent, length, the low four limbs) in the first cache line, and those of `hi` at
/// the start of the fifth: at up to 256 bits an interval's ends are read from two cache lines,
/// as the Taylor convolutions do, term after term.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[repr(C, align(64))]
pub struct MpInterval {
    pub(crate) prec: u32,
    pub(crate) lo: Mp,
    _pad: [u64; 4],
    pub(crate) hi: Mp,
}

// the layout the doc describes: `lo` from byte 8, `hi` from byte 256 (a cache line's start)
const _: () = assert!(core::mem::offset_of!(MpInterval, lo) == 8);
const _: () = assert!(core::mem::offset_of!(MpInterval, hi) == 256);

/// The smallest precision accepted (smaller requests are raised to it).
pub const MIN_PREC: u32 = 8;

impl MpInterval {
    pub(super) fn raw(lo: Mp, hi: Mp, prec: u32) -> MpInterval {
        MpInterval {
            prec,
            lo,
            _pad: [0; 4],
            hi,
        }
    }

    /// The empty interval.
    pub fn empty(prec: u32) -> MpInterval {
        MpInterval::raw(Mp::infinity(false), Mp::infinity(true), prec.max(MIN_PREC))
    }

    /// The whole real line `[-inf, +inf]`.
    pub fn entire(prec: u32) -> MpInterval {
        MpInterval::raw(Mp::infinity(true), Mp::infinity(false), prec.max(MIN_PREC))
    }

    /// `[x, x]` for an exact double `x`, its ends rounded outward to `prec` bits (exact for
    /// `prec >= 53`); a NaN gives the empty interval, an infinite `x` the unbounded interval
    /// beyond `f64::MAX` on its side (an infinity is not a real number).
    pub fn from_f64(x: f64, prec: u32) -> MpInterval {
        match Mp::from_f64(x) {
            None => MpInterval::empty(prec),
            Some(m) if m.is_infinite() => {
                let max = Mp::from_f64(f64::MAX.copysign(x)).unwrap_or_else(Mp::zero);
                if x > 0.0 {
                    MpInterval::raw(max, m, prec.max(MIN_PREC))
                } else {
                    MpInterval::raw(m, max, prec.max(MIN_PREC))
                }
            }
            Some(m) => MpInterval::point(&m, prec),
        }
    }

    /// The enclosure of an exact point `x` at `prec` bits (`[x, x]` when `x` has at most
    /// `prec` significant bits); an infinity gives the unbounded interval on its side.
    pub fn point(x: &Mp, prec: u32) -> MpInterval {
        let prec = prec.max(MIN_PREC);
        if x.is_infinite() {
            let max = if x.is_negative() {
                Mp::max_value(prec).neg()
            } else {
                Mp::max_value(prec)
            };
            return if x.is_negative() {
                MpInterval::raw(*x, max, prec)
            } else {
                MpInterval::raw(max, *x, prec)
            };
        }
        MpInterval::raw(x.round(prec, Round::Down), x.round(prec, Round::Up), prec)
    }

    /// `[lo, hi]` with its ends rounded outward to `prec`; `None` unless `lo <= hi`,
    /// `lo < +inf` and `hi > -inf`.
    pub fn new(lo: &Mp, hi: &Mp, prec: u32) -> Option<MpInterval> {
        if lo > hi
            || (lo.is_infinite() && lo.is_positive())
            || (hi.is_infinite() && hi.is_negative())
        {
            return None;
        }
        let prec = prec.max(MIN_PREC);
        Some(MpInterval::raw(
            lo.round(prec, Round::Down),
            hi.round(prec, Round::Up),
            prec,
        ))
    }

    /// The set of a double-double interval: each end, the exact sum `hi + lo` of its two
    /// doubles, rounded once outward to `prec` bits (12.2.1's sum; exact whenever it fits).
    pub fn from_dd(x: DdInterval, prec: u32) -> MpInterval {
        if x.is_empty() {
            return MpInterval::empty(prec);
        }
        let end = |d: Dd, mode: Round| {
            Mp::from_f64(d.hi())?.add(&Mp::from_f64(d.lo())?, prec.max(MIN_PREC), mode)
        };
        match (end(x.inf(), Round::Down), end(x.sup(), Round::Up)) {
            (Some(lo), Some(hi)) => {
                MpInterval::new(&lo, &hi, prec).unwrap_or(MpInterval::entire(prec))
            }
            _ => MpInterval::entire(prec),
        }
    }

    /// `[lo, hi]` from two doubles (ends exact for `prec >= 53`); `None` unless `lo <= hi`
    /// (NaN fails) and the ends are not `+inf`/`-inf` respectively.
    pub fn from_f64_pair(lo: f64, hi: f64, prec: u32) -> Option<MpInterval> {
        MpInterval::new(&Mp::from_f64(lo)?, &Mp::from_f64(hi)?, prec)
    }

    /// An enclosure of the exact value of a decimal string `[+-]d[.d][e[+-]d]`, the tightest
    /// at `prec` bits (each end one directed rounding of the exact rational): (12.2.6).
    /// `None` for a malformed string or a decimal exponent beyond `10^6` in magnitude.
    pub fn from_decimal(s: &str, prec: u32) -> Option<MpInterval> {
        let prec = prec.max(MIN_PREC);
        let (neg, n, e) = parse_decimal(s)?;
        Some(MpInterval::raw(
            decimal_to_mp(neg, &n, e, prec, Round::Down),
            decimal_to_mp(neg, &n, e, prec, Round::Up),
            prec,
        ))
    }

    /// The interval's precision in bits.
    pub fn prec(&self) -> u32 {
        self.prec
    }

    /// The same interval with its ends rounded outward to `prec` bits.
    pub fn with_prec(&self, prec: u32) -> MpInterval {
        if self.is_empty() {
            return MpInterval::empty(prec);
        }
        let prec = prec.max(MIN_PREC);
        MpInterval::raw(
            self.lo.round(prec, Round::Down),
            self.hi.round(prec, Round::Up),
            prec,
        )
    }

    /// The lower end (`+inf` for the empty interval).
    pub fn inf(&self) -> &Mp {
        &self.lo
    }

    /// The upper end (`-inf` for the empty interval).
    pub fn sup(&self) -> &Mp {
        &self.hi
    }

    /// A double at or below the lower end (`+inf` if empty).
    pub fn inf_f64(&self) -> f64 {
        self.lo.to_f64(Round::Down)
    }

    /// A double at or above the upper end (`-inf` if empty).
    pub fn sup_f64(&self) -> f64 {
        self.hi.to_f64(Round::Up)
    }

    /// A point inside a non-empty interval: the midpoint rounded to nearest at a precision
    /// that holds both ends (so it lies within them, rounding being monotone); 0 for the
    /// whole line, the finite end (or `±Mp::max_value`) for a half-line; zero if empty.
    pub fn mid(&self) -> Mp {
        if self.is_empty() {
            return Mp::zero();
        }
        match (self.lo.is_infinite(), self.hi.is_infinite()) {
            (true, true) => Mp::zero(),
            (true, false) => self.hi.min(Mp::max_value(self.prec).neg()),
            (false, true) => self.lo.max(Mp::max_value(self.prec)),
            (false, false) => {
                let p = (self.prec as u64)
                    .max(self.lo.significant_bits())
                    .max(self.hi.significant_bits())
                    .min(u32::MAX as u64) as u32;
                let s = self
                    .lo
                    .add(&self.hi, p + 1, Round::Near)
                    .unwrap_or_else(Mp::zero);
                // the sum of two p-bit numbers rounded to p + 1 bits, halved (exact), then
                // rounded to p bits: each step is monotone and maps lo + lo to lo and
                // hi + hi to hi, so the result lies in [lo, hi]
                s.ldexp(-1, Round::Near)
                    .round(p, Round::Near)
                    .max(self.lo)
                    .min(self.hi)
            }
        }
    }

    /// An upper bound of `hi - lo` as a double (`+inf` if unbounded, 0 if empty).
    pub fn wid_up(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        self.hi
            .sub(&self.lo, self.prec, Round::Up)
            .map_or(f64::INFINITY, |w| w.to_f64(Round::Up))
    }

    /// An upper bound of `max |x|` over the interval as a double (0 if empty).
    pub fn mag_up(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        self.lo.abs().max(self.hi.abs()).to_f64(Round::Up)
    }

    /// A lower bound of `min |x|` over the interval as a double (0 if empty or if it holds 0).
    pub fn mig_down(&self) -> f64 {
        if self.is_empty() || (!self.lo.is_positive() && !self.hi.is_negative()) {
            return 0.0;
        }
        self.lo.abs().min(self.hi.abs()).to_f64(Round::Down)
    }

    /// `max |x|` over the interval, exact.
    pub fn mag(&self) -> Mp {
        if self.is_empty() {
            return Mp::zero();
        }
        self.lo.abs().max(self.hi.abs())
    }

    /// `min |x|` over the interval, exact.
    pub fn mig(&self) -> Mp {
        if self.is_empty() || (!self.lo.is_positive() && !self.hi.is_negative()) {
            return Mp::zero();
        }
        self.lo.abs().min(self.hi.abs())
    }

    /// Whether the interval is empty.
    pub fn is_empty(&self) -> bool {
        // by the invariant only the empty interval has the lower end +inf
        self.lo.is_infinite() && self.lo.is_positive()
    }

    /// Whether both ends are finite (the empty interval counts as bounded).
    pub fn is_finite(&self) -> bool {
        self.is_empty() || (self.lo.is_finite() && self.hi.is_finite())
    }

    /// Whether the interval is `[0, 0]`.
    pub fn is_exact_zero(&self) -> bool {
        self.lo.is_zero() && self.hi.is_zero()
    }

    /// Whether `x` lies in the interval.
    pub fn contains(&self, x: &Mp) -> bool {
        x.is_finite() && self.lo <= *x && *x <= self.hi
    }

    /// Whether the double `x` lies in the interval.
    pub fn contains_f64(&self, x: f64) -> bool {
        Mp::from_f64(x).is_some_and(|m| self.contains(&m))
    }

    /// Whether `self` is a subset of `other` (the empty interval is a subset of every one).
    pub fn subset(&self, other: &MpInterval) -> bool {
        self.is_empty() || (other.lo <= self.lo && self.hi <= other.hi)
    }

    /// Whether `self` lies in the interior of `other` (each end strictly inside, an infinite
    /// end of `other` counting as interior to itself, as in IEEE 1788).
    pub fn interior(&self, other: &MpInterval) -> bool {
        if self.is_empty() {
            return true;
        }
        let lo_ok = other.lo < self.lo || (other.lo.is_infinite() && self.lo.is_infinite());
        let hi_ok = self.hi < other.hi || (other.hi.is_infinite() && self.hi.is_infinite());
        lo_ok && hi_ok
    }

    /// Whether the intervals have no common point.
    pub fn disjoint(&self, other: &MpInterval) -> bool {
        self.is_empty() || other.is_empty() || self.hi < other.lo || other.hi < self.lo
    }

    /// The smallest interval holding both.
    pub fn hull(&self, other: &MpInterval) -> MpInterval {
        let p = self.prec.max(other.prec);
        if self.is_empty() {
            return other.with_prec(p);
        }
        if other.is_empty() {
            return self.with_prec(p);
        }
        MpInterval::raw(self.lo.min(other.lo), self.hi.max(other.hi), p)
    }

    /// The common part (empty if disjoint).
    pub fn intersection(&self, other: &MpInterval) -> MpInterval {
        let p = self.prec.max(other.prec);
        if self.disjoint(other) {
            return MpInterval::empty(p);
        }
        MpInterval::raw(self.lo.max(other.lo), self.hi.min(other.hi), p)
    }

    /// `-x` (exact).
    pub fn neg(&self) -> MpInterval {
        if self.is_empty() {
            return *self;
        }
        MpInterval::raw(self.hi.neg(), self.lo.neg(), self.prec)
    }

    /// `|x|`: the range of the absolute value (exact).
    pub fn abs(&self) -> MpInterval {
        if self.is_empty() {
            return *self;
        }
        MpInterval::raw(self.mig(), self.mag(), self.prec)
    }

    /// `x + y` rounded outward (12.2.2).
    pub fn add_ref(&self, y: &MpInterval) -> MpInterval {
        let p = self.prec.max(y.prec);
        if self.is_empty() || y.is_empty() {
            return MpInterval::empty(p);
        }
        // lo + lo never meets +inf and hi + hi never meets -inf (the invariant), so the
        // sums are defined
        let lo = self.lo.add(&y.lo, p, Round::Down);
        let hi = self.hi.add(&y.hi, p, Round::Up);
        match (lo, hi) {
            (Some(lo), Some(hi)) => MpInterval::raw(lo, hi, p),
            _ => MpInterval::entire(p),
        }
    }

    /// `x - y` rounded outward (12.2.2).
    pub fn sub_ref(&self, y: &MpInterval) -> MpInterval {
        self.add_ref(&y.neg())
    }

    /// `x y` rounded outward, by the signs of the ends (12.2.2).
    pub fn mul_ref(&self, y: &MpInterval) -> MpInterval {
        let p = self.prec.max(y.prec);
        if self.is_empty() || y.is_empty() {
            return MpInterval::empty(p);
        }
        let (a, b, c, d) = (&self.lo, &self.hi, &y.lo, &y.hi);
        let dn = |u: &Mp, v: &Mp| u.mul(v, p, Round::Down);
        let up = |u: &Mp, v: &Mp| u.mul(v, p, Round::Up);
        let (lo, hi) = if !a.is_negative() {
            if !c.is_negative() {
                (dn(a, c), up(b, d))
            } else if !d.is_positive() {
                (dn(b, c), up(a, d))
            } else {
                (dn(b, c), up(b, d))
            }
        } else if !b.is_positive() {
            if !c.is_negative() {
                (dn(a, d), up(b, c))
            } else if !d.is_positive() {
                (dn(b, d), up(a, c))
            } else {
                (dn(a, d), up(a, c))
            }
        } else if !c.is_negative() {
            (dn(a, d), up(b, d))
        } else if !d.is_positive() {
            (dn(b, c), up(a, c))
        } else {
            (dn(a, d).min(dn(b, c)), up(a, c).max(up(b, d)))
        };
        MpInterval::raw(lo, hi, p)
    }

    /// `x / y` rounded outward (12.2.2): empty if `y = [0, 0]` or either is empty; the
    /// whole line if `y` holds 0 in its interior or at one end (unless `x = [0, 0]`: then
    /// `[0, 0]`).
    pub fn div_ref(&self, y: &MpInterval) -> MpInterval {
        let p = self.prec.max(y.prec);
        if self.is_empty() || y.is_empty() || y.is_exact_zero() {
            return MpInterval::empty(p);
        }
        if self.is_exact_zero() {
            return MpInterval::raw(Mp::zero(), Mp::zero(), p);
        }
        let (a, b, c, d) = (&self.lo, &self.hi, &y.lo, &y.hi);
        if !c.is_positive() && !d.is_negative() {
            return MpInterval::entire(p);
        }
        let dn = |u: &Mp, v: &Mp| u.div(v, p, Round::Down);
        let up = |u: &Mp, v: &Mp| u.div(v, p, Round::Up);
        let r = if c.is_positive() {
            if !a.is_negative() {
                (dn(a, d), up(b, c))
            } else if !b.is_positive() {
                (dn(a, c), up(b, d))
            } else {
                (dn(a, c), up(b, c))
            }
        } else if !a.is_negative() {
            (dn(b, d), up(a, c))
        } else if !b.is_positive() {
            (dn(b, c), up(a, d))
        } else {
            (dn(b, d), up(a, d))
        };
        match r {
            (Some(lo), Some(hi)) => MpInterval::raw(lo, hi, p),
            _ => MpInterval::entire(p),
        }
    }

    /// `x / n` for a positive integer `n`, rounded outward (division by a positive number is
    /// increasing).
    pub fn div_u64(&self, n: u64) -> MpInterval {
        let p = self.prec;
        if self.is_empty() || n == 0 {
            return MpInterval::empty(p);
        }
        match (
            self.lo.div_u64(n, p, Round::Down),
            self.hi.div_u64(n, p, Round::Up),
        ) {
            (Some(lo), Some(hi)) => MpInterval::raw(lo, hi, p),
            _ => MpInterval::entire(p),
        }
    }

    /// `1 / x` rounded outward.
    pub fn recip(&self) -> MpInterval {
        MpInterval::from_f64(1.0, self.prec).div_ref(self)
    }

    /// `x^2`: the range of the square (nonnegative), rounded outward.
    pub fn sqr(&self) -> MpInterval {
        if self.is_empty() {
            return *self;
        }
        let (mig, mag) = (self.mig(), self.mag());
        MpInterval::raw(
            mig.mul(&mig, self.prec, Round::Down),
            mag.mul(&mag, self.prec, Round::Up),
            self.prec,
        )
    }

    /// `x^n` for an integer `n` (`x^0 = 1`; a negative `n` is `1 / x^|n|`), the range of the
    /// power rounded outward: even powers from `[mig, mag]`, odd ones from the ends (12.2.2).
    pub fn powi(&self, n: i32) -> MpInterval {
        let p = self.prec;
        if self.is_empty() {
            return *self;
        }
        if n == 0 {
            return MpInterval::from_f64(1.0, p);
        }
        let m = n.unsigned_abs();
        let r = if m.is_multiple_of(2) {
            MpInterval::raw(
                pow_mag(&self.mig(), m, p, Round::Down),
                pow_mag(&self.mag(), m, p, Round::Up),
                p,
            )
        } else {
            // odd powers are increasing: x^m = sign(x) |x|^m
            let end = |x: &Mp, mode: Round| {
                if x.is_negative() {
                    let opp = if mode == Round::Down {
                        Round::Up
                    } else {
                        Round::Down
                    };
                    pow_mag(&x.abs(), m, p, opp).neg()
                } else {
                    pow_mag(x, m, p, mode)
                }
            };
            MpInterval::raw(end(&self.lo, Round::Down), end(&self.hi, Round::Up), p)
        };
        if n < 0 {
            r.recip()
        } else {
            r
        }
    }

    /// `self * a + b`, rounded outward (two roundings, unfused).
    pub fn mul_add(&self, a: &MpInterval, b: &MpInterval) -> MpInterval {
        self.mul_ref(a).add_ref(b)
    }

    /// Multiplication by `2^k`, exact unless it leaves the exponent range (then outward).
    pub fn ldexp(&self, k: i64) -> MpInterval {
        if self.is_empty() {
            return *self;
        }
        MpInterval::raw(
            self.lo.ldexp(k, Round::Down),
            self.hi.ldexp(k, Round::Up),
            self.prec,
        )
    }

    /// The lower end written with `digits` significant digits, rounded down (12.2.6).
    pub fn inf_decimal(&self, digits: usize) -> String {
        to_decimal(&self.lo, digits, false)
    }

    /// The upper end written with `digits` significant digits, rounded up (12.2.6).
    pub fn sup_decimal(&self, digits: usize) -> String {
        to_decimal(&self.hi, digits, true)
    }

    /// The number of decimal digits that carry the precision: `ceil(prec log10 2) + 2`.
    pub fn default_digits(&self) -> usize {
        ((self.prec as f64) * core::f64::consts::LOG10_2).ceil() as usize + 2
    }
}

/// `|x|^n` (for `x >= 0`) with every product rounded in direction `mode`: the products of
/// nonnegative numbers are increasing in each factor, so rounding each one down (up) gives a
/// lower (upper) bound.
fn pow_mag(x: &Mp, n: u32, p: u32, mode: Round) -> Mp {
    let mut result = Mp::from_i64(1);
    let mut base = *x;
    let mut n = n;
    while n > 0 {
        if n & 1 == 1 {
            result = result.mul(&base, p, mode);
        }
        n >>= 1;
        if n > 0 {
            base = base.mul(&base, p, mode);
        }
    }
    result
}

impl fmt::Display for MpInterval {
    /// `[lo, hi]` with each end written with [`MpInterval::default_digits`] digits, rounded
    /// outward; `[empty]` for the empty interval.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            return write!(f, "[empty]");
        }
        let d = self.default_digits();
        write!(f, "[{}, {}]", self.inf_decimal(d), self.sup_decimal(d))
    }
}

impl fmt::Debug for MpInterval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

macro_rules! binop {
    ($tr:ident, $m:ident, $by:ident) => {
        impl $tr for MpInterval {
            type Output = MpInterval;
            fn $m(self, y: MpInterval) -> MpInterval {
                self.$by(&y)
            }
        }
        impl<'a> $tr<&'a MpInterval> for &'a MpInterval {
            type Output = MpInterval;
            fn $m(self, y: &'a MpInterval) -> MpInterval {
                self.$by(y)
            }
        }
    };
}
binop!(Add, add, add_ref);
binop!(Sub, sub, sub_ref);
binop!(Mul, mul, mul_ref);
binop!(Div, div, div_ref);

impl Neg for MpInterval {
    type Output = MpInterval;
    fn neg(self) -> MpInterval {
        MpInterval::neg(&self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: u32 = 160;

    fn iv(x: f64) -> MpInterval {
        MpInterval::from_f64(x, P)
    }

    fn ulps_wide(x: &MpInterval) -> u64 {
        // the number of steps of 2^(top - prec) in the width, rounded up
        let w = x.hi.sub(&x.lo, 4096, Round::Up).unwrap();
        if w.is_zero() {
            return 0;
        }
        let t = x.hi.abs().max(x.lo.abs()).top();
        let u = Mp::from_i64(1).ldexp(t - x.prec as i64, Round::Near);
        w.div(&u, 64, Round::Up).unwrap().ceil().to_i64().unwrap() as u64
    }

    #[test]
    fn exact_products_and_one_third() {
        let p = iv(3.0) * iv(-7.0);
        assert_eq!(p, iv(-21.0));
        let t = iv(1.0) / iv(3.0);
        assert!(ulps_wide(&t) <= 1);
        let one = t * iv(3.0);
        assert!(one.contains_f64(1.0));
        assert!(!one.is_exact_zero());
        let s = (iv(1.0) / iv(3.0)) - (iv(1.0) / iv(3.0));
        assert!(s.contains_f64(0.0));
        // (2^80 + 1) - 2^80 = 1 exactly at 160 bits
        let a = iv(2f64.powi(80)) + iv(1.0);
        assert_eq!(a - iv(2f64.powi(80)), iv(1.0));
    }

    #[test]
    fn division_and_powers_by_cases() {
        let x = MpInterval::from_f64_pair(-2.0, 3.0, P).unwrap();
        assert_eq!(x.sqr(), MpInterval::from_f64_pair(0.0, 9.0, P).unwrap());
        assert_eq!(x.powi(3), MpInterval::from_f64_pair(-8.0, 27.0, P).unwrap());
        assert_eq!(x.powi(2), x.sqr());
        assert!(iv(1.0).div_ref(&x).lo.is_infinite());
        assert!(iv(1.0).div_ref(&iv(0.0)).is_empty());
        let y = MpInterval::from_f64_pair(2.0, 4.0, P).unwrap();
        let q = x.div_ref(&y);
        assert_eq!(q, MpInterval::from_f64_pair(-1.0, 1.5, P).unwrap());
        let q = x.div_ref(&MpInterval::neg(&y));
        assert_eq!(q, MpInterval::from_f64_pair(-1.5, 1.0, P).unwrap());
        assert_eq!(y.powi(-1), MpInterval::from_f64_pair(0.25, 0.5, P).unwrap());
        let m = x.mul_ref(&MpInterval::neg(&y));
        assert_eq!(m, MpInterval::from_f64_pair(-12.0, 8.0, P).unwrap());
        let e = MpInterval::entire(P);
        assert_eq!(e.mul_ref(&iv(0.0)), iv(0.0));
        assert!((e + iv(1.0)).lo.is_infinite());
        assert!(MpInterval::empty(P).add_ref(&iv(1.0)).is_empty());
    }

    #[test]
    fn decimal_round_trip_and_printing() {
        let x = MpInterval::from_decimal("0.1", P).unwrap();
        assert!(ulps_wide(&x) <= 1);
        assert!(!x.contains_f64(0.1));
        let d = x.default_digits();
        assert_eq!(d, 51);
        let lo = MpInterval::from_decimal(&x.inf_decimal(d), 4 * P).unwrap();
        let hi = MpInterval::from_decimal(&x.sup_decimal(d), 4 * P).unwrap();
        assert!(lo.hi <= x.lo && x.hi <= hi.lo);
        assert_eq!(format!("{}", iv(1.5)), "[1.5e0, 1.5e0]");
        assert_eq!(format!("{}", MpInterval::empty(P)), "[empty]");
        assert_eq!(format!("{}", MpInterval::entire(P)), "[-inf, inf]");
        assert!(MpInterval::from_decimal("abc", P).is_none());
        let m = MpInterval::from_decimal("-1e-400", P).unwrap();
        assert!(m.hi.is_negative() && m.inf_f64() == -5e-324 && m.sup_f64() == 0.0);
    }

    #[test]
    fn ends_tests_and_set_operations() {
        let x = MpInterval::from_f64_pair(-1.0, 2.0, P).unwrap();
        let y = MpInterval::from_f64_pair(1.5, 3.0, P).unwrap();
        assert_eq!(x.mid(), Mp::from_f64(0.5).unwrap());
        assert_eq!(x.wid_up(), 3.0);
        assert_eq!(x.mag_up(), 2.0);
        assert_eq!(x.mig_down(), 0.0);
        assert_eq!(y.mig_down(), 1.5);
        assert!(!x.disjoint(&y));
        assert_eq!(
            x.intersection(&y),
            MpInterval::from_f64_pair(1.5, 2.0, P).unwrap()
        );
        assert_eq!(x.hull(&y), MpInterval::from_f64_pair(-1.0, 3.0, P).unwrap());
        assert!(iv(0.5).interior(&x) && !iv(-1.0).interior(&x));
        assert!(iv(-1.0).subset(&x));
        assert!(MpInterval::new(&Mp::from_i64(2), &Mp::from_i64(1), P).is_none());
        assert!(MpInterval::from_f64_pair(f64::NAN, 1.0, P).is_none());
        let t = MpInterval::from_decimal("0.1", P).unwrap();
        assert!(t.contains(&t.mid()));
        assert_eq!(iv(f64::INFINITY).lo, Mp::from_f64(f64::MAX).unwrap());
        assert!(iv(f64::NAN).is_empty());
    }
}
