//! `dalembert` with no arguments: a demonstration on the paper's nonholonomic particle.

use crate::oracle::{check_trajectory, CheckOptions};
use crate::schemes::{NewtonOptions, Scheme, SchemeKind};
use crate::{exact, AnyScene, Error, FlowOptions, Interval, Model};
use std::time::Instant;

pub fn run() -> Result<(), Error> {
    let model = Model::new(&AnyScene::new("particle", &[])?)?;
    let opts = FlowOptions::default();
    let (q, u) = ([0.0, 0.0, 0.0], [0.8, 0.8]);
    outln!("dalembert: the nonholonomic particle (paper Example 2.1), q0 = 0, u0 = (0.8, 0.8)");
    outln!("\n1. Certified enclosures of the exact flow (they contain the true state)");
    outln!(
        "{:>8} {:>22} {:>22} {:>10} {:>6} {:>9}",
        "t",
        "x(t)",
        "z(t)",
        "max width",
        "steps",
        "ms"
    );
    for t in [0.5, 50.0, 600.0] {
        let start = Instant::now();
        let e = crate::flow(&model, &q, &u, t, &opts)?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let w = e.q.iter().chain(&e.v).map(|x| x.wid()).fold(0.0, f64::max);
        outln!(
            "{t:>8} {:>22.16} {:>22.16} {w:>10.2e} {:>6} {ms:>9.1}",
            e.q[0].mid(),
            e.q[2].mid(),
            e.stats.steps
        );
    }
    outln!("\n2. The exact retraction and the exact discrete flow at h = 0.5");
    let h = 0.5;
    let q0 = [Interval::point(0.0); 3];
    for q1 in [
        [0.4, 0.4, 0.08],
        [0.3900353197707153, 0.4, 0.0770329614269008],
    ] {
        let s = exact::step(&model, &q0, &q1.map(Interval::point), h, &opts)?;
        let r = &s.retraction;
        outln!(
            "   Q1 = {q1:?}: defect s in [{:.3e}, {:.3e}] -> {}; u0 in [{:.15}, {:.15}]; q2.x in [{:.15}, {:.15}]",
            r.s[0].inf(),
            r.s[0].sup(),
            if r.possibly_member() { "on M_h^{e,nh} (possibly)" } else { "proved off M_h^{e,nh}" },
            r.u0[0].inf(),
            r.u0[0].sup(),
            s.q2[0].inf(),
            s.q2[0].sup()
        );
    }
    outln!("\n3. DLA and MLA (paper section 5, h = 0.5, N = 1200, q1 = (0.4, 0.4, z1) on M_h^d)");
    for kind in [SchemeKind::Dla, SchemeKind::Mla] {
        let tr = Scheme::new(&model, kind).integrate(
            &[0.0; 3],
            &[0.4, 0.4, 0.0],
            h,
            1200,
            &NewtonOptions::default(),
        )?;
        let e = &tr.energy;
        let drift = e
            .iter()
            .skip(10)
            .map(|x| (x - e[10]).abs())
            .fold(0.0, f64::max);
        let short: Vec<Vec<f64>> = tr.q[..41].to_vec();
        let v = check_trajectory(
            &model,
            h,
            &short,
            &CheckOptions {
                pairs: false,
                ..CheckOptions::default()
            },
        )?;
        outln!(
            "   {kind:?}: H|D* from {:.6} to {:.6}, drift after step 10 {drift:.2e}; certified max distance to the exact discrete flow over 40 steps <= {:.3e}",
            e[0],
            e[e.len() - 1],
            v.max_distance.sup()
        );
    }
    every_scene()
}

/// 4. The same certified flow on every scene the crate knows (default parameters).
fn every_scene() -> Result<(), Error> {
    outln!(
        "\n4. Every scene (`dalembert scenes`): certified flow to t = 5 from q = 0, u = (0.8, 0.8)"
    );
    outln!(
        "{:>22} {:>3} {:>3} {:>10} {:>6} {:>9}",
        "scene",
        "n",
        "k",
        "max width",
        "steps",
        "ms"
    );
    for info in crate::scene::SCENES {
        let model = Model::new(&AnyScene::new(info.name, &[])?)?;
        let (q, u) = (vec![0.0; model.n], vec![0.8; model.n - model.k]);
        let start = Instant::now();
        let e = crate::flow(&model, &q, &u, 5.0, &FlowOptions::default())?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let w = e.q.iter().chain(&e.v).map(|x| x.wid()).fold(0.0, f64::max);
        outln!(
            "{:>22} {:>3} {:>3} {w:>10.2e} {:>6} {ms:>9.1}",
            info.name,
            model.n,
            model.k,
            e.stats.steps
        );
    }
    outln!("\nMore: dalembert --help; `dalembert figures --out DIR` and `dalembert stability` (README).");
    Ok(())
}
