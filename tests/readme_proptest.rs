use dalembert::integrator::{NewtonOptions, Scheme, SchemeKind};
use dalembert::oracle::{check_trajectory, CheckOptions};
use dalembert::{AnyScene, Model};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]
    /// MLA on the particle stays within h^2 of the exact discrete flow for 20 steps,
    /// for every start it is tried on: a certified statement, not a float comparison.
    #[test]
    fn mla_is_close_to_the_exact_discrete_flow(
        x in -1.0..1.0f64, y in -1.0..1.0f64, u1 in -1.0..1.0f64, u2 in -1.0..1.0f64,
        h in 0.05..0.2f64,
    ) {
        let model = Model::new(&AnyScene::new("particle", &[]).unwrap()).unwrap();
        let (q0, q1) = ([x, y, 0.0], [x + h * u1, y + h * u2, h * y * u1]); // q1 ~ q(h)
        let mla = Scheme::new(&model, SchemeKind::Mla);
        let traj = mla.integrate(&q0, &q1, h, 20, &NewtonOptions::default()).unwrap();
        let v = check_trajectory(&model, h, &traj.q, &CheckOptions::default()).unwrap();
        // proved: every q_k is within h^2 of the exact discrete flow from (q_0, q_1)
        prop_assert!(v.max_distance.sup() <= h * h, "{}", v.max_distance.sup());
    }
}
