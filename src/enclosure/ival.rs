//! The interval types the validated integrator computes with ([spec/12-precision.md](crate::spec::precision)):
//! inari's intervals (53 bits, the default) and, through the same code, wider
//! significands. The integrator is written once over [`Ival`]; its steps, proofs and
//! choices are those of [spec/05-enclosure.md](crate::spec::enclosure) at every precision.

use crate::tape::{finite, Coef};
use crate::precision::dd::{Dd, DdInterval};
use crate::precision::wide::{self, Wide, WideInterval};
use inari::Interval;
use std::fmt::Debug;

/// Each interval rounded outward to f64 ends (`Ival::inf`, `Ival::sup`; the whole line
/// should those not form an interval): the f64 enclosures that the f64 evaluations of
/// (5.5'''), (5.6''') and (5.10'''') start from, and the box a refusal is worded from.
pub(super) fn rounded_to_f64<I: Ival>(v: &[I]) -> Vec<Interval> {
    v.iter().map(|x| crate::scalar::iv(x.inf(), x.sup())).collect()
}

/// An interval type for the validated integrator: a coefficient type of the Taylor
/// recurrences (the tape's `Coef`) with the set operations, the bounds and the points the
/// method needs. Implemented by the crate's interval types (inari's `Interval`,
/// [`crate::precision::dd::DdInterval`]); the choice of type is the choice of precision.
///
/// Every method that returns an interval returns one containing the real result for every
/// choice of reals in its arguments ([spec eq. (1.1)](crate::spec::scalars)); the `f64` bounds are rounded
/// in the safe direction (`inf` down, `sup`, `wid`, `mag` up). The points (`Pt`) are exact
/// data: the centres of sets, which the method only ever *chooses* ([spec 0.2](crate::spec::overview#02-the-global-promise)).
pub trait Ival: Coef + PartialEq + Debug + Send + Sync {
    /// The points of this precision (centres of sets): `f64` for inari's intervals.
    type Pt: Copy + PartialEq + Debug + Send + Sync + 'static;
    /// The interval of the answers at this precision: [`crate::Interval`] for inari's (it
    /// prints `[lo, hi]`), the type itself otherwise.
    type Public: Clone + Debug + PartialEq + Send + Sync + 'static;
    /// As an answer's interval.
    fn public(self) -> Self::Public;
    /// From an answer's interval (the same set).
    fn from_public(p: Self::Public) -> Self;
    /// `{:?}` as `[lo, hi]` (inari's own `Debug` shows its SIMD representation).
    fn readable(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result;
    /// The unit of the rounding level that tolerances are relative to: `2^-52` for 53-bit
    /// significands ([`f64::EPSILON`]), `2^(1 - bits)` in general.
    /// (A function, not a constant: a precision may be chosen at run time.)
    fn eps() -> f64;
    /// The Taylor order of the steps when none is given ([spec eq. (5.8)](crate::spec::enclosure)): more bits
    /// want a higher order.
    fn order() -> usize;
    /// The order of a span of two or three steps ([spec (5.8)](crate::spec::enclosure) (e)).
    fn short_order() -> usize;
    /// The orders tried for the variational equation, lowest first ([spec eq. (5.6)](crate::spec::enclosure)).
    fn jac_orders() -> &'static [usize];
    /// The orders tried for the variational equation when the derivative is asked to the
    /// rounding level, up to the last one whatever the state's order (spec (5.6), Theorem
    /// 5.3); `None`: [`Ival::jac_orders`] up to the state's order, as for the state.
    fn precise_jac_orders() -> Option<&'static [usize]> {
        None
    }
    /// The lower orders a last step may take instead of the flow's ([spec (5.8')](crate::spec::enclosure)).
    fn low_orders() -> &'static [usize];
    /// Whether the Taylor series over a priori boxes are tried first in inari's f64
    /// intervals ([spec (5.5''')](crate::spec::enclosure)).
    fn box_series_in_f64() -> bool {
        false
    }
    /// The field `F` (the tape `field`) at the point `m`, enclosed at a higher precision and
    /// rounded outward to this type ([spec (5.10'')](crate::spec::enclosure)); `None` when the type has no
    /// higher precision at hand or an evaluation is not proved.
    fn field_finer(field: &crate::tape::Tape, m: &[Self::Pt]) -> Option<Vec<Self>> {
        let _ = (field, m);
        None
    }
    /// The degenerate interval of a point.
    fn pt(x: Self::Pt) -> Self;
    /// A point in the interval (its midpoint, or near it), for a non-empty bounded one.
    fn mid_pt(&self) -> Self::Pt;
    /// The point nearest an f64 (exact: every f64 is a point of every precision).
    fn pt_of(x: f64) -> Self::Pt;
    /// An f64 near a point (for choices: scales and step sizes).
    fn pt_f64(x: Self::Pt) -> f64;
    /// `[lo, hi]`, or the whole line when that is no interval (as [`crate::scalar::iv`]).
    fn iv(lo: f64, hi: f64) -> Self;
    /// An f64 lower bound of the lower end (`+inf` when empty).
    fn inf(&self) -> f64;
    /// An f64 upper bound of the upper end (`-inf` when empty).
    fn sup(&self) -> f64;
    /// An f64 upper bound of the width.
    fn wid(&self) -> f64;
    /// An f64 upper bound of `max |x|`.
    fn mag(&self) -> f64;
    /// An f64 lower bound of `min |x|`.
    fn mig(&self) -> f64;
    /// The f64 midpoint, for choices only.
    fn mid(&self) -> f64 {
        Self::pt_f64(self.mid_pt())
    }
    /// Whether the real `x` is in the interval.
    fn contains(&self, x: f64) -> bool;
    /// Whether `self` is inside `other`.
    fn subset(&self, other: Self) -> bool;
    /// Whether `self` is inside the interior of `other`.
    fn interior(&self, other: Self) -> bool;
    /// The intersection (possibly empty).
    fn intersection(&self, other: Self) -> Self;
    /// The smallest interval containing both.
    fn convex_hull(&self, other: Self) -> Self;
    /// Whether empty.
    fn is_empty(&self) -> bool;
    /// The interval of the exact value of the decimal `[+-]digits[.digits][(e|E)[+-]digits]`
    /// at this precision, rounded outward; `None` for another string or a type that does not
    /// read decimals (inari's: its inputs are f64 values).
    fn from_decimal(s: &str) -> Option<Self> {
        let _ = s;
        None
    }
    /// Non-empty with finite ends.
    fn is_finite(&self) -> bool {
        self.is_finite_coef()
    }
    /// `acc + sum_j x_j y_j` (`acc - ...` when `neg`), `y_j = y[len - 1 - j]` when `rev`
    /// ([spec (1.4)](crate::spec::scalars)).
    fn dot(acc: Self, neg: bool, x: &[Self], y: &[Self], rev: bool) -> Self {
        let mut s = acc;
        let n = x.len();
        for j in 0..n {
            let yj = if rev { y[n - 1 - j] } else { y[j] };
            s = if neg { s - x[j] * yj } else { s.mul_acc(x[j], yj) };
        }
        s
    }
    /// Horner's scheme for many polynomials at once: entry `i` encloses
    /// `sum_k rows[k][i] t^k` for every `t` in `h` ([spec (1.4)](crate::spec::scalars)).
    fn horner(rows: &[&[Self]], h: Self) -> Vec<Self> {
        let Some(top) = rows.last() else {
            return Vec::new();
        };
        let mut s = top.to_vec();
        for r in rows[..rows.len() - 1].iter().rev() {
            for (si, ci) in s.iter_mut().zip(r.iter()) {
                *si = ci.mul_acc(*si, h);
            }
        }
        s
    }
    /// Row `a` times the rows `b` (`a.len() == b.len()`), appended to `out`: entry `j` is
    /// `sum_k a_k b[k][j]` ([spec (1.4)](crate::spec::scalars)).
    fn row_times(a: &[Self], b: &[&[Self]], out: &mut Vec<Self>) {
        let cols = b.first().map_or(0, |r| r.len());
        for j in 0..cols {
            let mut s = Self::zero();
            for (ak, bk) in a.iter().zip(b) {
                s = s.mul_acc(*ak, bk[j]);
            }
            out.push(s);
        }
    }
}

