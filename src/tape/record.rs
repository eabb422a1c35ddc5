//! Recording: a computation written once over `S: Scalar`, run with [`Tracer`], becomes a
//! tape. Every operation is stored once (hash-consing), and the exact identities of real
//! arithmetic (`x + 0 = x`, `x * 0 = 0`, `x * 1 = x`, `x / 1 = x`) and exact constant
//! folding are applied on the way, so replaying is sound.
//!
//! The recording a tracer writes to is found through this thread's stack of open
//! recordings, since [`Scalar::cst`] has no receiver to carry it. A [`Tape::record`] made
//! inside the closure of another opens its own recording on top of the stack and closes it
//! before the outer closure goes on, so a nested recording never touches the outer one. A
//! tracer carries the id of the recording that made it, and is refused (a panic) by any
//! other: the crate only ever passes a closure the tracers of its own recording.

// Float comparisons are written as guards on purpose: `c == 0.0` also matches -0.0.
#![allow(clippy::redundant_guards)]

use super::program::{key, Op};
use super::Tape;
use crate::scalar::{point, Scalar};
use inari::Interval;
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::marker::PhantomData;
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::sync::atomic::{AtomicU32, Ordering};

/// A tape being recorded, with a table of the operations already on it so that an
/// operation recorded twice on the same arguments is stored once (hash-consing).
#[derive(Default)]
struct Recording {
    /// Unique among the recordings of the process (never 0).
    id: u32,
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
    /// The recordings open on this thread, innermost last.
    static OPEN: RefCell<Vec<Recording>> = const { RefCell::new(Vec::new()) };
    /// The id of the innermost open recording; 0 when none is open.
    static CURRENT: Cell<u32> = const { Cell::new(0) };
}

/// The operations a recording makes room for when it opens (only the speed depends on it).
const RECORDING_ROOM: usize = 256;

/// The id of the next recording opened, in any thread.
static NEXT_ID: AtomicU32 = AtomicU32::new(1);

/// An open recording, innermost on this thread's stack for as long as the guard lives. It
/// is closed when the guard drops: after [`Open::close`] took its operations, or while a
/// panic unwinds out of the recording closure (the stack then stays that of the enclosing
/// recordings). Guards are local to one function call, so they close in the reverse order
/// they opened; not `Send`, since the stack is the thread's.
pub(super) struct Open {
    id: u32,
    _thread: PhantomData<*const ()>,
}

impl Open {
    pub(super) fn new() -> Open {
        let id = loop {
            let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
            if id != 0 {
                break id;
            }
        };
        OPEN.with(|r| {
            r.borrow_mut().push(Recording {
                id,
                // room for a model's tapes (a few hundred operations) without regrowing
                ops: Vec::with_capacity(RECORDING_ROOM),
                seen: HashMap::with_capacity_and_hasher(RECORDING_ROOM, Default::default()),
            })
        });
        CURRENT.with(|c| c.set(id));
        Open {
            id,
            _thread: PhantomData,
        }
    }

    /// The operations recorded; the recording is closed.
    pub(super) fn close(self) -> Vec<Op> {
        OPEN.with(|r| {
            let mut r = r.borrow_mut();
            let top = r.last_mut().filter(|t| t.id == self.id);
            std::mem::take(&mut top.expect("the innermost recording is this guard's").ops)
        })
    }
}

impl Drop for Open {
    fn drop(&mut self) {
        OPEN.with(|r| {
            let mut r = r.borrow_mut();
            if r.last().is_some_and(|t| t.id == self.id) {
                r.pop();
            }
            CURRENT.with(|c| c.set(r.last().map_or(0, |t| t.id)));
        });
    }
}

/// A node of a tape being recorded, valid only inside the [`Tape::record`] that made it
/// (and the recordings that [`Tape::record_simplified`] makes of it).
#[derive(Clone, Copy, Debug)]
pub struct Tracer {
    node: u32,
    recording: u32,
}

