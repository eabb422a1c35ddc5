//! Recording a computation once and replaying it: over any
//! [`Scalar`](crate::scalar::Scalar) (one value per node) and over truncated Taylor series
//! of intervals ([spec/02-taylor.md](crate::spec::taylor), eqs. (2.1)-(2.7)).
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
//!
//! One concern a file:
//! - `program`: the operations of a tape and the passes over a recorded program;
//! - `record`: recording with hash-consing, the [`Tracer`](crate::tape::Tracer) scalar, the stack of open
//!   recordings;
//! - `simplify`: the exact normal forms of cancelling sums ([spec (2.13)](crate::spec::taylor));
//! - `replay`: evaluation over a scalar, Taylor series of `x' = F(x)`;
//! - `series`: the Taylor recurrences over a coefficient type ([`Coef`](crate::tape::Coef));
//! - `coeffs`: the coefficients a series returns ([`Coeffs`](crate::tape::Coeffs),
//!   [`Rows`](crate::tape::Rows));
//! - `work`: the work meter ([`work_done`](crate::tape::work_done)).

mod coeffs;
mod program;
mod record;
mod replay;
mod series;
mod simplify;
mod work;

pub use coeffs::{Coeffs, Rows};
pub use record::Tracer;
pub(crate) use replay::OdeSeries;
pub use series::{finite, Coef};
pub use work::work_done;

/// A recorded straight-line program from `inputs` values to `outputs` values. Two equal
/// tapes are the same program: they compute the same values over every scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    /// The operations in the order recorded; each reads earlier nodes only.
    ops: Vec<program::Op>,
    n_inputs: usize,
    /// The node of each output.
    outputs: Vec<u32>,
}

impl Tape {
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
}
