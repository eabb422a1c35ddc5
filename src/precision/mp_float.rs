//! `Mp`: a binary floating-point number of up to [`MAX_PREC`] bits (the ends of
//! [`MpInterval`](super::mp::MpInterval) and of [`WideInterval`](super::wide::WideInterval)),
//! with every operation rounded in a chosen direction.
//!
//! A finite `Mp` is `(-1)^neg * man * 2^exp` with `man` a natural number of at most
//! [`MAX_PREC`] bits held in a fixed array of [`LIMBS`] 64-bit limbs (`Nat`, so `Mp` is
//! `Copy` and no operation allocates) and `exp` an `i64`; `man` is odd or zero (canonical
//! form, so equal values have equal representations). The precision is not stored in the
//! number: each operation takes the number of significand bits of its result (clamped to
//! `1..=MAX_PREC`: a directed rounding to fewer bits is still a bound on its side) and a
//! direction ([`Round`]). Every operation computes the exact result in a `Nat` of twice the
//! limbs (or an exact stand-in that provably rounds the same way) and rounds it once:
//! [spec (12.2.1)](crate::spec::precision). Exponents are kept within `[-EXP_LIMIT,
//! EXP_LIMIT]`: beyond, a result overflows to an infinity or to the largest finite number, or
//! underflows to 0 or the smallest positive number, as the direction says (12.2.1).

use super::limbs::Nat;
use core::cmp::Ordering;
use num_bigint::BigUint;

pub use super::mp_decimal::{decimal_to_mp, parse_decimal, to_decimal};

/// Rounding direction of an [`Mp`] operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Round {
    /// Toward minus infinity (the lower end of an interval).
    Down,
    /// Toward plus infinity (the upper end of an interval).
    Up,
    /// To nearest, ties to even (points: centres and Newton guesses).
    Near,
}

/// The bound on the binary exponent of a finite nonzero [`Mp`]: `2^-EXP_LIMIT <= |x| <
/// 2^EXP_LIMIT`.
pub const EXP_LIMIT: i64 = 1 << 40;

/// The 64-bit limbs of an [`Mp`] significand.
pub const LIMBS: usize = 24;

/// The most significant bits an [`Mp`] holds (1,536: the 1,024 bits of the largest
/// `--precision`, the guard bits of the elementary functions, and the extra bits of the
/// argument reduction of sin and cos of every double at 256 bits, 12.2.0).
pub const MAX_PREC: u32 = 64 * LIMBS as u32;

/// The limbs of an exact intermediate result: a product of two significands, a sum of
/// significands shifted apart by at most `MAX_PREC + 4` bits, a numerator or radicand of
/// `2 MAX_PREC + 6` bits, with one limb to spare for Knuth's division (12.2.0).
const WORK: usize = 2 * LIMBS + 4;

type Man = Nat<LIMBS>;
type Work = Nat<WORK>;

/// Calls `$f::<N>(args)` with the smallest work size `N` of at least `$need` limbs: the same
/// exact arithmetic (12.2.0) in a smaller array when the operands are short, so that a
/// 160-bit operation does not clear and copy arrays sized for 1,536 bits.
macro_rules! with_work {
    ($need:expr, $f:ident($($a:expr),*)) => {{
        let need: usize = $need;
        if need <= 8 {
            $f::<8>($($a),*)
        } else if need <= 14 {
            $f::<14>($($a),*)
        } else if need <= 24 {
            $f::<24>($($a),*)
        } else {
            $f::<WORK>($($a),*)
        }
    }};
}

/// The limbs of an intermediate of `bits` bits, with one to spare (carries, algorithm D).
fn limbs_for(bits: u64) -> usize {
    bits.div_ceil(64) as usize + 2
}

/// An arbitrary precision binary floating-point number, or an infinity (see the module doc).
///
/// `repr(C)`, the significand last: the sign, the exponent, the length and the low limbs come
/// first, together in memory (see [`MpInterval`](super::mp::MpInterval)'s layout).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct Mp {
    neg: bool,
    inf: bool,
    exp: i64,
    man: Man,
}

fn clamp_prec(prec: u64) -> u64 {
    prec.clamp(1, MAX_PREC as u64)
}

