//! A scene compiled once into tapes (spec/04-dynamics.md, eq. (4.11)): every later object
//! (validated flow, retractions, float schemes) replays these tapes, so the float and the
//! interval computations run the same program.

use crate::dynamics::Geometry;
use crate::scalar::{Dual, Scalar};
use crate::scene::{AnyScene, Scene};
use crate::tape::{Tape, Tracer};
use crate::with_scene;

/// An autonomous ODE `x' = F(x)` as tapes: `field: x -> F(x)`,
/// `field_var: (x, V) -> (F(x), DF(x) V)`, V a d x d matrix row-major (spec eq. (5.6)), and
/// `field_var_tail`, the same for a d x `tail` matrix W: the derivatives with respect to
/// the last `tail` components of the initial state only (the shooting Jacobian of the
/// retraction needs D x / D u0, not D x / D q0).
pub struct System {
    pub field: Tape,
    pub field_var: Tape,
    pub field_var_tail: Tape,
}

impl System {
    /// The number of columns of `field_var_tail` (its inputs are `d + d tail`).
    pub fn tail(&self) -> usize {
        let d = self.field.n_inputs();
        (self.field_var_tail.n_inputs() - d)
            .checked_div(d)
            .unwrap_or(0)
    }
    /// Record `f` and its variational equation, f written once over any scalar.
    fn record(
        d: usize,
        tail: usize,
        f: impl Fn(&[Tracer]) -> Vec<Tracer>,
        fd: impl Fn(&[Dual<Tracer>]) -> Vec<Dual<Tracer>>,
    ) -> System {
        let var = |c: usize| {
            Tape::record(d + d * c, |xv| {
                let x: Vec<Dual<Tracer>> = (0..d)
                    .map(|i| Dual::new(xv[i], xv[d + i * c..d + (i + 1) * c].to_vec()))
                    .collect();
                let f = fd(&x);
                let mut out: Vec<Tracer> = f.iter().map(|fi| fi.v).collect();
                for fi in &f {
                    out.extend((0..c).map(|j| fi.der(j)));
                }
                out
            })
        };
        System {
            field: Tape::record(d, f),
            field_var: var(d),
            field_var_tail: var(tail),
        }
    }
}

/// The reduced field with the Lagrangian appended (spec eq. (6.8)).
pub fn field_with_action<Sc: Scene, S: Scalar>(sc: &Sc, x: &[S]) -> Vec<S> {
    let n = sc.dim();
    let d = x.len() - 1;
    let v = Geometry::at(sc, &x[..n]).velocity(&x[n..d]);
    let lag = crate::dynamics::lagrangian(sc, &x[..n], &v);
    let mut f = reduced_field(sc, &x[..d]);
    f.push(lag);
    f
}

/// The reduced state x = (q, u): the dimension is n + (n - k).
pub struct Model {
    pub scene: AnyScene,
    /// Number of coordinates n.
    pub n: usize,
    /// Number of constraints k.
    pub k: usize,
    /// x' = F(x), x = (q, u) (spec eq. (4.4)), and its variational equation.
    pub dynamics: System,
    /// The same with the action: (q, u, l)' = (F(q, u), L(q, E^T u)) (spec eq. (6.8)).
    pub with_action: System,
    /// x -> v = E(q)^T u (spec eq. (4.2)).
    pub velocity: Tape,
    /// x -> (v, Dv/Dx) for the centred form (spec eq. (5.12)).
    pub velocity_jac: Tape,
    /// q -> mu(q), k x n row-major (spec eq. (3.1)).
    pub constraints: Tape,
    /// (q, v) -> p_a = <M(q) v, e_a(q)> (spec eq. (4.8)).
    pub momentum_d: Tape,
    /// (q, v) -> E_L(q, v) (spec eq. (4.9)).
    pub energy: Tape,
    /// (q, v) -> F_nh(q, v) (spec eq. (4.6)).
    pub nh_force: Tape,
}

/// The reduced vector field of spec eq. (4.4) at x = (q, u), generic over the scalar.
pub fn reduced_field<Sc: Scene, S: Scalar>(sc: &Sc, x: &[S]) -> Vec<S> {
    let n = sc.dim();
    let (qd, ud) = Geometry::at(sc, &x[..n]).reduced_field(&x[n..]);
    qd.into_iter().chain(ud).collect()
}

impl Model {
    pub fn new(scene: AnyScene) -> Model {
        let (n, k) = with_scene!(&scene, s => (s.dim(), s.n_constraints()));
        let d = 2 * n - k;
        let dynamics = with_scene!(&scene, s => System::record(d, n - k, |x| reduced_field(s, x), |x| reduced_field(s, x)));
        let with_action = with_scene!(&scene, s => System::record(
            d + 1,
            0,
            |x| field_with_action(s, x),
            |x| field_with_action(s, x),
        ));
        let velocity = with_scene!(&scene, s => Tape::record(d, |x| {
            Geometry::at(s, &x[..n]).velocity(&x[n..])
        }));
        let velocity_jac = with_scene!(&scene, s => Tape::record_with_jacobian(d, |x| {
            Geometry::at(s, &x[..n]).velocity(&x[n..])
        }));
        let constraints = with_scene!(&scene, s => Tape::record(n, |q| {
            s.constraints(q).into_iter().flatten().collect()
        }));
        let momentum_d = with_scene!(&scene, s => Tape::record(2 * n, |x| {
            Geometry::at(s, &x[..n]).momentum_d(&x[n..])
        }));
        let energy = with_scene!(&scene, s => Tape::record(2 * n, |x| {
            vec![crate::dynamics::energy(s, &x[..n], &x[n..])]
        }));
        let nh_force = with_scene!(&scene, s => Tape::record(2 * n, |x| {
            Geometry::at(s, &x[..n]).nh_force(&x[n..])
        }));
        Model {
            scene,
            n,
            k,
            dynamics,
            with_action,
            velocity,
            velocity_jac,
            constraints,
            momentum_d,
            energy,
            nh_force,
        }
    }

    /// Dimension of the reduced state, 2n - k.
    pub fn state_dim(&self) -> usize {
        2 * self.n - self.k
    }
}
