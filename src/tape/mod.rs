//! Recording a computation once and replaying it: over any
//! [`Scalar`](crate::scalar::Scalar) (one value per node) and over truncated Taylor series
//! of intervals (spec/02-taylor.md, eqs. (2.1)-(2.7)).
//!
//! A scene's vector field is written once over `S: Scalar`. Instantiated with
//! [`Tracer`](crate::tape::Tracer), it records a straight-line program (a tape); the
//! validated integrator replays the tape with the recurrences of automatic Taylor
//! differentiation, O(p^2) per node for p coefficients. Replaying over `f64` gives the
//! float field, over `Interval` the rigorous one: they cannot drift apart because they are
//! the same tape.
//!
//! The only simplifications made while recording are exact identities of real arithmetic
//! (`x + 0 = x`, `x * 0 = 0`, `x * 1 = x`, `x / 1 = x`), so replaying is sound.

// Float comparisons are written as guards on purpose: `c == 0.0` also matches -0.0.
#![allow(clippy::redundant_guards)]

use crate::scalar::{point, Scalar};
use inari::Interval;
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::thread::LocalKey;

mod simplify;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Input(usize),
    Const(f64),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Sin(u32),
    Cos(u32),
    Sqrt(u32),
    Exp(u32),
    Ln(u32),
    Atan(u32),
    Sinh(u32),
    Cosh(u32),
    /// The real number pi (not an f64: intervals enclose it).
    Pi,
    /// Product with the exact constant c.
    Scale(u32, f64),
}

/// The tape being recorded, with a table of the operations already on it so that an
/// operation recorded twice on the same arguments is stored once (hash-consing).
#[derive(Default)]
struct Recording {
    ops: Vec<Op>,
    seen: HashMap<(u8, u64, u64), u32, BuildHasherDefault<KeyHasher>>,
}

