//! The integration tests, one crate (compiled and linked once): a module per subject, and
//! the helpers they share in `common`. It needs the features the `[[test]]` entry of
//! Cargo.toml lists (`cli`, `proptest`, `quickcheck`, `fuzzing`, `internals`), which the
//! crate's self dev-dependency turns on for `cargo test`.

mod common;

// The fuzzing example's solver and replay, as a user copies them into their own tests
// (`replay.rs` reaches the solver as `crate::my_solver`).
#[path = "../../examples/fuzz_newton/my_solver.rs"]
mod my_solver;
#[path = "../../examples/fuzz_newton/replay.rs"]
mod replay;

mod batch_talk;
mod cli_exact;
mod cli_flow;
mod cli_input;
mod cli_jacobian;
mod closed_forms;
mod clusterfuzzlite;
mod dense_and_nonuniform;
mod disk_sleigh_oscillator;
mod elementary;
mod energy_disk_sleigh_oscillator;
mod exact_discrete;
mod figures;
mod fuzz_corpus;
mod input_readers;
mod knife_eps;
mod oracle_properties;
mod precision_dd;
mod precision_dot;
mod precision_fixed;
mod precision_flow;
mod precision_mp;
mod precision_wide;
mod public_types;
mod readme_commands;
mod readme_own_scheme;
mod readme_proptest;
mod refusal_causes;
mod reversibility;
mod scene_file_cli;
mod scene_files;
mod schemes;
mod serde_answers;
mod sleigh_closed_form;
mod testing_fuzz;
mod testing_kit;
mod tightness;
mod user_met;
mod user_scene;
mod work_budget;
mod work_limit;
