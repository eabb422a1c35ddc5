//! Scenes: the data of one natural mechanical system with linear nonholonomic constraints
//! ([spec/03-scenes.md](crate::spec::scenes)). A scene is nothing but data, written once over `S: Scalar`:
//!
//! - `L(q, qd) = 1/2 qd^T M(q) qd + A(q) qd - V(q)` on `Q = R^n` (angles as real
//!   coordinates; the one-form `A` is absent, i.e. zero, unless a scene declares one),
//! - `k` constraint covectors `mu^a(q)` (rows of the k x n matrix `mu(q)`), `mu(q) qd = 0`,
//! - a basis `e_1(q) .. e_{n-k}(q)` of `D_q = ker mu(q)`, so that `v = E(q)^T u` is in D exactly.
//!
//! Everything else (dynamics, multipliers, enclosures, schemes) is derived in generic code;
//! nothing downstream knows which scene it is running. Each scene file also declares, as a
//! [`SceneInfo`], its name, coordinates, parameters (defaults and validation) and a readable
//! description of its data; this module only keeps the registry: the [`AnyScene`] enum, the
//! `with_scene!` arms and the list [`SCENES`].

mod contact_oscillator;
#[cfg(feature = "scene-files")]
mod expr;
#[cfg(feature = "scene-files")]
mod file;
mod knife;
mod particle;
mod rolling_disk;
mod sleigh;

pub use contact_oscillator::ContactOscillator;
#[cfg(feature = "scene-files")]
#[cfg_attr(docsrs, doc(cfg(feature = "scene-files")))]
pub use file::SceneFile;
pub use knife::{Knife, KnifeEps};
pub use particle::Particle;
pub use rolling_disk::RollingDisk;
pub use sleigh::Sleigh;

use crate::scalar::Scalar;
use crate::{Error, InputKind};

/// Dense matrix as rows.
pub type Mat<S> = Vec<Vec<S>>;

/// The data of one nonholonomic system ([spec eq. (3.1)](crate::spec::scenes)); `q` has length `dim()`.
///
/// Any type that implements it builds a [`crate::Model`]: the built-in scenes, scene files
/// (`SceneFile`) and users' own types alike. Only [`Scene::name`], [`Scene::dim`] and
/// [`Scene::constraints`] are required; every other datum has its natural default (M = I,
/// V = 0, A = 0, the basis of D derived from the constraints, [spec eq. (3.15)](crate::spec::scenes)). The data are
/// written once over `S: Scalar` and must be analytic where they are evaluated ([spec
/// eq. (3.17)](crate::spec::scenes) says what [`crate::Model::new`] and [`crate::Model::check_at`] check and what
/// stays assumed).
///
/// # Example
/// The particle of [spec eq. (3.2)](crate::spec::scenes) as a user's own type: only its constraint is given, so
/// `M = I`, `V = 0` and the basis is derived with the free coordinates `(x, y)`:
/// `e_1 = (1, 0, y)`, `e_2 = (0, 1, 0)`.
/// ```
/// use dalembert::scalar::Scalar;
/// use dalembert::scene::{Mat, Scene};
/// use dalembert::{flow, FlowOptions, Model};
///
/// struct MyParticle;
/// impl Scene for MyParticle {
///     fn name(&self) -> String {
///         "my-particle".into()
///     }
///     fn dim(&self) -> usize {
///         3
///     }
///     /// zd - y xd = 0
///     fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
///         vec![vec![-q[1].clone(), S::zero(), S::one()]]
///     }
/// }
///
/// let model = Model::new(&MyParticle)?;
/// let e = flow(&model, &[0.0, 0.0, 0.0], &[0.8, 0.8], 2.0, &FlowOptions::default())?;
/// assert!(e.q[1].contains(1.6)); // y(t) = 0.8 t, as for the built-in `particle`
/// # Ok::<(), dalembert::Error>(())
/// ```
pub trait Scene {
    /// The name shown in answers and messages.
    fn name(&self) -> String;
    /// Number of coordinates n.
    fn dim(&self) -> usize;
    /// Constraint covectors: row a is mu^a(q) (k x n, k the same at every q).
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S>;
    /// Mass matrix M(q), n x n, symmetric positive definite (default: the identity).
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        identity(self.dim())
    }
    /// Potential V(q) (default 0).
    fn potential<S: Scalar>(&self, _q: &[S]) -> S {
        S::zero()
    }
    /// The one-form `A(q)` of a Lagrangian term `A(q) qd` linear in the velocities
    /// ([spec eq. (3.1)](crate::spec::scenes)); `None`, the default, for a natural Lagrangian (A = 0).
    fn one_form<S: Scalar>(&self, _q: &[S]) -> Option<Vec<S>> {
        None
    }
    /// The free coordinates of the derived basis ([spec eq. (3.15)](crate::spec::scenes)): n - k indices into q.
    /// Default: the first n - k coordinates. Used only by the default [`Scene::basis`].
    fn free(&self) -> Vec<usize> {
        (0..self.dim().saturating_sub(self.n_constraints())).collect()
    }
    /// Basis of D_q: row a is e_a(q) ((n-k) x n) with mu(q) e_a(q) = 0. Default: the basis
    /// derived from the constraints and [`Scene::free`] ([spec eq. (3.15)](crate::spec::scenes)).
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        derived_basis(&self.constraints(q), &self.free(), self.dim())
    }
    /// Number of constraints k: the rows of `constraints` (read once, at q = 0).
    fn n_constraints(&self) -> usize {
        self.constraints::<f64>(&vec![0.0; self.dim()]).len()
    }
    /// What the scene says about itself, for people and for `dalembert scenes` (default:
    /// the name, coordinates `q1 .. qn`, quasi-velocities `u1 .. um`).
    fn description(&self) -> Description {
        Description::plain(self.name(), self.dim(), self.n_constraints())
    }
}