/// The hash of the hash-consing table: operation keys are three small integers, so a
/// multiply-rotate mix finished by splitmix64's is enough (the default SipHash was a third of
/// the time of `Model::new`). Only the speed of recording depends on it, never a result.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(*b as u64);
        }
    }
    fn write_u8(&mut self, x: u8) {
        self.write_u64(x as u64);
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
    fn finish(&self) -> u64 {
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

thread_local! {
    static RECORDING: RefCell<Recording> = RefCell::new(Recording::default());
}

/// A hashable key of an operation; commutative operations are ordered.
fn key(op: &Op) -> (u8, u64, u64) {
    let ord = |a: u32, b: u32| (a.min(b) as u64, a.max(b) as u64);
    match *op {
        Op::Input(i) => (0, i as u64, 0),
        Op::Const(c) => (1, c.to_bits(), 0),
        Op::Add(a, b) => {
            let (x, y) = ord(a, b);
            (2, x, y)
        }
        Op::Sub(a, b) => (3, a as u64, b as u64),
        Op::Mul(a, b) => {
            let (x, y) = ord(a, b);
            (4, x, y)
        }
        Op::Div(a, b) => (5, a as u64, b as u64),
        Op::Neg(a) => (6, a as u64, 0),
        Op::Sin(a) => (7, a as u64, 0),
        Op::Cos(a) => (8, a as u64, 0),
        Op::Sqrt(a) => (9, a as u64, 0),
        Op::Scale(a, c) => (10, a as u64, c.to_bits()),
        Op::Exp(a) => (11, a as u64, 0),
        Op::Ln(a) => (12, a as u64, 0),
        Op::Atan(a) => (13, a as u64, 0),
        Op::Sinh(a) => (14, a as u64, 0),
        Op::Cosh(a) => (15, a as u64, 0),
        Op::Pi => (16, 0, 0),
    }
}

/// A node of the tape being recorded (valid only inside [`Tape::record`]).
#[derive(Clone, Copy, Debug)]
pub struct Tracer(u32);

impl Tracer {
    /// The node's index on the tape being recorded: equal indices are the same expression
    /// (hash-consing), so this is a cheap test of structural identity.
    pub fn index(&self) -> u32 {
        self.0
    }
}

fn push(op: Op) -> Tracer {
    let op = fold(op);
    RECORDING.with(|t| {
        let mut t = t.borrow_mut();
        let k = key(&op);
        if let Some(i) = t.seen.get(&k) {
            return Tracer(*i);
        }
        t.ops.push(op);
        let i = (t.ops.len() - 1) as u32;
        t.seen.insert(k, i);
        Tracer(i)
    })
}

fn constant_of(x: Tracer) -> Option<f64> {
    RECORDING.with(|t| match t.borrow().ops[x.0 as usize] {
        Op::Const(c) => Some(c),
        _ => None,
    })
}

/// Exact constant folding: an operation on constants whose interval result is a single
/// f64 (so the real result is that f64) becomes a constant; a product with one constant
/// operand, or a quotient by a constant whose reciprocal is an f64 (a power of two), becomes
/// a scaling, whose Taylor recurrence costs O(1) instead of O(k).
fn fold(op: Op) -> Op {
    let c = |i: u32| constant_of(Tracer(i));
    let exact = |x: Interval| (x.inf() == x.sup() && x.inf().is_finite()).then(|| x.inf());
    let folded = match op {
        Op::Add(a, b) => c(a).zip(c(b)).and_then(|(x, y)| exact(point(x) + point(y))),
        Op::Sub(a, b) => c(a).zip(c(b)).and_then(|(x, y)| exact(point(x) - point(y))),
        Op::Mul(a, b) => c(a).zip(c(b)).and_then(|(x, y)| exact(point(x) * point(y))),
        Op::Div(a, b) => c(a).zip(c(b)).and_then(|(x, y)| {
            if y == 0.0 {
                None
            } else {
                exact(point(x) / point(y))
            }
        }),
        Op::Neg(a) => c(a).map(|x| -x),
        _ => None,
    };
    if let Some(v) = folded {
        return Op::Const(v);
    }
    match op {
        Op::Mul(a, b) => match (c(a), c(b)) {
            (Some(x), None) => Op::Scale(b, x),
            (None, Some(y)) => Op::Scale(a, y),
            _ => op,
        },
        // a / c = a * (1/c) exactly when 1/c is an f64 (c a power of two): a scaling
        Op::Div(a, b) => match c(b)
            .filter(|y| *y != 0.0)
            .and_then(|y| exact(point(1.0) / point(y)))
        {
            Some(r) => Op::Scale(a, r),
            None => op,
        },
        _ => op,
    }
}

impl Add for Tracer {
    type Output = Tracer;
    fn add(self, o: Tracer) -> Tracer {
        match (constant_of(self), constant_of(o)) {
            (Some(c), _) if c == 0.0 => o,
            (_, Some(c)) if c == 0.0 => self,
            _ => push(Op::Add(self.0, o.0)),
        }
    }
}
impl Sub for Tracer {
    type Output = Tracer;
    fn sub(self, o: Tracer) -> Tracer {
        match (constant_of(self), constant_of(o)) {
            (_, Some(c)) if c == 0.0 => self,
            (Some(c), _) if c == 0.0 => -o,
            _ => push(Op::Sub(self.0, o.0)),
        }
    }
}
impl Mul for Tracer {
    type Output = Tracer;
    fn mul(self, o: Tracer) -> Tracer {
        match (constant_of(self), constant_of(o)) {
            (Some(c), _) | (_, Some(c)) if c == 0.0 => Tracer::cst(0.0),
            (Some(c), _) if c == 1.0 => o,
            (_, Some(c)) if c == 1.0 => self,
            _ => push(Op::Mul(self.0, o.0)),
        }
    }
}
impl Div for Tracer {
    type Output = Tracer;
    fn div(self, o: Tracer) -> Tracer {
        match (constant_of(self), constant_of(o)) {
            (_, Some(c)) if c == 1.0 => self,
            _ => push(Op::Div(self.0, o.0)),
        }
    }
}
impl Neg for Tracer {
    type Output = Tracer;
    fn neg(self) -> Tracer {
        match constant_of(self) {
            Some(c) if c == 0.0 => self,
            _ => push(Op::Neg(self.0)),
        }
    }
}
impl Scalar for Tracer {
    fn cst(c: f64) -> Self {
        push(Op::Const(c))
    }
    fn sin(&self) -> Self {
        push(Op::Sin(self.0))
    }
    fn cos(&self) -> Self {
        push(Op::Cos(self.0))
    }
    fn sqrt(&self) -> Self {
        push(Op::Sqrt(self.0))
    }
    fn exp(&self) -> Self {
        push(Op::Exp(self.0))
    }
    fn ln(&self) -> Self {
        push(Op::Ln(self.0))
    }
    fn atan(&self) -> Self {
        push(Op::Atan(self.0))
    }
    fn sinh(&self) -> Self {
        push(Op::Sinh(self.0))
    }
    fn cosh(&self) -> Self {
        push(Op::Cosh(self.0))
    }
    fn pi() -> Self {
        push(Op::Pi)
    }
}

/// A recorded straight-line program from `inputs` values to `outputs` values. Two equal
/// tapes are the same program: they compute the same values over every scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    ops: Vec<Op>,
    n_inputs: usize,
    outputs: Vec<u32>,
}

impl Tape {
    /// Record `f` on `n_inputs` symbolic inputs.
    pub fn record(n_inputs: usize, f: impl FnOnce(&[Tracer]) -> Vec<Tracer>) -> Tape {
        RECORDING.with(|t| *t.borrow_mut() = Recording::default());
        let inputs: Vec<Tracer> = (0..n_inputs).map(|i| push(Op::Input(i))).collect();
        let outs = f(&inputs);
        let rec = RECORDING.with(|t| std::mem::take(&mut *t.borrow_mut()));
        Tape {
            ops: rec.ops,
            n_inputs,
            outputs: outs.iter().map(|t| t.0).collect(),
        }
        .without_dead_code()
    }

    /// [`Tape::record`], then simplified exactly (spec (2.13)): the cancelling sums are
    /// replaced by their normal forms. Used for the vector fields the validated integrator
    /// carries sets through, where the cancelled terms' widths cap the steps; the float
    /// schemes' tapes are recorded as written (an expanded normal form can round worse in
    /// f64 near overflow).
    pub fn record_simplified(n_inputs: usize, f: impl FnOnce(&[Tracer]) -> Vec<Tracer>) -> Tape {
        Tape::record(n_inputs, f).simplified()
    }

    /// This program with its cancelling sums replaced by their normal forms (spec (2.13)).
    fn simplified(self) -> Tape {
        #[cfg(test)]
        if !simplify::ENABLED.with(|e| e.get()) {
            return self;
        }
        let record = |fold_zeros: bool| {
            RECORDING.with(|t| *t.borrow_mut() = Recording::default());
            let (new, divisors) = simplify::rerecord(&self.ops, fold_zeros);
            let rec = RECORDING.with(|t| std::mem::take(&mut *t.borrow_mut()));
            let tape = Tape {
                ops: rec.ops,
                n_inputs: self.n_inputs,
                outputs: self.outputs.iter().map(|o| new[*o as usize].0).collect(),
            };
            (tape, divisors)
        };
        // With the nodes that are 0 folded, kept if every folded quotient's domain check is
        // still made by a quotient by the same divisor that the outputs depend on (an
        // evaluation fails as a whole when any check fails, (2.8)); otherwise without.
        let (tape, divisors) = record(true);
        let live = tape.live();
        let checked = |d: &u32| {
            (tape.ops.iter().zip(&live)).any(|(op, l)| *l && matches!(op, Op::Div(_, b) if b == d))
        };
        if divisors.iter().all(checked) {
            return tape.without_dead_code();
        }
        record(false).0.without_dead_code()
    }

    /// Record `f` and its Jacobian by forward-mode duals: the outputs are `f` and then
    /// `df/dx` row-major.
    pub fn record_with_jacobian(
        n_inputs: usize,
        f: impl FnOnce(&[crate::scalar::Dual<Tracer>]) -> Vec<crate::scalar::Dual<Tracer>>,
    ) -> Tape {
        Tape::record(n_inputs, |x| {
            let xd: Vec<_> = (0..n_inputs)
                .map(|j| crate::scalar::Dual::var(x[j], j, n_inputs))
                .collect();
            let y = f(&xd);
            let mut out: Vec<Tracer> = y.iter().map(|v| v.v).collect();
            for v in &y {
                out.extend((0..n_inputs).map(|j| v.der(j)));
            }
            out
        })
    }

    /// Which nodes the outputs depend on.
    fn needed(&self) -> Vec<bool> {
        let mut needed = vec![false; self.ops.len()];
        for o in &self.outputs {
            needed[*o as usize] = true;
        }
        for i in (0..self.ops.len()).rev() {
            if needed[i] {
                for a in args(&self.ops[i]) {
                    needed[a as usize] = true;
                }
            }
        }
        needed
    }

    /// Which nodes the outputs depend on, and the inputs.
    fn live(&self) -> Vec<bool> {
        let mut live = self.needed();
        for (l, op) in live.iter_mut().zip(&self.ops) {
            *l |= matches!(op, Op::Input(_));
        }
        live
    }

    /// For each input, whether an output depends on it through the tape's operations. An
    /// input not marked is not read: the outputs are functions of the other inputs alone.
    pub fn inputs_read(&self) -> Vec<bool> {
        let mut read = vec![false; self.n_inputs];
        for (op, needed) in self.ops.iter().zip(self.needed()) {
            if let (Op::Input(j), true) = (op, needed) {
                read[*j] = true;
            }
        }
        read
    }

    /// Drop the operations no output depends on (inputs are kept, in order).
    fn without_dead_code(self) -> Tape {
        let n = self.ops.len();
        let live = self.live();
        let mut new_index = vec![0u32; n];
        let mut ops = Vec::new();
        for i in 0..n {
            if live[i] {
                new_index[i] = ops.len() as u32;
                ops.push(remap(&self.ops[i], &new_index));
            }
        }
        Tape {
            ops,
            n_inputs: self.n_inputs,
            outputs: self
                .outputs
                .iter()
                .map(|o| new_index[*o as usize])
                .collect(),
        }
    }

    /// Whether `other` computes the same outputs by the same operations on the same
    /// constants, up to the order in which independent nodes were recorded and the order
    /// of the arguments of `+` and `*`: then both give bit-identical values over every
    /// scalar (each node is the same function of the inputs, evaluated the same way).
    pub fn same_program(&self, other: &Tape) -> bool {
        let mut table: HashMap<(u8, u64, u64), u32> = HashMap::new();
        let mut canon = |t: &Tape| -> Vec<u32> {
            let mut ids: Vec<u32> = Vec::with_capacity(t.ops.len());
            for op in &t.ops {
                let c = |a: u32| ids[a as usize];
                let rewritten = match *op {
                    Op::Add(a, b) => Op::Add(c(a).min(c(b)), c(a).max(c(b))),
                    Op::Mul(a, b) => Op::Mul(c(a).min(c(b)), c(a).max(c(b))),
                    _ => remap(op, &ids),
                };
                let n = table.len() as u32;
                ids.push(*table.entry(key(&rewritten)).or_insert(n));
            }
            t.outputs.iter().map(|o| ids[*o as usize]).collect()
        };
        self.n_inputs == other.n_inputs && canon(self) == canon(other)
    }

    /// Number of inputs of the recorded function.
    pub fn n_inputs(&self) -> usize {
        self.n_inputs
    }
    /// Number of outputs.
    pub fn n_outputs(&self) -> usize {
        self.outputs.len()
    }
    /// Number of recorded operations.
    pub fn len(&self) -> usize {
        self.ops.len()
    }
    /// Whether no operation was recorded.
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Replay over any scalar: the outputs at `x` (spec eq. (2.1)).
    pub fn eval<S: Scalar>(&self, x: &[S]) -> Vec<S> {
        let mut v: Vec<S> = Vec::with_capacity(self.ops.len());
        for op in &self.ops {
            let g = |i: &u32| v[*i as usize].clone();
            let r = match op {
                Op::Input(i) => x[*i].clone(),
                Op::Const(c) => S::cst(*c),
                Op::Add(a, b) => g(a) + g(b),
                Op::Sub(a, b) => g(a) - g(b),
                Op::Mul(a, b) => g(a) * g(b),
                Op::Div(a, b) => g(a) / g(b),
                Op::Neg(a) => -g(a),
                Op::Scale(a, c) => g(a) * S::cst(*c),
                Op::Sin(a) => g(a).sin(),
                Op::Cos(a) => g(a).cos(),
                Op::Sqrt(a) => g(a).sqrt(),
                Op::Exp(a) => g(a).exp(),
                Op::Ln(a) => g(a).ln(),
                Op::Atan(a) => g(a).atan(),
                Op::Sinh(a) => g(a).sinh(),
                Op::Cosh(a) => g(a).cosh(),
                Op::Pi => S::pi(),
            };
            v.push(r);
        }
        self.outputs
            .iter()
            .map(|o| v[*o as usize].clone())
            .collect()
    }

    /// Taylor coefficients `x_0 .. x_order` at t = 0 of every solution of `x' = F(x)` with
    /// `x(0)` in the box `x0`, where F is this tape (inputs and outputs of equal number):
    /// for every such solution, its k-th coefficient `x^(k)(0)/k!` lies in `result[k]`
    /// (spec eqs. (2.2)-(2.7)). Division by an interval containing 0 yields a non-finite or
    /// empty coefficient, which the caller must treat as failure.
    ///
    /// Returns `None` when the tape is not proved smooth on the box: a divisor enclosure
    /// containing 0, a square root of an enclosure not in (0, inf), or a non-finite
    /// coefficient (spec eq. (2.8)).
    pub fn ode_taylor<T: Coef>(&self, x0: &[T], order: usize) -> Option<Coeffs<T>> {
        self.ode_taylor_until(x0, order, order, |_| true)
    }

    /// [`Tape::ode_taylor`] to `order`, then on to `more` unless `enough`, shown the
    /// coefficients to `order`, says they suffice (the recurrences go on from where they
    /// stopped: the coefficients to `more` are those of `ode_taylor(x0, more)`). Should a
    /// coefficient past `order` not be finite (or a check of (2.8) fail there), the
    /// coefficients to `order` are returned: going on is a choice, and never costs the
    /// series it started from.
    pub fn ode_taylor_until<T: Coef>(
        &self,
        x0: &[T],
        order: usize,
        more: usize,
        enough: impl FnOnce(Rows<'_, T>) -> bool,
    ) -> Option<Coeffs<T>> {
        let d = self.n_inputs;
        let top = order.max(more);
        charge(terms(self.ops.len(), order));
        let mut s = Series::new(self.ops.len(), order + 1);
        let mut flat: Vec<T> = Vec::with_capacity((order + 1) * d);
        flat.extend_from_slice(x0);
        let mut target = order;
        let mut enough = Some(enough);
        let mut k = 0;
        loop {
            if k == target && target < top {
                if let Some(enough) = enough.take() {
                    let rows = Rows {
                        width: d,
                        len: k + 1,
                        flat: &flat,
                    };
                    if !enough(rows) {
                        let ops = self.ops.len();
                        charge(terms(ops, top) - terms(ops, order));
                        s.widen(top + 1);
                        target = top;
                    }
                }
            }
            // Coefficient `target` of the nodes is not needed (only x_0 .. x_target are
            // returned); step 0 always runs, since it carries the domain checks (2.8).
            if k == target && k > 0 {
                break;
            }
            s.step(&self.ops, k, &flat[k * d..(k + 1) * d]);
            let mut failed = !s.ok;
            if !failed && k < target {
                let kk = T::cst((k + 1) as f64);
                for i in 0..d {
                    let next = s.get(self.outputs[i], k).quot(kk);
                    failed |= !next.is_finite_coef();
                    flat.push(next);
                }
            }
            if failed {
                // steps 0 .. order - 1 make the coefficients to `order`, step 0 the domain
                // checks (2.8): a failure there fails the series
                if k < order || k == 0 {
                    return None;
                }
                // past `order`: the series to `order` stands
                flat.truncate((order + 1) * d);
                target = order;
                break;
            }
            if k == target {
                break;
            }
            k += 1;
        }
        Some(Coeffs {
            width: d,
            len: target + 1,
            flat,
        })
    }

    /// Rigorous evaluation over intervals, with the same smoothness checks as
    /// [`Tape::ode_taylor`]: `None` unless every output is a finite enclosure of the exact
    /// value at every point of the box (spec eq. (2.8)).
    pub fn eval_checked<T: Coef>(&self, x: &[T]) -> Option<Vec<T>> {
        let mut s = Series::new(self.ops.len(), 1);
        s.step(&self.ops, 0, x);
        let out: Vec<T> = self.outputs.iter().map(|o| s.get(*o, 0)).collect();
        (s.ok && out.iter().all(|x| x.is_finite_coef())).then_some(out)
    }
}

/// Taylor coefficients `x_0 .. x_{len-1}`, each of `width` components, in one buffer: row
/// `k` is `x_k` (spec eq. (2.2)). [`Tape::ode_taylor`]'s result.
#[derive(Clone, Debug, PartialEq)]
pub struct Coeffs<T> {
    width: usize,
    len: usize,
    flat: Vec<T>,
}

/// Rows `0 .. len` of a [`Coeffs`], borrowed.
#[derive(Debug)]
pub struct Rows<'a, T> {
    width: usize,
    len: usize,
    flat: &'a [T],
}

impl<T> Clone for Rows<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for Rows<'_, T> {}

impl<T: Copy> Coeffs<T> {
    /// Coefficients from rows of `width` entries each.
    pub fn from_rows<'a>(width: usize, rows: impl IntoIterator<Item = &'a [T]>) -> Self
    where
        T: 'a,
    {
        let mut flat = Vec::new();
        let mut len = 0;
        for r in rows {
            flat.extend_from_slice(&r[..width]);
            len += 1;
        }
        Coeffs { width, len, flat }
    }
    /// Every row.
    pub fn rows(&self) -> Rows<'_, T> {
        Rows {
            width: self.width,
            len: self.len,
            flat: &self.flat,
        }
    }
    /// The same coefficients through `f`, entry by entry.
    pub fn map<U>(&self, f: impl Fn(&T) -> U) -> Coeffs<U> {
        self.rows().map(f)
    }
    /// The number of rows (the order plus one).
    pub fn len(&self) -> usize {
        self.len
    }
    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The rows, in order.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &[T]> + ExactSizeIterator + '_ {
        self.rows().iter()
    }
}

