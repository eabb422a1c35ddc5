//! The solver under test (template; README section "Fuzzing your own Newton solver"). Replace `MySolver` by your solver and
//! `tolerance` by the accuracy you claim for it; the fuzz target
//! (`fuzz_targets/my_solver.rs`) and the replay test (`replay.rs`) use these three items.
//! Here the solver is the crate's DLA scheme with its own Newton, as a stand-in.

use dalembert::schemes::{NewtonOptions, Scheme, SchemeKind};
use dalembert::testing::fuzz::{NewtonSolver, SolverAnswer, SolverInput};
use dalembert::{AnyScene, Model};

/// Your solver: one step `q2` of your two-step integrator from `(q0, q1, h)`.
pub struct MySolver {
    scheme: Scheme,
    newton: NewtonOptions,
}

impl NewtonSolver for MySolver {
    /// Your solver's typed failure: never a finding.
    type Error = String;
    fn solve(&self, q0: &[f64], q1: &[f64], h: f64) -> Result<SolverAnswer, String> {
        match self.scheme.step(q0, q1, h, &self.newton) {
            Ok((q2, _iterations, _residual)) => Ok(SolverAnswer {
                q2,
                converged: true,
            }),
            Err(failure) => Err(failure.to_string()),
        }
    }
}

/// The system (a scene of dalembert, a scene file, or your `Scene` type) and the solver,
/// built once per process.
pub fn setup() -> (Model, MySolver) {
    let scene = AnyScene::new("particle", &[]).expect("a registered scene");
    let model = Model::new(&scene).expect("the particle compiles");
    let scheme = Scheme::new(&model, SchemeKind::Dla);
    let newton = NewtonOptions::default();
    (model, MySolver { scheme, newton })
}

/// The accuracy you claim for a converged answer against the exact discrete step: here
/// rounding (`1e-9` relative) plus DLA's local error, of order `scale^3`, and four times the
/// distance of a pair put near `M_h^{e,nh}`; no claim on Euler pairs (not checked).
pub fn tolerance(input: &SolverInput) -> f64 {
    input.tolerance(1e-9, 2.0, 3)
}
