//! The fixed-limb `Mp` (spec (12.2.0), (12.2.1)) against exact rational arithmetic on big
//! integers (`num-bigint`, independent of the limbs code): every basic operation, rounded down
//! and up, brackets the exact value, and the two ends are equal (exact value representable)
//! or adjacent `prec`-bit numbers (tightest, so each end is at most one ulp outside the exact
//! value), at the extremes: carries through every limb, cancellation to zero, the largest and
//! smallest exponents, subnormal f64 inputs, results one ulp from a rounding boundary.

use crate::common::Gen;
use dalembert::precision::mp::{Mp, Round};
use dalembert::precision::mp_float::{EXP_LIMIT, MAX_PREC};
use num_bigint::{BigInt, BigUint, Sign};
use std::cmp::Ordering;

/// An exact dyadic `m 2^e`.
#[derive(Clone, Debug)]
struct Dy(BigInt, i64);

fn dy(x: &Mp) -> Dy {
    assert!(x.is_finite());
    let s = if x.is_negative() {
        Sign::Minus
    } else {
        Sign::Plus
    };
    Dy(BigInt::from_biguint(s, x.mantissa()), x.exponent())
}

fn cmp(a: &Dy, b: &Dy) -> Ordering {
    // exponents of the compared numbers differ by at most a few thousand here
    let e = a.1.min(b.1);
    let x = &a.0 << ((a.1 - e) as u64);
    let y = &b.0 << ((b.1 - e) as u64);
    x.cmp(&y)
}

fn mul(a: &Dy, b: &Dy) -> Dy {
    Dy(&a.0 * &b.0, a.1 + b.1)
}

fn add(a: &Dy, b: &Dy) -> Dy {
    let e = a.1.min(b.1);
    Dy(
        (&a.0 << ((a.1 - e) as u64)) + (&b.0 << ((b.1 - e) as u64)),
        e,
    )
}

/// `2^(top(max(|lo|, |hi|)) - prec)`: the spacing of `prec`-bit numbers there.
fn ulp(lo: &Mp, hi: &Mp, prec: u32) -> Dy {
    let t = lo.abs().max(hi.abs()).top();
    Dy(BigInt::from(1), t - prec as i64)
}

/// `lo <= v <= hi` where `below(d)` says `d < v` ... given as `side(d)`: the sign of `d - v`.
fn check(lo: &Mp, hi: &Mp, prec: u32, side: impl Fn(&Dy) -> Ordering, what: &str) {
    let (l, h) = (dy(lo), dy(hi));
    assert!(lo.significant_bits() <= prec as u64 && hi.significant_bits() <= prec as u64);
    assert_ne!(side(&l), Ordering::Greater, "{what}: lower end above");
    assert_ne!(side(&h), Ordering::Less, "{what}: upper end below");
    if side(&l) == Ordering::Equal {
        assert_eq!(
            cmp(&l, &h),
            Ordering::Equal,
            "{what}: exact but ends differ"
        );
    } else {
        // adjacent: hi - lo is at most one spacing at the larger magnitude
        let w = add(&h, &Dy(-l.0.clone(), l.1));
        assert_ne!(
            cmp(&w, &ulp(lo, hi, prec)),
            Ordering::Greater,
            "{what}: {lo:?} {hi:?} not adjacent"
        );
    }
}

/// Awkward significands and exponents from the stream.
impl Gen {
    /// A number of at most `prec` bits: all ones, a single bit, ones with a hole, random.
    fn mp_spanning(&mut self, prec: u32, exp_span: i64) -> Mp {
        let bits = 1 + self.next() % prec as u64;
        let man = match self.next() % 5 {
            0 => (BigUint::from(1u32) << bits) - 1u32,
            1 => BigUint::from(1u32) << (bits - 1),
            2 => ((BigUint::from(1u32) << bits) - 1u32) ^ (BigUint::from(1u32) << (bits / 2)),
            _ => {
                let words: Vec<u64> = (0..bits.div_ceil(64)).map(|_| self.next()).collect();
                let mut w32 = vec![];
                for d in words {
                    w32.push(d as u32);
                    w32.push((d >> 32) as u32);
                }
                BigUint::new(w32) >> (64 * bits.div_ceil(64) - bits)
            }
        };
        let e = (self.next() % (2 * exp_span as u64 + 1)) as i64 - exp_span;
        Mp::from_parts(self.next().is_multiple_of(2), man, e, prec, Round::Near)
    }
}