impl<'a, T> Rows<'a, T> {
    /// The number of rows.
    pub fn len(&self) -> usize {
        self.len
    }
    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The entries of a row.
    pub fn width(&self) -> usize {
        self.width
    }
    /// These rows through `f`, entry by entry.
    pub fn map<U>(self, f: impl Fn(&T) -> U) -> Coeffs<U> {
        Coeffs {
            width: self.width,
            len: self.len,
            flat: self.flat[..self.len * self.width].iter().map(f).collect(),
        }
    }
    /// The first `n` rows (all of them if there are fewer).
    pub fn first(self, n: usize) -> Rows<'a, T> {
        Rows {
            len: n.min(self.len),
            ..self
        }
    }
    /// Row `k`.
    pub fn row(self, k: usize) -> &'a [T] {
        assert!(k < self.len, "row {k} of {}", self.len);
        &self.flat[k * self.width..(k + 1) * self.width]
    }
    /// The rows, in order.
    pub fn iter(self) -> impl DoubleEndedIterator<Item = &'a [T]> + ExactSizeIterator {
        (0..self.len).map(move |k| self.row(k))
    }
}

impl<T: Copy> std::ops::Index<usize> for Coeffs<T> {
    type Output = [T];
    fn index(&self, k: usize) -> &[T] {
        self.rows().row(k)
    }
}

