//! The nonholonomic particle (paper Example 2.1; spec eq. (3.2)).

use super::{identity, Mat, Scene};
use crate::scalar::Scalar;

/// q = (x, y, z); L = 1/2 |qd|^2; constraint zd - y xd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle;

impl Scene for Particle {
    fn dim(&self) -> usize {
        3
    }
    fn n_constraints(&self) -> usize {
        1
    }
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        identity(3)
    }
    fn potential<S: Scalar>(&self, _q: &[S]) -> S {
        S::zero()
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![vec![-q[1].clone(), S::zero(), S::one()]]
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![
            vec![S::one(), S::zero(), q[1].clone()],
            vec![S::zero(), S::one(), S::zero()],
        ]
    }
}
