//! The operations a tape records, and the passes over a recorded program: which nodes the
//! outputs depend on, dead-code removal, and structural identity of two programs.

use super::Tape;
use std::collections::HashMap;

/// One operation of a tape; arguments are indices of earlier nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Op {
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

/// A hashable key of an operation; commutative operations are ordered.
pub(super) fn key(op: &Op) -> (u8, u64, u64) {
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

/// The nodes an operation reads.
pub(super) fn args(op: &Op) -> Vec<u32> {
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

/// `op` with every argument `a` replaced by `m[a]`.
pub(super) fn remap(op: &Op, m: &[u32]) -> Op {
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

impl Tape {
    /// Which nodes the outputs depend on.
    pub(super) fn needed(&self) -> Vec<bool> {
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
    pub(super) fn live(&self) -> Vec<bool> {
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
    pub(super) fn without_dead_code(self) -> Tape {
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
}

#[cfg(test)]
mod tests {
    use crate::tape::{Tape, Tracer};
    use crate::scalar::Scalar;

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
