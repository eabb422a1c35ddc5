//! The knife edge on an inclined plane and its perturbation (paper section 5; spec
//! eqs. (3.3)-(3.4)). Coordinates in the contract's order q = (x, y, phi).

use super::{identity, Mat, Scene};
use crate::scalar::Scalar;

/// L = 1/2 (xd^2 + yd^2 + phid^2) + x/2; constraint sin(phi) xd - cos(phi) yd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knife;

/// As [`Knife`] with constraint sin(phi) xd - (cos(phi) - eps) yd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnifeEps {
    pub eps: f64,
}

/// Shared data of both knives: the blade direction is (cos(phi) - eps, sin(phi)).
fn knife_constraints<S: Scalar>(q: &[S], eps: f64) -> Mat<S> {
    let c = q[2].cos() - S::cst(eps);
    vec![vec![q[2].sin(), -c, S::zero()]]
}

fn knife_basis<S: Scalar>(q: &[S], eps: f64) -> Mat<S> {
    let c = q[2].cos() - S::cst(eps);
    vec![
        vec![c, q[2].sin(), S::zero()],
        vec![S::zero(), S::zero(), S::one()],
    ]
}

/// V = -x/2 (gravity along the incline).
fn knife_potential<S: Scalar>(q: &[S]) -> S {
    -(q[0].clone() * S::cst(0.5))
}

impl Scene for Knife {
    fn dim(&self) -> usize {
        3
    }
    fn n_constraints(&self) -> usize {
        1
    }
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        identity(3)
    }
    fn potential<S: Scalar>(&self, q: &[S]) -> S {
        knife_potential(q)
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        knife_constraints(q, 0.0)
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        knife_basis(q, 0.0)
    }
}

impl Scene for KnifeEps {
    fn dim(&self) -> usize {
        3
    }
    fn n_constraints(&self) -> usize {
        1
    }
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        identity(3)
    }
    fn potential<S: Scalar>(&self, q: &[S]) -> S {
        knife_potential(q)
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        knife_constraints(q, self.eps)
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        knife_basis(q, self.eps)
    }
}