/// Rounds `(-1)^neg * man * 2^exp` (exact) to at most `prec` significant bits, at an exponent
/// of at least `emin`, in direction `mode`; a result at or beyond `2^emax` in magnitude
/// overflows (12.2.1).
fn round_parts<const N: usize>(
    neg: bool,
    mut man: Nat<N>,
    mut exp: i64,
    prec: u64,
    emin: i64,
    emax: i64,
    mode: Round,
) -> Mp {
    let prec = clamp_prec(prec);
    if man.is_zero() {
        return Mp::zero();
    }
    let bits = man.bits() as i64;
    let k = (bits - prec as i64).max(emin - exp).max(0);
    if k > 0 {
        // the value lies in [t, t + 1) * 2^(exp + k), t = floor(man / 2^k)
        let (inexact, half, above_half) = if k > bits + 1 {
            (true, false, false)
        } else {
            let tz = man.trailing_zeros() as i64;
            let inexact = tz < k;
            let half = man.bit((k - 1) as u64);
            // strictly above the half: the half bit set and some bit below it set
            let above_half = half && tz < k - 1;
            (inexact, half, above_half)
        };
        man.shr_assign(k as u64);
        exp += k;
        if inexact {
            let away = match mode {
                Round::Up => !neg,
                Round::Down => neg,
                Round::Near => above_half || (half && man.bit(0)),
            };
            if away {
                man.add_one_assign();
            }
        }
    }
    if man.is_zero() {
        return Mp::zero();
    }
    let tz = man.trailing_zeros();
    if tz > 0 {
        man.shr_assign(tz);
        exp += tz as i64;
    }
    if exp + man.bits() as i64 > emax {
        // overflow: away from zero gives the infinity, toward zero the largest finite number
        let away = match mode {
            Round::Up => !neg,
            Round::Down => neg,
            Round::Near => true,
        };
        return if away {
            Mp::infinity(neg)
        } else {
            Mp::max_finite(neg, prec, emax)
        };
    }
    Mp {
        neg,
        inf: false,
        man: man.resize(),
        exp,
    }
}

impl Mp {
    /// Zero.
    pub const fn zero() -> Mp {
        Mp {
            neg: false,
            inf: false,
            man: Man::ZERO,
            exp: 0,
        }
    }

    /// Plus (`neg = false`) or minus infinity.
    pub const fn infinity(neg: bool) -> Mp {
        Mp {
            neg,
            inf: true,
            man: Man::ZERO,
            exp: 0,
        }
    }

    /// The largest finite number of `prec` bits below `2^emax`, with sign `neg`.
    fn max_finite(neg: bool, prec: u64, emax: i64) -> Mp {
        let prec = clamp_prec(prec);
        let man = Man::from_u64(1)
            .resize::<WORK>()
            .shl(prec)
            .sub(&Work::from_u64(1));
        Mp {
            neg,
            inf: false,
            man: man.resize(),
            exp: emax - prec as i64,
        }
    }

    /// The largest finite `Mp` of `prec` bits (just below `2^EXP_LIMIT`).
    pub fn max_value(prec: u32) -> Mp {
        Mp::max_finite(false, prec as u64, EXP_LIMIT)
    }

    /// The smallest positive `Mp`, `2^-EXP_LIMIT`.
    pub fn min_positive() -> Mp {
        Mp {
            neg: false,
            inf: false,
            man: Man::from_u64(1),
            exp: -EXP_LIMIT,
        }
    }

    /// `(-1)^neg * man * 2^exp` rounded to `prec` bits in direction `mode`, for a big integer
    /// `man` of any size: its bits below the `MAX_PREC + 2` leading ones are first folded into
    /// one sticky bit, which rounds the same way in every direction (12.2.1).
    pub fn from_parts(neg: bool, man: BigUint, exp: i64, prec: u32, mode: Round) -> Mp {
        let keep = MAX_PREC as u64 + 2;
        let (man, exp) = if man.bits() > keep {
            let k = man.bits() - keep;
            let sticky = man.trailing_zeros().unwrap_or(0) < k;
            let top = (&man >> k) << 1u32;
            let top = if sticky { top + 1u32 } else { top };
            (top, exp.saturating_add(k as i64 - 1))
        } else {
            (man, exp)
        };
        let man = Work::from_limbs(&man.to_u64_digits());
        let exp = exp.clamp(-4 * EXP_LIMIT, 4 * EXP_LIMIT);
        round_parts(neg, man, exp, prec as u64, -EXP_LIMIT, EXP_LIMIT, mode)
    }

