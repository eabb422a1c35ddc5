//! Exact simplification of a recorded tape ([spec eq. (2.13)](crate::spec::taylor)): sums whose terms cancel as
//! polynomials are replaced by what is left, so that an interval evaluation does not carry
//! the cancelled terms' widths (the dependency effect).
//!
//! Every node built from `+ - *`, negation, scaling and constants has a normal form: a
//! polynomial with f64 coefficients in *atoms* (inputs, pi, and the results of `/`, sin, cos,
//! sqrt, exp, ln, atan, sinh, cosh, which stay as they are), with `sin(x)^2` rewritten as
//! `1 - cos(x)^2`. Two expressions with the same normal form are the same real function.
//! A sum or difference whose normal form is its operands' terms with some cancelled to 0 and
//! no other coefficient changed is recorded as its normal form instead; every other node is
//! recorded as it was (merging like terms without cancelling them is not done: it can turn
//! exact differences into cancellations of large terms). This is sound because:
//! - the normal form is computed exactly: a coefficient is kept only when its sum or product
//!   is a single f64 (checked by outward-rounded interval arithmetic); otherwise, or when a
//!   form would exceed [`MAX_TERMS`] terms, the node is left alone (and is an atom above);
//! - the rewriting uses identities of real arithmetic only (`sin^2 + cos^2 = 1`, ring laws);
//! - a partial atom (a quotient, square root or logarithm, or anything built on one) is never
//!   cancelled away: a node whose normal form would lose one is left alone, so every domain
//!   check of the original tape is still made (a tape never becomes defined where it was not).

use super::program::{args, remap, Op};
use super::record::{constant_of, push, Open, Tracer};
use super::Tape;
use crate::scalar::{point, Scalar};
use std::collections::BTreeMap;

