//! The fused dot product of [`MpInterval`]s: `acc + sum_j x_j y_j` (or `acc - sum`) with each
//! end accumulated exactly in a fixed-point window and rounded once
//! ([spec (12.2.8)](crate::spec::precision)).
//!
//! Each end of each product is the exact product of two ends (`Nat` multiplication: the
//! significands are at most `L` limbs, the product at most `2 L`), chosen by the signs of the
//! ends as in [`MpInterval::mul_ref`] (where both factors hold 0 inside, the larger in
//! magnitude of the two exact candidates of each end, which have one sign). The ends
//! are summed in a two's complement window of `K` limbs ([`Acc`]) whose lowest bit weighs `2^e`;
//! bits of a term below the window are dropped by `floor` and counted, so the exact sum `S`
//! always satisfies `v 2^e <= S <= (v + c) 2^e`. The lower end of the result is `v 2^e` rounded
//! down once, the upper end `(v + c) 2^e` rounded up once.

use super::limbs::Nat;
use super::mp::MpInterval;
use super::mp_float::{Mp, Round};
use core::cmp::Ordering;

/// A two's complement accumulator of `K` limbs at the weight `2^e` (see the module doc):
/// the exact sum `S` of the terms added so far satisfies `v 2^e <= S <= (v + c) 2^e`, and
/// `-2^H <= v < 2^H` with `H = 64 (K - 1) - 1` between additions.
struct Acc<const K: usize> {
    v: [u64; K],
    e: i64,
    c: u64,
    started: bool,
}

impl<const K: usize> Acc<K> {
    const H: i64 = 64 * (K as i64 - 1) - 1;

    fn new() -> Acc<K> {
        Acc {
            v: [0; K],
            e: 0,
            c: 0,
            started: false,
        }
    }

    /// Whether `-2^H <= v < 2^H`: the top limb repeats the sign bit of the one below.
    fn in_range(&self) -> bool {
        self.v[K - 1] == ((self.v[K - 2] as i64) >> 63) as u64
    }

    /// `v <- floor(v / 2^(64 s))`, `e <- e + 64 s`; the bound `c` becomes `[c > 0] + [bits
    /// dropped]` (12.2.8: the dropped part and `c` are each below one unit of the new weight).
    fn shr_limbs(&mut self, s: u64) {
        let sign = ((self.v[K - 1] as i64) >> 63) as u64;
        let k = s.min(K as u64) as usize;
        let dropped = self.v[..k].iter().any(|&d| d != 0);
        self.v.copy_within(k.., 0);
        self.v[K - k..].fill(sign);
        self.e += 64 * s as i64;
        self.c = (self.c > 0) as u64 + dropped as u64;
    }

