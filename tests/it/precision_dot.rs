//! The fused dot product of arbitrary precision intervals (`MpInterval::dot_acc`, spec
//! (12.2.8)) against exact rational arithmetic (`num-bigint`): each end on its side of the
//! exact end of the range, at most one step of the precision outside the tightest, and never
//! wider than the term-by-term computation it replaces; at the extremes: carries and borrows
//! through every limb, cancellation to zero, the largest and smallest exponents, subnormal
//! doubles, sums one unit from a rounding boundary.

use crate::common::Gen;
use dalembert::precision::mp::{Mp, MpInterval, Round};
use num_bigint::{BigInt, BigUint, Sign};

/// Values are compared as integers scaled by `2^SCALE` (every exponent of the random tests is
/// above `-SCALE / 2`).
const SCALE: i64 = 8000;

fn scaled(m: &Mp) -> BigInt {
    let sign = if m.is_negative() {
        Sign::Minus
    } else {
        Sign::Plus
    };
    let man = BigInt::from_biguint(sign, m.mantissa());
    let s = m.exponent() + SCALE;
    assert!(s >= 0);
    man << (s as u64)
}

/// `n 2^-SCALE` rounded to `p` bits in direction `mode`.
fn round_scaled(n: &BigInt, p: u32, mode: Round) -> Mp {
    Mp::from_parts(
        n.sign() == Sign::Minus,
        n.magnitude().clone(),
        -SCALE,
        p,
        mode,
    )
}

/// The next `p`-bit number beyond `x` in direction `mode` (`x` nonzero).
fn next(x: &Mp, p: u32, mode: Round) -> Mp {
    let tiny = Mp::from_parts(false, BigUint::from(1u32), x.top() - 4 * p as i64, p, mode);
    match mode {
        Round::Up => x.add(&tiny, p, Round::Up).unwrap(),
        _ => x.sub(&tiny, p, Round::Down).unwrap(),
    }
}

/// The term-by-term computation the fused product replaces: each product and sum rounded.
fn stepwise(acc: &MpInterval, neg: bool, pairs: &[(MpInterval, MpInterval)]) -> MpInterval {
    let mut s = MpInterval::from_f64(0.0, acc.prec());
    for (x, y) in pairs {
        if x.is_exact_zero() || y.is_exact_zero() {
            continue;
        }
        s = x.mul_add(y, &s);
    }
    if neg {
        acc.sub_ref(&s)
    } else {
        acc.add_ref(&s)
    }
}

fn dot(acc: &MpInterval, neg: bool, pairs: &[(MpInterval, MpInterval)]) -> MpInterval {
    let p = acc.prec();
    MpInterval::dot_acc(acc, neg, pairs.iter().map(|(x, y)| (x, y)), p).expect("bounded")
}

/// The exact ends of `acc + sum x y` (`acc - sum` when `neg`), scaled.
fn exact_ends(acc: &MpInterval, neg: bool, pairs: &[(MpInterval, MpInterval)]) -> (BigInt, BigInt) {
    let (mut lo, mut hi) = (scaled(acc.inf()), scaled(acc.sup()));
    for (x, y) in pairs {
        let c = [
            scaled(x.inf()) * scaled(y.inf()),
            scaled(x.inf()) * scaled(y.sup()),
            scaled(x.sup()) * scaled(y.inf()),
            scaled(x.sup()) * scaled(y.sup()),
        ];
        // exact: every product's exponent is above -SCALE
        let mn = c.iter().min().unwrap() >> (SCALE as u64);
        let mx = c.iter().max().unwrap() >> (SCALE as u64);
        if neg {
            lo -= &mx;
            hi -= &mn;
        } else {
            lo += &mn;
            hi += &mx;
        }
    }
    (lo, hi)
}