impl Ival for Interval {
    type Pt = f64;
    type Public = crate::Interval;
    fn public(self) -> crate::Interval {
        crate::Interval::from(self)
    }
    fn from_public(p: crate::Interval) -> Self {
        Interval::from(p)
    }
    fn readable(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        Debug::fmt(&crate::Interval::from(*self), f)
    }
    fn eps() -> f64 {
        f64::EPSILON
    }
    fn order() -> usize {
        super::orders::DEFAULT_ORDER
    }
    fn short_order() -> usize {
        super::orders::SHORT_ORDER
    }
    fn jac_orders() -> &'static [usize] {
        &super::orders::JAC_ORDERS
    }
    fn precise_jac_orders() -> Option<&'static [usize]> {
        Some(&super::orders::PRECISE_JAC_ORDERS)
    }
    fn low_orders() -> &'static [usize] {
        &super::orders::LOW_ORDERS
    }
    /// In double-double intervals, each end rounded outward to f64 (one ulp of `F` at most).
    fn field_finer(field: &crate::tape::Tape, m: &[f64]) -> Option<Vec<Self>> {
        let x: Vec<DdInterval> = m.iter().map(|v| <DdInterval as Ival>::pt(Dd::from_f64(*v))).collect();
        let f = field.eval_checked(&x)?;
        Some(
            f.iter()
                .map(|v| crate::scalar::iv(<DdInterval as Ival>::inf(v), <DdInterval as Ival>::sup(v)))
                .collect(),
        )
    }
    fn pt(x: f64) -> Self {
        crate::scalar::point(x)
    }
    fn mid_pt(&self) -> f64 {
        Interval::mid(*self)
    }
    fn pt_of(x: f64) -> f64 {
        x
    }
    fn pt_f64(x: f64) -> f64 {
        x
    }
    fn iv(lo: f64, hi: f64) -> Self {
        crate::scalar::iv(lo, hi)
    }
    fn inf(&self) -> f64 {
        Interval::inf(*self)
    }
    fn sup(&self) -> f64 {
        Interval::sup(*self)
    }
    fn wid(&self) -> f64 {
        Interval::wid(*self)
    }
    fn mag(&self) -> f64 {
        Interval::mag(*self)
    }
    fn mig(&self) -> f64 {
        Interval::mig(*self)
    }
    fn mid(&self) -> f64 {
        Interval::mid(*self)
    }
    fn contains(&self, x: f64) -> bool {
        Interval::contains(*self, x)
    }
    fn subset(&self, other: Self) -> bool {
        Interval::subset(*self, other)
    }
    fn interior(&self, other: Self) -> bool {
        Interval::interior(*self, other)
    }
    fn intersection(&self, other: Self) -> Self {
        Interval::intersection(*self, other)
    }
    fn convex_hull(&self, other: Self) -> Self {
        Interval::convex_hull(*self, other)
    }
    fn is_empty(&self) -> bool {
        Interval::is_empty(*self)
    }
    fn is_finite(&self) -> bool {
        finite(*self)
    }
    fn dot(acc: Self, neg: bool, x: &[Self], y: &[Self], rev: bool) -> Self {
        crate::dot::dot(acc, neg, x, y, rev)
    }
    fn horner(rows: &[&[Self]], h: Self) -> Vec<Self> {
        crate::dot::horner(rows, h)
    }
    fn row_times(a: &[Self], b: &[&[Self]], out: &mut Vec<Self>) {
        crate::dot::row_times(a, b, out)
    }
}

