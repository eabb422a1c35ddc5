//! Runs the example Python clients against this build's binary, as a user would:
//! examples/python/check_dla.py (a DLA step written in Python checked through the batch
//! protocol), examples/python/own_system.py (a system that is not built in, posed inline
//! in `batch` queries, checked against its closed form) and
//! examples/python/validate_scheme.py (a scheme written in Python validated on the contact
//! oscillator through the module). Each script asserts its own properties and exits
//! non-zero on failure. Also the unit tests of the Python module
//! clients/python/dalembert_oracle.py and of clients/python/shard.py (`python3 -m unittest`,
//! with $DALEMBERT set to this build's binary). Where `python3` cannot be run, the tests say
//! so and pass.

use std::process::Command;

/// Whether `python3` runs here; if not, says which test is skipped.
fn python3(test: &str) -> bool {
    let runs = Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !runs {
        eprintln!("skipped {test}: python3 cannot be run here");
    }
    runs
}

fn run_client(script: &str) {
    if !python3(script) {
        return;
    }
    let path = format!("{}/examples/python/{script}", env!("CARGO_MANIFEST_DIR"));
    let out = Command::new("python3")
        .arg(&path)
        .arg(env!("CARGO_BIN_EXE_dalembert"))
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .expect("python3 is needed for this test (CPython 3 is on the CI machines)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{script} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.trim_end().ends_with("ok"), "{stdout}");
}

#[test]
fn python_dla_client_passes_against_the_oracle() {
    run_client("check_dla.py");
}

#[test]
fn python_poses_its_own_system_inline() {
    run_client("own_system.py");
}

#[test]
fn python_validates_a_scheme_through_the_module() {
    run_client("validate_scheme.py");
}

#[test]
fn python_module_unit_tests_pass() {
    if !python3("python_module_unit_tests_pass") {
        return;
    }
    let dir = format!("{}/clients/python", env!("CARGO_MANIFEST_DIR"));
    let out = Command::new("python3")
        .args(["-m", "unittest", "-v", "test_dalembert_oracle"])
        .current_dir(&dir)
        .env("DALEMBERT", env!("CARGO_BIN_EXE_dalembert"))
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .expect("python3 is needed for this test (CPython 3 is on the CI machines)");
    assert!(
        out.status.success(),
        "python3 -m unittest test_dalembert_oracle failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
