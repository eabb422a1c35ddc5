//! The scalar abstraction: mechanics is written once over `S: Scalar` ([spec/01-scalars.md](crate::spec::scalars)).
//!
//! Instances: `f64` (fast float schemes), `inari::Interval` (rigorous point evaluation; its
//! elementary functions are those of [`crate::elementary`], [spec (1.3)](crate::spec::scalars)),
//! [`Dual`] (forward-mode derivatives in several directions, nestable) and
//! a tracer (`tape::Tracer`) (records the computation once so that it can be replayed over
//! Taylor series of intervals).
//!
//! Every constant enters through [`Scalar::cst`], which takes an exact `f64`: the interval
//! instance turns it into the degenerate interval `[c, c]`, so no rounding happens on input.

use crate::elementary;
use inari::Interval;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A commutative ring with division and the analytic elementary functions scenes and scene
/// files use ([spec/01-scalars.md](crate::spec::scalars)): sin, cos, sqrt, exp, ln, atan, sinh, cosh, and from them
/// tan = sin / cos and tanh = sinh / cosh; the constant pi.
///
/// The laws are those of the real numbers; an implementation may return a superset
/// (intervals) but never a value that misses the real result ([spec eq. (1.1)](crate::spec::scalars)).
pub trait Scalar:
    Clone
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The exact real number `c` (a finite f64).
    fn cst(c: f64) -> Self;
    /// The sine (argument in radians).
    fn sin(&self) -> Self;
    /// The cosine (argument in radians).
    fn cos(&self) -> Self;
    /// The square root, defined for arguments `>= 0` (over tapes, checked `> 0`: [spec (2.8)](crate::spec::taylor)).
    fn sqrt(&self) -> Self;
    /// The exponential.
    fn exp(&self) -> Self;
    /// The natural logarithm.
    fn ln(&self) -> Self;
    /// The arctangent, with values in `(-pi/2, pi/2)`.
    fn atan(&self) -> Self;
    /// The hyperbolic sine.
    fn sinh(&self) -> Self;
    /// The hyperbolic cosine.
    fn cosh(&self) -> Self;
    /// The real number pi (an enclosure of it for intervals: it is not an f64).
    fn pi() -> Self;
    /// The tangent, `sin / cos` unless an instance has its own.
    fn tan(&self) -> Self {
        self.sin() / self.cos()
    }
    /// The hyperbolic tangent, `sinh / cosh` unless an instance has its own.
    fn tanh(&self) -> Self {
        self.sinh() / self.cosh()
    }
    /// The exact number 0.
    fn zero() -> Self {
        Self::cst(0.0)
    }
    /// The exact number 1.
    fn one() -> Self {
        Self::cst(1.0)
    }
    /// The square `self * self`.
    fn sqr(&self) -> Self {
        self.clone() * self.clone()
    }
}

/// Double-double intervals ([spec (12.1)](crate::spec::precision)): every operation outward rounded.
impl Scalar for crate::precision::dd::DdInterval {
    fn cst(c: f64) -> Self {
        Self::from_f64(c)
    }
    fn sin(&self) -> Self {
        Self::sin(*self)
    }
    fn cos(&self) -> Self {
        Self::cos(*self)
    }
    fn sqrt(&self) -> Self {
        Self::sqrt(*self)
    }
    fn exp(&self) -> Self {
        Self::exp(*self)
    }
    fn ln(&self) -> Self {
        Self::ln(*self)
    }
    fn atan(&self) -> Self {
        Self::atan(*self)
    }
    fn sinh(&self) -> Self {
        Self::sinh(*self)
    }
    fn cosh(&self) -> Self {
        Self::cosh(*self)
    }
    fn pi() -> Self {
        Self::pi()
    }
    fn tan(&self) -> Self {
        Self::tan(*self)
    }
    fn tanh(&self) -> Self {
        Self::tanh(*self)
    }
    fn sqr(&self) -> Self {
        Self::sqr(*self)
    }
}

