//! Rigorous elementary functions of double-double intervals ([spec (12.1.10)–(12.1.16)](crate::spec::precision)):
//! exp, ln, sin, cos, tan, atan, sinh, cosh, tanh, asinh and the constant pi.
//!
//! Each point value is an interval computation: an exact or enclosed argument reduction, a
//! truncated Taylor (or atanh) series evaluated by Horner's scheme in [`DdInterval`] arithmetic
//! (so every rounding is outward), and the series remainder added as an interval `[-rho, rho]`
//! with `rho` an upward-rounded f64 bound. Interval arguments follow from monotone pieces; the
//! extrema of sin and cos and the poles of tan are located from the exact reduction of both
//! ends. Conventions are inari's: empty maps to empty; ln is restricted to its domain
//! (`ln([-1, 4]) = [-inf, ln 4]`, `ln([-2, 0])` is empty); an end that overflows is infinite.
//!
//! # Containment
//! For every function `f` here and every interval `x`, `f(x)` contains `f(t)` for every real
//! `t` in `x` where `f` is defined.

use super::dd::{big_to_interval, dd_to_big, pow2, two_prod, Ball, Dd, DdInterval};
use super::dd_big::Big;
use std::sync::OnceLock;

// Constants: for c in {pi, pi/2, ln 2}, HI + LO_DOWN <= c <= HI + LO_UP (checked against
// mpmath by tests/data/dd_reference.py, whose table tests/it/precision_dd.rs reads).
const PI_HI: f64 = f64::from_bits(0x400921fb54442d18);
const PI_LO_DOWN: f64 = f64::from_bits(0x3ca1a62633145c06);
const PI_LO_UP: f64 = f64::from_bits(0x3ca1a62633145c07);
const FRAC_PI_2_HI: f64 = f64::from_bits(0x3ff921fb54442d18);
const FRAC_PI_2_LO_DOWN: f64 = f64::from_bits(0x3c91a62633145c06);
const FRAC_PI_2_LO_UP: f64 = f64::from_bits(0x3c91a62633145c07);
const LN2_HI: f64 = f64::from_bits(0x3fe62e42fefa39ef);
const LN2_LO_DOWN: f64 = f64::from_bits(0x3c7abc9e3b39803f);
const LN2_LO_UP: f64 = f64::from_bits(0x3c7abc9e3b398040);
/// ln 2 as a triple-double `C1 + C2 + C3` with `|ln 2 - (C1 + C2 + C3)| <= 2^-140`; `C1` and
/// `C2` have 42 significant bits, so `k C1` and `k C2` are exact for `|k| < 2^11` (Cody and
/// Waite reduction, [spec (12.1.10)](crate::spec::precision)).
const LN2_C1: f64 = f64::from_bits(0x3fe62e42fefa3800);
const LN2_C2: f64 = f64::from_bits(0x3d2ef35793c76000);
const LN2_C3: f64 = f64::from_bits(0x3a8cc01f97b57a08);
const LN2_C_ERR: f64 = f64::from_bits(883 << 52); // 2^-140
/// `floor(2/pi * 2^1500)`, 47 limbs of 32 bits, least significant first (Payne and Hanek
/// reduction, [spec (12.1.12)](crate::spec::precision)).
const TWO_OVER_PI_BITS: u64 = 1500;
const TWO_OVER_PI: [u32; 47] = [
    0x10606155, 0x04d73273, 0x08dffd88, 0xf14a0684, 0x86599855, 0x15ee61b0, 0xda9e3916, 0x09af4361,
    0xbf0cfbc2, 0x6fc7b6ba, 0x85603304, 0x11f8d5d0, 0xa6bfb5fb, 0x78a5292e, 0xb3d0739f, 0x7ebe5f17,
    0xd7527bac, 0x69e5fea2, 0x74f463f6, 0xf27cb09b, 0xf6d367ec, 0xb5a0a6d1, 0xfef2f118, 0xfde05980,
    0xb1ff897f, 0xbbdf9283, 0x49c845f8, 0x9835339f, 0x13991d63, 0x6b45f7e4, 0x4e99c702, 0x52ebb448,
    0xee88235f, 0xcb129a73, 0xcfe1deb1, 0xa09d1921, 0x006492ee, 0xa424dd2e, 0x1b7246e3, 0xbdebbc56,
    0x1fe5163a, 0x93c43904, 0x0db62959, 0x1f534ddc, 0x9fc2757d, 0xe4e44152, 0x0a2f9836,
];

/// `[lo, hi]` from the pair of bounds of a constant.
const fn constant(hi: f64, lo_down: f64, lo_up: f64) -> DdInterval {
    DdInterval {
        lo: Dd::from_parts(hi, lo_down),
        hi: Dd::from_parts(hi, lo_up),
    }
}

