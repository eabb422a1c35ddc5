//! `dalembert figures --out DIR [--quick]`: compute the figures (`crate::report`) and
//! write them as SVG and CSV (`render.rs`).

use super::progress::SharedBar;
use super::render;
use crate::report::figures::{self, Settings};
use crate::Error;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

pub fn run(out: &str, quick: bool, as_json: bool) -> Result<String, Error> {
    let dir = Path::new(out);
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::input(format!("cannot create directory {out}: {e}")))?;
    let start = Instant::now();
    let settings = if quick {
        Settings::quick()
    } else {
        Settings::paper()
    };
    let bar = SharedBar::new();
    let figs = figures::all(&settings, &bar.progress())?;
    bar.clear();
    let mut files = vec![];
    for f in &figs {
        files.extend(render::write_figure(f, dir).map_err(Error::input)?);
    }
    let names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    let seconds = start.elapsed().as_secs_f64();
    Ok(if as_json {
        json!({"files": names, "seconds": seconds}).to_string()
    } else {
        format!(
            "{}\n({} files in {seconds:.1} s)",
            names.join("\n"),
            names.len()
        )
    })
}
