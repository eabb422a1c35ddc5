//! A scene compiled once into tapes ([spec/04-dynamics.md](crate::spec::dynamics), eq. (4.11)): every later object
//! (validated flow, retractions, float schemes) replays these tapes, so the float and the
//! interval computations run the same program.

use crate::dynamics::Geometry;
use crate::enclosure::System;
use crate::scalar::{point, Scalar};
use crate::scene::{derived_basis, det, Description, Mat, Scene};
use crate::tape::{finite, Tape, Tracer};
use crate::{Cause, Error, InputKind};
use inari::Interval;

/// The reduced field with the Lagrangian appended ([spec eq. (6.8)](crate::spec::exact_discrete)).
pub fn field_with_action<Sc: Scene, S: Scalar>(sc: &Sc, x: &[S]) -> Vec<S> {
    let n = sc.dim();
    let d = x.len() - 1;
    let v = Geometry::at(sc, &x[..n]).velocity(&x[n..d]);
    let lag = crate::dynamics::lagrangian(sc, &x[..n], &v);
    let mut f = reduced_field(sc, &x[..d]);
    f.push(lag);
    f
}

/// A scene compiled once into tapes ([spec eq. (4.11)](crate::spec::dynamics)); the reduced state is x = (q, u), of
/// dimension n + (n - k). Built by [`Model::new`], read through its methods.
pub struct Model {
    /// The scene's data recorded on tapes: every later computation reads the scene here
    /// (shared with the recorders of the tapes recorded on first use).
    pub(crate) scene: std::sync::Arc<CompiledScene>,
    /// Number of coordinates n.
    pub(crate) n: usize,
    /// Number of constraints k.
    pub(crate) k: usize,
    /// x' = F(x), x = (q, u) ([spec eq. (4.4)](crate::spec::dynamics)), and its variational equation.
    pub(crate) dynamics: System,
    /// x' = -F(x), the time-reversed field, recorded on the first backward flow ([spec
    /// (5.17)](crate::spec::enclosure)).
    reversed: std::sync::OnceLock<System>,
    /// The same with the action: (q, u, l)' = (F(q, u), L(q, E^T u)) ([spec eq. (6.8)](crate::spec::exact_discrete)),
    /// recorded on first use (only the exact discrete Lagrangian needs it).
    with_action: std::sync::OnceLock<System>,
    /// x -> v = E(q)^T u ([spec eq. (4.2)](crate::spec::dynamics)).
    pub(crate) velocity: Tape,
    /// x -> (v, Dv/Dx) for the centred form ([spec eq. (5.12)](crate::spec::enclosure)).
    pub(crate) velocity_jac: Tape,
    /// q -> mu(q), k x n row-major ([spec eq. (3.1)](crate::spec::scenes)).
    pub(crate) constraints: Tape,
    /// (q, v) -> p_a = <M(q) v + A(q), e_a(q)> ([spec eq. (4.8)](crate::spec::dynamics)),
    /// recorded on first use.
    momentum_d: std::sync::OnceLock<Tape>,
    /// (q, v) -> E_L(q, v) ([spec eq. (4.9)](crate::spec::dynamics)), recorded on first use.
    energy: std::sync::OnceLock<Tape>,
    /// (q, v) -> F_nh(q, v) ([spec eq. (4.6)](crate::spec::dynamics)).
    #[cfg(feature = "internals")]
    pub(crate) nh_force: Tape,
}

/// A summary: the scene's name and sizes (the tapes are long).
impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("scene", &self.name())
            .field("n", &self.n)
            .field("k", &self.k)
            .finish_non_exhaustive()
    }
}
/// The widest box [`Model::explain_stop`] looks at, relative to `1 + |q_i|`.
pub(crate) use crate::enclosure::WIDEST;

/// Largest number of coordinates a scene may have.
pub const MAX_DIM: usize = 64;

