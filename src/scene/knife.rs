//! The knife edge on an inclined plane and its perturbation (paper section 5; [spec
//! eqs. (3.3)-(3.4)](crate::spec::scenes)). Coordinates in the contract's order q = (x, y, phi).

use super::{identity, AnyScene, Mat, ParamInfo, Params, Scene, SceneInfo};
use crate::scalar::Scalar;
use crate::Error;

/// L = 1/2 (xd^2 + yd^2 + phid^2) + x/2; constraint sin(phi) xd - cos(phi) yd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knife;

/// As [`Knife`] with constraint sin(phi) xd - (cos(phi) - eps) yd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnifeEps {
    /// The `eps` of `cos(phi) - eps`; [`AnyScene::new`] requires `|eps| < 1` ([spec eq. (3.4)](crate::spec::scenes)).
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

/// `knife` (contract; [spec eq. (3.3)](crate::spec::scenes)).
pub const KNIFE_INFO: SceneInfo = SceneInfo {
    name: "knife",
    summary: "the knife edge on an inclined plane (paper section 5)",
    coordinates: &["x", "y", "phi"],
    velocities: &["s", "phid"],
    params: &[] as &[ParamInfo],
    n: 3,
    k: 1,
    lagrangian: "L = 1/2 (xd^2 + yd^2 + phid^2) + x/2",
    constraints: &["mu = (sin phi, -cos phi, 0)   [sin(phi) xd - cos(phi) yd = 0]"],
    basis: &[
        "e1 = cos(phi) d/dx + sin(phi) d/dy = (cos phi, sin phi, 0)",
        "e2 = d/dphi = (0, 0, 1)",
    ],
    invariants: &["E = 1/2 (xd^2 + yd^2 + phid^2) - x/2", "phid"],
    build: build_knife,
};

/// `knife-eps` (contract; [spec eq. (3.4)](crate::spec::scenes)).
pub const KNIFE_EPS_INFO: SceneInfo = SceneInfo {
    name: "knife-eps",
    summary: "the perturbed knife edge of the paper's section 5 (not a knife for eps != 0)",
    coordinates: &["x", "y", "phi"],
    velocities: &["u1", "phid"],
    params: &[ParamInfo {
        name: "eps",
        default: 0.1,
        description: "perturbation of the blade direction, |eps| < 1",
    }],
    n: 3,
    k: 1,
    lagrangian: "L = 1/2 (xd^2 + yd^2 + phid^2) + x/2",
    constraints: &["mu = (sin phi, -(cos phi - eps), 0)   [sin(phi) xd - (cos(phi) - eps) yd = 0]"],
    basis: &[
        "e1 = (cos(phi) - eps) d/dx + sin(phi) d/dy = (cos phi - eps, sin phi, 0)",
        "e2 = d/dphi = (0, 0, 1)",
    ],
    invariants: &["E = 1/2 (xd^2 + yd^2 + phid^2) - x/2", "phid"],
    build: build_knife_eps,
};

fn build_knife(_: &Params) -> Result<AnyScene, Error> {
    Ok(AnyScene::Knife(Knife))
}

fn build_knife_eps(p: &Params) -> Result<AnyScene, Error> {
    let eps = p.get("eps")?;
    if eps.abs() >= 1.0 {
        return Err(Error::input(format!(
            "knife-eps needs |eps| < 1 (got {eps}); at |eps| >= 1 the basis of D degenerates"
        )));
    }
    Ok(AnyScene::KnifeEps(KnifeEps { eps }))
}

impl Scene for Knife {
    super::described_by!(KNIFE_INFO);
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
    super::described_by!(KNIFE_EPS_INFO);
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