/// Awkward numbers from the stream: all-ones and single-bit significands, random limbs,
/// zeros, exponents from `2^-300` to `2^300`.
impl Gen {
    fn mp(&mut self, p: u32) -> Mp {
        let r = self.next();
        let bits = 1 + (self.next() % p as u64) as u32;
        let man = match r % 6 {
            0 => return Mp::zero(),
            1 => (BigUint::from(1u32) << bits) - 1u32,
            2 => BigUint::from(1u32) << (bits - 1),
            _ => {
                let mut m = BigUint::from(0u32);
                for _ in 0..bits.div_ceil(64) {
                    m = (m << 64u32) + self.next();
                }
                (m >> (64 * bits.div_ceil(64) - bits)) | (BigUint::from(1u32) << (bits - 1))
            }
        };
        let e = (self.next() % 600) as i64 - 300 - bits as i64;
        Mp::from_parts(self.next() & 1 == 0, man, e, p, Round::Near)
    }

    fn interval(&mut self, p: u32) -> MpInterval {
        let a = self.mp(p);
        match self.next() % 5 {
            0 => MpInterval::point(&a, p),
            // symmetric about 0 (a product's ends then need no comparison of products)
            4 => MpInterval::new(&a.abs().neg(), &a.abs(), p).unwrap(),
            1 => {
                // a narrow interval: a and a number near it
                let d = Mp::from_parts(
                    false,
                    BigUint::from(self.next()),
                    a.top() - p as i64,
                    p,
                    Round::Near,
                );
                let b = a.add(&d, p, Round::Up).unwrap();
                MpInterval::new(&a.min(b), &a.max(b), p).unwrap()
            }
            _ => {
                let b = self.mp(p);
                MpInterval::new(&a.min(b), &a.max(b), p).unwrap()
            }
        }
    }
}

/// The fused product of `acc` and `pairs` contains the exact range, is no wider than the
/// stepwise one, and each end is at most one step of the precision outside the tightest;
/// returns how many ends are the tightest.
fn check(acc: &MpInterval, neg: bool, pairs: &[(MpInterval, MpInterval)]) -> usize {
    let p = acc.prec();
    let r = dot(acc, neg, pairs);
    let (lo, hi) = exact_ends(acc, neg, pairs);
    assert!(scaled(r.inf()) <= lo && hi <= scaled(r.sup()), "{r}");
    let old = stepwise(acc, neg, pairs);
    assert!(r.subset(&old), "{r} wider than {old}");
    tight_ends(&r, &lo, &hi, p)
}

/// Each end of `r` at most one step of the precision `p` outside the tightest rounding of
/// the exact end (`lo`, `hi`, scaled); returns how many ends are the tightest.
fn tight_ends(r: &MpInterval, lo: &BigInt, hi: &BigInt, p: u32) -> usize {
    let mut tight = 0;
    for (end, e, mode) in [(r.inf(), &lo, Round::Down), (r.sup(), &hi, Round::Up)] {
        let t = round_scaled(e, p, mode);
        if *end == t {
            tight += 1;
            continue;
        }
        // t = 0: the ends cancel exactly; the window's dropped bits leave at most a unit of
        // its lowest bit (below 2^-(2 p) of the largest term), tested in
        // carries_and_borrows_run_through_every_limb with exact terms
        if t.is_zero() {
            continue;
        }
        let one_off = next(&t, p, mode);
        assert!(
            if mode == Round::Down {
                *end >= one_off
            } else {
                *end <= one_off
            },
            "{r} vs tightest {t:?}"
        );
    }
    tight
}

#[test]
fn random_dot_products_against_exact_rationals() {
    let mut g = Gen(46);
    let mut tight = 0;
    for case in 0..1500 {
        let p = [113u32, 160, 192, 256, 320, 512, 1024][case % 7];
        let n = 1 + (g.next() % 24) as usize;
        let acc = g.interval(p);
        let pairs: Vec<_> = (0..n).map(|_| (g.interval(p), g.interval(p))).collect();
        let neg = g.next() & 1 == 0;
        tight += check(&acc, neg, &pairs);
    }
    // almost every end is the tightest (one rounding of the exact sum)
    assert!(tight > 2800, "{tight}");
}

fn pt(x: &Mp, p: u32) -> MpInterval {
    MpInterval::point(x, p)
}

fn two(k: i64) -> Mp {
    Mp::from_i64(1).ldexp(k, Round::Near)
}

