//! The stability table at the extremes ([spec/09-report.md](crate::spec::report), (9.5)): for each case, does the
//! certified step answer or refuse, how wide is its answer, do the DLA and MLA Newton solves
//! converge and in how many iterations.

use super::{max_width, points, Progress};
use crate::exact;
use crate::schemes::{NewtonOptions, Scheme, SchemeError, SchemeKind};
use crate::{AnyScene, Error, FlowOptions, Model};

/// One input pair.
#[derive(Clone, Debug)]
pub struct Case {
    /// The scene's name.
    pub scene: String,
    /// Its parameters (the others at their defaults).
    pub params: Vec<(String, f64)>,
    /// The family and what is extreme: "h", "coordinates", "phi", "eps".
    pub family: String,
    /// The step `h`.
    pub h: f64,
    /// The first configuration.
    pub q0: Vec<f64>,
    /// `q0 + h E(q0)^T u`, `u = (0.8, 0.8)`, in f64 ([spec (9.5)](crate::spec::report)).
    pub q1: Vec<f64>,
}

/// What the certified step (`exact::step`, [spec Theorem 6.2](crate::spec::exact_discrete)) did.
#[derive(Clone, Debug, PartialEq)]
pub enum Certified {
    /// Answered.
    Answered {
        /// The largest width over `q1`, `q2`, `p_minus`, `p_plus`.
        width: f64,
        /// The largest width relative to `max(1, |component|)`.
        relative: f64,
    },
    /// Refused.
    Refused {
        /// The exit status: 2 (input) or 3 (not certified).
        code: i32,
        /// The error's message.
        reason: String,
    },
}

/// What a scheme's Newton solves did on the first two steps (projection of q1 onto M_h^d,
/// then q2).
#[derive(Clone, Debug, PartialEq)]
pub enum Solve {
    /// Both solves converged.
    Converged {
        /// Newton iterations of the projection and of the step.
        iterations: Vec<usize>,
    },
    /// A solve failed.
    Failed {
        /// Where: 0 the projection of q1, 1 the step to q2 (for a momentum or energy not
        /// finite, its row k = 0..=2).
        step: usize,
        /// The named failure ([spec eq. (7.6)](crate::spec::schemes)), or why the input or the result was refused.
        failure: String,
    },
}

/// One row of the table: a case and what each method did with it.
#[derive(Clone, Debug)]
pub struct Row {
    /// The case.
    pub case: Case,
    /// What the certified step did.
    pub certified: Certified,
    /// What DLA's Newton solves did.
    pub dla: Solve,
    /// What MLA's Newton solves did.
    pub mla: Solve,
    /// Wall time of the case (certified step and both schemes), seconds.
    pub seconds: f64,
}

/// `q1 = q0 + h E(q0)^T u`, u = (0.8, 0.8): a pair one step of speed about 1 apart (off
/// M_h^{e,nh} by O(h^2): the retraction's defect and the schemes' projection take care of
/// that).
fn pair(model: &Model, h: f64, q0: Vec<f64>) -> (Vec<f64>, Vec<f64>) {
    let x: Vec<f64> = q0.iter().copied().chain([0.8, 0.8]).collect();
    let v = model.velocity.eval::<f64>(&x);
    let q1 = q0.iter().zip(&v).map(|(q, v)| q + h * v).collect();
    (q0, q1)
}

fn case(
    scene: &str,
    params: &[(&str, f64)],
    family: &str,
    h: f64,
    q0: Vec<f64>,
) -> Result<Case, Error> {
    let model = Model::new(&AnyScene::new(scene, params)?)?;
    let params: Vec<(String, f64)> = params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    let (q0, q1) = pair(&model, h, q0);
    Ok(Case {
        scene: scene.to_string(),
        params,
        family: family.to_string(),
        h,
        q0,
        q1,
    })
}

