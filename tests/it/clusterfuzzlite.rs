//! The ClusterFuzzLite files (`.clusterfuzzlite/`, `.github/workflows/cflite_pr.yml`) stay in
//! step with the cargo-fuzz workspace: the build script builds and copies exactly the
//! targets of `fuzz/Cargo.toml`, each with a source file and a committed corpus. (The build
//! itself needs nightly and a fuzzing toolchain; `.ci/run` runs it where `cargo fuzz` is
//! installed.) Without `fuzz/` or `.clusterfuzzlite/` (a copy of the crate that does not ship
//! them) the tests say so and pass.

use std::collections::BTreeSet;
use std::path::Path;

fn read(path: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
        .unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Whether `path` (from the package root) is here; if not, says which test is skipped.
fn present(path: &str, test: &str) -> bool {
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join(path).exists();
    if !here {
        eprintln!("skipped {test}: no {path} in this copy of the crate");
    }
    here
}

/// `(name, path)` of every `[[bin]]` table of fuzz/Cargo.toml.
fn fuzz_bins() -> Vec<(String, String)> {
    let manifest: toml::Table = read("fuzz/Cargo.toml").parse().expect("fuzz/Cargo.toml");
    manifest["bin"]
        .as_array()
        .expect("[[bin]] tables")
        .iter()
        .map(|b| {
            let s = |k: &str| b[k].as_str().expect("a string").to_string();
            (s("name"), s("path"))
        })
        .collect()
}

/// The words of the `TARGETS=(...)` line of the build script.
fn build_targets(script: &str) -> Vec<String> {
    let lines: Vec<&str> = script
        .lines()
        .filter(|l| l.starts_with("TARGETS=("))
        .collect();
    assert_eq!(lines.len(), 1, "one TARGETS=(...) line in build.sh");
    lines[0]
        .trim_start_matches("TARGETS=(")
        .trim_end_matches(')')
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

#[test]
fn build_script_builds_exactly_the_fuzz_targets() {
    if !present("fuzz", "build_script_builds_exactly_the_fuzz_targets")
        || !present(
            ".clusterfuzzlite",
            "build_script_builds_exactly_the_fuzz_targets",
        )
    {
        return;
    }
    let bins = fuzz_bins();
    let script = read(".clusterfuzzlite/build.sh");
    let targets = build_targets(&script);
    let names: BTreeSet<String> = bins.iter().map(|(n, _)| n.clone()).collect();
    let listed: BTreeSet<String> = targets.iter().cloned().collect();
    assert_eq!(listed.len(), targets.len(), "a target listed twice");
    assert_eq!(
        listed, names,
        "build.sh's TARGETS differ from the [[bin]] names of fuzz/Cargo.toml"
    );
    // built all at once, optimised, and each copied to $OUT with the CPU flag inari needs
    assert!(script.contains("cargo fuzz build -O"));
    assert!(
        script.contains("bins=\"${CARGO_TARGET_DIR:-target}/x86_64-unknown-linux-gnu/release\"")
    );
    assert!(script.contains("cp \"$bins/$target\" \"$OUT/\""));
    assert!(script.contains("-Ctarget-cpu=haswell"));
    assert!(script.starts_with("#!/bin/bash -eu\n"));
    for (name, path) in &bins {
        assert!(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("fuzz")
                .join(path)
                .is_file(),
            "{name}: no source {path}"
        );
        let corpus = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fuzz/corpus")
            .join(name);
        assert!(
            std::fs::read_dir(&corpus).is_ok_and(|mut d| d.next().is_some()),
            "{name}: no seed corpus in {}",
            corpus.display()
        );
    }
}

#[test]
fn the_image_and_the_workflow_are_the_documented_rust_setup() {
    if !present(
        ".clusterfuzzlite",
        "the_image_and_the_workflow_are_the_documented_rust_setup",
    ) || !present(
        ".github/workflows/cflite_pr.yml",
        "the_image_and_the_workflow_are_the_documented_rust_setup",
    ) {
        return;
    }
    let project = read(".clusterfuzzlite/project.yaml");
    assert!(project.lines().any(|l| l.trim() == "language: rust"));
    let docker = read(".clusterfuzzlite/Dockerfile");
    let first = docker
        .lines()
        .find(|l| !l.starts_with('#') && !l.trim().is_empty())
        .unwrap_or_default();
    assert_eq!(first, "FROM gcr.io/oss-fuzz-base/base-builder-rust");
    assert!(docker.contains("COPY .clusterfuzzlite/build.sh $SRC/"));
    let workflow = read(".github/workflows/cflite_pr.yml");
    for needle in [
        "google/clusterfuzzlite/actions/build_fuzzers@v1",
        "google/clusterfuzzlite/actions/run_fuzzers@v1",
        "language: rust",
        "mode: 'code-change'",
    ] {
        assert!(workflow.contains(needle), "cflite_pr.yml lacks `{needle}`");
    }
}

#[test]
fn the_targets_in_the_fuzz_readme_are_the_fuzz_targets() {
    if !present(
        "fuzz",
        "the_targets_in_the_fuzz_readme_are_the_fuzz_targets",
    ) {
        return;
    }
    // fuzz/README.md's list of binaries copied to $OUT, `{a,b,...}`
    let readme = read("fuzz/README.md");
    let start = readme
        .find("fuzz/target/x86_64-unknown-linux-gnu/release/{")
        .expect("fuzz/README.md names the binaries");
    let rest = &readme[start..];
    let list = &rest[rest.find('{').unwrap() + 1..rest.find('}').unwrap()];
    let named: BTreeSet<String> = list.split(',').map(|s| s.trim().to_string()).collect();
    let bins: BTreeSet<String> = fuzz_bins().into_iter().map(|(n, _)| n).collect();
    assert_eq!(named, bins);
}
