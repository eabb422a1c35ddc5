//! The double-double intervals against independent references: the mpmath table
//! tests/data/dd_reference.txt (containment AND a width bound for every line, compared
//! exactly), and property tests against exact dyadic arithmetic (spec (12.1)).

use core::cmp::Ordering;
use dalembert::precision::dd::{Dd, DdInterval};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

const TABLE: &str = include_str!("../data/dd_reference.txt");

/// `2^-104`: the unit of the width bounds.
const W: f64 = f64::from_bits(919 << 52);

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The exact sign of a sum of doubles (Shewchuk's Grow-Expansion with zero elimination: the
/// expansion is non-overlapping and increasing, so its sign is that of its last component).
fn exact_sign(terms: &[f64]) -> Ordering {
    let mut e: Vec<f64> = Vec::new();
    for &t in terms {
        assert!(t.is_finite());
        let mut q = t;
        let mut h = Vec::with_capacity(e.len() + 1);
        for &x in &e {
            let (s, err) = two_sum(q, x);
            if err != 0.0 {
                h.push(err);
            }
            q = s;
        }
        h.push(q);
        e = h;
    }
    match e.iter().rev().find(|x| **x != 0.0) {
        None => Ordering::Equal,
        Some(x) if *x > 0.0 => Ordering::Greater,
        _ => Ordering::Less,
    }
}

/// `x <= sum(parts)` exactly.
fn le(x: Dd, parts: &[f64]) -> bool {
    let mut t: Vec<f64> = parts.to_vec();
    t.push(-x.hi());
    t.push(-x.lo());
    exact_sign(&t) != Ordering::Less
}

/// `x >= sum(parts)` exactly.
fn ge(x: Dd, parts: &[f64]) -> bool {
    let mut t: Vec<f64> = parts.iter().map(|p| -p).collect();
    t.push(x.hi());
    t.push(x.lo());
    exact_sign(&t) != Ordering::Less
}

fn hex(s: &str) -> f64 {
    f64::from_bits(u64::from_str_radix(s, 16).expect("hex bits"))
}

fn eval(op: &str, a: Dd, b: Dd) -> DdInterval {
    let x = DdInterval::point(a);
    let y = DdInterval::point(b);
    let iv = || DdInterval::new(a, b).expect("ordered interval");
    match op {
        "const_pi" => DdInterval::pi(),
        "const_frac_pi_2" => DdInterval::frac_pi_2(),
        "const_ln2" => DdInterval::ln2(),
        "add" => x + y,
        "sub" => x - y,
        "mul" => x * y,
        "div" => x / y,
        "sqrt" => x.sqrt(),
        "exp" => x.exp(),
        "ln" => x.ln(),
        "atan" => x.atan(),
        "sinh" => x.sinh(),
        "cosh" => x.cosh(),
        "tanh" => x.tanh(),
        "asinh" => x.asinh(),
        "sin" => x.sin(),
        "cos" => x.cos(),
        "tan" => x.tan(),
        "sin_iv" => iv().sin(),
        "cos_iv" => iv().cos(),
        "tan_iv" => iv().tan(),
        "exp_iv" => iv().exp(),
        "ln_iv" => iv().ln(),
        "atan_iv" => iv().atan(),
        "sinh_iv" => iv().sinh(),
        "cosh_iv" => iv().cosh(),
        "tanh_iv" => iv().tanh(),
        "asinh_iv" => iv().asinh(),
        "sqrt_iv" => iv().sqrt(),
        _ => panic!("unknown op {op}"),
    }
}

/// Every line of the mpmath table: the enclosure contains the reference range exactly, and
/// its excess over that range (for a point argument: its width) is at most `tol * 2^-104 * |value| + 256 * 2^-1074` (the absolute term only matters
/// for subnormal values).
#[test]
fn mpmath_table_contained_and_tight() {
    let mut n = 0;
    let mut worst: Vec<(String, f64)> = Vec::new();
    for line in TABLE
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(f.len(), 17, "{line}");
        let a = Dd::new(hex(f[1]), hex(f[2]));
        let b = Dd::new(hex(f[3]), hex(f[4]));
        let l: Vec<f64> = f[6..10].iter().map(|s| hex(s)).collect();
        let u: Vec<f64> = f[11..15].iter().map(|s| hex(s)).collect();
        let tol: f64 = f[16].parse().expect("tol");
        let r = eval(f[0], a, b);
        assert!(!r.is_empty(), "{line}: empty");
        assert!(
            le(r.inf(), &l),
            "{line}: lower end {} above the reference",
            r.inf_decimal(40)
        );
        assert!(
            ge(r.sup(), &u),
            "{line}: upper end {} below the reference",
            r.sup_decimal(40)
        );
        // How far the ends lie outside the reference range (its width for a point argument).
        let width = ((l[0] - r.inf().hi()) + (l[1] - r.inf().lo()) + l[2])
            + ((r.sup().hi() - u[0]) + (r.sup().lo() - u[1]) - u[2]);
        let scale = l[0].abs().max(u[0].abs());
        let allowed = tol * W * scale + 256.0 * f64::from_bits(1);
        assert!(
            width <= allowed,
            "{line}: excess width {width:e} > {allowed:e} ({} ulps)",
            width / (W * scale)
        );
        worst.push((f[0].to_string(), width / (W * scale)));
        n += 1;
    }
    assert!(n > 300, "table too short: {n}");
}

