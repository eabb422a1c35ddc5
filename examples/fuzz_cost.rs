//! What each fuzz target costs per input: the committed corpus (and regressions) of every
//! target run through its check function (`dalembert::fuzzing`), timed one input at a
//! time. Prints per target the number of inputs, the total, median and largest time, the
//! slowest input, and the inputs a second this replay reaches (one core, release build):
//!
//! ```sh
//! cargo run --release --features fuzzing --example fuzz_cost [TARGET]
//! ```
//!
//! With `FUZZ_COST_DIR=DIR` (and a TARGET) it times the inputs in DIR instead, for example
//! the corpus copy a campaign grew; `FUZZ_COST_SLOWEST=N` lists the slowest N inputs (8
//! when N is not a number), each with its outcome.

use std::path::Path;
use std::time::Instant;

type Check = fn(&[u8]) -> dalembert::fuzzing::Tally;

fn main() {
    let only = std::env::args().nth(1);
    let targets: [(&str, Check); 7] = [
        ("newton_step", dalembert::fuzzing::newton_step),
        ("retraction", dalembert::fuzzing::retraction),
        ("scenes_step", dalembert::fuzzing::scenes_step),
        ("batch_line", dalembert::fuzzing::batch_line),
        ("scene_file", dalembert::fuzzing::scene_file),
        ("precision_step", dalembert::fuzzing::precision_step),
        (
            "precision_wide_step",
            dalembert::fuzzing::precision_wide_step,
        ),
    ];
    for (name, check) in targets {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let mut times = Vec::new();
        let mut tally = dalembert::fuzzing::Tally::default();
        let dirs: Vec<std::path::PathBuf> = match std::env::var_os("FUZZ_COST_DIR") {
            Some(d) => vec![d.into()],
            None => ["corpus", "regressions"]
                .iter()
                .map(|dir| {
                    Path::new(env!("CARGO_MANIFEST_DIR"))
                        .join("fuzz")
                        .join(dir)
                        .join(name)
                })
                .collect(),
        };
        for path in dirs {
            let Ok(entries) = std::fs::read_dir(&path) else {
                continue;
            };
            for e in entries.filter_map(Result::ok) {
                let data = std::fs::read(e.path()).expect("readable corpus file");
                // the first call builds the scene's model: warm it so it is not charged
                if times.is_empty() {
                    check(&data);
                }
                let t = Instant::now();
                let outcome = check(&data);
                times.push((t.elapsed().as_secs_f64(), e.path(), format!("{outcome}")));
                tally.add(outcome);
            }
        }
        times.sort_by(|a, b| a.0.total_cmp(&b.0));
        let total: f64 = times.iter().map(|t| t.0).sum();
        let Some((max, slowest, _)) = times.last() else {
            continue;
        };
        let tail: f64 = times[times.len() * 9 / 10..].iter().map(|t| t.0).sum();
        println!(
            "{name:12} {:5} inputs  total {total:7.3} s  median {:8.3} ms  max {:8.3} ms  \
             {:8.0} inputs/s  (the slowest tenth: {:.0}% of the time)\n             {tally}\n             slowest: {}",
            times.len(),
            1e3 * times[times.len() / 2].0,
            1e3 * max,
            times.len() as f64 / total,
            100.0 * tail / total,
            slowest.display()
        );
        if std::env::var_os("FUZZ_COST_SLOWEST").is_some() {
            for (t, path, outcome) in times.iter().rev().take(
                std::env::var("FUZZ_COST_SLOWEST")
                    .ok()
                    .and_then(|v| v.parse().ok())
                    .unwrap_or(8),
            ) {
                println!("  {:8.3} ms  {}  {outcome}", 1e3 * t, path.display());
            }
        }
    }
}
