//! Taylor-series arithmetic: the coefficients of every node of a tape, computed order by
//! order by the recurrences of automatic differentiation ([spec eqs. (2.3)-(2.12)](crate::spec::taylor)), over a
//! coefficient type ([`Coef`]: intervals, rigorous; or f64, to choose things).

use super::program::Op;
use crate::scalar::Scalar;
use crate::precision::dd::DdInterval;
use crate::precision::wide::WideInterval;
use inari::Interval;
use std::cell::RefCell;
use std::thread::LocalKey;

/// Storage of the Taylor coefficients of every node, node-major. The storage (and the
/// record of non-zero coefficients) is per-thread scratch, reused from one evaluation to the
/// next: a small pool per thread, so that series alive at once (a step's centre series while
/// its a priori and variational series are computed) each reuse a buffer instead of
/// allocating one (a fresh buffer of a large tape costs page faults).
pub(super) struct Series<T: Coef> {
    n: usize,
    /// False once a singular operation (divisor or sqrt argument not proved safe) was met.
    pub(super) ok: bool,
    /// The coefficients of node i at `i n ..`, then the companion series (cos for a Sin
    /// node, sin for a Cos node, cosh for Sinh, sinh for Cosh, 1 + a^2 for Atan(a)) of
    /// node i at `(nodes + i) n ..`. Coefficient k of every node (and of every companion
    /// that its operation keeps) is written by `step(k)` before anything reads it; the
    /// companion rows of the other operations are never read.
    c: Vec<T>,
    aux_at: usize,
    /// Per node, the first and last index of a coefficient (or companion) not exactly 0
    /// so far; `(usize::MAX, 0)` while all are 0.
    nz: Vec<(usize, usize)>,
}

impl<T: Coef> Series<T> {
    /// The storage is not cleared: every coefficient is written (a constant's past 0 as 0,
    /// a companion by its operation) before it is read, the stale values of an earlier series
    /// never are; clearing megabytes of wide intervals per series was a measurable part of
    /// the work above 106 bits.
    pub(super) fn new(nodes: usize, n: usize) -> Self {
        let mut c = T::scratch().with(|s| s.borrow_mut().pop()).unwrap_or_default();
        c.truncate(2 * nodes * n);
        c.resize(2 * nodes * n, T::zero());
        let mut nz = SCRATCH_NZ.with(|s| s.borrow_mut().pop()).unwrap_or_default();
        nz.clear();
        nz.resize(nodes, (usize::MAX, 0));
        Series {
            n,
            ok: true,
            c,
            aux_at: nodes * n,
            nz,
        }
    }
    /// Room for `n` coefficients per node (and companion), those computed kept. In place:
    /// the rows move up, last first, in the storage grown (a fresh buffer per growth cost
    /// page faults); the room past each row's coefficients is left as it was, since every
    /// coefficient is written before it is read (as in `new`).
    pub(super) fn widen(&mut self, n: usize) {
        let old = self.n;
        if n <= old {
            return;
        }
        let rows = 2 * self.aux_at / old;
        self.c.resize(rows * n, T::zero());
        for r in (1..rows).rev() {
            self.c.copy_within(r * old..(r + 1) * old, r * n);
        }
        self.aux_at = rows / 2 * n;
        self.n = n;
    }
    pub(super) fn get(&self, node: u32, k: usize) -> T {
        self.c[node as usize * self.n + k]
    }
    fn aux(&self, node: u32, k: usize) -> T {
        self.c[self.aux_at + node as usize * self.n + k]
    }