impl Tracer {
    /// The node's index on the tape being recorded: equal indices are the same expression
    /// (hash-consing), so this is a cheap test of structural identity.
    pub fn index(&self) -> u32 {
        self.node
    }

    /// Node `node` of the innermost open recording.
    pub(super) fn at(node: u32) -> Tracer {
        Tracer {
            node,
            recording: CURRENT.with(Cell::get),
        }
    }

    /// This node's index, which must be on the innermost open recording: a tracer of
    /// another recording (an outer one, or one already closed) names a node of a different
    /// program, and taking it as an argument here would record a wrong tape.
    fn arg(self) -> u32 {
        let current = CURRENT.with(Cell::get);
        if self.recording != current {
            foreign(current);
        }
        self.node
    }
}

#[cold]
#[inline(never)]
fn foreign(current: u32) -> ! {
    if current == 0 {
        panic!("a Tracer was used with no Tape::record open (a tracer is valid only inside the recording that made it)");
    }
    panic!(
        "a Tracer was used inside a Tape::record that did not make it (a tracer belongs to \
         the recording whose closure received it)"
    );
}

/// Records `op` on the innermost open recording, or finds it there.
pub(super) fn push(op: Op) -> Tracer {
    OPEN.with(|r| {
        let mut r = r.borrow_mut();
        let Some(t) = r.last_mut() else {
            foreign(0);
        };
        // (the constants read from the recording already borrowed, not through the
        // thread-local once per operand)
        let op = fold(op, |i| match t.ops[i as usize] {
            Op::Const(c) => Some(c),
            _ => None,
        });
        let k = key(&op);
        if let Some(i) = t.seen.get(&k) {
            return Tracer {
                node: *i,
                recording: t.id,
            };
        }
        t.ops.push(op);
        let i = (t.ops.len() - 1) as u32;
        t.seen.insert(k, i);
        Tracer {
            node: i,
            recording: t.id,
        }
    })
}

/// The value of `x` if it is a constant node.
pub(super) fn constant_of(x: Tracer) -> Option<f64> {
    constant_at(x.arg())
}

/// The value of node `i` of the innermost open recording if it is a constant.
fn constant_at(i: u32) -> Option<f64> {
    OPEN.with(|r| match r.borrow().last()?.ops[i as usize] {
        Op::Const(c) => Some(c),
        _ => None,
    })
}

/// Exact constant folding: an operation on constants whose interval result is a single
/// f64 (so the real result is that f64) becomes a constant; a product with one constant
/// operand, or a quotient by a constant whose reciprocal is an f64 (a power of two), becomes
/// a scaling, whose Taylor recurrence costs O(1) instead of O(k).
fn fold(op: Op, c: impl Fn(u32) -> Option<f64>) -> Op {
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
            _ => push(Op::Add(self.node, o.node)),
        }
    }
}
impl Sub for Tracer {
    type Output = Tracer;
    fn sub(self, o: Tracer) -> Tracer {
        match (constant_of(self), constant_of(o)) {
            (_, Some(c)) if c == 0.0 => self,
            (Some(c), _) if c == 0.0 => -o,
            _ => push(Op::Sub(self.node, o.node)),
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
            _ => push(Op::Mul(self.node, o.node)),
        }
    }
}
impl Div for Tracer {
    type Output = Tracer;
    fn div(self, o: Tracer) -> Tracer {
        match (constant_of(self), constant_of(o)) {
            (_, Some(c)) if c == 1.0 => self,
            _ => push(Op::Div(self.node, o.node)),
        }
    }
}
impl Neg for Tracer {
    type Output = Tracer;
    fn neg(self) -> Tracer {
        match constant_of(self) {
            Some(c) if c == 0.0 => self,
            _ => push(Op::Neg(self.arg())),
        }
    }
}
impl Scalar for Tracer {
    fn cst(c: f64) -> Self {
        push(Op::Const(c))
    }
    fn sin(&self) -> Self {
        push(Op::Sin(self.arg()))
    }
    fn cos(&self) -> Self {
        push(Op::Cos(self.arg()))
    }
    fn sqrt(&self) -> Self {
        push(Op::Sqrt(self.arg()))
    }
    fn exp(&self) -> Self {
        push(Op::Exp(self.arg()))
    }
    fn ln(&self) -> Self {
        push(Op::Ln(self.arg()))
    }
    fn atan(&self) -> Self {
        push(Op::Atan(self.arg()))
    }
    fn sinh(&self) -> Self {
        push(Op::Sinh(self.arg()))
    }
    fn cosh(&self) -> Self {
        push(Op::Cosh(self.arg()))
    }
    fn pi() -> Self {
        push(Op::Pi)
    }
}

