//! `WideInterval`: intervals of more than 106 bits that the validated integrator computes
//! with ([spec (12.3)](crate::spec::precision)).
//!
//! A `WideInterval` is an [`MpInterval`] at the precision in force on the thread: its ends
//! are [`Mp`] numbers, whose significands are fixed arrays of 64-bit limbs (`Copy`, no heap
//! in any arithmetic operation, [spec (12.2.0)](crate::spec::precision)), and every operation
//! is the [`MpInterval`] one (one proved outward rounding per end, 12.2): every proof of 12.2
//! is a proof here.
//!
//! The precision is chosen at run time, per thread: [`with_bits`] runs a computation with
//! results rounded to that many bits ([`bits`], 256 unless set). Results carry the precision
//! they were made at; a binary operation works at the larger of its operands' precisions.

use super::mp::MpInterval;
use super::mp_float::{Mp, Round};
use std::cell::Cell;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The most significant bits of [`with_bits`] (E20, E29 of the contract).
pub const MAX_BITS: u32 = 1024;
/// The smallest precision of [`with_bits`] (below it the double-double type serves).
pub const MIN_BITS: u32 = 107;
/// The precision in force on a thread where [`with_bits`] was not called.
pub const DEFAULT_BITS: u32 = 256;

thread_local! {
    static BITS: Cell<u32> = const { Cell::new(DEFAULT_BITS) };
    static PI: Cell<Option<WideInterval>> = const { Cell::new(None) };
}

/// The precision of the [`WideInterval`] results computed on this thread.
pub fn bits() -> u32 {
    BITS.with(|b| b.get())
}

/// Runs `f` with [`WideInterval`] results rounded to `bits` significant bits (clamped to
/// `MIN_BITS..=MAX_BITS`) on this thread, then restores the previous precision.
pub fn with_bits<R>(bits: u32, f: impl FnOnce() -> R) -> R {
    struct Restore(u32);
    impl Drop for Restore {
        fn drop(&mut self) {
            BITS.with(|b| b.set(self.0));
        }
    }
    let _restore = Restore(BITS.with(|b| b.replace(bits.clamp(MIN_BITS, MAX_BITS))));
    f()
}

/// A binary floating-point number (the ends of a [`WideInterval`], and its points): an
/// [`Mp`].
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Wide(Mp);

impl Wide {
    /// Zero.
    pub const ZERO: Wide = Wide(Mp::zero());

    /// Minus (`neg`) or plus infinity.
    pub fn infinity(neg: bool) -> Wide {
        Wide(Mp::infinity(neg))
    }

    /// The number `x`.
    pub fn from_mp(x: &Mp) -> Option<Wide> {
        Some(Wide(*x))
    }

    /// The same number as an [`Mp`].
    pub fn to_mp(&self) -> Mp {
        self.0
    }

    /// The exact value of a finite double (`None` for NaN; infinities give infinities).
    pub fn from_f64(x: f64) -> Option<Wide> {
        Mp::from_f64(x).map(Wide)
    }

    /// The double nearest to this number.
    pub fn to_f64(&self) -> f64 {
        self.0.to_f64(Round::Near)
    }
}

impl fmt::Debug for Wide {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.0, f)
    }
}

/// An interval with [`Mp`] ends, rounded outward to the precision in force ([`bits`]);
/// every operation returns a superset of the exact range ([spec (12.3)](crate::spec::precision)).
/// The empty interval is `[+inf, -inf]`.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct WideInterval(MpInterval);

impl WideInterval {
    /// The same set as an [`MpInterval`].
    pub fn to_mp(&self) -> MpInterval {
        self.0
    }

    /// The same set as `x`.
    pub fn from_mp(x: &MpInterval) -> WideInterval {
        WideInterval(*x)
    }

    /// `[x, x]`; the half-line beyond the largest number for an infinite `x`, as
    /// [`MpInterval::point`].
    pub fn point(x: Wide) -> WideInterval {
        WideInterval(MpInterval::point(&x.0, bits()))
    }

    /// `[x, x]` for a double (`x` exact; NaN gives the empty interval).
    pub fn from_f64(x: f64) -> WideInterval {
        WideInterval(MpInterval::from_f64(x, bits()))
    }