    /// Adds the exact term `(-1)^neg m 2^me`, `m` the nonzero natural number of limbs `m`
    /// (little-endian, top limb nonzero).
    fn add_term(&mut self, neg: bool, m: &[u64], me: i64) {
        let len = m.len();
        let bits = 64 * len as i64 - m[len - 1].leading_zeros() as i64;
        // |term| < 2^t
        let t = me + bits;
        if !self.started {
            self.e = t - Self::H;
            self.started = true;
        }
        if t - self.e > Self::H {
            self.shr_limbs(((t - self.e - Self::H) as u64).div_ceil(64));
        }
        // w = |term| / 2^e, floored (ceiled for a negative term, so that v - w is the floor),
        // added to (subtracted from) v limb by limb as it is shifted: its limbs from `lo` on,
        // `n` of them, then the carry (borrow) upward; a negative term with dropped bits
        // starts with a borrow of 1 (w + 1, the ceiling)
        let d = me - self.e;
        let (lo, n, first);
        let mut buf = [0u64; K];
        if d >= 0 {
            // t - e <= H: m 2^d fits below limb K - 1
            let (ws, bs) = ((d / 64) as usize, (d % 64) as u32);
            n = (len + (bs > 0) as usize).min(K - ws);
            for (i, b) in buf[..n].iter_mut().enumerate() {
                let cur = if i < len { m[i] } else { 0 };
                *b = if bs == 0 {
                    cur
                } else if i == 0 {
                    cur << bs
                } else {
                    (cur << bs) | (m[i - 1] >> (64 - bs))
                };
            }
            (lo, first) = (ws, 0);
        } else {
            let s = (-d) as u64;
            let (ws, bs) = ((s / 64) as usize, (s % 64) as u32);
            let dropped = if ws >= len {
                n = 0;
                true
            } else {
                n = (len - ws).min(K);
                for (i, b) in buf[..n].iter_mut().enumerate() {
                    let hi = if bs > 0 && i + ws + 1 < len {
                        m[i + ws + 1] << (64 - bs)
                    } else {
                        0
                    };
                    *b = (m[i + ws] >> bs) | hi;
                }
                m[..ws].iter().any(|&x| x != 0) || (bs > 0 && m[ws] & ((1u64 << bs) - 1) != 0)
            };
            if dropped {
                self.c += 1;
            }
            (lo, first) = (0, (dropped && neg) as u64);
        }
        // v <- v -+ w modulo 2^(64 K)
        let mut c = first;
        let mut i = lo;
        if neg {
            for &x in &buf[..n] {
                let (y, b1) = self.v[i].overflowing_sub(x);
                let (y, b2) = y.overflowing_sub(c);
                self.v[i] = y;
                c = (b1 | b2) as u64;
                i += 1;
            }
            while c != 0 && i < K {
                let (y, b) = self.v[i].overflowing_sub(1);
                self.v[i] = y;
                c = b as u64;
                i += 1;
            }
        } else {
            for &x in &buf[..n] {
                let (y, c1) = self.v[i].overflowing_add(x);
                let (y, c2) = y.overflowing_add(c);
                self.v[i] = y;
                c = (c1 | c2) as u64;
                i += 1;
            }
            while c != 0 && i < K {
                let (y, o) = self.v[i].overflowing_add(1);
                self.v[i] = y;
                c = o as u64;
                i += 1;
            }
        }
        // |v| < 2^H + 2^H: no overflow of the K limbs; one limb down restores the range
        if !self.in_range() {
            self.shr_limbs(1);
        }
    }

    /// Adds the exact value of a finite `x` times `(-1)^neg`.
    fn add_mp(&mut self, x: &Mp, neg: bool) {
        if x.is_zero() {
            return;
        }
        let (s, m, e) = x.parts();
        self.add_term(s != neg, m, e);
    }

    /// Adds the exact product `w u v` times `(-1)^neg`; `false` if the product does not fit
    /// in `K` limbs (the caller then takes the stepwise path).
    fn add_product(&mut self, u: &Mp, v: &Mp, w: u64, neg: bool) -> bool {
        let mut r = [0u64; K];
        match product(u, v, w, &mut r) {
            Some(Some((s, n, e))) => {
                self.add_term(s != neg, &r[..n], e);
                true
            }
            Some(None) => true,
            None => false,
        }
    }

    /// Adds the one of the exact products `w u1 v1`, `w u2 v2` (of one sign) of the larger
    /// magnitude, times `(-1)^neg`; `false` if a product does not fit in `K` limbs.
    fn add_larger(&mut self, u1: &Mp, v1: &Mp, u2: &Mp, v2: &Mp, w: u64, neg: bool) -> bool {
        // the four are nonzero; |u v| lies in [2^(top u + top v - 2), 2^(top u + top v))
        let (t1, t2) = (u1.top() + v1.top(), u2.top() + v2.top());
        if t1 >= t2 + 2 {
            return self.add_product(u1, v1, w, neg);
        }
        if t2 >= t1 + 2 {
            return self.add_product(u2, v2, w, neg);
        }
        match quick_larger(u1, v1, u2, v2, t1, t2) {
            Some(true) => return self.add_product(u1, v1, w, neg),
            Some(false) => return self.add_product(u2, v2, w, neg),
            None => {}
        }
        let (mut r1, mut r2) = ([0u64; K], [0u64; K]);
        let (Some(a), Some(b)) = (product(u1, v1, w, &mut r1), product(u2, v2, w, &mut r2)) else {
            return false;
        };
        let (s, m, e) = match (a, b) {
            (None, None) => return true,
            (Some((s, n, e)), None) => (s, &r1[..n], e),
            (None, Some((s, n, e))) => (s, &r2[..n], e),
            (Some((s1, n1, e1)), Some((s2, n2, e2))) => {
                if mag_cmp::<K>(&r1[..n1], e1, &r2[..n2], e2) == Ordering::Less {
                    (s2, &r2[..n2], e2)
                } else {
                    (s1, &r1[..n1], e1)
                }
            }
        };
        self.add_term(s != neg, m, e);
        true
    }

