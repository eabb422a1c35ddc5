//! The rolling disk, the sleigh and the contact oscillators: `rolling-disk` (k = 2),
//! `sleigh` (configuration-dependent mass matrix), `contact-oscillator` and its
//! non-reversible variant `contact-oscillator-nr`
//! (spec eqs. (3.6)-(3.9), closed forms (3.10)-(3.14)).
//!
//! 1. Soundness of `flow` against closed forms evaluated in interval arithmetic (inari,
//!    correctly rounded elementary functions, from the exact f64 inputs): the flow's
//!    enclosure and the reference enclosure must intersect in every component, and, so
//!    that the comparison is not vacuous, the flow's enclosures must be narrow. The
//!    reference formulas are themselves checked against RK4 in f64.
//! 2. Invariants as certified enclosures: the energy (and for the oscillator E_y and
//!    E - E_y) evaluated in intervals over the flow's enclosure must contain the initial
//!    value, computed in intervals from the exact inputs.
//! 3. k = 2 end to end on the rolling disk: `retract` (two defect components, member "no"
//!    off M_h^{e,nh}, "possible" on it), `step`, `integrate` (both schemes), `batch`.
//! 4. `dalembert scenes --json`.
//!
//! The MLA vs DLA energy comparison on these scenes is in tests/energy_disk_sleigh_oscillator.rs.
//!
//! Random cases come from SplitMix64 with fixed seeds: the same cases on every run.

// Index loops mirror the formulas (components i, j), as in the library.
#![allow(clippy::needless_range_loop)]

use crate::common::{describe, model, rk4, run, show, SplitMix64};
use dalembert::dynamics::Geometry;
use dalembert::elementary::asinh;
use dalembert::scalar::{iv, point as pt, Scalar};
use dalembert::scene::{Scene, Sleigh};
use dalembert::{FlowEnclosure, Model};
use inari::Interval;
use serde_json::Value;
use std::process::{Command, Stdio};

// ---------------------------------------------------------------------------------------
// Interval helpers.

/// sin(h)/h (= 1 at 0): Taylor series with the alternating remainder for |h| <= 1.
fn sinc(h: Interval) -> Interval {
    if h.mag() <= 1.0 {
        let x = h.sqr();
        // sum_{j < 12} (-1)^j x^j / (2j+1)!, remainder <= x^12 / 25!
        let mut fact = pt(1.0);
        let mut term_coef = Vec::new();
        for j in 0..=12u32 {
            if j > 0 {
                fact = fact * pt(f64::from(2 * j)) * pt(f64::from(2 * j + 1));
            }
            term_coef.push(pt(1.0) / fact);
        }
        let mut p = term_coef[11];
        for j in (0..11).rev() {
            p = term_coef[j] - x * p;
        }
        let mut r = term_coef[12];
        for _ in 0..12 {
            r *= pt(x.sup());
        }
        p + iv(-r.sup(), r.sup())
    } else {
        h.sin() / h
    }
}

/// The library's answers as inari intervals, for arithmetic.
fn ia(v: &[dalembert::Interval]) -> Vec<Interval> {
    v.iter().map(|x| Interval::from(*x)).collect()
}

/// Two enclosures of the same number must intersect; a failure is a bug of the reference.
fn meet(a: impl Into<Interval>, b: impl Into<Interval>, what: &str) -> Interval {
    let (a, b) = (a.into(), b.into());
    let m = a.intersection(b);
    assert!(!m.is_empty(), "{what}: {} vs {}", show(a), show(b));
    m
}

/// Every component of the flow meets the reference; returns the widest flow component
/// relative to max(1, |value|), and the widest reference component likewise.
fn check_against(
    e: &FlowEnclosure,
    q: &[Interval],
    u: &[Interval],
    v: &[Interval],
    ctx: &str,
) -> (f64, f64) {
    let (mut wf, mut wr) = (0.0f64, 0.0f64);
    let groups = [("q", &e.q, q), ("u", &e.u, u), ("v", &e.v, v)];
    for (name, got, want) in groups {
        assert_eq!(got.len(), want.len());
        for (i, (g, w)) in got.iter().zip(want.iter()).enumerate() {
            assert!(
                !g.intersection(*w).is_empty(),
                "{name}[{i}]: flow {} excludes the closed form {}\n{ctx}",
                show(*g),
                show(*w)
            );
            wf = wf.max(g.wid() / g.mag().max(1.0));
            wr = wr.max(w.wid() / w.mag().max(1.0));
        }
    }
    (wf, wr)
}

// ---------------------------------------------------------------------------------------
// 1. Rolling disk (spec eq. (3.10)).

/// Parameters (m, I, J, R).
type DiskParams = [f64; 4];

fn disk_model(p: &DiskParams) -> Model {
    model(
        "rolling-disk",
        &[("m", p[0]), ("I", p[1]), ("J", p[2]), ("R", p[3])],
    )
}

/// Spec eq. (3.10): thetad, phid constant; phi = phi0 + w2 t;
/// x = x0 + R w1 t cos(phi0 + w2 t/2) sinc(w2 t/2), y likewise with sin (exact for w2 = 0).
fn disk_exact(
    p: &DiskParams,
    q: [f64; 4],
    u: [f64; 2],
    t: f64,
) -> (Vec<Interval>, Vec<Interval>, Vec<Interval>) {
    let r = pt(p[3]);
    let (w1, w2, tt) = (pt(u[0]), pt(u[1]), pt(t));
    let half = w2 * tt * pt(0.5);
    let mid = pt(q[3]) + half;
    let travel = r * w1 * tt * sinc(half);
    let phi = pt(q[3]) + w2 * tt;
    let x = pt(q[0]) + travel * mid.cos();
    let y = pt(q[1]) + travel * mid.sin();
    let theta = pt(q[2]) + w1 * tt;
    let v = vec![r * w1 * phi.cos(), r * w1 * phi.sin(), w1, w2];
    (vec![x, y, theta, phi], vec![w1, w2], v)
}