/// A scene's data recorded once on tapes ([spec eq. (3.16)](crate::spec::scenes)): q -> M(q) (as given, row-major),
/// V(q), A(q), mu(q), E(q). It is itself a [`Scene`] (replaying the tapes over any scalar),
/// so everything downstream reads any scene, built-in, file or user type, the same way.
/// The mass matrix it hands on is the given one's upper triangle mirrored ([spec eq. (3.17)](crate::spec::scenes)).
#[derive(Clone, Debug)]
pub struct CompiledScene {
    description: Description,
    n: usize,
    k: usize,
    mass: Tape,
    potential: Tape,
    one_form: Option<Tape>,
    constraints: Tape,
    basis: Tape,
    /// When the basis is the one derived from the constraints ([spec eq. (3.15)](crate::spec::scenes)): the free
    /// coordinates and `q -> det B`, B the pivot block (the constraint columns of the other
    /// coordinates). Read only to name the cause of a refusal.
    derived: Option<(Vec<usize>, Tape)>,
}

fn rows<S: Clone>(flat: Vec<S>, r: usize, c: usize) -> Mat<S> {
    (0..r).map(|i| flat[i * c..(i + 1) * c].to_vec()).collect()
}

impl Scene for CompiledScene {
    fn name(&self) -> String {
        self.description.name.clone()
    }
    fn dim(&self) -> usize {
        self.n
    }
    fn n_constraints(&self) -> usize {
        self.k
    }
    fn description(&self) -> Description {
        self.description.clone()
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        rows(self.constraints.eval(q), self.k, self.n)
    }
    fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        let m = self.mass.eval(q);
        let n = self.n;
        (0..n)
            .map(|i| (0..n).map(|j| m[i.min(j) * n + i.max(j)].clone()).collect())
            .collect()
    }
    fn potential<S: Scalar>(&self, q: &[S]) -> S {
        self.potential.eval(q).swap_remove(0)
    }
    fn one_form<S: Scalar>(&self, q: &[S]) -> Option<Vec<S>> {
        self.one_form.as_ref().map(|t| t.eval(q))
    }
    fn basis<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        rows(self.basis.eval(q), self.n - self.k, self.n)
    }
}

/// Fixed sample configurations at which [`CompiledScene::compile`] checks the structure
/// ([spec eq. (3.17)](crate::spec::scenes)): components of varied sign and size, none a multiple of pi/2.
fn samples(n: usize) -> Vec<Vec<f64>> {
    let base = [
        0.3125, -0.71875, 1.15625, -0.4375, 0.90625, -1.40625, 0.5625,
    ];
    (0..3)
        .map(|s| {
            (0..n)
                .map(|i| base[(i + 2 * s) % base.len()] * (1.0 + s as f64 * 0.375))
                .collect()
        })
        .collect()
}

/// The most constraints whose pivot block is recorded for the messages of
/// [`Model::explain_stop`] (the cofactor expansion of `det B` costs about k! operations; a
/// derived basis takes at most 6, [spec (10.1)](crate::spec::scene_files)).
const MAX_PIVOT_K: usize = 6;

/// `Some((free, q -> det B))` when `sc`'s basis is the one derived from its constraints and
/// free coordinates ([spec eq. (3.15)](crate::spec::scenes)), B the pivot block: the basis recorded equals the
/// derived one at the sample configurations (to 1e-9). Only names a cause in a refusal's
/// message; nothing is proved with it.
fn derived_pivot<Sc: Scene + ?Sized>(
    sc: &Sc,
    basis: &Tape,
    free: &[usize],
    n: usize,
    k: usize,
) -> Option<(Vec<usize>, Tape)> {
    if k > MAX_PIVOT_K {
        return None;
    }
    let derived = Tape::record(n, |q| {
        derived_basis(&sc.constraints(q), free, n)
            .into_iter()
            .flatten()
            .collect()
    });
    let same = samples(n).iter().all(|q| {
        let (a, b) = (basis.eval(q), derived.eval(q));
        a.len() == b.len()
            && a.iter()
                .zip(&b)
                .all(|(x, y)| (x - y).abs() <= 1e-9 * (1.0 + x.abs()))
    });
    if !same {
        return None;
    }
    let dep: Vec<usize> = (0..n).filter(|i| !free.contains(i)).collect();
    let pivot = Tape::record(n, |q| {
        let mu = sc.constraints(q);
        let block: Mat<Tracer> = mu
            .iter()
            .map(|r| dep.iter().map(|&c| r[c]).collect())
            .collect();
        vec![det(&block)]
    });
    Some((free.to_vec(), pivot))
}