    /// `v 2^e` rounded down (`Round::Down`) or `(v + c) 2^e` rounded up, to `prec` bits.
    fn finish(&self, prec: u32, mode: Round) -> Mp {
        if !self.started {
            return Mp::zero();
        }
        let mut x = self.v;
        if mode == Round::Up {
            add_small(&mut x, self.c);
        }
        let neg = (x[K - 1] as i64) < 0;
        if neg {
            // two's complement magnitude: !x + 1
            for d in x.iter_mut() {
                *d = !*d;
            }
            add_small(&mut x, 1);
        }
        Mp::round_nat(neg, Nat::<K>::from_limbs(&x), self.e, prec, mode)
    }
}

/// The exact product `w u v` (`w >= 1` a small integer weight) written in `r` (its limbs
/// `r[..n]`, the top one nonzero): `(sign, n, exponent)`; `Some(None)` when it is zero, `None`
/// when it does not fit in `K` limbs. Only the limbs `r[..n]` (and `r[n]`) are written: the
/// first row of the schoolbook product stores, the others accumulate, so `r` need not be
/// cleared.
fn product<const K: usize>(
    u: &Mp,
    v: &Mp,
    w: u64,
    r: &mut [u64; K],
) -> Option<Option<(bool, usize, i64)>> {
    if u.is_zero() || v.is_zero() {
        return Some(None);
    }
    let (su, mu, eu) = u.parts();
    let (sv, mv, ev) = v.parts();
    let (m, n) = (mu.len(), mv.len());
    let mut len = m + n;
    if len + (w > 1) as usize > K {
        return None;
    }
    // schoolbook product straight from the limbs (12.2.0), in place; short significands
    // (the 160- and 256-bit cases) padded to a fixed size, the loops then unrolled
    if m <= 3 && n <= 3 && 6 < K {
        fixed_product::<3, K>(mu, mv, r);
    } else if m <= 4 && n <= 4 && 8 < K {
        fixed_product::<4, K>(mu, mv, r);
    } else {
        schoolbook(mu, mv, r);
    }
    if w > 1 {
        // times the weight, exactly: one more limb at most
        let mut carry = 0u64;
        for d in r[..len].iter_mut() {
            let t = *d as u128 * w as u128 + carry as u128;
            *d = t as u64;
            carry = (t >> 64) as u64;
        }
        r[len] = carry;
        len += 1;
    }
    while len > 0 && r[len - 1] == 0 {
        len -= 1;
    }
    Some(Some((su != sv, len, eu + ev)))
}

/// `r[..m + n] = a b` (`m`, `n` the lengths of `a`, `b`), row by row.
fn schoolbook<const K: usize>(a: &[u64], b: &[u64], r: &mut [u64; K]) {
    let n = b.len();
    let mut carry = 0u64;
    for (rj, &y) in r[..n].iter_mut().zip(b) {
        let t = a[0] as u128 * y as u128 + carry as u128;
        *rj = t as u64;
        carry = (t >> 64) as u64;
    }
    r[n] = carry;
    for (i, &x) in a.iter().enumerate().skip(1) {
        let row = &mut r[i..i + n + 1];
        let mut carry = 0u64;
        for (rj, &y) in row[..n].iter_mut().zip(b) {
            let t = x as u128 * y as u128 + *rj as u128 + carry as u128;
            *rj = t as u64;
            carry = (t >> 64) as u64;
        }
        row[n] = carry;
    }
}