    /// Coefficient k of every node, given all coefficients below k ([spec eq. (2.3)-(2.7)](crate::spec::taylor)).
    pub(super) fn step(&mut self, ops: &[Op], k: usize, input_k: &[T]) {
        let zero = T::zero();
        for (idx, op) in ops.iter().enumerate() {
            let (val, aux) = match *op {
                Op::Input(i) => (input_k[i], None),
                // a constant's coefficients past 0 are 0 (written: `new` leaves the storage
                // as the last series left it)
                Op::Const(_) | Op::Pi if k > 0 => (zero, None),
                Op::Const(c) => (T::cst(c), None),
                Op::Pi => (T::pi(), None),
                Op::Add(a, b) => (self.get(a, k) + self.get(b, k), None),
                Op::Sub(a, b) => (self.get(a, k) - self.get(b, k), None),
                Op::Neg(a) => (-self.get(a, k), None),
                Op::Scale(a, c) => (self.get(a, k) * T::cst(c), None),
                Op::Mul(a, b) => {
                    // (2.3) w_k = sum_{j=0..k} a_j b_{k-j}
                    (self.conv(zero, false, a, b, self.terms(a, b, k, 0, k), k), None)
                }
                Op::Div(a, b) => {
                    // (2.4) w_k = (a_k - sum_{j=1..k} b_j w_{k-j}) / b_0
                    let me = idx as u32;
                    let acc = self.conv(self.get(a, k), true, b, me, self.terms(b, me, k, 1, k), k);
                    let b0 = self.get(b, 0);
                    if !b0.safe_divisor() {
                        self.ok = false;
                    }
                    (acc.quot(b0), None)
                }
                Op::Sqrt(a) => {
                    // (2.5) w_0 = sqrt(a_0); w_k = (a_k - sum_{j=1..k-1} w_j w_{k-j}) / (2 w_0)
                    if k == 0 {
                        let a0 = self.get(a, 0);
                        if !a0.safe_sqrt_arg() {
                            self.ok = false;
                        }
                        (a0.sqrt(), None)
                    } else {
                        let me = idx as u32;
                        let terms = self.terms(me, me, k, 1, k - 1);
                        let acc = self.conv(self.get(a, k), true, me, me, terms, k);
                        let w0 = self.get(me, 0);
                        (acc.quot(w0 + w0), None)
                    }
                }
                Op::Sin(a) | Op::Cos(a) => {
                    // (2.6)-(2.7) s_k = (1/k) sum j u_j c_{k-j}, c_k = -(1/k) sum j u_j s_{k-j}
                    let me = idx as u32;
                    let is_sin = matches!(op, Op::Sin(_));
                    let (s, c) = if k == 0 {
                        let u0 = self.get(a, 0);
                        (u0.sin(), u0.cos())
                    } else {
                        let (lo, hi) = self.nz[a as usize];
                        let (sp, cp) = if is_sin { (false, true) } else { (true, false) };
                        let (s, c) =
                            self.weighted_pair(true, a, (me, cp), (me, sp), lo.max(1), hi.min(k), k);
                        (s.quot_int(k), c.quot_int(k))
                    };
                    if is_sin {
                        (s, Some(c))
                    } else {
                        (c, Some(s))
                    }
                }
                Op::Exp(a) => {
                    // (2.9) w_0 = exp(a_0); w_k = (1/k) sum_{j=1..k} j a_j w_{k-j}
                    let me = idx as u32;
                    if k == 0 {
                        (self.get(a, 0).exp(), None)
                    } else {
                        let (lo, hi) = self.nz[a as usize];
                        let acc = self.weighted(false, a, (me, false), lo.max(1), hi.min(k), k);
                        (acc.quot_int(k), None)
                    }
                }
                Op::Ln(a) => {
                    // (2.10) w_0 = ln(a_0), a_0 > 0;
                    // w_k = (a_k - (1/k) sum_{j=1..k-1} j w_j a_{k-j}) / a_0
                    let me = idx as u32;
                    let a0 = self.get(a, 0);
                    if k == 0 {
                        if !a0.safe_sqrt_arg() {
                            self.ok = false;
                        }
                        (a0.ln(), None)
                    } else {
                        let mut acc = zero;
                        for j in 1..k {
                            acc =
                                acc.mul_acc(T::cst(j as f64) * self.get(me, j), self.get(a, k - j));
                        }
                        ((self.get(a, k) - acc.quot_int(k)).quot(a0), None)
                    }
                }
                Op::Atan(a) => {
                    // (2.11) g = 1 + a^2 (companion); w_0 = atan(a_0);
                    // w_k = (a_k - (1/k) sum_{j=1..k-1} j w_j g_{k-j}) / g_0
                    let me = idx as u32;
                    let mut g = if k == 0 { T::one() } else { zero };
                    for j in 0..=k {
                        g = g.mul_acc(self.get(a, j), self.get(a, k - j));
                    }
                    if k == 0 {
                        (self.get(a, 0).atan(), Some(g))
                    } else {
                        let mut acc = zero;
                        for j in 1..k {
                            acc = acc
                                .mul_acc(T::cst(j as f64) * self.get(me, j), self.aux(me, k - j));
                        }
                        ((self.get(a, k) - acc.quot_int(k)).quot(self.aux(me, 0)), Some(g))
                    }
                }
                Op::Sinh(a) | Op::Cosh(a) => {
                    // (2.12) s_k = (1/k) sum j a_j c_{k-j}, c_k = (1/k) sum j a_j s_{k-j}
                    let me = idx as u32;
                    let is_sinh = matches!(op, Op::Sinh(_));
                    let (s, c) = if k == 0 {
                        let u0 = self.get(a, 0);
                        (u0.sinh(), u0.cosh())
                    } else {
                        let (lo, hi) = self.nz[a as usize];
                        let (sp, cp) = if is_sinh { (false, true) } else { (true, false) };
                        let (s, c) =
                            self.weighted_pair(false, a, (me, cp), (me, sp), lo.max(1), hi.min(k), k);
                        (s.quot_int(k), c.quot_int(k))
                    };
                    if is_sinh {
                        (s, Some(c))
                    } else {
                        (c, Some(s))
                    }
                }
            };
            // companions are stored for the operations that have one; the others' are never
            // read
            self.c[idx * self.n + k] = val;
            let mut nonzero = !val.is_exact_zero();
            if let Some(aux) = aux {
                self.c[self.aux_at + idx * self.n + k] = aux;
                nonzero |= !aux.is_exact_zero();
            }
            if nonzero {
                let e = &mut self.nz[idx];
                e.0 = e.0.min(k);
                e.1 = k;
            }
        }
    }

