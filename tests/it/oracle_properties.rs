//! Property suites built on the oracle (`dalembert::oracle`) and on the exact discrete objects
//! (`dalembert::exact`), for the particle and the knife.
//!
//! # 1. The float schemes against the exact discrete flow (proptest)
//!
//! Random initial states `q0 in [-1, 1]^3`, quasi-velocities `u in [-1, 1]^2`, a step
//! `h in [0.05, 0.2]` and `N in 10..=20` steps; `q1 = q0 + h E(q0)^T u` (a velocity in D at
//! q0). DLA and MLA integrate `q_0 .. q_N`, `check_trajectory` certifies the verdict, and the
//! property asserts, with `T = N h` and `V` a certified upper bound of the speed `|qd(t)|_2`
//! of the exact discrete trajectory at `t = 0, h, .., T` (from `verdict.exact.v`):
//!
//! - the verdict is certified (`Ok`) and sharp (width of the max distance <= 1e-10), and every
//!   pair defect and energy error is enclosed;
//! - global error, second order: `max_k |q_k - q^e_k|_inf <= C_DIST h^2 T (V + V^3)`;
//! - energy: `max_k |E_k - E_0| <= C_ENERGY h^2 (V + V^4)` (the oracle's energy error of the
//!   pair `(q_k, q_{k+1})`, from `R^{e-}`);
//! - defects: `max_k |s_k| <= C_DEFECT h^3 (V + V^3)` (the schemes' pairs lie on M_h^d, which
//!   is within O(h^3) of M_h^{e,nh});
//!
//! all three as *certified* statements (the upper ends of the enclosures), plus 1e-13 for
//! rounding. The scale `V + V^3` (resp. `V + V^4`): for the particle (no potential) the
//! scaling `u -> lambda u`, `h -> h / lambda` maps discrete trajectories to discrete
//! trajectories, so the error of a second-order scheme at fixed N is `h^2 T V^3` times a
//! function of the direction (`h^2 V^4` for the energy); the knife's gravity adds motion that
//! is not proportional to the initial speed, hence the linear term.
//!
//! Calibration: the largest error / scale over DLA and MLA met on two samples of the same
//! distribution (two one-off samples of 1000 particle and 300 knife states each, about 2
//! minutes; the harness is not kept in the suite):
//!
//! | scene    | distance        | energy          | defect          |
//! |----------|-----------------|-----------------|-----------------|
//! | particle | 0.0121 / 0.0133 | 0.0163 / 0.0175 | 0.0058 / 0.0057 |
//! | knife    | 0.0470 / 0.0441 | 0.0221 / 0.0228 | 0.0267 / 0.0317 |
//!
//! The constants are the larger value times about 1.5 (1.75 for the particle's defect). The
//! tests print the largest ratio measured / allowed they met, and assert that it is at least
//! 0.25, so a constant that became loose would be noticed.
//!
//! A second property, order of convergence: halving h (same `q0`, `u`, `T`) divides the
//! certified distance by at least 2.8 (observed order >= 1.5; smallest measured ratio 3.5).
//!
//! # 2. Laws of the exact discrete flow (quickcheck)
//!
//! For `q0 in [-2, 2]^3`, `u0 in [-1.5, 1.5]^2`, `h in [0.02, 0.4]`: `Q1 = flow(q0, u0, h).q`,
//! a box containing the point `q(h)` of M_h^{e,nh} over q0; `step(q0, Q1)` encloses
//! `q1 ∋ q(h)`, `q2 ∋ q(2h)`, `p_minus ∋ p(0)`, `p_plus ∋ p(h)`. The laws are checked in two
//! forms. The *box* form passes the enclosures themselves, which contain the exact pair on
//! M, so the claims are exact (containment of an exact point, or overlap of two
//! enclosures of one real quantity). The *float* form passes the midpoints, which are off M
//! by rounding; there exact claims are wrong in principle, and the tolerance is the width of
//! the box form: the midpoints lie inside the boxes, so the box form's result encloses both
//! the exact object and the float pair's object, and their distance is at most its width.
//! (Throughout, as in the library, "the" solution of the shooting equation is the unique one
//! in the Krawczyk box; for these step sizes it is the true trajectory's.)
//!
//! - momentum matching: `F^+ l(q0, q(h)) = F^- l(q(h), q(2h))`;
//! - reversibility (`L` quadratic in the velocities and constraints linear in them, so
//!   `t -> q(2h - t)` is a trajectory): `step(q(2h), q(h))` reaches `q(2h)` of the reversed
//!   trajectory, which is exactly `q0`, passing `q(h)` with momentum `-p(h)`;
//! - invariance of M_h^{e,nh}: `(q0, q(h))` has defect 0 and quasi-velocity `u0`, and its
//!   image `(q(h), q(2h))` has defect 0 and the quasi-velocity `u(h)` of the flow; moving
//!   `q(2h)` along `N` by `delta` moves the defect by exactly `-delta` (N is constant along
//!   those lines for both scenes) and is proved off M.
//!
//! # 3. A planted bug
//!
//! `planted::residual` rebuilds the MLA step from the crate's generic pieces (`ld_gradients`,
//! `discrete_force`, `discrete_constraint`, the scene's basis) with the sign of the force as a
//! parameter; with `+1` it equals `step_residual(.., Mla, ..)` (tested), with `-1` it is MLA
//! with the force sign flipped. It is solved by `newton::solve` with the Jacobian from
//! `Dual<f64>`. The suite of item 1 must fail on it, and proptest's shrunk input is printed.
//!
//! The flipped force is *not* a first-order perturbation. `F_nh(m)` annihilates `D_m`, so
//! `<F(m_{k+-1/2}), e_a(q_k)> = <F, e_a(q_k) - e_a(m_{k+-1/2})> = -+(h/2) <F, De_a v> + O(h^2)`:
//! the two forces' projections cancel to O(h^2), times the factor h/2 of eq. (7.2) gives
//! O(h^3) in the momentum equation, i.e. an O(h^2) change of the acceleration, and the
//! perturbed scheme is still second order (`halving_h_quarters_the_distance` asserts that for the bug too; measured
//! smallest distance ratios per halving 3.48 (particle) and 3.57 (knife), against 3.60 and
//! 3.50 for MLA). What changes is the error constant: at worst the bug's distance / scale
//! and energy error / scale are about 2.8 times the correct schemes' worst, and they exceed
//! the calibrated constants on 10% (particle) and 27% (knife) of the calibration states.
//! So the suite catches the bug through the constants, not through the order.
//!
//! # Determinism
//!
//! proptest: fixed ChaCha seeds, no failure persistence; quickcheck: `Gen::from_size_and_seed`
//! with inputs built from generated u64 words mapped into the ranges.