/// `1 - 2^-p`: every bit of a `p`-bit significand set.
fn below_one(p: u32) -> Mp {
    Mp::from_parts(
        false,
        (BigUint::from(1u32) << p) - 1u32,
        -(p as i64),
        p,
        Round::Near,
    )
}

#[test]
fn carries_and_borrows_run_through_every_limb() {
    for p in [128u32, 192, 320, 576, 1024] {
        // (1 - 2^-p) + 2^-p = 1: a carry out of every limb of the window
        let ones = below_one(p);
        let one = pt(&Mp::from_i64(1), p);
        let r = dot(&pt(&two(-(p as i64)), p), false, &[(pt(&ones, p), one)]);
        assert_eq!(r, one, "{p}");
        // 1 - 2^-p: a borrow through every limb, exact
        let r = dot(&one, true, &[(pt(&two(-(p as i64)), p), one)]);
        assert_eq!(r, pt(&ones, p), "{p}");
        // cancellation to zero: a b - a b = 0 exactly, with a b of 2 p bits
        let a = pt(&ones, p);
        let b = pt(&ones.neg(), p);
        let r = dot(&MpInterval::from_f64(0.0, p), false, &[(a, a), (a, b)]);
        assert!(r.is_exact_zero(), "{p}: {r}");
    }
}

#[test]
fn extreme_exponents_and_subnormal_doubles() {
    let p = 256;
    let lim = dalembert::precision::mp_float::EXP_LIMIT;
    let zero = MpInterval::from_f64(0.0, p);
    // beyond the largest exponent: the upper end overflows to +inf, the lower stays finite
    let big = pt(&two(lim - 2), p);
    let r = dot(&zero, false, &[(big, big)]);
    assert!(r.sup().is_infinite() && r.inf().is_finite() && r.inf().is_positive());
    assert_eq!(r, stepwise(&zero, false, &[(big, big)]));
    // below the smallest: [0, 2^-EXP_LIMIT]
    let small = pt(&two(-lim + 1), p);
    let r = dot(&zero, false, &[(small, small)]);
    assert!(r.inf().is_zero() && *r.sup() == Mp::min_positive(), "{r:?}");
    // subnormal doubles: the tightest ends
    let f = |x: f64| MpInterval::from_f64(x, p);
    let pairs = [(f(5e-324), f(-3e-310)), (f(2.2e-310), f(1e300))];
    assert_eq!(check(&f(1.0), false, &pairs), 2);
    assert_eq!(check(&f(1.0), true, &pairs), 2);
    assert_eq!(check(&f(0.0), false, &[(f(5e-324), f(-5e-324))]), 2);
    // terms 2^2000 apart: [2^1000, 2^1000 + one unit]
    let r = dot(
        &pt(&two(1000), p),
        false,
        &[(pt(&two(-500), p), pt(&two(-500), p))],
    );
    assert_eq!(*r.inf(), two(1000));
    assert_eq!(*r.sup(), next(&two(1000), p, Round::Up));
    // and the small one first, the big one after (the window moves up)
    let r = dot(
        &pt(&two(-1000), p),
        false,
        &[(pt(&two(500), p), pt(&two(500), p))],
    );
    assert_eq!(*r.inf(), two(1000));
    assert_eq!(*r.sup(), next(&two(1000), p, Round::Up));
}

#[test]
fn sums_one_unit_from_a_rounding_boundary() {
    for p in [113u32, 160, 256, 512, 1024] {
        let one = pt(&Mp::from_i64(1), p);
        let u = two(1 - p as i64); // one unit of 1
                                   // 1 + u/2 is a tie: [1, 1 + u]
        let r = dot(&one, false, &[(pt(&u, p), pt(&two(-1), p))]);
        assert_eq!(
            (*r.inf(), *r.sup()),
            (Mp::from_i64(1), next(&Mp::from_i64(1), p, Round::Up))
        );
        // 1 + u exactly
        let r = dot(&one, false, &[(pt(&u, p), pt(&Mp::from_i64(1), p))]);
        assert_eq!(r.inf(), r.sup());
        // 1 + u - u 2^-p: just below the boundary 1 + u
        let r = dot(
            &one,
            false,
            &[
                (pt(&u, p), pt(&Mp::from_i64(1), p)),
                (pt(&u, p), pt(&two(-(p as i64)).neg(), p)),
            ],
        );
        assert_eq!(
            (*r.inf(), *r.sup()),
            (Mp::from_i64(1), next(&Mp::from_i64(1), p, Round::Up)),
            "{p}"
        );
    }
}

