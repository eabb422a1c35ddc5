//! The continuous nonholonomic dynamics derived from scene data, generic over the scalar
//! ([spec/04-dynamics.md](crate::spec::dynamics), eqs. (4.1)-(4.9)).
//!
//! Derivatives of the scene data with respect to q are taken by forward-mode
//! [`Dual`](crate::scalar::Dual) numbers in n directions, so scenes provide no derivative
//! by hand.

use crate::scalar::{Dual, Scalar};
use crate::scene::{Mat, Scene};

/// Scene data at one configuration, with first derivatives in q ([spec eq. (4.1)](crate::spec::dynamics)).
#[derive(Debug)]
pub struct Geometry<S> {
    /// Number of coordinates `n`.
    pub n: usize,
    /// Number of constraints `k`.
    pub k: usize,
    /// M(q), n x n.
    pub mass: Mat<S>,
    /// `dmass[j] = dM/dq_j`.
    pub dmass: Vec<Mat<S>>,
    /// dV/dq_j.
    pub dpot: Vec<S>,
    /// mu(q), k x n.
    pub mu: Mat<S>,
    /// `dmu[j] = dmu/dq_j`.
    pub dmu: Vec<Mat<S>>,
    /// E(q) as rows e_a, (n-k) x n.
    pub basis: Mat<S>,
    /// `dbasis[j] = dE/dq_j`.
    pub dbasis: Vec<Mat<S>>,
    /// The one-form A(q) of the Lagrangian's linear term and `dA[j][i] = dA_i/dq_j`;
    /// `None` for a natural Lagrangian ([spec eq. (3.1)](crate::spec::scenes)).
    pub one_form: Option<(Vec<S>, Mat<S>)>,
}

fn split<S: Scalar>(m: Mat<Dual<S>>, n: usize) -> (Mat<S>, Vec<Mat<S>>) {
    let val = m
        .iter()
        .map(|r| r.iter().map(|x| x.v.clone()).collect())
        .collect();
    let ders = (0..n)
        .map(|j| {
            m.iter()
                .map(|r| r.iter().map(|x| x.der(j)).collect())
                .collect()
        })
        .collect();
    (val, ders)
}

impl<S: Scalar> Geometry<S> {
    /// The geometry at `q`: one evaluation of the scene over duals in `n` directions ([spec eq.
    /// (4.1)](crate::spec::dynamics)).
    pub fn at<Sc: Scene>(sc: &Sc, q: &[S]) -> Self {
        let n = sc.dim();
        let qd: Vec<Dual<S>> = (0..n).map(|j| Dual::var(q[j].clone(), j, n)).collect();
        let (mass, dmass) = split(sc.mass(&qd), n);
        let (mu, dmu) = split(sc.constraints(&qd), n);
        let (basis, dbasis) = split(sc.basis(&qd), n);
        let pot = sc.potential(&qd);
        let dpot = (0..n).map(|j| pot.der(j)).collect();
        let one_form = sc.one_form(&qd).map(|a| {
            let (val, ders) = split(vec![a], n);
            let dadq = ders.into_iter().map(|mut d| d.remove(0)).collect();
            (val.into_iter().next().unwrap_or_default(), dadq)
        });
        Geometry {
            n,
            k: sc.n_constraints(),
            mass,
            dmass,
            dpot,
            mu,
            dmu,
            basis,
            dbasis,
            one_form,
        }
    }

    /// v = E(q)^T u = sum_a u_a e_a(q) ([spec eq. (4.2)](crate::spec::dynamics)).
    pub fn velocity(&self, u: &[S]) -> Vec<S> {
        (0..self.n)
            .map(|i| sum((0..u.len()).map(|a| u[a].clone() * self.basis[a][i].clone())))
            .collect()
    }

    /// w(q, v) = Mdot v - 1/2 d/dq (v^T M v) + grad V + (dA - dA^T) v: the
    /// Lagrange-d'Alembert equations read M a + w = mu^T lambda ([spec eq. (4.3)](crate::spec::dynamics)).
    pub fn bias(&self, v: &[S]) -> Vec<S> {
        let n = self.n;
        let natural = (0..n).map(|i| {
            let mdot_v = sum((0..n)
                .flat_map(|j| (0..n).map(move |l| (j, l)))
                .map(|(j, l)| self.dmass[j][i][l].clone() * v[j].clone() * v[l].clone()));
            let half_grad = sum((0..n)
                .flat_map(|l| (0..n).map(move |r| (l, r)))
                .map(|(l, r)| self.dmass[i][l][r].clone() * v[l].clone() * v[r].clone()))
                * S::cst(0.5);
            mdot_v - half_grad + self.dpot[i].clone()
        });
        match &self.one_form {
            None => natural.collect(),
            Some((_, da)) => natural
                .enumerate()
                .map(|(i, w)| {
                    // (dA_i/dq_j - dA_j/dq_i) v_j; the term j = i is zero and is left out.
                    w + sum((0..n)
                        .filter(|&j| j != i)
                        .map(|j| (da[j][i].clone() - da[i][j].clone()) * v[j].clone()))
                })
                .collect(),
        }
    }

