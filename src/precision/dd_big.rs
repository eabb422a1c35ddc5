//! Exact unsigned big integers (little-endian `u32` limbs): the few operations that the exact
//! decimal conversions and the sin/cos argument reduction of the double-double intervals need
//! ([spec (12.1.9)](crate::spec::precision)). Every operation is exact (no rounding anywhere);
//! speed matters only for the argument reduction, which multiplies two numbers of at most a
//! few dozen limbs.

use core::cmp::Ordering;

/// A non-negative integer; `limbs` has no high zero limb (zero is the empty vector).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Big {
    limbs: Vec<u32>,
}

impl Big {
    pub(crate) fn zero() -> Big {
        Big { limbs: Vec::new() }
    }

    pub(crate) fn from_u64(x: u64) -> Big {
        let mut b = Big {
            limbs: vec![x as u32, (x >> 32) as u32],
        };
        b.trim();
        b
    }

    /// The integer whose limbs (least significant first) are `limbs`.
    pub(crate) fn from_limbs(limbs: &[u32]) -> Big {
        let mut b = Big {
            limbs: limbs.to_vec(),
        };
        b.trim();
        b
    }

    fn trim(&mut self) {
        while self.limbs.last() == Some(&0) {
            self.limbs.pop();
        }
    }

    pub(crate) fn is_zero(&self) -> bool {
        self.limbs.is_empty()
    }

    /// The number of significant bits (0 for zero).
    pub(crate) fn bit_len(&self) -> u64 {
        match self.limbs.last() {
            None => 0,
            Some(&top) => 32 * (self.limbs.len() as u64 - 1) + (32 - top.leading_zeros() as u64),
        }
    }

    /// Bit `i` (0 = least significant).
    pub(crate) fn bit(&self, i: u64) -> bool {
        let w = (i / 32) as usize;
        w < self.limbs.len() && (self.limbs[w] >> (i % 32)) & 1 == 1
    }

    /// `self * m + a` in place.
    pub(crate) fn mul_small_add(&mut self, m: u32, a: u32) {
        let mut carry = a as u64;
        for l in self.limbs.iter_mut() {
            let t = (*l as u64) * (m as u64) + carry;
            *l = t as u32;
            carry = t >> 32;
        }
        if carry != 0 {
            self.limbs.push(carry as u32);
        }
        self.trim();
    }

    /// `floor(self / d)` in place; returns the remainder. `d > 0`.
    pub(crate) fn div_small(&mut self, d: u32) -> u32 {
        let mut rem = 0u64;
        for l in self.limbs.iter_mut().rev() {
            let t = (rem << 32) | (*l as u64);
            *l = (t / d as u64) as u32;
            rem = t % d as u64;
        }
        self.trim();
        rem as u32
    }

    pub(crate) fn mul(&self, o: &Big) -> Big {
        if self.is_zero() || o.is_zero() {
            return Big::zero();
        }
        let mut r = vec![0u32; self.limbs.len() + o.limbs.len()];
        for (i, &a) in self.limbs.iter().enumerate() {
            let mut carry = 0u64;
            for (j, &b) in o.limbs.iter().enumerate() {
                let t = (a as u64) * (b as u64) + r[i + j] as u64 + carry;
                r[i + j] = t as u32;
                carry = t >> 32;
            }
            let mut k = i + o.limbs.len();
            while carry != 0 {
                let t = r[k] as u64 + carry;
                r[k] = t as u32;
                carry = t >> 32;
                k += 1;
            }
        }
        let mut b = Big { limbs: r };
        b.trim();
        b
    }

    pub(crate) fn add(&self, o: &Big) -> Big {
        let n = self.limbs.len().max(o.limbs.len());
        let mut r = Vec::with_capacity(n + 1);
        let mut carry = 0u64;
        for i in 0..n {
            let t = *self.limbs.get(i).unwrap_or(&0) as u64
                + *o.limbs.get(i).unwrap_or(&0) as u64
                + carry;
            r.push(t as u32);
            carry = t >> 32;
        }
        r.push(carry as u32);
        let mut b = Big { limbs: r };
        b.trim();
        b
    }

    /// `self - o`; requires `self >= o`.
    pub(crate) fn sub(&self, o: &Big) -> Big {
        debug_assert!(self.cmp_big(o) != Ordering::Less);
        let mut r = self.limbs.clone();
        let mut borrow = 0i64;
        for (i, l) in r.iter_mut().enumerate() {
            let t = *l as i64 - *o.limbs.get(i).unwrap_or(&0) as i64 - borrow;
            if t < 0 {
                *l = (t + (1i64 << 32)) as u32;
                borrow = 1;
            } else {
                *l = t as u32;
                borrow = 0;
            }
        }
        let mut b = Big { limbs: r };
        b.trim();
        b
    }

    pub(crate) fn cmp_big(&self, o: &Big) -> Ordering {
        if self.limbs.len() != o.limbs.len() {
            return self.limbs.len().cmp(&o.limbs.len());
        }
        for i in (0..self.limbs.len()).rev() {
            match self.limbs[i].cmp(&o.limbs[i]) {
                Ordering::Equal => {}
                c => return c,
            }
        }
        Ordering::Equal
    }

