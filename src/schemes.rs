//! The floating-point schemes DLA and MLA of the contract, generic over the scene
//! ([spec/07-schemes.md](crate::spec::schemes), eqs. (7.1)-(7.7)). The discrete equations are written once over
//! `S: Scalar`, recorded as tapes with their Jacobians (forward-mode duals), and replayed
//! over f64 inside a damped Newton solver with a typed result.

use crate::newton;

use crate::dynamics::{lagrangian, solve_spd, Geometry};
use crate::model::Model;
use crate::scalar::{Dual, Scalar};
use crate::scene::Scene;
use crate::tape::{Tape, Tracer};
use crate::Error;
use nalgebra::{DMatrix, DVector};
pub use newton::{NewtonFailure, NewtonOptions, NewtonOutcome};

/// Which scheme: DLA (Cortes–Martinez, no forces) or MLA (the paper's modified
/// Lagrange–d'Alembert, with the discrete nonholonomic forces).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SchemeKind {
    /// DLA (Cortes–Martinez): the equations (7.4) without discrete forces.
    Dla,
    /// MLA (the paper's): (7.4) with the discrete forces `F^± = (h/2) F_nh` of (7.2).
    Mla,
}

impl SchemeKind {
    /// The name the command line and the protocol use (`"dla"`, `"mla"`); `parse` reads it.
    pub fn name(self) -> &'static str {
        match self {
            SchemeKind::Dla => "dla",
            SchemeKind::Mla => "mla",
        }
    }
}

impl std::str::FromStr for SchemeKind {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "dla" => Ok(SchemeKind::Dla),
            "mla" => Ok(SchemeKind::Mla),
            _ => Err(Error::input(format!(
                "unknown scheme `{s}` (known: mla, dla)"
            ))),
        }
    }
}

/// `(D1 L_d, D2 L_d)` of the midpoint discrete Lagrangian
/// `L_d(q0, q1) = h L((q0 + q1)/2, (q1 - q0)/h)` ([spec eq. (7.1)](crate::spec::schemes)).
pub fn ld_gradients<Sc: Scene, S: Scalar>(sc: &Sc, q0: &[S], q1: &[S], h: &S) -> (Vec<S>, Vec<S>) {
    let n = q0.len();
    let half = S::cst(0.5);
    let mid: Vec<Dual<S>> = (0..n)
        .map(|i| Dual::var((q0[i].clone() + q1[i].clone()) * half.clone(), i, 2 * n))
        .collect();
    let vel: Vec<Dual<S>> = (0..n)
        .map(|i| Dual::var((q1[i].clone() - q0[i].clone()) / h.clone(), n + i, 2 * n))
        .collect();
    let l = lagrangian(sc, &mid, &vel);
    let d1 = (0..n)
        .map(|i| h.clone() * half.clone() * l.der(i) - l.der(n + i))
        .collect();
    let d2 = (0..n)
        .map(|i| h.clone() * half.clone() * l.der(i) + l.der(n + i))
        .collect();
    (d1, d2)
}

/// The discrete force `F^+ = F^- = (h/2) F_nh((q0+q1)/2, (q1-q0)/h)` of MLA ([spec eq. (7.2)](crate::spec::schemes));
/// zero for DLA.
pub fn discrete_force<Sc: Scene, S: Scalar>(
    sc: &Sc,
    kind: SchemeKind,
    q0: &[S],
    q1: &[S],
    h: &S,
) -> Vec<S> {
    let n = q0.len();
    if kind == SchemeKind::Dla {
        return vec![S::zero(); n];
    }
    let half = S::cst(0.5);
    let mid: Vec<S> = (0..n)
        .map(|i| (q0[i].clone() + q1[i].clone()) * half.clone())
        .collect();
    let vel: Vec<S> = (0..n)
        .map(|i| (q1[i].clone() - q0[i].clone()) / h.clone())
        .collect();
    Geometry::at(sc, &mid)
        .nh_force(&vel)
        .into_iter()
        .map(|f| f * h.clone() * half.clone())
        .collect()
}