/// Double-double intervals ([spec (12.1)](crate::spec::precision)): about 106 bits, so a rounding level of
/// `2^-104` (a few units of the last place of one operation), and Taylor orders about twice
/// those of 53 bits (the step rule (5.8) aims at the same step sizes with twice the bits).
impl Ival for DdInterval {
    type Pt = Dd;
    type Public = DdInterval;
    fn public(self) -> DdInterval {
        self
    }
    fn from_public(p: DdInterval) -> Self {
        p
    }
    fn readable(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        Debug::fmt(self, f)
    }
    fn eps() -> f64 {
        f64::EPSILON * f64::EPSILON
    }
    fn order() -> usize {
        40
    }
    fn short_order() -> usize {
        50
    }
    fn jac_orders() -> &'static [usize] {
        &[3, 5, 8, 12, 16, 20, 26, 32, 40]
    }
    fn low_orders() -> &'static [usize] {
        &[8, 12, 16, 20, 24, 28, 32]
    }
    fn pt(x: Dd) -> Self {
        DdInterval::point(x)
    }
    fn mid_pt(&self) -> Dd {
        DdInterval::mid(*self)
    }
    fn pt_of(x: f64) -> Dd {
        Dd::from_f64(x)
    }
    fn pt_f64(x: Dd) -> f64 {
        x.to_f64()
    }
    fn iv(lo: f64, hi: f64) -> Self {
        DdInterval::from_f64_pair(lo, hi).unwrap_or(DdInterval::ENTIRE)
    }
    fn inf(&self) -> f64 {
        self.inf_f64()
    }
    fn sup(&self) -> f64 {
        self.sup_f64()
    }
    fn wid(&self) -> f64 {
        self.wid_up()
    }
    fn mag(&self) -> f64 {
        self.mag_up()
    }
    fn mig(&self) -> f64 {
        self.mig_down()
    }
    fn contains(&self, x: f64) -> bool {
        self.contains_f64(x)
    }
    fn subset(&self, other: Self) -> bool {
        DdInterval::subset(*self, other)
    }
    fn interior(&self, other: Self) -> bool {
        DdInterval::interior(*self, other)
    }
    fn intersection(&self, other: Self) -> Self {
        DdInterval::intersection(*self, other)
    }
    fn convex_hull(&self, other: Self) -> Self {
        self.hull(other)
    }
    fn from_decimal(s: &str) -> Option<Self> {
        DdInterval::from_decimal(s)
    }
    fn is_empty(&self) -> bool {
        DdInterval::is_empty(*self)
    }
}