/// `r[..2 L] = a b` for `a`, `b` of at most `L` limbs, both padded with zeros to `L` (the
/// same exact product as [`schoolbook`], with fixed trip counts; limbs of `r` past `m + n`
/// are then 0).
#[inline(always)]
fn fixed_product<const L: usize, const K: usize>(a: &[u64], b: &[u64], r: &mut [u64; K]) {
    // limb by limb with a select (a copy of a variable length would be a library call)
    let x: [u64; L] = core::array::from_fn(|i| if i < a.len() { a[i] } else { 0 });
    let y: [u64; L] = core::array::from_fn(|i| if i < b.len() { b[i] } else { 0 });
    let r = &mut r[..2 * L];
    let mut carry = 0u64;
    for j in 0..L {
        let t = x[0] as u128 * y[j] as u128 + carry as u128;
        r[j] = t as u64;
        carry = (t >> 64) as u64;
    }
    r[L] = carry;
    for i in 1..L {
        let mut carry = 0u64;
        for j in 0..L {
            let t = x[i] as u128 * y[j] as u128 + r[i + j] as u128 + carry as u128;
            r[i + j] = t as u64;
            carry = (t >> 64) as u64;
        }
        r[i + L] = carry;
    }
}

/// `|a| 2^ea` against `|b| 2^eb` for nonzero significands (limbs, top one nonzero): by their
/// tops, then (equal tops) by the significands aligned at the smaller exponent (the shift is
/// below the longer one's bits, so it fits in `K` limbs).
fn mag_cmp<const K: usize>(a: &[u64], ea: i64, b: &[u64], eb: i64) -> Ordering {
    let bits = |m: &[u64]| 64 * m.len() as i64 - m[m.len() - 1].leading_zeros() as i64;
    let (ta, tb) = (ea + bits(a), eb + bits(b));
    if ta != tb {
        return ta.cmp(&tb);
    }
    if ea == eb {
        // equal tops and exponents: equal lengths, compared from the top limb
        return a.iter().rev().cmp(b.iter().rev());
    }
    let (a, b) = (Nat::<K>::from_limbs(a), Nat::<K>::from_limbs(b));
    // one sign: at equal tops the shift is that of the longer significand
    if ea > eb {
        a.shl((ea - eb) as u64).cmp(&b)
    } else {
        a.cmp(&b.shl((eb - ea) as u64))
    }
}

/// `x <- x + a` in two's complement (wrapping).
fn add_small<const K: usize>(x: &mut [u64; K], a: u64) {
    let mut carry = a;
    for d in x.iter_mut() {
        if carry == 0 {
            break;
        }
        let (s, c) = d.overflowing_add(carry);
        *d = s;
        carry = c as u64;
    }
}

/// One end of the range of a product of intervals: the exact product of two ends, or (both
/// factors holding 0 inside) the larger in magnitude of two exact products of one sign.
enum End<'a> {
    Prod(&'a Mp, &'a Mp),
    Larger(&'a Mp, &'a Mp, &'a Mp, &'a Mp),
}

