//! Replaying a tape: over any [`Scalar`] (one value per node, [spec eq. (2.1)](crate::spec::taylor)), and over
//! truncated Taylor series for the solutions of `x' = F(x)` ([spec eqs. (2.2)-(2.8)](crate::spec::taylor)).

use super::program::Op;
use super::series::{Coef, Series};
use super::work::{charge, terms};
use super::{Coeffs, Rows, Tape};
use crate::scalar::Scalar;

impl Tape {
    /// Replay over any scalar: the outputs at `x` ([spec eq. (2.1)](crate::spec::taylor)).
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
    /// ([spec eqs. (2.2)-(2.7)](crate::spec::taylor)). Division by an interval containing 0 yields a non-finite or
    /// empty coefficient, which the caller must treat as failure.
    ///
    /// Returns `None` when the tape is not proved smooth on the box: a divisor enclosure
    /// containing 0, a square root of an enclosure not in (0, inf), or a non-finite
    /// coefficient ([spec eq. (2.8)](crate::spec::taylor)).
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
        let mut s = self.ode_series(x0, order.max(more));
        if !s.grow(order) {
            return None;
        }
        if more > order && !enough(s.rows()) {
            // past `order` a failure leaves the series at `order`
            s.grow(more);
        }
        Some(s.coeffs())
    }

    /// The Taylor series of [`Tape::ode_taylor`] at `x0`, grown one order at a time as its
    /// reader asks ([`OdeSeries::grow`]): the coefficients to an order are those of
    /// `ode_taylor(x0, order)`, bit for bit, however many times it was grown to get there
    /// (each coefficient's recurrence reads only the coefficients below it, [spec eqs.
    /// (2.3)-(2.7)](crate::spec::taylor)). `room`: the order it is expected to reach (it may grow past it).
    pub(crate) fn ode_series<T: Coef>(&self, x0: &[T], room: usize) -> OdeSeries<'_, T> {
        self.ode_series_scaled(x0, room, None)
    }
    /// [`Tape::ode_series`] of `y(s) = x(h s)`, the solution of `y' = h F(y)`, when `h` is
    /// given: its coefficients are `h^k x_k` ([spec (5.5''')](crate::spec::enclosure)),
    /// each made by `y_{k+1} = (h F_k) / (k + 1)` with `F_k` the field's coefficients along
    /// `y` (for `x' = F(x)` autonomous, as every tape's field is).
    pub(crate) fn ode_series_scaled<T: Coef>(&self, x0: &[T], room: usize, h: Option<T>) -> OdeSeries<'_, T> {
        let d = self.n_inputs;
        let mut flat: Vec<T> = Vec::with_capacity((room + 1) * d);
        flat.extend_from_slice(x0);
        // the work of order 0 (spec (5.8''')): a series grown to an order charges what
        // `ode_taylor(x0, order)` does
        charge(terms(self.ops.len(), 0));
        OdeSeries {
            tape: self,
            s: Series::new(self.ops.len(), room + 1),
            flat,
            steps: 0,
            order: 0,
            broken: false,
            h,
        }
    }
    /// Rigorous evaluation over intervals, with the same smoothness checks as
    /// [`Tape::ode_taylor`]: `None` unless every output is a finite enclosure of the exact
    /// value at every point of the box ([spec eq. (2.8)](crate::spec::taylor)).
    pub fn eval_checked<T: Coef>(&self, x: &[T]) -> Option<Vec<T>> {
        let mut s = Series::new(self.ops.len(), 1);
        s.step(&self.ops, 0, x);
        let out: Vec<T> = self.outputs.iter().map(|o| s.get(*o, 0)).collect();
        (s.ok && out.iter().all(|x| x.is_finite_coef())).then_some(out)
    }
}

/// A Taylor series of `x' = F(x)` grown order by order ([`Tape::ode_series`]).
pub(crate) struct OdeSeries<'t, T: Coef> {
    tape: &'t Tape,
    s: Series<T>,
    /// rows `x_0 .. x_order`
    flat: Vec<T>,
    /// the recurrences' steps run (step k makes the nodes' coefficient k)
    steps: usize,
    order: usize,
    /// a check of (2.8) or a finite coefficient failed: the series grows no further
    broken: bool,
    /// the time scale of [`Tape::ode_series_scaled`]
    h: Option<T>,
}