const PI: DdInterval = constant(PI_HI, PI_LO_DOWN, PI_LO_UP);
const FRAC_PI_2: DdInterval = constant(FRAC_PI_2_HI, FRAC_PI_2_LO_DOWN, FRAC_PI_2_LO_UP);
const LN2: DdInterval = constant(LN2_HI, LN2_LO_DOWN, LN2_LO_UP);

/// `1/n!` for `n <= 40`, enclosed by interval division `[1/n!] = [1/(n-1)!] / n`, as balls
/// ([spec (12.1.10)](crate::spec::precision)).
fn inv_fact() -> &'static [Ball; 41] {
    static T: OnceLock<[Ball; 41]> = OnceLock::new();
    T.get_or_init(|| {
        let mut iv = DdInterval::ONE;
        let mut t = [Ball::from_interval(iv); 41];
        for (n, c) in t.iter_mut().enumerate().skip(1) {
            iv = iv / DdInterval::from_f64(n as f64);
            *c = Ball::from_interval(iv);
        }
        t
    })
}

/// `1/(2n+1)` for `n <= 30`, enclosed, as balls.
fn inv_odd() -> &'static [Ball; 31] {
    static T: OnceLock<[Ball; 31]> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = [Ball::from_interval(DdInterval::ONE); 31];
        for (n, c) in t.iter_mut().enumerate() {
            *c = Ball::from_interval(DdInterval::ONE / DdInterval::from_f64((2 * n + 1) as f64));
        }
        t
    })
}

/// `[-r, r]` for a finite `r >= 0`.
fn sym(r: f64) -> DdInterval {
    DdInterval {
        lo: Dd::from_f64(-r),
        hi: Dd::from_f64(r),
    }
}

/// An upper bound of `m^n c` for `m, c >= 0` (every product rounded up; exactly 0 for `m = 0`).
fn rem_bound(m: f64, n: u32, c: f64) -> f64 {
    if m == 0.0 {
        return 0.0;
    }
    (pow_up(m, n) * c).next_up()
}

/// An upper bound of `m^n` for `m >= 0` (every product rounded up).
fn pow_up(m: f64, n: u32) -> f64 {
    let mut r = 1.0f64;
    for _ in 0..n {
        r = (r * m).next_up();
    }
    r
}

/// `sum_{n <= nmax} coef(n) s^n` by Horner's scheme in ball arithmetic (12.1.19).
fn horner(s: Ball, nmax: usize, coef: impl Fn(usize) -> Ball) -> Ball {
    let mut acc = coef(nmax);
    for n in (0..nmax).rev() {
        acc = acc.mul(s).add(coef(n));
    }
    acc
}

fn alt(n: usize, c: Ball) -> Ball {
    if n % 2 == 1 {
        c.neg()
    } else {
        c
    }
}

// ---------------------------------------------------------------------------------------------
// exp ([spec (12.1.10)](crate::spec::precision)).

/// Degree of the exp series on `|r| <= 0.35`: `1.5 * 0.35^25 / 25! < 2^-120`.
const EXP_DEG: usize = 24;

/// `exp(r)` for an interval `r` with `|r| <= 0.36`: Taylor polynomial of degree 24 plus the
/// Lagrange remainder `e^|r| |r|^25 / 25!` (`<= 1.5 |r|^25 * 6.45e-26`).
fn exp_kernel(r: DdInterval) -> DdInterval {
    let t = inv_fact();
    let p = horner(Ball::from_interval(r), EXP_DEG, |n| t[n]);
    let m = r.mag_up();
    // e^m 1/25! <= 1.0e-25 for m <= 0.36; otherwise e^m <= 3^ceil(m).
    let c = if m <= 0.36 {
        1.0e-25
    } else {
        (pow_up(3.0, m.ceil().min(1000.0) as u32) * 6.5e-26).next_up()
    };
    let rho = rem_bound(m, EXP_DEG as u32 + 1, c);
    p.widen(rho).to_interval()
}

