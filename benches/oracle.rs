//! Cost of the certified objects and of the float schemes (criterion).
//! `cargo bench --bench oracle` (add `-- NAME` to filter, e.g. `-- precision`).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use dalembert::protocol::Session;
use dalembert::schemes::{NewtonOptions, Scheme, SchemeKind};
use dalembert::{exact, flow, AnyScene, FlowOptions, Interval, Model};

const SCENES: [(&str, [f64; 3]); 3] = [
    ("particle", [0.4, 0.4, 0.08]),
    ("knife", [0.4, 0.08, 0.4]),
    ("knife-eps", [0.4, 0.08, 0.4]),
];

fn model(name: &str) -> Model {
    Model::new(&AnyScene::new(name, &[]).expect("known scene")).unwrap()
}

fn certified(c: &mut Criterion) {
    let opts = FlowOptions::default();
    for (name, q1) in SCENES {
        // what every start of the command line pays before it computes (spec (4.11))
        c.bench_function(&format!("model/{name}"), |b| {
            b.iter(|| model(black_box(name)))
        });
        let m = model(name);
        c.bench_function(&format!("flow/{name}/t=0.5"), |b| {
            b.iter(|| flow(&m, black_box(&[0.0; 3]), &[0.8, 0.8], 0.5, &opts))
        });
        let (p0, p1) = (
            vec![Interval::point(0.0); 3],
            q1.map(Interval::point).to_vec(),
        );
        c.bench_function(&format!("step/{name}/h=0.5"), |b| {
            b.iter(|| exact::step(&m, black_box(&p0), &p1, 0.5, &opts))
        });
    }
}

/// The same scenes written as scene files (issue "Your own system": a file scene costs what
/// the built-in costs; both compile to the same programs, spec eq. (3.16)).
const FILES: [(&str, &str); 2] = [
    (
        "particle",
        r#"coordinates = ["x", "y", "z"]
constraints = [["-y", 0, 1]]
basis = [[1, 0, "y"], [0, 1, 0]]"#,
    ),
    (
        "knife",
        r#"coordinates = ["x", "y", "phi"]
potential = "-(x*0.5)"
constraints = [["sin(phi)", "-cos(phi)", 0]]
basis = [["cos(phi)", "sin(phi)", 0], [0, 0, 1]]"#,
    ),
];

fn files(c: &mut Criterion) {
    let opts = FlowOptions::default();
    for ((name, text), (_, q1)) in FILES.iter().zip(SCENES) {
        let f = dalembert::scene::SceneFile::from_toml(text, name).expect("valid file");
        let m = Model::new(&f).expect("compiles");
        c.bench_function(&format!("flow/{name}-file/t=0.5"), |b| {
            b.iter(|| flow(&m, black_box(&[0.0; 3]), &[0.8, 0.8], 0.5, &opts))
        });
        let (p0, p1) = (
            vec![Interval::point(0.0); 3],
            q1.map(Interval::point).to_vec(),
        );
        c.bench_function(&format!("step/{name}-file/h=0.5"), |b| {
            b.iter(|| exact::step(&m, black_box(&p0), &p1, 0.5, &opts))
        });
    }
}

fn schemes(c: &mut Criterion) {
    let opts = NewtonOptions::default();
    for (name, q1) in SCENES {
        let m = model(name);
        for kind in [SchemeKind::Dla, SchemeKind::Mla] {
            let s = Scheme::new(&m, kind);
            let q1 = s.project(&[0.0; 3], &q1, &opts).expect("projection").0;
            c.bench_function(&format!("{kind:?}/{name}/h=0.5"), |b| {
                b.iter(|| s.step(black_box(&[0.0; 3]), &q1, 0.5, &opts))
            });
        }
    }
}

fn batch(c: &mut Criterion) {
    let mut session = Session::default();
    let line =
        r#"{"id":1,"cmd":"step","scene":"particle","q0":[0,0,0],"q1":[0.4,0.4,0.08],"h":0.5}"#;
    c.bench_function("batch/particle step line", |b| {
        b.iter(|| session.batch_line(black_box(line)))
    });
}

/// The knife flow to T = 50 (as `dalembert figures`' precision figure) at 106 bits
/// (double-double) and at 160, 256 and 512 bits (`WideInterval`), and the interval multiply-add
/// of the Taylor convolutions at those precisions (issue 46: the cost per extra bit).
fn precision(c: &mut Criterion) {
    use dalembert::precision::dd::DdInterval;
    use dalembert::precision::wide::{self, WideInterval};
    let m = model("knife");
    let opts = FlowOptions::default();
    let (q, u) = ([0.0; 3], [0.8, 0.8]);
    let mut g = c.benchmark_group("precision");
    g.sample_size(10);
    g.bench_function("knife t=50/106", |b| {
        b.iter(|| dalembert::flow_at_in::<DdInterval>(&m, black_box(&q), &u, &[50.0], &opts))
    });
    // the 1 / k of the Taylor recurrences at 106 bits: the general quotient and the
    // quotient by an integer (spec (12.1.22))
    let x = DdInterval::from_f64(1.0) / DdInterval::from_f64(3.0);
    g.bench_function("quotient by 7/106", |b| {
        b.iter(|| black_box(x) / DdInterval::from_f64(black_box(7.0)))
    });
    g.bench_function("div_int by 7/106", |b| {
        b.iter(|| black_box(x).div_int(black_box(7)))
    });
    for bits in [160u32, 256, 512] {
        g.bench_function(format!("knife t=50/{bits}"), |b| {
            wide::with_bits(bits, || {
                b.iter(|| {
                    dalembert::flow_at_in::<WideInterval>(&m, black_box(&q), &u, &[50.0], &opts)
                })
            })
        });
        g.bench_function(format!("mul_acc/{bits}"), |b| {
            wide::with_bits(bits, || {
                let x = WideInterval::from_f64(1.0) / WideInterval::from_f64(3.0);
                let y = WideInterval::from_f64(2.0) / WideInterval::from_f64(7.0);
                let acc = WideInterval::from_f64(0.5);
                b.iter(|| black_box(acc).mul_acc(black_box(&x), black_box(&y)))
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = certified, files, schemes, batch, precision
}
criterion_main!(benches);