/// The basis of D_q derived from the constraints ([spec eq. (3.15)](crate::spec::scenes)): with `free` the n - k
/// free coordinates and the other k coordinates `dep`, e_a is the vector of ker mu(q) whose
/// components on the free coordinates are the a-th unit vector; its components on `dep` are
/// `-B^{-1} mu[:, free_a]`, B = mu[:, dep] the k x k pivot block, computed by Cramer's rule
/// (one division, by det B, so the only singularity is det B = 0, which a validated
/// evaluation refuses as a division by an interval containing 0). `free` must hold n - k
/// distinct indices below n (checked by [`crate::Model::new`]; here a bad one gives rows
/// of the right size with unspecified entries, never a panic).
pub fn derived_basis<S: Scalar>(mu: &Mat<S>, free: &[usize], n: usize) -> Mat<S> {
    let k = mu.len();
    let dep: Vec<usize> = (0..n).filter(|i| !free.contains(i)).collect();
    if dep.len() != k {
        // not n - k distinct free coordinates below n: rows of zeros, which
        // `Model::new` refuses (it checks `free` itself)
        return vec![vec![S::zero(); n]; free.len()];
    }
    let col = |r: usize, c: usize| {
        mu.get(r)
            .and_then(|row| row.get(c))
            .cloned()
            .unwrap_or_else(S::zero)
    };
    let block: Mat<S> = (0..k)
        .map(|r| dep.iter().map(|&c| col(r, c)).collect())
        .collect();
    let det_b = det(&block);
    free.iter()
        .enumerate()
        .map(|(a, &fa)| {
            let mut e: Vec<S> = (0..n)
                .map(|i| {
                    if free.get(a) == Some(&i) {
                        S::one()
                    } else {
                        S::zero()
                    }
                })
                .collect();
            for (i, &di) in dep.iter().enumerate().take(k) {
                // Cramer: column i of B replaced by mu[:, free_a]
                let bi: Mat<S> = (0..k)
                    .map(|r| {
                        (0..k)
                            .map(|c| {
                                if c == i {
                                    col(r, fa)
                                } else {
                                    block[r][c].clone()
                                }
                            })
                            .collect()
                    })
                    .collect();
                if di < n {
                    e[di] = -(det(&bi) / det_b.clone());
                }
            }
            e
        })
        .collect()
}

/// The determinant by cofactor expansion along the first row (the minors repeat; recorded
/// on a tape they are stored once). Division-free, so it is defined everywhere.
pub fn det<S: Scalar>(m: &Mat<S>) -> S {
    let k = m.len();
    match k {
        0 => S::one(),
        1 => m[0][0].clone(),
        2 => m[0][0].clone() * m[1][1].clone() - m[0][1].clone() * m[1][0].clone(),
        _ => {
            let mut acc = S::zero();
            for j in 0..k {
                let minor: Mat<S> = m[1..]
                    .iter()
                    .map(|r| {
                        r.iter()
                            .enumerate()
                            .filter(|(c, _)| *c != j)
                            .map(|(_, x)| x.clone())
                            .collect()
                    })
                    .collect();
                let t = m[0][j].clone() * det(&minor);
                acc = if j % 2 == 0 { acc + t } else { acc - t };
            }
            acc
        }
    }
}

