//! Soundness of `flow` against the closed-form solutions of the two integrable scenes.
//!
//! The closed forms are evaluated in interval arithmetic (inari, with the elementary functions
//! of spec (1.3), proved against a 256-bit reference in tests/elementary.rs) from the exact
//! f64 inputs, so each reference is itself an
//! enclosure of the true state. The property is therefore: for every component of q, u and
//! v, the enclosure returned by `flow` and the reference enclosure intersect. Where the
//! reference is narrower than 1e-14 * max(1, |value|) this pins the true value, and the
//! random tests also check that this is the case for the large majority of components, so
//! that the comparison is not vacuous.
//!
//! # The closed forms
//!
//! Particle (q = (x, y, z), u = (xd, yd)), from the contract (paper eqs. nhsolution and
//! nhsolution0): yd = yd0, y = y0 + yd0 t, xd = xd0 sqrt(1 + y0^2) / sqrt(1 + y^2),
//! zd = y xd,
//!     x = x0 + xd0 / yd0 sqrt(1 + y0^2) (asinh(y) - asinh(y0))       (yd0 != 0),
//!     z = z0 + xd0 / yd0 sqrt(1 + y0^2) (sqrt(1 + y^2) - sqrt(1 + y0^2)).
//! Rewritten without cancellation (both are used and intersected):
//!     sqrt(1 + y^2) - sqrt(1 + y0^2) = yd0 t (y + y0) / (sqrt(1 + y^2) + sqrt(1 + y0^2)),
//!     asinh(y) - asinh(y0) = asinh(y sqrt(1 + y0^2) - y0 sqrt(1 + y^2)) = asinh(yd0 r),
//!     r = t (y + y0) / (y sqrt(1 + y0^2) + y0 sqrt(1 + y^2)),
//! so that z = z0 + xd0 sqrt(1 + y0^2) t (y + y0) / (sqrt(1 + y^2) + sqrt(1 + y0^2)) and
//! x = x0 + xd0 sqrt(1 + y0^2) r asinhc(yd0 r) with asinhc(v) = asinh(v) / v.
//!
//! Knife (q = (x, y, phi), u = (s, w)), derived here. The equations of motion are
//! phid = w, wd = 0, sd = cos(phi) / 2, xd = s cos(phi), yd = s sin(phi). With
//! theta = w t, phi = phi0 + theta and
//!     sigma = sin(theta / 2) / w            (= t/2 sinc(theta/2); = t/2 when w = 0),
//!     D = (sin phi - sin phi0) / w = 2 cos(phi0 + theta/2) sigma,
//!     C = (cos phi0 - cos phi) / w = 2 sin(phi0 + theta/2) sigma,
//! the solution is
//!     s = s0 + D / 2,
//!     x = x0 + s0 D + D^2 / 4,
//!     y = y0 + s0 C + (2 theta - sin 2 theta) / (8 w^2)
//!            + sin(2 phi0) cos(theta) sigma^2 / 2 - sin(phi0)^2 sin(theta) sigma^2,
//! where (2 theta - sin 2 theta) / (8 w^2) = w t^3 g(4 theta^2), g(a^2) = (a - sin a) / a^3.
//! (Derivation: s = S0 + sin(phi) / (2w) with S0 = s0 - sin(phi0) / (2w); integrate
//! s cos(phi) = S0 cos(phi) + sin(2 phi) / (4w) and s sin(phi) = S0 sin(phi) +
//! (1 - cos(2 phi)) / (4w), then collect the terms in 1/w^2; for x they collapse to
//! (sin phi - sin phi0)^2 / (4 w^2).) For w = 0 this reduces to the polynomials
//!     s = s0 + t cos(phi0) / 2,  x = x0 + s0 cos(phi0) t + cos(phi0)^2 t^2 / 4,
//!     y = y0 + s0 sin(phi0) t + sin(phi0) cos(phi0) t^2 / 4,
//! and for w != 0 the textbook form
//!     x = x0 + S0 (sin phi - sin phi0) / w + (sin^2 phi - sin^2 phi0) / (4 w^2),
//!     y = y0 + S0 (cos phi0 - cos phi) / w + t / (4 w) - (sin 2phi - sin 2phi0) / (8 w^2)
//! is also evaluated and intersected. The test `reference_matches_rk4` checks all these
//! formulas against a fine RK4 integration of the equations of motion in f64.
//!
//! # Determinism
//!
//! proptest runs with a fixed ChaCha seed and no failure persistence; quickcheck runs with
//! `Gen::from_size_and_seed` (available in quickcheck 1.1) and its inputs are derived from
//! generated u64 words mapped into the intended ranges, so every run sees the same cases.

use crate::common::{describe, hex, model, rk4, run, show, SplitMix64};
use dalembert::elementary::asinh;
use dalembert::scalar::{iv, point as pt, Scalar};
use dalembert::{Error, FlowEnclosure, Model};
use inari::Interval;
use proptest::prelude::*;
use proptest::test_runner::{Config as ProptestConfig, RngAlgorithm, TestRng, TestRunner};
use quickcheck::{Arbitrary, Gen, QuickCheck, TestResult};
use std::cell::{Cell, RefCell};

