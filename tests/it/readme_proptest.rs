use dalembert::schemes::{Scheme, SchemeKind};
use dalembert::testing::{check_stepper, strategies::pairs_on_manifold};
use dalembert::{AnyScene, FlowOptions, Model};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use std::sync::{Arc, LazyLock};

static MODEL: LazyLock<Arc<Model>> =
    LazyLock::new(|| Arc::new(Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap()));

proptest! {
    #![proptest_config(ProptestConfig { cases: 8, rng_seed: RngSeed::Fixed(7), ..ProptestConfig::default() })]
    /// MLA on the particle stays within h^2 of the exact discrete flow for 20 steps, from
    /// any start pair on M_h^{e,nh}: a certified statement, not a float comparison.
    #[test]
    fn mla_is_close_to_the_exact_discrete_flow(p in pairs_on_manifold(MODEL.clone(), 1.0, 1.0, 0.05..=0.2)) {
        let mut mla = Scheme::new(&MODEL, SchemeKind::Mla);
        let v = check_stepper(&MODEL, &mut mla, &p.q0, &p.q1, p.h, 20, &FlowOptions::default()).unwrap();
        // proved: every q_k is within h^2 of the exact discrete flow from (q_0, q_1)
        prop_assert!(v.discrete.max_distance.sup() <= p.h * p.h, "{}", v.discrete.max_distance.sup());
    }
}
