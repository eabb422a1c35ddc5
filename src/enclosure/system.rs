//! The ODE the validated integrator carries sets through: a vector field and its
//! variational equations recorded as tapes (spec eq. (5.6)). It knows nothing of mechanics;
//! `Model` (one layer up) records its reduced equations into one.

use crate::scalar::Dual;
use crate::tape::{Tape, Tracer};

/// An autonomous ODE `x' = F(x)` as tapes: `field: x -> F(x)`,
/// `field_var: (x, V) -> (F(x), DF(x) V)`, V a d x d matrix row-major (spec eq. (5.6)), and
/// `field_var_tail`, the same for a d x `tail` matrix W: the derivatives with respect to
/// the last `tail` components of the initial state only (the shooting Jacobian of the
/// retraction needs D x / D u0, not D x / D q0).
pub struct System {
    /// `x -> F(x)`, `d` inputs and outputs.
    pub field: Tape,
    /// `(x, V) -> (F(x), DF(x) V)`, `V` a `d x d` matrix row-major.
    pub field_var: Tape,
    /// `(x, W) -> (F(x), DF(x) W)`, `W` a `d x tail` matrix row-major.
    pub field_var_tail: Tape,
}

impl System {
    /// The number of columns of `field_var_tail` (its inputs are `d + d tail`).
    pub fn tail(&self) -> usize {
        let d = self.field.n_inputs();
        (self.field_var_tail.n_inputs() - d)
            .checked_div(d)
            .unwrap_or(0)
    }
    /// Record `f` and its variational equation, f written once over any scalar.
    pub(crate) fn record(
        d: usize,
        tail: usize,
        f: impl Fn(&[Tracer]) -> Vec<Tracer>,
        fd: impl Fn(&[Dual<Tracer>]) -> Vec<Dual<Tracer>>,
    ) -> System {
        let var = |c: usize| {
            Tape::record_simplified(d + d * c, |xv| {
                let x: Vec<Dual<Tracer>> = (0..d)
                    .map(|i| Dual::new(xv[i], xv[d + i * c..d + (i + 1) * c].to_vec()))
                    .collect();
                let f = fd(&x);
                let mut out: Vec<Tracer> = f.iter().map(|fi| fi.v).collect();
                for fi in &f {
                    out.extend((0..c).map(|j| fi.der(j)));
                }
                out
            })
        };
        System {
            field: Tape::record_simplified(d, f),
            field_var: var(d),
            field_var_tail: var(tail),
        }
    }
}