    /// `self * 2^n`.
    pub(crate) fn shl(&self, n: u64) -> Big {
        if self.is_zero() {
            return Big::zero();
        }
        let words = (n / 32) as usize;
        let bits = (n % 32) as u32;
        let mut r = vec![0u32; words];
        let mut carry = 0u32;
        for &l in &self.limbs {
            if bits == 0 {
                r.push(l);
            } else {
                r.push((l << bits) | carry);
                carry = l >> (32 - bits);
            }
        }
        r.push(carry);
        let mut b = Big { limbs: r };
        b.trim();
        b
    }

    /// `floor(self / 2^n)`.
    pub(crate) fn shr(&self, n: u64) -> Big {
        let words = (n / 32) as usize;
        if words >= self.limbs.len() {
            return Big::zero();
        }
        let bits = (n % 32) as u32;
        let src = &self.limbs[words..];
        let mut r = Vec::with_capacity(src.len());
        for i in 0..src.len() {
            let lo = src[i] >> bits;
            let hi = if bits == 0 {
                0
            } else {
                src.get(i + 1).map_or(0, |&h| h << (32 - bits))
            };
            r.push(lo | hi);
        }
        let mut b = Big { limbs: r };
        b.trim();
        b
    }

    /// `self mod 2^n`.
    pub(crate) fn low_bits(&self, n: u64) -> Big {
        let words = (n / 32) as usize;
        let bits = (n % 32) as u32;
        let mut r: Vec<u32> = self.limbs.iter().take(words + 1).copied().collect();
        if r.len() > words {
            r[words] &= if bits == 0 { 0 } else { (1u32 << bits) - 1 };
        }
        let mut b = Big { limbs: r };
        b.trim();
        b
    }

    /// True when some bit below position `n` is set (`self mod 2^n != 0`).
    pub(crate) fn any_low_bits(&self, n: u64) -> bool {
        !self.low_bits(n).is_zero()
    }

    /// The low 64 bits.
    pub(crate) fn low_u64(&self) -> u64 {
        let a = *self.limbs.first().unwrap_or(&0) as u64;
        let b = *self.limbs.get(1).unwrap_or(&0) as u64;
        a | (b << 32)
    }

    /// `5^m`.
    pub(crate) fn pow5(m: u64) -> Big {
        let mut r = Big::from_u64(1);
        let mut left = m;
        while left >= 13 {
            r.mul_small_add(1_220_703_125, 0); // 5^13
            left -= 13;
        }
        r.mul_small_add(5u32.pow(left as u32), 0);
        r
    }

    /// `(floor(self / d), self mod d != 0)` by binary long division; `d > 0`.
    pub(crate) fn div_floor(&self, d: &Big) -> (Big, bool) {
        let mut q = Big::zero();
        let mut rem = Big::zero();
        let n = self.bit_len();
        for i in (0..n).rev() {
            rem = rem.shl(1);
            if self.bit(i) {
                rem.mul_small_add(1, 1);
            }
            q = q.shl(1);
            if rem.cmp_big(d) != Ordering::Less {
                rem = rem.sub(d);
                q.mul_small_add(1, 1);
            }
        }
        let inexact = !rem.is_zero();
        (q, inexact)
    }

    /// The decimal digits (no sign, no leading zero; "0" for zero).
    pub(crate) fn to_decimal(&self) -> String {
        if self.is_zero() {
            return "0".to_string();
        }
        let mut t = self.clone();
        let mut chunks = Vec::new();
        while !t.is_zero() {
            chunks.push(t.div_small(1_000_000_000));
        }
        let mut s = chunks.pop().map(|c| c.to_string()).unwrap_or_default();
        for c in chunks.iter().rev() {
            s.push_str(&format!("{c:09}"));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_on_known_values() {
        let a = Big::from_u64(u64::MAX);
        let sq = a.mul(&a); // (2^64 - 1)^2 = 2^128 - 2^65 + 1
        let expect = Big::from_u64(1)
            .shl(128)
            .sub(&Big::from_u64(1).shl(65))
            .add(&Big::from_u64(1));
        assert_eq!(sq, expect);
        assert_eq!(Big::pow5(27).to_decimal(), "7450580596923828125");
        let (q, inexact) = Big::pow5(40).div_floor(&Big::pow5(27));
        assert_eq!((q.to_decimal().as_str(), inexact), ("1220703125", false));
        let (q, inexact) = Big::from_u64(100).div_floor(&Big::from_u64(7));
        assert_eq!((q.low_u64(), inexact), (14, true));
        assert_eq!(Big::from_u64(0b1011_0000).shr(4).low_u64(), 0b1011);
        assert_eq!(Big::from_u64(0b1011_0110).low_bits(4).low_u64(), 0b0110);
        assert_eq!(Big::from_u64(1).shl(100).bit_len(), 101);
    }
}
