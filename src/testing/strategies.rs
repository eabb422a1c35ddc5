//! proptest strategies of admissible inputs for any [`Model`] (feature `proptest`; [spec
//! eq. (11.6)](crate::spec::testing)): configurations where the scene passes its checks, pairs on
//! `M_h^{e,nh}` from the exact exponential map with their certified defect, pairs at a chosen
//! distance from it, and the extreme step sizes of the stability table. Values shrink toward
//! the origin and the smallest step of the range.
//!
//! ```
//! use dalembert::testing::strategies::pairs_on_manifold;
//! use dalembert::{AnyScene, Model};
//! use proptest::prelude::*;
//! use std::sync::Arc;
//! let model = Arc::new(Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap());
//! proptest!(ProptestConfig::with_cases(4), |(p in pairs_on_manifold(model.clone(), 1.0, 1.0, 0.05..=0.2))| {
//!     // p.q1 is the float point of the exact motion from (p.q0, p.u0) at p.h,
//!     // p.defect encloses its distance parameter s to M_h^{e,nh}
//!     prop_assert!(p.defect.iter().all(|s| s.mag() < 1e-12));
//! });
//! ```

use super::{exact_pair, points, Pair};
use crate::Model;
use proptest::prelude::*;
use std::ops::RangeInclusive;
use std::sync::Arc;

/// Configurations in `[-bound, bound]^n` at which the scene passes the checks of [spec
/// eq. (3.17)](crate::spec::scenes) (others are rejected, not answered).
pub fn configurations(model: Arc<Model>, bound: f64) -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(-bound..=bound, model.n)
        .prop_filter("the scene's checks at q (3.17)", move |q| {
            model.check_at(&points(q)).is_ok()
        })
}

/// Pairs `(q0, q1)` on `M_h^{e,nh}` up to rounding: `q1` is the midpoint of the certified
/// exact exponential map from `(q0, u0)` at `h` (q0 in `[-q_bound, q_bound]^n`, u0 in
/// `[-u_bound, u_bound]^m`, h in `h`), with the defect the retraction certifies for the
/// float pair. Starts the oracle cannot certify are rejected.
pub fn pairs_on_manifold(
    model: Arc<Model>,
    q_bound: f64,
    u_bound: f64,
    h: RangeInclusive<f64>,
) -> impl Strategy<Value = Pair> {
    let m = model.n - model.k;
    (
        configurations(model.clone(), q_bound),
        proptest::collection::vec(-u_bound..=u_bound, m),
        h,
    )
        .prop_filter_map("the oracle certified the start", move |(q0, u0, h)| {
            exact_pair(&model, q0, u0, h, 0.0)
        })
}

/// As [`pairs_on_manifold`], with `q1` then moved by `distance` along the first constraint
/// normal `N(q1) e_1` (normalised): pairs at a chosen distance from `M_h^{e,nh}`, for
/// testing what a scheme or a projection does off the manifold. The defect is certified for
/// the moved pair.
pub fn pairs_near(
    model: Arc<Model>,
    q_bound: f64,
    u_bound: f64,
    h: RangeInclusive<f64>,
    distance: f64,
) -> impl Strategy<Value = Pair> {
    let m = model.n - model.k;
    (
        configurations(model.clone(), q_bound),
        proptest::collection::vec(-u_bound..=u_bound, m),
        h,
    )
        .prop_filter_map("the oracle certified the start", move |(q0, u0, h)| {
            exact_pair(&model, q0, u0, h, distance)
        })
}

/// The step sizes of the stability table's extremes, smallest first (shrinks toward it).
pub fn extreme_steps() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(1e-8),
        Just(1e-6),
        Just(1e-3),
        Just(0.1),
        Just(0.5),
        Just(1.0),
        Just(2.0)
    ]
}

/// Configurations with large coordinates: each component `+-10^e`, e in `0..=max_exponent`
/// (the stability table goes to 1e6), at which the scene passes its checks.
pub fn large_configurations(
    model: Arc<Model>,
    max_exponent: i32,
) -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec((0..=max_exponent, any::<bool>()), model.n)
        .prop_map(|v| {
            v.into_iter()
                .map(|(e, neg)| if neg { -(10f64.powi(e)) } else { 10f64.powi(e) })
                .collect::<Vec<f64>>()
        })
        .prop_filter("the scene's checks at q (3.17)", move |q| {
            model.check_at(&points(q)).is_ok()
        })
}