    /// The significand of the canonical form as a big integer (decimal output).
    pub fn mantissa(&self) -> BigUint {
        let mut words = Vec::with_capacity(2 * self.man.limbs().len());
        for d in self.man.limbs() {
            words.push(*d as u32);
            words.push((*d >> 32) as u32);
        }
        BigUint::new(words)
    }

    /// The exact value of the integer `i`.
    pub fn from_i64(i: i64) -> Mp {
        let man = Nat::<8>::from_u64(i.unsigned_abs());
        round_parts(i < 0, man, 0, 64, -EXP_LIMIT, EXP_LIMIT, Round::Near)
    }

    /// The exact value of a double; `None` for NaN. Infinite doubles give infinities.
    pub fn from_f64(x: f64) -> Option<Mp> {
        if x.is_nan() {
            return None;
        }
        if x.is_infinite() {
            return Some(Mp::infinity(x < 0.0));
        }
        let bits = x.to_bits();
        let neg = bits >> 63 == 1;
        let be = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        let (man, exp) = if be == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), be - 1075)
        };
        Some(round_parts(
            neg,
            Nat::<8>::from_u64(man),
            exp,
            64,
            -EXP_LIMIT,
            EXP_LIMIT,
            Round::Near,
        ))
    }

    /// This number rounded to a double in direction `mode` (overflow: an infinity in the
    /// away direction, `f64::MAX` toward zero; underflow through the subnormals to 0).
    pub fn to_f64(&self, mode: Round) -> f64 {
        if self.inf {
            return if self.neg {
                f64::NEG_INFINITY
            } else {
                f64::INFINITY
            };
        }
        let r = with_work!(self.man.limbs().len() + 1, to_f64_grid(self, mode));
        if r.inf {
            return if r.neg {
                f64::NEG_INFINITY
            } else {
                f64::INFINITY
            };
        }
        if r.is_zero() {
            return 0.0;
        }
        // r = m 2^e exactly, m < 2^53, e >= -1074, m 2^e < 2^1024
        let mut m = r.man.low();
        let mut e = r.exp;
        let shift = 53 - (64 - m.leading_zeros() as i64);
        // normalize to 53 bits where the exponent allows (a normal double)
        let s = shift.min(e + 1074).max(0);
        m <<= s;
        e -= s;
        let bits = if m >> 52 == 0 {
            // subnormal: e = -1074
            m
        } else {
            let be = (e + 1075) as u64;
            (be << 52) | (m & ((1u64 << 52) - 1))
        };
        let v = f64::from_bits(bits);
        if r.neg {
            -v
        } else {
            v
        }
    }

    fn work<const N: usize>(&self) -> Nat<N> {
        self.man.resize()
    }

    /// The canonical form `(sign, significand limbs, exponent)` of a finite number (the fused
    /// dot product of `mp_dot.rs` reads its operands exactly).
    pub(super) fn parts(&self) -> (bool, &[u64], i64) {
        (self.neg, self.man.limbs(), self.exp)
    }

    /// `(-1)^neg man 2^exp` (exact) rounded once to `prec` bits in direction `mode` (12.2.1).
    pub(super) fn round_nat<const N: usize>(
        neg: bool,
        man: Nat<N>,
        exp: i64,
        prec: u32,
        mode: Round,
    ) -> Mp {
        round_parts(neg, man, exp, prec as u64, -EXP_LIMIT, EXP_LIMIT, mode)
    }

    /// Whether this is zero.
    pub fn is_zero(&self) -> bool {
        !self.inf && self.man.is_zero()
    }

    /// Whether this is finite.
    pub fn is_finite(&self) -> bool {
        !self.inf
    }

    /// Whether this is an infinity.
    pub fn is_infinite(&self) -> bool {
        self.inf
    }

    /// Whether this is strictly negative (minus infinity included).
    pub fn is_negative(&self) -> bool {
        self.neg && (self.inf || !self.man.is_zero())
    }

    /// Whether this is strictly positive (plus infinity included).
    pub fn is_positive(&self) -> bool {
        !self.neg && (self.inf || !self.man.is_zero())
    }

    /// The number of significant bits of the (finite) significand.
    pub fn significant_bits(&self) -> u64 {
        self.man.bits()
    }

    /// For a finite nonzero number, `t` with `2^(t-1) <= |x| < 2^t`.
    pub fn top(&self) -> i64 {
        self.exp + self.man.bits() as i64
    }

    /// The exponent of the canonical form `(-1)^neg man 2^exp` (man odd).
    pub fn exponent(&self) -> i64 {
        self.exp
    }

    /// `-x` (exact).
    pub fn neg(&self) -> Mp {
        let mut r = *self;
        if r.inf || !r.man.is_zero() {
            r.neg = !r.neg;
        }
        r
    }

    /// `|x|` (exact).
    pub fn abs(&self) -> Mp {
        let mut r = *self;
        r.neg = false;
        r
    }

    /// `x 2^k` rounded (exact unless it leaves the exponent range).
    pub fn ldexp(&self, k: i64, mode: Round) -> Mp {
        if self.inf || self.is_zero() {
            return *self;
        }
        let k = k.clamp(-4 * EXP_LIMIT, 4 * EXP_LIMIT);
        with_work!(self.man.limbs().len() + 1, ldexp_in(self, k, mode))
    }

    /// This number rounded to `prec` bits in direction `mode`.
    pub fn round(&self, prec: u32, mode: Round) -> Mp {
        if self.inf || (self.man.bits() <= prec as u64) {
            return *self;
        }
        with_work!(self.man.limbs().len() + 1, round_in(self, prec, mode))
    }

    /// `x + y` rounded to `prec` bits; `inf + (-inf)` is `None` (12.2.1).
    pub fn add(&self, y: &Mp, prec: u32, mode: Round) -> Option<Mp> {
        let prec = clamp_prec(prec as u64);
        if self.inf || y.inf {
            if self.inf && y.inf && self.neg != y.neg {
                return None;
            }
            return Some(if self.inf { *self } else { *y });
        }
        if self.is_zero() {
            return Some(y.round(prec as u32, mode));
        }
        if y.is_zero() {
            return Some(self.round(prec as u32, mode));
        }
        let (a, b) = if self.top() >= y.top() {
            (self, y)
        } else {
            (y, self)
        };
        // far apart: b is replaced by a nonzero number of its sign below every rounding
        // breakpoint near a (12.2.1)
        let l = (a.man.bits().max(prec + 2) + 1) as i64;
        let far = a.top() - b.top() > l;
        let bexp = if far { a.top() - l - 1 } else { b.exp };
        let e = a.exp.min(bexp);
        Some(with_work!(
            limbs_for((a.top() - e) as u64 + 1),
            add_in(a, b, far, bexp, e, prec, mode)
        ))
    }

    /// `x - y` rounded to `prec` bits; `None` for `inf - inf` of one sign.
    pub fn sub(&self, y: &Mp, prec: u32, mode: Round) -> Option<Mp> {
        self.add(&y.neg(), prec, mode)
    }

    /// `x y` rounded to `prec` bits, with `0 * inf = 0` (the interval convention: a zero end
    /// times an unbounded end) (12.2.1).
    pub fn mul(&self, y: &Mp, prec: u32, mode: Round) -> Mp {
        let neg = self.neg != y.neg;
        if self.is_zero() || y.is_zero() {
            return Mp::zero();
        }
        if self.inf || y.inf {
            return Mp::infinity(neg);
        }
        with_work!(
            self.man.limbs().len() + y.man.limbs().len() + 1,
            mul_in(self, y, neg, prec as u64, mode)
        )
    }

    /// `x / y` rounded to `prec` bits; `None` when `y = 0` or both are infinite;
    /// `finite / inf = 0` (12.2.1).
    pub fn div(&self, y: &Mp, prec: u32, mode: Round) -> Option<Mp> {
        let prec = clamp_prec(prec as u64);
        if y.is_zero() || (self.inf && y.inf) {
            return None;
        }
        let neg = self.neg != y.neg;
        if self.inf {
            return Some(Mp::infinity(neg));
        }
        if y.inf || self.is_zero() {
            return Some(Mp::zero());
        }
        // q = floor(man_x 2^s / man_y) has at least prec + 2 bits; a nonzero remainder is
        // kept as a sticky bit below q
        let s = (prec as i64 + 2 + y.man.bits() as i64 - self.man.bits() as i64).max(0) as u64;
        Some(with_work!(
            limbs_for(self.man.bits() + s),
            div_in(self, y, neg, s, prec, mode)
        ))
    }

    /// `x / d` for a positive integer `d`, rounded to `prec` bits (the quotient of (12.2.1)
    /// with a one-limb divisor); `None` for `d = 0`.
    pub fn div_u64(&self, d: u64, prec: u32, mode: Round) -> Option<Mp> {
        if d == 0 {
            return None;
        }
        if self.inf || self.is_zero() {
            return Some(*self);
        }
        let prec = clamp_prec(prec as u64);
        // q = floor(man 2^s / d) has at least prec + 2 bits (d < 2^64)
        let s = (prec as i64 + 2 + 64 - self.man.bits() as i64).max(0) as u64;
        Some(with_work!(
            limbs_for(self.man.bits() + s),
            div_u64_in(self, d, s, prec, mode)
        ))
    }

    /// `sqrt(x)` rounded to `prec` bits; `None` for `x < 0` (12.2.1).
    pub fn sqrt(&self, prec: u32, mode: Round) -> Option<Mp> {
        let prec = clamp_prec(prec as u64);
        if self.is_negative() {
            return None;
        }
        if self.inf || self.is_zero() {
            return Some(*self);
        }
        // m 2^e with e even and m of at least 2 prec + 4 bits; r = floor(sqrt(m)) has at least
        // prec + 2 bits; an inexact root keeps a sticky bit below r
        let mut s = (2 * prec as i64 + 4 - self.man.bits() as i64).max(0);
        if (self.exp - s).rem_euclid(2) != 0 {
            s += 1;
        }
        Some(with_work!(
            limbs_for(self.man.bits() + s as u64),
            sqrt_in(self, s as u64, prec, mode)
        ))
    }

    /// The smaller of two numbers.
    pub fn min(self, y: Mp) -> Mp {
        if y < self {
            y
        } else {
            self
        }
    }

    /// The larger of two numbers.
    pub fn max(self, y: Mp) -> Mp {
        if y > self {
            y
        } else {
            self
        }
    }

    /// `floor(x)` for finite `x` (exact).
    pub fn floor(&self) -> Mp {
        self.round_to_integer(false)
    }

    /// `ceil(x)` for finite `x` (exact).
    pub fn ceil(&self) -> Mp {
        self.round_to_integer(true)
    }

    fn round_to_integer(&self, up: bool) -> Mp {
        if self.inf || self.exp >= 0 {
            return *self;
        }
        with_work!(self.man.limbs().len() + 1, integer_in(self, up))
    }

    /// For an integer-valued `x`, `x mod 4` in `0..4`.
    pub fn integer_mod4(&self) -> u32 {
        if self.is_zero() || self.inf || self.exp >= 2 {
            return 0;
        }
        let low = self.man.low();
        let v = ((low << self.exp.max(0)) & 3) as u32;
        if self.neg {
            (4 - v) % 4
        } else {
            v
        }
    }

    /// The value of an integer-valued `x` if it fits an `i64`.
    pub fn to_i64(&self) -> Option<i64> {
        if self.inf || self.exp < 0 || self.top() > 62 {
            return None;
        }
        let m = self.man.low() << self.exp;
        Some(if self.neg { -(m as i64) } else { m as i64 })
    }
}

