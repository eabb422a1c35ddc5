//! The interval of the crate's answers ([spec/01-scalars.md](crate::spec::scalars), "The answers' interval"): a
//! closed set of reals `[lo, hi]` with f64 ends, as inari computes it, that prints, compares
//! and serializes as its two ends.
//!
//! The mathematics runs on `inari::Interval` (the [`crate::scalar::Scalar`] instance, the
//! tapes, the validated integrator); every public answer carries this type instead, so that
//! `{:?}` of an answer shows `[lo, hi]` and not inari's internal representation (its SIMD
//! register, lower end negated). The two convert into each other for free, both ways
//! ([`From`]), so a user who wants interval arithmetic takes `inari::Interval::from(x)`.

use std::fmt;

/// A closed interval `[lo, hi]` of reals with f64 ends (`lo <= hi`, infinite ends allowed),
/// or the empty set: an enclosure of an exact real quantity in one of the crate's answers.
///
/// The same value as an `inari::Interval` (a transparent wrapper; [`From`] both ways);
/// it offers the read-only operations a user of the answers needs and no arithmetic
/// (convert to `inari::Interval` for that).
///
/// # Printing
/// `{:?}` and `{}` both print `[lo, hi]`, each end in Rust's shortest round-trip form for
/// f64 (the `{:?}` of f64: `[0.1, 0.30000000000000004]`, `[-1.0, 2.5]`, `[-inf, 1e300]`),
/// so the printed ends read back (`str::parse::<f64>`) to the same f64; the empty set
/// prints `[empty]`. The ends are [`Interval::inf`] and [`Interval::sup`]: a zero lower end
/// is `-0.0` (`[0, 0]` prints `[-0.0, 0.0]`, IEEE 1788). Formatting flags (width, precision)
/// are ignored: a shortened end would no longer be an end of the enclosure.
///
/// # Comparing
/// `==` is equality of sets (inari's): the same two ends, or both empty.
///
/// # Serializing
/// With the `serde` feature, as the two-element array `[lo, hi]` (the form of the JSON
/// protocol); an infinite end is `null` in JSON (JSON has no infinities), read back as
/// `-inf` in the first place and `+inf` in the second. The empty set has no such form: it
/// serializes as `[null, null]` (which reads back as the whole line); no answer carries it.
#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(transparent)]
pub struct Interval(inari::Interval);

/// An enclosure computed with more than 53 bits ([spec/12-precision.md](crate::spec::precision)), as the
/// answers at such a precision carry it: each end a decimal number, the lower end rounded
/// down and the upper end rounded up, with enough significant digits to carry the precision
/// (so `inf <= x <= sup` for the exact `x`, read as exact decimals).
///
/// Serializes (feature `serde`) as the two-element array of strings `["inf", "sup"]`, the
/// form of the JSON protocol at such a precision (contract E18).
#[derive(Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DecimalInterval(
    /// The lower end: a decimal rounded down.
    pub String,
    /// The upper end: a decimal rounded up.
    pub String,
);

impl fmt::Display for DecimalInterval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}]", self.0, self.1)
    }
}

/// Interval types whose ends print as decimals rounded outward ([`DecimalInterval`]).
pub trait OutwardDecimal {
    /// The ends as decimals, the lower rounded down and the upper up, with enough digits
    /// to carry the type's precision.
    fn decimal(&self) -> DecimalInterval;
}

impl OutwardDecimal for crate::precision::dd::DdInterval {
    fn decimal(&self) -> DecimalInterval {
        let digits = crate::precision::dd::DISPLAY_DIGITS;
        DecimalInterval(self.inf_decimal(digits), self.sup_decimal(digits))
    }
}

impl Interval {
    /// The empty set.
    pub const EMPTY: Interval = Interval(inari::Interval::EMPTY);
    /// The whole real line `[-inf, +inf]`.
    pub const ENTIRE: Interval = Interval(inari::Interval::ENTIRE);

    /// The degenerate interval `[x, x]`; the whole line when `x` is not finite (never a
    /// number hidden in an interval), as [`crate::scalar::point`].
    pub fn point(x: f64) -> Interval {
        Interval(crate::scalar::point(x))
    }

    /// `[lo, hi]`, or `None` when the pair is no interval (a NaN end, `lo > hi`,
    /// `lo = +inf` or `hi = -inf`).
    pub fn try_new(lo: f64, hi: f64) -> Option<Interval> {
        inari::Interval::try_from((lo, hi)).ok().map(Interval)
    }

    /// The lower end (`-0.0` when it is zero; `+inf` for the empty set).
    pub fn inf(self) -> f64 {
        self.0.inf()
    }

    /// The upper end (`0.0` when it is zero; `-inf` for the empty set).
    pub fn sup(self) -> f64 {
        self.0.sup()
    }

    /// A float in the interval, near its middle (inari's `mid`: 0 for the whole line, the
    /// finite end's neighbour side for a half-line; NaN for the empty set).
    pub fn mid(self) -> f64 {
        self.0.mid()
    }

    /// The width `hi - lo`, rounded up (NaN for the empty set).
    pub fn wid(self) -> f64 {
        self.0.wid()
    }

