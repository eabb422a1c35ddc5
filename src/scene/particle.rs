//! The nonholonomic particle (paper Example 2.1; [spec eq. (3.2)](crate::spec::scenes)).

use super::{identity, AnyScene, Mat, ParamInfo, Params, Scene, SceneInfo};
use crate::scalar::Scalar;
use crate::Error;

/// q = (x, y, z); L = 1/2 |qd|^2; constraint zd - y xd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle;

/// `particle` (contract; [spec eq. (3.2)](crate::spec::scenes)).
pub const INFO: SceneInfo = SceneInfo {
    name: "particle",
    summary: "the nonholonomic particle (paper Example 2.1)",
    coordinates: &["x", "y", "z"],
    velocities: &["xd", "yd"],
    params: &[] as &[ParamInfo],
    n: 3,
    k: 1,
    lagrangian: "L = 1/2 (xd^2 + yd^2 + zd^2)",
    constraints: &["mu = (-y, 0, 1)   [zd - y xd = 0]"],
    basis: &["e1 = d/dx + y d/dz = (1, 0, y)", "e2 = d/dy = (0, 1, 0)"],
    invariants: &["E = 1/2 (xd^2 + yd^2 + zd^2)", "yd"],
    build,
};

fn build(_: &Params) -> Result<AnyScene, Error> {
    Ok(AnyScene::Particle(Particle))
}

impl Scene for Particle {
    super::described_by!(INFO);
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