// ---------------------------------------------------------------------------------------
// Interval helpers.

/// `sum_{j < K} (-1)^j c_j x^j` plus the alternating-series remainder `[-r, r]`,
/// `r = c_K |x|^K`, where `coef = [c_0, ..., c_K]`.
///
/// Valid when x >= 0 and the terms `c_j x^j` decrease in magnitude for j >= K (true for
/// the series below on the ranges where they are used).
fn alternating_series(x: Interval, coef: &[Interval]) -> Interval {
    assert!(x.inf() >= 0.0, "alternating_series needs x >= 0");
    let k = coef.len() - 1;
    let mut p = coef[k - 1];
    for j in (0..k - 1).rev() {
        p = coef[j] - x * p;
    }
    let xm = pt(x.mag());
    let mut b = coef[k];
    for _ in 0..k {
        b *= xm;
    }
    let r = b.sup();
    p + iv(-r, r)
}

/// n! as an interval.
fn fact(n: u32) -> Interval {
    (1..=n).fold(pt(1.0), |acc, i| acc * pt(f64::from(i)))
}

const TERMS: u32 = 12;

/// sin(h) / h (= 1 at 0).
fn sinc(h: Interval) -> Interval {
    if h.mag() <= 1.0 {
        let coef: Vec<Interval> = (0..=TERMS).map(|j| pt(1.0) / fact(2 * j + 1)).collect();
        alternating_series(h.sqr(), &coef)
    } else {
        h.sin() / h
    }
}

/// (a - sin a) / a^3 for |a| <= 1 (= 1/6 at 0).
fn a_minus_sin_over_cube(a: Interval) -> Interval {
    assert!(a.mag() <= 1.0);
    let coef: Vec<Interval> = (0..=TERMS).map(|j| pt(1.0) / fact(2 * j + 3)).collect();
    alternating_series(a.sqr(), &coef)
}

/// asinh(v) / v (= 1 at 0).
fn asinhc(v: Interval) -> Interval {
    if v.mag() <= 0.5 {
        // asinh v = sum_j (-1)^j (2j)! / (4^j (j!)^2 (2j + 1)) v^(2j+1).
        let coef: Vec<Interval> = (0..=TERMS)
            .map(|j| {
                let mut c = pt(1.0);
                for i in 1..=j {
                    c = c * pt(f64::from(2 * i - 1)) / pt(f64::from(2 * i));
                }
                c / pt(f64::from(2 * j + 1))
            })
            .collect();
        alternating_series(v.sqr(), &coef)
    } else {
        asinh(v) / v
    }
}

/// Intersection of two enclosures of the same number; an empty result means that one of
/// the reference formulas is wrong (a bug of this test, not of the crate).
fn meet(a: Interval, b: Interval, what: &str) -> Interval {
    let m = a.intersection(b);
    assert!(
        !m.is_empty(),
        "reference formulas disagree for {what}: {} vs {}",
        show(a),
        show(b)
    );
    m
}

// ---------------------------------------------------------------------------------------
// Closed forms.

/// Enclosure of the exact state at time t.
#[derive(Clone, Copy, Debug)]
struct Exact {
    q: [Interval; 3],
    u: [Interval; 2],
    v: [Interval; 3],
}

impl Exact {
    fn meet(&self, o: &Exact, what: &str) -> Exact {
        let f = |a: &[Interval], b: &[Interval]| -> Vec<Interval> {
            a.iter().zip(b).map(|(x, y)| meet(*x, *y, what)).collect()
        };
        let (q, u, v) = (f(&self.q, &o.q), f(&self.u, &o.u), f(&self.v, &o.v));
        Exact {
            q: [q[0], q[1], q[2]],
            u: [u[0], u[1]],
            v: [v[0], v[1], v[2]],
        }
    }
}

/// The paper's form (nhsolution for yd0 != 0, nhsolution0 for yd0 = 0), evaluated as written.
fn particle_paper(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    let (x0, y0, z0) = (pt(q[0]), pt(q[1]), pt(q[2]));
    let (xd0, yd0, tt) = (pt(u[0]), pt(u[1]), pt(t));
    if u[1] == 0.0 {
        return Exact {
            q: [xd0 * tt + x0, y0, y0 * xd0 * tt + z0],
            u: [xd0, yd0],
            v: [xd0, yd0, y0 * xd0],
        };
    }
    let y = yd0 * tt + y0;
    let r0 = (y0.sqr() + pt(1.0)).sqrt();
    let r1 = (y.sqr() + pt(1.0)).sqrt();
    let k = xd0 / yd0 * r0;
    let xd = xd0 * r0 / r1;
    Exact {
        q: [k * (asinh(y) - asinh(y0)) + x0, y, k * (r1 - r0) + z0],
        u: [xd, yd0],
        v: [xd, yd0, y * xd],
    }
}

