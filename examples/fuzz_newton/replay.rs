//! Replays the fuzz corpus through the harness on the stable toolchain, so that `cargo test`
//! keeps every committed input (seeds and past findings) passing (template: copy to your
//! `tests/`).
use crate::my_solver::{setup, tolerance}; // in your crate: `use your_crate::{setup, tolerance};`
use dalembert::testing::fuzz::{fuzz_solver, replay_dir};
use std::path::Path;

/// The corpus, from the package root (in your crate: "fuzz/corpus/my_solver").
const CORPUS: &str = "examples/fuzz_newton/corpus/my_solver";

#[test]
fn fuzz_corpus_replays() {
    let (model, solver) = setup();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(CORPUS);
    let tally = replay_dir(&dir, |data| fuzz_solver(&model, &solver, tolerance, data))
        .expect("a readable corpus");
    println!("{tally}");
    assert!(tally.total() > 0, "no inputs in {}", dir.display());
}
