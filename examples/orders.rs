//! The certified local and global orders of DLA and MLA on every scene (README table):
//! `cargo run --release --example orders`. Each entry is the observed order between the
//! last two rungs of the ladder, a certified interval (spec eqs. (11.1)-(11.3)). The starts
//! and ladders are `dalembert::report::orders`, shared with the figure `orders`.

use dalembert::report::orders::{ladders, starts, GLOBAL_H, LOCAL_H, T_END};
use dalembert::testing::Ladder;
use dalembert::Error;

fn show(x: dalembert::Interval) -> String {
    if x.is_entire() {
        "(none proved)".into()
    } else {
        // rounded outward to 3 decimals, so the printed interval contains the certified one
        let lo = (x.inf() * 1000.0 - 1e-6).floor() / 1000.0;
        let hi = (x.sup() * 1000.0 + 1e-6).ceil() / 1000.0;
        format!("[{lo:.3}, {hi:.3}]")
    }
}

/// The last observed order of a ladder, or the refusal.
fn cell(l: &Result<Ladder, Error>) -> String {
    l.as_ref().map_or_else(
        |e| format!("refused: {e}"),
        |l| show(l.orders[l.orders.len() - 1]),
    )
}

fn main() {
    let rows = ladders(
        &starts(),
        &LOCAL_H,
        &GLOBAL_H,
        T_END,
        &dalembert::Progress::default(),
    )
    .expect("built-in scene");
    println!(
        "| scene | q0, u0 | DLA local | MLA local | DLA global (T = {T_END}) | MLA global (T = {T_END}) |"
    );
    println!("|---|---|---|---|---|---|");
    for r in &rows {
        let s = &r.start;
        let cells: Vec<String> = r.local.iter().chain(&r.global).map(cell).collect();
        println!(
            "| `{}` | {:?}, {:?} | {} |",
            s.scene,
            s.q0,
            s.u0,
            cells.join(" | ")
        );
    }
}