    /// The radius: half the width, rounded up (NaN for the empty set).
    pub fn rad(self) -> f64 {
        self.0.rad()
    }

    /// The magnitude `max |x|` over the interval (NaN for the empty set).
    pub fn mag(self) -> f64 {
        self.0.mag()
    }

    /// The mignitude `min |x|` over the interval (NaN for the empty set).
    pub fn mig(self) -> f64 {
        self.0.mig()
    }

    /// Whether the real `x` lies in the interval (false for a NaN).
    pub fn contains(self, x: f64) -> bool {
        self.0.contains(x)
    }

    /// Whether `self` is a subset of `other` (the empty set is a subset of every set).
    /// `other` may also be an `inari::Interval` (a user's own enclosure), as in the
    /// other relations and set operations.
    pub fn subset(self, other: impl Into<Interval>) -> bool {
        self.0.subset(other.into().0)
    }

    /// Whether the two intervals have no common point.
    pub fn disjoint(self, other: impl Into<Interval>) -> bool {
        self.0.disjoint(other.into().0)
    }

    /// Whether the two intervals have a common point (`!disjoint`).
    pub fn overlaps(self, other: impl Into<Interval>) -> bool {
        !self.disjoint(other)
    }

    /// Whether this is the empty set.
    pub fn is_empty(self) -> bool {
        self.0.is_empty()
    }

    /// Whether this is the whole line `[-inf, +inf]`.
    pub fn is_entire(self) -> bool {
        self.0.is_entire()
    }

    /// Whether this is one real `[x, x]`.
    pub fn is_singleton(self) -> bool {
        self.0.is_singleton()
    }

    /// The smallest interval that contains both (their convex hull).
    pub fn convex_hull(self, other: impl Into<Interval>) -> Interval {
        Interval(self.0.convex_hull(other.into().0))
    }

    /// The common part of both (possibly empty).
    pub fn intersection(self, other: impl Into<Interval>) -> Interval {
        Interval(self.0.intersection(other.into().0))
    }
}

impl From<inari::Interval> for Interval {
    fn from(x: inari::Interval) -> Interval {
        Interval(x)
    }
}

impl From<Interval> for inari::Interval {
    fn from(x: Interval) -> inari::Interval {
        x.0
    }
}

impl fmt::Debug for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            f.write_str("[empty]")
        } else {
            write!(f, "[{:?}, {:?}]", self.0.inf(), self.0.sup())
        }
    }
}

impl fmt::Display for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

/// The answers' intervals from the computation's (free: the same value).
pub(crate) fn wrap(x: Vec<inari::Interval>) -> Vec<Interval> {
    x.into_iter().map(Interval).collect()
}

/// [`wrap`] on every row of a matrix.
pub(crate) fn wrap_rows(x: Vec<Vec<inari::Interval>>) -> Vec<Vec<Interval>> {
    x.into_iter().map(wrap).collect()
}

/// The computation's intervals from an argument's.
pub(crate) fn unwrap(x: &[Interval]) -> Vec<inari::Interval> {
    x.iter().map(|v| v.0).collect()
}

#[cfg(feature = "serde")]
impl serde::Serialize for Interval {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        (self.0.inf(), self.0.sup()).serialize(s)
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Interval {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // JSON writes an infinite end as null
        let (lo, hi) = <(Option<f64>, Option<f64>)>::deserialize(d)?;
        let (lo, hi) = (lo.unwrap_or(f64::NEG_INFINITY), hi.unwrap_or(f64::INFINITY));
        Interval::try_new(lo, hi)
            .ok_or_else(|| serde::de::Error::custom(format!("[{lo:?}, {hi:?}] is not an interval")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prints_its_ends_in_order_and_round_trip_form() {
        let x = Interval::try_new(0.1, 0.30000000000000004).unwrap();
        assert_eq!(format!("{x:?}"), "[0.1, 0.30000000000000004]");
        assert_eq!(format!("{x}"), "[0.1, 0.30000000000000004]");
        // a defect below 0: inari's own Debug prints its lower end negated
        let d = Interval::try_new(-1.00000000001e-6, -0.99999999999e-6).unwrap();
        assert_eq!(format!("{d:?}"), "[-1.00000000001e-6, -9.9999999999e-7]");
        assert_eq!(format!("{:?}", Interval::ENTIRE), "[-inf, inf]");
        assert_eq!(format!("{:?}", Interval::EMPTY), "[empty]");
        assert_eq!(format!("{:?}", vec![Interval::point(1.0)]), "[[1.0, 1.0]]");
    }

    #[test]
    fn converts_both_ways_without_change() {
        let a = crate::scalar::iv(-2.0, 3.5);
        let b: Interval = a.into();
        assert_eq!(inari::Interval::from(b), a);
        assert_eq!((b.inf(), b.sup(), b.wid(), b.mag()), (-2.0, 3.5, 5.5, 3.5));
        assert!(b.contains(0.0) && !b.contains(3.6) && !b.contains(f64::NAN));
        assert_eq!(Interval::try_new(1.0, 0.0), None);
        assert_eq!(Interval::point(f64::NAN), Interval::ENTIRE);
    }
}
