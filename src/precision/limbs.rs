//! `Nat<N>`: natural numbers of at most `N` 64-bit limbs in a fixed array, `Copy`, no heap
//! ([spec (12.2.0)](crate::spec::precision)).
//!
//! The significands of [`Mp`](super::mp_float::Mp) and the exact intermediate results of its
//! operations (products, shifted sums, quotients, square roots) are `Nat`s. Every operation
//! here is exact integer arithmetic; a result that would not fit in `N` limbs is a bug of the
//! caller, whose sizes are bounded in 12.2.0 (the index panics rather than wrap). The limb
//! count is a const generic; the operations touch only the `len` limbs in use, so a number of
//! three limbs costs three limbs' work in an array of any `N`.

use core::cmp::Ordering;

/// A natural number `sum d[i] 2^(64 i)`, `i < len`; `d[len - 1] != 0` and `d[len..] == 0`
/// (canonical: equal numbers have equal representations).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(C)]
pub(crate) struct Nat<const N: usize> {
    len: usize,
    d: [u64; N],
}

impl<const N: usize> Nat<N> {
    /// Zero.
    pub(crate) const ZERO: Nat<N> = Nat { len: 0, d: [0; N] };

    /// The number `x`.
    pub(crate) fn from_u64(x: u64) -> Nat<N> {
        let mut r = Nat::ZERO;
        if x != 0 {
            r.d[0] = x;
            r.len = 1;
        }
        r
    }

    /// The number with little-endian limbs `s` (trailing zero limbs allowed).
    pub(crate) fn from_limbs(s: &[u64]) -> Nat<N> {
        let mut r = Nat::ZERO;
        r.d[..s.len()].copy_from_slice(s);
        r.len = s.len();
        r.trim();
        r
    }

    /// The limbs in use, little-endian.
    pub(crate) fn limbs(&self) -> &[u64] {
        &self.d[..self.len]
    }

    /// The same number in another limb count (it must fit).
    pub(crate) fn resize<const M: usize>(&self) -> Nat<M> {
        Nat::<M>::from_limbs(self.limbs())
    }

    fn trim(&mut self) {
        while self.len > 0 && self.d[self.len - 1] == 0 {
            self.len -= 1;
        }
    }

    /// Whether zero.
    pub(crate) fn is_zero(&self) -> bool {
        self.len == 0
    }

    /// The lowest limb.
    pub(crate) fn low(&self) -> u64 {
        self.d[0]
    }

    /// The number of significant bits (0 for zero).
    pub(crate) fn bits(&self) -> u64 {
        if self.len == 0 {
            return 0;
        }
        64 * self.len as u64 - self.d[self.len - 1].leading_zeros() as u64
    }

    /// The number of trailing zero bits (0 for zero).
    pub(crate) fn trailing_zeros(&self) -> u64 {
        for i in 0..self.len {
            if self.d[i] != 0 {
                return 64 * i as u64 + self.d[i].trailing_zeros() as u64;
            }
        }
        0
    }

    /// Bit `i`.
    pub(crate) fn bit(&self, i: u64) -> bool {
        let w = (i / 64) as usize;
        w < self.len && (self.d[w] >> (i % 64)) & 1 == 1
    }

    /// `self 2^k` (must fit in `N` limbs).
    pub(crate) fn shl(&self, k: u64) -> Nat<N> {
        if self.len == 0 {
            return *self;
        }
        let (w, b) = ((k / 64) as usize, (k % 64) as u32);
        let mut r = Nat::ZERO;
        if b == 0 {
            r.d[w..w + self.len].copy_from_slice(&self.d[..self.len]);
            r.len = self.len + w;
        } else {
            let mut carry = 0u64;
            for i in 0..self.len {
                r.d[i + w] = (self.d[i] << b) | carry;
                carry = self.d[i] >> (64 - b);
            }
            r.len = self.len + w;
            if carry != 0 {
                r.d[self.len + w] = carry;
                r.len += 1;
            }
        }
        r
    }