/// `q 2^e` when `exact`, else a number strictly between `q 2^e` and `(q + 1) 2^e` (the sticky
/// bit `(2q + 1) 2^(e-1)`), rounded: `q` has at least `prec + 2` bits, so both round alike.
fn sticky_round<const N: usize>(
    neg: bool,
    q: Nat<N>,
    exact: bool,
    e: i64,
    prec: u64,
    mode: Round,
) -> Mp {
    if exact {
        round_parts(neg, q, e, prec, -EXP_LIMIT, EXP_LIMIT, mode)
    } else {
        round_parts(
            neg,
            q.shl(1).add_one(),
            e - 1,
            prec,
            -EXP_LIMIT,
            EXP_LIMIT,
            mode,
        )
    }
}

// The bodies of the operations in a work array of `N` limbs (`with_work!`), each exact until
// its one `round_parts` (12.2.1).

fn to_f64_grid<const N: usize>(x: &Mp, mode: Round) -> Mp {
    round_parts::<N>(x.neg, x.work(), x.exp, 53, -1074, 1024, mode)
}

fn ldexp_in<const N: usize>(x: &Mp, k: i64, mode: Round) -> Mp {
    round_parts::<N>(
        x.neg,
        x.work(),
        x.exp + k,
        x.man.bits().max(1),
        -EXP_LIMIT,
        EXP_LIMIT,
        mode,
    )
}