use crate::common::{gap, overlap};
use dalembert::exact::{self, ExactStep};
use dalembert::newton::{self, NewtonOutcome};
use dalembert::oracle::{check_trajectory, CheckOptions, Verdict};
use dalembert::scalar::{point, Dual, Scalar};
use dalembert::scene::{Knife, Particle, Scene};
use dalembert::schemes::{
    discrete_constraint, discrete_force, ld_gradients, step_residual, NewtonOptions, Scheme,
    SchemeKind,
};
use dalembert::Interval;
use dalembert::{flow, FlowOptions, Model};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestError, TestRng, TestRunner};
use quickcheck::{Arbitrary, Gen, QuickCheck, TestResult};
use std::cell::RefCell;

// ---------------------------------------------------------------------------------------
// Scenes.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Which {
    Particle,
    Knife,
}

impl Which {
    fn name(self) -> &'static str {
        match self {
            Which::Particle => "particle",
            Which::Knife => "knife",
        }
    }
    fn model(self) -> Model {
        crate::common::model(self.name(), &[])
    }
    /// Rows e_a(q) of the basis of D_q.
    fn basis(self, q: &[f64]) -> Vec<Vec<f64>> {
        match self {
            Which::Particle => Particle.basis(q),
            Which::Knife => Knife.basis(q),
        }
    }
    /// N(q) = mu(q)^T (k = 1: one column).
    fn normal(self, q: &[f64]) -> Vec<f64> {
        match self {
            Which::Particle => Particle.constraints(q)[0].clone(),
            Which::Knife => Knife.constraints(q)[0].clone(),
        }
    }
}

fn pts(v: &[f64]) -> Vec<Interval> {
    v.iter().map(|x| Interval::point(*x)).collect()
}

fn mids(v: &[Interval]) -> Vec<f64> {
    v.iter().map(|x| x.mid()).collect()
}