/// What a scene says about itself: the words `dalembert scenes` prints and external
/// implementations use to pose the same problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Description {
    /// The scene's name (for a built-in scene, its `--scene` name).
    pub name: String,
    /// One line: what the system is and where it comes from.
    pub summary: String,
    /// Names of q's components, in order.
    pub coordinates: Vec<String>,
    /// Names of the quasi-velocities u_a.
    pub velocities: Vec<String>,
    /// Parameters: name, value in this scene (the default in a listing), description.
    pub params: Vec<(String, f64, String)>,
    /// Number of coordinates `n`.
    pub n: usize,
    /// Number of constraints `k` (rows of mu).
    pub k: usize,
    /// The Lagrangian, as a formula.
    pub lagrangian: String,
    /// The constraint covectors mu^a, one string each.
    pub constraints: Vec<String>,
    /// The basis e_a of D, one string each.
    pub basis: Vec<String>,
    /// Known first integrals (formulas), possibly empty.
    pub invariants: Vec<String>,
}

impl Description {
    /// A description with nothing but a name and the sizes.
    pub fn plain(name: String, n: usize, k: usize) -> Description {
        Description {
            summary: name.clone(),
            name,
            coordinates: (1..=n).map(|i| format!("q{i}")).collect(),
            velocities: (1..=n.saturating_sub(k)).map(|a| format!("u{a}")).collect(),
            params: Vec::new(),
            n,
            k,
            lagrangian: String::new(),
            constraints: Vec::new(),
            basis: Vec::new(),
            invariants: Vec::new(),
        }
    }
}

/// The descriptive methods of a built-in scene, from its static [`SceneInfo`].
macro_rules! described_by {
    ($info:expr) => {
        fn name(&self) -> String {
            $info.name.to_string()
        }
        fn dim(&self) -> usize {
            $info.n
        }
        fn n_constraints(&self) -> usize {
            $info.k
        }
        fn description(&self) -> $crate::scene::Description {
            $info.description()
        }
    };
}
pub(crate) use described_by;

/// A scene parameter: name, default and a one-line description (with its admissible range).
#[derive(Debug)]
pub struct ParamInfo {
    /// The name in `--param name=value`.
    pub name: &'static str,
    /// The value used when none is given.
    pub default: f64,
    /// One line: what the parameter is, and its admissible range.
    pub description: &'static str,
}

/// What a scene file declares about its scene, in words external implementations can use to
/// pose the same problem (`dalembert scenes --json`), plus its constructor.
#[derive(Debug)]
pub struct SceneInfo {
    /// The name on the command line (`--scene`).
    pub name: &'static str,
    /// One line: what the system is and where it comes from.
    pub summary: &'static str,
    /// Names of q's components, in order.
    pub coordinates: &'static [&'static str],
    /// Names of the quasi-velocities u_a (components of v in the basis e_a).
    pub velocities: &'static [&'static str],
    /// The parameters the scene takes.
    pub params: &'static [ParamInfo],
    /// Number of coordinates `n`.
    pub n: usize,
    /// Number of constraints `k` (rows of mu).
    pub k: usize,
    /// The Lagrangian, as a formula.
    pub lagrangian: &'static str,
    /// The constraint covectors mu^a, one string each.
    pub constraints: &'static [&'static str],
    /// The basis e_a of D, one string each.
    pub basis: &'static [&'static str],
    /// Known first integrals of the continuous flow (formulas), possibly empty.
    pub invariants: &'static [&'static str],
    /// The scene with validated parameter values (every parameter resolved to a value).
    pub build: fn(&Params) -> Result<AnyScene, Error>,
}

impl SceneInfo {
    /// The description, with the parameters' defaults.
    pub fn description(&self) -> Description {
        let strings = |v: &[&str]| v.iter().map(|s| s.to_string()).collect();
        Description {
            name: self.name.into(),
            summary: self.summary.into(),
            coordinates: strings(self.coordinates),
            velocities: strings(self.velocities),
            params: self
                .params
                .iter()
                .map(|p| (p.name.into(), p.default, p.description.into()))
                .collect(),
            n: self.n,
            k: self.k,
            lagrangian: self.lagrangian.into(),
            constraints: strings(self.constraints),
            basis: strings(self.basis),
            invariants: strings(self.invariants),
        }
    }
}