/// The discrete constraint `mu((q0+q1)/2) (q1 - q0)` of M_h^d ([spec eq. (7.3)](crate::spec::schemes)).
pub fn discrete_constraint<Sc: Scene, S: Scalar>(sc: &Sc, q0: &[S], q1: &[S]) -> Vec<S> {
    let n = q0.len();
    let mid: Vec<S> = (0..n)
        .map(|i| (q0[i].clone() + q1[i].clone()) * S::cst(0.5))
        .collect();
    sc.constraints(&mid)
        .iter()
        .map(|row| {
            (0..n).fold(S::zero(), |a, i| {
                a + row[i].clone() * (q1[i].clone() - q0[i].clone())
            })
        })
        .collect()
}

/// `(F^- l_d, F^+ l_d)` in the basis of D ([spec eq. (7.5)](crate::spec::schemes)):
/// `p^-_a = -<D1 L_d + F^-, e_a(q0)>`, `p^+_a = <D2 L_d + F^+, e_a(q1)>`.
pub fn legendre<Sc: Scene, S: Scalar>(
    sc: &Sc,
    kind: SchemeKind,
    q0: &[S],
    q1: &[S],
    h: &S,
) -> (Vec<S>, Vec<S>) {
    let (d1, d2) = ld_gradients(sc, q0, q1, h);
    let f = discrete_force(sc, kind, q0, q1, h);
    let pair = |e: Vec<Vec<S>>, g: &[S], sign: S| -> Vec<S> {
        e.iter()
            .map(|ea| {
                sign.clone()
                    * (0..g.len()).fold(S::zero(), |a, i| {
                        a + ea[i].clone() * (g[i].clone() + f[i].clone())
                    })
            })
            .collect()
    };
    (
        pair(sc.basis(q0), &d1, -S::one()),
        pair(sc.basis(q1), &d2, S::one()),
    )
}

/// The residual of one step ([spec eq. (7.4)](crate::spec::schemes)): the projection onto D*_{q_k} of
/// `D2 L_d(q_{k-1}, q_k) + D1 L_d(q_k, q_{k+1}) + F^+(q_{k-1}, q_k) + F^-(q_k, q_{k+1})`,
/// i.e. `p^+(q_{k-1}, q_k) - p^-(q_k, q_{k+1})`, followed by the discrete constraint at
/// `(q_k, q_{k+1})`.
pub fn step_residual<Sc: Scene, S: Scalar>(
    sc: &Sc,
    kind: SchemeKind,
    qm: &[S],
    qk: &[S],
    qp: &[S],
    h: &S,
) -> Vec<S> {
    let (_, p_plus) = legendre(sc, kind, qm, qk, h);
    let (p_minus, _) = legendre(sc, kind, qk, qp, h);
    p_plus
        .into_iter()
        .zip(p_minus)
        .map(|(a, b)| a - b)
        .chain(discrete_constraint(sc, qk, qp))
        .collect()
}

/// `H|_{D*}(q, p) = 1/2 p'^T (E M E^T)^{-1} p' + V(q)`, `p' = p - <A, e>` ([spec eq. (7.7)](crate::spec::schemes)).
pub fn hamiltonian_d<Sc: Scene, S: Scalar>(sc: &Sc, q: &[S], p: &[S]) -> S {
    let g = Geometry::at(sc, q);
    let p: Vec<S> = match g.one_form_d() {
        None => p.to_vec(),
        Some(a) => p.iter().zip(a).map(|(x, y)| x.clone() - y).collect(),
    };
    let p = &p[..];
    let m = p.len();
    let me: Vec<Vec<S>> = g
        .basis
        .iter()
        .map(|e| crate::dynamics::mat_vec(&g.mass, e))
        .collect();
    let gram: Vec<Vec<S>> = (0..m)
        .map(|a| {
            (0..m)
                .map(|b| crate::dynamics::dot(&g.basis[a], &me[b]))
                .collect()
        })
        .collect();
    let u = solve_spd(gram, p.to_vec());
    crate::dynamics::dot(&u, p) * S::cst(0.5) + sc.potential(q)
}