/// `q` as [`fmt_q`] writes it, formatted only when displayed.
struct AtQ<'a>(&'a [Interval]);

impl std::fmt::Display for AtQ<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&fmt_q(self.0))
    }
}

fn fmt_q(q: &[Interval]) -> String {
    let v: Vec<String> = q
        .iter()
        .map(|x| {
            if x.inf() == x.sup() {
                format!("{}", x.inf())
            } else {
                format!("[{}, {}]", x.inf(), x.sup())
            }
        })
        .collect();
    format!("({})", v.join(", "))
}

impl CompiledScene {
    /// Record `sc`'s data on tapes and check its structure ([spec eq. (3.17)](crate::spec::scenes)): sizes, a mass
    /// matrix symmetric (identical entries, or not proved different at the sample points),
    /// basis rows in ker mu at the sample points. Input errors name what is wrong.
    pub fn compile<Sc: Scene + ?Sized>(sc: &Sc) -> Result<CompiledScene, Error> {
        let mut description = sc.description();
        let name = description.name.clone();
        let n = sc.dim();
        if n == 0 || n > MAX_DIM {
            return Err(Error::input_at(
                InputKind::Scene(name.clone()),
                format!("scene `{name}`: {n} coordinates (1 to {MAX_DIM} allowed)"),
            ));
        }
        let mut sizes_ok = Ok(());
        let mut k = 0;
        let constraints = Tape::record(n, |q| {
            let mu = sc.constraints(q);
            k = mu.len();
            if let Some((a, r)) = mu.iter().enumerate().find(|(_, r)| r.len() != n) {
                sizes_ok = Err(format!(
                    "constraint row {} has {} entries, not {n}",
                    a + 1,
                    r.len()
                ));
            }
            mu.into_iter().flatten().collect()
        });
        let size_error = |m: String| {
            Error::input_at(
                InputKind::Scene(name.clone()),
                format!("scene `{name}`: {m}"),
            )
        };
        sizes_ok.map_err(size_error)?;
        if k == 0 || k >= n {
            return Err(size_error(format!(
                "{k} constraints for {n} coordinates (1 to n - 1 = {} allowed)",
                n - 1
            )));
        }
        let free = sc.free();
        let mut distinct = free.clone();
        distinct.sort_unstable();
        distinct.dedup();
        if free.len() != n - k || distinct.len() != free.len() || free.iter().any(|&i| i >= n) {
            return Err(size_error(format!(
                "the free coordinates must be n - k = {} distinct indices below {n} (got {free:?})",
                n - k
            )));
        }
        let mut mass_ok = Ok(());
        let mut mirror = Vec::new();
        let mass = Tape::record(n, |q| {
            let m = sc.mass(q);
            if m.len() != n || m.iter().any(|r| r.len() != n) {
                mass_ok = Err(format!("the mass matrix must be {n} x {n}"));
                return vec![Tracer::zero(); n * n];
            }
            for i in 0..n {
                for j in i + 1..n {
                    if m[i][j].index() != m[j][i].index() {
                        mirror.push((i, j));
                    }
                }
            }
            m.into_iter().flatten().collect()
        });
        mass_ok.map_err(size_error)?;
        let potential = Tape::record(n, |q| vec![sc.potential(q)]);
        let mut form_ok = Ok(());
        let a = Tape::record(n, |q| match sc.one_form(q) {
            Some(a) if a.len() != n => {
                form_ok = Err(format!("the one-form has {} entries, not {n}", a.len()));
                vec![]
            }
            Some(a) => a,
            None => vec![],
        });
        form_ok.map_err(size_error)?;
        let one_form = (a.n_outputs() == n).then_some(a);
        let m = n - k;
        let mut basis_ok = Ok(());
        let basis = Tape::record(n, |q| {
            let e = sc.basis(q);
            if e.len() != m || e.iter().any(|r| r.len() != n) {
                basis_ok = Err(format!(
                    "the basis of D must be {m} rows of {n} entries (n - k = {m})"
                ));
                return vec![Tracer::zero(); m * n];
            }
            e.into_iter().flatten().collect()
        });
        basis_ok.map_err(size_error)?;
        let derived = derived_pivot(sc, &basis, &free, n, k);
        description.n = n;
        description.k = k;
        let c = CompiledScene {
            description,
            n,
            k,
            mass,
            potential,
            one_form,
            constraints,
            basis,
            derived,
        };
        for q in samples(n) {
            let q: Vec<Interval> = q.iter().map(|x| point(*x)).collect();
            match c.violation_at(&q, &mirror, false) {
                Some(Violation::Input(m)) => return Err(size_error(m)),
                _ => continue,
            }
        }
        Ok(c)
    }