/// `2^s exp(x)` for a point `x` (`|s| <= 2`).
fn exp_scaled_pt(x: Dd, s: i32) -> DdInterval {
    let xh = x.hi();
    let shifted = xh + s as f64 * std::f64::consts::LN_2;
    if shifted > 709.8 {
        // 2^s e^x > e^709.8 > f64::MAX.
        return DdInterval {
            lo: Dd::MAX,
            hi: Dd::INFINITY,
        };
    }
    if shifted < -745.2 {
        // 2^s e^x < e^-745.2 < 2^-1074.
        return DdInterval {
            lo: Dd::ZERO,
            hi: Dd::from_f64(pow2(-1074)),
        };
    }
    if xh == 0.0 {
        return DdInterval::ONE.scale_pow2(s);
    }
    let k = (xh * std::f64::consts::LOG2_E).round();
    // r = x - k C1 - k C2 - k C3 - k delta: k C1, k C2 exact doubles, k C3 an exact pair.
    let mut r = DdInterval::point(x) + DdInterval::from_f64(-k * LN2_C1);
    r = r + DdInterval::from_f64(-k * LN2_C2);
    let (p, e) = two_prod(-k, LN2_C3);
    r = r + DdInterval::point(Dd::new(p, e));
    r = r + sym(k.abs() * LN2_C_ERR);
    exp_kernel(r).scale_pow2(k as i32 + s)
}

impl DdInterval {
    /// `e^x` ([spec (12.1.10)](crate::spec::precision)); an end that overflows is `+inf`.
    pub fn exp(self) -> DdInterval {
        self.exp_scaled(0)
    }

    /// `2^s e^x`, increasing.
    fn exp_scaled(self, s: i32) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let lo = if self.lo.is_finite() {
            exp_scaled_pt(self.lo, s).lo
        } else {
            Dd::ZERO
        };
        let hi = if self.hi.is_finite() {
            exp_scaled_pt(self.hi, s).hi
        } else {
            Dd::INFINITY
        };
        DdInterval { lo, hi }
    }
}

// ---------------------------------------------------------------------------------------------
// ln ([spec (12.1.11)](crate::spec::precision)).

/// Degree in `s^2` of the atanh series: `0.1716^44 / (45 * 0.97) < 2^-117`.
const LN_DEG: usize = 21;

/// `ln(1 + y)` for an interval `y` with `1 + y` in `[1/sqrt2, sqrt2]`:
/// `2 atanh(s)`, `s = y / (2 + y)`, `|s| <= 0.1716`, series `2 s sum s^2n/(2n+1)` with the
/// remainder `|s|^(2N+2) / ((2N+3)(1 - s^2))` relative to `2 s`.
fn ln1p_kernel(y: DdInterval) -> DdInterval {
    let s = y / (y + DdInterval::from_f64(2.0));
    let sb = Ball::from_interval(s);
    let t = inv_odd();
    let p = horner(Ball::from_interval(s.sqr()), LN_DEG, |n| t[n]);
    let m = s.mag_up();
    // 1 - s^2 rounded down; not positive only for arguments far outside the intended range.
    let den = (1.0 - (m * m).next_up()).next_down();
    if den.is_nan() || den <= 0.0 {
        return DdInterval::ENTIRE;
    }
    let rho = (rem_bound(
        m,
        2 * LN_DEG as u32 + 2,
        1.0 / (2 * LN_DEG + 3) as f64 * (1.0 + 1e-15),
    ) / den)
        .next_up();
    sb.mul(p.widen(rho)).to_interval().scale_pow2(1)
}

/// `ln x` for a finite point `x > 0`: `x = 2^k m` with `m` in `[1/sqrt2, sqrt2]`,
/// `ln x = k ln2 + ln(1 + (m - 1))`.
fn ln_pt(x: Dd) -> DdInterval {
    if x == Dd::ONE {
        return DdInterval::ZERO;
    }
    // x.hi = mant 2^k with mant in [1, 2), exactly (a subnormal is first scaled by 2^600).
    let (h, k0) = if x.hi().abs() < f64::MIN_POSITIVE {
        (x.hi() * pow2(600), -600)
    } else {
        (x.hi(), 0)
    };
    let mut k = ((h.to_bits() >> 52) & 0x7ff) as i32 - 1023 + k0;
    let mant = f64::from_bits((h.to_bits() & ((1u64 << 52) - 1)) | (1023u64 << 52));
    if mant > std::f64::consts::SQRT_2 {
        k += 1;
    }
    let m = DdInterval::point(x).scale_pow2(-k);
    let y = m - DdInterval::ONE;
    let l = ln1p_kernel(y);
    if k == 0 {
        l
    } else {
        DdInterval::from_f64(k as f64) * LN2 + l
    }
}

impl DdInterval {
    /// Natural logarithm over the positive part: `ln([-1, 4]) = [-inf, ln 4]`, `ln([0, 0])` and
    /// `ln([-2, 0])` are empty, as inari ([spec (12.1.11)](crate::spec::precision)).
    pub fn ln(self) -> DdInterval {
        if self.is_empty() || self.hi.hi() <= 0.0 {
            return DdInterval::EMPTY;
        }
        let lo = if self.lo.hi() <= 0.0 {
            Dd::NEG_INFINITY
        } else {
            ln_pt(self.lo).lo
        };
        let hi = if self.hi.is_finite() {
            ln_pt(self.hi).hi
        } else {
            Dd::INFINITY
        };
        DdInterval { lo, hi }
    }
}