/// Record `f(fixed, unknown)` and its Jacobian in `unknown` as one tape:
/// outputs `f` then `df/dunknown` row-major.
fn record_with_jacobian(
    n_fixed: usize,
    n_unknown: usize,
    f: impl Fn(&[Dual<Tracer>], &[Dual<Tracer>]) -> Vec<Dual<Tracer>>,
) -> Tape {
    Tape::record(n_fixed + n_unknown, |x| {
        let fixed: Vec<Dual<Tracer>> = x[..n_fixed].iter().map(|t| Dual::new(*t, vec![])).collect();
        let unknown: Vec<Dual<Tracer>> = (0..n_unknown)
            .map(|j| Dual::var(x[n_fixed + j], j, n_unknown))
            .collect();
        let r = f(&fixed, &unknown);
        let mut out: Vec<Tracer> = r.iter().map(|y| y.v).collect();
        for y in &r {
            out.extend((0..n_unknown).map(|j| y.der(j)));
        }
        out
    })
}

/// A scheme compiled for one scene ([spec eq. (7.8)](crate::spec::schemes)).
pub struct Scheme {
    /// Which scheme was compiled.
    pub kind: SchemeKind,
    /// Number of coordinates `n` of the scene.
    pub n: usize,
    /// Number of constraints `k` of the scene.
    pub k: usize,
    /// (q_{k-1}, q_k, h, q_{k+1}) -> (R, dR/dq_{k+1}).
    residual: Tape,
    /// (q0, q1, s) -> (C(s), dC/ds) with C(s) = mu(mid)(q1 + N(q1) s - q0).
    projection: Tape,
    /// (q0, q1, h) -> (p^-, p^+).
    legendre: Tape,
    /// (q, p) -> H|_{D*}.
    hamiltonian: Tape,
    /// q -> mu(q), k x n row-major.
    normals: Tape,
}

/// A summary: the kind and the sizes (the compiled tapes are long).
impl std::fmt::Debug for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scheme")
            .field("kind", &self.kind)
            .field("n", &self.n)
            .field("k", &self.k)
            .finish_non_exhaustive()
    }
}

/// A float trajectory of a scheme, with what the user may want to look at. Serialized
/// (feature `serde`) as the `integrate` answer of the JSON protocol.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct Trajectory {
    /// `q_0 .. q_N`: `q_0` as given, `q_1` moved onto M_h^d ([spec eq. (7.3)](crate::spec::schemes)), then the steps
    /// (7.4).
    pub q: Vec<Vec<f64>>,
    /// `p_k` in D* coordinates: `F^- l_d(q_0, q_1)` at k = 0, `F^+ l_d(q_{k-1}, q_k)` after.
    pub p: Vec<Vec<f64>>,
    /// `H|_{D*}(q_k, p_k)`.
    pub energy: Vec<f64>,
    /// Newton iterations of each step (the projection of q_1 first); serialized as
    /// `newton_iterations`.
    #[cfg_attr(feature = "serde", serde(rename = "newton_iterations"))]
    pub iterations: Vec<usize>,
    /// Largest final residual `|R|_inf` over all Newton solves.
    pub max_residual: f64,
}

/// One row of [`Scheme::integrate_each`].
#[derive(Clone, Copy, Debug)]
pub struct Row<'a> {
    /// The index `k` of the row.
    pub k: usize,
    /// `q_k` (for `k = 1`, after the projection onto M_h^d).
    pub q: &'a [f64],
    /// `p_k` in D* coordinates, as in [`Trajectory::p`]; `None` when `steps = 0`.
    pub p: Option<&'a [f64]>,
    /// `H|_{D*}(q_k, p_k)` ([spec eq. (7.7)](crate::spec::schemes)); `None` when `steps = 0`.
    pub energy: Option<f64>,
    /// Newton iterations of the solve that gave `q` (the projection of q_1 for k = 1).
    pub iterations: Option<usize>,
}

/// A scheme that could not go on: which step and why.
#[derive(Clone, Debug, PartialEq)]
pub enum SchemeError {
    /// Malformed input (sizes, non-finite numbers, `h <= 0`): [`Error::Input`].
    Input(String),
    /// Newton failed at step `step` (0 = projecting q_1 onto M_h^d).
    Newton {
        /// The index `k` of the solve that failed (`q_{k+1}` was sought; 0: the projection).
        step: usize,
        /// Why Newton stopped ([spec eq. (7.6)](crate::spec::schemes)).
        failure: NewtonFailure,
    },
    /// The states are finite but the momentum or energy at `step` is not (overflow).
    NonFinite {
        /// The index `k` of the row whose `p_k` or `H|_{D*}` is not finite.
        step: usize,
    },
}