    /// `sum_{j = lo..=hi} (j a_j) b_{k-j}` (`-sum` when `neg`; `0` when `lo > hi`), `b` the
    /// node `b.0`'s coefficients or (`b.1`) its companion's: the sums of (2.6)-(2.12) as one
    /// [`Coef::weighted_conv`].
    fn weighted(&self, neg: bool, a: u32, b: (u32, bool), lo: usize, hi: usize, k: usize) -> T {
        if lo > hi {
            return T::zero();
        }
        let a = a as usize * self.n;
        let b = b.0 as usize * self.n + if b.1 { self.aux_at } else { 0 };
        T::weighted_conv(
            T::zero(),
            neg,
            lo,
            &self.c[a + lo..=a + hi],
            &self.c[b + k - hi..=b + k - lo],
        )
    }

    /// The two sums of [`Series::weighted`] over the same `a` and weights that a sine and
    /// cosine (or sinh and cosh) recurrence takes, `b` for the first and `c` for the second
    /// (`-sum` when `neg_c`), as one [`Coef::weighted_conv_pair`].
    #[allow(clippy::too_many_arguments)]
    fn weighted_pair(
        &self,
        neg_c: bool,
        a: u32,
        b: (u32, bool),
        c: (u32, bool),
        lo: usize,
        hi: usize,
        k: usize,
    ) -> (T, T) {
        if lo > hi {
            return (T::zero(), T::zero());
        }
        let at = |node: (u32, bool)| node.0 as usize * self.n + if node.1 { self.aux_at } else { 0 };
        let (a, b, c) = (a as usize * self.n, at(b), at(c));
        T::weighted_conv_pair(
            neg_c,
            lo,
            &self.c[a + lo..=a + hi],
            &self.c[b + k - hi..=b + k - lo],
            &self.c[c + k - hi..=c + k - lo],
        )
    }

    /// `acc + sum_{j in terms} a_j b_{k-j}` (`acc - ...` when `neg`).
    fn conv(
        &self,
        acc: T,
        neg: bool,
        a: u32,
        b: u32,
        terms: std::ops::RangeInclusive<usize>,
        k: usize,
    ) -> T {
        if terms.is_empty() {
            return acc;
        }
        let (lo, hi) = (*terms.start(), *terms.end());
        let (a, b) = (a as usize * self.n, b as usize * self.n);
        T::conv(acc, neg, &self.c[a + lo..=a + hi], &self.c[b + k - hi..=b + k - lo])
    }

    /// The indices j in [from, to] for which both a_j and b_{k-j} may be non-zero: terms
    /// with an exactly zero factor are zero and are skipped ([spec eq. (2.3)](crate::spec::taylor)).
    fn terms(
        &self,
        a: u32,
        b: u32,
        k: usize,
        from: usize,
        to: usize,
    ) -> std::ops::RangeInclusive<usize> {
        let (la, ha) = self.nz[a as usize];
        let (lb, hb) = self.nz[b as usize];
        if la > ha || lb > hb || k < lb {
            #[allow(clippy::reversed_empty_ranges)]
            return 1..=0;
        }
        from.max(la).max(k.saturating_sub(hb))..=to.min(ha).min(k - lb)
    }
}