fn max_wid(v: &[Interval]) -> f64 {
    v.iter().map(|x| x.wid()).fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------
// 3. The planted bug: MLA rebuilt from the generic pieces, with the force sign a parameter.

mod planted {
    use super::*;

    /// `<D2 L_d(qm, qk) + sign F(qm, qk) + D1 L_d(qk, qp) + sign F(qk, qp), e_a(qk)>`, then
    /// `mu((qk + qp)/2)(qp - qk)` (spec eq. (7.4) when sign = +1).
    pub fn residual<Sc: Scene, S: Scalar>(
        sc: &Sc,
        sign: f64,
        qm: &[S],
        qk: &[S],
        qp: &[S],
        h: &S,
    ) -> Vec<S> {
        let n = qk.len();
        let (_, d2) = ld_gradients(sc, qm, qk, h);
        let (d1, _) = ld_gradients(sc, qk, qp, h);
        let fa = discrete_force(sc, SchemeKind::Mla, qm, qk, h);
        let fb = discrete_force(sc, SchemeKind::Mla, qk, qp, h);
        let g: Vec<S> = (0..n)
            .map(|i| d2[i].clone() + d1[i].clone() + S::cst(sign) * (fa[i].clone() + fb[i].clone()))
            .collect();
        sc.basis(qk)
            .iter()
            .map(|ea| (0..n).fold(S::zero(), |a, i| a + ea[i].clone() * g[i].clone()))
            .chain(discrete_constraint(sc, qk, qp))
            .collect()
    }

    /// `q_{k+1}` by Newton from `2 q_k - q_{k-1}`, Jacobian by forward-mode duals.
    pub fn step<Sc: Scene>(
        sc: &Sc,
        sign: f64,
        qm: &[f64],
        qk: &[f64],
        h: f64,
    ) -> Result<Vec<f64>, String> {
        let n = qk.len();
        let cst =
            |x: &[f64]| -> Vec<Dual<f64>> { x.iter().map(|v| Dual::new(*v, vec![])).collect() };
        let (dm, dk, dh) = (cst(qm), cst(qk), Dual::new(h, vec![]));
        let f = |x: &DVector<f64>| {
            let u: Vec<Dual<f64>> = (0..n).map(|j| Dual::var(x[j], j, n)).collect();
            let r = residual(sc, sign, &dm, &dk, &u, &dh);
            (
                DVector::from_fn(n, |i, _| r[i].v),
                DMatrix::from_fn(n, n, |i, j| r[i].der(j)),
            )
        };
        let mut x = DVector::from_fn(n, |i, _| 2.0 * qk[i] - qm[i]);
        match newton::solve(&mut x, f, &NewtonOptions::default()) {
            NewtonOutcome::Converged { .. } => Ok(x.iter().copied().collect()),
            NewtonOutcome::Failed(e) => Err(format!("Newton failed: {e}")),
        }
    }

    /// `q_0 .. q_N`; `q_1` projected onto M_h^d by the library's MLA (the projection does not
    /// involve the forces, so it is the same for the bug).
    pub fn integrate<Sc: Scene>(
        sc: &Sc,
        projector: &Scheme,
        sign: f64,
        q0: &[f64],
        q1: &[f64],
        h: f64,
        n: usize,
    ) -> Result<Vec<Vec<f64>>, String> {
        let (q1p, _, _) = projector
            .project(q0, q1, &NewtonOptions::default())
            .map_err(|e| format!("projection failed: {e}"))?;
        let mut q = vec![q0.to_vec(), q1p];
        for k in 1..n {
            let next = step(sc, sign, &q[k - 1], &q[k], h)?;
            q.push(next);
        }
        Ok(q)
    }
}

// ---------------------------------------------------------------------------------------
// The subjects: a scene and a candidate scheme.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Candidate {
    Dla,
    Mla,
    /// MLA with the sign of the discrete nonholonomic force flipped (the planted bug).
    FlippedForceMla,
}

struct Subject {
    which: Which,
    cand: Candidate,
    model: Model,
    scheme: Scheme,
}

impl Subject {
    fn new(which: Which, cand: Candidate) -> Subject {
        let model = which.model();
        let kind = match cand {
            Candidate::Dla => SchemeKind::Dla,
            Candidate::Mla | Candidate::FlippedForceMla => SchemeKind::Mla,
        };
        let scheme = Scheme::new(&model, kind);
        Subject {
            which,
            cand,
            model,
            scheme,
        }
    }

    fn integrate(&self, q0: &[f64], q1: &[f64], h: f64, n: usize) -> Result<Vec<Vec<f64>>, String> {
        match self.cand {
            Candidate::Dla | Candidate::Mla => self
                .scheme
                .integrate(q0, q1, h, n, &NewtonOptions::default())
                .map(|t| t.q)
                .map_err(|e| format!("{e:?}")),
            Candidate::FlippedForceMla => match self.which {
                Which::Particle => planted::integrate(&Particle, &self.scheme, -1.0, q0, q1, h, n),
                Which::Knife => planted::integrate(&Knife, &self.scheme, -1.0, q0, q1, h, n),
            },
        }
    }
}

// ---------------------------------------------------------------------------------------
// 1. The property suite.

/// Calibrated constants (see the module documentation for the measured values).
struct Constants {
    dist: f64,
    energy: f64,
    defect: f64,
}

fn constants(which: Which) -> Constants {
    match which {
        // measured maxima 0.0133, 0.0175, 0.0058
        Which::Particle => Constants {
            dist: 0.020,
            energy: 0.026,
            defect: 0.010,
        },
        // measured maxima 0.0470, 0.0228, 0.0317
        Which::Knife => Constants {
            dist: 0.071,
            energy: 0.034,
            defect: 0.048,
        },
    }
}

/// Rounding allowance of the float schemes (absolute).
const ROUNDING: f64 = 1e-13;

#[derive(Clone, Debug)]
struct Case {
    q0: [f64; 3],
    u: [f64; 2],
    h: f64,
    n: usize,
}

fn case_strategy() -> impl Strategy<Value = Case> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        prop::array::uniform2(-1.0f64..1.0),
        0.05f64..0.2,
        10usize..=20,
    )
        .prop_map(|(q0, u, h, n)| Case { q0, u, h, n })
}

/// `(q0, q0 + h E(q0)^T u)`.
fn start(which: Which, q0: &[f64; 3], u: &[f64; 2], h: f64) -> (Vec<f64>, Vec<f64>) {
    let e = which.basis(q0);
    let q1 = (0..3)
        .map(|i| q0[i] + h * (u[0] * e[0][i] + u[1] * e[1][i]))
        .collect();
    (q0.to_vec(), q1)
}

/// Certified upper bound of `max_k |qd(kh)|_2` along the exact trajectory.
fn speed_bound(v: &Verdict) -> f64 {
    v.exact
        .v
        .iter()
        .map(|w| {
            let s: f64 = w.iter().map(|x| x.mag() * x.mag()).sum();
            s.sqrt() * (1.0 + 1e-15)
        })
        .fold(0.0, f64::max)
}

