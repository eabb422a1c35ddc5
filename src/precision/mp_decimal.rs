//! Decimal input and output of [`Mp`] numbers, exact on the dyadic value
//! ([spec (12.2.6)](crate::spec::precision)). Only these conversions use heap big integers
//! (`num_bigint`): a decimal string is read or written once per number, never per
//! arithmetic operation.

use super::mp_float::{Mp, Round, MAX_PREC};
use num_bigint::BigUint;

/// The decimal number `(-1)^neg n 10^e` rounded to `prec` bits in direction `mode` (not
/// `Near`); `e` limited to `|e| <= 10^6` by the caller.
pub fn decimal_to_mp(neg: bool, n: &BigUint, e: i64, prec: u32, mode: Round) -> Mp {
    if n.bits() == 0 {
        return Mp::zero();
    }
    if e >= 0 {
        let v = n * BigUint::from(10u32).pow(e as u32);
        return Mp::from_parts(neg, v, 0, prec, mode);
    }
    // n 10^e = (n / 5^k) 2^-k, k = -e: q = floor(n 2^s / 5^k) has at least prec + 2 bits and
    // a nonzero remainder is kept as a sticky bit below q (12.2.6)
    let k = (-e) as u64;
    let den = BigUint::from(5u32).pow(k as u32);
    let p = prec.clamp(1, MAX_PREC) as u64;
    let s = (p + 2 + den.bits()).saturating_sub(n.bits());
    let num = n << s;
    let q = &num / &den;
    let exact = &q * &den == num;
    let man = if exact { q << 1u32 } else { (q << 1u32) + 1u32 };
    Mp::from_parts(neg, man, -(k as i64) - s as i64 - 1, prec, mode)
}

/// Parses a decimal `[+-]digits[.digits][(e|E)[+-]digits]` into sign, digits and exponent.
pub fn parse_decimal(s: &str) -> Option<(bool, BigUint, i64)> {
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
    let mut e: i64 = match exp {
        Some(t) => {
            let (eneg, digits) = match t.as_bytes().first()? {
                b'-' => (true, &t[1..]),
                b'+' => (false, &t[1..]),
                _ => (false, t),
            };
            if digits.is_empty() || digits.len() > 8 || !digits.bytes().all(|c| c.is_ascii_digit())
            {
                return None;
            }
            let v: i64 = digits.parse().ok()?;
            if eneg {
                -v
            } else {
                v
            }
        }
        None => 0,
    };
    let digits = format!("{ip}{fp}");
    let digits = digits.trim_start_matches('0');
    e -= fp.len() as i64;
    let n = if digits.is_empty() {
        BigUint::ZERO
    } else {
        if digits.len() > 100_000 {
            return None;
        }
        BigUint::parse_bytes(digits.as_bytes(), 10)?
    };
    if e.abs() > 1_000_000 {
        return None;
    }
    Some((neg, n, e))
}

/// `x` written with `digits` significant decimal digits, rounded down (`up = false`) or up,
/// as `d.ddd...e±X` (12.2.6). Infinities print as `inf` / `-inf`, zero as `0`.
pub fn to_decimal(x: &Mp, digits: usize, up: bool) -> String {
    if x.is_infinite() {
        return if x.is_negative() {
            "-inf".into()
        } else {
            "inf".into()
        };
    }
    if x.is_zero() {
        return "0".into();
    }
    let digits = digits.clamp(1, 100_000);
    // round the magnitude away from zero when the direction and the sign agree
    let away = up != x.is_negative();
    let sign = if x.is_negative() { "-" } else { "" };
    // beyond 2^(±2^16) the exact expansion is too long: a power of ten on the safe side
    // (2^(t-1) <= |x| < 2^t; log10 2 is taken 1e-12 wide of its value on each side)
    if x.top() > 1 << 16 {
        if away {
            return format!("{sign}inf");
        }
        let k = ((x.top() - 1) as f64 * (core::f64::consts::LOG10_2 - 1e-12)).floor() as i64;
        return format!("{sign}1e{}", k - 1);
    }
    if x.top() < -(1 << 16) {
        if !away {
            return "0".into();
        }
        let k = (x.top() as f64 * (core::f64::consts::LOG10_2 - 1e-12)).ceil() as i64;
        return format!("{sign}1e{}", k + 1);
    }
    // first guess of the decimal exponent F with 10^(d-1) <= |x| 10^-F < 10^d
    let mut f =
        (((x.top() - 1) as f64) * core::f64::consts::LOG10_2).floor() as i64 - (digits as i64 - 1);
    let lo = BigUint::from(10u32).pow(digits as u32 - 1);
    let hi = &lo * 10u32;
    loop {
        // |x| 10^-F = man 2^exp 10^-F = num / den exactly
        let mut num = x.mantissa();
        let mut den = BigUint::from(1u32);
        if x.exponent() >= 0 {
            num <<= x.exponent() as u64;
        } else {
            den <<= (-x.exponent()) as u64;
        }
        if f >= 0 {
            den *= BigUint::from(10u32).pow(f as u32);
        } else {
            num *= BigUint::from(10u32).pow((-f) as u32);
        }
        let q = &num / &den;
        if q >= hi {
            f += 1;
            continue;
        }
        if q < lo {
            f -= 1;
            continue;
        }
        let exact = &q * &den == num;
        let mut q = q;
        if !exact && away {
            q += 1u32;
        }
        if q == hi {
            // 99..9 rounded up to 10^d: one digit fewer
            q = lo.clone();
            f += 1;
        }
        let s = q.to_str_radix(10);
        let e10 = f + digits as i64 - 1;
        let (head, tail) = s.split_at(1);
        let tail = tail.trim_end_matches('0');
        return if tail.is_empty() {
            format!("{sign}{head}e{e10}")
        } else {
            format!("{sign}{head}.{tail}e{e10}")
        };
    }
}
