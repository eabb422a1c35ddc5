//! Runs the example Python client (examples/python/check_dla.py) against this build's binary:
//! a DLA step written in Python is checked through the batch protocol (issue: the oracle
//! used from another language). The script asserts its own properties and exits non-zero on
//! failure.

use std::process::Command;

#[test]
fn python_dla_client_passes_against_the_oracle() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/python/check_dla.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_dalembert"))
        .output()
        .expect("python3 is needed for this test (CPython 3 is on the CI machines)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "client failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.trim_end().ends_with("ok"), "{stdout}");
}