// ---------------------------------------------------------------------------------------------
// sin, cos, tan ([spec (12.1.12)–(12.1.13)](crate::spec::precision)).

/// The reduction of a finite point `x`: `x 2/pi = K + f` for an integer `K` and a real `f`
/// with `|f| <= 1/2 + 2^-300`; returns `(K mod 4, enclosure of f, enclosure of f pi/2)`.
/// Without `need_f`, the enclosure of `f` may be the whole line when `|x| < pi/4`.
fn reduce(x: Dd, need_f: bool) -> (u32, DdInterval, DdInterval) {
    let a = x.abs();
    if a.hi() <= 0.785 {
        // |x| < pi/4: K = 0, r = x exactly.
        let r = DdInterval::point(x);
        let f = if need_f {
            r / FRAC_PI_2
        } else {
            DdInterval::ENTIRE
        };
        return (0, f, r);
    }
    let (_, q, e) = dd_to_big(a);
    // |x| in [2^t, 2^(t+1)).
    let t = q.bit_len() as i64 - 1 + e;
    let n = (t.max(0) + 320) as u64;
    let p = Big::from_limbs(&TWO_OVER_PI).shr(TWO_OVER_PI_BITS - n);
    // |x| 2/pi lies in [Q P, Q P + Q] 2^(e - n); F = n - e > 0 fractional bits.
    let fbits = (n as i64 - e) as u64;
    let z = q.mul(&p).low_bits(fbits + 2); // the value mod 4
    let half = Big::from_u64(1).shl(fbits - 1);
    let k = z.add(&half).shr(fbits).low_u64() as u32; // round(z 2^-F), in 0..=4
    let kk = Big::from_u64(k as u64).shl(fbits);
    // f in [W, W + Q] 2^-F with W = z - k 2^F (signed).
    let (wneg, w) = if z.cmp_big(&kk) == core::cmp::Ordering::Less {
        (true, kk.sub(&z))
    } else {
        (false, z.sub(&kk))
    };
    let (w2neg, w2) = if !wneg {
        (false, w.add(&q))
    } else if w.cmp_big(&q) == core::cmp::Ordering::Greater {
        (true, w.sub(&q))
    } else {
        (false, q.sub(&w))
    };
    let fe = -(fbits as i64);
    let f_lo = big_to_interval(wneg, &w, fe, false).lo;
    let f_hi = big_to_interval(w2neg, &w2, fe, false).hi;
    let f = DdInterval { lo: f_lo, hi: f_hi };
    let r = f * FRAC_PI_2;
    let k = k % 4;
    if x.hi() < 0.0 {
        ((4 - k) % 4, -f, -r)
    } else {
        (k, f, r)
    }
}

/// Degree in `r^2` of the sin series on `|r| <= 0.7854 + 2^-300`: `|r|^29/29! < 2^-112`.
const SIN_DEG: usize = 13;
/// Degree in `r^2` of the cos series: `|r|^30/30! < 2^-118`.
const COS_DEG: usize = 14;

/// `sin r = r (sum (-1)^n r^2n/(2n+1)! + rho)`, `|rho| <= |r|^28/29!` (Lagrange; all
/// derivatives of sin are bounded by 1).
fn sin_kernel(r: DdInterval) -> DdInterval {
    let t = inv_fact();
    let rb = Ball::from_interval(r);
    let p = horner(rb.mul(rb), SIN_DEG, |n| alt(n, t[2 * n + 1]));
    let rho = rem_bound(r.mag_up(), 2 * SIN_DEG as u32 + 2, 1.2e-31); // 1/29! < 1.2e-31
    rb.mul(p.widen(rho)).to_interval()
}

/// `cos r = sum (-1)^n r^2n/(2n)! + rho`, `|rho| <= |r|^30/30!`.
fn cos_kernel(r: DdInterval) -> DdInterval {
    let t = inv_fact();
    let rb = Ball::from_interval(r);
    let p = horner(rb.mul(rb), COS_DEG, |n| alt(n, t[2 * n]));
    let rho = rem_bound(r.mag_up(), 2 * COS_DEG as u32 + 2, 3.8e-33); // 1/30! < 3.8e-33
    p.widen(rho).to_interval()
}