    /// The whole line.
    pub fn entire() -> WideInterval {
        WideInterval(MpInterval::entire(bits()))
    }

    /// The decimal string `s` (`[-]digits[.digits][e[-]digits]`) as the interval of its
    /// exact value rounded outward at the precision in force ([spec (12.2.6)](crate::spec::precision)).
    pub fn from_decimal(s: &str) -> Option<WideInterval> {
        MpInterval::from_decimal(s, bits()).map(WideInterval)
    }

    /// The lower end.
    pub fn inf(&self) -> Wide {
        Wide(self.0.lo)
    }

    /// The upper end.
    pub fn sup(&self) -> Wide {
        Wide(self.0.hi)
    }

    /// Whether empty.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Non-empty with finite ends ([`MpInterval::is_finite`] counts the empty interval as
    /// bounded; the method's checks, such as Krawczyk's `K(X)` in the interior of `X`, need
    /// an empty enclosure refused).
    pub fn is_finite(&self) -> bool {
        !self.0.is_empty() && self.0.is_finite()
    }

    /// Exactly `[0, 0]`.
    pub fn is_exact_zero(&self) -> bool {
        self.0.is_exact_zero()
    }

    /// A point of a non-empty interval: its midpoint rounded to nearest at the precision in
    /// force, within the ends ([`MpInterval::mid`]).
    pub fn mid(&self) -> Wide {
        let m = &self.0;
        Wide(m.mid().round(bits(), Round::Near).max(m.lo).min(m.hi))
    }

    /// An f64 at most the lower end (`+inf` when empty).
    pub fn inf_f64(&self) -> f64 {
        self.0.lo.to_f64(Round::Down)
    }

    /// An f64 at least the upper end (`-inf` when empty).
    pub fn sup_f64(&self) -> f64 {
        self.0.hi.to_f64(Round::Up)
    }

    /// An f64 at least the width.
    pub fn wid_up(&self) -> f64 {
        self.0.wid_up()
    }

    /// An f64 at least the largest magnitude.
    pub fn mag_up(&self) -> f64 {
        self.0.mag_up()
    }

    /// An f64 at most the smallest magnitude.
    pub fn mig_down(&self) -> f64 {
        self.0.mig_down()
    }

    /// Whether the double `x` is in the interval.
    pub fn contains_f64(&self, x: f64) -> bool {
        self.0.contains_f64(x)
    }

    /// Whether `self` is inside `other`.
    pub fn subset(&self, other: &WideInterval) -> bool {
        self.0.subset(&other.0)
    }

    /// Whether `self` is inside the interior of `other`.
    pub fn interior(&self, other: &WideInterval) -> bool {
        self.0.interior(&other.0)
    }

    /// The intersection (possibly empty).
    pub fn intersection(&self, other: &WideInterval) -> WideInterval {
        WideInterval(self.0.intersection(&other.0))
    }

    /// The smallest interval containing both.
    pub fn hull(&self, other: &WideInterval) -> WideInterval {
        WideInterval(self.0.hull(&other.0))
    }

    /// `self + a b`, outward rounded: the fused dot product of one term (each end the exact
    /// sum rounded once, [spec (12.2.8)](crate::spec::precision)).
    pub fn mul_acc(&self, a: &WideInterval, b: &WideInterval) -> WideInterval {
        let p = self.0.prec().max(a.0.prec()).max(b.0.prec());
        match MpInterval::dot_acc(&self.0, false, core::iter::once((&a.0, &b.0)), p) {
            Some(r) => WideInterval(r),
            None => WideInterval(a.0.mul_add(&b.0, &self.0)),
        }
    }

    /// `acc + sum_j x_j y_{n-1-j}` (`acc - ...` when `neg`): the fused dot product, each end
    /// summed exactly and rounded once ([spec (12.2.8)](crate::spec::precision)); with an
    /// empty or unbounded operand, each operation outward rounded in turn.
    pub fn conv(
        acc: &WideInterval,
        neg: bool,
        x: &[WideInterval],
        y: &[WideInterval],
    ) -> WideInterval {
        let n = x.len();
        let pairs = || (0..n).map(|j| (&x[j].0, &y[n - 1 - j].0));
        let p = pairs().fold(acc.0.prec().max(bits()), |p, (a, b)| {
            p.max(a.prec()).max(b.prec())
        });
        if let Some(r) = MpInterval::dot_acc(&acc.0, neg, pairs(), p) {
            return WideInterval(r);
        }
        let mut s = MpInterval::from_f64(0.0, bits());
        for (a, b) in pairs() {
            if a.is_exact_zero() || b.is_exact_zero() {
                continue;
            }
            s = a.mul_add(b, &s);
        }
        WideInterval(if neg {
            acc.0.sub_ref(&s)
        } else {
            acc.0.add_ref(&s)
        })
    }