/// The width of one arithmetic operation on points is a few units of `2^-104`.
#[test]
fn arithmetic_widths_are_a_few_ulps() {
    let x = DdInterval::from_decimal("0.7").unwrap().mid();
    let y = DdInterval::from_decimal("-1.3").unwrap().mid();
    let (px, py) = (DdInterval::point(x), DdInterval::point(y));
    for (name, r) in [
        ("add", px + py),
        ("sub", px - py),
        ("mul", px * py),
        ("div", px / py),
        ("sqrt", px.sqrt()),
    ] {
        let rel = r.wid_up() / (W * r.mag_up());
        assert!(rel <= 4.0, "{name}: {rel} units of 2^-104");
    }
}

/// An exact dyadic `num * 2^exp`.
#[derive(Clone, Copy, Debug)]
struct Dy {
    num: i128,
    exp: i32,
}

impl Dy {
    fn align(a: Dy, b: Dy) -> Option<(i128, i128, i32)> {
        let e = a.exp.min(b.exp);
        let an = a.num.checked_mul(1i128.checked_shl((a.exp - e) as u32)?)?;
        let bn = b.num.checked_mul(1i128.checked_shl((b.exp - e) as u32)?)?;
        if an.unsigned_abs() >= 1 << 100 || bn.unsigned_abs() >= 1 << 100 {
            return None;
        }
        Some((an, bn, e))
    }

    fn to_dd(self) -> Option<Dd> {
        if self.num.unsigned_abs() >= 1 << 105 {
            return None;
        }
        let hi = self.num as f64;
        let lo = (self.num - hi as i128) as f64;
        let s = 2f64.powi(self.exp);
        Some(Dd::new(hi * s, lo * s))
    }
}

#[derive(Clone, Debug)]
enum Expr {
    Leaf(i32, i32, i32), // [lo, hi] * 2^-8 and a point in it
    Add(Box<Expr>, Box<Expr>),
    Sub(Box<Expr>, Box<Expr>),
    Mul(Box<Expr>, Box<Expr>),
    Sqr(Box<Expr>),
    MulAdd(Box<Expr>, Box<Expr>, Box<Expr>),
}

fn expr() -> impl Strategy<Value = Expr> {
    let leaf = (-4096i32..4096, 0i32..64, 0i32..=64)
        .prop_map(|(lo, w, t)| Expr::Leaf(lo, lo + w, lo + w * t / 64));
    leaf.prop_recursive(3, 12, 3, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Expr::Add(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Expr::Sub(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Expr::Mul(Box::new(a), Box::new(b))),
            inner.clone().prop_map(|a| Expr::Sqr(Box::new(a))),
            (inner.clone(), inner.clone(), inner).prop_map(|(a, b, c)| Expr::MulAdd(
                Box::new(a),
                Box::new(b),
                Box::new(c)
            )),
        ]
    })
}