/// `sin x` from `x = K pi/2 + r` with `K mod 4 = k`.
fn sin_from(k: u32, r: DdInterval) -> DdInterval {
    match k {
        0 => sin_kernel(r),
        1 => cos_kernel(r),
        2 => -sin_kernel(r),
        _ => -cos_kernel(r),
    }
}

fn cos_from(k: u32, r: DdInterval) -> DdInterval {
    sin_from((k + 1) % 4, r)
}

const UNIT: DdInterval = DdInterval {
    lo: Dd::from_parts(-1.0, 0.0),
    hi: Dd::from_parts(1.0, 0.0),
};

/// The multiples `j pi/2` (as `j mod 4`) that may lie in `[a, b]`, from the reductions of both
/// ends, when `b - a < 3.1`: `t(b) - t(a) < 1.974`, so the difference of the integer parts is the
/// unique element of `{-1, 0, 1, 2}` congruent to `kb - ka` mod 4
/// ([spec (12.1.13)](crate::spec::precision)). Returns a bit set over `j mod 4`.
fn critical(ka: u32, fa: DdInterval, kb: u32, fb: DdInterval) -> u32 {
    let d = ((kb + 4 - ka) % 4) as i32;
    let d = if d == 3 { -1 } else { d };
    let mut set = 0u32;
    for i in -1i32..=3 {
        let fi = Dd::from_f64(i as f64);
        let fid = Dd::from_f64((i - d) as f64);
        // j = Ka + i lies in [t(a), t(b)] only if i >= fa and i - d <= fb for some fa, fb.
        if fi >= fa.inf() && fid <= fb.sup() {
            set |= 1 << ((ka as i32 + i).rem_euclid(4));
        }
    }
    set
}

impl DdInterval {
    /// sin ([spec (12.1.12)–(12.1.13)](crate::spec::precision)); `[-1, 1]` for an unbounded
    /// argument or one at least 6.2 wide (less than 2 pi).
    pub fn sin(self) -> DdInterval {
        self.sin_cos(false)
    }

    /// cos, as [`DdInterval::sin`].
    pub fn cos(self) -> DdInterval {
        self.sin_cos(true)
    }

    fn sin_cos(self, cos: bool) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        if !self.is_finite() {
            return UNIT;
        }
        let eval = |k: u32, r: DdInterval| if cos { cos_from(k, r) } else { sin_from(k, r) };
        let (ka, fa, ra) = reduce(self.lo, !self.is_point());
        if self.is_point() {
            return eval(ka, ra).intersection(UNIT);
        }
        let w = self.wid_up();
        if w >= 6.2 {
            return UNIT;
        }
        if w >= 3.1 {
            // Two halves, each narrower than 3.1; the range is the hull of their ranges.
            let m = self.mid();
            let left = DdInterval { lo: self.lo, hi: m };
            let right = DdInterval { lo: m, hi: self.hi };
            return left.sin_cos(cos).hull(right.sin_cos(cos));
        }
        let (kb, fb, rb) = reduce(self.hi, true);
        let mut y = eval(ka, ra).hull(eval(kb, rb));
        let set = critical(ka, fa, kb, fb);
        // sin: max at j = 1 mod 4, min at j = 3; cos: max at 0, min at 2.
        let (jmax, jmin) = if cos { (0, 2) } else { (1, 3) };
        if set & (1 << jmax) != 0 {
            y = DdInterval {
                lo: y.lo,
                hi: Dd::ONE,
            };
        }
        if set & (1 << jmin) != 0 {
            y = DdInterval {
                lo: -Dd::ONE,
                hi: y.hi,
            };
        }
        y.intersection(UNIT)
    }

    /// tan; the whole line when a pole may lie in the argument (or it is at least 3.1 wide).
    pub fn tan(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        if !self.is_finite() {
            return DdInterval::ENTIRE;
        }
        let tan_at = |k: u32, r: DdInterval| {
            if k.is_multiple_of(2) {
                sin_kernel(r) / cos_kernel(r)
            } else {
                -(cos_kernel(r) / sin_kernel(r))
            }
        };
        let (ka, fa, ra) = reduce(self.lo, !self.is_point());
        if self.is_point() {
            return tan_at(ka, ra);
        }
        if self.wid_up() >= 3.1 {
            return DdInterval::ENTIRE;
        }
        let (kb, fb, rb) = reduce(self.hi, true);
        let set = critical(ka, fa, kb, fb);
        if set & 0b1010 != 0 {
            return DdInterval::ENTIRE;
        }
        DdInterval {
            lo: tan_at(ka, ra).lo,
            hi: tan_at(kb, rb).hi,
        }
    }

    /// An enclosure of pi.
    pub fn pi() -> DdInterval {
        PI
    }

    /// An enclosure of pi/2.
    pub fn frac_pi_2() -> DdInterval {
        FRAC_PI_2
    }

    /// An enclosure of ln 2.
    pub fn ln2() -> DdInterval {
        LN2
    }
}

