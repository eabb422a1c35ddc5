//! A scene compiled once into tapes (spec/04-dynamics.md, eq. (4.11)): every later object
//! (validated flow, retractions, float schemes) replays these tapes, so the float and the
//! interval computations run the same program.

use crate::dynamics::Geometry;
use crate::scalar::{Dual, Scalar};
use crate::scene::{AnyScene, Scene};
use crate::tape::Tape;
use crate::with_scene;

/// The reduced state x = (q, u): the dimension is n + (n - k).
pub struct Model {
    pub scene: AnyScene,
    /// Number of coordinates n.
    pub n: usize,
    /// Number of constraints k.
    pub k: usize,
    /// x' = F(x), x = (q, u) (spec eq. (4.4)).
    pub field: Tape,
    /// (x, V) -> (F(x), DF(x) V), V a d x d matrix row-major (spec eq. (5.6)).
    pub field_var: Tape,
    /// x -> v = E(q)^T u (spec eq. (4.2)).
    pub velocity: Tape,
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
        let field = with_scene!(&scene, s => Tape::record(d, |x| reduced_field(s, x)));
        let field_var = with_scene!(&scene, s => Tape::record(d + d * d, |xv| {
            let x: Vec<Dual<_>> = (0..d)
                .map(|i| Dual::new(xv[i], xv[d + i * d..d + (i + 1) * d].to_vec()))
                .collect();
            let f = reduced_field(s, &x);
            let mut out: Vec<_> = f.iter().map(|fi| fi.v).collect();
            for fi in &f {
                out.extend((0..d).map(|j| fi.der(j)));
            }
            out
        }));
        let velocity = with_scene!(&scene, s => Tape::record(d, |x| {
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
            field,
            field_var,
            velocity,
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