    /// `floor(self / 2^k)`.
    pub(crate) fn shr(&self, k: u64) -> Nat<N> {
        let (w, b) = ((k / 64) as usize, (k % 64) as u32);
        if w >= self.len {
            return Nat::ZERO;
        }
        let mut r = Nat::ZERO;
        let n = self.len - w;
        if b == 0 {
            r.d[..n].copy_from_slice(&self.d[w..self.len]);
        } else {
            for i in 0..n {
                let hi = if i + w + 1 < self.len {
                    self.d[i + w + 1] << (64 - b)
                } else {
                    0
                };
                r.d[i] = (self.d[i + w] >> b) | hi;
            }
        }
        r.len = n;
        r.trim();
        r
    }

    /// `self <- floor(self / 2^k)`, in place.
    pub(crate) fn shr_assign(&mut self, k: u64) {
        let (w, b) = ((k / 64) as usize, (k % 64) as u32);
        if w >= self.len {
            self.d[..self.len].fill(0);
            self.len = 0;
            return;
        }
        let n = self.len - w;
        if b == 0 {
            self.d.copy_within(w..self.len, 0);
        } else {
            for i in 0..n {
                let hi = if i + w + 1 < self.len {
                    self.d[i + w + 1] << (64 - b)
                } else {
                    0
                };
                self.d[i] = (self.d[i + w] >> b) | hi;
            }
        }
        self.d[n..self.len].fill(0);
        self.len = n;
        self.trim();
    }

    /// `self <- self + 1`, in place (must fit).
    pub(crate) fn add_one_assign(&mut self) {
        for i in 0..self.len {
            let (s, c) = self.d[i].overflowing_add(1);
            self.d[i] = s;
            if !c {
                return;
            }
        }
        self.d[self.len] = 1;
        self.len += 1;
    }

    /// `self + y` (must fit).
    pub(crate) fn add(&self, y: &Nat<N>) -> Nat<N> {
        let n = self.len.max(y.len);
        let mut r = Nat::ZERO;
        let mut carry = false;
        for i in 0..n {
            let (s, c1) = self.d[i].overflowing_add(y.d[i]);
            let (s, c2) = s.overflowing_add(carry as u64);
            r.d[i] = s;
            carry = c1 || c2;
        }
        r.len = n;
        if carry {
            r.d[n] = 1;
            r.len += 1;
        }
        r
    }

    /// `self + 1`.
    pub(crate) fn add_one(&self) -> Nat<N> {
        self.add(&Nat::from_u64(1))
    }

    /// `self - y` for `y <= self`.
    pub(crate) fn sub(&self, y: &Nat<N>) -> Nat<N> {
        debug_assert!(*y <= *self);
        let mut r = Nat::ZERO;
        let mut borrow = false;
        for i in 0..self.len {
            let (s, b1) = self.d[i].overflowing_sub(y.d[i]);
            let (s, b2) = s.overflowing_sub(borrow as u64);
            r.d[i] = s;
            borrow = b1 || b2;
        }
        r.len = self.len;
        r.trim();
        r
    }

    /// `self y` (must fit: `len + y.len <= N`).
    pub(crate) fn mul(&self, y: &Nat<N>) -> Nat<N> {
        let mut r = Nat::ZERO;
        if self.len == 0 || y.len == 0 {
            return r;
        }
        for i in 0..self.len {
            let a = self.d[i] as u128;
            let mut carry = 0u128;
            for j in 0..y.len {
                let t = a * y.d[j] as u128 + r.d[i + j] as u128 + carry;
                r.d[i + j] = t as u64;
                carry = t >> 64;
            }
            r.d[i + y.len] = carry as u64;
        }
        r.len = self.len + y.len;
        r.trim();
        r
    }

    /// `(floor(self / d), self mod d)` for `d > 0`.
    pub(crate) fn divrem_u64(&self, d: u64) -> (Nat<N>, u64) {
        let mut q = Nat::ZERO;
        let mut rem = 0u128;
        for i in (0..self.len).rev() {
            let cur = (rem << 64) | self.d[i] as u128;
            q.d[i] = (cur / d as u128) as u64;
            rem = cur % d as u128;
        }
        q.len = self.len;
        q.trim();
        (q, rem as u64)
    }

