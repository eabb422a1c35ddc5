//! A scene the crate does not have, written by a user as a Rust type: the planar unicycle
//! (a blade on a horizontal plane, no gravity) with mass m and moment of inertia J,
//!
//!     L = m/2 (xd^2 + yd^2) + J/2 thetad^2,   constraint -sin(theta) xd + cos(theta) yd = 0,
//!
//! given by its name, its size, its constraint and its mass only: the basis of D is the
//! derived one with free coordinates (x, theta), e1 = (1, tan theta, 0), e2 = (0, 0, 1)
//! (spec eq. (3.15)), so u = (xd, thetad).
//!
//! Independent reference, derived by hand: no force acts along the blade and no torque, so
//! the speed along the blade s and the turning rate w are constant:
//!     theta(t) = theta0 + w t,
//!     x(t) = x0 + (s / w) (sin theta(t) - sin theta0),
//!     y(t) = y0 - (s / w) (cos theta(t) - cos theta0),
//! with s = u1 / cos(theta0) (xd = s cos theta) and w = u2. It is evaluated here in interval
//! arithmetic, so a certified enclosure must contain it.

#![allow(clippy::needless_range_loop)] // loops over coordinates mirror the formulas

use dalembert::oracle::{check_trajectory, CheckOptions};
use dalembert::scalar::{point, Scalar};
use dalembert::scene::{diagonal, Mat, Scene};
use dalembert::schemes::{NewtonOptions, Scheme, SchemeKind};
use dalembert::{exact, flow, Error, FlowOptions, Model, Reason};
use inari::Interval;

struct Unicycle {
    m: f64,
    j: f64,
}

impl Scene for Unicycle {
    fn name(&self) -> String {
        "unicycle".into()
    }
    fn dim(&self) -> usize {
        3
    }
    fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
        vec![vec![-q[2].sin(), q[2].cos(), S::zero()]]
    }
    fn mass<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
        diagonal(&[self.m, self.m, self.j])
    }
    fn free(&self) -> Vec<usize> {
        vec![0, 2]
    }
}

fn unicycle() -> Model {
    Model::new(&Unicycle { m: 2.0, j: 0.75 }).unwrap()
}

/// The closed form at time t, in interval arithmetic.
fn closed_form(q0: [f64; 3], u: [f64; 2], t: f64) -> [Interval; 3] {
    let (th0, t) = (point(q0[2]), point(t));
    let s = point(u[0]) / th0.cos();
    let w = point(u[1]);
    let th = th0 + w * t;
    [
        point(q0[0]) + s / w * (th.sin() - th0.sin()),
        point(q0[1]) - s / w * (th.cos() - th0.cos()),
        th,
    ]
}

fn overlaps(a: dalembert::Interval, b: Interval) -> bool {
    !a.disjoint(b)
}

#[test]
fn the_derived_basis_is_the_hand_computed_one() {
    let m = unicycle();
    let q = [0.3, -1.2, 0.7];
    let e = m.scene().basis(&q);
    assert_eq!(e[0][0], 1.0);
    assert!((e[0][1] - 0.7f64.tan()).abs() <= 2.0 * f64::EPSILON * 0.7f64.tan().abs());
    assert_eq!((e[0][2], e[1][0], e[1][1], e[1][2]), (0.0, 0.0, 0.0, 1.0));
    assert_eq!((m.n(), m.k()), (3, 1));
}

#[test]
fn certified_flow_contains_the_closed_form() {
    let m = unicycle();
    let cases = [
        ([0.0, 0.0, 0.0], [0.8, 0.8], 0.5),
        ([1.0, -2.0, 0.4], [0.3, -0.3], 3.0),
        ([-0.5, 0.25, -1.0], [-1.5, 0.2], 10.0), // theta stays in (-pi/2, pi/2)
    ];
    for (q0, u, t) in cases {
        let e = flow(&m, &q0, &u, t, &FlowOptions::default()).unwrap();
        let r = closed_form(q0, u, t);
        for i in 0..3 {
            assert!(
                overlaps(e.q[i], r[i]),
                "q{i} at t = {t}: [{}, {}] misses [{}, {}]",
                e.q[i].inf(),
                e.q[i].sup(),
                r[i].inf(),
                r[i].sup()
            );
            assert!(e.q[i].wid() < 1e-11, "width {}", e.q[i].wid());
        }
    }
}

/// Crossing theta = pi/2, where the derived basis (1, tan theta, 0) is singular, is refused
/// (exit 3), never answered: the free coordinate x stops being a coordinate of D there.
#[test]
fn the_derived_basis_singularity_is_a_refusal() {
    let m = unicycle();
    let r = flow(
        &m,
        &[0.0, 0.0, 1.4],
        &[0.5, 1.0],
        1.0,
        &FlowOptions::default(),
    );
    // proved up to a time before the crossing at t = pi/2 - 1.4, never past it (the steps
    // shrink towards it, so the refusal may be the step budget's)
    match &r {
        Err(Error::Uncertified(refusal)) => {
            let crossing = std::f64::consts::FRAC_PI_2 - 1.4;
            assert!(refusal.reached.is_some_and(|t| t < crossing), "{r:?}");
        }
        _ => panic!("{r:?}"),
    }
    // starting on the singularity: the basis is not proved regular there
    let r = flow(
        &m,
        &[0.0, 0.0, std::f64::consts::FRAC_PI_2],
        &[0.5, 1.0],
        0.1,
        &FlowOptions::default(),
    );
    assert_eq!(
        r.as_ref().err().and_then(Error::reason),
        Some(Reason::Undefined),
        "{r:?}"
    );
}

