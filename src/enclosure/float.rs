//! The float flows: Taylor integrations in plain f64 of the state and its variational
//! equation. Not rigorous; used only to choose points (Newton guesses).

use super::control::*;
use super::options::FlowOptions;
use super::orders::{DEFAULT_ORDER, LOW_ORDERS, SHORT_ORDER};
use super::system::System;
use nalgebra::DMatrix;

/// A float Taylor integration of `x' = F(x)` and of its variational equation over time `t`,
/// for the derivatives with respect to the last `sys.tail()` components
/// of `x0` only (`D x(t) / D x0[d - tail..]`, d x tail), also returning the number of Taylor
/// steps taken (the work, for callers that bound their total work).
pub fn float_flow_tail_counted(
    sys: &System,
    x0: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
    let (d, c) = (x0.len(), sys.tail());
    let w0 = DMatrix::from_fn(d, c, |i, j| if i + c == d + j { 1.0 } else { 0.0 });
    float_flow_var(sys.field_var_tail(), x0, w0, t, opts)
}

/// A float Taylor integration of `x' = F(x)` alone over time `t` (the state at `t` and the
/// number of steps taken); not rigorous, as [`float_flow_tail_counted`].
pub fn float_flow_counted(
    sys: &System,
    x0: &[f64],
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, usize)> {
    let w0 = DMatrix::zeros(x0.len(), 0);
    float_flow_var(&sys.field, x0, w0, t, opts).map(|(x, _, steps)| (x, steps))
}

/// Float Taylor integration of `(x, W)' = (F(x), DF(x) W)` from `(x0, w0)`; `tape` is the
/// variational tape for `w0.ncols()` columns. W(t) = D x(t)/D x0 * w0.
pub(super) fn float_flow_var(
    tape: &crate::tape::Tape,
    x0: &[f64],
    w0: DMatrix<f64>,
    t: f64,
    opts: &FlowOptions,
) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
    let (d, cols) = (x0.len(), w0.ncols());
    let mut p = opts.given_order().unwrap_or(DEFAULT_ORDER);
    // (5.8) (e) as in the validated flows: a span of two or three steps at order p runs at
    // SHORT_ORDER (the series of the first step goes on from p)
    let mut choose_order = opts.given_order().is_none();
    let mut xw: Vec<f64> = x0.to_vec();
    xw.extend(
        (0..d)
            .flat_map(|i| (0..cols).map(move |j| (i, j)))
            .map(|(i, j)| w0[(i, j)]),
    );
    let mut done = 0.0;
    for steps in 0..opts.max_taylor_steps {
        if done >= t {
            let w = DMatrix::from_fn(d, cols, |i, j| xw[d + i * cols + j]);
            return Some((xw[..d].to_vec(), w, steps));
        }
        let rest = t - done;
        let more = if choose_order { SHORT_ORDER } else { p };
        let mut series = tape.ode_series::<f64>(&xw, more);
        // (5.8') as in the validated flows: a step that a lower order also takes to the end
        // takes the lowest such order, the series grown through them and no further
        let low = match opts.given_order() {
            Some(_) => None,
            None => LOW_ORDERS.iter().copied().filter(|&q| q < p).find(|&q| {
                series.grow(q) && step_size(series.rows(), q, &xw, f64::EPSILON) >= rest
            }),
        };
        let q = match low {
            Some(q) => q,
            None => {
                if !series.grow(p) {
                    return None;
                }
                // (5.8) (e) the order of a short span (`more > p` only at the first step); past
                // p a failure leaves the series at p
                if more > p && short_span(rest, rest, step_size(series.rows(), p, &xw, f64::EPSILON)) {
                    series.grow(more);
                }
                choose_order = false;
                p = series.order();
                p
            }
        };
        let c = series.coeffs();
        // The step rule (5.8) on the state AND the variational series: the Jacobian's series
        // can have a smaller radius of convergence than the state's (e.g. the particle with
        // u1 = 0: x(t) stays 0 while D x / D u1 = asinh(u2 t) / u2 is singular at t = i/u2).
        let h = step_size(c.rows(), q, &xw, f64::EPSILON).min(rest);
        xw = (0..xw.len())
            .map(|i| c.iter().rev().fold(0.0, |acc, ck| acc * h + ck[i]))
            .collect();
        done = if h >= t - done { t } else { done + h };
        if !xw.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    None
}
