use dalembert::scene::SceneFile;
use dalembert::testing::{check_stepper, strategies::pairs_on_manifold, Stepper};
use dalembert::{FlowOptions, Model};
use proptest::{prelude::*, test_runner::RngSeed};
use std::sync::{Arc, LazyLock};

/// Your scheme: here the straight-line two-step map q2 = 2 q1 - q0 (second order in h).
struct MyScheme;
impl Stepper for MyScheme {
    type Error = std::convert::Infallible;
    fn step(&mut self, q0: &[f64], q1: &[f64], _h: f64, q2: &mut [f64]) -> Result<(), Self::Error> {
        for ((x, a), b) in q2.iter_mut().zip(q0).zip(q1) {
            *x = 2.0 * b - a;
        }
        Ok(())
    }
}

/// Your system, as a scene file (here the README's unicycle).
static MODEL: LazyLock<Arc<Model>> = LazyLock::new(|| {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes/unicycle.toml");
    Arc::new(Model::new(&SceneFile::read(path.as_ref()).unwrap()).unwrap())
});

proptest! {
    #![proptest_config(ProptestConfig { cases: 8, rng_seed: RngSeed::Fixed(3), ..ProptestConfig::default() })]
    #[test]
    fn my_scheme_is_second_order_on_my_unicycle(p in pairs_on_manifold(MODEL.clone(), 1.0, 1.0, 0.01..=0.1)) {
        let v = check_stepper(&MODEL, &mut MyScheme, &p.q0, &p.q1, p.h, 2, &FlowOptions::default()).unwrap();
        // proved: q_2 is within 3 h^2 of the exact discrete flow from (q_0, q_1)
        prop_assert!(v.discrete.max_distance.sup() <= 3.0 * p.h * p.h, "{}", v.discrete.max_distance.sup());
    }
}