fn round_in<const N: usize>(x: &Mp, prec: u32, mode: Round) -> Mp {
    round_parts::<N>(
        x.neg,
        x.work(),
        x.exp,
        prec as u64,
        -EXP_LIMIT,
        EXP_LIMIT,
        mode,
    )
}

/// `a + b` (`|a| >= |b|` by top) aligned at exponent `e`; `far`: `b` replaced by
/// `sign(b) 2^bexp` (12.2.1).
fn add_in<const N: usize>(
    a: &Mp,
    b: &Mp,
    far: bool,
    bexp: i64,
    e: i64,
    prec: u64,
    mode: Round,
) -> Mp {
    // one of the two shifts is zero (e is one of the exponents)
    let mut am: Nat<N> = a.work();
    if a.exp > e {
        am = am.shl((a.exp - e) as u64);
    }
    let mut bm: Nat<N> = if far { Nat::from_u64(1) } else { b.work() };
    if bexp > e {
        bm = bm.shl((bexp - e) as u64);
    }
    let (neg, man) = if a.neg == b.neg {
        (a.neg, am.add(&bm))
    } else if am >= bm {
        (a.neg, am.sub(&bm))
    } else {
        (b.neg, bm.sub(&am))
    };
    if man.is_zero() {
        return Mp::zero();
    }
    round_parts(neg, man, e, prec, -EXP_LIMIT, EXP_LIMIT, mode)
}