impl<T> std::ops::Index<usize> for Rows<'_, T> {
    type Output = [T];
    fn index(&self, k: usize) -> &[T] {
        self.row(k)
    }
}

fn args(op: &Op) -> Vec<u32> {
    match *op {
        Op::Input(_) | Op::Const(_) | Op::Pi => vec![],
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => vec![a, b],
        Op::Neg(a)
        | Op::Sin(a)
        | Op::Cos(a)
        | Op::Sqrt(a)
        | Op::Exp(a)
        | Op::Ln(a)
        | Op::Atan(a)
        | Op::Sinh(a)
        | Op::Cosh(a)
        | Op::Scale(a, _) => vec![a],
    }
}

fn remap(op: &Op, m: &[u32]) -> Op {
    let r = |a: u32| m[a as usize];
    match *op {
        Op::Input(i) => Op::Input(i),
        Op::Const(c) => Op::Const(c),
        Op::Add(a, b) => Op::Add(r(a), r(b)),
        Op::Sub(a, b) => Op::Sub(r(a), r(b)),
        Op::Mul(a, b) => Op::Mul(r(a), r(b)),
        Op::Div(a, b) => Op::Div(r(a), r(b)),
        Op::Neg(a) => Op::Neg(r(a)),
        Op::Sin(a) => Op::Sin(r(a)),
        Op::Cos(a) => Op::Cos(r(a)),
        Op::Sqrt(a) => Op::Sqrt(r(a)),
        Op::Exp(a) => Op::Exp(r(a)),
        Op::Ln(a) => Op::Ln(r(a)),
        Op::Atan(a) => Op::Atan(r(a)),
        Op::Sinh(a) => Op::Sinh(r(a)),
        Op::Cosh(a) => Op::Cosh(r(a)),
        Op::Pi => Op::Pi,
        Op::Scale(a, c) => Op::Scale(r(a), c),
    }
}