/// Parameter values handed to a scene's constructor: the given ones, else the defaults.
#[derive(Debug)]
pub struct Params<'a> {
    info: &'static SceneInfo,
    given: &'a [(&'a str, f64)],
}

impl Params<'_> {
    /// The value of parameter `name` (the last one given, else its default); an error if
    /// the scene declares no such parameter (a bug in the scene file, named, not a panic).
    pub fn get(&self, name: &str) -> Result<f64, Error> {
        self.given
            .iter()
            .rev()
            .find(|(k, _)| *k == name)
            .map(|(_, v)| *v)
            .or_else(|| {
                self.info
                    .params
                    .iter()
                    .find(|p| p.name == name)
                    .map(|p| p.default)
            })
            .ok_or_else(|| {
                Error::internal_at(
                    crate::Invariant::UndeclaredParameter,
                    format!(
                        "scene `{}` reads an undeclared parameter `{name}`",
                        self.info.name
                    ),
                )
            })
    }

    /// `get(name)`, required to be > 0 (an input error otherwise).
    pub fn positive(&self, name: &str) -> Result<f64, Error> {
        let v = self.get(name)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(Error::input_at(
                InputKind::Parameter(name.to_string()),
                format!("{} needs {name} > 0 (got {v})", self.info.name),
            ))
        }
    }
}

/// A scene chosen by name at run time, with its parameters fixed.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyScene {
    /// `particle` ([spec eq. (3.2)](crate::spec::scenes)).
    Particle(Particle),
    /// `knife` ([spec eq. (3.3)](crate::spec::scenes)).
    Knife(Knife),
    /// `knife-eps` ([spec eq. (3.4)](crate::spec::scenes)).
    KnifeEps(KnifeEps),
    /// `rolling-disk` ([spec eq. (3.6)](crate::spec::scenes)).
    RollingDisk(RollingDisk),
    /// `sleigh` ([spec eq. (3.7)](crate::spec::scenes)).
    Sleigh(Sleigh),
    /// `contact-oscillator` ([spec eq. (3.8)](crate::spec::scenes)), or `contact-oscillator-nr` (3.9) when `delta` is
    /// given.
    ContactOscillator(ContactOscillator),
}

/// Every scene the crate knows, in the order `dalembert scenes` lists them.
pub const SCENES: &[&SceneInfo] = &[
    &particle::INFO,
    &knife::KNIFE_INFO,
    &knife::KNIFE_EPS_INFO,
    &rolling_disk::INFO,
    &sleigh::INFO,
    &contact_oscillator::INFO,
    &contact_oscillator::NR_INFO,
];

/// The names of every scene, in the contract's spelling.
pub fn scene_names() -> Vec<&'static str> {
    SCENES.iter().map(|s| s.name).collect()
}

/// The scene description called `name`.
pub fn info_of(name: &str) -> Result<&'static SceneInfo, Error> {
    SCENES
        .iter()
        .copied()
        .find(|s| s.name == name)
        .ok_or_else(|| {
            Error::input_at(
                InputKind::Scene(name.to_string()),
                format!(
                    "unknown scene `{name}` (known: {})",
                    scene_names().join(", ")
                ),
            )
        })
}

impl AnyScene {
    /// The scene `name` with parameters `params` (name, exact f64 value; the last one
    /// given counts): `AnyScene::new("knife-eps", &[("eps", 0.1)])`. Unknown names, unknown
    /// parameters, non-finite values and values the scene rejects are input errors
    /// ([`InputKind::Scene`], [`InputKind::Parameter`]).
    pub fn new(name: &str, params: &[(&str, f64)]) -> Result<AnyScene, Error> {
        let info = info_of(name)?;
        for &(k, v) in params {
            let at = || InputKind::Parameter(k.to_string());
            if !info.params.iter().any(|p| p.name == k) {
                return Err(Error::input_at(
                    at(),
                    format!("scene `{name}` has no parameter `{k}`"),
                ));
            }
            if !v.is_finite() {
                return Err(Error::input_at(
                    at(),
                    format!("parameter `{k}` must be finite"),
                ));
            }
        }
        (info.build)(&Params {
            info,
            given: params,
        })
    }