/// The same solution rewritten without cancellation (see the module documentation).
fn particle_stable(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    let (x0, y0, z0) = (pt(q[0]), pt(q[1]), pt(q[2]));
    let (xd0, yd0, tt) = (pt(u[0]), pt(u[1]), pt(t));
    let y = y0 + yd0 * tt;
    let r0 = (pt(1.0) + y0.sqr()).sqrt();
    let r1 = (pt(1.0) + y.sqr()).sqrt();
    let ysum = y + y0;
    let z = z0 + xd0 * r0 * tt * ysum / (r0 + r1);
    // r = t (y + y0) / (y r0 + y0 r1); it is exactly t when y0 = 0.
    let den = y * r0 + y0 * r1;
    let x = if q[1] == 0.0 {
        x0 + xd0 * tt * asinhc(yd0 * tt)
    } else if den.contains(0.0) {
        // y(t) = -y0: 0/0, no information from this form (the paper's form is fine there).
        Interval::ENTIRE
    } else {
        let r = tt * ysum / den;
        x0 + xd0 * r0 * r * asinhc(yd0 * r)
    };
    let xd = if u[1] == 0.0 { xd0 } else { xd0 * r0 / r1 };
    Exact {
        q: [x, y, z],
        u: [xd, yd0],
        v: [xd, yd0, y * xd],
    }
}

fn particle_exact(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    particle_paper(q, u, t).meet(&particle_stable(q, u, t), "particle")
}

/// Knife, uniform in w (valid for w = 0 too).
fn knife_stable(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    let (x0, y0, p0) = (pt(q[0]), pt(q[1]), pt(q[2]));
    let (s0, w, tt) = (pt(u[0]), pt(u[1]), pt(t));
    let half = pt(0.5);
    let th = w * tt;
    let h = th * half;
    let phi = p0 + th;
    let sigma = tt * half * sinc(h); // sin(theta/2) / w
    let m = p0 + h;
    let (cm, sm) = (m.cos(), m.sin());
    let d = pt(2.0) * cm * sigma; // (sin phi - sin phi0) / w
    let c = pt(2.0) * sm * sigma; // (cos phi0 - cos phi) / w
    let s = s0 + cm * sigma;
    let x = x0 + s0 * d + d.sqr() * pt(0.25);
    let a = pt(2.0) * th;
    let e = if a.mag() <= 1.0 {
        w * tt * tt * tt * a_minus_sin_over_cube(a)
    } else {
        (a - a.sin()) / (pt(8.0) * w.sqr())
    };
    let (sp0, cp0) = (p0.sin(), p0.cos());
    let sig2 = sigma.sqr();
    let y = y0 + s0 * c + e + sp0 * cp0 * th.cos() * sig2 - sp0.sqr() * th.sin() * sig2;
    Exact {
        q: [x, y, phi],
        u: [s, w],
        v: [s * phi.cos(), s * phi.sin(), w],
    }
}

/// Knife with w = 0: polynomials in t.
fn knife_poly(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    assert!(u[1] == 0.0);
    let (x0, y0, p0) = (pt(q[0]), pt(q[1]), pt(q[2]));
    let (s0, w, tt) = (pt(u[0]), pt(u[1]), pt(t));
    let (sp0, cp0) = (p0.sin(), p0.cos());
    let quarter = pt(0.25);
    let s = s0 + tt * cp0 * pt(0.5);
    let x = x0 + s0 * cp0 * tt + (cp0 * tt).sqr() * quarter;
    let y = y0 + s0 * sp0 * tt + sp0 * cp0 * tt.sqr() * quarter;
    Exact {
        q: [x, y, p0],
        u: [s, w],
        v: [s * cp0, s * sp0, w],
    }
}

/// Knife with w != 0, textbook form (cancels badly for small w).
fn knife_textbook(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    assert!(u[1] != 0.0);
    let (x0, y0, p0) = (pt(q[0]), pt(q[1]), pt(q[2]));
    let (s0, w, tt) = (pt(u[0]), pt(u[1]), pt(t));
    let phi = p0 + w * tt;
    let (sp0, cp0, sp, cp) = (p0.sin(), p0.cos(), phi.sin(), phi.cos());
    let two = pt(2.0);
    let big_s = s0 - sp0 / (two * w);
    let s = s0 + (sp - sp0) / (two * w);
    let x = x0 + big_s * (sp - sp0) / w + (sp.sqr() - sp0.sqr()) / (pt(4.0) * w.sqr());
    let y = y0 + big_s * (cp0 - cp) / w + tt / (pt(4.0) * w)
        - ((two * phi).sin() - (two * p0).sin()) / (pt(8.0) * w.sqr());
    Exact {
        q: [x, y, phi],
        u: [s, w],
        v: [s * cp, s * sp, w],
    }
}