// ---------------------------------------------------------------------------------------------
// atan ([spec (12.1.14)](crate::spec::precision)).

/// Degree in `z^2` of the atan series on `|z| <= tan(pi/16) < 0.1990`: `z^48/49 < 2^-117`.
const ATAN_DEG: usize = 23;

/// `atan y` for an interval `y` in `[0, 1]`: two half-angle steps
/// `atan y = 2 atan(y / (1 + sqrt(1 + y^2)))`, then `z (sum (-1)^n z^2n/(2n+1) + rho)`,
/// `|rho| <= |z|^(2N+2)/(2N+3)` (alternating series with decreasing terms).
fn atan_kernel(y: DdInterval) -> DdInterval {
    let mut z = y;
    for _ in 0..2 {
        z = z / (DdInterval::ONE + (DdInterval::ONE + z.sqr()).sqrt());
    }
    let t = inv_odd();
    let zb = Ball::from_interval(z);
    let p = horner(zb.mul(zb), ATAN_DEG, |n| alt(n, t[n]));
    let rho = rem_bound(
        z.mag_up(),
        2 * ATAN_DEG as u32 + 2,
        1.0 / (2 * ATAN_DEG + 3) as f64 * (1.0 + 1e-15),
    );
    zb.mul(p.widen(rho)).to_interval().scale_pow2(2)
}

/// `atan x` for a finite point.
fn atan_pt(x: Dd) -> DdInterval {
    let a = x.abs();
    if a == Dd::ZERO {
        return DdInterval::ZERO;
    }
    let v = if a.hi() > 1.0 {
        FRAC_PI_2 - atan_kernel(DdInterval::point(a).recip())
    } else {
        atan_kernel(DdInterval::point(a))
    };
    if x.hi() < 0.0 {
        -v
    } else {
        v
    }
}

impl DdInterval {
    /// atan, increasing, `atan(±inf) = ±pi/2` ([spec (12.1.14)](crate::spec::precision)).
    pub fn atan(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let lo = if self.lo.is_finite() {
            atan_pt(self.lo).lo
        } else {
            -FRAC_PI_2.hi
        };
        let hi = if self.hi.is_finite() {
            atan_pt(self.hi).hi
        } else {
            FRAC_PI_2.hi
        };
        DdInterval { lo, hi }
    }
}

// ---------------------------------------------------------------------------------------------
// sinh, cosh, tanh, asinh ([spec (12.1.15)–(12.1.16)](crate::spec::precision)).

/// Degree in `x^2` of the sinh series on `|x| <= 1/2`: `1.13 * 0.5^26/27! < 2^-118`.
const SINH_DEG: usize = 12;

/// `sinh x` for a finite point: the series `x (sum x^2n/(2n+1)! + rho)` with
/// `|rho| <= cosh(1/2) |x|^26/27!` for `|x| <= 1/2`, else `2^-1 e^x - 2^-1 e^-x`.
fn sinh_pt(x: Dd) -> DdInterval {
    let xi = DdInterval::point(x);
    if x.abs().hi() <= 0.5 {
        let t = inv_fact();
        let xb = Ball::from_interval(xi);
        let p = horner(xb.mul(xb), SINH_DEG, |n| t[2 * n + 1]);
        let rho = rem_bound(x.abs().to_f64_up(), 2 * SINH_DEG as u32 + 2, 1.1e-28); // 1.13/27! < 1.1e-28
        return xb.mul(p.widen(rho)).to_interval();
    }
    xi.exp_scaled(-1) - (-xi).exp_scaled(-1)
}

/// `tanh x` for a finite point: `sinh/cosh` for `|x| <= 1/2`, else `±(1 - 2/(e^2|x| + 1))`
/// (`[1 - 2^-1000, 1]` beyond 400).
fn tanh_pt(x: Dd) -> DdInterval {
    let a = x.abs();
    let v = if a.hi() <= 0.5 {
        let xi = DdInterval::point(x);
        return sinh_pt(x) / (xi.exp_scaled(-1) + (-xi).exp_scaled(-1));
    } else if a.hi() > 400.0 {
        DdInterval {
            lo: Dd::new(1.0, -pow2(-1000)),
            hi: Dd::ONE,
        }
    } else {
        let e = DdInterval::point(a).scale_pow2(1).exp();
        DdInterval::ONE - DdInterval::from_f64(2.0) / (e + DdInterval::ONE)
    };
    let v = v.intersection(UNIT);
    if x.hi() < 0.0 {
        -v
    } else {
        v
    }
}

