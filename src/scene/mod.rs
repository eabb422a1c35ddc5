//! Scenes: the data of one natural mechanical system with linear nonholonomic constraints
//! (spec/03-scenes.md). A scene is nothing but data, written once over `S: Scalar`:
//!
//! - `L(q, qd) = 1/2 qd^T M(q) qd - V(q)` on `Q = R^n` (angles as real coordinates),
//! - `k` constraint covectors `mu^a(q)` (rows of the k x n matrix `mu(q)`), `mu(q) qd = 0`,
//! - a basis `e_1(q) .. e_{n-k}(q)` of `D_q = ker mu(q)`, so that `v = E(q) u` is in D exactly.
//!
//! Everything else (dynamics, multipliers, enclosures, schemes) is derived in generic code;
//! nothing downstream knows which scene it is running.

mod knife;
mod particle;

pub use knife::{Knife, KnifeEps};
pub use particle::Particle;

use crate::scalar::Scalar;
use crate::Error;

/// Dense matrix as rows.
pub type Mat<S> = Vec<Vec<S>>;

/// The data of one scene (spec eq. (3.1)). `q` has length `dim()`.
pub trait Scene {
    /// Number of coordinates n.
    fn dim(&self) -> usize;
    /// Number of constraints k (the rank of D is n - k).
    fn n_constraints(&self) -> usize;
    /// Mass matrix M(q), n x n, symmetric positive definite.
    fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S>;
    /// Potential V(q).
    fn potential<S: Scalar>(&self, q: &[S]) -> S;
    /// Constraint covectors: row a is mu^a(q) (k x n).
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S>;
    /// Basis of D_q: row a is e_a(q) ((n-k) x n); mu(q) e_a(q) = 0 identically.
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S>;
}

/// A scene chosen by name at run time, with its parameters fixed.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyScene {
    Particle(Particle),
    Knife(Knife),
    KnifeEps(KnifeEps),
}

/// Description of a scene parameter: name and default.
pub struct ParamInfo {
    pub name: &'static str,
    pub default: f64,
}

/// Every scene the crate knows, in the contract's spelling.
pub const SCENE_NAMES: [&str; 3] = ["particle", "knife", "knife-eps"];

impl AnyScene {
    /// The scene `name` with parameters `params` (name, exact f64 value); unknown names,
    /// unknown parameters and non-finite values are input errors.
    pub fn new(name: &str, params: &[(String, f64)]) -> Result<AnyScene, Error> {
        let allowed = Self::params_of(name)?;
        for (k, v) in params {
            if !allowed.iter().any(|p| p.name == k) {
                return Err(Error::input(format!(
                    "scene `{name}` has no parameter `{k}`"
                )));
            }
            if !v.is_finite() {
                return Err(Error::input(format!("parameter `{k}` must be finite")));
            }
        }
        let get = |p: &str, d: f64| {
            params
                .iter()
                .rev()
                .find(|(k, _)| k == p)
                .map(|(_, v)| *v)
                .unwrap_or(d)
        };
        Ok(match name {
            "particle" => AnyScene::Particle(Particle),
            "knife" => AnyScene::Knife(Knife),
            _ => {
                let eps = get("eps", 0.1);
                if eps.abs() >= 1.0 {
                    return Err(Error::input(format!(
                        "knife-eps needs |eps| < 1 (got {eps}); at |eps| >= 1 the basis of D degenerates"
                    )));
                }
                AnyScene::KnifeEps(KnifeEps { eps })
            }
        })
    }

    /// The parameters a scene takes, with defaults.
    pub fn params_of(name: &str) -> Result<Vec<ParamInfo>, Error> {
        match name {
            "particle" | "knife" => Ok(vec![]),
            "knife-eps" => Ok(vec![ParamInfo {
                name: "eps",
                default: 0.1,
            }]),
            _ => Err(Error::input(format!(
                "unknown scene `{name}` (known: {})",
                SCENE_NAMES.join(", ")
            ))),
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            AnyScene::Particle(_) => "particle",
            AnyScene::Knife(_) => "knife",
            AnyScene::KnifeEps(_) => "knife-eps",
        }
    }
}

/// Dispatch a generic computation on the concrete scene inside an [`AnyScene`].
#[macro_export]
macro_rules! with_scene {
    ($any:expr, $s:ident => $body:expr) => {
        match $any {
            $crate::scene::AnyScene::Particle($s) => $body,
            $crate::scene::AnyScene::Knife($s) => $body,
            $crate::scene::AnyScene::KnifeEps($s) => $body,
        }
    };
}

/// The n x n identity over S (a constant mass matrix written as data).
pub fn identity<S: Scalar>(n: usize) -> Mat<S> {
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| if i == j { S::one() } else { S::zero() })
                .collect()
        })
        .collect()
}
