//! Double-double intervals: outward-rounded ends, the point kernels with their error bounds,
//! and the interval operations ([spec (12.1.3)-(12.1.8)](crate::spec::precision)).

use super::*;

/// Lower end `h + l` from doubles with `h + l` exactly its value (TwoSum, exact); a sum that
/// overflows is `>= 2^1023` in magnitude, so `f64::MAX` (positive) or `-inf` (negative) bounds it
/// from below.
#[inline(always)]
pub(in crate::precision) fn end_down(h: f64, l: f64) -> Dd {
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
pub(in crate::precision) fn end_up(h: f64, l: f64) -> Dd {
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
pub(in crate::precision) fn enclose(h: f64, l: f64, e: f64) -> DdInterval {
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
pub(in crate::precision) fn next_up_fast(x: f64) -> f64 {
    let y = x + 0.0;
    let b = y.to_bits();
    let step = if y >= 0.0 { 1u64 } else { u64::MAX };
    f64::from_bits(b.wrapping_add(step))
}

/// The enclosure of a real known to be at least `2^1023` in magnitude with the sign of `h`.
#[inline(never)]
pub(in crate::precision) fn overflow(h: f64) -> DdInterval {
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
pub(in crate::precision) fn add_core(x: Dd, y: Dd) -> (f64, f64, f64) {
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
pub(in crate::precision) fn add_pt(x: Dd, y: Dd) -> DdInterval {
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
pub(in crate::precision) fn mul_core(x: Dd, y: Dd) -> (f64, f64, f64) {
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
pub(in crate::precision) fn mul_pt(x: Dd, y: Dd) -> DdInterval {
    let (h, l, e) = mul_core(x, y);
    if e == 0.0 && h.is_finite() {
        let d = Dd { hi: h, lo: l };
        return DdInterval { lo: d, hi: d };
    }
    enclose(h, l, e)
}

/// An upper bound of `a + b` for `a, b >= 0` (exact when one is 0).
#[inline(always)]
pub(in crate::precision) fn add_up(a: f64, b: f64) -> f64 {
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
pub(in crate::precision) fn mul_up(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        0.0
    } else {
        up(a * b)
    }
}

/// `2^-969`: a product of two doubles at least this large has an exact FMA error term (its
/// error is a multiple of `2^-1073`).
pub(in crate::precision) const EXACT_PRODUCT: f64 = f64::from_bits(54 << 52);

/// `[a, b] / [c, d]` in f64 with outward rounding (`c, d` of one strict sign, all finite).
#[inline]
pub(in crate::precision) fn div_f64_iv(a: f64, b: f64, c: f64, d: f64) -> (f64, f64) {
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
pub(in crate::precision) fn div_pt(x: Dd, y: Dd) -> DdInterval {
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
pub(in crate::precision) const SMALL: f64 = f64::from_bits(123 << 52);

/// The exponent `k` of a finite non-zero double: `2^k <= |x| < 2^(k+1)`.
#[inline]
pub(in crate::precision) fn exponent(x: f64) -> i32 {
    let b = x.to_bits() & 0x7fff_ffff_ffff_ffff;
    let e = (b >> 52) as i32;
    if e == 0 {
        63 - b.leading_zeros() as i32 - 1074
    } else {
        e - 1023
    }
}

#[inline]
pub(in crate::precision) fn div_pt_normal(x: Dd, y: Dd) -> DdInterval {
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
pub(in crate::precision) fn add_pt_iv(x: Dd, p: DdInterval) -> DdInterval {
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
pub(in crate::precision) fn sqrt_pt(x: Dd) -> DdInterval {
    if x.hi < SMALL {
        // sqrt(x) = sqrt(x 2^2k) 2^-k, the scaling up exact.
        let k = -exponent(x.hi) / 2;
        return sqrt_pt_normal(x.scale_pow2_up(2 * k)).scale_pow2(-k);
    }
    sqrt_pt_normal(x)
}

pub(in crate::precision) fn sqrt_pt_normal(x: Dd) -> DdInterval {
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
pub(in crate::precision) fn mul2(x: f64, k: i32, down: bool) -> f64 {
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
pub(in crate::precision) fn mul2_step(x: f64, k: i32, down: bool) -> f64 {
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
pub(in crate::precision) fn pow_nonneg(x: DdInterval, mut n: u32) -> DdInterval {
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
pub(in crate::precision) fn dmin(a: Dd, b: Dd) -> Dd {
    if b < a {
        b
    } else {
        a
    }
}

#[inline(always)]
pub(in crate::precision) fn dmax(a: Dd, b: Dd) -> Dd {
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
pub(in crate::precision) fn mul_end(x: Dd, y: Dd) -> DdInterval {
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
pub(in crate::precision) fn div_end(x: Dd, y: Dd) -> DdInterval {
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