/// Storage of the Taylor coefficients of every node, node-major. The storage (and the
/// record of non-zero coefficients) is per-thread scratch, reused from one evaluation to the
/// next (it is reset first).
struct Series<T: Coef> {
    n: usize,
    /// False once a singular operation (divisor or sqrt argument not proved safe) was met.
    ok: bool,
    /// The coefficients of node i at `i n ..`, then the companion series (cos for a Sin
    /// node, sin for a Cos node, cosh for Sinh, sinh for Cosh, 1 + a^2 for Atan(a)) of
    /// node i at `(nodes + i) n ..`.
    c: Vec<T>,
    aux_at: usize,
    /// Per node, the first and last index of a coefficient (or companion) not exactly 0
    /// so far; `(usize::MAX, 0)` while all are 0.
    nz: Vec<(usize, usize)>,
}

impl<T: Coef> Series<T> {
    fn new(nodes: usize, n: usize) -> Self {
        let mut c = T::scratch().with(|s| s.take());
        c.clear();
        c.resize(2 * nodes * n, T::zero());
        let mut nz = SCRATCH_NZ.with(|s| s.take());
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
    /// Room for `n` coefficients per node (and companion), those computed kept.
    fn widen(&mut self, n: usize) {
        if n <= self.n {
            return;
        }
        let rows = 2 * self.aux_at / self.n;
        let mut c = vec![T::zero(); rows * n];
        for (to, from) in c.chunks_mut(n).zip(self.c.chunks(self.n)) {
            to[..self.n].copy_from_slice(from);
        }
        self.c = c;
        self.aux_at = rows / 2 * n;
        self.n = n;
    }
    fn get(&self, node: u32, k: usize) -> T {
        self.c[node as usize * self.n + k]
    }
    fn aux(&self, node: u32, k: usize) -> T {
        self.c[self.aux_at + node as usize * self.n + k]
    }

    /// Coefficient k of every node, given all coefficients below k (spec eq. (2.3)-(2.7)).
    fn step(&mut self, ops: &[Op], k: usize, input_k: &[T]) {
        let zero = T::zero();
        let kf = T::cst(k as f64);
        for (idx, op) in ops.iter().enumerate() {
            let (val, aux) = match *op {
                Op::Input(i) => (input_k[i], None),
                // a constant's coefficients past 0 are 0, as `new` and `widen` left them
                Op::Const(_) | Op::Pi if k > 0 => continue,
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
                        let (mut s, mut c) = (zero, zero);
                        let (lo, hi) = self.nz[a as usize];
                        for j in lo.max(1)..=hi.min(k) {
                            let ju = T::cst(j as f64) * self.get(a, j);
                            let (sp, cp) = if is_sin {
                                (self.get(me, k - j), self.aux(me, k - j))
                            } else {
                                (self.aux(me, k - j), self.get(me, k - j))
                            };
                            s = s.mul_acc(ju, cp);
                            c = c.mul_acc(-ju, sp);
                        }
                        (s.quot(kf), c.quot(kf))
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
                        let mut acc = zero;
                        let (lo, hi) = self.nz[a as usize];
                        for j in lo.max(1)..=hi.min(k) {
                            acc =
                                acc.mul_acc(T::cst(j as f64) * self.get(a, j), self.get(me, k - j));
                        }
                        (acc.quot(kf), None)
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
                        ((self.get(a, k) - acc.quot(kf)).quot(a0), None)
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
                        ((self.get(a, k) - acc.quot(kf)).quot(self.aux(me, 0)), Some(g))
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
                        let (mut s, mut c) = (zero, zero);
                        let (lo, hi) = self.nz[a as usize];
                        for j in lo.max(1)..=hi.min(k) {
                            let ju = T::cst(j as f64) * self.get(a, j);
                            let (sp, cp) = if is_sinh {
                                (self.get(me, k - j), self.aux(me, k - j))
                            } else {
                                (self.aux(me, k - j), self.get(me, k - j))
                            };
                            s = s.mul_acc(ju, cp);
                            c = c.mul_acc(ju, sp);
                        }
                        (s.quot(kf), c.quot(kf))
                    };
                    if is_sinh {
                        (s, Some(c))
                    } else {
                        (c, Some(s))
                    }
                }
            };
            // companions are stored for the operations that have one; the others' stay 0
            // from `new`
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
    /// with an exactly zero factor are zero and are skipped (spec eq. (2.3)).
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
        T::scratch().with(|s| s.replace(c));
        let nz = std::mem::take(&mut self.nz);
        SCRATCH_NZ.with(|s| s.replace(nz));
    }
}

