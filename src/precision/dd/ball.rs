//! Balls (midpoint-radius) of the elementary-function series and the fused dot product of the
//! Taylor convolutions ([spec (12.1.19), (12.1.21)](crate::spec::precision)).

use super::*;

/// A ball `c +- r`: a double-double centre and an f64 radius, standing for every real within
/// `r` of `c` ([spec (12.1.19)](crate::spec::precision)). The elementary functions evaluate
/// their series in balls: one error-free product or sum per operation instead of one per end.
#[derive(Clone, Copy, Debug)]
pub(in crate::precision) struct Ball {
    c: Dd,
    r: f64,
}

impl Ball {
    /// A ball containing the interval (finite, non-empty; otherwise the radius is infinite).
    pub(in crate::precision) fn from_interval(x: DdInterval) -> Ball {
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
    pub(in crate::precision) fn to_interval(self) -> DdInterval {
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
    pub(in crate::precision) fn add(self, o: Ball) -> Ball {
        let (h, l, e) = add_core(self.c, o.c);
        Ball::make(h, l, add_up(add_up(self.r, o.r), e))
    }

    /// `|ab - c_a c_b| <= |c_a| r_b + |c_b| r_a + r_a r_b`, plus the rounding of `c_a c_b`.
    #[inline(always)]
    pub(in crate::precision) fn mul(self, o: Ball) -> Ball {
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
    pub(in crate::precision) fn widen(self, rho: f64) -> Ball {
        Ball {
            c: self.c,
            r: add_up(self.r, rho),
        }
    }

    #[inline(always)]
    pub(in crate::precision) fn neg(self) -> Ball {
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
pub(in crate::precision) fn up0(x: f64) -> f64 {
    let b = x.to_bits();
    f64::from_bits(b + u64::from(b != 0))
}

/// `u (1 + 2^-50)`: at least `u (1 + u)^3`, the factor of the rounding bound of a radius
/// ([spec (12.1.21)](crate::spec::precision)).
pub(in crate::precision) const U_RAD: f64 = U * (1.0 + 1.0 / 1125899906842624.0);

/// `1 + 2^-40`: at least `(1 + u)^k` for `k <= 2^12`, the factor that bounds the rounding of
/// a sum of at most `2^12` non-negative terms each rounded at most `2^12` times
/// ([spec (12.1.21)](crate::spec::precision)).
pub(in crate::precision) const GROW: f64 = 1.0 + 1.0 / 1099511627776.0;

/// The longest sum [`dot_fused`] takes (longer ones take the chain of interval operations).
pub(in crate::precision) const DOT_MAX: u32 = 1024;

/// A centre `c1 + c2` (two doubles, not necessarily normalised), `m = |fl(c1 + c2)|` and a
/// radius `r`: every real of `x` lies within `r` of `c1 + c2`, and `|c1 + c2| <= (1 + u) m`
/// ([spec (12.1.21)](crate::spec::precision)). A point has radius 0; an empty or unbounded
/// interval has a NaN radius.
#[inline(always)]
pub(in crate::precision) fn centre_radius(x: DdInterval) -> (f64, f64, f64, f64) {
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
pub(in crate::precision) struct DotSums {
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
pub(in crate::precision) fn dot_fused(
    pairs: impl Iterator<Item = (DdInterval, DdInterval)>,
) -> Option<DdInterval> {
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
pub(in crate::precision) fn dot_chain(
    acc: DdInterval,
    neg: bool,
    pairs: impl Iterator<Item = (DdInterval, DdInterval)>,
) -> DdInterval {
    pairs.fold(
        acc,
        |s, (x, y)| if neg { s - x * y } else { x.mul_add(y, s) },
    )
}
