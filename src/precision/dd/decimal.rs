//! Exact decimal conversions of double-double numbers and intervals, and their printing
//! ([spec (12.1.9)](crate::spec::precision)).

use super::*;

// ---------------------------------------------------------------------------------------------
// Exact decimal conversions ([spec (12.1.9)](crate::spec::precision)).

/// A finite non-zero double as `(negative, m, e)` with `|x| = m * 2^e` exactly.
pub(in crate::precision) fn decompose(x: f64) -> (bool, u64, i64) {
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
pub(in crate::precision) fn dd_to_big(x: Dd) -> (bool, Big, i64) {
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
pub(in crate::precision) fn big_to_interval(neg: bool, q: &Big, e: i64, s: bool) -> DdInterval {
    let (mlo, mhi) = big_mag_bounds(q, e, s);
    if neg {
        DdInterval { lo: -mhi, hi: -mlo }
    } else {
        DdInterval { lo: mlo, hi: mhi }
    }
}

/// Lower and upper double-double bounds of a magnitude in `[Q, Q + s] * 2^e`.
pub(in crate::precision) fn big_mag_bounds(q: &Big, e: i64, s: bool) -> (Dd, Dd) {
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
pub(in crate::precision) fn small_big_to_dd(n: &Big, g: i32) -> Dd {
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
pub(in crate::precision) fn pow2_wide(k: i32) -> f64 {
    if k > 1023 {
        f64::INFINITY
    } else {
        pow2(k)
    }
}

/// The significant digits of a decimal read exactly; the rest only bound the value.
pub(in crate::precision) const MAX_DECIMAL_DIGITS: usize = 800;

/// `10^k` splits as `5^k 2^k`: the exact value of a decimal `±D * 10^k`, bounded outward.
pub(in crate::precision) fn decimal_to_interval(neg: bool, d: &Big, k: i64) -> DdInterval {
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