const PRECS: [u32; 6] = [107, 160, 192, 256, 512, 1024];

#[test]
fn add_sub_mul_div_sqrt_bracket_the_exact_value_tightly() {
    let mut g = Gen(46);
    for &p in &PRECS {
        for i in 0..300 {
            let span = if i % 3 == 0 { 3 } else { 300 };
            let (a, b) = (g.mp_spanning(p, span), g.mp_spanning(p, span));
            let (da, db) = (dy(&a), dy(&b));
            // sum: far-apart operands stay within a few thousand bits of exponent here
            let s = add(&da, &db);
            check(
                &a.add(&b, p, Round::Down).unwrap(),
                &a.add(&b, p, Round::Up).unwrap(),
                p,
                |d| cmp(d, &s),
                "add",
            );
            let nb = Dy(-db.0.clone(), db.1);
            let s = add(&da, &nb);
            check(
                &a.sub(&b, p, Round::Down).unwrap(),
                &a.sub(&b, p, Round::Up).unwrap(),
                p,
                |d| cmp(d, &s),
                "sub",
            );
            let m = mul(&da, &db);
            check(
                &a.mul(&b, p, Round::Down),
                &a.mul(&b, p, Round::Up),
                p,
                |d| cmp(d, &m),
                "mul",
            );
            if !b.is_zero() {
                // d < a / b  <=>  d b < a for b > 0 (reversed for b < 0)
                let flip = b.is_negative();
                let q = |d: &Dy| {
                    let o = cmp(&mul(d, &db), &da);
                    if flip {
                        o.reverse()
                    } else {
                        o
                    }
                };
                check(
                    &a.div(&b, p, Round::Down).unwrap(),
                    &a.div(&b, p, Round::Up).unwrap(),
                    p,
                    q,
                    "div",
                );
                let k = g.next() | 1;
                let dk = Dy(BigInt::from(k), 0);
                check(
                    &a.div_u64(k, p, Round::Down).unwrap(),
                    &a.div_u64(k, p, Round::Up).unwrap(),
                    p,
                    |d| cmp(&mul(d, &dk), &da),
                    "div_u64",
                );
            }
            let x = a.abs();
            // d < sqrt(x) <=> d^2 < x for d >= 0
            check(
                &x.sqrt(p, Round::Down).unwrap(),
                &x.sqrt(p, Round::Up).unwrap(),
                p,
                |d| cmp(&mul(d, d), &dy(&x)),
                "sqrt",
            );
            // nearest lies at one of the directed results
            let n = a.mul(&b, p, Round::Near);
            assert!(n == a.mul(&b, p, Round::Down) || n == a.mul(&b, p, Round::Up));
        }
    }
}

#[test]
fn carries_through_every_limb_and_cancellation_to_zero() {
    for &p in &PRECS {
        let ones = Mp::from_parts(false, (BigUint::from(1u32) << p) - 1u32, 0, p, Round::Near);
        let one = Mp::from_i64(1);
        // (2^p - 1) + 1 = 2^p: one bit after a carry through every limb
        let s = ones.add(&one, p, Round::Down).unwrap();
        assert_eq!(s, Mp::from_i64(1).ldexp(p as i64, Round::Near));
        assert_eq!(s.significant_bits(), 1);
        // 2^p - (2^p - 1) = 1: borrows through every limb
        assert_eq!(s.sub(&ones, p, Round::Up).unwrap(), one);
        // x - x = 0 exactly in every direction, at every size
        for mode in [Round::Down, Round::Up, Round::Near] {
            let z = ones.sub(&ones, p, mode).unwrap();
            assert!(z.is_zero() && !z.is_negative());
        }
        // (2^p - 1)^2 = 2^2p - 2^(p+1) + 1 rounds to 2^2p - 2^(p+1) down, 2^2p - 2^p... up
        let sq_d = ones.mul(&ones, p, Round::Down);
        let sq_u = ones.mul(&ones, p, Round::Up);
        let exact = Dy(BigInt::from((BigUint::from(1u32) << p) - 1u32).pow(2), 0);
        assert_eq!(cmp(&dy(&sq_d), &exact), Ordering::Less);
        assert_eq!(cmp(&dy(&sq_u), &exact), Ordering::Greater);
        let w = add(&dy(&sq_u), &Dy(-dy(&sq_d).0, dy(&sq_d).1));
        assert_eq!(cmp(&w, &Dy(BigInt::from(1), p as i64)), Ordering::Equal);
        // the division undoes the product's exact part: (2^p - 1) / (2^p - 1) = 1 exactly
        assert_eq!(ones.div(&ones, p, Round::Up).unwrap(), one);
        assert_eq!(s.sqrt(p, Round::Down).unwrap().top(), p as i64 / 2 + 1);
    }
}