impl std::fmt::Display for SchemeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SchemeError::Input(m) => f.write_str(m),
            SchemeError::Newton { step, failure } => {
                write!(f, "Newton solver failed at step {step}: {failure}")
            }
            SchemeError::NonFinite { step } => {
                write!(f, "momentum or energy not finite at step {step} (overflow)")
            }
        }
    }
}

impl std::error::Error for SchemeError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SchemeError::Newton { failure, .. } => Some(failure),
            _ => None,
        }
    }
}

/// An input error keeps its message; a Newton failure is a failed proof
/// ([`crate::Reason::NoProof`]); a non-finite momentum or energy is
/// [`crate::Reason::Unbounded`]. The message is this error's `Display`.
impl From<SchemeError> for Error {
    fn from(e: SchemeError) -> Error {
        let message = e.to_string();
        match e {
            SchemeError::Input(_) => Error::input(message),
            SchemeError::Newton { .. } => Error::uncertified(message),
            SchemeError::NonFinite { .. } => Error::refused(crate::Reason::Unbounded, message),
        }
    }
}

impl Scheme {
    /// Record the scheme for a compiled scene ([spec eq. (7.8)](crate::spec::schemes)): the residual of (7.4) and
    /// the projection (7.3) with their Jacobians, the Legendre transforms (7.5) and
    /// `H|_{D*}` (7.7).
    pub fn new(model: &Model, kind: SchemeKind) -> Scheme {
        let (n, k) = (model.n, model.k);
        let s = &*model.scene;
        let residual = record_with_jacobian(2 * n + 1, n, |f, u| {
            step_residual(s, kind, &f[..n], &f[n..2 * n], u, &f[2 * n])
        });
        let projection = record_with_jacobian(2 * n, k, |f, sv| {
            let (q0, q1) = (&f[..n], &f[n..]);
            let mu = s.constraints(q1);
            let moved: Vec<_> = (0..n)
                .map(|i| (0..k).fold(q1[i].clone(), |a, b| a + mu[b][i].clone() * sv[b].clone()))
                .collect();
            discrete_constraint(s, q0, &moved)
        });
        let legendre = Tape::record(2 * n + 1, |x| {
            let (a, b) = legendre(s, kind, &x[..n], &x[n..2 * n], &x[2 * n]);
            a.into_iter().chain(b).collect()
        });
        let hamiltonian = Tape::record(2 * n - k, |x| vec![hamiltonian_d(s, &x[..n], &x[n..])]);
        Scheme {
            kind,
            n,
            k,
            residual,
            projection,
            legendre,
            hamiltonian,
            normals: model.constraints.clone(),
        }
    }

    fn split(out: Vec<f64>, rows: usize, cols: usize) -> (DVector<f64>, DMatrix<f64>) {
        let r = DVector::from_column_slice(&out[..rows]);
        let j = DMatrix::from_row_slice(rows, cols, &out[rows..rows + rows * cols]);
        (r, j)
    }

    /// Move `q1` along `N(q1)` onto M_h^d at `q0` ([spec eq. (7.3)](crate::spec::schemes)).
    pub fn project(
        &self,
        q0: &[f64],
        q1: &[f64],
        opts: &NewtonOptions,
    ) -> Result<(Vec<f64>, usize, f64), NewtonFailure> {
        let (n, k) = (self.n, self.k);
        let mut s = DVector::zeros(k);
        let f = |s: &DVector<f64>| {
            let x: Vec<f64> = q0.iter().chain(q1).chain(s.iter()).copied().collect();
            Self::split(self.projection.eval::<f64>(&x), k, k)
        };
        // The residual mu(m) (q1' - q0) can be evaluated only to about eps |mu| |q|: stop
        // there (spec eq. (7.6)), not at a step relative to |s|.
        let mu1 = self.normals.eval::<f64>(q1);
        let size = q0.iter().chain(q1).fold(1.0f64, |a, x| a.max(x.abs()));
        let mu_size = mu1.iter().fold(0.0f64, |a, x| a + x.abs());
        let o = NewtonOptions {
            tol: opts.tol.max(16.0 * f64::EPSILON * size * mu_size),
            ..opts.clone()
        };
        match newton::solve(&mut s, f, &o) {
            NewtonOutcome::Converged {
                iterations,
                residual,
            } => {
                let mu = mu1;
                let moved = (0..n)
                    .map(|i| (0..k).fold(q1[i], |a, b| a + mu[b * n + i] * s[b]))
                    .collect();
                Ok((moved, iterations, residual))
            }
            NewtonOutcome::Failed(e) => Err(e),
        }
    }

