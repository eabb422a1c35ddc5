//! Cost of the interval elementary functions of `dalembert::elementary`: median over 9 runs
//! of 100,000 calls on thin intervals `[x, x + 1e-12]`, x uniform in [-10, 10], beside the
//! bare correctly rounded point call.
//!
//! `cargo run --profile test --example elementary_cost`
//!
//! Before inari was built without MPFR, the same loop timed inari's own interval functions
//! (MPFR, one call per endpoint and direction) on the same loaded 2-core machine, in ns per
//! call: sin 2030, cos 1426, exp 1450, atan 3549, sinh 1959, cosh 2048; these functions took
//! sin 107, cos 111, exp 21, atan 45, sinh 43, cosh 42 in that run.

use dalembert::elementary as el;
use inari::Interval;
use std::hint::black_box;
use std::time::Instant;

fn median_ns<T: Copy, R>(xs: &[T], f: impl Fn(T) -> R) -> f64 {
    let mut runs: Vec<f64> = (0..9)
        .map(|_| {
            let t = Instant::now();
            for &x in xs {
                black_box(f(black_box(x)));
            }
            t.elapsed().as_nanos() as f64 / xs.len() as f64
        })
        .collect();
    runs.sort_by(f64::total_cmp);
    runs[4]
}

fn main() {
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let pts: Vec<f64> = (0..100_000)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
        })
        .collect();
    let xs: Vec<Interval> = pts
        .iter()
        .map(|&x| Interval::try_from((x, x + 1e-12)).unwrap())
        .collect();
    type Pair = (&'static str, fn(Interval) -> Interval, fn(f64) -> f64);
    let pairs: [Pair; 9] = [
        ("sin", el::sin, core_math::sin),
        ("cos", el::cos, core_math::cos),
        ("tan", el::tan, core_math::tan),
        ("exp", el::exp, core_math::exp),
        ("atan", el::atan, core_math::atan),
        ("sinh", el::sinh, core_math::sinh),
        ("cosh", el::cosh, core_math::cosh),
        ("tanh", el::tanh, core_math::tanh),
        ("asinh", el::asinh, core_math::asinh),
    ];
    println!("function  interval (ns/call)  point core-math (ns/call)");
    for (name, interval, point) in pairs {
        let a = median_ns(&xs, interval);
        let b = median_ns(&pts, point);
        println!("{name:8}  {a:18.1}  {b:25.1}");
    }
    let one = Interval::try_from((1.0, 1.0)).unwrap();
    let pos: Vec<Interval> = xs.iter().map(|&x| x.abs() + one).collect();
    println!("{:8}  {:18.1}", "ln", median_ns(&pos, el::ln));
}