impl Scalar for f64 {
    fn cst(c: f64) -> Self {
        c
    }
    fn sin(&self) -> Self {
        f64::sin(*self)
    }
    fn cos(&self) -> Self {
        f64::cos(*self)
    }
    fn sqrt(&self) -> Self {
        f64::sqrt(*self)
    }
    fn exp(&self) -> Self {
        f64::exp(*self)
    }
    fn ln(&self) -> Self {
        f64::ln(*self)
    }
    fn atan(&self) -> Self {
        f64::atan(*self)
    }
    fn sinh(&self) -> Self {
        f64::sinh(*self)
    }
    fn cosh(&self) -> Self {
        f64::cosh(*self)
    }
    fn pi() -> Self {
        std::f64::consts::PI
    }
}

impl Scalar for Interval {
    fn cst(c: f64) -> Self {
        point(c)
    }
    fn sin(&self) -> Self {
        elementary::sin(*self)
    }
    fn cos(&self) -> Self {
        elementary::cos(*self)
    }
    fn sqrt(&self) -> Self {
        Interval::sqrt(*self)
    }
    fn exp(&self) -> Self {
        elementary::exp(*self)
    }
    fn ln(&self) -> Self {
        elementary::ln(*self)
    }
    fn atan(&self) -> Self {
        elementary::atan(*self)
    }
    fn sinh(&self) -> Self {
        elementary::sinh(*self)
    }
    fn cosh(&self) -> Self {
        elementary::cosh(*self)
    }
    fn pi() -> Self {
        elementary::pi()
    }
    fn tan(&self) -> Self {
        elementary::tan(*self)
    }
    fn tanh(&self) -> Self {
        elementary::tanh(*self)
    }
    fn sqr(&self) -> Self {
        Interval::sqr(*self)
    }
}

/// The degenerate interval `[c, c]`; ENTIRE when `c` is not finite (never hidden as a number).
pub fn point(c: f64) -> Interval {
    Interval::try_from((c, c)).unwrap_or(Interval::ENTIRE)
}

/// `[lo, hi]` (an infinite end is kept: `iv(f64::NEG_INFINITY, 1.0)` is `[-inf, 1]`), or
/// ENTIRE when the pair is no interval (a NaN, `lo > hi`, `lo = +inf` or `hi = -inf`).
pub fn iv(lo: f64, hi: f64) -> Interval {
    Interval::try_from((lo, hi)).unwrap_or(Interval::ENTIRE)
}

/// Forward-mode dual number `v + sum_j d_j eps_j` with `eps_i eps_j = 0` ([spec eq. (1.2)](crate::spec::scalars)).
///
/// The number of directions is set by the values that enter a computation; a constant has
/// none and broadcasts. Nesting (`Dual<Dual<S>>`) gives mixed second derivatives.
#[derive(Clone, Debug)]
pub struct Dual<S> {
    /// The value `v`.
    pub v: S,
    /// The tangents `d_j`, one per direction (empty for a constant).
    pub d: Vec<S>,
}

impl<S: Scalar> Dual<S> {
    /// The variable `v` seeded with direction `j` of `n`.
    pub fn var(v: S, j: usize, n: usize) -> Self {
        let d = (0..n)
            .map(|i| if i == j { S::one() } else { S::zero() })
            .collect();
        Dual { v, d }
    }
    /// A value with given tangents.
    pub fn new(v: S, d: Vec<S>) -> Self {
        Dual { v, d }
    }
    /// Derivative in direction `j` (zero for a constant).
    pub fn der(&self, j: usize) -> S {
        self.d.get(j).cloned().unwrap_or_else(S::zero)
    }
    fn map_d(&self, f: impl Fn(&S) -> S) -> Vec<S> {
        self.d.iter().map(f).collect()
    }
}

fn zip_d<S: Scalar>(a: &[S], b: &[S], f: impl Fn(S, S) -> S) -> Vec<S> {
    let n = a.len().max(b.len());
    (0..n)
        .map(|i| {
            let x = a.get(i).cloned().unwrap_or_else(S::zero);
            let y = b.get(i).cloned().unwrap_or_else(S::zero);
            f(x, y)
        })
        .collect()
}