/// The expression over intervals, and exactly at the chosen points (None on i128 overflow).
fn run(e: &Expr) -> (DdInterval, Option<Dy>) {
    match e {
        Expr::Leaf(lo, hi, t) => {
            let s = 1.0 / 256.0;
            let iv = DdInterval::from_f64_pair(*lo as f64 * s, *hi as f64 * s).unwrap();
            (
                iv,
                Some(Dy {
                    num: *t as i128,
                    exp: -8,
                }),
            )
        }
        Expr::Add(a, b) | Expr::Sub(a, b) => {
            let ((x, p), (y, q)) = (run(a), run(b));
            let sub = matches!(e, Expr::Sub(..));
            let exact = p.zip(q).and_then(|(p, q)| {
                let (pn, qn, ex) = Dy::align(p, q)?;
                Some(Dy {
                    num: if sub { pn - qn } else { pn + qn },
                    exp: ex,
                })
            });
            (if sub { x - y } else { x + y }, exact)
        }
        Expr::Mul(a, b) => {
            let ((x, p), (y, q)) = (run(a), run(b));
            let exact = p.zip(q).and_then(|(p, q)| {
                Some(Dy {
                    num: p.num.checked_mul(q.num)?,
                    exp: p.exp + q.exp,
                })
            });
            (x * y, exact)
        }
        Expr::Sqr(a) => {
            let (x, p) = run(a);
            (
                x.sqr(),
                p.and_then(|p| {
                    Some(Dy {
                        num: p.num.checked_mul(p.num)?,
                        exp: 2 * p.exp,
                    })
                }),
            )
        }
        Expr::MulAdd(a, b, c) => {
            let ((x, p), (y, q), (z, r)) = (run(a), run(b), run(c));
            let exact = p.zip(q).zip(r).and_then(|((p, q), r)| {
                let m = Dy {
                    num: p.num.checked_mul(q.num)?,
                    exp: p.exp + q.exp,
                };
                let (mn, rn, ex) = Dy::align(m, r)?;
                Some(Dy {
                    num: mn + rn,
                    exp: ex,
                })
            });
            (x.mul_add(y, z), exact)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, rng_seed: RngSeed::Fixed(12), ..ProptestConfig::default() })]

    /// Random expressions over intervals contain the same expression evaluated exactly at
    /// any point of the leaves (exact dyadic arithmetic in i128).
    #[test]
    fn expressions_contain_exact_values(e in expr()) {
        let (iv, exact) = run(&e);
        let exact = exact.and_then(Dy::to_dd);
        prop_assume!(exact.is_some());
        let v = exact.unwrap();
        prop_assert!(iv.contains(v), "{e:?}: {iv} misses {v}");
    }

    /// Quotients and square roots of random dyadics, checked exactly: `lo * b <= a <= hi * b`
    /// and `lo^2 <= a <= hi^2` with the products expanded by TwoProd (exact here).
    #[test]
    fn quotients_and_roots_enclose(an in -1_000_000i64..1_000_000, bn in 1i64..1_000_000, sh in -30i32..30) {
        let a = an as f64 * 2f64.powi(sh);
        let b = bn as f64;
        let q = DdInterval::from_f64(a) / DdInterval::from_f64(b);
        let prod = |x: Dd, y: f64| -> Vec<f64> {
            let (p1, e1) = (x.hi() * y, x.hi().mul_add(y, -(x.hi() * y)));
            let (p2, e2) = (x.lo() * y, x.lo().mul_add(y, -(x.lo() * y)));
            vec![p1, e1, p2, e2]
        };
        let mut t = prod(q.inf(), b);
        t.push(-a);
        prop_assert!(exact_sign(&t) != Ordering::Greater);
        let mut t = prod(q.sup(), b);
        t.push(-a);
        prop_assert!(exact_sign(&t) != Ordering::Less);
        prop_assert!(q.wid_up() <= 6.0 * W * q.mag_up() + 1e-300);
        let r = DdInterval::from_f64(a.abs()).sqrt();
        let sq = |x: Dd| -> Vec<f64> {
            let (h, l) = (x.hi(), x.lo());
            let (p1, e1) = (h * h, h.mul_add(h, -(h * h)));
            let (p2, e2) = (2.0 * h * l, (2.0 * h).mul_add(l, -(2.0 * h * l)));
            let (p3, e3) = (l * l, l.mul_add(l, -(l * l)));
            vec![p1, e1, p2, e2, p3, e3]
        };
        let mut t = sq(r.inf());
        t.push(-a.abs());
        prop_assert!(exact_sign(&t) != Ordering::Greater);
        let mut t = sq(r.sup());
        t.push(-a.abs());
        prop_assert!(exact_sign(&t) != Ordering::Less);
    }
}