fn knife_exact(q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
    let e = knife_stable(q, u, t);
    if u[1] == 0.0 {
        e.meet(&knife_poly(q, u, t), "knife (w = 0)")
    } else if u[1].abs() >= 1e-100 {
        e.meet(&knife_textbook(q, u, t), "knife (w != 0)")
    } else {
        e
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scene {
    Particle,
    Knife,
}

impl Scene {
    fn name(self) -> &'static str {
        match self {
            Scene::Particle => "particle",
            Scene::Knife => "knife",
        }
    }
    fn model(self) -> Model {
        model(self.name(), &[])
    }
    fn exact(self, q: [f64; 3], u: [f64; 2], t: f64) -> Exact {
        match self {
            Scene::Particle => particle_exact(q, u, t),
            Scene::Knife => knife_exact(q, u, t),
        }
    }
}

// ---------------------------------------------------------------------------------------
// The reference itself, checked against RK4 in f64.

/// Equations of motion as first-order systems on (q, u), from the contract.
fn particle_field(x: &[f64; 5]) -> [f64; 5] {
    let (y, u1, u2) = (x[1], x[3], x[4]);
    // d/dt (xd) = -y yd xd / (1 + y^2) (differentiate xd0 sqrt(1 + y0^2) / sqrt(1 + y^2)).
    [u1, u2, y * u1, -y * u1 * u2 / (1.0 + y * y), 0.0]
}

fn knife_field(x: &[f64; 5]) -> [f64; 5] {
    let (phi, s, w) = (x[2], x[3], x[4]);
    [s * phi.cos(), s * phi.sin(), w, phi.cos() / 2.0, 0.0]
}

#[test]
fn reference_matches_rk4() {
    let cases: &[([f64; 3], [f64; 2], f64)] = &[
        ([0.0, 0.0, 0.0], [0.8, 0.8], 2.0),
        ([1.0, -2.0, 3.0], [-5.0, 7.0], 1.0),
        ([0.5, 3.0, -1.0], [2.0, -4.0], 1.5),
        ([0.5, -0.3, -1.0], [2.0, 0.0], 1.5),
        ([0.5, -0.3, -1.0], [2.0, 1e-8], 1.5),
        ([-7.0, 9.5, 2.0], [-3.0, 0.25], 3.0),
        ([1.0, 2.0, 0.3], [-1.5, 10.0], 0.7),
        ([1.0, 2.0, 0.3], [1.5, -3e-4], 2.0),
        ([0.0, 0.0, 0.0], [1.0, 1.0], 1.0),
    ];
    let n = 20_000;
    let mut worst = 0.0f64;
    for &(q, u, t) in cases {
        let x0 = [q[0], q[1], q[2], u[0], u[1]];
        for (scene, field) in [
            (Scene::Particle, particle_field as fn(&[f64; 5]) -> [f64; 5]),
            (Scene::Knife, knife_field),
        ] {
            let num = rk4(field, x0, t, n);
            let e = scene.exact(q, u, t);
            let v_num = match scene {
                Scene::Particle => [num[3], num[4], num[1] * num[3]],
                Scene::Knife => [num[3] * num[2].cos(), num[3] * num[2].sin(), num[4]],
            };
            let mut formulas = vec![("combined", e)];
            match scene {
                Scene::Particle => {
                    formulas.push(("paper", particle_paper(q, u, t)));
                    formulas.push(("stable", particle_stable(q, u, t)));
                }
                Scene::Knife => {
                    formulas.push(("stable", knife_stable(q, u, t)));
                    if u[1] == 0.0 {
                        formulas.push(("poly", knife_poly(q, u, t)));
                    } else {
                        formulas.push(("textbook", knife_textbook(q, u, t)));
                    }
                }
            }
            for (fname, e) in formulas {
                let comps = e.q.iter().chain(&e.u).chain(&e.v);
                let nums = num.iter().chain(&v_num);
                for (i, (c, r)) in comps.zip(nums).enumerate() {
                    let err = (c.mid() - r).abs() / r.abs().max(1.0);
                    // The cancelling textbook forms are loose for tiny w: only their
                    // containment of the RK4 value (up to its own error) is meaningful.
                    let tol = 1e-9 + c.wid();
                    worst = worst.max((c.mid() - r).abs() / r.abs().max(1.0) - c.wid());
                    assert!(
                        err <= tol,
                        "{} {fname} component {i}: closed form {} vs RK4 {r:e} at q={q:?} u={u:?} t={t}",
                        scene.name(),
                        show(*c)
                    );
                }
            }
        }
    }
    println!("worst relative distance closed form vs RK4: {worst:e}");
}

#[test]
fn reference_is_tight_and_degenerates_correctly() {
    // The combined references are narrow on ordinary inputs (so that they pin the truth).
    for &(q, u, t) in &[
        ([1.0, -2.0, 3.0], [-5.0, 7.0], 1.0),
        ([0.1, 0.2, 0.3], [0.4, 1e-300], 1.0),
        ([0.1, 0.2, 0.3], [0.4, 1e-12], 1.0),
        ([0.1, 1e6, 0.3], [0.4, -10.0], 1.0),
        ([0.1, 0.2, 0.3], [0.4, 0.0], 1.0),
    ] {
        for scene in [Scene::Particle, Scene::Knife] {
            let e = scene.exact(q, u, t);
            for c in e.q.iter().chain(&e.u).chain(&e.v) {
                assert!(
                    c.wid() <= 1e-14 * c.mag().max(1.0),
                    "{} reference too wide at q={q:?} u={u:?} t={t}: {}",
                    scene.name(),
                    show(*c)
                );
            }
        }
    }
    // Tiny w / yd0 is continuous with w = 0 / yd0 = 0.
    for scene in [Scene::Particle, Scene::Knife] {
        let (q, t) = ([0.3, -0.7, 1.1], 0.9);
        let a = scene.exact(q, [1.3, 1e-300], t);
        let b = scene.exact(q, [1.3, 0.0], t);
        for (x, y) in a.q.iter().zip(&b.q) {
            assert!(
                !x.disjoint(*y),
                "{}: {} vs {}",
                scene.name(),
                show(*x),
                show(*y)
            );
        }
    }
    // t = 0 gives the initial state.
    let (q, u) = ([0.3, -0.7, 1.1], [1.3, -2.0]);
    for scene in [Scene::Particle, Scene::Knife] {
        let e = scene.exact(q, u, 0.0);
        for (c, x) in e.q.iter().zip(q).chain(e.u.iter().zip(u)) {
            assert!(c.contains(x) && c.wid() <= 1e-15 * x.abs(), "{}", show(*c));
        }
    }
}

// ---------------------------------------------------------------------------------------
// Comparison of flow with the reference.

/// What one comparison found.
#[derive(Default, Debug)]
struct Tally {
    cases: usize,
    uncertified: usize,
    /// Components whose reference is narrow enough to pin the truth.
    pinned: usize,
    components: usize,
}

const PIN: f64 = 1e-14;

/// Every component of `got` must meet the reference; returns how many were pinned.
fn compare(
    scene: Scene,
    q: [f64; 3],
    u: [f64; 2],
    t: f64,
    got: &FlowEnclosure,
) -> Result<usize, String> {
    let e = scene.exact(q, u, t);
    let mut pinned = 0;
    let mut bad = Vec::new();
    let groups: [(&str, &[dalembert::Interval], &[Interval]); 3] = [
        ("q", &got.q, &e.q),
        ("u", &got.u, &e.u),
        ("v", &got.v, &e.v),
    ];
    for (gname, g, r) in groups {
        assert_eq!(g.len(), r.len(), "dimension of {gname}");
        for (i, (a, b)) in g.iter().zip(r).enumerate() {
            let narrow = b.wid() <= PIN * b.mag().max(1.0);
            pinned += usize::from(narrow);
            if !(a.inf().is_finite() && a.sup().is_finite()) {
                bad.push(format!(
                    "  {gname}[{i}]: flow returned an empty or unbounded box {}",
                    show(*a)
                ));
            } else if a.intersection(*b).is_empty() {
                bad.push(format!(
                    "  {gname}[{i}]: flow {}  closed form {}{}",
                    show(*a),
                    show(*b),
                    if narrow {
                        "  (closed form pins the truth)"
                    } else {
                        ""
                    }
                ));
            }
        }
    }
    if bad.is_empty() {
        Ok(pinned)
    } else {
        Err(format!(
            "SOUNDNESS: flow's enclosure misses the closed form\n{}{}\n  stats: {:?}",
            describe(scene.name(), &[], &q, &u, t),
            bad.join("\n"),
            got.stats
        ))
    }
}

/// Run flow and compare; `Uncertified` is tallied, `Input` is a failure.
fn check(
    scene: Scene,
    m: &Model,
    q: [f64; 3],
    u: [f64; 2],
    t: f64,
    tally: &mut Tally,
) -> Result<(), String> {
    tally.cases += 1;
    match run(m, &q, &u, t) {
        Ok(e) => {
            tally.pinned += compare(scene, q, u, t, &e)?;
            tally.components += 8;
            Ok(())
        }
        Err(Error::Uncertified(msg)) => {
            eprintln!(
                "note: uncertified ({msg}) for\n{}",
                describe(scene.name(), &[], &q, &u, t)
            );
            tally.uncertified += 1;
            Ok(())
        }
        Err(Error::Input(msg)) => Err(format!(
            "valid input rejected as invalid ({msg})\n{}",
            describe(scene.name(), &[], &q, &u, t)
        )),
        // an internal fault, or a kind of error added later
        Err(msg) => Err(format!(
            "internal fault ({msg})\n{}",
            describe(scene.name(), &[], &q, &u, t)
        )),
    }
}

/// `check` for the explicit tests: the state must be certified.
fn check_one(scene: Scene, q: [f64; 3], u: [f64; 2], t: f64) -> FlowEnclosure {
    let m = scene.model();
    let e = run(&m, &q, &u, t).unwrap_or_else(|err| {
        panic!(
            "flow failed: {err}\n{}",
            describe(scene.name(), &[], &q, &u, t)
        )
    });
    if let Err(msg) = compare(scene, q, u, t, &e) {
        panic!("{msg}");
    }
    e
}

/// At most 2% (and at least one allowed) of random ordinary cases may be refused, and
/// most components must be pinned by a narrow reference.
fn assert_tally(what: &str, t: &Tally) {
    println!("{what}: {t:?}");
    assert!(t.cases > 0);
    assert!(
        t.uncertified <= (t.cases / 50).max(1),
        "{what}: too many Uncertified answers: {t:?}"
    );
    assert!(
        t.pinned * 10 >= t.components * 9,
        "{what}: the closed form pinned too few components ({t:?}); the test would be weak"
    );
}

// ---------------------------------------------------------------------------------------
// proptest.

const PROPTEST_SEED: [u8; 32] = *b"dalembert closed forms, seed #1.";

fn proptest_runner(cases: u32) -> TestRunner {
    let config = ProptestConfig {
        cases,
        rng_algorithm: RngAlgorithm::ChaCha,
        failure_persistence: None,
        max_shrink_iters: 64,
        fork: false,
        timeout: 0,
        ..ProptestConfig::default()
    };
    TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &PROPTEST_SEED),
    )
}