impl<T: Coef> Drop for Series<T> {
    fn drop(&mut self) {
        let c = std::mem::take(&mut self.c);
        let _ = T::scratch().try_with(|s| keep(s, c));
        let nz = std::mem::take(&mut self.nz);
        let _ = SCRATCH_NZ.try_with(|s| keep(s, nz));
    }
}

/// Buffers kept per thread and type for the series to come (more series are seldom alive at
/// once).
const POOL: usize = 4;

/// A per-thread pool of buffers.
pub(super) type Pool<T> = RefCell<Vec<Vec<T>>>;

/// Back into the pool, unless it is full.
fn keep<T>(pool: &Pool<T>, buffer: Vec<T>) {
    let mut pool = pool.borrow_mut();
    if pool.len() < POOL {
        pool.push(buffer);
    }
}

thread_local! {
    static SCRATCH_INTERVAL: Pool<Interval> = const { RefCell::new(Vec::new()) };
    static SCRATCH_F64: Pool<f64> = const { RefCell::new(Vec::new()) };
    static SCRATCH_DD: Pool<DdInterval> = const { RefCell::new(Vec::new()) };
    static SCRATCH_WIDE: Pool<WideInterval> = const { RefCell::new(Vec::new()) };
    static SCRATCH_NZ: Pool<(usize, usize)> = const { RefCell::new(Vec::new()) };
}

/// A coefficient type for the Taylor recurrences: intervals (rigorous, with the domain
/// checks of [spec eq. (2.8)](crate::spec::taylor)) or f64 (only to *choose* things, e.g. Newton guesses).
pub trait Coef: Scalar + Copy + 'static {
    /// The per-thread storage reused by the Taylor series of this coefficient type.
    fn scratch() -> &'static LocalKey<Pool<Self>>;
    /// Exactly 0 (terms with such a factor are skipped).
    fn is_exact_zero(&self) -> bool;
    /// Proved non-zero (Interval: 0 not in it).
    fn safe_divisor(&self) -> bool;
    /// Proved positive.
    fn safe_sqrt_arg(&self) -> bool;
    /// Finite (intervals: non-empty with finite ends).
    fn is_finite_coef(&self) -> bool;
    /// `self + a b`; for intervals fused (one outward rounding, inari's `mul_add`), which
    /// encloses the exact value as the unfused form does, and is tighter and faster.
    fn mul_acc(self, a: Self, b: Self) -> Self;
    /// `acc + sum_j x_j y_{n-1-j}` (`acc - ...` when `neg`), `n = x.len() = y.len()`: the
    /// convolutions of (2.3)-(2.5). Intervals: [spec (1.4)](crate::spec::scalars); f64: four partial sums.
    fn conv(acc: Self, neg: bool, x: &[Self], y: &[Self]) -> Self;
    /// `acc + sum_i ((first + i) x_i) y_{n-1-i}` (`acc - ...` when `neg`), `n = x.len() =
    /// y.len()`: the weighted sums of (2.6)-(2.12). By default each weighted factor
    /// `(first + i) x_i` is computed and added in turn with [`Coef::mul_acc`]; wide intervals
    /// sum in one fused dot product with exact weights ([spec (12.2.9)](crate::spec::precision)).
    fn weighted_conv(acc: Self, neg: bool, first: usize, x: &[Self], y: &[Self]) -> Self {
        weighted_stepwise(acc, neg, first, x, y)
    }
    /// `(weighted_conv(0, false, first, x, y), weighted_conv(0, neg_z, first, x, z))`. By
    /// default in one pass that computes each weighted factor `(first + i) x_i` once for
    /// both sums (the same operations, in the same order, as two [`Coef::weighted_conv`]).
    fn weighted_conv_pair(neg_z: bool, first: usize, x: &[Self], y: &[Self], z: &[Self]) -> (Self, Self) {
        let n = x.len();
        let (mut s, mut c) = (Self::zero(), Self::zero());
        for (i, &xi) in x.iter().enumerate() {
            let ju = Self::cst((first + i) as f64) * xi;
            s = s.mul_acc(ju, y[n - 1 - i]);
            c = c.mul_acc(if neg_z { -ju } else { ju }, z[n - 1 - i]);
        }
        (s, c)
    }
    /// `self / b`, with `b` proved non-zero where the recurrences divide (intervals: [spec
    /// (1.4)](crate::spec::scalars), inari's quotient).
    fn quot(self, b: Self) -> Self;
    /// `self / k` for the positive integer `k` of a recurrence's `1 / k`: [`Coef::quot`] by
    /// the constant `k` unless the type divides by an integer more cheaply (double-double
    /// intervals, [spec (12.1.22)](crate::spec::precision)).
    fn quot_int(self, k: usize) -> Self {
        self.quot(Self::cst(k as f64))
    }
}