    /// Derivative along v of a q-dependent matrix given its partials: sum_j v_j dX/dq_j.
    fn along(d: &[Mat<S>], v: &[S]) -> Mat<S> {
        let (r, c) = (d[0].len(), d[0].first().map_or(0, |x| x.len()));
        (0..r)
            .map(|a| {
                (0..c)
                    .map(|i| sum((0..v.len()).map(|j| v[j].clone() * d[j][a][i].clone())))
                    .collect()
            })
            .collect()
    }

    /// The reduced (quasi-velocity) equations on D ([spec eq. (4.4)](crate::spec::dynamics)):
    /// `E M E^T ud = -E (M Edot^T u + w(q, v))`, v = E^T u; returns (qd, ud).
    pub fn reduced_field(&self, u: &[S]) -> (Vec<S>, Vec<S>) {
        let n = self.n;
        let m = u.len();
        let v = self.velocity(u);
        let edot = Self::along(&self.dbasis, &v);
        let edot_u: Vec<S> = (0..n)
            .map(|i| sum((0..m).map(|a| u[a].clone() * edot[a][i].clone())))
            .collect();
        let m_edot_u = mat_vec(&self.mass, &edot_u);
        let w = self.bias(&v);
        let rhs: Vec<S> =
            (0..m)
                .map(|a| {
                    -sum((0..n)
                        .map(|i| self.basis[a][i].clone() * (m_edot_u[i].clone() + w[i].clone())))
                })
                .collect();
        let me: Vec<Vec<S>> = self.basis.iter().map(|e| mat_vec(&self.mass, e)).collect();
        let g: Mat<S> = (0..m)
            .map(|a| (0..m).map(|b| dot(&self.basis[a], &me[b])).collect())
            .collect();
        (v, solve_spd(g, rhs))
    }

    /// The Lagrange multipliers lambda = -C^{-1} Gamma_L(Phi) with C = mu M^{-1} mu^T
    /// (paper eq. (lambda-def); [spec eq. (4.5)](crate::spec::dynamics)), for v in D_q.
    pub fn multiplier(&self, v: &[S]) -> Vec<S> {
        let w = self.bias(v);
        // unconstrained acceleration a_L = -M^{-1} w
        let a_l: Vec<S> = solve_spd(self.mass.clone(), w)
            .into_iter()
            .map(|x| -x)
            .collect();
        let mudot = Self::along(&self.dmu, v);
        // Gamma_L(Phi^b) = mudot^b v + mu^b a_L
        let gamma: Vec<S> = (0..self.k)
            .map(|b| dot(&mudot[b], v) + dot(&self.mu[b], &a_l))
            .collect();
        let minv_mut: Vec<Vec<S>> = self
            .mu
            .iter()
            .map(|row| solve_spd(self.mass.clone(), row.clone()))
            .collect();
        let c: Mat<S> = (0..self.k)
            .map(|a| {
                (0..self.k)
                    .map(|b| dot(&self.mu[a], &minv_mut[b]))
                    .collect()
            })
            .collect();
        solve_spd(c, gamma).into_iter().map(|x| -x).collect()
    }

    /// The nonholonomic force F_nh = lambda_a mu^a (paper Remark 2.2; [spec eq. (4.6)](crate::spec::dynamics)).
    pub fn nh_force(&self, v: &[S]) -> Vec<S> {
        let lam = self.multiplier(v);
        (0..self.n)
            .map(|i| sum((0..self.k).map(|a| lam[a].clone() * self.mu[a][i].clone())))
            .collect()
    }

    /// The acceleration of the multiplier form: M a = F_nh - w ([spec eq. (4.7)](crate::spec::dynamics)).
    #[cfg(any(test, feature = "internals"))]
    pub fn acceleration(&self, v: &[S]) -> Vec<S> {
        let f = self.nh_force(v);
        let w = self.bias(v);
        let r: Vec<S> = f.into_iter().zip(w).map(|(a, b)| a - b).collect();
        solve_spd(self.mass.clone(), r)
    }