#[test]
fn rolling_disk_reference_matches_rk4() {
    let p = [1.3, 0.4, 0.7, 0.8];
    for (q, u, t) in [
        ([0.1, -0.2, 0.3, 0.4], [1.1, -0.7], 3.0),
        ([0.0; 4], [0.5, 0.0], 2.0),
        ([1.0, 2.0, -1.0, 2.5], [-2.0, 3.0], 1.5),
    ] {
        let f = |x: &[f64; 6]| {
            [
                p[3] * x[4] * x[3].cos(),
                p[3] * x[4] * x[3].sin(),
                x[4],
                x[5],
                0.0,
                0.0,
            ]
        };
        let num = rk4(f, [q[0], q[1], q[2], q[3], u[0], u[1]], t, 20_000);
        let (eq, _, _) = disk_exact(&p, q, u, t);
        for i in 0..4 {
            assert!(
                (eq[i].mid() - num[i]).abs() < 1e-10,
                "{i}: {eq:?} vs {num:?}"
            );
        }
    }
}

/// The certified flow of the rolling disk encloses the closed form (3.10): random states
/// and parameters, phid = 0 exactly (the limit form), and long times.
#[test]
fn rolling_disk_flow_encloses_the_closed_form() {
    let mut g = SplitMix64(0x0d15_c0de);
    let mut cases: Vec<(DiskParams, [f64; 4], [f64; 2], f64)> = vec![
        ([1.0, 0.5, 0.25, 1.0], [0.0; 4], [1.2, 0.7], 0.5),
        ([1.0, 0.5, 0.25, 1.0], [0.0; 4], [1.2, 0.7], 50.0),
        ([1.0, 0.5, 0.25, 1.0], [0.0; 4], [1.2, 0.0], 50.0),
        (
            [1.0, 0.5, 0.25, 1.0],
            [0.3, -0.2, 0.1, 2.0],
            [-0.8, 0.0],
            200.0,
        ),
        (
            [2.0, 0.3, 1.5, 0.5],
            [1.0, 1.0, 1.0, -1.0],
            [0.9, -1.1],
            200.0,
        ),
    ];
    for _ in 0..12 {
        let p = [
            g.uniform(0.2, 3.0),
            g.uniform(0.1, 2.0),
            g.uniform(0.1, 2.0),
            g.uniform(0.2, 2.0),
        ];
        let q = [
            g.uniform(-3.0, 3.0),
            g.uniform(-3.0, 3.0),
            g.uniform(-3.0, 3.0),
            g.uniform(-3.0, 3.0),
        ];
        let w2 = if g.next_u64().is_multiple_of(3) {
            0.0
        } else {
            g.uniform(-2.0, 2.0)
        };
        let u = [g.uniform(-2.0, 2.0), w2];
        cases.push((p, q, u, g.uniform(0.0, 20.0)));
    }
    for (p, q, u, t) in cases {
        let m = disk_model(&p);
        let params = [("m", p[0]), ("I", p[1]), ("J", p[2]), ("R", p[3])];
        let ctx = describe("rolling-disk", &params, &q, &u, t);
        let e = run(&m, &q, &u, t).unwrap_or_else(|err| panic!("flow failed: {err}\n{ctx}"));
        let (rq, ru, rv) = disk_exact(&p, q, u, t);
        let (wf, wr) = check_against(&e, &rq, &ru, &rv, &ctx);
        // not vacuous: the flow pins the state (the reference is a few ulps wide)
        assert!(wr < 1e-12, "reference too wide {wr:e}\n{ctx}");
        assert!(wf < 1e-9 * t.max(1.0), "flow too wide {wf:e}\n{ctx}");
        // phid = 0 exactly: phi stays exactly phi0 and the disk rolls on a line
        if u[1] == 0.0 {
            assert!(e.q[3].contains(q[3]) && e.q[3].wid() == 0.0, "{:?}", e.q[3]);
        }
    }
}