impl<S: Scalar> Add for Dual<S> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual {
            v: self.v + o.v,
            d: zip_d(&self.d, &o.d, |x, y| x + y),
        }
    }
}
impl<S: Scalar> Sub for Dual<S> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual {
            v: self.v - o.v,
            d: zip_d(&self.d, &o.d, |x, y| x - y),
        }
    }
}
impl<S: Scalar> Mul for Dual<S> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.v.clone(), o.v.clone());
        Dual {
            v: self.v * o.v,
            d: zip_d(&self.d, &o.d, |x, y| x * b.clone() + a.clone() * y),
        }
    }
}
impl<S: Scalar> Div for Dual<S> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        // (a/b)' = (a' - (a/b) b') / b
        let w = self.v.clone() / o.v.clone();
        let (wc, b) = (w.clone(), o.v.clone());
        Dual {
            v: w,
            d: zip_d(&self.d, &o.d, |x, y| (x - wc.clone() * y) / b.clone()),
        }
    }
}
impl<S: Scalar> Neg for Dual<S> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual {
            v: -self.v,
            d: self.d.into_iter().map(|x| -x).collect(),
        }
    }
}
impl<S: Scalar> Scalar for Dual<S> {
    fn cst(c: f64) -> Self {
        Dual {
            v: S::cst(c),
            d: Vec::new(),
        }
    }
    fn sin(&self) -> Self {
        let c = self.v.cos();
        Dual {
            v: self.v.sin(),
            d: self.map_d(|x| x.clone() * c.clone()),
        }
    }
    fn cos(&self) -> Self {
        let s = self.v.sin();
        Dual {
            v: self.v.cos(),
            d: self.map_d(|x| -(x.clone() * s.clone())),
        }
    }
    fn sqrt(&self) -> Self {
        let w = self.v.sqrt();
        let two_w = w.clone() + w.clone();
        Dual {
            v: w,
            d: self.map_d(|x| x.clone() / two_w.clone()),
        }
    }
    fn exp(&self) -> Self {
        let w = self.v.exp();
        Dual {
            d: self.map_d(|x| x.clone() * w.clone()),
            v: w,
        }
    }
    fn ln(&self) -> Self {
        Dual {
            v: self.v.ln(),
            d: self.map_d(|x| x.clone() / self.v.clone()),
        }
    }
    fn atan(&self) -> Self {
        let g = S::one() + self.v.sqr();
        Dual {
            v: self.v.atan(),
            d: self.map_d(|x| x.clone() / g.clone()),
        }
    }
    fn sinh(&self) -> Self {
        let c = self.v.cosh();
        Dual {
            v: self.v.sinh(),
            d: self.map_d(|x| x.clone() * c.clone()),
        }
    }
    fn cosh(&self) -> Self {
        let s = self.v.sinh();
        Dual {
            v: self.v.cosh(),
            d: self.map_d(|x| x.clone() * s.clone()),
        }
    }
    fn pi() -> Self {
        Dual {
            v: S::pi(),
            d: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dual_derivatives_of_a_product_quotient_and_sine() {
        // f(x, y) = sin(x) * y / (1 + y^2) at (0.3, 2.0)
        let x = Dual::var(0.3f64, 0, 2);
        let y = Dual::var(2.0f64, 1, 2);
        let f = x.sin() * y.clone() / (Dual::one() + y.sqr());
        let fx = 0.3f64.cos() * 2.0 / 5.0;
        let fy = 0.3f64.sin() * (1.0 - 4.0) / 25.0;
        assert!((f.der(0) - fx).abs() < 1e-15);
        assert!((f.der(1) - fy).abs() < 1e-15);
    }

    #[test]
    fn interval_constants_are_exact_and_non_finite_is_entire() {
        let c = point(0.1);
        assert_eq!(c.inf(), 0.1);
        assert_eq!(c.sup(), 0.1);
        assert!(point(f64::NAN).is_entire());
        assert!(point(f64::INFINITY).is_entire());
    }
}