/// A coordinate in [-r, r], sometimes exactly 0 or a small integer.
fn coord(r: f64) -> impl Strategy<Value = f64> {
    let ri = r as i32;
    prop_oneof![
        8 => -r..=r,
        1 => Just(0.0),
        1 => (-ri..=ri).prop_map(f64::from),
    ]
}

fn state(r: f64, t: (f64, f64)) -> impl Strategy<Value = ([f64; 3], [f64; 2], f64)> {
    (
        [coord(r), coord(r), coord(r)],
        [coord(r), coord(r)],
        t.0..=t.1,
    )
}

fn proptest_scene(scene: Scene, cases: u32, r: f64, t: (f64, f64)) -> Tally {
    let m = scene.model();
    let tally = Cell::new(Tally::default());
    let mut runner = proptest_runner(cases);
    let res = runner.run(&state(r, t), |(q, u, t)| {
        let mut tl = tally.take();
        let r = check(scene, &m, q, u, t, &mut tl);
        tally.set(tl);
        r.map_err(TestCaseError::fail)
    });
    if let Err(e) = res {
        panic!("{} (proptest): {e}", scene.name());
    }
    tally.take()
}

#[test]
fn proptest_particle() {
    let t = proptest_scene(Scene::Particle, 400, 10.0, (0.0, 1.0));
    assert_tally("proptest particle", &t);
}