/// Intervals of more than 106 bits ([spec (12.3)](crate::spec::precision)), at the precision in
/// force on the thread ([`wide::with_bits`]): a rounding level of `2^(1 - bits)` and the order
/// `3 bits / 8` ([`wide::order_at`]).
impl Ival for WideInterval {
    type Pt = Wide;
    type Public = WideInterval;
    fn public(self) -> WideInterval {
        self
    }
    fn from_public(p: WideInterval) -> Self {
        p
    }
    fn readable(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        Debug::fmt(self, f)
    }
    fn eps() -> f64 {
        // exact: 2^-511 at most 512 bits is a normal double
        2f64.powi(1 - wide::bits() as i32)
    }
    fn order() -> usize {
        wide::order_at(wide::bits())
    }
    fn short_order() -> usize {
        wide::order_at(wide::bits()) * 5 / 4
    }
    fn jac_orders() -> &'static [usize] {
        wide::jac_orders()
    }
    fn low_orders() -> &'static [usize] {
        wide::low_orders()
    }
    fn box_series_in_f64() -> bool {
        true
    }
    fn pt(x: Wide) -> Self {
        WideInterval::point(x)
    }
    fn mid_pt(&self) -> Wide {
        WideInterval::mid(self)
    }
    fn pt_of(x: f64) -> Wide {
        Wide::from_f64(x).unwrap_or(Wide::ZERO)
    }
    fn pt_f64(x: Wide) -> f64 {
        x.to_f64()
    }
    fn iv(lo: f64, hi: f64) -> Self {
        match (Wide::from_f64(lo), Wide::from_f64(hi)) {
            (Some(l), Some(h)) if lo <= hi && lo < f64::INFINITY && hi > f64::NEG_INFINITY => {
                WideInterval::point(l).hull(&WideInterval::point(h))
            }
            _ => WideInterval::entire(),
        }
    }
    fn inf(&self) -> f64 {
        self.inf_f64()
    }
    fn sup(&self) -> f64 {
        self.sup_f64()
    }
    fn wid(&self) -> f64 {
        self.wid_up()
    }
    fn mag(&self) -> f64 {
        self.mag_up()
    }
    fn mig(&self) -> f64 {
        self.mig_down()
    }
    fn contains(&self, x: f64) -> bool {
        self.contains_f64(x)
    }
    fn subset(&self, other: Self) -> bool {
        WideInterval::subset(self, &other)
    }
    fn interior(&self, other: Self) -> bool {
        WideInterval::interior(self, &other)
    }
    fn intersection(&self, other: Self) -> Self {
        WideInterval::intersection(self, &other)
    }
    fn convex_hull(&self, other: Self) -> Self {
        self.hull(&other)
    }
    fn from_decimal(s: &str) -> Option<Self> {
        WideInterval::from_decimal(s)
    }
    fn is_empty(&self) -> bool {
        WideInterval::is_empty(self)
    }
}