/// `asinh x` for a finite point `x`: odd; for `0 < x <= 0.35`, `ln(1 + y)` with the
/// cancellation-free `y = x + x^2/(1 + sqrt(1 + x^2))`; up to `2^60`,
/// `ln(x + sqrt(x^2 + 1))`; beyond, `ln x + ln 2 + [0, 2^-120]` (the rest is
/// `ln((1 + sqrt(1 + x^-2))/2) <= 1/(4x^2)`).
fn asinh_pt(x: Dd) -> DdInterval {
    let a = x.abs();
    if a == Dd::ZERO {
        return DdInterval::ZERO;
    }
    let ai = DdInterval::point(a);
    let v = if a.hi() <= 0.35 {
        let a2 = ai.sqr();
        let y = ai + a2 / (DdInterval::ONE + (DdInterval::ONE + a2).sqrt());
        ln1p_kernel(y)
    } else if a.hi() <= 1.152921504606847e18 {
        (ai + (ai.sqr() + DdInterval::ONE).sqrt()).ln()
    } else {
        ln_pt(a)
            + LN2
            + DdInterval {
                lo: Dd::ZERO,
                hi: Dd::from_f64(pow2(-120)),
            }
    };
    if x.hi() < 0.0 {
        -v
    } else {
        v
    }
}

impl DdInterval {
    /// sinh, increasing ([spec (12.1.15)](crate::spec::precision)).
    pub fn sinh(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let lo = if self.lo.is_finite() {
            sinh_pt(self.lo).lo
        } else {
            Dd::NEG_INFINITY
        };
        let hi = if self.hi.is_finite() {
            sinh_pt(self.hi).hi
        } else {
            Dd::INFINITY
        };
        DdInterval { lo, hi }
    }

    /// cosh, decreasing then increasing, at least 1.
    pub fn cosh(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let a = self.abs();
        let c = |p: Dd| {
            let xi = DdInterval::point(p);
            xi.exp_scaled(-1) + (-xi).exp_scaled(-1)
        };
        let lo = if a.lo.is_finite() {
            c(a.lo).lo
        } else {
            Dd::INFINITY
        };
        let hi = if a.hi.is_finite() {
            c(a.hi).hi
        } else {
            Dd::INFINITY
        };
        let lo = if lo < Dd::ONE { Dd::ONE } else { lo };
        DdInterval { lo, hi }
    }

    /// tanh, increasing, in `[-1, 1]`.
    pub fn tanh(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let lo = if self.lo.is_finite() {
            tanh_pt(self.lo).lo
        } else {
            -Dd::ONE
        };
        let hi = if self.hi.is_finite() {
            tanh_pt(self.hi).hi
        } else {
            Dd::ONE
        };
        DdInterval { lo, hi }
    }