/// Measured / allowed, for each of the three bounds (the property holds iff all are <= 1,
/// up to the rounding allowance).
#[derive(Clone, Copy, Debug, Default)]
struct Figures {
    dist: f64,
    energy: f64,
    defect: f64,
}

impl Figures {
    fn max(self, o: Figures) -> Figures {
        Figures {
            dist: self.dist.max(o.dist),
            energy: self.energy.max(o.energy),
            defect: self.defect.max(o.defect),
        }
    }
}

/// The three errors of one candidate trajectory and their scales.
struct Measured {
    /// Certified upper bounds: max distance, max |energy error|, max |defect|.
    error: Figures,
    /// `h^2 T (V + V^3)`, `h^2 (V + V^4)`, `h^3 (V + V^3)`.
    scale: Figures,
    v: f64,
    t: f64,
}

fn measure(s: &Subject, c: &Case) -> Result<Measured, String> {
    let (q0, q1) = start(s.which, &c.q0, &c.u, c.h);
    let q = s.integrate(&q0, &q1, c.h, c.n)?;
    let v = check_trajectory(&s.model, c.h, &q, &CheckOptions::default())
        .map_err(|e| format!("oracle did not certify the verdict: {e}"))?;
    if v.max_distance.wid() > 1e-10 {
        return Err(format!(
            "verdict not sharp: max distance {:?}",
            v.max_distance
        ));
    }
    if v.defect.len() != c.n || v.energy_error.len() != c.n {
        return Err("missing pair figures".into());
    }
    let t = c.h * c.n as f64;
    let vb = speed_bound(&v);
    let mag_max = |it: &mut dyn Iterator<Item = &Interval>| it.map(|e| e.mag()).fold(0.0, f64::max);
    Ok(Measured {
        error: Figures {
            dist: v.max_distance.sup(),
            energy: mag_max(&mut v.energy_error.iter()),
            defect: mag_max(&mut v.defect.iter().flatten()),
        },
        scale: Figures {
            dist: c.h * c.h * t * (vb + vb.powi(3)),
            energy: c.h * c.h * (vb + vb.powi(4)),
            defect: c.h.powi(3) * (vb + vb.powi(3)),
        },
        v: vb,
        t,
    })
}

/// The property of item 1 for one subject and one case; on success, measured / allowed.
fn property(s: &Subject, c: &Case) -> Result<Figures, String> {
    let m = measure(s, c)?;
    let k = constants(s.which);
    let (e, sc) = (m.error, m.scale);
    let allowed = Figures {
        dist: k.dist * sc.dist,
        energy: k.energy * sc.energy,
        defect: k.defect * sc.defect,
    };
    let fig = Figures {
        dist: e.dist / allowed.dist,
        energy: e.energy / allowed.energy,
        defect: e.defect / allowed.defect,
    };
    let mut bad = Vec::new();
    if e.dist > allowed.dist + ROUNDING {
        bad.push(format!(
            "distance to the exact flow {:e} exceeds C h^2 T (V + V^3) = {:e}",
            e.dist, allowed.dist
        ));
    }
    if e.energy > allowed.energy + ROUNDING {
        bad.push(format!(
            "energy error {:e} exceeds C h^2 (V + V^4) = {:e}",
            e.energy, allowed.energy
        ));
    }
    if e.defect > allowed.defect + ROUNDING {
        bad.push(format!(
            "defect {:e} exceeds C h^3 (V + V^3) = {:e}",
            e.defect, allowed.defect
        ));
    }
    if bad.is_empty() {
        Ok(fig)
    } else {
        Err(format!(
            "{} {:?}: {} (V = {:.4}, T = {:.4}; measured/allowed {fig:?})",
            s.which.name(),
            s.cand,
            bad.join("; "),
            m.v,
            m.t
        ))
    }
}

// The calibration of the constants (1000 particle and 300 knife states, about two minutes)
// was a one-off measurement; its figures are in the table at the top of this file.

const SEED_PARTICLE: [u8; 32] = *b"dalembert oracle props, particle";
const SEED_KNIFE: [u8; 32] = *b"dalembert oracle props, knife #1";

fn runner(seed: &[u8; 32], cases: u32, shrink_iters: u32) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            max_shrink_iters: shrink_iters,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, seed),
    )
}

fn seed(which: Which) -> &'static [u8; 32] {
    match which {
        Which::Particle => &SEED_PARTICLE,
        Which::Knife => &SEED_KNIFE,
    }
}

/// Run the suite of item 1 on one subject; the largest ratios met on passing cases.
fn run_suite(s: &Subject, cases: u32, shrink_iters: u32) -> (Result<(), TestError<Case>>, Figures) {
    let worst = RefCell::new(Figures::default());
    let mut r = runner(seed(s.which), cases, shrink_iters);
    let res = r.run(&case_strategy(), |c| {
        let f = property(s, &c).map_err(TestCaseError::fail)?;
        let w = worst.borrow().max(f);
        *worst.borrow_mut() = w;
        Ok(())
    });
    (res, worst.into_inner())
}