    /// `(floor(self / v), whether the remainder is zero)` for `v > 0` (Knuth's algorithm D,
    /// TAOCP 4.3.1; `self` must have fewer than `N` limbs).
    pub(crate) fn div_exact(&self, v: &Nat<N>) -> (Nat<N>, bool) {
        debug_assert!(v.len > 0);
        if v.len == 1 {
            let (q, r) = self.divrem_u64(v.d[0]);
            return (q, r == 0);
        }
        if *self < *v {
            return (Nat::ZERO, self.is_zero());
        }
        let n = v.len;
        let m = self.len - n;
        let s = v.d[n - 1].leading_zeros();
        // normalised copies: vn's top bit set, un with one extra limb
        let vn = v.shl(s as u64);
        let mut un = [0u64; N];
        if s == 0 {
            un[..self.len].copy_from_slice(&self.d[..self.len]);
        } else {
            let mut carry = 0u64;
            for i in 0..self.len {
                un[i] = (self.d[i] << s) | carry;
                carry = self.d[i] >> (64 - s);
            }
            un[self.len] = carry;
        }
        let mut q = Nat::ZERO;
        let b: u128 = 1 << 64;
        let vtop = vn.d[n - 1] as u128;
        let vnext = vn.d[n - 2] as u128;
        for j in (0..=m).rev() {
            let num = ((un[j + n] as u128) << 64) | un[j + n - 1] as u128;
            let mut qhat = num / vtop;
            let mut rhat = num % vtop;
            while qhat >= b || qhat * vnext > ((rhat << 64) | un[j + n - 2] as u128) {
                qhat -= 1;
                rhat += vtop;
                if rhat >= b {
                    break;
                }
            }
            // un[j..=j+n] -= qhat vn
            let mut k: i128 = 0;
            for i in 0..n {
                let p = qhat * vn.d[i] as u128;
                let t = un[i + j] as i128 - k - (p as u64) as i128;
                un[i + j] = t as u64;
                k = (p >> 64) as i128 - (t >> 64);
            }
            let t = un[j + n] as i128 - k;
            un[j + n] = t as u64;
            if t < 0 {
                // qhat was one too large: add vn back
                qhat -= 1;
                let mut c: u128 = 0;
                for i in 0..n {
                    let t = un[i + j] as u128 + vn.d[i] as u128 + c;
                    un[i + j] = t as u64;
                    c = t >> 64;
                }
                un[j + n] = un[j + n].wrapping_add(c as u64);
            }
            q.d[j] = qhat as u64;
        }
        q.len = m + 1;
        q.trim();
        let exact = un[..n].iter().all(|&x| x == 0);
        (q, exact)
    }

    /// `(floor(sqrt(self)), whether exact)`: Newton's iteration from above, `x <- floor((x +
    /// floor(self / x)) / 2)`, which decreases strictly until `x = floor(sqrt(self))`.
    pub(crate) fn sqrt_exact(&self) -> (Nat<N>, bool) {
        if self.len == 0 {
            return (*self, true);
        }
        // 2^ceil(bits / 2) >= sqrt(self)
        let mut x = Nat::<N>::from_u64(1).shl(self.bits().div_ceil(2));
        loop {
            let (q, _) = self.div_exact(&x);
            let y = x.add(&q).shr(1);
            if y >= x {
                break;
            }
            x = y;
        }
        let exact = x.mul(&x) == *self;
        (x, exact)
    }
}