#[test]
fn retract_and_step_on_a_pair_of_the_exact_motion() {
    let m = unicycle();
    let (q0, u, h) = ([0.2, -0.1, 0.3], [0.6, 0.9], 0.25);
    let r1 = closed_form(q0, u, h);
    let q1: Vec<f64> = r1.iter().map(|x| x.mid()).collect();
    let (iq0, iq1): (Vec<dalembert::Interval>, Vec<dalembert::Interval>) = (
        q0.iter().map(|x| dalembert::Interval::point(*x)).collect(),
        q1.iter().map(|x| dalembert::Interval::point(*x)).collect(),
    );
    let opts = FlowOptions::default();
    let r = exact::retract(&m, &iq0, &iq1, h, &opts).unwrap();
    // u0 = (xd, thetad) at t = 0 of the motion through q0 and q1: u up to q1's rounding
    assert!(r.u0[0].inf() - 1e-12 <= u[0] && u[0] <= r.u0[0].sup() + 1e-12);
    assert!(r.u0[1].inf() - 1e-12 <= u[1] && u[1] <= r.u0[1].sup() + 1e-12);
    assert!(r.s[0].mag() < 1e-14, "defect {:?}", r.s[0].sup());
    let s = exact::step(&m, &iq0, &iq1, h, &opts).unwrap();
    let r2 = closed_form(q0, u, 2.0 * h);
    for i in 0..3 {
        // q2 of the exact motion through (q0, q1 + N s), s ~ 1e-16: within 1e-13 of the
        // closed form through (q0, u)
        let gap = (s.q2[i].mid() - r2[i].mid()).abs();
        assert!(gap < 1e-13, "q2[{i}] off by {gap}");
    }
}

#[test]
fn mla_on_the_user_scene_passes_the_oracle() {
    let m = unicycle();
    let (q0, u, h) = ([0.0, 0.0, 0.1], [0.5, 0.4], 0.1);
    let q1: Vec<f64> = closed_form(q0, u, h).iter().map(|x| x.mid()).collect();
    let mla = Scheme::new(&m, SchemeKind::Mla);
    let traj = mla
        .integrate(&q0, &q1, h, 20, &NewtonOptions::default())
        .unwrap();
    let v = check_trajectory(&m, h, &traj.q, &CheckOptions::default()).unwrap();
    // MLA is second order: 20 steps of 0.1 stay within h^2 of the exact discrete flow
    assert!(v.max_distance.sup() <= h * h, "{}", v.max_distance.sup());
    // and not by accident: it is not the exact flow either
    assert!(v.max_distance.sup() > 0.0);
    // every pair of MLA's is close to M_h^{e,nh} (second order: defect O(h^3))
    assert_eq!(v.defect.len(), 20);
    for (k, d) in v.defect.iter().enumerate() {
        assert!(d[0].mag() < h * h * h, "pair {k}: defect {}", d[0].mag());
    }
    // the energy of the exact motion through each pair stays that of the first pair to
    // O(h^2): MLA conserves no energy exactly, but nothing here drifts
    assert_eq!(v.energy_error.len(), 20);
    for (k, e) in v.energy_error.iter().enumerate() {
        assert!(e.mag() < h * h, "pair {k}: energy error {}", e.mag());
    }
}

/// A user scene is checked before use: a mass matrix that is not symmetric, and one that
/// is not positive definite at the configuration asked about, are input errors.
#[test]
fn a_broken_user_scene_is_refused_with_the_reason() {
    struct Lopsided;
    impl Scene for Lopsided {
        fn name(&self) -> String {
            "lopsided".into()
        }
        fn dim(&self) -> usize {
            2
        }
        fn constraints<S: Scalar>(&self, q: &[S]) -> Mat<S> {
            vec![vec![q[1].clone(), S::one()]]
        }
        fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S> {
            vec![vec![S::one(), q[0].clone()], vec![S::zero(), S::one()]]
        }
    }
    let e = Model::new(&Lopsided).expect_err("a non-symmetric mass is refused");
    assert!(
        matches!(e, Error::Input(_)) && e.message().contains("symmetric"),
        "{e}"
    );

    struct Indefinite;
    impl Scene for Indefinite {
        fn name(&self) -> String {
            "indefinite".into()
        }
        fn dim(&self) -> usize {
            2
        }
        fn constraints<S: Scalar>(&self, _q: &[S]) -> Mat<S> {
            vec![vec![S::zero(), S::one()]]
        }
        fn mass<S: Scalar>(&self, q: &[S]) -> Mat<S> {
            vec![vec![q[0].clone(), S::zero()], vec![S::zero(), S::one()]]
        }
    }
    let m = Model::new(&Indefinite).unwrap();
    let e = flow(&m, &[-1.0, 0.0], &[1.0], 1.0, &FlowOptions::default()).unwrap_err();
    assert!(
        matches!(e, Error::Input(_)) && e.message().contains("positive definite"),
        "{e}"
    );
    assert!(flow(&m, &[1.0, 0.0], &[0.1], 0.5, &FlowOptions::default()).is_ok());
}