impl Coef for Interval {
    fn scratch() -> &'static LocalKey<Pool<Self>> {
        &SCRATCH_INTERVAL
    }
    fn is_exact_zero(&self) -> bool {
        self.inf() == 0.0 && self.sup() == 0.0
    }
    fn safe_divisor(&self) -> bool {
        !self.is_empty() && !self.contains(0.0)
    }
    fn safe_sqrt_arg(&self) -> bool {
        !self.is_empty() && self.inf() > 0.0
    }
    fn is_finite_coef(&self) -> bool {
        finite(*self)
    }
    fn mul_acc(self, a: Self, b: Self) -> Self {
        a.mul_add(b, self)
    }
    fn conv(acc: Self, neg: bool, x: &[Self], y: &[Self]) -> Self {
        crate::dot::dot(acc, neg, x, y, true)
    }
    fn quot(self, b: Self) -> Self {
        crate::dot::quotient(self, b)
    }
}

impl Coef for DdInterval {
    fn scratch() -> &'static LocalKey<Pool<Self>> {
        &SCRATCH_DD
    }
    fn is_exact_zero(&self) -> bool {
        DdInterval::is_exact_zero(*self)
    }
    fn safe_divisor(&self) -> bool {
        !self.is_empty() && !self.contains_f64(0.0)
    }
    fn safe_sqrt_arg(&self) -> bool {
        !self.is_empty() && self.inf_f64() > 0.0
    }
    fn is_finite_coef(&self) -> bool {
        self.is_finite()
    }
    fn mul_acc(self, a: Self, b: Self) -> Self {
        // a b + self, each operation outward rounded ([spec (12.1)](crate::spec::precision))
        a.mul_add(b, self)
    }
    fn conv(acc: Self, neg: bool, x: &[Self], y: &[Self]) -> Self {
        // one midpoint-radius sum ([spec (12.1.21)](crate::spec::precision))
        DdInterval::dot_acc(acc, neg, x.iter().copied().zip(y.iter().rev().copied()))
    }
    fn quot(self, b: Self) -> Self {
        self / b
    }
    fn quot_int(self, k: usize) -> Self {
        match u32::try_from(k) {
            Ok(k) => self.div_int(k),
            Err(_) => self.quot(Self::cst(k as f64)),
        }
    }
}

/// Intervals of more than 106 bits ([spec (12.3)](crate::spec::precision)).
impl Coef for WideInterval {
    fn scratch() -> &'static LocalKey<Pool<Self>> {
        &SCRATCH_WIDE
    }
    fn is_exact_zero(&self) -> bool {
        WideInterval::is_exact_zero(self)
    }
    fn safe_divisor(&self) -> bool {
        !self.is_empty() && !self.contains_f64(0.0)
    }
    fn safe_sqrt_arg(&self) -> bool {
        !self.is_empty() && self.inf_f64() > 0.0
    }
    fn is_finite_coef(&self) -> bool {
        self.is_finite()
    }
    fn mul_acc(self, a: Self, b: Self) -> Self {
        WideInterval::mul_acc(&self, &a, &b)
    }
    fn conv(acc: Self, neg: bool, x: &[Self], y: &[Self]) -> Self {
        WideInterval::conv(&acc, neg, x, y)
    }
    fn weighted_conv(acc: Self, neg: bool, first: usize, x: &[Self], y: &[Self]) -> Self {
        WideInterval::weighted_conv(&acc, neg, first as u64, x, y)
            .unwrap_or_else(|| weighted_stepwise(acc, neg, first, x, y))
    }
    fn weighted_conv_pair(neg_z: bool, first: usize, x: &[Self], y: &[Self], z: &[Self]) -> (Self, Self) {
        let zero = Self::zero();
        (
            <Self as Coef>::weighted_conv(zero, false, first, x, y),
            <Self as Coef>::weighted_conv(zero, neg_z, first, x, z),
        )
    }
    fn quot(self, b: Self) -> Self {
        self / b
    }
}