impl<T: Coef> OdeSeries<'_, T> {
    /// Grow the coefficients to `order` (nothing when they reach it already). `false` when
    /// the tape is not proved smooth on the box to that order (a divisor enclosure holding
    /// 0, a square root's argument not in (0, inf), a coefficient not finite: [spec eq.
    /// (2.8)](crate::spec::taylor)): the series then stays at the order it had, and grows no further.
    /// Step 0 always runs, since it carries the domain checks.
    pub fn grow(&mut self, order: usize) -> bool {
        if self.broken {
            return false;
        }
        let (d, ops) = (self.tape.n_inputs, self.tape.ops.len());
        let from = self.order;
        if order > from {
            charge(terms(ops, order) - terms(ops, from));
            self.s.widen(order + 1);
        }
        let last = order.max(1);
        // rows to `rows` are made; step k needs row k and makes row k + 1
        let rows = self.flat.len() / d - 1;
        for k in rows..last {
            let mut failed = false;
            if k == self.steps {
                self.s.step(&self.tape.ops, k, &self.flat[k * d..(k + 1) * d]);
                self.steps += 1;
                failed = !self.s.ok;
            }
            if !failed && k < order {
                for i in 0..d {
                    let f = self.s.get(self.tape.outputs[i], k);
                    let next = self.h.map_or(f, |h| f * h).quot_int(k + 1);
                    failed |= !next.is_finite_coef();
                    self.flat.push(next);
                }
            }
            if failed {
                self.broken = true;
                self.flat.truncate((from + 1) * d);
                return false;
            }
        }
        self.order = self.order.max(order);
        true
    }

    /// The order the coefficients reach.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Rows `x_0 .. x_order`.
    pub fn rows(&self) -> Rows<'_, T> {
        Rows {
            width: self.tape.n_inputs,
            len: self.order + 1,
            flat: &self.flat,
        }
    }

    /// The coefficients to the order reached.
    pub fn coeffs(self) -> Coeffs<T> {
        Coeffs {
            width: self.tape.n_inputs,
            len: self.order + 1,
            flat: self.flat,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::scalar::{point, Scalar};
    use crate::tape::{work_done, Coeffs, Tape, Tracer};
    use inari::Interval;

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

    /// `ode_series` grown in stages (0, 3, the same 3 again, 8, 15) has, at each stage, the
    /// coefficients of `ode_taylor` at that order, bit for bit, and charges the same work in
    /// all as one series of the last order; grown into an overflow it keeps the order it had
    /// and grows no further (`x' = x^2` from `x0`: `x_k = x0^(k+1)`).
    #[test]
    fn a_series_grown_in_stages_is_the_series_of_each_order() {
        let tape = Tape::record(3, |x| {
            let (y, u1, u2) = (x[0], x[1], x[2]);
            vec![u2, -(y * u1 * u2) / (Tracer::one() + y * y) + y.sin(), u1.cos()]
        });
        let x0 = [point(0.4), crate::scalar::iv(0.8, 0.8000000000000002), point(0.8)];
        let bits = |c: &Coeffs<Interval>| -> Vec<(u64, u64)> {
            c.iter().flatten().map(|x| (x.inf().to_bits(), x.sup().to_bits())).collect()
        };
        let before = work_done();
        let mut s = tape.ode_series(&x0, 4);
        let mut staged = work_done() - before;
        for order in [0, 3, 3, 8, 15] {
            let before = work_done();
            assert!(s.grow(order));
            staged += work_done() - before;
            assert_eq!(s.order(), order);
            let rows = s.rows();
            let grown = Coeffs::from_rows(3, rows.iter());
            assert_eq!(bits(&grown), bits(&tape.ode_taylor(&x0, order).unwrap()));
        }
        let before = work_done();
        tape.ode_taylor(&x0, 15).unwrap();
        assert_eq!(work_done() - before, staged);

        let tape = Tape::record(1, |x| vec![x[0] * x[0]]);
        // x0 = 2^40: every coefficient and sum a small integer times a power of 2, exact;
        // x_k = 2^(40 (k + 1)) overflows at k = 25
        let x0 = [2f64.powi(40)];
        let mut s = tape.ode_series(&x0, 30);
        assert!(s.grow(20));
        assert!(!s.grow(30));
        assert_eq!(s.order(), 20);
        assert!(!s.grow(21));
        let c = s.coeffs();
        assert_eq!(c.len(), 21);
        for (k, row) in c.iter().enumerate() {
            assert_eq!(row[0], 2f64.powi(40 * (k as i32 + 1)));
        }
        // the domain checks of step 0 fail a series of order 0 too, and it grows no more
        let tape = Tape::record(1, |x| vec![x[0].sqrt()]);
        let mut s = tape.ode_series(&[point(-1.0)], 3);
        assert!(!s.grow(0));
        assert!(!s.grow(3));
    }
}