#[test]
fn proptest_knife() {
    let t = proptest_scene(Scene::Knife, 120, 10.0, (0.0, 1.0));
    assert_tally("proptest knife", &t);
}

// ---------------------------------------------------------------------------------------
// quickcheck: deterministic by a seeded `Gen`; the state is built from u64 words mapped
// into the ranges, so every generated input is a valid, finite state in range.

#[derive(Clone, Debug)]
struct QcState {
    q: [f64; 3],
    u: [f64; 2],
    t: f64,
}

/// A coordinate in [-10, 10] from a random word: mostly uniform, sometimes 0, an integer,
/// or a tiny number.
fn qc_coord(g: &mut Gen) -> f64 {
    let w = u64::arbitrary(g);
    match w % 16 {
        0 => 0.0,
        1 => ((w >> 8) % 21) as f64 - 10.0,
        2 => {
            if w & 0x100 == 0 {
                1e-12
            } else {
                -1e-300
            }
        }
        _ => crate::common::from_bits_in(u64::arbitrary(g), -10.0, 10.0),
    }
}

impl Arbitrary for QcState {
    fn arbitrary(g: &mut Gen) -> Self {
        QcState {
            q: [qc_coord(g), qc_coord(g), qc_coord(g)],
            u: [qc_coord(g), qc_coord(g)],
            t: crate::common::from_bits_in(u64::arbitrary(g), 0.0, 1.0),
        }
    }
    /// Simpler states: a component set to 0 or truncated to an integer, or half the time.
    /// They stay in range.
    fn shrink(&self) -> Box<dyn Iterator<Item = Self>> {
        let mut out = Vec::new();
        for i in 0..6 {
            let get = |s: &QcState| if i < 3 { s.q[i] } else { s.u[i - 3] };
            let set = |s: &mut QcState, v: f64| {
                if i < 3 {
                    s.q[i] = v
                } else {
                    s.u[i - 3] = v
                }
            };
            let v = get(self);
            for c in [0.0, v.trunc()] {
                if c != v {
                    let mut s = self.clone();
                    set(&mut s, c);
                    out.push(s);
                }
            }
        }
        if self.t > 1e-3 {
            out.push(QcState {
                t: self.t / 2.0,
                ..self.clone()
            });
        }
        Box::new(out.into_iter())
    }
}

thread_local! {
    /// The scene, model and tally of the quickcheck property running on this thread
    /// (quickcheck takes a plain `fn`, which cannot capture them).
    static QC: RefCell<Option<(Scene, Model, Tally)>> = const { RefCell::new(None) };
}

fn qc_property(s: QcState) -> TestResult {
    // Every generated input is finite and in range by construction; the guard only
    // documents it (a state out of range would be discarded, not tested).
    if !(s
        .q
        .iter()
        .chain(&s.u)
        .all(|x| x.is_finite() && x.abs() <= 10.0)
        && (0.0..=1.0).contains(&s.t))
    {
        return TestResult::discard();
    }
    QC.with(|qc| {
        let mut qc = qc.borrow_mut();
        let (scene, m, tally) = qc.as_mut().expect("quickcheck state");
        match check(*scene, m, s.q, s.u, s.t, tally) {
            Ok(()) => TestResult::passed(),
            Err(msg) => TestResult::error(msg),
        }
    })
}