impl Coef for f64 {
    fn scratch() -> &'static LocalKey<Pool<Self>> {
        &SCRATCH_F64
    }
    fn is_exact_zero(&self) -> bool {
        *self == 0.0
    }
    fn safe_divisor(&self) -> bool {
        *self != 0.0 && self.is_finite()
    }
    fn safe_sqrt_arg(&self) -> bool {
        *self > 0.0
    }
    fn is_finite_coef(&self) -> bool {
        self.is_finite()
    }
    fn mul_acc(self, a: Self, b: Self) -> Self {
        self + a * b
    }
    fn conv(acc: Self, neg: bool, x: &[Self], y: &[Self]) -> Self {
        // Four partial sums of every fourth term, added at the end: four chains of additions
        // run side by side, where one chain waits for each addition before the next. The
        // float series only choose (steps, the Newton guess), so the order of the sum is free.
        let n = x.len();
        let mut part = [0.0f64; 4];
        let mut rest = 0.0;
        let mut j = 0;
        while j + 4 <= n {
            for (l, p) in part.iter_mut().enumerate() {
                *p += x[j + l] * y[n - 1 - j - l];
            }
            j += 4;
        }
        for i in j..n {
            rest += x[i] * y[n - 1 - i];
        }
        let sum = (part[0] + part[1]) + (part[2] + part[3]) + rest;
        if neg {
            acc - sum
        } else {
            acc + sum
        }
    }
    fn quot(self, b: Self) -> Self {
        self / b
    }
}

/// [`Coef::weighted_conv`] term by term: `acc <- acc + ((first + i) x_i) y_{n-1-i}` (the
/// weighted factor negated when `neg`), each step [`Coef::mul_acc`].
fn weighted_stepwise<T: Coef>(acc: T, neg: bool, first: usize, x: &[T], y: &[T]) -> T {
    let n = x.len();
    let mut acc = acc;
    for (i, &xi) in x.iter().enumerate() {
        let ju = T::cst((first + i) as f64) * xi;
        acc = acc.mul_acc(if neg { -ju } else { ju }, y[n - 1 - i]);
    }
    acc
}

/// A non-empty interval with finite endpoints.
pub fn finite(x: Interval) -> bool {
    !x.is_empty() && x.inf().is_finite() && x.sup().is_finite()
}

#[cfg(test)]
mod tests {
    use crate::scalar::{point, Scalar};
    use crate::tape::{Tape, Tracer};

    /// A constant's coefficients past 0 are exactly 0 (the recurrences skip them): for
    /// `x' = x + (3 + pi)`, `x_k = x_{k-1} / k` exactly from k = 2 on, in a series that
    /// reuses the storage of an earlier one and in one carried on to a higher order.
    #[test]
    fn constants_have_no_coefficients_past_zero() {
        let dirty = Tape::record(1, |x| vec![x[0] * x[0] + Tracer::cst(5.0)]);
        let tape = Tape::record(1, |x| vec![x[0] + (Tracer::cst(3.0) + Tracer::pi())]);
        for _ in 0..2 {
            dirty.ode_taylor(&[0.5f64], 20).unwrap();
            let plain = tape.ode_taylor(&[0.25f64], 12).unwrap();
            let carried = tape.ode_taylor_until(&[0.25f64], 8, 16, |_| false).unwrap();
            for c in [&plain, &carried] {
                let x: Vec<f64> = c.iter().map(|r| r[0]).collect();
                assert_eq!(x[1], 0.25 + (3.0 + std::f64::consts::PI));
                for k in 2..x.len() {
                    assert_eq!(x[k], x[k - 1] / k as f64, "k = {k}");
                }
            }
            let iv = tape.ode_taylor(&[point(0.25)], 12).unwrap();
            for k in 2..iv.len() {
                let q = crate::dot::quotient(iv[k - 1][0], point(k as f64));
                assert!(iv[k][0].inf() == q.inf() && iv[k][0].sup() == q.sup());
            }
        }
    }