#[test]
fn one_ulp_from_a_rounding_boundary() {
    for &p in &PRECS {
        let one = Mp::from_i64(1);
        let half_ulp = one.ldexp(-(p as i64), Round::Near);
        // 1 + 2^-p: the tie between 1 and 1 + 2^(1-p); nearest goes to even (1)
        assert_eq!(one.add(&half_ulp, p, Round::Near).unwrap(), one);
        assert_eq!(one.add(&half_ulp, p, Round::Down).unwrap(), one);
        let up = one.add(&half_ulp, p, Round::Up).unwrap();
        assert_eq!(
            up,
            one.add(&half_ulp.ldexp(1, Round::Near), p, Round::Near)
                .unwrap()
        );
        // just above and just below the tie (2^-(p + 200) away, far below the last bit)
        let tiny = one.ldexp(-(p as i64) - 200, Round::Near);
        let above = half_ulp.add(&tiny, MAX_PREC, Round::Near).unwrap();
        let below = half_ulp.sub(&tiny, MAX_PREC, Round::Near).unwrap();
        assert_eq!(one.add(&above, p, Round::Near).unwrap(), up);
        assert_eq!(one.add(&below, p, Round::Near).unwrap(), one);
        assert_eq!(one.add(&below, p, Round::Up).unwrap(), up);
        assert_eq!(one.sub(&tiny, p, Round::Up).unwrap(), one);
        assert!(one.sub(&tiny, p, Round::Down).unwrap() < one);
        // the odd neighbour ties upward to the even one
        let odd = up;
        let t = odd.add(&half_ulp, p, Round::Near).unwrap();
        assert_eq!(t, odd.add(&half_ulp, p, Round::Up).unwrap());
    }
}

#[test]
fn largest_and_smallest_exponents_overflow_and_underflow_by_direction() {
    for &p in &PRECS {
        let max = Mp::max_value(p);
        let two = Mp::from_i64(2);
        assert!(max.mul(&two, p, Round::Up).is_infinite());
        assert_eq!(max.mul(&two, p, Round::Down), max);
        assert!(max.add(&max, p, Round::Up).unwrap().is_infinite());
        assert_eq!(max.add(&max, p, Round::Down), Some(max));
        assert_eq!(max.neg().mul(&two, p, Round::Up), max.neg());
        assert!(max.neg().mul(&two, p, Round::Down).is_infinite());
        assert_eq!(max.top(), EXP_LIMIT);
        let min = Mp::min_positive();
        let half = Mp::from_f64(0.5).unwrap();
        assert!(min.mul(&half, p, Round::Down).is_zero());
        assert_eq!(min.mul(&half, p, Round::Up), min);
        assert_eq!(min.neg().mul(&half, p, Round::Down), min.neg());
        assert_eq!(min.div(&max, p, Round::Up), Some(min));
        assert!(min.div(&max, p, Round::Down).unwrap().is_zero());
        assert!(max.div(&min, p, Round::Up).unwrap().is_infinite());
        assert_eq!(min.sqrt(p, Round::Down).unwrap().top(), -EXP_LIMIT / 2 + 1);
        // the largest times the smallest is exact: 2^0 scale
        let prod = max.mul(&min, p, Round::Down);
        assert_eq!(prod, max.mul(&min, p, Round::Up));
        assert!(prod < Mp::from_i64(1) && prod.top() == 0);
    }
}

