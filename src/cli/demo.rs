//! `dalembert` with no arguments: a demonstration on the paper's nonholonomic particle.

use dalembert::{AnyScene, Error, FlowOptions, Model};
use std::time::Instant;

pub fn run() -> Result<(), Error> {
    let model = Model::new(AnyScene::new("particle", &[])?);
    let (q, u) = ([0.0, 0.0, 0.0], [0.8, 0.8]);
    println!("dalembert: the nonholonomic particle (paper Example 2.1), q0 = 0, u0 = (0.8, 0.8)");
    println!("certified enclosures of the exact flow (contains the true state; widths are max over components)");
    println!(
        "{:>8} {:>24} {:>24} {:>10} {:>7} {:>6} {:>10}",
        "t", "x(t)", "z(t)", "width", "steps", "order", "ms"
    );
    for t in [0.5, 50.0, 600.0] {
        let start = Instant::now();
        let e = dalembert::flow(&model, &q, &u, t, &FlowOptions::default())?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let w = e.q.iter().chain(&e.v).map(|x| x.wid()).fold(0.0, f64::max);
        println!(
            "{:>8} {:>24.17} {:>24.17} {:>10.2e} {:>7} {:>6} {:>10.1}",
            t,
            e.q[0].mid(),
            e.q[2].mid(),
            w,
            e.stats.steps,
            e.stats.order,
            ms
        );
    }
    Ok(())
}