    /// Legendre map p = dL/dqd = M v + A ([spec eq. (4.8)](crate::spec::dynamics)).
    pub fn momentum(&self, v: &[S]) -> Vec<S> {
        let mv = mat_vec(&self.mass, v);
        match &self.one_form {
            None => mv,
            Some((a, _)) => mv.into_iter().zip(a).map(|(x, y)| x + y.clone()).collect(),
        }
    }

    /// `<A(q), e_a(q)>`, the D* part of the one-form (zero when there is none).
    pub fn one_form_d(&self) -> Option<Vec<S>> {
        self.one_form
            .as_ref()
            .map(|(a, _)| self.basis.iter().map(|e| dot(a, e)).collect())
    }

    /// The restricted Legendre map in D* coordinates: p_a = <M v + A, e_a(q)> ([spec eq. (4.8)](crate::spec::dynamics)).
    pub fn momentum_d(&self, v: &[S]) -> Vec<S> {
        let p = self.momentum(v);
        self.basis.iter().map(|e| dot(&p, e)).collect()
    }
}

/// Kinetic energy 1/2 v^T M(q) v.
fn kinetic<Sc: Scene, S: Scalar>(sc: &Sc, q: &[S], v: &[S]) -> S {
    dot(v, &mat_vec(&sc.mass(q), v)) * S::cst(0.5)
}

/// Energy E_L = 1/2 v^T M v + V(q) ([spec eq. (4.9)](crate::spec::dynamics)).
pub fn energy<Sc: Scene, S: Scalar>(sc: &Sc, q: &[S], v: &[S]) -> S {
    kinetic(sc, q, v) + sc.potential(q)
}

/// The Lagrangian L = 1/2 v^T M v + A(q) v - V(q) ([spec eq. (3.1)](crate::spec::scenes)).
pub fn lagrangian<Sc: Scene, S: Scalar>(sc: &Sc, q: &[S], v: &[S]) -> S {
    let l = kinetic(sc, q, v) - sc.potential(q);
    match sc.one_form(q) {
        None => l,
        Some(a) => l + dot(&a, v),
    }
}

/// The sum of the items, from 0, in order.
pub fn sum<S: Scalar>(it: impl Iterator<Item = S>) -> S {
    it.fold(S::zero(), |a, b| a + b)
}

/// `sum_i a_i b_i` (over the shorter of the two).
pub fn dot<S: Scalar>(a: &[S], b: &[S]) -> S {
    sum(a.iter().zip(b).map(|(x, y)| x.clone() * y.clone()))
}

/// `m v` for a matrix stored by rows.
pub fn mat_vec<S: Scalar>(m: &Mat<S>, v: &[S]) -> Vec<S> {
    m.iter().map(|r| dot(r, v)).collect()
}