    /// `acc + sum_i ((first + i) x_i) y_{n-1-i}` (`acc - ...` when `neg`): one fused dot
    /// product with exact integer weights, each end summed exactly and rounded once ([spec
    /// (12.2.9)](crate::spec::precision)); `None` with an empty or unbounded operand or a
    /// significand too long for the window (the caller then goes term by term).
    pub fn weighted_conv(
        acc: &WideInterval,
        neg: bool,
        first: u64,
        x: &[WideInterval],
        y: &[WideInterval],
    ) -> Option<WideInterval> {
        let n = x.len();
        let terms = || (0..n).map(|j| (&x[j].0, &y[n - 1 - j].0, first + j as u64));
        let p = terms().fold(acc.0.prec().max(bits()), |p, (a, b, _)| {
            p.max(a.prec()).max(b.prec())
        });
        MpInterval::dot_acc_weighted(&acc.0, neg, terms(), p).map(WideInterval)
    }

    fn unary(&self, f: impl FnOnce(&MpInterval) -> MpInterval) -> WideInterval {
        WideInterval(f(&self.0))
    }

    /// An enclosure of pi at the precision in force (computed once per thread and precision).
    pub fn pi() -> WideInterval {
        let b = bits();
        PI.with(|c| {
            if let Some(v) = c.get() {
                if v.0.prec() == b {
                    return v;
                }
            }
            let v = WideInterval(MpInterval::pi(b));
            c.set(Some(v));
            v
        })
    }
}

impl fmt::Debug for WideInterval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

macro_rules! binop {
    ($tr:ident, $m:ident, $by:ident) => {
        impl $tr for WideInterval {
            type Output = WideInterval;
            fn $m(self, y: WideInterval) -> WideInterval {
                WideInterval(self.0.$by(&y.0))
            }
        }
    };
}
binop!(Add, add, add_ref);
binop!(Sub, sub, sub_ref);
binop!(Mul, mul, mul_ref);
binop!(Div, div, div_ref);

impl Neg for WideInterval {
    type Output = WideInterval;
    fn neg(self) -> WideInterval {
        WideInterval(self.0.neg())
    }
}

impl crate::scalar::Scalar for WideInterval {
    fn cst(c: f64) -> Self {
        WideInterval::from_f64(c)
    }
    fn sin(&self) -> Self {
        self.unary(MpInterval::sin)
    }
    fn cos(&self) -> Self {
        self.unary(MpInterval::cos)
    }
    fn sqrt(&self) -> Self {
        self.unary(MpInterval::sqrt)
    }
    fn exp(&self) -> Self {
        self.unary(MpInterval::exp)
    }
    fn ln(&self) -> Self {
        self.unary(MpInterval::ln)
    }
    fn atan(&self) -> Self {
        self.unary(MpInterval::atan)
    }
    fn sinh(&self) -> Self {
        self.unary(MpInterval::sinh)
    }
    fn cosh(&self) -> Self {
        self.unary(MpInterval::cosh)
    }
    fn pi() -> Self {
        WideInterval::pi()
    }
    fn tan(&self) -> Self {
        self.unary(MpInterval::tan)
    }
    fn tanh(&self) -> Self {
        self.unary(MpInterval::tanh)
    }
    fn sqr(&self) -> Self {
        self.unary(MpInterval::sqr)
    }
}

impl crate::OutwardDecimal for WideInterval {
    fn decimal(&self) -> crate::DecimalInterval {
        let m = &self.0;
        let digits = m.default_digits();
        crate::DecimalInterval(m.inf_decimal(digits), m.sup_decimal(digits))
    }
}