    /// The weighted sums of (2.6)-(2.12) over wide intervals (one fused dot product with exact
    /// weights, spec (12.2.9)) are never wider than the term-by-term recurrence they replace,
    /// for point, narrow, straddling and wide factors, at 160, 256 and 1024 bits.
    #[test]
    fn wide_weighted_sums_are_no_wider_than_term_by_term() {
        use super::{weighted_stepwise, Coef};
        use crate::precision::wide::{with_bits, WideInterval as W};
        for bits in [160, 256, 1024] {
            with_bits(bits, || {
                let c = |x: f64| W::cst(x);
                let seven = c(7.0);
                let x: Vec<W> = (0..23)
                    .map(|i| match i % 4 {
                        0 => c(i as f64 + 0.5),
                        1 => c(i as f64 + 1.0) / seven,
                        2 => c(i as f64) / seven - c(1.5),
                        _ => c(-(i as f64)) / seven + c(2.0).hull(&c(-0.25)),
                    })
                    .collect();
                let y: Vec<W> = x.iter().rev().map(|v| *v / c(3.0) - c(0.125)).collect();
                for first in [1usize, 5, 300] {
                    for neg in [false, true] {
                        for acc in [W::zero(), c(1.0) / seven] {
                            let fused = W::weighted_conv(&acc, neg, first as u64, &x, &y)
                                .expect("bounded");
                            let old = weighted_stepwise(acc, neg, first, &x, &y);
                            assert!(fused.subset(&old), "{bits}: {fused:?} wider than {old:?}");
                            assert_eq!(<W as Coef>::weighted_conv(acc, neg, first, &x, &y), fused);
                        }
                    }
                }
            })
        }
    }

    /// `Series::new` does not clear the reused storage: a series computed after a larger one
    /// that left other values everywhere equals the same series computed on a fresh thread
    /// (fresh storage), bit for bit, for every operation, constants read past order 0 (by
    /// `+`, `ln`, `atan`) and a constant output, over f64, intervals and wide intervals.
    #[test]
    fn stale_storage_is_never_read() {
        use super::Coef;
        use crate::precision::wide::{with_bits, WideInterval};
        let dirty = Tape::record(3, |x| {
            let mut v = vec![];
            for i in 0..40 {
                let c = Tracer::cst(1.0 + i as f64 / 8.0);
                v.push((x[i % 3].exp() * c).sinh() + x[0].atan() * c);
            }
            v.truncate(3);
            v
        });
        let tape = Tape::record(3, |x| {
            let c = Tracer::cst(0.75);
            let p = Tracer::pi();
            vec![
                (x[0] + c).ln() + c.ln() * x[1] + c.atan() + (x[1] - p).sin() * x[2].cos(),
                (x[2] / (x[0] + Tracer::cst(2.0))).exp() + (c + x[1] * x[1]).sqrt()
                    - x[0].sinh() * x[1].cosh()
                    + (-x[2]).atan()
                    + Tracer::cst(3.0) * x[0],
                c + p,
            ]
        });
        fn run<T: Coef + Send + std::fmt::Debug>(
            dirty: &Tape,
            tape: &Tape,
            dirty_x: &[T],
            x: &[T],
        ) -> (String, String) {
            assert!(dirty.ode_taylor(dirty_x, 30).is_some());
            let after = format!("{:?}", tape.ode_taylor(x, 12).unwrap());
            let (tape, x) = (tape.clone(), x.to_vec());
            let fresh = std::thread::spawn(move || format!("{:?}", tape.ode_taylor(&x, 12).unwrap()))
                .join()
                .unwrap();
            (after, fresh)
        }
        let (a, b) = run(&dirty, &tape, &[0.5f64, 0.25, 0.125], &[0.3f64, 0.2, 0.1]);
        assert_eq!(a, b);
        let iv = |v: f64| point(v);
        let (a, b) = run(
            &dirty,
            &tape,
            &[iv(0.5), iv(0.25), iv(0.125)],
            &[iv(0.3), iv(0.2), iv(0.1)],
        );
        assert_eq!(a, b);
        let w = |v: f64| WideInterval::cst(v);
        let a = with_bits(160, || {
            run(
                &dirty,
                &tape,
                &[w(0.5), w(0.25), w(0.125)],
                &[w(0.3), w(0.2), w(0.1)],
            )
            .0
        });
        let t = tape.clone();
        let fresh = std::thread::spawn(move || {
            with_bits(160, || {
                let w = |v: f64| WideInterval::cst(v);
                format!("{:?}", t.ode_taylor(&[w(0.3), w(0.2), w(0.1)], 12).unwrap())
            })
        })
        .join()
        .unwrap();
        assert_eq!(a, fresh);
    }