#[cfg(test)]
thread_local! {
    /// Tests switch the simplification off to compare with the tapes as recorded.
    pub(crate) static ENABLED: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// The largest number of terms of a normal form that is carried.
pub(super) const MAX_TERMS: usize = 8;

impl Tape {
    /// [`Tape::record`], then simplified exactly ([spec (2.13)](crate::spec::taylor)): the cancelling sums are
    /// replaced by their normal forms. Used for the vector fields the validated integrator
    /// carries sets through, where the cancelled terms' widths cap the steps; the float
    /// schemes' tapes are recorded as written (an expanded normal form can round worse in
    /// f64 near overflow).
    pub fn record_simplified(n_inputs: usize, f: impl FnOnce(&[Tracer]) -> Vec<Tracer>) -> Tape {
        Tape::record(n_inputs, f).simplified()
    }

    /// This program with its cancelling sums replaced by their normal forms ([spec (2.13)](crate::spec::taylor)).
    fn simplified(self) -> Tape {
        #[cfg(test)]
        if !ENABLED.with(|e| e.get()) {
            return self;
        }
        let record = |fold_zeros: bool| {
            let open = Open::new();
            let (new, divisors) = rerecord(&self.ops, fold_zeros);
            let tape = Tape {
                ops: open.close(),
                n_inputs: self.n_inputs,
                outputs: self.outputs.iter().map(|o| new[*o as usize].index()).collect(),
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
}

/// An atom of a normal form: a node of the new recording, or a constant (a positive f64,
/// by its bits). Constants order after nodes and by value, so that a normal form is emitted
/// in the same order whenever its constants were recorded: a scene written as a file gives
/// the same tapes as the built-in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Atom {
    Node(u32),
    Const(u64),
}

/// A monomial: (atom, power) pairs sorted by atom; the empty monomial is 1.
type Mono = Vec<(Atom, u32)>;

/// A polynomial in atoms: (monomial, nonzero coefficient) pairs sorted by monomial, each
/// monomial once (a sorted vector rather than a map: the forms have at most [`MAX_TERMS`]
/// terms, and building the models' tapes allocates a good deal less).
#[derive(Clone, Debug, PartialEq)]
struct Poly(Vec<(Mono, f64)>);

/// The normal form of the constant `c`. A constant whose square is an f64 (a short
/// significand: 0.5, 3, -2) is a coefficient. Any other constant of magnitude at most
/// [`ATOM_CONSTANT_MAX`] (0.1, an `eps` given by the user) is `sign(c)` times an atom `|c|`
/// like an input, so that `eps * eps` stays the exact product it is instead of blocking the
/// normal form with an inexact coefficient. Larger ones are coefficients too, so that a
/// product with them is refused unless it is exact.
fn constant_form(c: f64) -> Poly {
    let atom = c.abs() <= ATOM_CONSTANT_MAX && exact(point(c) * point(c)).is_none();
    if atom {
        Poly(vec![(vec![(Atom::Const(c.abs().to_bits()), 1)], c.signum())])
    } else {
        Poly::constant(c)
    }
}

/// The largest constant that is an atom of normal forms ([spec eq. (2.13)](crate::spec::taylor)). The bound keeps
/// expansions well conditioned: `(cos x - e)^2 + sin(x)^2` becomes `1 - 2 e cos x + e e`,
/// whose terms are up to `(1 + |e|)^2 / (1 - |e|)^2` times its value (9 at |e| = 1/2). Near
/// |e| = 1 that ratio amplifies rounding into the high Taylor coefficients of a quotient by
/// it: measured on `knife-eps` at eps = 0.95, T = 50, 665 rejected steps against 34.
const ATOM_CONSTANT_MAX: f64 = 0.5;

fn exact(x: inari::Interval) -> Option<f64> {
    (x.inf() == x.sup() && x.inf().is_finite()).then(|| x.inf())
}

impl Poly {
    fn constant(c: f64) -> Poly {
        if c != 0.0 {
            Poly(vec![(Vec::new(), c)])
        } else {
            Poly(Vec::new())
        }
    }
    fn atom(a: u32) -> Poly {
        Poly(vec![(vec![(Atom::Node(a), 1)], 1.0)])
    }
    fn terms(&self) -> usize {
        self.0.len()
    }
    fn contains(&self, m: &Mono) -> bool {
        self.0.binary_search_by(|(k, _)| k.cmp(m)).is_ok()
    }
    /// The value if `self` is a nonzero constant.
    fn as_constant(&self) -> Option<f64> {
        match self.0.as_slice() {
            [(m, c)] if m.is_empty() => Some(*c),
            _ => None,
        }
    }
    /// `self + s * other` (s = 1 or -1), exactly; `None` if a coefficient is not an f64.
    fn add(&self, other: &Poly, s: f64) -> Option<Poly> {
        let mut out = self.clone();
        out.add_assign(other, s)?;
        Some(out)
    }
    /// `self += s * other` as [`Poly::add`], in place (`None`: `self` is then garbage).
    fn add_assign(&mut self, other: &Poly, s: f64) -> Option<()> {
        for (m, c) in &other.0 {
            match self.0.binary_search_by(|(k, _)| k.cmp(m)) {
                Ok(i) => {
                    let e = exact(point(self.0[i].1) + point(s * c))?;
                    if e == 0.0 {
                        self.0.remove(i);
                    } else {
                        self.0[i].1 = e;
                    }
                }
                Err(i) => {
                    // (s = 1 or -1: s c is exact, and c is nonzero)
                    self.0.insert(i, (m.clone(), s * c));
                }
            }
        }
        (self.0.len() <= MAX_TERMS).then_some(())
    }
    /// `c * self`, exactly.
    fn scale(&self, c: f64) -> Option<Poly> {
        let mut out = Vec::with_capacity(self.0.len());
        for (m, x) in &self.0 {
            let y = exact(point(*x) * point(c))?;
            if y != 0.0 {
                out.push((m.clone(), y));
            }
        }
        Some(Poly(out))
    }
    /// `self * other`, exactly, with `sin(x)^2 = 1 - cos(x)^2` applied.
    fn mul(&self, other: &Poly, atoms: &mut Atoms) -> Option<Poly> {
        let mut out = Poly(Vec::new());
        for (m1, c1) in &self.0 {
            for (m2, c2) in &other.0 {
                let c = exact(point(*c1) * point(*c2))?;
                let term = atoms.reduce(mono_mul(m1, m2), c)?;
                out.add_assign(&term, 1.0)?;
            }
        }
        Some(out)
    }
    /// Every partial atom of `self`.
    fn partial_atoms(&self, atoms: &Atoms) -> Vec<u32> {
        let mut v: Vec<u32> = self
            .0
            .iter()
            .flat_map(|(m, _)| m)
            .filter_map(|(a, _)| match a {
                Atom::Node(i) => Some(*i),
                Atom::Const(_) => None,
            })
            .filter(|a| atoms.partial(*a))
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// The product of two monomials (each sorted by atom, each atom once): their merge.
fn mono_mul(a: &Mono, b: &Mono) -> Mono {
    let mut m = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].0.cmp(&b[j].0) {
            std::cmp::Ordering::Less => {
                m.push(a[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                m.push(b[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                m.push((a[i].0, a[i].1 + b[j].1));
                i += 1;
                j += 1;
            }
        }
    }
    m.extend_from_slice(&a[i..]);
    m.extend_from_slice(&b[j..]);
    m
}

/// What is known of the nodes of the new recording: which are partial, which are sines
/// and cosines of what.
#[derive(Default)]
struct Atoms {
    partial: Vec<bool>,
    sin_of: BTreeMap<u32, u32>,
}

impl Atoms {
    fn partial(&self, a: u32) -> bool {
        self.partial.get(a as usize).copied().unwrap_or(false)
    }
    fn note(&mut self, node: Tracer, partial: bool) {
        let i = node.index() as usize;
        if self.partial.len() <= i {
            self.partial.resize(i + 1, false);
        }
        self.partial[i] |= partial;
    }
    /// `c m` with every `sin(x)^k`, k >= 2, rewritten as `sin(x)^(k-2) (1 - cos(x)^2)`.
    fn reduce(&mut self, m: Mono, c: f64) -> Option<Poly> {
        let Some((s, k, x)) = m.iter().find_map(|&(a, k)| {
            let Atom::Node(i) = a else { return None };
            let x = *self.sin_of.get(&i)?;
            (k >= 2).then_some((a, k, x))
        }) else {
            return Some(Poly(vec![(m, c)]));
        };
        let cos = push(Op::Cos(x));
        self.note(cos, self.partial(x));
        let rest: Mono = m
            .iter()
            .filter_map(|&(a, p)| {
                if a == s {
                    (k > 2).then_some((a, k - 2))
                } else {
                    Some((a, p))
                }
            })
            .collect();
        // c rest - c rest cos^2
        let one = self.reduce(rest.clone(), c)?;
        let two = self.reduce(mono_mul(&rest, &vec![(Atom::Node(cos.index()), 2)]), c)?;
        one.add(&two, -1.0)
    }
}

/// Whether `sum` (of `x` and `y`) is `x` and `y` with some terms cancelled to 0 and no
/// other coefficient changed: then the normal form drops work and width, and creates no
/// new cancellation of large terms (merging `a q - 2 q` style terms would: `(q2 - q1) r -
/// (q1 - q0) r` as `q2 r - 2 q1 r + q0 r` loses the exact differences).
fn only_cancels(x: &Poly, y: &Poly, sum: &Poly) -> bool {
    let common = x.0.iter().filter(|(m, _)| y.contains(m)).count();
    common > 0 && sum.terms() + 2 * common == x.terms() + y.terms()
}

/// Record `p` with the current recording's operations: a sum of monomials (in the order of
/// the normal form), each the coefficient times its atoms' powers.
fn emit(p: &Poly) -> Tracer {
    let mut sum: Option<Tracer> = None;
    for (m, c) in &p.0 {
        let mut t: Option<Tracer> = None;
        for &(a, k) in m {
            let x = match a {
                Atom::Node(i) => Tracer::at(i),
                Atom::Const(bits) => Tracer::cst(f64::from_bits(bits)),
            };
            for _ in 0..k {
                t = Some(t.map_or(x, |t| t * x));
            }
        }
        let term = match t {
            None => Tracer::cst(*c),
            Some(t) if *c == 1.0 => t,
            Some(t) if *c == -1.0 => -t,
            Some(t) => Tracer::cst(*c) * t,
        };
        sum = Some(sum.map_or(term, |s| s + term));
    }
    sum.unwrap_or_else(|| Tracer::cst(0.0))
}

/// Re-record `ops` (a recorded tape's operations) into the current recording with the
/// cancelling sums replaced by their normal forms; returns the new node of every old one.
/// With `fold_zeros`, a product, negation, scaling or quotient whose normal form is 0 and
/// whose operands (a quotient's numerator) carry no partial atom is recorded as the
/// constant 0; the divisors of the quotients so folded are returned, and the caller keeps
/// the result only if each is the divisor of a quotient still in the tape (whose check is
/// the folded one's).
pub(super) fn rerecord(ops: &[Op], fold_zeros: bool) -> (Vec<Tracer>, Vec<u32>) {
    let mut atoms = Atoms::default();
    let mut new: Vec<Tracer> = Vec::with_capacity(ops.len());
    // the new node of every old one, as indices for `remap`
    let mut index: Vec<u32> = Vec::with_capacity(ops.len());
    let mut forms: Vec<Option<Poly>> = Vec::with_capacity(ops.len());
    let mut folded_divisors = Vec::new();
    for op in ops {
        let t = |a: u32| new[a as usize];
        let f = |a: u32| forms[a as usize].as_ref();
        let (node, form) = match *op {
            Op::Const(c) => (Tracer::cst(c), Some(constant_form(c))),
            Op::Add(a, b) | Op::Sub(a, b) => {
                let s = if matches!(op, Op::Add(..)) { 1.0 } else { -1.0 };
                let plain = || {
                    if s > 0.0 {
                        t(a) + t(b)
                    } else {
                        t(a) - t(b)
                    }
                };
                match (f(a), f(b)) {
                    (Some(x), Some(y)) => match x.add(y, s) {
                        Some(sum) if only_cancels(x, y, &sum) => {
                            let mut kept = x.partial_atoms(&atoms);
                            kept.extend(y.partial_atoms(&atoms));
                            let left = sum.partial_atoms(&atoms);
                            if kept.iter().all(|a| left.contains(a)) {
                                (emit(&sum), Some(sum))
                            } else {
                                // would lose a domain check: left alone, opaque above
                                (plain(), None)
                            }
                        }
                        sum => (plain(), sum),
                    },
                    _ => (plain(), None),
                }
            }
            Op::Mul(a, b) => {
                let form = f(a).zip(f(b)).and_then(|(x, y)| x.mul(y, &mut atoms));
                // a factor cancelled to 0 keeps a partial factor (as `0 * y` scaled, not
                // the constant 0 that recording makes of it): (iii)
                let zero_times_partial = |x: Tracer, y: Tracer| {
                    constant_of(x) == Some(0.0) && atoms.partial(y.index())
                };
                let node = if zero_times_partial(t(a), t(b)) || zero_times_partial(t(b), t(a)) {
                    push(Op::Mul(t(a).index(), t(b).index()))
                } else {
                    t(a) * t(b)
                };
                (node, form)
            }
            Op::Div(a, b) => {
                // a quotient by a nonzero constant is a scaling of the numerator's form
                let by = f(b).and_then(Poly::as_constant);
                let form = by
                    .and_then(|c| exact(point(1.0) / point(c)))
                    .and_then(|r| f(a).and_then(|x| x.scale(r)));
                (t(a) / t(b), form)
            }
            Op::Neg(a) => (-t(a), f(a).and_then(|x| x.scale(-1.0))),
            Op::Scale(a, c) => {
                let form = f(a)
                    .and_then(|x| x.mul(&constant_form(c), &mut atoms));
                (push(Op::Scale(t(a).index(), c)), form)
            }
            other => {
                let node = push(remap(&other, &index));
                (node, None)
            }
        };
        // a node that is 0 as a function, built on nodes defined everywhere: the constant 0
        let zero = |x: Option<&Poly>| x.is_some_and(|x| x.0.is_empty());
        let total = |a: u32| !atoms.partial(new[a as usize].index());
        let folded = fold_zeros
            && match *op {
                Op::Div(a, _) => zero(f(a)) && total(a),
                Op::Mul(a, b) => zero(form.as_ref()) && total(a) && total(b),
                Op::Neg(a) | Op::Scale(a, _) => zero(form.as_ref()) && total(a),
                _ => false,
            };
        let (node, form) = if folded {
            // (a nonzero constant divisor has no check to keep)
            if let Op::Div(_, b) = *op {
                let d = new[b as usize];
                if constant_of(d).is_none_or(|c| c == 0.0) {
                    folded_divisors.push(d.index());
                }
            }
            (Tracer::cst(0.0), Some(Poly::constant(0.0)))
        } else {
            (node, form)
        };
        // an atom: partial if it is a quotient, root or logarithm or built on a partial node
        // (a folded quotient is the constant 0: its check is the caller's to keep)
        let by_constant = matches!(*op, Op::Div(_, b) if matches!(ops[b as usize], Op::Const(c) if c != 0.0) || forms[b as usize].as_ref().and_then(Poly::as_constant).is_some());
        let partial_op = matches!(op, Op::Sqrt(_) | Op::Ln(_)) || (matches!(op, Op::Div(..)) && !by_constant);
        let on_partial = args(op)
            .iter()
            .any(|a| atoms.partial(new[*a as usize].index()));
        atoms.note(node, (partial_op || on_partial) && !folded);
        if let Op::Sin(x) = *op {
            atoms.sin_of.insert(node.index(), new[x as usize].index());
        }
        let form = form.unwrap_or_else(|| Poly::atom(node.index()));
        new.push(node);
        index.push(node.index());
        forms.push(Some(form));
    }
    (new, folded_divisors)
}

#[cfg(test)]
mod tests {
    use crate::tape::program::Op;
    use crate::tape::{Tape, Tracer};
    use crate::scalar::{iv, point, Scalar};
    use inari::Interval;

    fn arithmetic(t: &Tape) -> usize {
        t.ops
            .iter()
            .filter(|o| !matches!(o, Op::Input(_) | Op::Const(_)))
            .count()
    }

    /// The knife's reduced field as the generic dynamics records it ([spec (4.4)](crate::spec::dynamics)): the
    /// cancelling terms `-u1 u2 sin cos + u1 u2 sin cos` and the denominator
    /// `cos^2 + sin^2` leave exactly `u1' = cos(phi) / 2`, as derived by hand.
    #[test]
    fn cancelling_terms_and_sin_squared_plus_cos_squared_go() {
        let tape = Tape::record_simplified(3, |x| {
            let (phi, u1, u2) = (x[0], x[1], x[2]);
            let (s, c) = (phi.sin(), phi.cos());
            let num = -(c * (u1 * (u2 * -s) + Tracer::cst(-0.5)) + s * (u1 * (u2 * c)));
            vec![num / (c * c + s * s)]
        });
        // sin, cos (kept by the rewrite's cos), one scaling: cos(phi)/2
        assert!(arithmetic(&tape) <= 3, "{:?}", tape.ops);
        let want = |p: f64| 0.5 * p.cos();
        for p in [-2.0, 0.3, 1.7] {
            let y = tape.eval(&[point(p), point(0.9), point(-1.1)])[0];
            assert!(y.contains(want(p)) && y.wid() < 1e-15, "{p}: {y:?}");
        }
        // over a box the width is that of cos alone, without the cancelled terms'
        let b = [iv(0.2, 0.3), iv(-3.0, 3.0), iv(-3.0, 3.0)];
        let y = tape.eval(&b)[0];
        assert!(y.wid() < 0.5 * (0.3f64.cos() - 0.2f64.cos()).abs() + 1e-15, "{y:?}");
    }

    /// Sound on every input: the simplified tape and the same expression evaluated directly
    /// (no tape, so no simplification) both enclose the real value, so they intersect, at
    /// random points and boxes; the simplified one is never wider at a point.
    #[test]
    fn simplified_tapes_enclose_the_same_function() {
        // one expression over any scalar: replayed from a tape, and directly over intervals
        fn exprs<S: Scalar>(x: &[S]) -> Vec<S> {
            let (a, b) = (x[0].clone(), x[1].clone());
            let (s, c) = (a.sin(), a.cos());
            vec![
                (a.clone() + b.clone()) * (a.clone() - b.clone()) - a.clone() * a.clone()
                    + b.clone() * b.clone()
                    + c.clone() * c.clone()
                    + s.clone() * s.clone(),
                (s.clone() * s.clone() * s.clone() + s.clone() * c.clone() * c.clone())
                    * b.clone()
                    - s.clone() * b.clone(),
                a.clone() * S::cst(0.1) * S::cst(0.1) - a * S::cst(0.01),
                b.clone() * s.clone() * s + b * c.clone() * c,
            ]
        }
        let f = exprs::<Interval>;
        let tape = Tape::record_simplified(2, exprs);
        let mut seed = 0x5eed_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 8.0 - 4.0
        };
        for _ in 0..200 {
            let (a, b, r) = (next(), next(), next().abs() * 1e-3);
            for x in [[point(a), point(b)], [iv(a - r, a + r), iv(b - r, b + r)]] {
                let (got, direct) = (tape.eval(&x), f(&x));
                for (g, d) in got.iter().zip(&direct) {
                    assert!(!g.intersection(*d).is_empty(), "{x:?}: {g:?} vs {d:?}");
                    if r == 0.0 {
                        assert!(g.wid() <= d.wid(), "{x:?}: {g:?} vs {d:?}");
                    }
                }
            }
        }
        // the first output is 1 exactly, the second 0 and the fourth b
        let y = tape.eval(&[iv(-1.0, 2.0), iv(3.0, 4.0)]);
        assert_eq!((y[0].inf(), y[0].sup()), (1.0, 1.0));
        assert_eq!((y[1].inf(), y[1].sup()), (0.0, 0.0));
        assert_eq!((y[3].inf(), y[3].sup()), (3.0, 4.0));
    }

    /// A quotient never cancels away: `a / b - a / b` stays undefined at b = 0, and a
    /// coefficient that is not an f64 (0.1 * 0.1) leaves its node as recorded.
    #[test]
    fn domains_and_inexact_coefficients_are_kept() {
        let tape = Tape::record_simplified(2, |x| vec![x[0] / x[1] - x[0] / x[1]]);
        assert!(tape.eval_checked(&[point(1.0), point(0.0)]).is_none());
        assert!(tape.ops.iter().any(|o| matches!(o, Op::Div(..))));
        let tape = Tape::record_simplified(1, |x| {
            vec![x[0] * Tracer::cst(0.1) * Tracer::cst(0.1) - x[0] * Tracer::cst(0.01)]
        });
        assert!(tape.ops.iter().any(|o| matches!(o, Op::Sub(..))), "{:?}", tape.ops);
    }

    /// Nodes that are 0 as functions ([spec (2.13)](crate::spec::taylor)): in the particle's pattern
    /// `(-(0 / d) * x, y / d)`, `d = 1 + y^2`, the first output is the constant 0 and one
    /// quotient is left, whose check still refuses a box where `d` may vanish. A zero
    /// quotient whose divisor no other quotient checks keeps its division, and a zero
    /// product keeps a factor that is not defined everywhere (before, `(x - x) * (1 / y)` was
    /// simplified to the constant 0: defined at y = 0, where the recorded tape is not).
    #[test]
    fn nodes_that_are_zero_fold_only_where_their_domain_checks_stay() {
        let divisions = |t: &Tape| t.ops.iter().filter(|o| matches!(o, Op::Div(..))).count();
        let d = |y: Tracer| Tracer::cst(1.0) + y * y;
        let tape = Tape::record_simplified(2, |x| {
            vec![-(Tracer::cst(0.0) / d(x[1])) * x[0], x[1] / d(x[1])]
        });
        assert_eq!(divisions(&tape), 1, "{:?}", tape.ops);
        assert!(matches!(tape.ops[tape.outputs[0] as usize], Op::Const(c) if c == 0.0));
        let at = tape.eval_checked(&[point(3.0), point(2.0)]).unwrap();
        assert!(at[0].is_singleton() && at[0].contains(0.0) && at[1].contains(0.4));
        // beside a zero quotient by a constant (no check to keep), the same
        let with_constant = Tape::record_simplified(2, |x| {
            let zero_by_three = (x[0] - x[0]) / Tracer::cst(3.0);
            vec![zero_by_three - (Tracer::cst(0.0) / d(x[1])) * x[0], x[1] / d(x[1])]
        });
        assert_eq!(divisions(&with_constant), 1, "{:?}", with_constant.ops);
        // 1 + y^2 over a box that reaches -1 in y^2 (a degenerate field): refused
        let wide = [iv(-1.0, 1.0), iv(-2.0, 2.0)];
        let neg = Tape::record_simplified(2, |x| {
            let d = Tracer::cst(1.0) - x[1] * x[1];
            vec![-(Tracer::cst(0.0) / d) * x[0], x[1] / d]
        });
        assert_eq!(divisions(&neg), 1, "{:?}", neg.ops);
        assert!(neg.eval_checked(&wide).is_none());
        // the only quotient by 1 - y^2 has numerator 0: it stays, and so does its check
        let alone = Tape::record_simplified(2, |x| {
            let d = Tracer::cst(1.0) - x[1] * x[1];
            vec![(Tracer::cst(0.0) / d) * x[0], x[0] + x[1]]
        });
        assert_eq!(divisions(&alone), 1, "{:?}", alone.ops);
        assert!(alone.eval_checked(&wide).is_none());
        assert!(alone.eval_checked(&[point(3.0), point(0.5)]).is_some());
        // (x - x) / ... is 0, but (x - x) * (1 / y) keeps 1 / y and its check
        let product = Tape::record_simplified(2, |x| {
            vec![(x[0] - x[0]) * (Tracer::cst(1.0) / x[1])]
        });
        assert_eq!(divisions(&product), 1, "{:?}", product.ops);
        assert!(product.eval_checked(&[point(1.0), point(0.0)]).is_none());
    }

    /// The domain never grows ([spec (2.13)](crate::spec::taylor), claim): tapes mixing zero quotients, zero
    /// products and cancelling sums with quotients by `d = y^2 - c`, recorded and
    /// simplified, at random boxes, many of which reach `d = 0`: where the recorded tape
    /// refuses, so does the simplified one, and where both answer they intersect.
    #[test]
    fn the_simplified_domain_is_never_larger() {
        fn shapes(x: &[Tracer], k: usize) -> Vec<Tracer> {
            let (a, y) = (x[0], x[1]);
            let d = y * y - Tracer::cst(0.25);
            let zero_q = Tracer::cst(0.0) / d;
            let cancel = a - a;
            match k {
                0 => vec![-zero_q * a, y / d],
                1 => vec![-zero_q * a, a + y],
                2 => vec![cancel * (Tracer::cst(1.0) / d), a],
                3 => vec![zero_q * zero_q, (cancel / d) * a, y],
                4 => vec![(a / d - a / d) * y, zero_q + a],
                _ => vec![-(cancel * zero_q), (Tracer::cst(2.0) / d) * Tracer::cst(0.0)],
            }
        }
        let mut seed = 0xd0_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for k in 0..6 {
            let recorded = Tape::record(2, |x| shapes(x, k));
            let simplified = Tape::record_simplified(2, |x| shapes(x, k));
            for _ in 0..100 {
                let (a, y, r) = (4.0 * next() - 2.0, 2.0 * next() - 1.0, 0.3 * next());
                let b = [iv(a - r, a + r), iv(y - r, y + r)];
                match (recorded.eval_checked(&b), simplified.eval_checked(&b)) {
                    (None, Some(s)) => panic!("shape {k} at {b:?}: recorded refuses, got {s:?}"),
                    (Some(r), Some(s)) => {
                        for (u, v) in r.iter().zip(&s) {
                            assert!(!u.intersection(*v).is_empty(), "{k} {b:?}: {r:?} {s:?}");
                        }
                    }
                    _ => {}
                }
            }
        }
    }

    /// A small inexact constant is an atom ([spec (2.13)](crate::spec::taylor)): `(cos x - e)^2 + sin(x)^2` with
    /// e = +-0.1 becomes `1 - 2 e cos x + e e`, whose width over a box of width `w` is
    /// `2 |e| |sin x| w` to first order (derived by hand), where the recorded form's is about
    /// `2 w`; it still meets the recorded form's enclosure. With e = 0.9 (above the bound
    /// 1/2) the form is left as recorded, so `sin` stays on the tape.
    #[test]
    fn small_inexact_constants_are_atoms() {
        fn denominator<S: Scalar>(x: &[S], e: f64) -> Vec<S> {
            let c = x[0].cos() - S::cst(e);
            vec![c.clone() * c + x[0].sin() * x[0].sin()]
        }
        let has_sin = |t: &Tape| t.ops.iter().any(|o| matches!(o, Op::Sin(_)));
        for e in [0.1, -0.1] {
            let tape = Tape::record_simplified(1, |x| denominator(x, e));
            assert!(!has_sin(&tape), "{e}: {:?}", tape.ops);
            for (a, w) in [(1.0, 1e-3), (-2.0, 1e-6), (0.0, 1e-4)] {
                let b = [iv(a, a + w)];
                let (got, direct) = (tape.eval(&b)[0], denominator::<Interval>(&b, e)[0]);
                assert!(!got.intersection(direct).is_empty(), "{e} {a}: {got:?} {direct:?}");
                let sin_max = a.sin().abs().max((a + w).sin().abs());
                let bound = 2.0 * e.abs() * (sin_max + w) * w + 1e-15;
                assert!(got.wid() <= bound, "{e} {a}: {got:?} wider than {bound:e}");
                assert!(direct.wid() > 5.0 * bound || a == 0.0, "{e} {a}: {direct:?}");
            }
        }
        let tape = Tape::record_simplified(1, |x| denominator(x, 0.9));
        assert!(has_sin(&tape), "{:?}", tape.ops);
    }

    /// Every tape of every built-in scene's model, simplified or as recorded, encloses the
    /// same values: at random points and small boxes the two interval evaluations intersect
    /// (both contain the exact value), and at points the simplified ones are at most 4 times
    /// as wide (an expanded remainder can round a little more than the factored form).
    #[test]
    fn every_scene_tape_encloses_what_it_did_before_simplification() {
        use crate::model::Model;
        use crate::scene::{AnyScene, SCENES};
        let build = |on: bool, name: &str| {
            super::ENABLED.with(|e| e.set(on));
            let m = Model::new(&AnyScene::new(name, &[]).unwrap()).unwrap();
            super::ENABLED.with(|e| e.set(true));
            m
        };
        let tapes = |m: &Model| -> Vec<Tape> {
            vec![
                m.dynamics.field.clone(),
                m.dynamics.field_var.clone(),
                m.dynamics.field_var_tail().clone(),
                m.action_system().field.clone(),
                m.velocity.clone(),
                m.velocity_jac.clone(),
                m.constraints.clone(),
                m.momentum_tape().clone(),
                m.energy_tape().clone(),
            ]
        };
        let mut seed = 0xfeed_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0
        };
        let mut compared = 0;
        for sc in SCENES {
            let (a, b) = (build(true, sc.name), build(false, sc.name));
            for (ta, tb) in tapes(&a).iter().zip(&tapes(&b)) {
                // a normal form can take a few more nodes than the factored form it
                // replaces (`1 - 2 e c + e e` against `(c - e)^2 + s^2`), never many more
                let most = tb.len() + tb.len() / 4;
                assert!(ta.len() <= most, "{}: {} > {most}", sc.name, ta.len());
                for _ in 0..40 {
                    let r = next().abs() * 1e-6;
                    let x: Vec<f64> = (0..ta.n_inputs()).map(|_| next()).collect();
                    let pts: Vec<Interval> = x.iter().map(|v| point(*v)).collect();
                    let boxes: Vec<Interval> = x.iter().map(|v| iv(v - r, v + r)).collect();
                    for input in [&pts, &boxes] {
                        let (Some(ya), Some(yb)) = (ta.eval_checked(input), tb.eval_checked(input))
                        else {
                            continue;
                        };
                        for (u, v) in ya.iter().zip(&yb) {
                            assert!(!u.intersection(*v).is_empty(), "{}: {u:?} vs {v:?}", sc.name);
                            if input == &pts {
                                let slack = 8.0 * f64::EPSILON * v.mag().max(1e-300);
                                assert!(u.wid() <= 4.0 * v.wid() + slack, "{}: {u:?} vs {v:?}", sc.name);
                            }
                            compared += 1;
                        }
                    }
                }
            }
        }
        assert!(compared > 10_000, "{compared}");
    }
}