fn mul_in<const N: usize>(x: &Mp, y: &Mp, neg: bool, prec: u64, mode: Round) -> Mp {
    round_parts::<N>(
        neg,
        x.work().mul(&y.work()),
        x.exp + y.exp,
        prec,
        -EXP_LIMIT,
        EXP_LIMIT,
        mode,
    )
}

fn div_in<const N: usize>(x: &Mp, y: &Mp, neg: bool, s: u64, prec: u64, mode: Round) -> Mp {
    let (q, exact) = x.work::<N>().shl(s).div_exact(&y.work());
    sticky_round(neg, q, exact, x.exp - y.exp - s as i64, prec, mode)
}

fn div_u64_in<const N: usize>(x: &Mp, d: u64, s: u64, prec: u64, mode: Round) -> Mp {
    let (q, r) = x.work::<N>().shl(s).divrem_u64(d);
    sticky_round(x.neg, q, r == 0, x.exp - s as i64, prec, mode)
}

fn sqrt_in<const N: usize>(x: &Mp, s: u64, prec: u64, mode: Round) -> Mp {
    let (r, exact) = x.work::<N>().shl(s).sqrt_exact();
    sticky_round(false, r, exact, (x.exp - s as i64) / 2, prec, mode)
}

/// `floor` (`up = false`) or `ceil` of a finite non-integer `x` (`exp < 0`).
fn integer_in<const N: usize>(x: &Mp, up: bool) -> Mp {
    let k = (-x.exp) as u64;
    let t = x.work::<N>().shr(k);
    // x is not an integer (man odd, exp < 0): its magnitude lies in (t, t + 1)
    let away = if up { !x.neg } else { x.neg };
    let t = if away { t.add_one() } else { t };
    // at most MAX_PREC bits: t < |x| < 2^MAX_PREC, and t + 1 <= 2^MAX_PREC is one bit
    round_parts(
        x.neg,
        t,
        0,
        MAX_PREC as u64,
        -EXP_LIMIT,
        EXP_LIMIT,
        Round::Near,
    )
}

