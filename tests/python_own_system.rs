//! Runs examples/python/own_system.py against this build's binary: a system that is not
//! built in, posed inline in `batch` queries from Python, checked against its closed form
//! and used to certify a Python step's error (README, "Your own system"). The script
//! asserts its own properties and exits non-zero on failure.

use std::process::Command;

#[test]
fn python_poses_its_own_system_inline() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/python/own_system.py");
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