thread_local! {
    static WORK: Cell<u64> = const { Cell::new(0) };
}

/// The arithmetic work this thread has done in Taylor series so far (spec (5.8''')): every
/// series of order `p` on a tape of `L` operations (`Tape::ode_taylor`) adds
/// `L (p + 1) (p + 2) / 2`, the number of coefficient terms a tape of products computes. A
/// measure of work that replays the same on every machine;
/// [`crate::FlowOptions::work_limit`] is stated in it.
pub fn work_done() -> u64 {
    WORK.with(Cell::get)
}

/// Adds `terms` to this thread's work.
fn charge(terms: u64) {
    WORK.with(|w| w.set(w.get().saturating_add(terms)));
}

/// `L (p + 1) (p + 2) / 2`.
fn terms(ops: usize, order: usize) -> u64 {
    let order = order as u64;
    let per_op = order.saturating_add(1).saturating_mul(order.saturating_add(2)) / 2;
    (ops as u64).saturating_mul(per_op)
}

thread_local! {
    static SCRATCH_INTERVAL: RefCell<Vec<Interval>> = const { RefCell::new(Vec::new()) };
    static SCRATCH_F64: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
    static SCRATCH_NZ: RefCell<Vec<(usize, usize)>> = const { RefCell::new(Vec::new()) };
}

