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

// The rest of the type, by concern (spec 12.1 says what each proves): `interval`, the interval
// operations; `ball`, balls and the fused dot product; `decimal`, exact decimal conversions.
mod ball;
mod decimal;
mod interval;
mod quotient;
pub(super) use ball::Ball;
pub(super) use decimal::{big_to_interval, dd_to_big};
pub use decimal::{dd_to_decimal, DISPLAY_DIGITS};
use interval::*;
#[cfg(test)]
use {ball::*, decimal::*};

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
