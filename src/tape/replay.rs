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

    /// [`Tape::ode_taylor`] to `order` (at least 1), kept so that it can be grown to higher
    /// orders ([`Growing::grow`]): the recurrences go on from where they stopped, and the
    /// coefficients to any order are those of `ode_taylor(x0, order)` ([spec eqs.
    /// (2.2)-(2.8)](crate::spec::taylor)). `None` as [`Tape::ode_taylor`]. `room`: the order
    /// it is expected to grow to, for which room is made at once (growing past it costs a
    /// copy of the coefficients).
    pub(crate) fn ode_taylor_growing<T: Coef>(
        &self,
        x0: &[T],
        order: usize,
        room: usize,
    ) -> Option<Growing<'_, T>> {
        let d = self.n_inputs;
        let mut flat: Vec<T> = Vec::with_capacity((order + 1) * d);
        flat.extend_from_slice(x0);
        charge(terms(self.ops.len(), 0));
        let mut g = Growing {
            tape: self,
            s: Series::new(self.ops.len(), order.max(room) + 1),
            flat,
            order: 0,
            dead: false,
        };
        g.grow(order.max(1)).then_some(g)
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

/// A Taylor series of the solution of `x' = F(x)` ([`Tape::ode_taylor_growing`]), to some
/// order, that can be grown.
pub(crate) struct Growing<'a, T: Coef> {
    tape: &'a Tape,
    s: Series<T>,
    /// the coefficients `x_0 .. x_order`, row after row
    flat: Vec<T>,
    order: usize,
    /// a coefficient past `order` was not proved (a check of (2.8) failed, or it is not
    /// finite): the series cannot grow
    dead: bool,
}

impl<T: Coef> Growing<'_, T> {
    /// Grows the series to order `to` (nothing when it is there already). `false`, the series
    /// left at its order, when a coefficient on the way is not proved ([spec eq.
    /// (2.8)](crate::spec::taylor)); it then grows no more.
    pub(crate) fn grow(&mut self, to: usize) -> bool {
        if to <= self.order {
            return true;
        }
        if self.dead {
            return false;
        }
        let (d, ops) = (self.tape.n_inputs, &self.tape.ops);
        charge(terms(ops.len(), to) - terms(ops.len(), self.order));
        self.s.widen(to + 1);
        // step k makes coefficient k of every node, hence coefficient k + 1 of the inputs
        for k in self.order..to {
            self.s.step(ops, k, &self.flat[k * d..(k + 1) * d]);
            let mut failed = !self.s.ok;
            if !failed {
                let kk = T::cst((k + 1) as f64);
                for i in 0..d {
                    let next = self.s.get(self.tape.outputs[i], k).quot(kk);
                    failed |= !next.is_finite_coef();
                    self.flat.push(next);
                }
            }
            if failed {
                self.flat.truncate((self.order + 1) * d);
                self.dead = true;
                return false;
            }
        }
        self.order = to;
        true
    }

    /// The coefficients `x_0 .. x_order`.
    pub(crate) fn rows(&self) -> Rows<'_, T> {
        Rows {
            width: self.tape.n_inputs,
            len: self.order + 1,
            flat: &self.flat,
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

    /// A growing series: grown rung by rung (3, 8, 20, 21), the coefficients of
    /// `ode_taylor(x0, order)` at each, bit for bit, and the work of the order reached; grown
    /// into an overflow, it keeps its order and grows no more.
    #[test]
    fn a_grown_series_is_the_series_of_its_order() {
        let tape = Tape::record(3, |x| {
            let (y, u1, u2) = (x[0], x[1], x[2]);
            vec![u2, -(y * u1 * u2) / (Tracer::one() + y * y) + y.sin(), Tracer::zero()]
        });
        let x0 = [point(0.4), crate::scalar::iv(0.8, 0.8000000000000002), point(0.8)];
        // the work charged is that of the order reached
        let before = work_done();
        let mut g = tape.ode_taylor_growing(&x0, 3, 3).unwrap();
        for q in [8, 20, 21] {
            assert!(g.grow(q));
        }
        let grown_work = work_done() - before;
        let before = work_done();
        tape.ode_taylor(&x0, 21).unwrap();
        assert_eq!(work_done() - before, grown_work);
        let mut g = tape.ode_taylor_growing(&x0, 3, 20).unwrap();
        for q in [3, 8, 8, 20, 21] {
            assert!(g.grow(q));
            let fresh = tape.ode_taylor(&x0, q).unwrap();
            assert_eq!(g.rows().len(), q + 1);
            for (r, s) in g.rows().iter().zip(fresh.iter()) {
                assert!(r.iter().zip(s).all(|(x, y)| x.inf() == y.inf() && x.sup() == y.sup()));
            }
        }
        // x' = x^2 from 10^12: x_k = 10^(12 (k + 1)), finite to k = 24
        let tape = Tape::record(1, |x| vec![x[0] * x[0]]);
        let mut g = tape.ode_taylor_growing(&[1e12f64], 20, 20).unwrap();
        assert!(!g.grow(28));
        assert_eq!(g.rows().len(), 21);
        assert!(!g.grow(22));
        assert_eq!(g.rows().iter().collect::<Vec<_>>(), tape.ode_taylor(&[1e12f64], 20).unwrap().iter().collect::<Vec<_>>());
        assert!(tape.ode_taylor_growing(&[1e12f64], 26, 30).is_none());
        let tape = Tape::record(1, |x| vec![x[0].sqrt()]);
        assert!(tape.ode_taylor_growing(&[point(-1.0)], 3, 3).is_none());
    }
}