/// The lower and upper ends of `x y` for finite non-empty intervals, by the signs of the ends
/// (the cases of [`MpInterval::mul_ref`], 12.2.2).
fn product_ends<'a>(x: &'a MpInterval, y: &'a MpInterval) -> (End<'a>, End<'a>) {
    use End::Prod;
    let (a, b, c, d) = (&x.lo, &x.hi, &y.lo, &y.hi);
    if !a.is_negative() {
        if !c.is_negative() {
            (Prod(a, c), Prod(b, d))
        } else if !d.is_positive() {
            (Prod(b, c), Prod(a, d))
        } else {
            (Prod(b, c), Prod(b, d))
        }
    } else if !b.is_positive() {
        if !c.is_negative() {
            (Prod(a, d), Prod(b, c))
        } else if !d.is_positive() {
            (Prod(b, d), Prod(a, c))
        } else {
            (Prod(a, d), Prod(a, c))
        }
    } else if !c.is_negative() {
        (Prod(a, d), Prod(b, d))
    } else if !d.is_positive() {
        (Prod(b, c), Prod(a, c))
    } else {
        // a < 0 < b, c < 0 < d: the lower end min(a d, b c) (both < 0), the upper max(a c,
        // b d) (both > 0); when a = -b (c = -d) the larger magnitude is that of the larger of
        // |c|, d (|a|, b), no product needed
        if opposite(a, b) {
            // |a d| >= |b c| and |b d| >= |a c| both when d >= |c|
            if mag_ge(d, c) {
                (Prod(a, d), Prod(b, d))
            } else {
                (Prod(b, c), Prod(a, c))
            }
        } else if opposite(c, d) {
            // |a d| >= |b c| and |a c| >= |b d| both when |a| >= b
            if mag_ge(a, b) {
                (Prod(a, d), Prod(a, c))
            } else {
                (Prod(b, c), Prod(b, d))
            }
        } else {
            (End::Larger(a, d, b, c), End::Larger(a, c, b, d))
        }
    }
}

fn add_end<const K: usize>(acc: &mut Acc<K>, end: &End, w: u64, neg: bool) -> bool {
    match end {
        End::Prod(u, v) => acc.add_product(u, v, w, neg),
        End::Larger(u1, v1, u2, v2) => acc.add_larger(u1, v1, u2, v2, w, neg),
    }
}

/// The leading 64 bits of the significand of a finite nonzero `x`: `|x| = (T + f) 2^(top - 64)`
/// with `0 <= f < 1`.
fn top64(x: &Mp) -> u64 {
    let (_, m, _) = x.parts();
    let n = m.len();
    let lz = m[n - 1].leading_zeros();
    if lz == 0 {
        m[n - 1]
    } else if n == 1 {
        m[0] << lz
    } else {
        (m[n - 1] << lz) | (m[n - 2] >> (64 - lz))
    }
}

/// `[l, h)` with `|u v|` in `[l, h) 2^(top u + top v - 128)`: `Tu Tv <= |u v| / 2^(...) <
/// (Tu + 1)(Tv + 1)`; `None` if `h` does not fit in 128 bits.
fn product_range(u: &Mp, v: &Mp) -> Option<(u128, u128)> {
    let (a, b) = (top64(u) as u128, top64(v) as u128);
    let l = a * b;
    Some((l, l.checked_add(a + b + 1)?))
}

/// Whether `|u1 v1| > |u2 v2|` (`Some(true)`) or `|u2 v2| > |u1 v1|` (`Some(false)`) as the
/// ranges of [`product_range`] show, for tops `t1`, `t2` at most 1 apart; `None` when the
/// ranges meet (the exact products decide).
fn quick_larger(u1: &Mp, v1: &Mp, u2: &Mp, v2: &Mp, t1: i64, t2: i64) -> Option<bool> {
    let (mut l1, mut h1) = product_range(u1, v1)?;
    let (mut l2, mut h2) = product_range(u2, v2)?;
    // both at the weight 2^(max(t1, t2) - 128): floor of the lower bound, ceiling of the upper
    if t1 > t2 {
        (l2, h2) = (l2 >> 1, (h2 >> 1) + (h2 & 1));
    } else if t2 > t1 {
        (l1, h1) = (l1 >> 1, (h1 >> 1) + (h1 & 1));
    }
    if l1 >= h2 {
        Some(true)
    } else if l2 >= h1 {
        Some(false)
    } else {
        None
    }
}

/// Whether `x = -y` (finite, nonzero).
fn opposite(x: &Mp, y: &Mp) -> bool {
    let ((sx, mx, ex), (sy, my, ey)) = (x.parts(), y.parts());
    sx != sy && ex == ey && same_limbs(mx, my)
}

/// Whether two limb slices are equal, compared limb by limb (short slices: no library call).
fn same_limbs(a: &[u64], b: &[u64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y)
}

/// Whether `|x| >= |y|`.
fn mag_ge(x: &Mp, y: &Mp) -> bool {
    x.abs() >= y.abs()
}