/// A function of the interval type.
type Fun = fn(DdInterval) -> DdInterval;

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, rng_seed: RngSeed::Fixed(13), ..ProptestConfig::default() })]

    /// The enclosure of a function over an interval meets (so, being an enclosure of a range
    /// that contains f(t), is consistent with) its enclosure at any point t of the interval; a
    /// wrong monotone piece or a missed extremum of sin/cos/tan would make them disjoint.
    #[test]
    fn interval_functions_meet_their_point_values(
        a in -20.0f64..20.0, w in 0.0f64..7.0, frac in 0.0f64..=1.0, scale in prop_oneof![Just(1.0), Just(1e6), Just(1e-3)],
    ) {
        let (lo, hi) = (a * scale, (a + w) * scale);
        let t = (lo + (hi - lo) * frac).clamp(lo, hi);
        let x = DdInterval::from_f64_pair(lo, hi).unwrap();
        let p = DdInterval::from_f64(t);
        let fs: [(&str, Fun); 12] = [
            ("sin", DdInterval::sin), ("cos", DdInterval::cos), ("tan", DdInterval::tan),
            ("exp", DdInterval::exp), ("ln", DdInterval::ln), ("sqrt", DdInterval::sqrt),
            ("atan", DdInterval::atan), ("sinh", DdInterval::sinh), ("cosh", DdInterval::cosh),
            ("tanh", DdInterval::tanh), ("asinh", DdInterval::asinh), ("sqr", DdInterval::sqr),
        ];
        for (name, f) in fs {
            let (fx, fp) = (f(x), f(p));
            if fp.is_empty() {
                continue; // t outside the domain
            }
            prop_assert!(!fx.disjoint(fp), "{name} on {x}: {fx}, at {t}: {fp}");
            prop_assert!(fp.is_finite() || name == "exp" || name == "sinh" || name == "cosh" || name == "tan");
        }
    }
}

/// Printing rounds outward and reads back: from_decimal(inf_decimal(x)) lies at or below x,
/// from_decimal(sup_decimal(x)) at or above, for many digit counts.
#[test]
fn printing_round_trip() {
    let values = [
        DdInterval::pi(),
        DdInterval::from_decimal("-0.1").unwrap(),
        DdInterval::from_decimal("1e-310").unwrap(),
        DdInterval::from_decimal("123456789.123456789123456789123456789").unwrap(),
        DdInterval::from_f64(2.0).sqrt(),
        -DdInterval::from_f64(3.0).exp(),
    ];
    for x in values {
        for digits in [1, 2, 5, 17, 34, 40] {
            let lo = DdInterval::from_decimal(&x.inf_decimal(digits)).unwrap();
            let hi = DdInterval::from_decimal(&x.sup_decimal(digits)).unwrap();
            // The printed decimals enclose x: necessary conditions at every digit count, and
            // proved orderings (the decimal's enclosure entirely outside x) when the rounding
            // gap, at least 10^-17 relative, exceeds the enclosures' widths.
            assert!(lo.inf() <= x.inf() && hi.sup() >= x.sup(), "{x} {digits}");
            if digits <= 17 {
                assert!(
                    lo.sup() <= x.inf(),
                    "{x} {digits}: {}",
                    x.inf_decimal(digits)
                );
                assert!(
                    hi.inf() >= x.sup(),
                    "{x} {digits}: {}",
                    x.sup_decimal(digits)
                );
            }
        }
    }
    assert_eq!(DdInterval::from_f64(0.5).to_string(), "[5e-1, 5e-1]");
    assert_eq!(DdInterval::from_f64(-3.0).to_string(), "[-3, -3]");
    assert_eq!(
        DdInterval::from_decimal("0.1").unwrap().inf_decimal(3),
        "9.99e-2"
    );
    assert_eq!(
        DdInterval::from_decimal("0.1").unwrap().sup_decimal(3),
        "1.01e-1"
    );
}

/// A double-double from `hi` and a `lo` at most half an ulp of it (normalised exactly).
fn dd_of(hi: f64, frac: f64) -> Dd {
    let lo = frac * hi * f64::EPSILON * 0.5;
    let (s, t) = two_sum(hi, lo);
    Dd::new(s, t)
}

