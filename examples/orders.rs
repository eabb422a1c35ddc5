//! The certified local and global orders of DLA and MLA on every scene (README table):
//! `cargo run --release --example orders`. Each entry is the observed order between the
//! last two rungs of the ladder, a certified interval (spec eqs. (11.1)-(11.3)).

use dalembert::integrator::{Scheme, SchemeKind};
use dalembert::testing::{global_order, local_order};
use dalembert::{AnyScene, FlowOptions, Model};

fn show(x: inari::Interval) -> String {
    if x.is_entire() {
        "(none proved)".into()
    } else {
        // rounded outward to 3 decimals, so the printed interval contains the certified one
        let lo = (x.inf() * 1000.0 - 1e-6).floor() / 1000.0;
        let hi = (x.sup() * 1000.0 + 1e-6).ceil() / 1000.0;
        format!("[{lo:.3}, {hi:.3}]")
    }
}

fn main() {
    let local_h = [0.125, 0.0625, 0.03125, 0.015625, 0.0078125];
    let global_h = [0.0625, 0.03125, 0.015625];
    let opts = FlowOptions::default();
    println!(
        "| scene | q0, u0 | DLA local | MLA local | DLA global (T = 1) | MLA global (T = 1) |"
    );
    println!("|---|---|---|---|---|---|");
    for info in dalembert::scene::SCENES {
        let m = Model::new(&AnyScene::new(info.name, &[]).expect("scene")).expect("model");
        let mut q0 = vec![0.0; m.n];
        q0[1] = 0.5;
        q0[m.n - 1] = 0.3;
        let u0: Vec<f64> = (0..m.n - m.k).map(|a| 0.8 - 0.3 * a as f64).collect();
        let mut row = format!("| `{}` | {:?}, {:?} |", info.name, q0, u0);
        let mut globals = String::new();
        for kind in [SchemeKind::Dla, SchemeKind::Mla] {
            let s = Scheme::new(&m, kind);
            let l = local_order(&m, &s, &q0, &u0, &local_h, &opts);
            row += &format!(
                " {} |",
                l.map_or_else(
                    |e| format!("refused: {e}"),
                    |l| show(l.orders[l.orders.len() - 1])
                )
            );
            let g = global_order(&m, &s, &q0, &u0, 1.0, &global_h, &opts);
            globals += &format!(
                " {} |",
                g.map_or_else(
                    |e| format!("refused: {e}"),
                    |g| show(g.orders[g.orders.len() - 1])
                )
            );
        }
        println!("{row}{globals}");
    }
}
