//! The Chaplygin sleigh ([spec eq. (3.7)](crate::spec::scenes)): a rigid body on the plane supported by a blade
//! that cannot slip sideways, with its centre of mass at distance `a` ahead of the blade's
//! contact point, on the blade's line. Coordinates q = (x, y, theta): the contact point and
//! the heading. The mass matrix depends on the configuration.

use super::{AnyScene, Mat, ParamInfo, Params, Scene, SceneInfo};
use crate::scalar::Scalar;
use crate::Error;

/// L = m/2 [(xd - a sin(theta) thetad)^2 + (yd + a cos(theta) thetad)^2] + I/2 thetad^2
/// (the centre of mass is at (x + a cos theta, y + a sin theta)); constraint
/// -sin(theta) xd + cos(theta) yd = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sleigh {
    /// Mass.
    pub m: f64,
    /// Moment of inertia about the centre of mass.
    pub i: f64,
    /// Distance from the contact point to the centre of mass, along the blade.
    pub a: f64,
}

/// `sleigh` ([spec eq. (3.7)](crate::spec::scenes)).
pub const INFO: SceneInfo = SceneInfo {
    name: "sleigh",
    summary:
        "the Chaplygin sleigh, centre of mass at distance a ahead of the blade's contact point",
    coordinates: &["x", "y", "theta"],
    velocities: &["v", "omega"],
    params: &[
        ParamInfo {
            name: "m",
            default: 1.0,
            description: "mass, > 0",
        },
        ParamInfo {
            name: "I",
            default: 0.75,
            description: "moment of inertia about the centre of mass, > 0",
        },
        ParamInfo {
            name: "a",
            default: 0.5,
            description: "offset of the centre of mass ahead of the contact point (any real)",
        },
    ],
    n: 3,
    k: 1,
    lagrangian:
        "L = m/2 ((xd - a sin(theta) thetad)^2 + (yd + a cos(theta) thetad)^2) + I/2 thetad^2",
    constraints: &["mu = (-sin theta, cos theta, 0)   [-sin(theta) xd + cos(theta) yd = 0]"],
    basis: &[
        "e1 = cos(theta) d/dx + sin(theta) d/dy = (cos theta, sin theta, 0)",
        "e2 = d/dtheta = (0, 0, 1)",
    ],
    invariants: &["E = 1/2 (m v^2 + (I + m a^2) omega^2), v = u1, omega = u2 = thetad"],
    build,
};

fn build(p: &Params) -> Result<AnyScene, Error> {
    Ok(AnyScene::Sleigh(Sleigh {
        m: p.positive("m")?,
        i: p.positive("I")?,
        a: p.get("a")?,
    }))
}

impl Scene for Sleigh {
    super::described_by!(INFO);
    /// M(q) = [[m, 0, -m a sin th], [0, m, m a cos th], [-m a sin th, m a cos th, I + m a^2]].
    fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        let (s, c) = (q[2].sin(), q[2].cos());
        let ma = S::cst(self.m) * S::cst(self.a);
        let m13 = -(ma.clone() * s);
        let m23 = ma * c;
        let m33 = S::cst(self.i) + S::cst(self.m) * S::cst(self.a) * S::cst(self.a);
        vec![
            vec![S::cst(self.m), S::zero(), m13.clone()],
            vec![S::zero(), S::cst(self.m), m23.clone()],
            vec![m13, m23, m33],
        ]
    }
    fn potential<S: Scalar>(&self, _q: &[S]) -> S {
        S::zero()
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![vec![-q[2].sin(), q[2].cos(), S::zero()]]
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![
            vec![q[2].cos(), q[2].sin(), S::zero()],
            vec![S::zero(), S::zero(), S::one()],
        ]
    }
}