/// The cases (9.5): h from 1e-8 to 4; coordinates from 1e-300 to 1e150; phi near pi/2;
/// eps from 0 to 0.99.
pub fn cases() -> Result<Vec<Case>, Error> {
    use std::f64::consts::FRAC_PI_2;
    let mut families: Vec<Vec<Case>> = vec![];
    for scene in ["particle", "knife"] {
        families.push(
            [1e-8, 1e-4, 0.1, 0.5, 1.0, 2.0, 4.0]
                .iter()
                .map(|&h| case(scene, &[], "h", h, vec![0.0; 3]))
                .collect::<Result<_, _>>()?,
        );
        families.push(
            [1e-300, 1e-8, 1e4, 1e8, 1e50, 1e150]
                .iter()
                .map(|&c| case(scene, &[], "coordinates", 0.5, vec![c; 3]))
                .collect::<Result<_, _>>()?,
        );
    }
    for (scene, params) in [("knife", vec![]), ("knife-eps", vec![("eps", 0.1)])] {
        families.push(
            [
                FRAC_PI_2 - 1e-2,
                FRAC_PI_2 - 1e-8,
                FRAC_PI_2,
                FRAC_PI_2 + 1e-8,
            ]
            .iter()
            .map(|&phi| case(scene, &params, "phi", 0.5, vec![0.0, 0.0, phi]))
            .collect::<Result<_, _>>()?,
        );
    }
    families.push(
        [0.0, 1e-8, 0.1, 0.5, 0.9, 0.99]
            .iter()
            .map(|&e| case("knife-eps", &[("eps", e)], "eps", 0.5, vec![0.0; 3]))
            .collect::<Result<_, _>>()?,
    );
    Ok(families.concat())
}

fn certified(model: &Model, c: &Case) -> Certified {
    let refused = |e: Error| Certified::Refused {
        code: crate::protocol::exit_code(&e),
        reason: e.message().to_string(),
    };
    match exact::step(
        model,
        &points(&c.q0),
        &points(&c.q1),
        c.h,
        &FlowOptions::default(),
    ) {
        Ok(s) => {
            let all = || s.q1.iter().chain(&s.q2).chain(&s.p_minus).chain(&s.p_plus);
            let width = max_width(all());
            let relative = all().fold(0.0f64, |a, x| a.max(x.wid() / x.mag().max(1.0)));
            if width.is_finite() {
                Certified::Answered { width, relative }
            } else {
                refused(Error::uncertified("answer not finite"))
            }
        }
        Err(e) => refused(e),
    }
}

fn solve(model: &Model, kind: SchemeKind, c: &Case) -> Solve {
    let s = Scheme::new(model, kind);
    match s.integrate(&c.q0, &c.q1, c.h, 2, &NewtonOptions::default()) {
        Ok(tr) => Solve::Converged {
            iterations: tr.iterations,
        },
        Err(SchemeError::Newton { step, failure }) => Solve::Failed {
            step,
            failure: failure.to_string(),
        },
        Err(SchemeError::NonFinite { step }) => Solve::Failed {
            step,
            failure: "momentum or energy not finite".into(),
        },
        Err(SchemeError::Input(m)) => Solve::Failed {
            step: 0,
            failure: format!("invalid input: {m}"),
        },
    }
}

/// Run one case.
pub fn run(c: &Case) -> Result<Row, Error> {
    let start = std::time::Instant::now();
    let model = Model::new(&AnyScene::new(
        &c.scene,
        &crate::protocol::borrowed(&c.params),
    )?)?;
    let (certified, dla, mla) = (
        certified(&model, c),
        solve(&model, SchemeKind::Dla, c),
        solve(&model, SchemeKind::Mla, c),
    );
    Ok(Row {
        case: c.clone(),
        certified,
        dla,
        mla,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Run all cases.
pub fn table(progress: &Progress) -> Result<Vec<Row>, Error> {
    let cs = cases()?;
    let mut rows = Vec::with_capacity(cs.len());
    for (i, c) in cs.iter().enumerate() {
        progress.count("stability cases", i, cs.len());
        rows.push(run(c)?);
    }
    progress.count("stability cases", cs.len(), cs.len());
    Ok(rows)
}