/// `|x|` against `|y|` for finite nonzero numbers of equal tops (the shifts are below
/// `MAX_PREC` bits).
fn cmp_mag_in<const N: usize>(x: &Mp, y: &Mp) -> Ordering {
    let e = x.exp.min(y.exp);
    let a = x.work::<N>().shl((x.exp - e) as u64);
    let b = y.work::<N>().shl((y.exp - e) as u64);
    a.cmp(&b)
}

impl PartialOrd for Mp {
    fn partial_cmp(&self, other: &Mp) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Mp {
    fn cmp(&self, y: &Mp) -> Ordering {
        let sx = sign(self);
        let sy = sign(y);
        if sx != sy {
            return sx.cmp(&sy);
        }
        if sx == 0 {
            return Ordering::Equal;
        }
        let mag = match (self.inf, y.inf) {
            (true, true) => Ordering::Equal,
            (true, false) => Ordering::Greater,
            (false, true) => Ordering::Less,
            (false, false) => {
                let (tx, ty) = (self.top(), y.top());
                if tx != ty {
                    tx.cmp(&ty)
                } else {
                    // equal tops: the shifts are below MAX_PREC bits
                    let need = limbs_for(self.man.bits().max(y.man.bits()));
                    with_work!(need, cmp_mag_in(self, y))
                }
            }
        };
        if sx < 0 {
            mag.reverse()
        } else {
            mag
        }
    }
}

fn sign(x: &Mp) -> i8 {
    if x.is_positive() {
        1
    } else if x.is_negative() {
        -1
    } else {
        0
    }
}

impl core::fmt::Debug for Mp {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.inf {
            return write!(f, "{}inf", if self.neg { "-" } else { "" });
        }
        write!(
            f,
            "{}{:#x}p{}",
            if self.neg { "-" } else { "" },
            self.mantissa(),
            self.exp
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mp(x: f64) -> Mp {
        Mp::from_f64(x).unwrap()
    }

    #[test]
    fn f64_round_trip_and_directed_conversion() {
        for &x in &[
            1.0,
            -2.5,
            0.1,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -3e-310,
            1e300,
        ] {
            let m = mp(x);
            assert_eq!(m.to_f64(Round::Down), x);
            assert_eq!(m.to_f64(Round::Up), x);
            assert_eq!(m.to_f64(Round::Near), x);
        }
        // 1 + 2^-60 lies strictly between 1 and next_up(1)
        let y = mp(1.0).add(&mp(2f64.powi(-60)), 200, Round::Near).unwrap();
        assert_eq!(y.to_f64(Round::Down), 1.0);
        assert_eq!(y.to_f64(Round::Up), 1.0f64.next_up());
        assert_eq!(y.to_f64(Round::Near), 1.0);
        let big = mp(f64::MAX).mul(&mp(2.0), 100, Round::Near);
        assert_eq!(big.to_f64(Round::Up), f64::INFINITY);
        assert_eq!(big.to_f64(Round::Down), f64::MAX);
        let tiny = mp(5e-324).mul(&mp(0.25), 100, Round::Near);
        assert_eq!(tiny.to_f64(Round::Down), 0.0);
        assert_eq!(tiny.to_f64(Round::Up), 5e-324);
    }

    #[test]
    fn directed_rounding_of_the_basic_operations() {
        // 1/3 at 10 bits: 1.010101010|10... 2^-2 -> down 682/2048, up 683/2048
        let t = mp(1.0).div(&mp(3.0), 10, Round::Down).unwrap();
        assert_eq!(
            t,
            Mp::from_parts(false, 341u32.into(), -10, 10, Round::Near)
        );
        let t = mp(1.0).div(&mp(3.0), 10, Round::Up).unwrap();
        assert_eq!(
            t,
            Mp::from_parts(false, 683u32.into(), -11, 10, Round::Near)
        );
        let t = mp(-1.0).div(&mp(3.0), 10, Round::Up).unwrap();
        assert_eq!(t, Mp::from_parts(true, 341u32.into(), -10, 10, Round::Near));
        for d in [3u64, 7, 10, u64::MAX] {
            for mode in [Round::Down, Round::Up, Round::Near] {
                let a = mp(-2.5).div(&Mp::from_parts(false, d.into(), 0, 64, mode), 100, mode);
                assert_eq!(mp(-2.5).div_u64(d, 100, mode), a);
            }
        }
        // exact results are not moved
        assert_eq!(mp(3.0).mul(&mp(7.0), 5, Round::Up), mp(21.0));
        assert_eq!(mp(9.0).sqrt(3, Round::Down).unwrap(), mp(3.0));
        // sqrt 2 at 8 bits: 1.0110101|0000010... -> [181/128, 182/128]
        assert_eq!(
            mp(2.0).sqrt(8, Round::Down).unwrap(),
            Mp::from_parts(false, 181u32.into(), -7, 8, Round::Near)
        );
        assert_eq!(
            mp(2.0).sqrt(8, Round::Up).unwrap(),
            Mp::from_parts(false, 182u32.into(), -7, 8, Round::Near)
        );
        // far apart sums
        let one = mp(1.0);
        let e = mp(1e-300);
        assert_eq!(one.add(&e, 100, Round::Down).unwrap(), one);
        assert!(one.add(&e, 100, Round::Up).unwrap() > one);
        assert!(one.sub(&e, 100, Round::Down).unwrap() < one);
        assert_eq!(one.sub(&e, 100, Round::Up).unwrap(), one);
        assert_eq!(one.add(&e, 100, Round::Near).unwrap(), one);
        // ties to even: 1 + 2^-10 at 10 bits is a tie between 1 and 1 + 2^-9
        let t = one.add(&mp(2f64.powi(-10)), 10, Round::Near).unwrap();
        assert_eq!(t, one);
        let t = mp(1.0 + 2f64.powi(-9))
            .add(&mp(2f64.powi(-10)), 10, Round::Near)
            .unwrap();
        assert_eq!(t, mp(1.0 + 2f64.powi(-8)));
    }

    #[test]
    fn ordering_floor_ceil_mod4() {
        assert!(mp(-2.0) < mp(-1.5));
        assert!(Mp::infinity(true) < mp(-1e300));
        assert!(mp(0.0) < mp(5e-324));
        assert_eq!(mp(2.5).floor(), mp(2.0));
        assert_eq!(mp(-2.5).floor(), mp(-3.0));
        assert_eq!(mp(-2.5).ceil(), mp(-2.0));
        assert_eq!(mp(7.0).integer_mod4(), 3);
        assert_eq!(mp(-7.0).integer_mod4(), 1);
        assert_eq!(mp(2f64.powi(80)).integer_mod4(), 0);
        assert_eq!(mp(-6.0).integer_mod4(), 2);
    }

    #[test]
    fn decimal_printing_is_directed() {
        let third = mp(1.0).div(&mp(3.0), 200, Round::Down).unwrap();
        assert_eq!(to_decimal(&third, 5, false), "3.3333e-1");
        assert_eq!(to_decimal(&third, 5, true), "3.3334e-1");
        assert_eq!(to_decimal(&third.neg(), 5, false), "-3.3334e-1");
        assert_eq!(to_decimal(&mp(1.0), 5, true), "1e0");
        assert_eq!(to_decimal(&mp(0.1), 3, false), "1e-1");
        assert_eq!(to_decimal(&mp(0.1), 3, true), "1.01e-1");
        assert_eq!(
            to_decimal(&mp(1e300), 20, false),
            "1.0000000000000000525e300"
        );
        let (n, d, e) = parse_decimal("-12.5e-3").unwrap();
        assert!(n);
        assert_eq!(d, BigUint::from(125u32));
        assert_eq!(e, -4);
        assert!(parse_decimal("1e").is_none());
        assert!(parse_decimal(".").is_none());
        assert!(parse_decimal("1.2.3").is_none());
        let x = decimal_to_mp(false, &BigUint::from(1u32), -1, 53, Round::Near);
        assert_eq!(x, mp(0.1));
    }
}