fn suite_passes(which: Which, cases: u32, shrink_iters: u32) {
    let k = constants(which);
    for cand in [Candidate::Dla, Candidate::Mla] {
        let s = Subject::new(which, cand);
        let (res, fig) = run_suite(&s, cases, shrink_iters);
        if let Err(e) = res {
            panic!("{} {cand:?}: {e}", which.name());
        }
        eprintln!(
            "{} {cand:?}: largest measured/allowed over {cases} cases: {fig:?} \
             (i.e. distance {:.4} h^2 T (V+V^3), energy {:.4} h^2 (V+V^4), defect {:.4} h^3 (V+V^3))",
            which.name(),
            fig.dist * k.dist,
            fig.energy * k.energy,
            fig.defect * k.defect
        );
        // The constants must stay tight enough to mean something (and to catch the bug).
        assert!(
            fig.dist > 0.25 && fig.energy > 0.25 && fig.defect > 0.25,
            "{} {cand:?}: a calibrated constant is loose by more than 4x: {fig:?}",
            which.name()
        );
    }
}

#[test]
fn dla_and_mla_particle_stay_within_second_order_bounds() {
    suite_passes(Which::Particle, 96, 128);
}

#[test]
fn dla_and_mla_knife_stay_within_second_order_bounds() {
    suite_passes(Which::Knife, 40, 48);
}

/// Observed order: the same (q0, u, T) at h and h/2.
fn halving(s: &Subject, c: &Case) -> Result<f64, String> {
    let o = CheckOptions::default().with_pairs(false);
    let dist = |h: f64, n: usize| -> Result<Interval, String> {
        let (q0, q1) = start(s.which, &c.q0, &c.u, h);
        let q = s.integrate(&q0, &q1, h, n)?;
        check_trajectory(&s.model, h, &q, &o)
            .map(|v| v.max_distance)
            .map_err(|e| format!("oracle did not certify: {e}"))
    };
    let (d1, d2) = (dist(c.h, c.n)?, dist(c.h / 2.0, 2 * c.n)?);
    if d1.sup() < 1e-11 {
        // no error to measure (e.g. a straight line): nothing to conclude
        return Ok(f64::INFINITY);
    }
    if 2.8 * d2.sup() > d1.inf() {
        return Err(format!(
            "halving h divided the distance only by {:.3} ({d1:?} -> {d2:?})",
            d1.inf() / d2.sup()
        ));
    }
    Ok(d1.inf() / d2.sup())
}