    #[test]
    fn taylor_coefficients_of_exp_and_rotation() {
        // x' = x from x(0) = 1: coefficients 1/k!
        let tape = Tape::record(1, |x| vec![x[0]]);
        let c = tape.ode_taylor(&[point(1.0)], 10).unwrap();
        let mut f = 1.0f64;
        for (k, ck) in c.iter().enumerate() {
            if k > 0 {
                f *= k as f64;
            }
            assert!(ck[0].contains(1.0 / f) || (ck[0].inf() - 1.0 / f).abs() < 1e-16);
            assert!(ck[0].wid() < 1e-15);
        }
        // phi' = 1, s' = cos(phi): s(t) = sin(t), coefficients of sin
        let tape = Tape::record(2, |x| vec![Tracer::one(), x[0].cos()]);
        let c = tape.ode_taylor(&[point(0.0), point(0.0)], 7).unwrap();
        assert!(c[1][1].contains(1.0));
        assert!(c[3][1].contains(-1.0 / 6.0) || (c[3][1].mid() + 1.0 / 6.0).abs() < 1e-16);
        assert!(c[2][1].contains(0.0) && c[2][1].wid() < 1e-16);
        assert!((c[5][1].mid() - 1.0 / 120.0).abs() < 1e-16);
    }

    /// The recurrences (2.9)-(2.12) against series known in closed form: with t' = 1 and
    /// y' = f(t), y_k = [t^{k-1}] f / k.
    #[test]
    fn taylor_coefficients_of_exp_ln_atan_sinh_cosh_pi() {
        type Coeffs = fn(usize) -> f64;
        type Case = (&'static str, fn(Tracer) -> Tracer, Coeffs);
        let cases: [Case; 6] = [
            (
                "exp",
                |t| t.exp(),
                |j| 1.0 / (1..=j).fold(1.0, |a, i| a * i as f64),
            ),
            (
                "ln(1+t)",
                |t| (Tracer::one() + t).ln(),
                |j| {
                    if j == 0 {
                        0.0
                    } else if j % 2 == 1 {
                        1.0 / j as f64
                    } else {
                        -1.0 / j as f64
                    }
                },
            ),
            (
                "atan",
                |t| t.atan(),
                |j| {
                    if j % 2 == 0 {
                        0.0
                    } else if j % 4 == 1 {
                        1.0 / j as f64
                    } else {
                        -1.0 / j as f64
                    }
                },
            ),
            (
                "sinh",
                |t| t.sinh(),
                |j| {
                    if j % 2 == 1 {
                        1.0 / (1..=j).fold(1.0, |a, i| a * i as f64)
                    } else {
                        0.0
                    }
                },
            ),
            (
                "cosh",
                |t| t.cosh(),
                |j| {
                    if j % 2 == 0 {
                        1.0 / (1..=j).fold(1.0, |a, i| a * i as f64)
                    } else {
                        0.0
                    }
                },
            ),
            (
                "pi*t",
                |t| Tracer::pi() * t,
                |j| if j == 1 { std::f64::consts::PI } else { 0.0 },
            ),
        ];
        for (name, f, coef) in cases {
            let tape = Tape::record(2, |x| vec![Tracer::one(), f(x[0])]);
            let c = tape.ode_taylor(&[point(0.0), point(0.0)], 12).unwrap();
            for k in 1..=12 {
                let want = coef(k - 1) / k as f64;
                let got = c[k][1];
                assert!(
                    got.inf() - 1e-15 * want.abs() <= want
                        && want <= got.sup() + 1e-15 * want.abs(),
                    "{name}: y_{k} = [{}, {}], want {want}",
                    got.inf(),
                    got.sup()
                );
                assert!(got.wid() <= 1e-14, "{name}: width");
            }
        }
        // ln refuses an argument not proved positive (2.10), as sqrt does
        let tape = Tape::record(1, |x| vec![x[0].ln()]);
        assert!(tape
            .ode_taylor(&[crate::scalar::iv(-0.5, 1.0)], 3)
            .is_none());
        // pi is enclosed, not rounded
        let p = Tape::record(1, |_| vec![Tracer::pi()])
            .eval_checked(&[point(0.0)])
            .unwrap()[0];
        assert!(p.inf() < p.sup() && p.contains(std::f64::consts::PI));
    }
}
