//! The quotient of a double-double interval by a small integer, the `1 / k` of the Taylor
//! recurrences ([spec (12.1.22)](crate::spec::precision)).

use super::*;

/// The largest divisor [`DdInterval::div_int`] divides by directly.
const DIV_INT_MAX: u32 = 1 << 20;

/// The enclosure of `x / k` for a finite `x` with `|x_h| >= 2^-900` or `x = 0`, and an
/// integer `1 <= k <= 2^20` exact in `k` ([spec (12.1.22)](crate::spec::precision)): one end
/// is `q_h + q_l` itself, the other `e` beyond it on the side of the sign of the rest.
/// `None` for a smaller or a non-finite `x`, or a rest too small for its remainder to be exact.
#[inline(always)]
fn div_int_end(x: Dd, k: f64) -> Option<DdInterval> {
    if x.hi == 0.0 {
        return Some(DdInterval::ZERO);
    }
    if !(x.hi.abs() >= SMALL && x.hi.is_finite()) {
        return None;
    }
    let qh = x.hi / k;
    // remainders of quotients rounded to nearest, exact away from underflow
    let r = (-qh).mul_add(k, x.hi);
    let (s, t) = two_sum(r, x.lo);
    let ql = s / k;
    if ql != 0.0 && ql.abs() < REST_MIN {
        return None;
    }
    let r2 = (-ql).mul_add(k, s);
    // x / k = qh + ql + (r2 + t) / k exactly; d has the sign of r2 + t
    let d = r2 + t;
    let exact = end_down(qh, ql);
    if d == 0.0 {
        return Some(DdInterval {
            lo: exact,
            hi: exact,
        });
    }
    let e = up(up(d.abs()) / k);
    let around = enclose(qh, ql, e);
    Some(if d > 0.0 {
        DdInterval {
            lo: exact,
            hi: around.hi,
        }
    } else {
        DdInterval {
            lo: around.lo,
            hi: exact,
        }
    })
}

/// `2^-960`: the smallest rest `q_l` whose remainder [`div_int_end`] takes as exact.
const REST_MIN: f64 = f64::from_bits(63 << 52);

impl DdInterval {
    /// `self / k` for a positive integer `k` (the `1 / k` of the Taylor recurrences), each
    /// end divided by the double `k` with the exact remainders of its two quotients
    /// ([spec (12.1.22)](crate::spec::precision)): one or two units in the last place of the
    /// low part wide, for a fraction of the work of the quotient of (12.1.7). `k = 0`,
    /// `k > 2^20`, and ends not finite or below `2^-900` take that quotient.
    pub fn div_int(self, k: u32) -> DdInterval {
        let kf = f64::from(k);
        if k == 1 && !self.is_empty() {
            return self;
        }
        if (1..=DIV_INT_MAX).contains(&k) {
            if self.is_point() {
                if let Some(q) = div_int_end(self.lo, kf) {
                    return q;
                }
            } else if let (Some(lo), Some(hi)) =
                (div_int_end(self.lo, kf), div_int_end(self.hi, kf))
            {
                return DdInterval {
                    lo: lo.lo,
                    hi: hi.hi,
                };
            }
        }
        self / DdInterval::point(Dd::from_f64(kf))
    }
}
