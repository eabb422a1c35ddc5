//! The vertical rolling disk (Bloch, *Nonholonomic Mechanics and Control*, sec. 1.4; [spec
//! eq. (3.6)](crate::spec::scenes)): a disk of radius R rolling without slipping, upright, on the plane.
//! Coordinates q = (x, y, theta, phi): contact point, rolling angle, heading.
//! Two constraints (k = 2).

use super::{diagonal, AnyScene, Mat, ParamInfo, Params, Scene, SceneInfo};
use crate::scalar::Scalar;
use crate::Error;

/// L = m/2 (xd^2 + yd^2) + I/2 thetad^2 + J/2 phid^2; constraints
/// xd = R cos(phi) thetad, yd = R sin(phi) thetad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingDisk {
    /// Mass.
    pub m: f64,
    /// Moment of inertia about the axle (rolling).
    pub i: f64,
    /// Moment of inertia about the vertical diameter (turning).
    pub j: f64,
    /// Radius.
    pub r: f64,
}

/// `rolling-disk` ([spec eq. (3.6)](crate::spec::scenes)).
pub const INFO: SceneInfo = SceneInfo {
    name: "rolling-disk",
    summary: "the vertical rolling disk (Bloch, Nonholonomic Mechanics and Control, sec. 1.4)",
    coordinates: &["x", "y", "theta", "phi"],
    velocities: &["thetad", "phid"],
    params: &[
        ParamInfo {
            name: "m",
            default: 1.0,
            description: "mass, > 0",
        },
        ParamInfo {
            name: "I",
            default: 0.5,
            description: "moment of inertia about the axle (rolling), > 0",
        },
        ParamInfo {
            name: "J",
            default: 0.25,
            description: "moment of inertia about a vertical diameter (turning), > 0",
        },
        ParamInfo {
            name: "R",
            default: 1.0,
            description: "radius, > 0",
        },
    ],
    n: 4,
    k: 2,
    lagrangian: "L = m/2 (xd^2 + yd^2) + I/2 thetad^2 + J/2 phid^2",
    constraints: &[
        "mu1 = (1, 0, -R cos phi, 0)   [xd = R cos(phi) thetad]",
        "mu2 = (0, 1, -R sin phi, 0)   [yd = R sin(phi) thetad]",
    ],
    basis: &[
        "e1 = R cos(phi) d/dx + R sin(phi) d/dy + d/dtheta = (R cos phi, R sin phi, 1, 0)",
        "e2 = d/dphi = (0, 0, 0, 1)",
    ],
    invariants: &[
        "E = 1/2 ((m R^2 + I) thetad^2 + J phid^2)",
        "thetad",
        "phid",
    ],
    build,
};

fn build(p: &Params) -> Result<AnyScene, Error> {
    Ok(AnyScene::RollingDisk(RollingDisk {
        m: p.positive("m")?,
        i: p.positive("I")?,
        j: p.positive("J")?,
        r: p.positive("R")?,
    }))
}

impl Scene for RollingDisk {
    super::described_by!(INFO);
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        diagonal(&[self.m, self.m, self.i, self.j])
    }
    fn potential<S: Scalar>(&self, _q: &[S]) -> S {
        S::zero()
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        let r = S::cst(self.r);
        vec![
            vec![S::one(), S::zero(), -(r.clone() * q[3].cos()), S::zero()],
            vec![S::zero(), S::one(), -(r * q[3].sin()), S::zero()],
        ]
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        let r = S::cst(self.r);
        vec![
            vec![r.clone() * q[3].cos(), r * q[3].sin(), S::one(), S::zero()],
            vec![S::zero(), S::zero(), S::zero(), S::one()],
        ]
    }
}