    /// The first property of [spec eq. (3.17)](crate::spec::scenes) found violated at the configuration box `q`, if any:
    /// the structural ones (symmetry of the pairs `mirror`, basis rows in ker mu) and, when
    /// `at_use`, those that hold only where the scene is used (data defined, mass positive
    /// definite, full rank).
    fn violation_at(
        &self,
        q: &[Interval],
        mirror: &[(usize, usize)],
        at_use: bool,
    ) -> Option<Violation> {
        let (n, k) = (self.n, self.k);
        // written out only into a message (most calls find nothing)
        let at = AtQ(q);
        // `what`: the datum not proved finite, named in the message
        let undefined = |what: &str| {
            Violation::Undefined(format!(
                "the scene's data are not proved finite at q = {at}: {what} (a division by \
                 zero, or a logarithm, square root or power outside its domain)"
            ))
        };
        let Some(mass) = self.mass.eval_checked(q) else {
            return Some(undefined("the mass matrix"));
        };
        let Some(mu) = self.constraints.eval_checked(q) else {
            return Some(undefined("the constraints"));
        };
        let Some(e) = self.basis.eval_checked(q) else {
            return Some(
                self.singular_pivot(q, false)
                    .unwrap_or_else(|| undefined("the basis of D")),
            );
        };
        if self.potential.eval_checked(q).is_none() {
            return Some(undefined("the potential"));
        }
        if self
            .one_form
            .as_ref()
            .is_some_and(|t| t.eval_checked(q).is_none())
        {
            return Some(undefined("the one-form"));
        }
        for &(i, j) in mirror {
            if mass[i * n + j].disjoint(mass[j * n + i]) {
                return Some(Violation::Input(format!(
                    "the mass matrix is not symmetric: entries ({}, {}) and ({}, {}) differ at q = {at}",
                    i + 1,
                    j + 1,
                    j + 1,
                    i + 1
                )));
            }
        }
        for a in 0..n - k {
            for b in 0..k {
                let r = (0..n).fold(point(0.0), |acc, i| {
                    mu[b * n + i].mul_add(e[a * n + i], acc)
                });
                if !r.contains(0.0) {
                    return Some(Violation::Input(format!(
                        "basis row {} is not in ker mu: mu^{} . e_{} = [{:e}, {:e}] at q = {at}",
                        a + 1,
                        b + 1,
                        a + 1,
                        r.inf(),
                        r.sup()
                    )));
                }
            }
        }
        if !at_use {
            return None;
        }
        // Positive definite: Cholesky in interval arithmetic, every pivot proved > 0.
        let mut l: Vec<Interval> = (0..n * n)
            .map(|i| mass[(i / n).min(i % n) * n + (i / n).max(i % n)])
            .collect();
        for p in 0..n {
            let d = l[p * n + p];
            if !(finite(d) && d.inf() > 0.0) {
                return Some(Violation::Indefinite(format!(
                    "the mass matrix is not proved positive definite at q = {at} (pivot {} of \
                     its Cholesky factorization is [{:e}, {:e}])",
                    p + 1,
                    d.inf(),
                    d.sup()
                )));
            }
            for r in p + 1..n {
                let f = l[r * n + p] / d;
                for c in p + 1..n {
                    l[r * n + c] = (-f).mul_add(l[p * n + c], l[r * n + c]);
                }
            }
        }
        // Full rank of [mu; E] (n x n): Gaussian elimination with pivots chosen by their
        // smallest magnitude; a pivot containing 0 is no proof.
        let mut a: Vec<Vec<Interval>> = (0..k)
            .map(|b| mu[b * n..(b + 1) * n].to_vec())
            .chain((0..n - k).map(|r| e[r * n..(r + 1) * n].to_vec()))
            .collect();
        for p in 0..n {
            let best = (p..n).max_by(|&x, &y| a[x][p].mig().total_cmp(&a[y][p].mig()))?;
            a.swap(p, best);
            let d = a[p][p];
            if d.contains(0.0) || !finite(d) {
                if let Some(v) = self.singular_pivot(q, true) {
                    return Some(v);
                }
                return Some(Violation::Rank(format!(
                    "the constraints and the basis of D are not proved of full rank at q = {at} \
                     (where the basis is derived, its pivot block is singular or nearly so)"
                )));
            }
            for r in p + 1..n {
                let f = a[r][p] / d;
                for c in p + 1..n {
                    a[r][c] = (-f).mul_add(a[p][c], a[r][c]);
                }
            }
        }
        None
    }
}