#[test]
fn unbounded_or_empty_operands_are_left_to_the_stepwise_path() {
    let p = 160;
    let one = MpInterval::from_f64(1.0, p);
    let all = MpInterval::entire(p);
    assert!(MpInterval::dot_acc(&one, false, [(&one, &all)].into_iter(), p).is_none());
    assert!(MpInterval::dot_acc(&all, false, [(&one, &one)].into_iter(), p).is_none());
    let e = MpInterval::empty(p);
    assert!(MpInterval::dot_acc(&one, false, [(&e, &one)].into_iter(), p).is_none());
    // an exactly zero factor is skipped, as the stepwise path does
    let z = MpInterval::from_f64(0.0, p);
    assert_eq!(
        MpInterval::dot_acc(&one, false, [(&z, &all)].into_iter(), p),
        Some(one)
    );
}

/// Products of two intervals holding 0 inside whose ends are close in magnitude: the ends of
/// each product are decided by their leading bits or, when those cannot tell, exactly.
#[test]
fn straddling_products_with_close_ends() {
    let mut g = Gen(1_046);
    let mut tight = 0;
    for case in 0..1500 {
        let p = [113u32, 160, 256, 512, 1024][case % 5];
        let end = |g: &mut Gen| {
            let bits = 1 + (g.next() % p as u64) as u32;
            let mut m = BigUint::from(0u32);
            for _ in 0..bits.div_ceil(64) {
                m = (m << 64u32) + g.next();
            }
            let m = (m >> (64 * bits.div_ceil(64) - bits)) | (BigUint::from(1u32) << (bits - 1));
            // magnitudes in [1/2, 2): the products' tops at most 1 apart, often equal
            let e = -(bits as i64) + (g.next() % 2) as i64;
            Mp::from_parts(false, m, e, p, Round::Near)
        };
        let straddle = |g: &mut Gen| {
            let (a, b) = (end(g), end(g));
            MpInterval::new(&a.neg(), &b, p).unwrap()
        };
        let acc = MpInterval::from_f64(0.0, p);
        let n = 1 + (g.next() % 4) as usize;
        let pairs: Vec<_> = (0..n)
            .map(|_| (straddle(&mut g), straddle(&mut g)))
            .collect();
        tight += check(&acc, g.next() & 1 == 0, &pairs);
    }
    assert!(tight > 2800, "{tight}");
}

/// A weighted term: `w x` and `y`.
type Weighted = (u64, MpInterval, MpInterval);

fn weighted_dot(acc: &MpInterval, neg: bool, terms: &[Weighted]) -> MpInterval {
    let p = acc.prec();
    MpInterval::dot_acc_weighted(acc, neg, terms.iter().map(|(w, x, y)| (x, y, *w)), p)
        .expect("bounded")
}

/// The term-by-term computation of the Taylor recurrences (2.6)-(2.12) that the weighted
/// product replaces: `w x` rounded outward, then each multiply-add rounded.
fn weighted_stepwise(acc: &MpInterval, neg: bool, terms: &[Weighted]) -> MpInterval {
    let p = acc.prec();
    let mut s = *acc;
    for (w, x, y) in terms {
        let wx = MpInterval::from_f64(*w as f64, p).mul_ref(x);
        let wx = if neg { wx.neg() } else { wx };
        s = wx.mul_add(y, &s);
    }
    s
}