/// Whether a bounded interval is one number.
fn is_point(x: &MpInterval) -> bool {
    let ((sa, ma, ea), (sb, mb, eb)) = (x.lo.parts(), x.hi.parts());
    sa == sb && ea == eb && same_limbs(ma, mb)
}

fn bounded(x: &MpInterval) -> bool {
    !x.is_empty() && x.lo.is_finite() && x.hi.is_finite()
}

fn dot_in<'a, const K: usize>(
    acc: &MpInterval,
    neg: bool,
    terms: impl Iterator<Item = (&'a MpInterval, &'a MpInterval, u64)>,
    p: u32,
) -> Option<MpInterval> {
    let (mut lo, mut hi) = (Acc::<K>::new(), Acc::<K>::new());
    lo.add_mp(&acc.lo, false);
    hi.add_mp(&acc.hi, false);
    for (x, y, w) in terms {
        if x.is_exact_zero() || y.is_exact_zero() {
            continue;
        }
        if !bounded(x) || !bounded(y) {
            return None;
        }
        if w == 0 {
            continue;
        }
        if is_point(x) && is_point(y) {
            // one exact product is both ends
            let mut r = [0u64; K];
            match product(&x.lo, &y.lo, w, &mut r) {
                None => return None,
                Some(None) => {}
                Some(Some((s, n, e))) => {
                    lo.add_term(s != neg, &r[..n], e);
                    hi.add_term(s != neg, &r[..n], e);
                }
            }
            continue;
        }
        let (l, h) = product_ends(x, y);
        // acc + x y: lower + l, upper + h; acc - x y: lower - h, upper - l; the ends of
        // (w x) y are w times those of x y (w > 0 keeps every sign and every comparison)
        let ok = if neg {
            add_end(&mut lo, &h, w, true) && add_end(&mut hi, &l, w, true)
        } else {
            add_end(&mut lo, &l, w, false) && add_end(&mut hi, &h, w, false)
        };
        if !ok {
            return None;
        }
    }
    Some(MpInterval::raw(
        lo.finish(p, Round::Down),
        hi.finish(p, Round::Up),
        p,
    ))
}

impl MpInterval {
    /// `acc + sum x_j y_j` (`acc - sum` when `neg`) at `p` bits, each end summed exactly in a
    /// fixed window and rounded outward once (12.2.8); the terms with an exactly zero factor
    /// are skipped. `None` when an operand is empty or unbounded, or a significand is longer
    /// than `p` bits allow (the caller then computes term by term).
    pub fn dot_acc<'a>(
        acc: &MpInterval,
        neg: bool,
        pairs: impl Iterator<Item = (&'a MpInterval, &'a MpInterval)>,
        p: u32,
    ) -> Option<MpInterval> {
        MpInterval::dot_acc_weighted(acc, neg, pairs.map(|(x, y)| (x, y, 1)), p)
    }

    /// `acc + sum w_j x_j y_j` (`acc - sum` when `neg`) at `p` bits for integer weights `w_j
    /// >= 1`: each end of `(w_j x_j) y_j` is the exact product of `w_j` and two ends, summed
    /// exactly and rounded outward once ([spec (12.2.9)](crate::spec::precision)); `w_j x_j`
    /// is never rounded; a term of weight 0 is 0 (when bounded). `None` as for
    /// [`MpInterval::dot_acc`].
    pub fn dot_acc_weighted<'a>(
        acc: &MpInterval,
        neg: bool,
        terms: impl Iterator<Item = (&'a MpInterval, &'a MpInterval, u64)>,
        p: u32,
    ) -> Option<MpInterval> {
        if !bounded(acc) {
            return None;
        }
        // K >= 2 L + 2 limbs, L the limbs of a p-bit significand (one more for a weight)
        match (p as usize).div_ceil(64) {
            0..=3 => dot_in::<8>(acc, neg, terms, p),
            4..=5 => dot_in::<12>(acc, neg, terms, p),
            6..=9 => dot_in::<20>(acc, neg, terms, p),
            10..=17 => dot_in::<36>(acc, neg, terms, p),
            _ => None,
        }
    }
}