impl CompiledScene {
    /// When the basis is derived ([spec eq. (3.15)](crate::spec::scenes)) and the determinant of its pivot block
    /// is not proved nonzero on the box `q` (or, `rank_failed`, the rank of `[mu; E]` was
    /// not proved there): that, naming the block's coordinates and its determinant.
    fn singular_pivot(&self, q: &[Interval], rank_failed: bool) -> Option<Violation> {
        let (free, pivot) = self.derived.as_ref()?;
        let d = *pivot.eval(q).first()?;
        let singular = d.contains(0.0) || !finite(d);
        if !singular && !rank_failed {
            return None;
        }
        let names = &self.description.coordinates;
        let name = |i: usize| {
            names
                .get(i)
                .cloned()
                .unwrap_or_else(|| format!("q{}", i + 1))
        };
        let dep: Vec<String> = (0..self.n)
            .filter(|i| !free.contains(i))
            .map(name)
            .collect();
        let free: Vec<String> = free.iter().map(|&i| name(i)).collect();
        Some(Violation::Rank(format!(
            "the derived basis of D (free coordinates {}) is not proved regular at q = {}: \
             its pivot block, the constraints' columns of {}, has determinant [{:e}, {:e}], {}",
            free.join(", "),
            fmt_q(q),
            dep.join(", "),
            d.inf(),
            d.sup(),
            if singular {
                "not proved nonzero"
            } else {
                "so small that the rank of the constraints and the basis is not proved"
            }
        )))
    }
}

enum Violation {
    /// A property the scene must have (exit 2).
    Input(String),
    /// The mass matrix not proved positive definite (exit 2 at a query's start, [spec eq.
    /// (3.17)](crate::spec::scenes); cause `mass` along a motion).
    Indefinite(String),
    /// Data not proved defined (exit 3).
    Undefined(String),
    /// Rank not proved (exit 3).
    Rank(String),
}

/// The reduced vector field of [spec eq. (4.4)](crate::spec::dynamics) at x = (q, u), generic over the scalar.
pub fn reduced_field<Sc: Scene, S: Scalar>(sc: &Sc, x: &[S]) -> Vec<S> {
    let n = sc.dim();
    let (qd, ud) = Geometry::at(sc, &x[..n]).reduced_field(&x[n..]);
    qd.into_iter().chain(ud).collect()
}

/// The time-reversed field `-F(x)` of [spec (5.17)](crate::spec::enclosure).
fn reversed_field<Sc: Scene, S: Scalar>(sc: &Sc, x: &[S]) -> Vec<S> {
    reduced_field(sc, x).into_iter().map(|y| -y).collect()
}

impl Model {
    /// The number of coordinates n.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The number of constraints k.
    pub fn k(&self) -> usize {
        self.k
    }

    /// The scene as compiled (a [`Scene`] itself: its constraints, mass, basis at any point,
    /// over any scalar).
    pub fn scene(&self) -> &CompiledScene {
        &self.scene
    }

    /// x' = -F(x) and its variational equation: its flow over a time s >= 0 is the flow of
    /// x' = F(x) over -s ([spec (5.17)](crate::spec::enclosure)). Recorded on first use.
    pub(crate) fn reversed(&self) -> &System {
        self.reversed.get_or_init(|| {
            let s = &*self.scene;
            let shared = self.scene.clone();
            System::record(
                self.state_dim(),
                self.n - self.k,
                |x| reversed_field(s, x),
                move |x| reversed_field(&*shared, x),
            )
        })
    }