/// Each end of the weighted product on its side of the exact end of the range (`w x_j y_j`
/// with `w x_j` exact), at most one step of the precision outside the tightest; returns how
/// many ends are the tightest.
fn check_weighted(acc: &MpInterval, neg: bool, terms: &[Weighted]) -> usize {
    let p = acc.prec();
    let r = weighted_dot(acc, neg, terms);
    let scaled_pairs: Vec<_> = terms.iter().map(|(_, x, y)| (*x, *y)).collect();
    // the exact ends, each term's candidates times its weight (w > 0 keeps min and max)
    let (mut lo, mut hi) = (scaled(acc.inf()), scaled(acc.sup()));
    for ((w, _, _), (x, y)) in terms.iter().zip(&scaled_pairs) {
        let c = [
            scaled(x.inf()) * scaled(y.inf()),
            scaled(x.inf()) * scaled(y.sup()),
            scaled(x.sup()) * scaled(y.inf()),
            scaled(x.sup()) * scaled(y.sup()),
        ];
        let mn = (c.iter().min().unwrap() * BigInt::from(*w)) >> (SCALE as u64);
        let mx = (c.iter().max().unwrap() * BigInt::from(*w)) >> (SCALE as u64);
        if neg {
            lo -= &mx;
            hi -= &mn;
        } else {
            lo += &mn;
            hi += &mx;
        }
    }
    assert!(scaled(r.inf()) <= lo && hi <= scaled(r.sup()), "{r}");
    tight_ends(&r, &lo, &hi, p)
}

/// The weighted fused product (spec (12.2.9)) against exact rationals, with the weights of
/// the recurrences (1 to 400) and with weights that carry out of a limb (`2^64 - 1`); no
/// wider than the term-by-term recurrence with the weighted factor rounded; with every
/// weight 1 it is the unweighted product.
#[test]
fn weighted_dot_products_against_exact_rationals() {
    let mut g = Gen(4_612);
    let mut tight = 0;
    for case in 0..1400 {
        let p = [113u32, 160, 192, 256, 320, 512, 1024][case % 7];
        let n = 1 + (g.next() % 24) as usize;
        let acc = g.interval(p);
        let big = case % 5 == 0;
        let terms: Vec<Weighted> = (0..n)
            .map(|_| {
                let w = if big {
                    [u64::MAX, 1 << 63, 3][(g.next() % 3) as usize]
                } else {
                    1 + g.next() % 400
                };
                (w, g.interval(p), g.interval(p))
            })
            .collect();
        let neg = g.next() & 1 == 0;
        tight += check_weighted(&acc, neg, &terms);
        if !big {
            let old = weighted_stepwise(&acc, neg, &terms);
            let r = weighted_dot(&acc, neg, &terms);
            assert!(r.subset(&old), "{r} wider than {old}");
        }
        let ones: Vec<_> = terms.iter().map(|(_, x, y)| (1, *x, *y)).collect();
        let pairs: Vec<_> = terms.iter().map(|(_, x, y)| (*x, *y)).collect();
        assert_eq!(weighted_dot(&acc, neg, &ones), dot(&acc, neg, &pairs));
    }
    assert!(tight > 2600, "{tight}");
}

/// Weights at the extremes: a carry of the weight out of every limb of the product, the
/// window's lowest bit, cancellation to zero, a zero weight (the term is 0).
#[test]
fn weighted_carries_cancellation_and_zero_weights() {
    for p in [128u32, 192, 320, 576, 1024] {
        let ones = below_one(p);
        let one = pt(&Mp::from_i64(1), p);
        let zero = MpInterval::from_f64(0.0, p);
        // (2^64 - 1)(1 - 2^-p) + (2^64 - 1) 2^-p = 2^64 - 1 exactly
        let w = u64::MAX;
        let r = weighted_dot(
            &zero,
            false,
            &[(w, pt(&ones, p), one), (w, pt(&two(-(p as i64)), p), one)],
        );
        let want = Mp::from_parts(false, BigUint::from(w), 0, p, Round::Near);
        assert_eq!((*r.inf(), *r.sup()), (want, want), "{p}");
        // 3 a b - a (3 b) = 0 exactly
        let a = pt(&ones, p);
        let three_b = pt(&ones.mul(&Mp::from_i64(3), 2 * p, Round::Near), 2 * p);
        let r = weighted_dot(&zero, false, &[(3, a, a), (1, a, three_b.neg())]);
        assert!(r.is_exact_zero(), "{p}: {r}");
        // a weight of 0 leaves the sum unchanged
        let r = weighted_dot(&one, true, &[(0, a, a)]);
        assert_eq!(r, one);
    }
}