/// k = 2: the multipliers solve the 2 x 2 system C lambda = -Gamma_L(Phi) (spec eq. (4.5))
/// in interval arithmetic, through the generic Geometry and through the model's tape, over
/// boxes of states; the result must contain the closed form lambda = m R u1 u2
/// (-sin phi, cos phi) (from M a = mu^T lambda with a = Edot^T u, spec eq. (3.10)) at every
/// corner and the centre of the box, and be narrow.
#[test]
fn rolling_disk_multipliers_solve_a_2x2_system_soundly() {
    use dalembert::scene::RollingDisk;
    let mut g = SplitMix64(0x2b2_0002);
    for _ in 0..40 {
        let sc = RollingDisk {
            m: g.uniform(0.2, 3.0),
            i: g.uniform(0.1, 2.0),
            j: g.uniform(0.1, 2.0),
            r: g.uniform(0.2, 2.0),
        };
        let mdl = Model::new(&dalembert::AnyScene::RollingDisk(sc)).unwrap();
        let q: Vec<f64> = (0..4).map(|_| g.uniform(-3.0, 3.0)).collect();
        let u = [g.uniform(-2.0, 2.0), g.uniform(-2.0, 2.0)];
        let rad = 1e-9;
        let qb: Vec<Interval> = q.iter().map(|x| iv(x - rad, x + rad)).collect();
        let ub: Vec<Interval> = u.iter().map(|x| iv(x - rad, x + rad)).collect();
        let geo = Geometry::at(&sc, &qb);
        let v = geo.velocity(&ub);
        let lam = geo.multiplier(&v);
        assert_eq!(lam.len(), 2);
        // F_nh through the recorded tape, over the same box
        let qv: Vec<Interval> = qb.iter().chain(&v).copied().collect();
        let f = mdl.nh_force().eval_checked(&qv).expect("F_nh enclosure");
        for (dq, du) in [
            (-1.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
            (1.0, -1.0),
            (0.0, 0.0),
        ] {
            let (phi, u1, u2) = (q[3] + dq * rad, u[0] + du * rad, u[1] - du * rad);
            let k = pt(sc.m) * pt(sc.r) * pt(u1) * pt(u2);
            let want = [-(k * pt(phi).sin()), k * pt(phi).cos()];
            for a in 0..2 {
                assert!(
                    !lam[a].intersection(want[a]).is_empty(),
                    "lambda[{a}] {} vs {}",
                    show(lam[a]),
                    show(want[a])
                );
            }
            // F_nh = lambda_1 mu^1 + lambda_2 mu^2 = (lambda_1, lambda_2, 0, 0)
            for (i, w) in [want[0], want[1], pt(0.0), pt(0.0)].iter().enumerate() {
                assert!(
                    !f[i].intersection(*w).is_empty(),
                    "F_nh[{i}] {}",
                    show(f[i])
                );
            }
        }
        for x in lam.iter().chain(&f) {
            assert!(x.wid() < 1e-6, "{}", show(*x));
        }
    }
}

// ---------------------------------------------------------------------------------------
// 2. Chaplygin sleigh (spec eqs. (3.11)-(3.13)).

/// Parameters (m, I, a).
type SleighParams = [f64; 3];

fn sleigh_model(p: &SleighParams) -> Model {
    model("sleigh", &[("m", p[0]), ("I", p[1]), ("a", p[2])])
}

/// Spec eq. (3.12): with K = I + m a^2, W = sqrt(K/m) |omega0|, V = sqrt(v0^2 + W^2),
/// c = a m V / K, alpha = asinh(v0 / W), s = c t + alpha:
///   v = V tanh s, omega = sign(omega0) sqrt(m/K) V / cosh s,
///   theta = theta0 + beta (gd s - gd alpha), beta = sign(omega0) sqrt(K / (m a^2)),
/// and, when K = 4 m a^2 (beta = 2 sign(omega0)), eq. (3.13) for the contact point.
/// Returns (q or None for x, y when eq. (3.13) does not apply, u, v).
fn sleigh_exact(
    p: &SleighParams,
    q: [f64; 3],
    u: [f64; 2],
    t: f64,
) -> (Vec<Interval>, Vec<Interval>, Vec<Interval>) {
    assert!(u[1] != 0.0 && p[2] > 0.0);
    let (m, a) = (pt(p[0]), pt(p[2]));
    let k = pt(p[1]) + m * a.sqr();
    let sigma = pt(u[1].signum());
    let w = (k / m).sqrt() * pt(u[1].abs());
    let vinf = (pt(u[0]).sqr() + w.sqr()).sqrt();
    let c = a * m * vinf / k;
    let alpha = asinh(pt(u[0]) / w);
    let s = c * pt(t) + alpha;
    let gd = |x: Interval| x.sinh().atan();
    let v = vinf * s.tanh();
    let omega = sigma * (m / k).sqrt() * vinf / s.cosh();
    let beta = sigma * (k / (m * a.sqr())).sqrt();
    let theta = pt(q[2]) + beta * (gd(s) - gd(alpha));
    let ratio = k / (m * a.sqr());
    let (xy, yy) = if ratio.inf() == 4.0 && ratio.sup() == 4.0 {
        // eq. (3.13), beta = 2 sigma
        let thc = pt(q[2]) - beta * gd(alpha);
        let f1 = |x: Interval| x.tanh().sqr() - x.cosh().ln();
        let f2 = |x: Interval| gd(x) - x.tanh() / x.cosh();
        let (d1, d2) = (f1(s) - f1(alpha), f2(s) - f2(alpha));
        let l = vinf / c;
        (
            pt(q[0]) + l * (thc.cos() * d1 - sigma * thc.sin() * d2),
            pt(q[1]) + l * (thc.sin() * d1 + sigma * thc.cos() * d2),
        )
    } else {
        (Interval::ENTIRE, Interval::ENTIRE)
    };
    let vel = vec![v * theta.cos(), v * theta.sin(), omega];
    (vec![xy, yy, theta], vec![v, omega], vel)
}

fn sleigh_field(p: &SleighParams) -> impl Fn(&[f64; 5]) -> [f64; 5] {
    let (m, i, a) = (p[0], p[1], p[2]);
    let k = i + m * a * a;
    move |x: &[f64; 5]| {
        let (th, v, w) = (x[2], x[3], x[4]);
        [
            v * th.cos(),
            v * th.sin(),
            w,
            a * w * w,
            -(m * a / k) * v * w,
        ]
    }
}

#[test]
fn sleigh_reference_matches_rk4() {
    for p in [[1.0, 0.75, 0.5], [2.0, 0.375, 0.25], [1.3, 0.4, 0.9]] {
        for (q, u, t) in [
            ([0.1, -0.2, 0.3], [0.4, 1.1], 3.0),
            ([0.0; 3], [-0.6, -0.7], 5.0),
            ([1.0, 2.0, -1.0], [0.0, 2.0], 2.0),
        ] {
            let num = rk4(sleigh_field(&p), [q[0], q[1], q[2], u[0], u[1]], t, 40_000);
            let (eq, eu, _) = sleigh_exact(&p, q, u, t);
            let closed = [eq[0], eq[1], eq[2], eu[0], eu[1]];
            for i in 0..5 {
                if closed[i].is_entire() {
                    continue;
                }
                assert!(
                    (closed[i].mid() - num[i]).abs() < 1e-9,
                    "p={p:?} {i}: {closed:?} vs {num:?}"
                );
            }
            // the position form applies exactly when K = 4 m a^2
            let applies = !closed[0].is_entire();
            assert_eq!(
                applies,
                p[1] + p[0] * p[2] * p[2] == 4.0 * p[0] * p[2] * p[2]
            );
        }
    }
}

/// The certified flow of the sleigh encloses the closed form (3.12)-(3.13), and the energy
/// E = 1/2 qd^T M(q) qd evaluated over the enclosure contains the initial energy.
#[test]
fn sleigh_flow_encloses_the_closed_form_and_the_energy() {
    let mut g = SplitMix64(0x51e1_9400);
    let mut cases: Vec<(SleighParams, [f64; 3], [f64; 2], f64)> = vec![
        ([1.0, 0.75, 0.5], [0.0; 3], [0.3, 1.0], 0.5),
        ([1.0, 0.75, 0.5], [0.0; 3], [0.3, 1.0], 50.0),
        ([1.0, 0.75, 0.5], [0.0; 3], [-0.5, -0.8], 20.0),
        ([2.0, 0.375, 0.25], [1.0, -1.0, 2.0], [0.2, 0.6], 10.0),
        ([1.3, 0.4, 0.9], [0.5, 0.5, -0.5], [0.7, -1.2], 10.0),
    ];
    for _ in 0..8 {
        // half of the cases with I = 3 m a^2 exactly (dyadic m and a), where eq. (3.13)
        // gives the contact point too
        let beta2 = g.next_u64().is_multiple_of(2);
        let (m, a, i) = if beta2 {
            let m = (4 + g.next_u64() % 13) as f64 / 8.0;
            let a = (3 + g.next_u64() % 14) as f64 / 16.0;
            (m, a, 3.0 * m * a * a)
        } else {
            (
                g.uniform(0.5, 2.0),
                g.uniform(0.2, 1.0),
                g.uniform(0.1, 1.5),
            )
        };
        let q = [
            g.uniform(-2.0, 2.0),
            g.uniform(-2.0, 2.0),
            g.uniform(-3.0, 3.0),
        ];
        let mut w = g.uniform(-1.5, 1.5);
        if w.abs() < 0.05 {
            w = 0.5;
        }
        cases.push(([m, i, a], q, [g.uniform(-1.0, 1.0), w], g.uniform(0.0, 8.0)));
    }
    let mut with_position = 0;
    for (p, q, u, t) in cases {
        let m = sleigh_model(&p);
        let params = [("m", p[0]), ("I", p[1]), ("a", p[2])];
        let ctx = describe("sleigh", &params, &q, &u, t);
        let e = run(&m, &q, &u, t).unwrap_or_else(|err| panic!("flow failed: {err}\n{ctx}"));
        let (rq, ru, rv) = sleigh_exact(&p, q, u, t);
        if !rq[0].is_entire() {
            with_position += 1;
        }
        let (wf, wr) = check_against(&e, &rq[..], &ru, &rv, &ctx);
        assert!(wf < 1e-8, "flow too wide {wf:e}\n{ctx}");
        let _ = wr;
        // the closed form pins u and theta to near rounding (non-vacuous comparison)
        for x in ru.iter().chain(&rq[2..]) {
            assert!(x.wid() < 1e-11, "reference too wide {}\n{ctx}", show(*x));
        }
        // energy enclosure contains the initial energy
        let e0 = sleigh_energy(&m, &q.map(pt), &[pt(u[0]), pt(u[1])]);
        let et = sleigh_energy(&m, &ia(&e.q), &ia(&e.u));
        assert!(
            !et.intersection(e0).is_empty(),
            "energy {} vs {}\n{ctx}",
            show(et),
            show(e0)
        );
        assert!(et.wid() < 1e-8, "{}", show(et));
    }
    assert!(
        with_position >= 4,
        "too few cases with the position closed form"
    );
}

/// E = 1/2 v^T M(q) v + V(q) over boxes, v = E(q)^T u, by the model's tapes.
fn sleigh_energy(m: &Model, q: &[Interval], u: &[Interval]) -> Interval {
    let x: Vec<Interval> = q.iter().chain(u).copied().collect();
    let v = m.velocity().eval_checked(&x).unwrap();
    let qv: Vec<Interval> = q.iter().chain(&v).copied().collect();
    m.energy().eval_checked(&qv).unwrap()[0]
}

/// Asymptotic alignment: omega -> 0 and v -> sqrt(2E/m), proved at t = 50 from the
/// enclosure alone (the closed form gives |omega(50)| ~ 1e-11 here).
#[test]
fn sleigh_aligns_with_its_blade() {
    let p = [1.0, 0.75, 0.5];
    let m = sleigh_model(&p);
    let (q, u) = ([0.0, 0.0, 0.0], [0.3, 1.0]);
    let e = run(&m, &q, &u, 50.0).unwrap();
    let e0 = 0.5 * (p[0] * 0.09 + (p[1] + p[0] * p[2] * p[2]) * 1.0);
    let vinf = (2.0 * e0 / p[0]).sqrt();
    assert!(e.u[1].mag() < 1e-9, "omega(50) = {}", show(e.u[1]));
    assert!(
        (Interval::from(e.u[0]) - pt(vinf)).mag() < 1e-9,
        "v(50) = {} vs {vinf}",
        show(e.u[0])
    );
    // and the heading has converged: theta(50) and theta(49) agree to the same order
    let e49 = run(&m, &q, &u, 49.0).unwrap();
    assert!((Interval::from(e.q[2]) - Interval::from(e49.q[2])).mag() < 1e-9);
}

/// The configuration-dependent mass matrix through the generic Geometry: M(q) as in spec
/// eq. (3.7), its q-derivative, and the reduced field equal to the sleigh's equations
/// vd = a omega^2, omegad = -(m a / K) v omega; the multiplier form agrees and keeps the
/// constraint.
#[test]
fn sleigh_geometry_with_configuration_dependent_mass() {
    let sc = Sleigh {
        m: 1.3,
        i: 0.4,
        a: 0.9,
    };
    let k = sc.i + sc.m * sc.a * sc.a;
    let q = [0.3, -1.2, 0.9];
    let g = Geometry::at(&sc, &q);
    let (s, c) = (q[2].sin(), q[2].cos());
    let want = [
        [sc.m, 0.0, -sc.m * sc.a * s],
        [0.0, sc.m, sc.m * sc.a * c],
        [-sc.m * sc.a * s, sc.m * sc.a * c, k],
    ];
    for i in 0..3 {
        for j in 0..3 {
            assert!((g.mass[i][j] - want[i][j]).abs() < 1e-15);
        }
    }
    // dM/dtheta
    assert!((g.dmass[2][0][2] + sc.m * sc.a * c).abs() < 1e-15);
    assert!((g.dmass[2][1][2] + sc.m * sc.a * s).abs() < 1e-15);
    assert_eq!(g.dmass[0][0][2], 0.0);
    let u = [0.7, -1.1];
    let (qd, ud) = g.reduced_field(&u);
    assert!((qd[0] - 0.7 * c).abs() < 1e-15 && (qd[1] - 0.7 * s).abs() < 1e-15);
    assert!((ud[0] - sc.a * 1.21).abs() < 1e-14, "{ud:?}");
    assert!(
        (ud[1] - (-(sc.m * sc.a / k) * 0.7 * -1.1)).abs() < 1e-14,
        "{ud:?}"
    );
    // multiplier form: a = Edot^T u + E^T ud
    let acc = g.acceleration(&qd);
    let want_a = [
        ud[0] * c - 0.7 * s * -1.1,
        ud[0] * s + 0.7 * c * -1.1,
        ud[1],
    ];
    for i in 0..3 {
        assert!((acc[i] - want_a[i]).abs() < 1e-13, "{acc:?} vs {want_a:?}");
    }
    // d/dt (mu(q) v) = mudot v + mu a = 0
    let mudot: f64 = (0..3).map(|j| qd[j] * g.dmu[j][0][0]).sum::<f64>() * qd[0]
        + (0..3).map(|j| qd[j] * g.dmu[j][0][1]).sum::<f64>() * qd[1];
    let mu_a: f64 = (0..3).map(|i| g.mu[0][i] * acc[i]).sum();
    assert!((mudot + mu_a).abs() < 1e-13);
    assert_eq!(sc.name(), "sleigh");
}

// ---------------------------------------------------------------------------------------
// 3. Contact oscillator and its non-reversible variant (spec eq. (3.14)).

/// E, E_y, E - E_y over boxes (q, v), in intervals.
fn oscillator_invariants(eps: f64, q: &[Interval], v: &[Interval]) -> [Interval; 3] {
    let half = pt(0.5);
    let (x, y, z) = (q[0], q[1], q[2]);
    let e = (v[0].sqr()
        + v[1].sqr()
        + v[2].sqr()
        + x.sqr()
        + y.sqr()
        + z.sqr()
        + pt(eps) * (x * z).sqr())
        * half;
    let ey = (y.sqr() + v[1].sqr()) * half;
    let rest =
        (x.sqr() + (pt(1.0) + pt(eps) * x.sqr()) * z.sqr() + (pt(1.0) + y.sqr()) * v[2].sqr())
            * half;
    [e, ey, rest]
}

/// The oscillator's flow: y(t) = y0 cos t + yd0 sin t (the y-equation is decoupled since
/// mu_y = 0), and the three invariants E, E_y, E - E_y of McLachlan-Perlmutter, as
/// certified enclosures containing their initial values; the model's own energy tape too.
/// The non-reversible variant has the same motion (A is closed): its flow meets the
/// oscillator's.
#[test]
fn contact_oscillator_invariants_are_certified() {
    let mut g = SplitMix64(0xc0_7ac7);
    let mut cases: Vec<(f64, [f64; 3], [f64; 2], f64)> = vec![
        (0.3, [1.0, 0.5, 0.2], [0.3, 0.4], 0.5),
        (0.3, [1.0, 0.5, 0.2], [0.3, 0.4], 50.0),
        (0.0, [0.5, 1.0, -0.5], [0.0, 0.7], 50.0),
        (1.0, [-0.7, 0.2, 1.1], [0.9, -0.3], 20.0),
    ];
    for _ in 0..6 {
        let q = [
            g.uniform(-1.0, 1.0),
            g.uniform(-1.0, 1.0),
            g.uniform(-1.0, 1.0),
        ];
        let u = [g.uniform(-1.0, 1.0), g.uniform(-1.0, 1.0)];
        cases.push((g.uniform(0.0, 1.0), q, u, g.uniform(0.0, 10.0)));
    }
    for (eps, q, u, t) in cases {
        let m = model("contact-oscillator", &[("eps", eps)]);
        let nr = model("contact-oscillator-nr", &[("eps", eps), ("delta", 1.0)]);
        let ctx = describe("contact-oscillator", &[("eps", eps)], &q, &u, t);
        let e = run(&m, &q, &u, t).unwrap_or_else(|err| panic!("flow failed: {err}\n{ctx}"));
        // y closed form
        let (tt, y0, yd0) = (pt(t), pt(q[1]), pt(u[0]));
        let y = y0 * tt.cos() + yd0 * tt.sin();
        let yd = yd0 * tt.cos() - y0 * tt.sin();
        meet(e.q[1], y, &format!("y\n{ctx}"));
        meet(e.u[0], yd, &format!("yd\n{ctx}"));
        meet(e.v[1], yd, &format!("v_y\n{ctx}"));
        // invariants
        let q0: Vec<Interval> = q.iter().map(|x| pt(*x)).collect();
        let v0 = vec![-(pt(q[1]) * pt(u[1])), pt(u[0]), pt(u[1])];
        let i0 = oscillator_invariants(eps, &q0, &v0);
        let it = oscillator_invariants(eps, &ia(&e.q), &ia(&e.v));
        for (k, name) in ["E", "E_y", "E - E_y"].iter().enumerate() {
            assert!(
                !it[k].intersection(i0[k]).is_empty(),
                "{name}: {} excludes the initial {}\n{ctx}",
                show(it[k]),
                show(i0[k])
            );
            assert!(
                it[k].wid() < 1e-8 * t.max(1.0),
                "{name} {}\n{ctx}",
                show(it[k])
            );
        }
        let qv: Vec<Interval> = ia(&e.q).into_iter().chain(ia(&e.v)).collect();
        let et = m.energy().eval_checked(&qv).unwrap()[0];
        meet(et, i0[0], &format!("energy tape\n{ctx}"));
        // the non-reversible variant moves the same way
        let en = run(&nr, &q, &u, t).unwrap();
        for (a, b) in e.q.iter().zip(&en.q).chain(e.u.iter().zip(&en.u)) {
            meet(*a, *b, &format!("nr vs plain\n{ctx}"));
        }
    }
}

/// In the non-reversible variant the momentum is p = qd + A, A = (0, 0, delta sin z): the
/// exact discrete Legendre transforms of `step` differ from the oscillator's by
/// <A, e_a> = (0, delta sin z) at the respective points, and the Lagrangian's action
/// differs by the exact S(q0) - S(q(h)) = delta (cos z0 - cos z(h)) (a closed one-form adds
/// a boundary term); the retraction and the exact discrete flow are the same.
#[test]
fn contact_oscillator_nr_differs_only_in_momenta_and_action() {
    let delta = 0.7;
    let m = model("contact-oscillator", &[]);
    let nr = model("contact-oscillator-nr", &[("delta", delta)]);
    let (q0, q1, h) = ([0.2, 0.5, -0.3], [0.1, 0.6, -0.1], 0.4);
    let b = |v: &[f64]| {
        v.iter()
            .map(|x| dalembert::Interval::point(*x))
            .collect::<Vec<_>>()
    };
    let o = dalembert::FlowOptions::default();
    let s = dalembert::exact::step(&m, &b(&q0), &b(&q1), h, &o).unwrap();
    let sn = dalembert::exact::step(&nr, &b(&q0), &b(&q1), h, &o).unwrap();
    for (a, c) in s.q2.iter().zip(&sn.q2).chain(s.q1.iter().zip(&sn.q1)) {
        meet(*a, *c, "q");
    }
    let shift0 = pt(delta) * pt(q0[2]).sin();
    let shift1 = pt(delta) * Interval::from(s.q1[2]).sin();
    meet(s.p_minus[0], sn.p_minus[0], "p_minus[0]");
    meet(
        Interval::from(s.p_minus[1]) + shift0,
        sn.p_minus[1],
        "p_minus[1]",
    );
    meet(s.p_plus[0], sn.p_plus[0], "p_plus[0]");
    meet(
        Interval::from(s.p_plus[1]) + shift1,
        sn.p_plus[1],
        "p_plus[1]",
    );
    let (_, l) = dalembert::exact::discrete_lagrangian(&m, &b(&q0), &b(&q1), h, &o).unwrap();
    let (_, ln) = dalembert::exact::discrete_lagrangian(&nr, &b(&q0), &b(&q1), h, &o).unwrap();
    // int_0^h delta sin(z) zd dt = delta (cos z0 - cos z(h))
    let boundary = pt(delta) * (pt(q0[2]).cos() - Interval::from(s.q1[2]).cos());
    meet(Interval::from(l) + boundary, ln, "action");
    assert!(boundary.mag() > 1e-3, "the test must see the boundary term");
}

// ---------------------------------------------------------------------------------------
// 4. k = 2 end to end (rolling disk), and the CLI on every new scene.

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn bin(args: &[&str], stdin: Option<&str>) -> Out {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .args(args)
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn dalembert");
    if let Some(text) = stdin {
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
    }
    let o = child.wait_with_output().unwrap();
    Out {
        code: o.status.code().expect("exit code"),
        stdout: String::from_utf8(o.stdout).unwrap(),
        stderr: String::from_utf8(o.stderr).unwrap(),
    }
}

fn json_ok(args: &[&str]) -> Value {
    let o = bin(args, None);
    assert_eq!(o.code, 0, "{args:?}: {}", o.stderr);
    assert_eq!(o.stdout.trim_end().lines().count(), 1);
    serde_json::from_str(&o.stdout).unwrap()
}

/// An array of `len` valid intervals.
fn intervals(v: &Value, len: usize) -> Vec<(f64, f64)> {
    let a = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    assert_eq!(a.len(), len, "{v}");
    a.iter()
        .map(|x| {
            let (lo, hi) = (x[0].as_f64().unwrap(), x[1].as_f64().unwrap());
            assert!(lo <= hi && lo.is_finite() && hi.is_finite(), "{x}");
            (lo, hi)
        })
        .collect()
}

/// `retract` with k = 2: the defect has two components; a pair off M_h^{e,nh} is "no";
/// a pair exactly on it (phid = 0, phi0 = 0: q(h) = (R thetad h, 0, thetad h, 0) in exact
/// f64) is "possible", with both defect components containing 0.
#[test]
fn rolling_disk_retract_has_two_defect_components() {
    let off = json_ok(&[
        "retract",
        "--scene",
        "rolling-disk",
        "--q0",
        "0,0,0,0",
        "--q1",
        "0.3,0.05,0.3,0.2",
        "--h",
        "0.5",
        "--json",
    ]);
    let d = intervals(&off["defect"], 2);
    assert_eq!(off["member"], "no");
    assert!(d.iter().any(|(lo, hi)| *lo > 0.0 || *hi < 0.0));
    intervals(&off["u0"], 2);
    intervals(&off["v0"], 4);
    intervals(&off["v1"], 4);
    intervals(&off["q1"], 4);
    // exactly on the manifold: thetad = 0.5, h = 0.5, R = 1
    let on = json_ok(&[
        "retract",
        "--scene",
        "rolling-disk",
        "--q0",
        "0,0,0,0",
        "--q1",
        "0.25,0,0.25,0",
        "--h",
        "0.5",
        "--json",
    ]);
    assert_eq!(on["member"], "possible");
    for (lo, hi) in intervals(&on["defect"], 2) {
        assert!(lo <= 0.0 && 0.0 <= hi && hi - lo < 1e-14);
    }
    let u0 = intervals(&on["u0"], 2);
    assert!(u0[0].0 <= 0.5 && 0.5 <= u0[0].1 && u0[1].0 <= 0.0 && 0.0 <= u0[1].1);
    // with other parameters, the same pair is off the manifold (R = 2 rolls twice as far)
    let r2 = json_ok(&[
        "retract",
        "--scene",
        "rolling-disk",
        "--param",
        "R=2",
        "--q0",
        "0,0,0,0",
        "--q1",
        "0.25,0,0.25,0",
        "--h",
        "0.5",
        "--json",
    ]);
    assert_eq!(r2["member"], "no");
}

/// `step`, `integrate` (both schemes), `lagrangian` and `batch` on every new scene.
#[test]
fn every_command_works_on_the_new_scenes() {
    let cases: &[(&str, &[&str], &str, &str)] = &[
        ("rolling-disk", &[], "0,0,0,0", "0.3,0.05,0.3,0.2"),
        (
            "rolling-disk",
            &["J=2"],
            "0.1,0.2,0.3,0.4",
            "0.4,0.35,0.6,0.5",
        ),
        ("sleigh", &[], "0,0,0", "0.1,0.01,0.2"),
        ("sleigh", &["a=-0.3", "I=1"], "0,0,0.5", "0.1,0.05,0.6"),
        ("contact-oscillator", &[], "1,0.5,0.2", "0.97,0.6,0.25"),
        (
            "contact-oscillator-nr",
            &["delta=0.5"],
            "1,0.5,0.2",
            "0.97,0.6,0.25",
        ),
    ];
    let mut batch = String::new();
    for (i, (scene, params, q0, q1)) in cases.iter().enumerate() {
        let mut sargs: Vec<&str> = vec!["--scene", scene];
        for p in params.iter() {
            sargs.extend(["--param", p]);
        }
        let n = q0.split(',').count();
        let k = if *scene == "rolling-disk" { 2 } else { 1 };
        let pair = |cmd: &'static str| {
            let mut a = vec![cmd];
            a.extend(sargs.iter().copied());
            a.extend(["--q0", q0, "--q1", q1, "--h", "0.25", "--json"]);
            a
        };
        let s = json_ok(&pair("step"));
        intervals(&s["q1"], n);
        intervals(&s["q2"], n);
        intervals(&s["p_minus"], n - k);
        intervals(&s["p_plus"], n - k);
        let r = json_ok(&pair("retract"));
        intervals(&r["defect"], k);
        let l = json_ok(&pair("lagrangian"));
        assert!(l["l"][0].as_f64().unwrap() <= l["l"][1].as_f64().unwrap());
        for scheme in ["mla", "dla"] {
            let mut a = pair("integrate");
            a.extend(["--scheme", scheme, "--steps", "20"]);
            let t = json_ok(&a);
            let q = t["q"].as_array().unwrap();
            assert_eq!(q.len(), 21);
            assert!(q.iter().all(|r| r.as_array().unwrap().len() == n));
            assert_eq!(t["p"][0].as_array().unwrap().len(), n - k);
            // energy is nearly constant over 20 steps of h = 0.25 (both schemes, all scenes)
            let e: Vec<f64> = t["energy"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            let spread = e.iter().fold(0.0f64, |m, x| m.max((x - e[0]).abs()));
            assert!(
                spread < 0.05 * e[0].abs().max(1.0),
                "{scene} {scheme}: {e:?}"
            );
        }
        // the same queries through batch
        let params_json: serde_json::Map<String, Value> = params
            .iter()
            .map(|p| {
                let (k, v) = p.split_once('=').unwrap();
                (k.to_string(), Value::from(v.parse::<f64>().unwrap()))
            })
            .collect();
        let vec = |s: &str| -> Value {
            s.split(',')
                .map(|x| x.parse::<f64>().unwrap())
                .collect::<Vec<_>>()
                .into()
        };
        for cmd in ["retract", "step", "integrate", "flow"] {
            let mut o = serde_json::json!({
                "id": format!("{i}-{cmd}"), "cmd": cmd, "scene": scene,
                "params": params_json.clone(),
            });
            if cmd == "flow" {
                o["q"] = vec(q0);
                o["u"] = vec(&vec!["0.3"; n - k].join(","));
                o["t"] = 0.5.into();
            } else {
                o["q0"] = vec(q0);
                o["q1"] = vec(q1);
                o["h"] = 0.25.into();
            }
            if cmd == "integrate" {
                o["scheme"] = "mla".into();
                o["steps"] = 5.into();
            }
            batch.push_str(&o.to_string());
            batch.push('\n');
        }
    }
    let out = bin(&["batch"], Some(&batch));
    assert_eq!(out.code, 0, "{}", out.stderr);
    let lines: Vec<Value> = out
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), cases.len() * 4);
    for l in &lines {
        assert!(l.get("ok").is_some(), "batch answer is an error: {l}");
    }
    // the step through batch is the step of the command line
    let direct = json_ok(&[
        "step",
        "--scene",
        "sleigh",
        "--q0",
        "0,0,0",
        "--q1",
        "0.1,0.01,0.2",
        "--h",
        "0.25",
        "--json",
    ]);
    let from_batch = lines.iter().find(|l| l["id"] == "2-step").unwrap();
    assert_eq!(from_batch["ok"], direct);
}