    /// The field with the action appended ([spec eq. (6.8)](crate::spec::exact_discrete)).
    /// Recorded on first use: a model that only flows never pays for it.
    pub(crate) fn action_system(&self) -> &System {
        self.with_action.get_or_init(|| {
            let s = &*self.scene;
            let shared = self.scene.clone();
            System::record(
                self.state_dim() + 1,
                0,
                |x| field_with_action(s, x),
                move |x| field_with_action(&*shared, x),
            )
        })
    }

    /// (q, v) -> p_a ([spec eq. (4.8)](crate::spec::dynamics)). Recorded on first use.
    pub(crate) fn momentum_tape(&self) -> &Tape {
        self.momentum_d.get_or_init(|| {
            let (s, n) = (&*self.scene, self.n);
            Tape::record(2 * n, |x| Geometry::at(s, &x[..n]).momentum_d(&x[n..]))
        })
    }

    /// (q, v) -> E_L(q, v) ([spec eq. (4.9)](crate::spec::dynamics)). Recorded on first use.
    pub(crate) fn energy_tape(&self) -> &Tape {
        self.energy.get_or_init(|| {
            let (s, n) = (&*self.scene, self.n);
            Tape::record(2 * n, |x| {
                vec![crate::dynamics::energy(s, &x[..n], &x[n..])]
            })
        })
    }

