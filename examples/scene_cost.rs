//! Cost of the same system as a built-in scene and as a scene file (issue "Your own
//! system"): `cargo run --release --example scene_cost -- builtin|file particle|knife N`
//! runs N certified flows to t = 0.5 and N exact steps at h = 0.5. Run it under
//! `valgrind --tool=callgrind` for deterministic instruction counts, or `time` it.

use dalembert::scene::{AnyScene, SceneFile};
use dalembert::{exact, flow, FlowOptions, Interval, Model};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (kind, scene) = (args[1].as_str(), args[2].as_str());
    let n: usize = args[3].parse().expect("N");
    let (text, q1) = match scene {
        "particle" => (
            "coordinates = [\"x\", \"y\", \"z\"]\nconstraints = [[\"-y\", 0, 1]]\nbasis = [[1, 0, \"y\"], [0, 1, 0]]",
            [0.4, 0.4, 0.08],
        ),
        _ => (
            "coordinates = [\"x\", \"y\", \"phi\"]\npotential = \"-(x*0.5)\"\nconstraints = [[\"sin(phi)\", \"-cos(phi)\", 0]]\nbasis = [[\"cos(phi)\", \"sin(phi)\", 0], [0, 0, 1]]",
            [0.4, 0.08, 0.4],
        ),
    };
    let m = match kind {
        "builtin" => Model::new(&AnyScene::new(scene, &[]).expect("scene")),
        _ => Model::new(&SceneFile::from_toml(text, scene).expect("file")),
    }
    .expect("model");
    let opts = FlowOptions::default();
    let (p0, p1) = (
        vec![Interval::point(0.0); 3],
        q1.map(Interval::point).to_vec(),
    );
    let mut acc = 0.0;
    for _ in 0..n {
        acc += flow(&m, &[0.0; 3], &[0.8, 0.8], 0.5, &opts)
            .expect("flow")
            .q[0]
            .wid();
        acc += exact::step(&m, &p0, &p1, 0.5, &opts).expect("step").q2[0].wid();
    }
    println!("{kind} {scene}: {n} flows and steps, sum of widths {acc:e}");
}