/// Parameters are validated with one-line input errors (exit 2).
#[test]
fn bad_parameters_of_the_new_scenes_are_input_errors() {
    for (scene, p, q, u) in [
        ("rolling-disk", "m=0", "0,0,0,0", "1,1"),
        ("rolling-disk", "R=-1", "0,0,0,0", "1,1"),
        ("rolling-disk", "I=-0.5", "0,0,0,0", "1,1"),
        ("rolling-disk", "J=0", "0,0,0,0", "1,1"),
        ("rolling-disk", "eps=1", "0,0,0,0", "1,1"),
        ("sleigh", "m=-1", "0,0,0", "1,1"),
        ("sleigh", "I=0", "0,0,0", "1,1"),
        ("sleigh", "R=1", "0,0,0", "1,1"),
        ("contact-oscillator", "delta=1", "0,0,0", "1,1"),
        ("contact-oscillator-nr", "eps=nan", "0,0,0", "1,1"),
    ] {
        let o = bin(
            &[
                "flow", "--scene", scene, "--param", p, "--q", q, "--u", u, "--t", "1",
            ],
            None,
        );
        assert_eq!(o.code, 2, "{scene} {p}: {}", o.stderr);
        assert!(o.stdout.is_empty());
        assert_eq!(o.stderr.lines().count(), 1);
        assert!(o.stderr.starts_with("error:"));
    }
    // wrong dimensions: the disk has n = 4 and n - k = 2
    let o = bin(
        &[
            "flow",
            "--scene",
            "rolling-disk",
            "--q",
            "0,0,0",
            "--u",
            "1,1",
            "--t",
            "1",
        ],
        None,
    );
    assert_eq!(o.code, 2);
    let o = bin(
        &[
            "retract",
            "--scene",
            "rolling-disk",
            "--q0",
            "0,0,0,0",
            "--q1",
            "0,0,0",
            "--h",
            "1",
        ],
        None,
    );
    assert_eq!(o.code, 2);
    // the unknown-scene message and the help list the new scenes
    let o = bin(
        &[
            "flow", "--scene", "nope", "--q", "0", "--u", "0", "--t", "1",
        ],
        None,
    );
    assert_eq!(o.code, 2);
    for name in [
        "rolling-disk",
        "sleigh",
        "contact-oscillator",
        "contact-oscillator-nr",
    ] {
        assert!(o.stderr.contains(name), "{}", o.stderr);
    }
    let help = bin(&["flow", "--help"], None);
    assert!(
        help.stdout.contains("contact-oscillator-nr"),
        "{}",
        help.stdout
    );
}

