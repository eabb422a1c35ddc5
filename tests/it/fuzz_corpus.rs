//! Replays the committed fuzz corpus and regressions through the fuzz targets' checks
//! (`dalembert::fuzzing`) on the stable toolchain: every input must pass its target's
//! invariant (a panic fails the test and names the file). Without `fuzz/` (a copy of the
//! crate that does not ship it) the tests say so and pass.

use dalembert::fuzzing::Tally;
use std::io::Write;
use std::path::Path;

fn replay(target: &str, check: fn(&[u8]) -> Tally) -> Tally {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    if !fuzz.is_dir() {
        eprintln!(
            "skipped {target}: no {} (the fuzz corpus is not here)",
            fuzz.display()
        );
        return Tally::default();
    }
    let mut n = 0;
    let mut tally = Tally::default();
    for dir in ["corpus", "regressions"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fuzz")
            .join(dir)
            .join(target);
        let Ok(entries) = std::fs::read_dir(&path) else {
            continue;
        };
        let mut files: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
        files.sort();
        for f in files {
            let data = std::fs::read(&f).expect("readable corpus file");
            let r = std::panic::catch_unwind(|| check(&data));
            match r {
                Ok(t) => tally.add(t),
                Err(_) => panic!("{target}: input {} broke the invariant", f.display()),
            }
            n += 1;
        }
    }
    assert!(n > 0, "no corpus for {target}");
    // written past the test harness's capture, so that every run shows the shares
    let _ = writeln!(std::io::stderr(), "{target}: {n} inputs: {tally}");
    tally
}

#[test]
fn newton_step_corpus() {
    replay("newton_step", dalembert::fuzzing::newton_step);
}

#[test]
fn retraction_corpus() {
    replay("retraction", dalembert::fuzzing::retraction);
}

#[test]
fn batch_line_corpus() {
    replay("batch_line", dalembert::fuzzing::batch_line);
}

#[test]
fn scenes_step_corpus() {
    replay("scenes_step", dalembert::fuzzing::scenes_step);
}

#[test]
fn scene_file_corpus() {
    replay("scene_file", dalembert::fuzzing::scene_file);
}

#[test]
fn precision_step_corpus() {
    let t = replay("precision_step", dalembert::fuzzing::precision_step);
    // the corpus is the retraction's: a good share of its pairs are answered at both
    // precisions, so the comparison is not vacuous
    assert!(t.answered >= 10, "{t}");
}

#[test]
fn precision_wide_step_corpus() {
    let t = replay(
        "precision_wide_step",
        dalembert::fuzzing::precision_wide_step,
    );
    // seeded from the retraction's corpus as precision_step is: answered at both precisions
    assert!(t.answered >= 10, "{t}");
}