/// The Taylor order at `bits` bits ([spec (12.0.3)](crate::spec::precision)): `3 bits / 8`
/// rounded up, the rule that gives 40 at 106 bits.
pub fn order_at(bits: u32) -> usize {
    (3 * bits as usize).div_ceil(8)
}

/// The variational orders tried at [`bits`] (those of double-double intervals, then on up to
/// the order).
pub(crate) fn jac_orders() -> &'static [usize] {
    const ALL: [usize; 17] = [
        3, 5, 8, 12, 16, 20, 26, 32, 40, 50, 60, 72, 84, 96, 120, 150, 192,
    ];
    let o = order_at(bits());
    let k = ALL.iter().take_while(|&&x| x < o).count();
    &ALL[..(k + 1).min(ALL.len())]
}

/// The lower orders a last step may take at [`bits`] (up to four fifths of the order).
pub(crate) fn low_orders() -> &'static [usize] {
    const ALL: [usize; 16] = [
        8, 12, 16, 20, 24, 28, 32, 40, 48, 56, 64, 80, 96, 112, 128, 152,
    ];
    let o = order_at(bits()) * 4 / 5;
    let k = ALL.iter().take_while(|&&x| x <= o).count();
    &ALL[..k.max(1)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::Scalar;

    fn parse(s: &str) -> MpInterval {
        MpInterval::from_decimal(s, 1024).unwrap()
    }

    #[test]
    fn conversions_are_exact_and_the_precision_is_per_call() {
        let third = with_bits(256, || WideInterval::cst(1.0) / WideInterval::cst(3.0));
        let m = third.to_mp();
        // both ends are 256-bit numbers, one unit apart, around 1/3
        assert!(m.lo.significant_bits() <= 256 && m.hi.significant_bits() <= 256);
        let exact = parse("0.333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333333");
        assert!(m.lo <= exact.lo && exact.hi <= m.hi);
        assert!(m.wid_up() < 2f64.powi(-255));
        let coarse = with_bits(160, || WideInterval::cst(1.0) / WideInterval::cst(3.0));
        assert!(
            coarse.to_mp().wid_up() > 2f64.powi(-162) && coarse.to_mp().wid_up() < 2f64.powi(-158)
        );
        assert_eq!(bits(), DEFAULT_BITS);
        assert_eq!(Wide::from_mp(&third.inf().to_mp()), Some(third.inf()));
        assert_eq!(-(-third), third);
        assert_eq!((-WideInterval::cst(0.0)), WideInterval::cst(0.0));
        assert!(with_bits(1_000_000, bits) == MAX_BITS && with_bits(3, bits) == MIN_BITS);
    }

    #[test]
    fn elementary_functions_enclose_their_values_at_256_bits() {
        // sin(1), e and pi to 82 digits (independent: mpmath at 90 digits), within 1e-81
        let near = |v: &str| {
            let r = parse("1e-81");
            parse(v).sub_ref(&r).hull(&parse(v).add_ref(&r))
        };
        let sin1 = near(
            "0.8414709848078965066525023216302989996225630607983710656727517099919104043912396689",
        );
        let e = near(
            "2.718281828459045235360287471352662497757247093699959574966967627724076630353547595",
        );
        let pi = near(
            "3.141592653589793238462643383279502884197169399375105820974944592307816406286208999",
        );
        with_bits(256, || {
            let one = WideInterval::cst(1.0);
            for (x, want) in [
                (one.sin(), &sin1),
                (one.exp(), &e),
                (WideInterval::pi(), &pi),
            ] {
                let m = x.to_mp();
                assert!(want.subset(&m), "{x:?}");
                assert!(m.wid_up() < 1e-75, "{x:?}");
            }
        });
    }

    #[test]
    fn empty_and_unbounded_sets_stay_so() {
        let e = WideInterval::from_f64(f64::NAN);
        assert!(e.is_empty() && (-e).is_empty() && (e + WideInterval::cst(1.0)).is_empty());
        assert!(!e.is_finite() && WideInterval::cst(1.0).is_finite());
        let all = WideInterval::entire();
        assert!(
            all.inf().to_mp().is_infinite() && all.sup().to_mp().is_infinite() && !all.is_empty()
        );
        let q = WideInterval::cst(1.0) / all;
        assert!(q.inf().to_mp().is_infinite());
    }
}