/// `x k` as an exact expansion (TwoProd of each part: exact for an integer `k < 2^53` and
/// parts far from underflow).
fn times_int(x: Dd, k: f64) -> Vec<f64> {
    let part = |p: f64| [p * k, p.mul_add(k, -(p * k))];
    let (a, b) = (part(x.hi()), part(x.lo()));
    vec![a[0], a[1], b[0], b[1]]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, rng_seed: RngSeed::Fixed(46), ..ProptestConfig::default() })]

    /// Spec (12.1.22): `x / k` for an integer `k`, checked exactly: `inf * k <= x_lo` and
    /// `sup * k >= x_hi` (the products expanded by TwoProd); for `k <= 2^20` a point's quotient
    /// at least `2^-800` in size at most `2^-103` of it wide, and every quotient no wider than
    /// the general one of (12.1.7) by more than `2^-104` of its size. The divisors run over 1 to
    /// `2^20` (the direct division) and past it (the general quotient); the dividends over
    /// points and intervals with non-zero low parts, of either sign, with exponents from
    /// `2^-890` to `2^1000` (near the direct division's `2^-900` floor and the overflow).
    #[test]
    fn integer_quotients_enclose_exactly_and_tightly(
        h1 in 0.5f64..1.0, neg in any::<bool>(), f1 in -1.0f64..1.0, e1 in -890i32..1000,
        spread in prop_oneof![Just(0.0f64), 0.0f64..1e-20, 0.0f64..1.0],
        f2 in -1.0f64..1.0,
        k in prop_oneof![1u32..=64, 1u32..=(1 << 20), Just(1 << 20), (1u32 << 20)..u32::MAX],
    ) {
        let a = dd_of(if neg { -h1 } else { h1 } * 2f64.powi(e1), f1);
        // an upper end above `a` (a spread too small to move `a_h`, or one that overflows,
        // gives the point)
        let b = dd_of(a.hi() + spread * a.hi().abs(), f2);
        let x = if spread > 0.0 && b.hi().is_finite() && (b.hi(), b.lo()) > (a.hi(), a.lo()) {
            DdInterval::new(a, b).expect("ordered")
        } else {
            DdInterval::point(a)
        };
        let spread = if x.is_point() { 0.0 } else { spread };
        let kf = f64::from(k);
        let q = x.div_int(k);
        prop_assert!(q.inf().hi().is_finite() && q.sup().hi().is_finite(), "{x} / {k} = {q}");
        let mut lo = times_int(q.inf(), kf);
        lo.extend([-x.inf().hi(), -x.inf().lo()]);
        prop_assert!(exact_sign(&lo) != Ordering::Greater, "{x} / {k}: {q} lower end too high");
        let mut hi = times_int(q.sup(), kf);
        hi.extend([-x.sup().hi(), -x.sup().lo()]);
        prop_assert!(exact_sign(&hi) != Ordering::Less, "{x} / {k}: {q} upper end too low");
        let general = x / DdInterval::from_f64(kf);
        let size = q.mag_up();
        prop_assert!(q.wid_up() <= general.wid_up() + W * size, "{x} / {k}: {q} wider than {general}");
        // far from the floors of the direct division (a rest `q_l` below `2^-960` takes the
        // general quotient)
        if spread == 0.0 && k <= 1 << 20 && e1 >= -800 {
            prop_assert!(q.wid_up() <= 2.0 * W * size, "{x} / {k}: {q} wider than 2^-103 of its size");
        }
    }
}

/// Spec (12.1.22) at its edges: a zero, exact quotients (a point), ends below `2^-900` and
/// not finite, `k = 0` and the empty set take the general quotient's answers.
#[test]
fn integer_quotients_at_the_edges() {
    let p = |x: f64| DdInterval::from_f64(x);
    assert_eq!(p(0.0).div_int(7), p(0.0));
    assert_eq!(p(21.0).div_int(7), p(3.0));
    assert_eq!(p(-1.5).div_int(1), p(-1.5));
    let tiny = p(f64::from_bits(3)).div_int(3);
    assert!(tiny.contains(Dd::from_f64(f64::from_bits(1))), "{tiny}");
    let small = DdInterval::from_f64(1e-280);
    assert_eq!(small.div_int(10), small / p(10.0));
    assert_eq!(p(5.0).div_int(0), p(5.0) / p(0.0));
    assert!(DdInterval::EMPTY.div_int(3).is_empty());
    let half =
        DdInterval::new(Dd::from_f64(1.0), Dd::from_f64(f64::INFINITY)).expect("a half-line");
    assert_eq!(half.div_int(4), half / p(4.0));
}