/// Solve A x = b for symmetric positive definite A by Gaussian elimination without
/// pivoting (no comparisons, so it works over every scalar; SPD makes every pivot > 0).
/// Over intervals a pivot enclosure containing 0 gives an unbounded result, which the
/// caller detects as a failure ([spec eq. (4.10)](crate::spec::dynamics)).
pub fn solve_spd<S: Scalar>(mut a: Mat<S>, mut b: Vec<S>) -> Vec<S> {
    let n = b.len();
    for p in 0..n {
        for r in p + 1..n {
            let f = a[r][p].clone() / a[p][p].clone();
            let pivot_row = a[p].clone();
            for (x, y) in a[r].iter_mut().zip(pivot_row).skip(p + 1) {
                *x = x.clone() - f.clone() * y;
            }
            let t = f * b[p].clone();
            b[r] = b[r].clone() - t;
        }
    }
    let mut x: Vec<S> = vec![S::zero(); n];
    for p in (0..n).rev() {
        let s = sum((p + 1..n).map(|c| a[p][c].clone() * x[c].clone()));
        x[p] = (b[p].clone() - s) / a[p][p].clone();
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Knife, Particle};

    #[test]
    fn particle_reduced_field_is_the_papers() {
        // paper Example 2.1: xdd = -y xd yd/(1+y^2), ydd = 0, with u = (xd, yd)
        let (q, u) = ([0.3, -1.7, 2.0], [0.8, -0.4]);
        let g = Geometry::at(&Particle, &q);
        let (qd, ud) = g.reduced_field(&u);
        assert_eq!(qd, vec![0.8, -0.4, -1.7 * 0.8]);
        let xdd = -(-1.7) * 0.8 * -0.4 / (1.0 + 1.7 * 1.7);
        assert!((ud[0] - xdd).abs() < 1e-15);
        assert_eq!(ud[1], 0.0);
    }

    /// A planar charge in a uniform magnetic field B: L = 1/2 |v|^2 + (B/2)(x yd - y xd),
    /// constraint zd = 0. The one-form is not closed (dA = B dx ^ dy): the Lorentz force
    /// gives xdd = B yd, ydd = -B xd ([spec eq. (4.3)](crate::spec::dynamics)), and p = v + A (eq. (4.8)).
    struct Charge(f64);
    impl Scene for Charge {
        fn name(&self) -> String {
            "charge".into()
        }
        fn dim(&self) -> usize {
            3
        }
        fn constraints<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
            vec![vec![S::zero(), S::zero(), S::one()]]
        }
        fn basis<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
            vec![
                vec![S::one(), S::zero(), S::zero()],
                vec![S::zero(), S::one(), S::zero()],
            ]
        }
        fn one_form<S: Scalar>(&self, q: &[S]) -> Option<Vec<S>> {
            let h = S::cst(self.0 / 2.0);
            Some(vec![
                -(h.clone() * q[1].clone()),
                h * q[0].clone(),
                S::zero(),
            ])
        }
    }

    #[test]
    fn a_one_form_gives_the_lorentz_force_and_shifts_the_momentum() {
        let b = 1.5;
        let (q, u) = ([0.3, -0.8, 0.2], [0.7, -0.4]);
        let g = Geometry::at(&Charge(b), &q);
        let (v, ud) = g.reduced_field(&u);
        assert_eq!(ud, vec![b * u[1], -b * u[0]]);
        assert_eq!(g.acceleration(&v), vec![b * u[1], -b * u[0], 0.0]);
        let p = g.momentum(&v);
        assert_eq!(p, vec![u[0] - b / 2.0 * q[1], u[1] + b / 2.0 * q[0], 0.0]);
        assert_eq!(g.momentum_d(&v), vec![p[0], p[1]]);
        // H|D*(q, p_D) = E_L: the one-form is subtracted before the kinetic energy
        let e = crate::schemes::hamiltonian_d(&Charge(b), &q, &g.momentum_d(&v));
        assert!((e - 0.5 * (u[0] * u[0] + u[1] * u[1])).abs() < 1e-15);
        // L = 1/2 |v|^2 + A v
        let l = lagrangian(&Charge(b), &q, &v);
        let want = 0.5 * (0.49 + 0.16) + b / 2.0 * (q[0] * v[1] - q[1] * v[0]);
        assert!((l - want).abs() < 1e-15);
    }

    /// A closed one-form (the non-reversible contact oscillator) changes neither the
    /// reduced field nor the multipliers, bitwise.
    #[test]
    fn a_closed_one_form_leaves_the_motion_unchanged() {
        use crate::scene::ContactOscillator;
        let plain = ContactOscillator {
            eps: 0.3,
            delta: None,
        };
        let nr = ContactOscillator {
            eps: 0.3,
            delta: Some(0.8),
        };
        let (q, u) = ([0.4, -0.7, 1.1], [0.2, -0.9]);
        let (g0, g1) = (Geometry::at(&plain, &q), Geometry::at(&nr, &q));
        assert_eq!(g0.reduced_field(&u), g1.reduced_field(&u));
        let v = g0.velocity(&u);
        assert_eq!(g0.multiplier(&v), g1.multiplier(&v));
        let (p0, p1) = (g0.momentum_d(&v), g1.momentum_d(&v));
        assert_eq!(p0[0], p1[0]);
        assert_eq!(p1[1], p0[1] + 0.8 * q[2].sin());
    }

    #[test]
    fn multiplier_form_agrees_with_reduced_form() {
        let (q, u) = ([0.3, -1.2, 0.9], [1.1, -0.6]);
        let g = Geometry::at(&Knife, &q);
        let (v, ud) = g.reduced_field(&u);
        let a = g.acceleration(&v);
        // a = d/dt (E^T u) = Edot^T u + E^T ud
        let h = 1e-6;
        let qp: Vec<f64> = (0..3).map(|i| q[i] + h * v[i]).collect();
        let up: Vec<f64> = (0..2).map(|i| u[i] + h * ud[i]).collect();
        let vp = Geometry::at(&Knife, &qp).velocity(&up);
        for i in 0..3 {
            assert!((a[i] - (vp[i] - v[i]) / h).abs() < 1e-5, "{i}: {a:?}");
        }
        // the acceleration keeps the constraint: d/dt mu(q) v = 0
        let c0 = dot(&g.mu[0], &v);
        let c1 = dot(&Geometry::at(&Knife, &qp).mu[0], &vp);
        assert!(c0.abs() < 1e-15 && c1.abs() < 1e-11);
    }
}