/// The exact value of an f64 from its bits (independently of `Mp::from_f64`).
fn f64_exact(x: f64) -> Dy {
    let b = x.to_bits();
    let be = ((b >> 52) & 0x7ff) as i64;
    let frac = (b & ((1 << 52) - 1)) as i64;
    let (m, e) = if be == 0 {
        (frac, -1074)
    } else {
        (frac | (1 << 52), be - 1075)
    };
    Dy(BigInt::from(if b >> 63 == 1 { -m } else { m }), e)
}

#[test]
fn f64_conversions_are_exact_and_directed_through_the_subnormals() {
    let xs = [
        5e-324,
        -5e-324,
        2.2250738585072014e-308,
        2.225073858507201e-308,
        -3e-310,
        1.0,
        0.1,
        -f64::MAX,
        1e300,
    ];
    for &x in &xs {
        let m = Mp::from_f64(x).unwrap();
        assert_eq!(cmp(&dy(&m), &f64_exact(x)), Ordering::Equal, "{x}");
        for mode in [Round::Down, Round::Up, Round::Near] {
            assert_eq!(m.to_f64(mode), x);
        }
        // a quarter of the spacing of the doubles above |x| beside x: the directed
        // conversions step to the neighbouring doubles, the nearest one stays at x
        let q = Mp::from_i64(1).ldexp((m.top() - 55).max(-1076), Round::Near);
        let above = m.add(&q, MAX_PREC, Round::Near).unwrap();
        let below = m.sub(&q, MAX_PREC, Round::Near).unwrap();
        assert_eq!(above.to_f64(Round::Up), x.next_up(), "{x}");
        assert_eq!(above.to_f64(Round::Down), x, "{x}");
        assert_eq!(below.to_f64(Round::Down), x.next_down(), "{x}");
        assert_eq!(below.to_f64(Round::Up), x, "{x}");
        if x > 0.0 {
            assert_eq!(above.to_f64(Round::Near), x, "{x}");
        } else {
            assert_eq!(below.to_f64(Round::Near), x, "{x}");
        }
    }
    assert!(Mp::from_f64(f64::NAN).is_none());
    assert!(Mp::from_f64(f64::INFINITY).unwrap().is_infinite());
    // beyond the doubles: 2^1100 rounds to f64::MAX down, to infinity up
    let big = Mp::from_i64(1).ldexp(1100, Round::Near);
    assert_eq!(big.to_f64(Round::Down), f64::MAX);
    assert_eq!(big.to_f64(Round::Up), f64::INFINITY);
}

/// Asking for more bits than an `Mp` holds rounds at `MAX_PREC` bits, on the asked side.
#[test]
fn precisions_above_the_limbs_round_at_the_limit_on_their_side() {
    let one = Mp::from_i64(1);
    let three = Mp::from_i64(3);
    let lo = one.div(&three, 4 * MAX_PREC, Round::Down).unwrap();
    let hi = one.div(&three, 4 * MAX_PREC, Round::Up).unwrap();
    check(
        &lo,
        &hi,
        MAX_PREC,
        |d| cmp(&mul(d, &dy(&three)), &dy(&one)),
        "1/3",
    );
}

/// Double-double intervals convert with each end `hi + lo` rounded once outward: exact when it
/// fits, else adjacent numbers around it (a trailing double far below, subnormal, negative).
#[test]
fn double_double_conversions_are_outward_and_tight() {
    use dalembert::precision::dd::{Dd, DdInterval};
    use dalembert::precision::mp::MpInterval;
    let dds = [
        (1.0, 2f64.powi(-200)),
        (1.0, -2f64.powi(-200)),
        (-3.0, 5e-324),
        (0.1, 0.1 * 2f64.powi(-54)),
        (1e300, -1e283),
        (2f64.powi(-1000), 2f64.powi(-1060)),
        (f64::MAX, 0.0),
    ];
    for &p in &[107u32, 160, 256, 1024] {
        for &(h, l) in &dds {
            let d = Dd::new(h, l);
            let x = MpInterval::from_dd(DdInterval::new(d, d).unwrap(), p);
            let exact = add(&f64_exact(d.hi()), &f64_exact(d.lo()));
            check(x.inf(), x.sup(), p, |v| cmp(v, &exact), "from_dd");
        }
    }
    let wide = DdInterval::from_f64_pair(-1.0, 2.0).unwrap();
    let x = MpInterval::from_dd(wide, 160);
    assert_eq!(x, MpInterval::from_f64_pair(-1.0, 2.0, 160).unwrap());
}