fn quickcheck_scene(scene: Scene, tests: u64, seed: u64) -> Tally {
    QC.with(|qc| *qc.borrow_mut() = Some((scene, scene.model(), Tally::default())));
    QuickCheck::new()
        .rng(Gen::from_size_and_seed(100, seed))
        .tests(tests)
        .max_tests(10 * tests)
        .quickcheck(qc_property as fn(QcState) -> TestResult);
    QC.with(|qc| qc.borrow_mut().take().expect("quickcheck state").2)
}

#[test]
fn quickcheck_particle() {
    let t = quickcheck_scene(Scene::Particle, 400, 0x5eed_0001);
    assert_tally("quickcheck particle", &t);
}

#[test]
fn quickcheck_knife() {
    let t = quickcheck_scene(Scene::Knife, 100, 0x5eed_0002);
    assert_tally("quickcheck knife", &t);
}

// ---------------------------------------------------------------------------------------
// Longer times (a few cases; the knife's cost grows with |w| t).

#[test]
fn long_times_particle() {
    let mut rng = SplitMix64(0x1009_71e5);
    let m = Scene::Particle.model();
    let mut tally = Tally::default();
    for _ in 0..6 {
        let q = [
            rng.uniform(-10.0, 10.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(-10.0, 10.0),
        ];
        let u = [rng.uniform(-10.0, 10.0), rng.uniform(-10.0, 10.0)];
        let t = rng.uniform(1.0, 50.0);
        check(Scene::Particle, &m, q, u, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
    }
    check(
        Scene::Particle,
        &m,
        [1.0, -3.0, 2.0],
        [-4.0, 6.0],
        50.0,
        &mut tally,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(tally.uncertified, 0, "{tally:?}");
    assert_tally("long particle", &tally);
}

#[test]
fn long_times_knife() {
    let mut rng = SplitMix64(0x10_6a1f);
    let m = Scene::Knife.model();
    let mut tally = Tally::default();
    for _ in 0..3 {
        let q = [
            rng.uniform(-10.0, 10.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(-10.0, 10.0),
        ];
        let u = [rng.uniform(-10.0, 10.0), rng.uniform(-1.0, 1.0)];
        let t = rng.uniform(1.0, 50.0);
        check(Scene::Knife, &m, q, u, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
    }
    check(
        Scene::Knife,
        &m,
        [2.0, -1.0, 0.5],
        [-3.0, 0.0],
        50.0,
        &mut tally,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    check(
        Scene::Knife,
        &m,
        [2.0, -1.0, 0.5],
        [3.0, -2.0],
        20.0,
        &mut tally,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(tally.uncertified, 0, "{tally:?}");
    assert_tally("long knife", &tally);
}

// ---------------------------------------------------------------------------------------
// Extremes.

/// Spec (5.8) (e) and (5.4'): a span of two or three steps at order 22 runs at order 28,
/// and the retry of a rejected try uses that try's a priori box; the state still meets
/// the closed form.
#[test]
fn particle_short_span_at_order_28_with_a_retry() {
    for q in [[0.0, 0.0, 0.0], [0.0, 0.4, 0.0], [1.0, 1.0, -1.0]] {
        let e = check_one(Scene::Particle, q, [0.8, 0.8], 0.5);
        assert_eq!(e.stats.order, 28, "q = {q:?}");
        assert!(e.stats.rejected >= 1, "q = {q:?}: {:?}", e.stats);
    }
    // a span of one step keeps order 22 (and its last step a lower one, (5.8'))
    let e = check_one(Scene::Particle, [0.0, 0.0, 0.0], [0.8, 0.8], 0.05);
    assert_eq!((e.stats.order, e.stats.steps), (22, 1));
}

#[test]
fn particle_u2_zero() {
    for (q, u, t) in [
        ([0.0, 0.0, 0.0], [0.8, 0.0], 1.0),
        ([1.5, -2.5, 3.0], [-7.0, 0.0], 0.75),
        ([-3.0, 9.0, -4.0], [10.0, 0.0], 1.0),
        ([-3.0, 9.0, -4.0], [10.0, -0.0], 20.0),
        ([0.0, 0.0, 0.0], [0.0, 0.0], 1.0),
    ] {
        let e = check_one(Scene::Particle, q, u, t);
        // y and yd stay exactly constant.
        assert!(e.q[1].contains(q[1]) && e.u[1].contains(0.0));
    }
}

#[test]
fn knife_w_zero() {
    for (q, u, t) in [
        ([0.0, 0.0, 0.0], [0.8, 0.0], 1.0),
        ([1.5, -2.5, 3.0], [-7.0, 0.0], 0.75),
        ([-3.0, 9.0, -4.0], [10.0, -0.0], 1.0),
        ([0.0, 0.0, std::f64::consts::FRAC_PI_2], [0.0, 0.0], 1.0),
        ([1.0, 1.0, 2.0], [-2.0, 0.0], 10.0),
    ] {
        let e = check_one(Scene::Knife, q, u, t);
        assert!(e.q[2].contains(q[2]) && e.u[1].contains(0.0));
    }
}

#[test]
fn tiny_second_velocity() {
    for w in [1e-300, -1e-300, 1e-12, -1e-12, f64::MIN_POSITIVE, 5e-324] {
        for (q, u0, t) in [
            ([0.0, 0.0, 0.0], 0.8, 1.0),
            ([1.0, -2.0, 3.0], -5.0, 1.0),
            ([-9.0, 7.5, 0.25], 10.0, 0.5),
        ] {
            check_one(Scene::Particle, q, [u0, w], t);
            check_one(Scene::Knife, q, [u0, w], t);
        }
    }
}

#[test]
fn particle_huge_y() {
    for y0 in [1e6, -1e6] {
        for (u, t) in [
            ([0.8, 0.8], 1.0),
            ([-10.0, 10.0], 1.0),
            ([10.0, -10.0], 0.5),
            ([3.0, 0.0], 1.0),
            ([3.0, 1e-12], 1.0),
        ] {
            check_one(Scene::Particle, [1.0, y0, -2.0], u, t);
        }
    }
}

#[test]
fn particle_t600() {
    let e = check_one(Scene::Particle, [0.0, 0.0, 0.0], [0.8, 0.8], 600.0);
    // y(600) = 480 exactly.
    assert!(e.q[1].contains(480.0));
}

#[test]
fn negative_velocities() {
    for (q, u, t) in [
        ([0.0, 0.0, 0.0], [-0.8, -0.8], 1.0),
        ([2.0, 5.0, -1.0], [-10.0, -10.0], 1.0),
        ([2.0, -5.0, -1.0], [-3.0, -7.0], 1.0),
        // y crosses 0.
        ([0.0, 2.0, 0.0], [-1.0, -4.0], 1.0),
        ([0.0, -2.0, 0.0], [-1.0, 4.0], 1.0),
    ] {
        check_one(Scene::Particle, q, u, t);
        check_one(Scene::Knife, q, u, t);
    }
}

#[test]
fn zero_time_returns_input_exactly() {
    for (q, u) in [
        ([0.0, 0.0, 0.0], [0.8, 0.8]),
        ([1.0, -2.0, 3.0], [-5.0, 7.0]),
        ([0.1, 0.2, 0.3], [0.4, 0.5]),
        ([-1e6, 1e6, 7.0], [1e-300, -10.0]),
    ] {
        for scene in [Scene::Particle, Scene::Knife] {
            let e = check_one(scene, q, u, 0.0);
            for (c, x) in e.q.iter().zip(q).chain(e.u.iter().zip(u)) {
                assert!(
                    c.wid() == 0.0 && c.contains(x),
                    "{}: t = 0 must return the input exactly, got {} for {}\n{}",
                    scene.name(),
                    show(*c),
                    hex(x),
                    describe(scene.name(), &[], &q, &u, 0.0)
                );
            }
        }
    }
}

#[test]
fn tiny_time() {
    for t in [1e-300, 5e-324, 1e-15] {
        for (q, u) in [
            ([0.0, 0.0, 0.0], [0.8, 0.8]),
            ([1.0, -2.0, 3.0], [-5.0, 7.0]),
            ([1.0, 1e6, 3.0], [-10.0, 10.0]),
        ] {
            for scene in [Scene::Particle, Scene::Knife] {
                let e = check_one(scene, q, u, t);
                // The state barely moves.
                for (c, x) in e.q.iter().zip(q).chain(e.u.iter().zip(u)) {
                    assert!(
                        c.wid() <= 1e-12 * x.abs().max(1.0),
                        "{}: too wide at tiny t: {}\n{}",
                        scene.name(),
                        show(*c),
                        describe(scene.name(), &[], &q, &u, t)
                    );
                }
            }
        }
    }
}

/// knife-eps with eps = 0 is the knife: the same closed form applies.
#[test]
fn knife_eps_zero_is_the_knife() {
    let m = model("knife-eps", &[("eps", 0.0)]);
    let mut rng = SplitMix64(0xe95_0000);
    let mut cases = vec![([1.0, -2.0, 3.0], [-5.0, 0.0], 1.0)];
    for _ in 0..12 {
        let q = [0; 3].map(|_| rng.uniform(-10.0, 10.0));
        let u = [0; 2].map(|_| rng.uniform(-10.0, 10.0));
        cases.push((q, u, rng.uniform(0.0, 1.0)));
    }
    for (q, u, t) in cases {
        let note = "NOTE: the model is knife-eps with eps = 0 (exactly), not knife";
        let e = run(&m, &q, &u, t).unwrap_or_else(|err| {
            panic!(
                "{note}: {err}\n{}",
                describe("knife-eps", &[("eps", 0.0)], &q, &u, t)
            )
        });
        if let Err(msg) = compare(Scene::Knife, q, u, t, &e) {
            panic!("{note}\n{msg}");
        }
    }
}
