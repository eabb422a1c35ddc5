//! quickcheck producers of admissible inputs for any [`Model`] (feature `quickcheck`; [spec
//! eq. (11.6)](crate::spec::testing)): the same objects as `testing::strategies`, drawn from a `quickcheck::Gen`.
//! A `Pair` needs its model, so these are functions of `(g, model)`, not `Arbitrary` impls;
//! call them from a property over seeds, or from your own `Arbitrary` type that holds the
//! model.
//!
//! ```
//! use dalembert::testing::quickcheck_inputs::pair_on_manifold;
//! use dalembert::{AnyScene, Model};
//! let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
//! let mut g = quickcheck::Gen::from_size_and_seed(100, 7);
//! let p = pair_on_manifold(&mut g, &model, 1.0, 1.0, (0.05, 0.2)).expect("a certified start");
//! assert!(p.defect.iter().all(|s| s.mag() < 1e-12));
//! ```

use super::{exact_pair, points, Pair};
use crate::Model;
use quickcheck::{Arbitrary, Gen};

/// Uniform in `[lo, hi]` from the generator's random bits.
fn uniform(g: &mut Gen, lo: f64, hi: f64) -> f64 {
    let u = (u64::arbitrary(g) >> 11) as f64 / (1u64 << 53) as f64;
    lo + (hi - lo) * u
}

/// A configuration in `[-bound, bound]^n` at which the scene passes its checks (3.17);
/// `None` after 32 draws that all fail them.
pub fn configuration(g: &mut Gen, model: &Model, bound: f64) -> Option<Vec<f64>> {
    (0..32).find_map(|_| {
        let q: Vec<f64> = (0..model.n).map(|_| uniform(g, -bound, bound)).collect();
        model.check_at(&points(&q)).is_ok().then_some(q)
    })
}

/// A pair on `M_h^{e,nh}` up to rounding, with its certified defect, as
/// `strategies::pairs_on_manifold`; `None` when no certified start was found in 8 draws.
pub fn pair_on_manifold(
    g: &mut Gen,
    model: &Model,
    q_bound: f64,
    u_bound: f64,
    h: (f64, f64),
) -> Option<Pair> {
    pair_near(g, model, q_bound, u_bound, h, 0.0)
}

/// As [`pair_on_manifold`], `q1` moved by `distance` along the first constraint normal.
pub fn pair_near(
    g: &mut Gen,
    model: &Model,
    q_bound: f64,
    u_bound: f64,
    h: (f64, f64),
    distance: f64,
) -> Option<Pair> {
    (0..8).find_map(|_| {
        let q0 = configuration(g, model, q_bound)?;
        let u0: Vec<f64> = (0..model.n - model.k)
            .map(|_| uniform(g, -u_bound, u_bound))
            .collect();
        let hh = uniform(g, h.0, h.1);
        exact_pair(model, q0, u0, hh, distance)
    })
}
