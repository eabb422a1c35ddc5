#![no_main]
// A cargo-fuzz target for your Newton solver: copy to your `fuzz/fuzz_targets/`.
use dalembert::testing::fuzz::fuzz_solver;
use libfuzzer_sys::fuzz_target;
use std::sync::LazyLock;

#[path = "../my_solver.rs"] // in your crate: `use your_crate::{setup, tolerance, MySolver};`
mod my_solver;
use my_solver::{setup, tolerance, MySolver};

static SETUP: LazyLock<(dalembert::Model, MySolver)> = LazyLock::new(setup);

fuzz_target!(|data: &[u8]| {
    let (model, solver) = &*SETUP;
    fuzz_solver(model, solver, tolerance, data); // panics on a finding
});