    /// One step: `q_{k+1}` from `(q_{k-1}, q_k)` ([spec eq. (7.4)](crate::spec::schemes)), with the Newton iterations
    /// and the final residual `|R|_inf`. The guess is `2 q_k - q_{k-1}`.
    ///
    /// # Example
    /// ```
    /// use dalembert::schemes::{NewtonOptions, Scheme, SchemeKind};
    /// use dalembert::{AnyScene, Model};
    /// let model = Model::new(&AnyScene::new("particle", &[])?)?;
    /// let mla = Scheme::new(&model, SchemeKind::Mla);
    /// let (q0, h, opts) = ([0.0; 3], 0.25, NewtonOptions::default());
    /// // q_1 moved onto M_h^d first (spec eq. (7.3)), then one step
    /// let (q1, _, _) = mla.project(&q0, &[0.2, 0.2, 0.0], &opts).expect("projection");
    /// let (q2, _iterations, residual) = mla.step(&q0, &q1, h, &opts).expect("step");
    /// assert!(residual < 1e-12);
    /// // (q_1, q_2) is on M_h^d: mu((q_1 + q_2)/2)(q_2 - q_1) = 0, mu = (-y, 0, 1)
    /// let c = -(q1[1] + q2[1]) / 2.0 * (q2[0] - q1[0]) + (q2[2] - q1[2]);
    /// assert!(c.abs() < 1e-12);
    /// # Ok::<(), dalembert::Error>(())
    /// ```
    pub fn step(
        &self,
        qm: &[f64],
        qk: &[f64],
        h: f64,
        opts: &NewtonOptions,
    ) -> Result<(Vec<f64>, usize, f64), NewtonFailure> {
        let n = self.n;
        let mut x = DVector::from_fn(n, |i, _| 2.0 * qk[i] - qm[i]);
        let f = |u: &DVector<f64>| {
            let inp: Vec<f64> = qm
                .iter()
                .chain(qk)
                .copied()
                .chain(std::iter::once(h))
                .chain(u.iter().copied())
                .collect();
            Self::split(self.residual.eval::<f64>(&inp), n, n)
        };
        match newton::solve(&mut x, f, opts) {
            NewtonOutcome::Converged {
                iterations,
                residual,
            } => Ok((x.iter().copied().collect(), iterations, residual)),
            NewtonOutcome::Failed(e) => Err(e),
        }
    }

    /// `(F^- l_d(q0, q1), F^+ l_d(q0, q1))` in D* coordinates.
    pub fn legendre(&self, q0: &[f64], q1: &[f64], h: f64) -> (Vec<f64>, Vec<f64>) {
        let m = self.n - self.k;
        let x: Vec<f64> = q0
            .iter()
            .chain(q1)
            .copied()
            .chain(std::iter::once(h))
            .collect();
        let out = self.legendre.eval::<f64>(&x);
        (out[..m].to_vec(), out[m..].to_vec())
    }

    /// `H|_{D*}(q, p)`.
    pub fn energy(&self, q: &[f64], p: &[f64]) -> f64 {
        let x: Vec<f64> = q.iter().chain(p).copied().collect();
        self.hamiltonian.eval::<f64>(&x)[0]
    }