    /// asinh, increasing ([spec (12.1.16)](crate::spec::precision)).
    pub fn asinh(self) -> DdInterval {
        if self.is_empty() {
            return self;
        }
        let lo = if self.lo.is_finite() {
            asinh_pt(self.lo).lo
        } else {
            Dd::NEG_INFINITY
        };
        let hi = if self.hi.is_finite() {
            asinh_pt(self.hi).hi
        } else {
            Dd::INFINITY
        };
        DdInterval { lo, hi }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(x: f64) -> DdInterval {
        DdInterval::from_f64(x)
    }

    fn pair(a: f64, b: f64) -> DdInterval {
        DdInterval::from_f64_pair(a, b).unwrap()
    }

    /// `2^-100`: every point value below is far tighter.
    const T: f64 = f64::from_bits(923 << 52);

    #[test]
    fn closed_forms() {
        let s = PI.sin();
        assert!(s.contains(Dd::ZERO) && s.mag_up() < 1e-31);
        assert!(FRAC_PI_2.sin().contains(Dd::ONE) && FRAC_PI_2.sin().wid_up() < T);
        assert!(PI.cos().contains_f64(-1.0));
        assert!(LN2.exp().contains_f64(2.0) && LN2.exp().wid_up() < T);
        assert!(iv(2.0).ln().subset(LN2.hull(iv(2.0).ln())) && !iv(2.0).ln().disjoint(LN2));
        assert!(iv(1.0).atan().scale_pow2(2).contains(PI.mid()));
        assert!(iv(1.0).exp().ln().contains_f64(1.0));
        assert!(iv(0.0).exp() == DdInterval::ONE);
        assert!(iv(1.0).ln() == DdInterval::ZERO);
        assert!(iv(0.0).sin().is_exact_zero() && iv(0.0).cos() == DdInterval::ONE);
        assert!(iv(0.0).atan().is_exact_zero() && iv(0.0).asinh().is_exact_zero());
        let x = iv(0.75);
        let (sh, ch) = (x.sinh(), x.cosh());
        assert!((ch.sqr() - sh.sqr()).contains_f64(1.0));
        assert!((sh / ch).intersection(x.tanh()).wid_up() > 0.0);
        assert!(x.sinh().asinh().contains_f64(0.75));
        let (s1, c1) = (iv(1e22).sin(), iv(1e22).cos());
        assert!((s1.sqr() + c1.sqr()).contains_f64(1.0));
        // sin(1e22) = -0.852200849767188801772705893753...: the table checks it against mpmath.
        assert!(s1.sup_f64() < -0.8522 && s1.inf_f64() > -0.8523 && s1.wid_up() < 1e-30);
    }

    #[test]
    fn intervals_and_domains() {
        assert!(pair(-1.0, 4.0).ln().inf() == Dd::NEG_INFINITY);
        assert!(pair(-2.0, 0.0).ln().is_empty());
        assert!(pair(1.0, 2.0).sin().sup() == Dd::ONE);
        assert!(pair(3.0, 4.0).cos().inf() == -Dd::ONE);
        assert!(pair(1.0, 2.0).tan() == DdInterval::ENTIRE);
        assert!(pair(-1.0, 1.0).tan().is_finite());
        assert!(pair(0.0, 100.0).sin() == UNIT);
        // 4.5 wide: split in two halves; sin on [0.5, 5] reaches both extremes (pi/2, 3pi/2
        // inside), and so does cos on [-0.5, 4] (0 and pi inside).
        assert!(pair(0.5, 5.0).sin() == UNIT);
        let c = pair(-0.5, 4.0).cos();
        assert!(c.inf() == -Dd::ONE && c.sup() == Dd::ONE);
        let s = pair(-1.4, 1.6).sin(); // 3.0 wide, no split: max 1 at pi/2, min sin(-1.4)
        assert!(s.sup() == Dd::ONE && s.inf_f64() > -0.99);
        let s = pair(-1.5, 1.6).sin(); // 3.1 wide: split, the same range
        assert!(s.sup() == Dd::ONE && s.inf_f64() > -0.9975 && s.inf_f64() < -0.9974);
        let e = pair(-1.0, 1.0).exp();
        assert!(e.contains(iv(1.0).exp().sup()) && e.contains(iv(-1.0).exp().inf()));
        assert!(DdInterval::ENTIRE.atan().subset(FRAC_PI_2.hull(-FRAC_PI_2)));
        assert!(DdInterval::ENTIRE.tanh() == UNIT && DdInterval::ENTIRE.exp().inf() == Dd::ZERO);
        assert!(pair(-2.0, 3.0).cosh().inf() == Dd::ONE);
        for f in [
            DdInterval::sin,
            DdInterval::cos,
            DdInterval::tan,
            DdInterval::exp,
            DdInterval::ln,
            DdInterval::atan,
            DdInterval::sinh,
            DdInterval::cosh,
            DdInterval::tanh,
            DdInterval::asinh,
        ] {
            assert!(f(DdInterval::EMPTY).is_empty());
            for x in [
                DdInterval::ENTIRE,
                pair(-f64::MAX, f64::MAX),
                iv(1e300),
                iv(-1e300),
                iv(5e-324),
                iv(710.0),
                iv(-746.0),
            ] {
                let y = f(x);
                assert!(y.is_empty() || y.inf() <= y.sup(), "{x:?} -> {y:?}");
                assert!(!y.inf().is_nan() && !y.sup().is_nan());
            }
        }
    }

    #[test]
    fn overflow_and_underflow() {
        let e = iv(710.0).exp();
        assert!(e.sup() == Dd::INFINITY && e.inf() == Dd::MAX);
        let e = iv(-746.0).exp();
        assert!(e.inf() == Dd::ZERO && e.sup_f64() <= 5e-324);
        assert!(
            iv(709.0).exp().is_finite()
                && iv(710.0).sinh().is_finite()
                && iv(710.0).cosh().is_finite()
        );
        assert!(
            iv(712.0).sinh().sup() == Dd::INFINITY && iv(-712.0).sinh().inf() == Dd::NEG_INFINITY
        );
        assert!(iv(1000.0).tanh().contains_f64(1.0) && iv(1000.0).tanh().inf_f64() > 0.999);
        assert!(
            iv(1e-300).sin().contains_f64(1e-300)
                && iv(1e-300).exp().contains(Dd::new(1.0, 1e-300))
        );
    }
}
