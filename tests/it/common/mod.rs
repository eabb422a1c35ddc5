//! Helpers shared by the integration tests: scenes, a fixed-seed generator of states and
//! failure messages that print every input as a hex float so a failure can be replayed
//! bit for bit; the closed forms of the particle and the knife in interval arithmetic
//! (`exact`); running the built binary (`binary`).

// Each module of the tests uses a different subset of these helpers.
#![allow(dead_code)]

mod binary;
mod exact;

pub use binary::*;
pub use exact::*;

use dalembert::scalar::point;
use dalembert::schemes::{NewtonOptions, Scheme, SchemeKind, Trajectory};
use dalembert::{flow, AnyScene, Error, FlowEnclosure, FlowOptions, Model};
use inari::Interval;

/// A scene by name, with parameters.
pub fn model(name: &str, params: &[(&str, f64)]) -> Model {
    Model::new(&AnyScene::new(name, params).expect("scene")).unwrap()
}

/// `x` as a decimal (`{:e}`, which is exact enough to round-trip) and as its bits.
pub fn hex(x: f64) -> String {
    format!("{x:e} (bits 0x{:016x})", x.to_bits())
}

/// An interval as `[inf, sup] (wid ...)`.
pub fn show(x: impl Into<Interval>) -> String {
    let x = x.into();
    if x.is_empty() {
        return "EMPTY".to_string();
    }
    format!("[{:e}, {:e}] (wid {:e})", x.inf(), x.sup(), x.wid())
}

/// Rust source of a vector of exact f64, e.g. `[f64::from_bits(0x...), ...]`.
fn bits_vec(x: &[f64]) -> String {
    let v: Vec<String> = x
        .iter()
        .map(|c| format!("f64::from_bits(0x{:016x})", c.to_bits()))
        .collect();
    format!("[{}]", v.join(", "))
}

/// The inputs of a flow call, readable and as a copy-paste reproducer.
pub fn describe(scene: &str, params: &[(&str, f64)], q: &[f64], u: &[f64], t: f64) -> String {
    let mut s = format!("scene `{scene}`");
    for (k, v) in params {
        s += &format!(", {k} = {}", hex(*v));
    }
    s += "\n";
    for (i, c) in q.iter().enumerate() {
        s += &format!("  q[{i}] = {}\n", hex(*c));
    }
    for (i, c) in u.iter().enumerate() {
        s += &format!("  u[{i}] = {}\n", hex(*c));
    }
    s += &format!("  t    = {}\n", hex(t));
    let ps: Vec<String> = params
        .iter()
        .map(|(k, v)| {
            format!(
                "(\"{k}\".to_string(), f64::from_bits(0x{:016x}))",
                v.to_bits()
            )
        })
        .collect();
    s += &format!(
        "  reproduce: flow(&Model::new(&AnyScene::new(\"{scene}\", &[{}]).unwrap()).unwrap(), &{}, &{}, f64::from_bits(0x{:016x}), &FlowOptions::default())\n",
        ps.join(", "),
        bits_vec(q),
        bits_vec(u),
        t.to_bits()
    );
    s
}

/// `flow` with the default options.
pub fn run(model: &Model, q: &[f64], u: &[f64], t: f64) -> Result<FlowEnclosure, Error> {
    flow(model, q, u, t, &FlowOptions::default())
}

/// `max(1, |x|)` for an interval: the scale of the relative width bounds.
pub fn scale(x: impl Into<Interval>) -> f64 {
    x.into().mag().max(1.0)
}

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny generator with a fixed seed, so that the
/// "random" cases are the same on every run and every machine.
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi] (a finite f64).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        from_bits_in(self.next_u64(), lo, hi)
    }
}

/// Map 64 random bits to a finite f64 in [lo, hi] (53 bits of the word are used).
pub fn from_bits_in(bits: u64, lo: f64, hi: f64) -> f64 {
    let unit = (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
    (lo + (hi - lo) * unit).clamp(lo, hi)
}

/// The classical Runge-Kutta method, n steps over [0, t] (a float reference, not rigorous).
pub fn rk4<const D: usize>(
    f: impl Fn(&[f64; D]) -> [f64; D],
    x0: [f64; D],
    t: f64,
    n: usize,
) -> [f64; D] {
    let h = t / n as f64;
    let mut x = x0;
    let add = |x: &[f64; D], k: &[f64; D], c: f64| -> [f64; D] {
        let mut y = *x;
        for i in 0..D {
            y[i] += c * k[i];
        }
        y
    };
    for _ in 0..n {
        let k1 = f(&x);
        let k2 = f(&add(&x, &k1, h / 2.0));
        let k3 = f(&add(&x, &k2, h / 2.0));
        let k4 = f(&add(&x, &k3, h));
        for i in 0..D {
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    x
}

/// `n` steps of a float scheme from `(q0, q1)`; every position and energy must be finite.
pub fn integrate(
    m: &Model,
    kind: SchemeKind,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    n: usize,
) -> Trajectory {
    let tr = Scheme::new(m, kind)
        .integrate(q0, q1, h, n, &NewtonOptions::default())
        .unwrap();
    assert_eq!(tr.q.len(), n + 1);
    assert_eq!(tr.energy.len(), n + 1);
    assert!(tr
        .q
        .iter()
        .flatten()
        .chain(&tr.energy)
        .all(|x| x.is_finite()));
    tr
}

/// The energy E_L(q0, R^{e-}(q0, q1)) of the exact trajectory through (q0, q1), certified
/// (the retraction's v0 and the model's energy tape in intervals), at most 1e-12 wide.
pub fn exact_energy(m: &Model, q0: &[f64], q1: &[f64], h: f64) -> Interval {
    let b = |v: &[f64]| v.iter().map(|x| point(*x)).collect::<Vec<_>>();
    let a = |v: &[f64]| {
        v.iter()
            .map(|x| dalembert::Interval::point(*x))
            .collect::<Vec<_>>()
    };
    let r = dalembert::exact::retract(m, &a(q0), &a(q1), h, &FlowOptions::default()).unwrap();
    let x: Vec<Interval> = b(q0)
        .into_iter()
        .chain(r.v0.into_iter().map(Interval::from))
        .collect();
    let e = m.energy().eval_checked(&x).unwrap()[0];
    assert!(e.wid() < 1e-12, "{e:?}");
    e
}

/// A deterministic stream of 64-bit words (a linear congruential generator, its high bits
/// folded down): the seed of each test's own draws.
pub struct Gen(pub u64);

impl Gen {
    pub fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 ^ (self.0 >> 29)
    }
}