    /// The parameters a scene takes, with defaults.
    pub fn params_of(name: &str) -> Result<&'static [ParamInfo], Error> {
        Ok(info_of(name)?.params)
    }

    /// The static description of this scene (for a `ContactOscillator` with `delta`, that of
    /// `contact-oscillator-nr`).
    pub fn info(&self) -> &'static SceneInfo {
        match self {
            AnyScene::Particle(_) => &particle::INFO,
            AnyScene::Knife(_) => &knife::KNIFE_INFO,
            AnyScene::KnifeEps(_) => &knife::KNIFE_EPS_INFO,
            AnyScene::RollingDisk(_) => &rolling_disk::INFO,
            AnyScene::Sleigh(_) => &sleigh::INFO,
            AnyScene::ContactOscillator(c) => match c.delta {
                None => &contact_oscillator::INFO,
                Some(_) => &contact_oscillator::NR_INFO,
            },
        }
    }
}

/// The registry's scenes are scenes like any other: each call goes to the scene inside.
impl Scene for AnyScene {
    fn name(&self) -> String {
        self.info().name.to_string()
    }
    fn dim(&self) -> usize {
        self.info().n
    }
    fn n_constraints(&self) -> usize {
        self.info().k
    }
    fn description(&self) -> Description {
        crate::with_scene!(self, s => s.description())
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        crate::with_scene!(self, s => s.constraints(q))
    }
    fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        crate::with_scene!(self, s => s.mass(q))
    }
    fn potential<S: Scalar>(&self, q: &[S]) -> S {
        crate::with_scene!(self, s => s.potential(q))
    }
    fn one_form<S: Scalar>(&self, q: &[S]) -> Option<Vec<S>> {
        crate::with_scene!(self, s => s.one_form(q))
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        crate::with_scene!(self, s => s.basis(q))
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
            $crate::scene::AnyScene::RollingDisk($s) => $body,
            $crate::scene::AnyScene::Sleigh($s) => $body,
            $crate::scene::AnyScene::ContactOscillator($s) => $body,
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

/// The n x n diagonal matrix with the exact constants `d` (a constant mass matrix).
pub fn diagonal<S: Scalar>(d: &[f64]) -> Mat<S> {
    let n = d.len();
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| if i == j { S::cst(d[i]) } else { S::zero() })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{dot, Geometry};

    /// Every scene's declared data agree with what it computes: n, k, the lengths of its
    /// strings, mu e_a = 0 at a few points, a symmetric mass matrix, and defaults that build.
    #[test]
    fn every_scene_is_consistent_with_its_description() {
        let pts: [[f64; 4]; 3] = [[0.3, -1.2, 0.9, 2.1], [0.0; 4], [-2.5, 0.7, -0.4, -1.3]];
        for info in SCENES {
            let sc = AnyScene::new(info.name, &[]).unwrap();
            assert_eq!(sc.name(), info.name);
            crate::with_scene!(&sc, s => {
                assert_eq!((s.dim(), s.n_constraints()), (info.n, info.k), "{}", info.name);
                for p in &pts {
                    let g = Geometry::at(s, &p[..info.n]);
                    assert_eq!(g.mu.len(), info.k);
                    assert_eq!(g.basis.len(), info.n - info.k);
                    for mu in &g.mu {
                        for e in &g.basis {
                            assert!(dot(mu, e).abs() < 1e-15, "{}: mu e != 0", info.name);
                        }
                    }
                    for i in 0..info.n {
                        for j in 0..info.n {
                            assert_eq!(g.mass[i][j], g.mass[j][i], "{}", info.name);
                        }
                    }
                }
            });
            assert_eq!(info.coordinates.len(), info.n, "{}", info.name);
            assert_eq!(info.velocities.len(), info.n - info.k, "{}", info.name);
            assert_eq!(info.constraints.len(), info.k, "{}", info.name);
            assert_eq!(info.basis.len(), info.n - info.k, "{}", info.name);
        }
        let mut names = scene_names();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), SCENES.len(), "scene names must be unique");
    }

    #[test]
    fn unknown_scenes_and_parameters_are_input_errors() {
        let e = AnyScene::new("nope", &[]).unwrap_err();
        assert!(e.message().contains("rolling-disk"), "{e}");
        assert!(AnyScene::new("knife", &[("eps", 0.1)]).is_err());
        assert!(AnyScene::new("sleigh", &[("m", f64::NAN)]).is_err());
        assert!(AnyScene::new("sleigh", &[("m", -1.0)]).is_err());
        assert!(AnyScene::new("rolling-disk", &[("R", 0.0)]).is_err());
        let e = AnyScene::new("knife", &[("eps", 0.1)]).unwrap_err();
        assert_eq!(e.input_kind(), Some(&InputKind::Parameter("eps".into())));
        let e = AnyScene::new("kinfe", &[]).unwrap_err();
        assert_eq!(e.input_kind(), Some(&InputKind::Scene("kinfe".into())));
    }
}
