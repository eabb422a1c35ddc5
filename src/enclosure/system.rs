//! The ODE the validated integrator carries sets through: a vector field and its
//! variational equations recorded as tapes ([spec eq. (5.6)](crate::spec::enclosure)). It knows nothing of mechanics;
//! `Model` (one layer up) records its reduced equations into one.

use crate::scalar::Dual;
use crate::tape::{Tape, Tracer};
use std::sync::OnceLock;

/// A recording of the variational equation for a given number of columns.
type VarRecorder = Box<dyn Fn(usize) -> Tape + Send + Sync>;

/// An autonomous ODE `x' = F(x)` as tapes: `field: x -> F(x)`,
/// `field_var: (x, V) -> (F(x), DF(x) V)` with V a d x c matrix row-major, its columns
/// those of `var_cols` ([spec eq. (5.6)](crate::spec::enclosure)), and `field_var_tail`, the same for a d x `tail`
/// matrix W: the derivatives with respect to the last `tail` components of the initial
/// state only (the shooting Jacobian of the retraction needs D x / D u0, not D x / D q0).
pub struct System {
    /// `x -> F(x)`, `d` inputs and outputs.
    pub field: Tape,
    /// `(x, V) -> (F(x), DF(x) V)`, `V` a `d x c` matrix row-major, `c = var_cols.len()`.
    pub field_var: Tape,
    /// The components of the state that `field` reads, increasing. Column `j` of
    /// `D x(t) / D x(0)` for a component `j` not read is the unit vector `e_j`, exactly
    /// ([spec eq. (5.6')](crate::spec::enclosure), cyclic components): only the others are carried by `field_var`.
    pub var_cols: Vec<usize>,
    /// `(x, W) -> (F(x), DF(x) W)`, `W` a `d x tail` matrix row-major: recorded on first
    /// use ([`System::field_var_tail`]), since only the float shooting of the retraction
    /// reads it and recording it is about a third of a model's start-up.
    field_var_tail: OnceLock<Tape>,
    tail: usize,
    record_var: VarRecorder,
}

/// The tapes (the recorder is a closure).
impl std::fmt::Debug for System {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("System")
            .field("field", &self.field)
            .field("field_var", &self.field_var)
            .field("var_cols", &self.var_cols)
            .field("field_var_tail", &self.field_var_tail.get())
            .field("tail", &self.tail)
            .finish_non_exhaustive()
    }
}

impl System {
    /// The number of columns of `field_var_tail` (its inputs are `d + d tail`).
    pub fn tail(&self) -> usize {
        self.tail
    }

    /// `(x, W) -> (F(x), DF(x) W)`, `W` a `d x tail` matrix row-major; recorded on the
    /// first call (the same tape as recorded with the others: one recording of the same
    /// closure).
    pub fn field_var_tail(&self) -> &Tape {
        self.field_var_tail
            .get_or_init(|| (self.record_var)(self.tail))
    }
    /// Record `f` and its variational equation, f written once over any scalar.
    pub(crate) fn record(
        d: usize,
        tail: usize,
        f: impl Fn(&[Tracer]) -> Vec<Tracer>,
        fd: impl Fn(&[Dual<Tracer>]) -> Vec<Dual<Tracer>> + Send + Sync + 'static,
    ) -> System {
        let var = move |c: usize| {
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
        let field = Tape::record_simplified(d, f);
        let read = field.inputs_read();
        let var_cols: Vec<usize> = (0..d).filter(|&j| read[j]).collect();
        System {
            field_var: var(var_cols.len()),
            field,
            var_cols,
            field_var_tail: OnceLock::new(),
            tail,
            record_var: Box::new(var),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::enclosure::{flow_set_c1, FlowOptions, LohnerSet};
    use crate::scalar::{iv, Scalar};
    use inari::Interval;

    /// `x0' = x1, x1' = x1, x2' = sin(x1) + 1/2` reads `x1` alone. Closed form:
    /// `x1(t) = x1(0) e^t`, `x0(t) = x0(0) + x1(0) (e^t - 1)`, so
    /// `D x(t) / D x(0) = [[1, e^t - 1, 0], [0, e^t, 0], [0, g, 1]]` with
    /// `g = int_0^t cos(x1(s)) e^s ds`.
    fn field<S: Scalar>(x: &[S]) -> Vec<S> {
        vec![
            x[1].clone(),
            x[1].clone(),
            x[1].sin() + S::cst(0.5),
        ]
    }

    #[test]
    fn components_the_field_does_not_read_have_unit_columns_exactly() {
        let sys = System::record(3, 1, field, field);
        assert_eq!(sys.var_cols, vec![1]);
        // V is 3 x 1: the variational tape has 3 + 3 inputs
        assert_eq!(sys.field_var.n_inputs(), 6);
        let x0 = [iv(0.25, 0.25 + 1e-9), iv(0.5, 0.5 + 1e-9), iv(-1.0, -1.0)];
        let t = 0.75;
        let (_, jac, _) = flow_set_c1(&sys, LohnerSet::from_box(&x0), t, &FlowOptions::default())
            .expect("certified");
        for (i, row) in jac.rows().enumerate() {
            for j in [0, 2] {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!(row[j].inf() == e && row[j].sup() == e, "J[{i}][{j}] = {:?}", row[j]);
            }
        }
        // column 1 by the closed form: e^t - 1 and e^t (inari's enclosures of them) are
        // in both enclosures, which must then meet
        let et = iv(t, t).exp();
        let meets = |a: Interval, b: Interval| !a.intersection(b).is_empty();
        assert!(meets(jac[0][1], et - iv(1.0, 1.0)), "{:?}", jac[0][1]);
        assert!(meets(jac[1][1], et), "{:?}", jac[1][1]);
        assert!(jac[0][1].wid() < 1e-6 && jac[1][1].wid() < 1e-6 && jac[2][1].wid() < 1e-6);
        // g by the midpoint rule on 4000 subintervals, |error| < 1e-6 here
        let n = 4000;
        let g: f64 = (0..n)
            .map(|k| {
                let s = t * (k as f64 + 0.5) / n as f64;
                (0.5 * s.exp()).cos() * s.exp() * t / n as f64
            })
            .sum();
        assert!((jac[2][1].mid() - g).abs() < 1e-6, "{:?} against {g}", jac[2][1]);
    }

    /// A field that reads nothing: no variational columns at all, `D x(t) / D x(0) = I`.
    #[test]
    fn a_constant_field_has_the_identity_as_its_jacobian() {
        fn constant<S: Scalar>(_: &[S]) -> Vec<S> {
            vec![S::cst(1.0), S::cst(-0.5)]
        }
        let sys = System::record(2, 0, constant, constant);
        assert!(sys.var_cols.is_empty());
        let x0 = [iv(1.0, 1.0 + 1e-9), iv(2.0, 2.0)];
        let (set, jac, _) =
            flow_set_c1(&sys, LohnerSet::from_box(&x0), 3.0, &FlowOptions::default())
                .expect("certified");
        for (i, row) in jac.rows().enumerate() {
            for (j, x) in row.iter().enumerate() {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!(x.inf() == e && x.sup() == e, "J[{i}][{j}] = {x:?}");
            }
        }
        let hull = set.hull();
        assert!(hull[0].contains(4.0) && hull[0].contains(4.0 + 1e-9), "{:?}", hull[0]);
        assert!(hull[1].contains(0.5) && hull[1].wid() < 1e-14, "{:?}", hull[1]);
    }
}