    /// The tape of x' = F(x) and its variational equation (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn dynamics(&self) -> &System {
        &self.dynamics
    }

    /// The tape of the field with the action appended ([spec eq. (6.8)](crate::spec::exact_discrete)) (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn with_action(&self) -> &System {
        self.action_system()
    }

    /// The tape of x -> v = E(q)^T u (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn velocity(&self) -> &crate::tape::Tape {
        &self.velocity
    }

    /// The tape of x -> (v, Dv/Dx) (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn velocity_jac(&self) -> &crate::tape::Tape {
        &self.velocity_jac
    }

    /// The tape of q -> mu(q) (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn constraints(&self) -> &crate::tape::Tape {
        &self.constraints
    }

    /// The tape of (q, v) -> p_a (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn momentum_d(&self) -> &crate::tape::Tape {
        self.momentum_tape()
    }

    /// The tape of (q, v) -> E_L(q, v) (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn energy(&self) -> &crate::tape::Tape {
        self.energy_tape()
    }

    /// The tape of (q, v) -> F_nh(q, v) (internals feature).
    #[cfg(feature = "internals")]
    #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
    pub fn nh_force(&self) -> &crate::tape::Tape {
        &self.nh_force
    }

    /// Compile any scene ([spec eq. (4.11)](crate::spec::dynamics)): record its data and check their structure
    /// ([`CompiledScene::compile`]), then record the dynamics and the derived maps on tapes.
    pub fn new<Sc: Scene + ?Sized>(scene: &Sc) -> Result<Model, Error> {
        let scene = std::sync::Arc::new(CompiledScene::compile(scene)?);
        let s = &*scene;
        let (n, k) = (s.n, s.k);
        let d = 2 * n - k;
        let shared = scene.clone();
        let dynamics = System::record(
            d,
            n - k,
            |x| reduced_field(s, x),
            move |x| reduced_field(&*shared, x),
        );
        let velocity = Tape::record(d, |x| Geometry::at(s, &x[..n]).velocity(&x[n..]));
        let velocity_jac =
            Tape::record_with_jacobian(d, |x| Geometry::at(s, &x[..n]).velocity(&x[n..]));
        let constraints = s.constraints.clone();
        #[cfg(feature = "internals")]
        let nh_force = Tape::record(2 * n, |x| Geometry::at(s, &x[..n]).nh_force(&x[n..]));
        Ok(Model {
            scene: scene.clone(),
            n,
            k,
            dynamics,
            reversed: std::sync::OnceLock::new(),
            with_action: std::sync::OnceLock::new(),
            velocity,
            velocity_jac,
            constraints,
            momentum_d: std::sync::OnceLock::new(),
            energy: std::sync::OnceLock::new(),
            #[cfg(feature = "internals")]
            nh_force,
        })
    }

    /// Check the scene at the configuration box `q` before it is used ([spec eq. (3.17)](crate::spec::scenes)): its data
    /// finite there, a symmetric positive definite mass matrix, the basis rows in ker mu,
    /// and [mu; E] of full rank. A property the scene lacks is an input error; data or a
    /// rank not proved at `q` are uncertified (the motion may still be fine elsewhere).
    pub fn check_at(&self, q: &[Interval]) -> Result<(), Error> {
        if q.len() != self.n {
            let at = InputKind::Dimension {
                what: "q".into(),
                got: q.len(),
                expected: self.n,
            };
            return Err(Error::input_at(
                at,
                format!(
                    "q has {} components, scene `{}` needs {}",
                    q.len(),
                    self.scene.description.name,
                    self.n
                ),
            ));
        }
        let mirror: Vec<(usize, usize)> = (0..self.n)
            .flat_map(|i| (i + 1..self.n).map(move |j| (i, j)))
            .collect();
        let name = &self.scene.description.name;
        match self.scene.violation_at(q, &mirror, true) {
            None => Ok(()),
            Some(Violation::Input(m) | Violation::Indefinite(m)) => Err(Error::input_at(
                InputKind::Scene(name.clone()),
                format!("scene `{name}`: {m}"),
            )),
            Some(Violation::Undefined(m)) => Err(Error::refused(
                crate::Reason::Undefined,
                format!("scene `{name}`: {m}"),
            )),
            Some(Violation::Rank(m)) => Err(Error::refused(
                crate::Reason::Undefined,
                format!("scene `{name}`: {m}"),
            )
            .with_cause(Cause::Basis)),
        }
    }

    /// Why a flow cannot be carried on from the state box `x = (q, u)` when its steps have
    /// shrunk to `h` (0: no step taken): the first of the boxes `q + [-r, r]` with
    /// `r_i = s |v_i| + 2^-48 8^j (1 + |q_i|)`, `s = 2^j h` for j = 0 to 8 while every
    /// `r_i <= 2^-6 (1 + |q_i|)` (the configurations the next few hundred such steps could
    /// reach, and the rounding-level neighbourhood of `q`), on which the scene's data are
    /// not proved defined or regular ([spec eqs. (3.17)](crate::spec::scenes), (5.18)), in words; `None` when they
    /// are on all of them. Only a diagnosis for a refusal's message: nothing is proved or
    /// answered with it.
    pub(crate) fn explain_stop(&self, x: &[Interval], h: f64) -> Option<(Cause, String)> {
        let n = self.n;
        let q = x.get(..n)?;
        let v = self.velocity.eval_checked(x);
        let h = if h.is_finite() { h.max(0.0) } else { 0.0 };
        for j in 0..=8 {
            let s = h * f64::powi(2.0, j);
            let rel = f64::powi(2.0, 3 * j - 48);
            let r: Vec<f64> = q
                .iter()
                .enumerate()
                .map(|(i, qi)| {
                    let speed = v.as_ref().map_or(0.0, |v| v[i].mag());
                    s * speed + rel * (1.0 + qi.mag())
                })
                .collect();
            // wider boxes say little of the state: interval checks of rank and definiteness
            // fail on them from overestimation alone
            if r.iter()
                .zip(q)
                .any(|(r, qi)| r.is_nan() || *r > WIDEST * (1.0 + qi.mag()))
            {
                break;
            }
            let b: Vec<Interval> = q
                .iter()
                .zip(&r)
                .map(|(qi, r)| *qi + crate::scalar::iv(-r, *r))
                .collect();
            match self.scene.violation_at(&b, &[], true) {
                None => continue,
                Some(Violation::Input(m) | Violation::Undefined(m)) => {
                    return Some((Cause::Domain, m))
                }
                Some(Violation::Indefinite(m)) => return Some((Cause::Mass, m)),
                Some(Violation::Rank(m)) => return Some((Cause::Basis, m)),
            }
        }
        None
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.scene.description.name
    }

    /// The names of the coordinates `q`.
    pub(crate) fn coordinates(&self) -> &[String] {
        &self.scene.description.coordinates
    }

    /// Dimension of the reduced state, 2n - k.
    pub fn state_dim(&self) -> usize {
        2 * self.n - self.k
    }
}