/// A coefficient type for the Taylor recurrences: intervals (rigorous, with the domain
/// checks of spec eq. (2.8)) or f64 (only to *choose* things, e.g. Newton guesses).
pub trait Coef: Scalar + Copy + 'static {
    /// The per-thread storage reused by the Taylor series of this coefficient type.
    fn scratch() -> &'static LocalKey<RefCell<Vec<Self>>>;
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
    /// convolutions of (2.3)-(2.5). Intervals: spec (1.4); f64: four partial sums.
    fn conv(acc: Self, neg: bool, x: &[Self], y: &[Self]) -> Self;
    /// `self / b`, with `b` proved non-zero where the recurrences divide (intervals: spec
    /// (1.4), inari's quotient).
    fn quot(self, b: Self) -> Self;
}

impl Coef for Interval {
    fn scratch() -> &'static LocalKey<RefCell<Vec<Self>>> {
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

impl Coef for f64 {
    fn scratch() -> &'static LocalKey<RefCell<Vec<Self>>> {
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

/// A non-empty interval with finite endpoints.
pub fn finite(x: Interval) -> bool {
    !x.is_empty() && x.inf().is_finite() && x.sup().is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replay_matches_direct_evaluation() {
        let tape = Tape::record(2, |x| {
            let (a, b) = (x[0], x[1]);
            vec![a * b + a.sin() / (Tracer::one() + b.sqr()), (a * a).sqrt()]
        });
        let v = tape.eval(&[0.7f64, -1.3]);
        let direct = 0.7 * -1.3 + 0.7f64.sin() / (1.0 + 1.69);
        assert_eq!(v[0], direct);
        assert_eq!(v[1], 0.7);
    }

    #[test]
    fn inputs_read_are_those_an_output_depends_on() {
        // x3 feeds a node no output uses; x1 - x1 reads x1 (structurally, unsimplified)
        let tape = Tape::record(4, |x| {
            let _unused = x[3] * x[3];
            vec![x[2], x[1] - x[1], Tracer::cst(2.0)]
        });
        assert_eq!(tape.inputs_read(), vec![false, true, true, false]);
        // simplified, x1 - x1 is 0 and x1 is no longer read
        let tape = Tape::record_simplified(4, |x| vec![x[2], x[1] - x[1], x[0] * x[2]]);
        assert_eq!(tape.inputs_read(), vec![true, false, true, false]);
    }

    #[test]
    fn identities_are_folded_exactly() {
        let tape = Tape::record(1, |x| vec![x[0] * Tracer::one() + Tracer::zero() * x[0]]);
        // no arithmetic node at all
        assert!(tape
            .ops
            .iter()
            .all(|o| matches!(o, Op::Input(_) | Op::Const(_))));
        assert_eq!(tape.eval(&[3.5f64])[0], 3.5);
        // common subexpressions are stored once, dead code is dropped
        let tape = Tape::record(2, |x| {
            let _unused = x[0].sin();
            vec![(x[0] * x[1]).cos() + (x[1] * x[0]).cos()]
        });
        assert_eq!(tape.len(), 2 + 1 + 1 + 1, "{:?}", tape.ops);
    }

    #[test]
    fn singular_operations_are_failures_not_numbers() {
        let tape = Tape::record(1, |x| vec![(Tracer::one() / x[0]) * x[0]]);
        assert!(tape.eval_checked(&[crate::scalar::iv(-1.0, 1.0)]).is_none());
        assert!(tape.eval_checked(&[point(2.0)]).is_some());
        let tape = Tape::record(1, |x| vec![x[0].sqrt()]);
        assert!(tape.eval_checked(&[crate::scalar::iv(-1.0, 4.0)]).is_none());
        assert!(tape.ode_taylor(&[point(0.0)], 3).is_none());
    }

    /// `ode_taylor_until`: stopped at `order`, the coefficients of `ode_taylor(x0, order)`;
    /// carried on, those of `ode_taylor(x0, more)`, bit for bit (the recurrences go on from
    /// where they stopped); and `enough` is shown the rows to `order`. On the field of the
    /// particle's velocity (with a quotient, whose recurrence reads its own coefficients)
    /// and a sine (with its companion series).
    #[test]
    fn a_series_carried_on_is_the_series_of_the_higher_order() {
        let tape = Tape::record(3, |x| {
            let (y, u1, u2) = (x[0], x[1], x[2]);
            vec![u2, -(y * u1 * u2) / (Tracer::one() + y * y) + y.sin(), Tracer::zero()]
        });
        let x0 = [point(0.4), crate::scalar::iv(0.8, 0.8000000000000002), point(0.8)];
        let same = |a: &Coeffs<Interval>, b: &Coeffs<Interval>| {
            a.len() == b.len()
                && a.iter()
                    .zip(b.iter())
                    .all(|(r, s)| r.iter().zip(s).all(|(x, y)| x.inf() == y.inf() && x.sup() == y.sup()))
        };
        let mut seen = 0;
        let stopped = tape
            .ode_taylor_until(&x0, 12, 20, |rows| {
                seen = rows.len();
                true
            })
            .unwrap();
        assert_eq!(seen, 13);
        assert!(same(&stopped, &tape.ode_taylor(&x0, 12).unwrap()));
        let carried = tape.ode_taylor_until(&x0, 12, 20, |_| false).unwrap();
        assert!(same(&carried, &tape.ode_taylor(&x0, 20).unwrap()));
        // the work counter charges the work of the order reached
        let before = work_done();
        tape.ode_taylor_until(&x0, 12, 20, |_| false).unwrap();
        let carried_work = work_done() - before;
        tape.ode_taylor(&x0, 20).unwrap();
        assert_eq!(work_done() - before - carried_work, carried_work);
    }

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

    /// A series carried on past a coefficient that overflows stops at `order`, with the
    /// coefficients to `order`: `x' = x^2` from `x0 = 10^12` has `x_k = x0^(k+1)`, finite to
    /// k = 24 and not at 25. Failures up to `order` still fail the series.
    #[test]
    fn a_series_carried_into_overflow_keeps_its_order() {
        let tape = Tape::record(1, |x| vec![x[0] * x[0]]);
        let x0 = [1e12f64];
        let c = tape.ode_taylor_until(&x0, 22, 28, |_| false).unwrap();
        assert_eq!(c.len(), 23);
        assert_eq!(c.iter().collect::<Vec<_>>(), tape.ode_taylor(&x0, 22).unwrap().iter().collect::<Vec<_>>());
        assert!(tape.ode_taylor(&x0, 28).is_none());
        assert!(tape.ode_taylor_until(&x0, 26, 28, |_| false).is_none());
        // the domain checks of step 0 fail a series of order 0 too
        let tape = Tape::record(1, |x| vec![x[0].sqrt()]);
        assert!(tape.ode_taylor_until(&[point(-1.0)], 0, 4, |_| false).is_none());
        assert!(tape.ode_taylor(&[point(-1.0)], 0).is_none());
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

    #[test]
    fn same_program_ignores_recording_order_only() {
        let a = Tape::record(2, |x| {
            let s = x[0].sin();
            let c = x[1].cos();
            vec![s * c, c + s]
        });
        let b = Tape::record(2, |x| {
            let c = x[1].cos();
            let s = x[0].sin();
            vec![c * s, s + c]
        });
        assert!(a.same_program(&b) && b.same_program(&a));
        let c = Tape::record(2, |x| {
            vec![x[0].sin() * x[1].cos(), x[1].cos() - x[0].sin()]
        });
        assert!(!a.same_program(&c));
        let d = Tape::record(2, |x| vec![x[0].sin() * x[1].cos()]);
        assert!(!a.same_program(&d));
        let e = Tape::record(2, |x| {
            vec![x[0].sin() * x[1].sin(), x[1].cos() + x[0].sin()]
        });
        assert!(!a.same_program(&e));
    }
}