impl<const N: usize> PartialOrd for Nat<N> {
    fn partial_cmp(&self, other: &Nat<N>) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl<const N: usize> Ord for Nat<N> {
    fn cmp(&self, y: &Nat<N>) -> Ordering {
        if self.len != y.len {
            return self.len.cmp(&y.len);
        }
        for i in (0..self.len).rev() {
            if self.d[i] != y.d[i] {
                return self.d[i].cmp(&y.d[i]);
            }
        }
        Ordering::Equal
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigUint;

    type N8 = Nat<8>;

    fn big(x: &N8) -> BigUint {
        let mut w = Vec::new();
        for d in x.limbs() {
            w.push(*d as u32);
            w.push((*d >> 32) as u32);
        }
        BigUint::new(w)
    }

    fn nat(x: &BigUint) -> N8 {
        N8::from_limbs(&x.to_u64_digits())
    }

    /// A deterministic stream of awkward limbs: all ones, all zeros, single bits, mixtures.
    fn limbs(seed: &mut u64, n: usize) -> N8 {
        let mut v = [0u64; 8];
        for d in v.iter_mut().take(n) {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *d = match *seed >> 61 {
                0 => u64::MAX,
                1 => 0,
                2 => 1 << (*seed >> 40 & 63),
                3 => u64::MAX - (*seed >> 20 & 7),
                _ => *seed ^ (*seed << 17),
            };
        }
        N8::from_limbs(&v)
    }

    #[test]
    fn every_operation_agrees_with_big_integers() {
        let mut s = 7u64;
        for _ in 0..4000 {
            let na = (s >> 3) as usize % 4 + 1;
            let a = limbs(&mut s, na);
            let nb = (s >> 5) as usize % 3 + 1;
            let b = limbs(&mut s, nb);
            let (ba, bb) = (big(&a), big(&b));
            assert_eq!(big(&a.add(&b)), &ba + &bb);
            assert_eq!(big(&a.mul(&b)), &ba * &bb);
            if a >= b {
                assert_eq!(big(&a.sub(&b)), &ba - &bb);
            }
            assert_eq!(a.cmp(&b), ba.cmp(&bb));
            let k = s % 130;
            assert_eq!(big(&a.shl(k)), &ba << k);
            assert_eq!(big(&a.shr(k)), &ba >> k);
            let mut c = a;
            c.shr_assign(k);
            assert_eq!(c, a.shr(k));
            let mut c = a;
            c.add_one_assign();
            assert_eq!(big(&c), &ba + 1u32);
            assert_eq!(a.bits(), ba.bits());
            assert_eq!(a.trailing_zeros(), ba.trailing_zeros().unwrap_or(0));
            if !b.is_zero() {
                let (q, exact) = a.div_exact(&b);
                assert_eq!(big(&q), &ba / &bb, "{ba:x} / {bb:x}");
                assert_eq!(exact, (&ba % &bb) == BigUint::ZERO);
                let (q, r) = a.divrem_u64(b.low().max(1));
                assert_eq!(big(&q), &ba / b.low().max(1));
                assert_eq!(BigUint::from(r), &ba % b.low().max(1));
            }
            let (r, exact) = a.sqrt_exact();
            assert_eq!(big(&r), ba.sqrt());
            assert_eq!(exact, &ba.sqrt() * &ba.sqrt() == ba);
        }
    }

    #[test]
    fn carries_run_through_every_limb() {
        let ones = N8::from_limbs(&[u64::MAX; 7]);
        let one = N8::from_u64(1);
        let p = ones.add(&one);
        assert_eq!(p.bits(), 7 * 64 + 1);
        assert_eq!(p.trailing_zeros(), 7 * 64);
        assert_eq!(p.sub(&one), ones);
        assert!(ones.sub(&ones).is_zero());
        let sq = N8::from_limbs(&[u64::MAX; 4]);
        assert_eq!(big(&sq.mul(&sq)), big(&sq) * big(&sq));
        // a divisor whose quotient digit estimate is too large (the add-back branch)
        let u = nat(&(BigUint::from(1u32) << 192u32));
        let v = nat(&((BigUint::from(1u32) << 128u32) - 1u32 + (BigUint::from(1u32) << 127u32)));
        assert_eq!(big(&u.div_exact(&v).0), big(&u) / big(&v));
    }
}