#[test]
fn halving_h_quarters_the_distance() {
    // The planted bug too: it is a second-order perturbation (see the module documentation).
    for (which, cases) in [(Which::Particle, 16), (Which::Knife, 6)] {
        for cand in [Candidate::Dla, Candidate::Mla, Candidate::FlippedForceMla] {
            let s = Subject::new(which, cand);
            let lo = RefCell::new(f64::INFINITY);
            let mut r = runner(seed(which), cases, 0);
            let res = r.run(&case_strategy(), |c| {
                let ratio = halving(&s, &c).map_err(TestCaseError::fail)?;
                let m = lo.borrow().min(ratio);
                *lo.borrow_mut() = m;
                Ok(())
            });
            if let Err(e) = res {
                panic!("{} {cand:?}: {e}", which.name());
            }
            eprintln!(
                "{} {cand:?}: smallest distance ratio per halving of h: {:.3}",
                which.name(),
                lo.into_inner()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// 3. The planted bug is caught by the same suite.

/// The hand-built residual with the library's sign is the library's MLA residual, and its
/// Newton step is the library's step: the bug below differs from MLA by the sign only.
#[test]
fn hand_built_mla_is_the_library_mla() {
    let mut r = runner(&SEED_PARTICLE, 32, 0);
    let res = r.run(&case_strategy(), |c| {
        for which in [Which::Particle, Which::Knife] {
            let model = which.model();
            let scheme = Scheme::new(&model, SchemeKind::Mla);
            let (q0, q1) = start(which, &c.q0, &c.u, c.h);
            let lib = scheme
                .integrate(&q0, &q1, c.h, 3, &NewtonOptions::default())
                .map_err(|e| TestCaseError::fail(format!("{e:?}")))?
                .q;
            let (qm, qk, qp) = (&lib[1], &lib[2], &lib[3]);
            let (a, b) = match which {
                Which::Particle => (
                    planted::residual(&Particle, 1.0, qm, qk, qp, &c.h),
                    step_residual(&Particle, SchemeKind::Mla, qm, qk, qp, &c.h),
                ),
                Which::Knife => (
                    planted::residual(&Knife, 1.0, qm, qk, qp, &c.h),
                    step_residual(&Knife, SchemeKind::Mla, qm, qk, qp, &c.h),
                ),
            };
            for (x, y) in a.iter().zip(&b) {
                prop_assert!((x - y).abs() <= 1e-14 * (1.0 + y.abs()), "{a:?} vs {b:?}");
            }
            let mine = match which {
                Which::Particle => planted::step(&Particle, 1.0, qm, qk, c.h),
                Which::Knife => planted::step(&Knife, 1.0, qm, qk, c.h),
            }
            .map_err(TestCaseError::fail)?;
            for (x, y) in mine.iter().zip(qp) {
                prop_assert!(
                    (x - y).abs() <= 1e-13 * (1.0 + y.abs()),
                    "{mine:?} vs {qp:?}"
                );
            }
        }
        Ok(())
    });
    if let Err(e) = res {
        panic!("{e}");
    }
}

fn planted_bug_is_caught(which: Which, cases: u32, shrink_iters: u32) {
    let bug = Subject::new(which, Candidate::FlippedForceMla);
    let (res, _) = run_suite(&bug, cases, shrink_iters);
    let (reason, minimal) = match res {
        Err(TestError::Fail(reason, minimal)) => (reason, minimal),
        Err(TestError::Abort(a)) => panic!("{}: the suite aborted: {a}", which.name()),
        Ok(()) => panic!(
            "{}: the planted bug (force sign flipped) passed the suite of {cases} cases",
            which.name()
        ),
    };
    eprintln!(
        "{}: planted bug caught; shrunk failing input {minimal:?}\n  reason: {reason}",
        which.name()
    );
    // It failed through a bound, not because something refused to run.
    let msg = reason.to_string();
    assert!(msg.contains("exceeds"), "unexpected failure: {msg}");
    // The same input passes with the correct scheme.
    let mla = Subject::new(which, Candidate::Mla);
    let ok = property(&mla, &minimal);
    assert!(
        ok.is_ok(),
        "MLA fails at the bug's minimal input {minimal:?}: {ok:?}"
    );
    eprintln!("  MLA at that input: measured/allowed {:?}", ok.unwrap());
}

#[test]
fn planted_bug_particle_is_caught() {
    planted_bug_is_caught(Which::Particle, 96, 128);
}

#[test]
fn planted_bug_knife_is_caught() {
    planted_bug_is_caught(Which::Knife, 40, 48);
}

// ---------------------------------------------------------------------------------------
// 2. Laws of the exact discrete flow (quickcheck).

#[derive(Clone, Debug)]
struct Pair {
    q0: [f64; 3],
    u0: [f64; 2],
    h: f64,
}

const H_MIN: f64 = 0.02;
const H_MAX: f64 = 0.4;

/// A uniform number in [lo, hi] from a random word.
fn in_range(g: &mut Gen, lo: f64, hi: f64) -> f64 {
    let unit = (u64::arbitrary(g) >> 11) as f64 / (1u64 << 53) as f64;
    (lo + (hi - lo) * unit).clamp(lo, hi)
}

impl Arbitrary for Pair {
    fn arbitrary(g: &mut Gen) -> Self {
        Pair {
            q0: [
                in_range(g, -2.0, 2.0),
                in_range(g, -2.0, 2.0),
                in_range(g, -2.0, 2.0),
            ],
            u0: [in_range(g, -1.5, 1.5), in_range(g, -1.5, 1.5)],
            h: in_range(g, H_MIN, H_MAX),
        }
    }
    /// Simpler pairs, still in range: a component set to 0 or rounded to one decimal, or
    /// h halved.
    fn shrink(&self) -> Box<dyn Iterator<Item = Self>> {
        let mut out = Vec::new();
        for i in 0..5 {
            let v = if i < 3 { self.q0[i] } else { self.u0[i - 3] };
            for c in [0.0, (v * 10.0).trunc() / 10.0] {
                if c != v {
                    let mut p = self.clone();
                    if i < 3 {
                        p.q0[i] = c;
                    } else {
                        p.u0[i - 3] = c;
                    }
                    out.push(p);
                }
            }
        }
        if self.h / 2.0 >= H_MIN {
            out.push(Pair {
                h: self.h / 2.0,
                ..self.clone()
            });
        }
        Box::new(out.into_iter())
    }
}

thread_local! {
    static MODELS: (Model, Model) = (Which::Particle.model(), Which::Knife.model());
    static TALLY: RefCell<Tally> = RefCell::new(Tally::default());
}

/// What the laws met: the widest box-form enclosure the claims rested on, and how often the
/// float form happened to satisfy the exact claim (overlap / containment) as well.
#[derive(Clone, Debug, Default)]
struct Tally {
    cases: usize,
    max_box_wid: f64,
    float_exact: usize,
}

fn tally(box_wid: f64, float_exact: bool) {
    TALLY.with(|t| {
        let mut t = t.borrow_mut();
        t.cases += 1;
        t.max_box_wid = t.max_box_wid.max(box_wid);
        t.float_exact += float_exact as usize;
    });
}

fn with_model<R>(which: Which, f: impl FnOnce(&Model) -> R) -> R {
    MODELS.with(|(p, k)| match which {
        Which::Particle => f(p),
        Which::Knife => f(k),
    })
}

/// Exact objects from (q0, u0, h): the flow's enclosure of (q(h), u(h)) and `step(q0, Q1)`.
struct Forward {
    q0: Vec<f64>,
    u_h: Vec<Interval>,
    st: ExactStep,
}

fn fopts() -> FlowOptions {
    FlowOptions::default()
}

fn forward(m: &Model, p: &Pair) -> Result<Forward, String> {
    let f = flow(m, &p.q0, &p.u0, p.h, &fopts()).map_err(|e| format!("flow: {e}"))?;
    let st = exact::step(m, &pts(&p.q0), &f.q, p.h, &fopts()).map_err(|e| format!("step: {e}"))?;
    // the flow's q(h) and the step's must agree, and the pair's quasi-velocity is u0
    if !overlap(&st.q1, &f.q) {
        return Err(format!("step q1 {:?} misses flow q(h) {:?}", st.q1, f.q));
    }
    Ok(Forward {
        q0: p.q0.to_vec(),
        u_h: f.u,
        st,
    })
}

/// Enclosures this wide would make the overlap claims nearly vacuous.
const SHARP: f64 = 1e-9;

fn sharp(what: &str, v: &[Interval]) -> Result<(), String> {
    if max_wid(v) > SHARP {
        return Err(format!("{what} not sharp: {v:?}"));
    }
    Ok(())
}

fn law_momentum_matching(which: Which, p: &Pair) -> Result<(), String> {
    with_model(which, |m| {
        let fw = forward(m, p)?;
        let st = &fw.st;
        // Box form: both enclose the D*-momentum of the one trajectory at q(h).
        let next = exact::step(m, &st.q1, &st.q2, p.h, &fopts())
            .map_err(|e| format!("step on the boxes (q(h), q(2h)): {e}"))?;
        if !overlap(&st.p_plus, &next.p_minus) {
            return Err(format!(
                "F+ l(q0, q(h)) {:?} and F- l(q(h), q(2h)) {:?} are disjoint",
                st.p_plus, next.p_minus
            ));
        }
        sharp("p_plus", &st.p_plus)?;
        sharp("p_minus on the boxes", &next.p_minus)?;
        // Float form: the midpoints lie in the boxes, so F- at the float pair lies in
        // `next.p_minus` as does the exact momentum: they differ by at most its width.
        let fl = exact::step(m, &pts(&mids(&st.q1)), &pts(&mids(&st.q2)), p.h, &fopts())
            .map_err(|e| format!("step on the float pair: {e}"))?;
        for a in 0..fl.p_minus.len() {
            let tol = next.p_minus[a].wid();
            if gap(fl.p_minus[a], st.p_plus[a]) > tol {
                return Err(format!(
                    "float pair: F- {:?} is farther than {tol:e} from F+ {:?}",
                    fl.p_minus, st.p_plus
                ));
            }
        }
        tally(
            max_wid(&st.p_plus).max(max_wid(&next.p_minus)),
            overlap(&fl.p_minus, &st.p_plus),
        );
        Ok(())
    })
}

fn law_reversibility(which: Which, p: &Pair) -> Result<(), String> {
    with_model(which, |m| {
        let fw = forward(m, p)?;
        let st = &fw.st;
        // Box form: (q(2h), q(h)) is on M (the reversed trajectory) and the exact discrete
        // flow maps it to (q(h), q0): q0 is an exact point, so it must be *contained*.
        let back = exact::step(m, &st.q2, &st.q1, p.h, &fopts())
            .map_err(|e| format!("step on the reversed boxes: {e}"))?;
        for i in 0..3 {
            if !back.q2[i].contains(fw.q0[i]) {
                return Err(format!(
                    "step(q(2h), q(h)).q2 = {:?} does not contain q0 = {:?}",
                    back.q2, fw.q0
                ));
            }
        }
        if !overlap(&back.q1, &st.q1) {
            return Err(format!("reversed q(h) {:?} vs {:?}", back.q1, st.q1));
        }
        // the reversed trajectory passes q(h) with momentum -p(h)
        let neg: Vec<inari::Interval> = st
            .p_plus
            .iter()
            .map(|x| -inari::Interval::from(*x))
            .collect();
        if !overlap(&back.p_plus, &neg) {
            return Err(format!(
                "reversed momentum at q(h) {:?} vs -p(h) {:?}",
                back.p_plus, neg
            ));
        }
        if !back.retraction.possibly_member() {
            return Err(format!(
                "reversed pair proved off M: s = {:?}",
                back.retraction.s
            ));
        }
        sharp("reversed q2", &back.q2)?;
        // Float form: (mid q(2h), mid q(h)) is off M by rounding, so its exact discrete flow
        // lands near q0, not at it: exact containment would be a wrong claim. Both it and q0
        // lie in `back.q2` (the float pair lies in the boxes), hence the tolerance.
        let fl = exact::step(m, &pts(&mids(&st.q2)), &pts(&mids(&st.q1)), p.h, &fopts())
            .map_err(|e| format!("step on the reversed float pair: {e}"))?;
        for i in 0..3 {
            let tol = back.q2[i].wid();
            if gap(fl.q2[i], point(fw.q0[i])) > tol {
                return Err(format!(
                    "float reversed pair lands at {:?}, farther than {tol:e} from q0 {:?}",
                    fl.q2, fw.q0
                ));
            }
        }
        tally(
            max_wid(&back.q2),
            (0..3).all(|i| fl.q2[i].contains(fw.q0[i])),
        );
        Ok(())
    })
}

fn law_invariance(which: Which, p: &Pair) -> Result<(), String> {
    with_model(which, |m| {
        let fw = forward(m, p)?;
        let st = &fw.st;
        // (q0, q(h)) is on M with quasi-velocity u0 (retract inverts exp)
        let r0 = &st.retraction;
        if !r0.possibly_member() {
            return Err(format!("(q0, q(h)) proved off M: s = {:?}", r0.s));
        }
        if !overlap(&r0.u0, &pts(&p.u0)) {
            return Err(format!("R^e-(q0, q(h)) = {:?} misses u0 {:?}", r0.u0, p.u0));
        }
        // the image pair (q(h), q(2h)) is on M with the flow's quasi-velocity u(h)
        let r1 = exact::retract(m, &st.q1, &st.q2, p.h, &fopts())
            .map_err(|e| format!("retract on (q(h), q(2h)): {e}"))?;
        if !r1.possibly_member() {
            return Err(format!("(q(h), q(2h)) proved off M: s = {:?}", r1.s));
        }
        if !overlap(&r1.u0, &fw.u_h) {
            return Err(format!(
                "R^e-(q(h), q(2h)) = {:?} misses u(h) {:?}",
                r1.u0, fw.u_h
            ));
        }
        sharp("defect on the boxes", &r1.s)?;
        // the float pair: its defect lies in r1.s (the pair lies in the boxes)
        let (q1m, q2m) = (mids(&st.q1), mids(&st.q2));
        let rf = exact::retract(m, &pts(&q1m), &pts(&q2m), p.h, &fopts())
            .map_err(|e| format!("retract on the float pair: {e}"))?;
        if !overlap(&rf.s, &r1.s) {
            return Err(format!("float defect {:?} vs box defect {:?}", rf.s, r1.s));
        }
        // control: q(2h) moved along N by delta is proved off M, defect shifted by -delta
        let delta = 1e-6;
        let nq = which.normal(&q2m);
        let moved: Vec<f64> = (0..3).map(|i| q2m[i] + delta * nq[i]).collect();
        let rc = exact::retract(m, &pts(&q1m), &pts(&moved), p.h, &fopts())
            .map_err(|e| format!("retract on the moved pair: {e}"))?;
        if rc.possibly_member() {
            return Err(format!("moved pair not proved off M: s = {:?}", rc.s));
        }
        let expect = rf.s[0].mid() - delta;
        if (rc.s[0].mid() - expect).abs() > 1e-12 {
            return Err(format!("moved pair: s = {:?}, expected {expect:e}", rc.s));
        }
        tally(max_wid(&r1.s), rf.possibly_member());
        Ok(())
    })
}

fn qc(what: &str, f: fn(Pair) -> TestResult, tests: u64, seed: u64) {
    TALLY.with(|t| *t.borrow_mut() = Tally::default());
    QuickCheck::new()
        .rng(Gen::from_size_and_seed(100, seed))
        .tests(tests)
        .max_tests(2 * tests)
        .quickcheck(f);
    let t = TALLY.with(|t| t.borrow().clone());
    eprintln!(
        "{what}: {} cases; widest box-form enclosure {:.1e}; float form met the exact claim in {} cases",
        t.cases, t.max_box_wid, t.float_exact
    );
    assert!(t.cases as u64 >= tests, "{what}: too few cases ran: {t:?}");
}

fn verdict(r: Result<(), String>) -> TestResult {
    match r {
        Ok(()) => TestResult::passed(),
        Err(e) => TestResult::error(e),
    }
}

#[test]
fn exact_flow_momentum_matching_particle() {
    fn prop(p: Pair) -> TestResult {
        verdict(law_momentum_matching(Which::Particle, &p))
    }
    qc(
        "exact_flow_momentum_matching_particle",
        prop,
        200,
        0x0c1e_0001,
    );
}

#[test]
fn exact_flow_momentum_matching_knife() {
    fn prop(p: Pair) -> TestResult {
        verdict(law_momentum_matching(Which::Knife, &p))
    }
    qc("exact_flow_momentum_matching_knife", prop, 60, 0x0c1e_0002);
}

#[test]
fn exact_flow_is_reversible_particle() {
    fn prop(p: Pair) -> TestResult {
        verdict(law_reversibility(Which::Particle, &p))
    }
    qc("exact_flow_is_reversible_particle", prop, 200, 0x0c1e_0003);
}

#[test]
fn exact_flow_is_reversible_knife() {
    fn prop(p: Pair) -> TestResult {
        verdict(law_reversibility(Which::Knife, &p))
    }
    qc("exact_flow_is_reversible_knife", prop, 60, 0x0c1e_0004);
}

#[test]
fn exact_flow_keeps_m_invariant_particle() {
    fn prop(p: Pair) -> TestResult {
        verdict(law_invariance(Which::Particle, &p))
    }
    qc(
        "exact_flow_keeps_m_invariant_particle",
        prop,
        200,
        0x0c1e_0005,
    );
}

#[test]
fn exact_flow_keeps_m_invariant_knife() {
    fn prop(p: Pair) -> TestResult {
        verdict(law_invariance(Which::Knife, &p))
    }
    qc("exact_flow_keeps_m_invariant_knife", prop, 60, 0x0c1e_0006);
}