impl Tape {
    /// Record `f` on `n_inputs` symbolic inputs. `f` may record tapes of its own (they are
    /// recordings of their own, and leave this one as it was).
    pub fn record(n_inputs: usize, f: impl FnOnce(&[Tracer]) -> Vec<Tracer>) -> Tape {
        let open = Open::new();
        let inputs: Vec<Tracer> = (0..n_inputs).map(|i| push(Op::Input(i))).collect();
        let outs = f(&inputs);
        let outputs = outs.iter().map(|t| t.arg()).collect();
        Tape {
            ops: open.close(),
            n_inputs,
            outputs,
        }
        .without_dead_code()
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
}

#[cfg(test)]
mod tests {
    use super::Op;
    use crate::scalar::Scalar;
    use crate::tape::{Tape, Tracer};

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

    /// A recording made inside the closure of another leaves the outer one as it was: the
    /// outer tape is the one recorded without the inner, the inner the one recorded alone
    /// (simplified too, which records twice more).
    #[test]
    fn a_nested_recording_leaves_the_outer_one_intact() {
        let outer_f = |x: &[Tracer]| {
            let s = x[0].sin() * x[1];
            (s, vec![s + x[1].cos(), s * s])
        };
        let inner_f = |y: &[Tracer]| vec![y[0].exp() * y[0] - y[0] * y[0].exp()];
        let outer_alone = Tape::record(2, |x| outer_f(x).1);
        let inner_alone = Tape::record_simplified(1, inner_f);
        let mut inner = None;
        let outer = Tape::record(2, |x| {
            let (s, _) = outer_f(x);
            inner = Some(Tape::record_simplified(1, inner_f));
            vec![s + x[1].cos(), s * s]
        });
        assert_eq!(outer, outer_alone);
        assert_eq!(inner.unwrap(), inner_alone);
        let s = 0.3f64.sin() * 0.7;
        assert_eq!(outer.eval(&[0.3f64, 0.7]), vec![s + 0.7f64.cos(), s * s]);
    }

    /// A tracer taken into a recording that did not make it is refused, not read as a node
    /// of the wrong program; the recordings open are closed as the panic unwinds, and the
    /// next recording is whole.
    #[test]
    fn a_tracer_of_another_recording_is_refused() {
        let caught = std::panic::catch_unwind(|| {
            Tape::record(1, |x| {
                let outer = x[0];
                let _ = Tape::record(1, |y| vec![y[0] + outer]);
                vec![x[0]]
            })
        });
        let message = caught.unwrap_err();
        let message = message.downcast_ref::<String>().map(String::as_str).or_else(|| message.downcast_ref::<&str>().copied());
        assert!(message.is_some_and(|m| m.contains("did not make it")), "{message:?}");
        let mut kept = None;
        let stale = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            Tape::record(1, |x| {
                kept = Some(x[0]);
                vec![x[0]]
            });
            kept.unwrap().sin()
        }));
        assert!(stale.is_err());
        let tape = Tape::record(1, |x| vec![x[0] * x[0] + Tracer::one()]);
        assert_eq!(tape.eval(&[3.0f64]), vec![10.0]);
        assert_eq!(tape, Tape::record(1, |x| vec![x[0] * x[0] + Tracer::one()]));
    }
}
