//! A damped Newton solver with a typed result ([spec/07-schemes.md](crate::spec::schemes), eq. (7.6)).

use nalgebra::{DMatrix, DVector};

/// How a Newton solve ended.
#[derive(Clone, Debug, PartialEq)]
pub enum NewtonOutcome {
    /// `|R(x)|_inf <= residual` after `iterations` iterations.
    Converged {
        /// Iterations taken.
        iterations: usize,
        /// `|R(x)|_inf` at the returned `x`.
        residual: f64,
    },
    /// The named failure; the state is not returned.
    Failed(NewtonFailure),
}

/// Why Newton stopped without converging.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NewtonFailure {
    /// The Jacobian could not be factorised or is numerically singular.
    SingularJacobian,
    /// No step along the Newton direction reduced the residual (line search exhausted).
    Diverged,
    /// A residual or Jacobian entry was NaN or infinite.
    NonFinite,
    /// The iteration limit was reached.
    IterationLimit,
}

impl std::fmt::Display for NewtonFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NewtonFailure::SingularJacobian => "singular Jacobian",
            NewtonFailure::Diverged => "divergence (line search found no decrease)",
            NewtonFailure::NonFinite => "non-finite values",
            NewtonFailure::IterationLimit => "iteration limit reached",
        })
    }
}

impl std::error::Error for NewtonFailure {}

/// Settings: at most `max_iter` iterations; converged when the Newton step is below
/// `4 eps max(1, |x|)` or the residual is below `tol`.
/// Build them with `NewtonOptions::default()` and the `with_*` setters.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct NewtonOptions {
    /// At most this many iterations (default 50); then `IterationLimit`.
    pub max_iter: usize,
    /// Converged once `|R(x)|_inf <= tol` (default 0: in practice the step criterion decides).
    pub tol: f64,
    /// Halvings of the step allowed in one line search (the step factor stays >= 2^-n).
    pub max_backtracks: u32,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            max_iter: 50,
            tol: 0.0,
            max_backtracks: 33,
        }
    }
}

impl NewtonOptions {
    /// With at most `n` iterations.
    pub fn with_max_iter(mut self, n: usize) -> Self {
        self.max_iter = n;
        self
    }
    /// With convergence once `|R(x)|_inf <= tol`.
    pub fn with_tol(mut self, tol: f64) -> Self {
        self.tol = tol;
        self
    }
    /// With at most `n` halvings of the step in one line search.
    pub fn with_max_backtracks(mut self, n: u32) -> Self {
        self.max_backtracks = n;
        self
    }
}

fn norm_inf(v: &DVector<f64>) -> f64 {
    v.iter().fold(0.0, |a, x| a.max(x.abs()))
}

/// Solve `R(x) = 0` from `x`, where `f(x)` returns `(R(x), DR(x))`. On success `x` holds the
/// solution. On `Diverged` and `IterationLimit`, `x` holds the last accepted iterate (a
/// caller that only needs a starting point may use it); on other failures it is unspecified.
pub fn solve(
    x: &mut DVector<f64>,
    f: impl Fn(&DVector<f64>) -> (DVector<f64>, DMatrix<f64>),
    opts: &NewtonOptions,
) -> NewtonOutcome {
    let finite = |v: &DVector<f64>| v.iter().all(|a| a.is_finite());
    let (mut r, mut j) = f(x);
    for it in 0..opts.max_iter {
        if !finite(&r) || !j.iter().all(|a| a.is_finite()) {
            return NewtonOutcome::Failed(NewtonFailure::NonFinite);
        }
        let rn = norm_inf(&r);
        if rn <= opts.tol {
            return NewtonOutcome::Converged {
                iterations: it,
                residual: rn,
            };
        }
        let lu = j.clone().lu();
        let dx = match lu.solve(&(-&r)) {
            Some(d) if finite(&d) => d,
            _ => return NewtonOutcome::Failed(NewtonFailure::SingularJacobian),
        };
        // Reject numerically singular systems: a step far larger than the state and the
        // residual can justify.
        let scale = norm_inf(x).max(1.0);
        if norm_inf(&dx) > 1e12 * scale.max(rn) {
            return NewtonOutcome::Failed(NewtonFailure::SingularJacobian);
        }
        // Backtracking line search on |R|_inf.
        let mut alpha = 1.0;
        let accepted = loop {
            let trial = &*x + &dx * alpha;
            let (rt, jt) = f(&trial);
            if finite(&rt) && norm_inf(&rt) <= (1.0 - 1e-4 * alpha) * rn {
                break Some((trial, rt, jt));
            }
            alpha *= 0.5;
            if alpha < 0.5f64.powi(opts.max_backtracks as i32) {
                break None;
            }
        };
        let small_step = norm_inf(&dx) <= 4.0 * f64::EPSILON * scale;
        match accepted {
            Some((trial, rt, jt)) => {
                *x = trial;
                r = rt;
                j = jt;
            }
            None if small_step => {
                // At rounding level already: no decrease is possible.
                return NewtonOutcome::Converged {
                    iterations: it,
                    residual: rn,
                };
            }
            None => return NewtonOutcome::Failed(NewtonFailure::Diverged),
        }
        if small_step {
            return NewtonOutcome::Converged {
                iterations: it + 1,
                residual: norm_inf(&r),
            };
        }
    }
    NewtonOutcome::Failed(NewtonFailure::IterationLimit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converges_on_a_smooth_system_and_names_failures() {
        // x^2 = 2, y = x y0 with y0 = 3
        let f = |x: &DVector<f64>| {
            (
                DVector::from_vec(vec![x[0] * x[0] - 2.0, x[1] - 3.0 * x[0]]),
                DMatrix::from_row_slice(2, 2, &[2.0 * x[0], 0.0, -3.0, 1.0]),
            )
        };
        let mut x = DVector::from_vec(vec![1.0, 0.0]);
        let out = solve(&mut x, f, &NewtonOptions::default());
        assert!(matches!(out, NewtonOutcome::Converged { .. }), "{out:?}");
        assert!((x[0] - std::f64::consts::SQRT_2).abs() < 1e-15);
        // singular: R(x) = (x0 + x1 - 1, 2 x0 + 2 x1 - 2)
        let g = |x: &DVector<f64>| {
            (
                DVector::from_vec(vec![x[0] + x[1] - 1.0, 2.0 * x[0] + 2.0 * x[1] - 5.0]),
                DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 2.0, 2.0]),
            )
        };
        let mut x = DVector::from_vec(vec![0.0, 0.0]);
        assert_eq!(
            solve(&mut x, g, &NewtonOptions::default()),
            NewtonOutcome::Failed(NewtonFailure::SingularJacobian)
        );
        // non-finite
        let h = |x: &DVector<f64>| {
            (
                DVector::from_vec(vec![f64::NAN * x[0]]),
                DMatrix::from_row_slice(1, 1, &[1.0]),
            )
        };
        let mut x = DVector::from_vec(vec![1.0]);
        assert_eq!(
            solve(&mut x, h, &NewtonOptions::default()),
            NewtonOutcome::Failed(NewtonFailure::NonFinite)
        );
    }
}