    /// [`Scheme::integrate`] one row at a time, in memory independent of `steps`: `row` is
    /// called for k = 0..=steps in order with q_k, p_k and H_k (no p_0, H_0 when steps = 0)
    /// and the Newton iterations of the solve that gave q_k (k >= 1). The rows are those of
    /// [`Scheme::integrate`]; an error of `row` stops the integration and is returned. Returns
    /// the largest final Newton residual.
    pub fn integrate_each<E: From<SchemeError>>(
        &self,
        q0: &[f64],
        q1: &[f64],
        h: f64,
        steps: usize,
        opts: &NewtonOptions,
        mut row: impl FnMut(Row) -> Result<(), E>,
    ) -> Result<f64, E> {
        let n = self.n;
        if q0.len() != n || q1.len() != n {
            return Err(SchemeError::Input(format!("q0 and q1 need {n} components")).into());
        }
        if !q0.iter().chain(q1).all(|x| x.is_finite()) {
            return Err(SchemeError::Input("non-finite number in q0 or q1".into()).into());
        }
        if !h.is_finite() || h <= 0.0 {
            return Err(SchemeError::Input(format!("h must be finite and > 0 (got {h})")).into());
        }
        let fail = |step| move |failure| SchemeError::Newton { step, failure };
        if steps == 0 {
            row(Row {
                k: 0,
                q: q0,
                p: None,
                energy: None,
                iterations: None,
            })?;
            return Ok(0.0);
        }
        let (mut cur, mut it, mut max_residual) = self.project(q0, q1, opts).map_err(fail(0))?;
        let mut prev = q0.to_vec();
        let checked = |k: usize, q: &[f64], p: Vec<f64>| {
            let e = self.energy(q, &p);
            if e.is_finite() && p.iter().all(|x| x.is_finite()) {
                Ok((p, e))
            } else {
                Err(SchemeError::NonFinite { step: k })
            }
        };
        let (p0, e0) = checked(0, q0, self.legendre(q0, &cur, h).0)?;
        row(Row {
            k: 0,
            q: q0,
            p: Some(&p0),
            energy: Some(e0),
            iterations: None,
        })?;
        for k in 1..=steps {
            let (pk, ek) = checked(k, &cur, self.legendre(&prev, &cur, h).1)?;
            row(Row {
                k,
                q: &cur,
                p: Some(&pk),
                energy: Some(ek),
                iterations: Some(it),
            })?;
            if k < steps {
                let (next, i, res) = self.step(&prev, &cur, h, opts).map_err(fail(k))?;
                max_residual = max_residual.max(res);
                it = i;
                prev = std::mem::replace(&mut cur, next);
            }
        }
        Ok(max_residual)
    }

    /// The sequence `q_0 .. q_N` (contract command 4).
    pub fn integrate(
        &self,
        q0: &[f64],
        q1: &[f64],
        h: f64,
        steps: usize,
        opts: &NewtonOptions,
    ) -> Result<Trajectory, SchemeError> {
        let n = self.n;
        if q0.len() != n || q1.len() != n {
            return Err(SchemeError::Input(format!("q0 and q1 need {n} components")));
        }
        if !q0.iter().chain(q1).all(|x| x.is_finite()) {
            return Err(SchemeError::Input("non-finite number in q0 or q1".into()));
        }
        if !h.is_finite() || h <= 0.0 {
            return Err(SchemeError::Input(format!(
                "h must be finite and > 0 (got {h})"
            )));
        }
        let fail = |step| move |failure| SchemeError::Newton { step, failure };
        let mut q = vec![q0.to_vec()];
        let mut iterations = Vec::with_capacity(steps);
        let mut max_residual: f64 = 0.0;
        if steps >= 1 {
            let (q1p, it, res) = self.project(q0, q1, opts).map_err(fail(0))?;
            q.push(q1p);
            iterations.push(it);
            max_residual = max_residual.max(res);
        }
        for k in 1..steps {
            let (next, it, res) = self.step(&q[k - 1], &q[k], h, opts).map_err(fail(k))?;
            q.push(next);
            iterations.push(it);
            max_residual = max_residual.max(res);
        }
        let mut p = Vec::with_capacity(q.len());
        let mut energy = Vec::with_capacity(q.len());
        for k in 0..q.len() {
            let pk = if k == 0 {
                if q.len() < 2 {
                    break;
                }
                self.legendre(&q[0], &q[1], h).0
            } else {
                self.legendre(&q[k - 1], &q[k], h).1
            };
            let ek = self.energy(&q[k], &pk);
            if !ek.is_finite() || !pk.iter().all(|x| x.is_finite()) {
                return Err(SchemeError::NonFinite { step: k });
            }
            energy.push(ek);
            p.push(pk);
        }
        Ok(Trajectory {
            q,
            p,
            energy,
            iterations,
            max_residual,
        })
    }
}