// ---------------------------------------------------------------------------------------
// 5. `dalembert scenes`.

/// `scenes --json`: one object listing every scene with its coordinates, velocities,
/// parameters (name, default, description), n, k, Lagrangian, mu (k strings), basis of D
/// (n - k strings); every default set builds and its dimensions are the listed ones.
#[test]
fn scenes_json_describes_every_scene() {
    let v = json_ok(&["scenes", "--json"]);
    let list = v["scenes"].as_array().unwrap();
    let names: Vec<&str> = list.iter().map(|s| s["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "particle",
            "knife",
            "knife-eps",
            "rolling-disk",
            "sleigh",
            "contact-oscillator",
            "contact-oscillator-nr"
        ]
    );
    for s in list {
        let name = s["name"].as_str().unwrap();
        let (n, k) = (
            s["n"].as_u64().unwrap() as usize,
            s["k"].as_u64().unwrap() as usize,
        );
        let strings = |key: &str, len: usize| {
            let a = s[key].as_array().unwrap_or_else(|| panic!("{name}: {key}"));
            assert_eq!(a.len(), len, "{name}: {key}");
            assert!(a.iter().all(|x| !x.as_str().unwrap().is_empty()));
        };
        strings("coordinates", n);
        strings("velocities", n - k);
        strings("mu", k);
        strings("basis", n - k);
        assert!(s["lagrangian"].as_str().unwrap().starts_with("L = "));
        assert!(!s["summary"].as_str().unwrap().is_empty());
        let mut params = vec![];
        for p in s["parameters"].as_array().unwrap() {
            let pname = p["name"].as_str().unwrap();
            let d = p["default"].as_f64().unwrap();
            assert!(!p["description"].as_str().unwrap().is_empty());
            params.push((pname, d));
        }
        // the defaults, given explicitly, are the scene with no parameters
        let m = dalembert::AnyScene::new(name, &params).unwrap();
        assert_eq!(m, dalembert::AnyScene::new(name, &[]).unwrap());
        let model = Model::new(&m).unwrap();
        assert_eq!((model.n(), model.k()), (n, k), "{name}");
    }
    assert_eq!(list[3]["k"], 2);
    // the plain-text form lists the same scenes
    let text = bin(&["scenes"], None);
    assert_eq!(text.code, 0);
    for n in names {
        assert!(text.stdout.contains(&format!("{n}: ")), "{n}");
    }
}
