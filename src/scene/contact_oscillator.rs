//! The nonholonomic (contact) oscillator of McLachlan and Perlmutter (J. Nonlinear Sci. 16,
//! 2006, sec. 5.2) and its non-reversible variant ([spec eqs. (3.8)-(3.9)](crate::spec::scenes)).
//! Coordinates q = (x, y, z); constraint dx + y dz = 0.
//!
//! The variant `contact-oscillator-nr` is the one of Verdier's `odelab` library (class
//! `NonReversibleContactOscillator`, by an author of Modin and Verdier, "What makes
//! nonholonomic integrators work?", Numer. Math. 145, 2020): the Hamiltonian becomes
//! `H(q, p) = 1/2 (|q|^2 + eps x^2 z^2 + |p + grad S|^2)` with `S = delta cos z`, i.e. the
//! Lagrangian gains the term `-grad S . qd = delta sin(z) zd`, the one-form
//! `A = (0, 0, delta sin z)`. `A` is closed, so the continuous motion (q(t), qd(t)) is the
//! oscillator's; what changes is the momentum `p = qd + A` and the Lagrangian the discrete
//! schemes sample, which is no longer even in qd (not reversible for `(q, qd) -> (q, -qd)`).

use super::{identity, AnyScene, Mat, ParamInfo, Params, Scene, SceneInfo};
use crate::scalar::Scalar;
use crate::Error;

/// L = 1/2 |qd|^2 + A(q) qd - 1/2 (|q|^2 + eps x^2 z^2), A = (0, 0, delta sin z) for the
/// non-reversible variant (`delta = Some(..)`), A = 0 for the oscillator (`delta = None`);
/// constraint xd + y zd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOscillator {
    /// The coefficient `eps` of the coupling `eps x^2 z^2 / 2` in V (any real).
    pub eps: f64,
    /// `Some(delta)`: the non-reversible variant, with S = delta cos z.
    pub delta: Option<f64>,
}

const EPS: ParamInfo = ParamInfo {
    name: "eps",
    default: 0.3,
    description: "coefficient of the quartic coupling eps x^2 z^2 / 2 (any real)",
};

const INVARIANTS: &[&str] = &[
    "E = 1/2 (xd^2 + yd^2 + zd^2 + x^2 + y^2 + z^2 + eps x^2 z^2)",
    "E_y = 1/2 (y^2 + yd^2)",
    "E - E_y = 1/2 (x^2 + (1 + eps x^2) z^2 + (1 + y^2) zd^2)",
];

/// `contact-oscillator` ([spec eq. (3.8)](crate::spec::scenes)).
pub const INFO: SceneInfo = SceneInfo {
    name: "contact-oscillator",
    summary: "the nonholonomic contact oscillator (McLachlan and Perlmutter 2006, sec. 5.2)",
    coordinates: &["x", "y", "z"],
    velocities: &["yd", "zd"],
    params: &[EPS],
    n: 3,
    k: 1,
    lagrangian: "L = 1/2 (xd^2 + yd^2 + zd^2) - 1/2 (x^2 + y^2 + z^2 + eps x^2 z^2)",
    constraints: &["mu = (1, 0, y)   [xd + y zd = 0]"],
    basis: &["e1 = d/dy = (0, 1, 0)", "e2 = -y d/dx + d/dz = (-y, 0, 1)"],
    invariants: INVARIANTS,
    build: build_plain,
};

/// `contact-oscillator-nr` ([spec eq. (3.9)](crate::spec::scenes)).
pub const NR_INFO: SceneInfo = SceneInfo {
    name: "contact-oscillator-nr",
    summary: "the contact oscillator with H = 1/2(|q|^2 + eps x^2 z^2 + |p + grad S|^2), \
              S = delta cos z: same motion, Lagrangian not even in qd (odelab's \
              NonReversibleContactOscillator; Modin and Verdier 2020)",
    coordinates: &["x", "y", "z"],
    velocities: &["yd", "zd"],
    params: &[
        EPS,
        ParamInfo {
            name: "delta",
            default: 1.0,
            description: "amplitude of S = delta cos z (any real; 0 gives the oscillator's motion and Lagrangian)",
        },
    ],
    n: 3,
    k: 1,
    lagrangian: "L = 1/2 (xd^2 + yd^2 + zd^2) + delta sin(z) zd - 1/2 (x^2 + y^2 + z^2 + eps x^2 z^2)",
    constraints: &["mu = (1, 0, y)   [xd + y zd = 0]"],
    basis: &["e1 = d/dy = (0, 1, 0)", "e2 = -y d/dx + d/dz = (-y, 0, 1)"],
    invariants: INVARIANTS,
    build: build_nr,
};

fn build_plain(p: &Params) -> Result<AnyScene, Error> {
    Ok(AnyScene::ContactOscillator(ContactOscillator {
        eps: p.get("eps")?,
        delta: None,
    }))
}

fn build_nr(p: &Params) -> Result<AnyScene, Error> {
    Ok(AnyScene::ContactOscillator(ContactOscillator {
        eps: p.get("eps")?,
        delta: Some(p.get("delta")?),
    }))
}

impl ContactOscillator {
    /// The oscillator's or the variant's declaration.
    pub fn info(&self) -> &'static SceneInfo {
        match self.delta {
            None => &INFO,
            Some(_) => &NR_INFO,
        }
    }
}

impl Scene for ContactOscillator {
    fn name(&self) -> String {
        self.info().name.to_string()
    }
    fn dim(&self) -> usize {
        3
    }
    fn n_constraints(&self) -> usize {
        1
    }
    fn description(&self) -> super::Description {
        self.info().description()
    }
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        identity(3)
    }
    /// V = 1/2 (x^2 + y^2 + z^2 + eps x^2 z^2).
    fn potential<S: Scalar>(&self, q: &[S]) -> S {
        let xz = q[0].clone() * q[2].clone();
        (q[0].sqr() + q[1].sqr() + q[2].sqr() + S::cst(self.eps) * xz.sqr()) * S::cst(0.5)
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![vec![S::one(), S::zero(), q[1].clone()]]
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![
            vec![S::zero(), S::one(), S::zero()],
            vec![-q[1].clone(), S::zero(), S::one()],
        ]
    }
    /// A = -grad S = (0, 0, delta sin z) for the non-reversible variant.
    fn one_form<S: Scalar>(&self, q: &[S]) -> Option<Vec<S>> {
        self.delta
            .map(|d| vec![S::zero(), S::zero(), S::cst(d) * q[2].sin()])
    }
}
