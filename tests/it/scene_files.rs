//! Scene files and inline JSON scenes (spec/10-scene-files.md):
//!
//! 1. a file equal to a built-in scene compiles and its tapes give the built-in's values at
//!    random points, in f64 and in intervals;
//! 2. a derived basis (`free`) is the hand-computed one;
//! 3. the JSON and TOML forms of one scene are the same scene (same key, same values);
//! 4. expressions agree with hand-computed values under the number, pi and exponent rules;
//! 5. every refusal is one input-error line naming what and where;
//! 6. every file in examples/scenes/ compiles and its certified flow conserves the energy;
//! 7. the fuzz check on random and mutated inputs never fails.
//!
//! Random points come from SplitMix64 with fixed seeds: the same cases on every run.

use dalembert::scalar::{iv, point, Scalar};
use dalembert::scene::{Particle, Scene, SceneFile};
use dalembert::{Error, FlowOptions, Model};
use inari::Interval;
use serde_json::json;
use std::path::{Path, PathBuf};

struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn toml(text: &str) -> SceneFile {
    SceneFile::from_toml(text, "test").unwrap_or_else(|e| panic!("{e}"))
}

const PARTICLE: &str = r#"
name = "particle"
coordinates = ["x", "y", "z"]
quasi_velocities = ["xd", "yd"]
constraints = [["-y", "0", "1"]]
basis = [[1, 0, "y"], [0, 1, 0]]
"#;

/// Both results agree: f64 to rounding, intervals overlapping with widths within 1.1x.
fn assert_close(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-13 * (1.0 + x.abs().max(y.abs())),
            "{what}: {x} vs {y}"
        );
    }
}

fn assert_overlap<T: Copy + Into<Interval>>(a: &[T], b: &[T], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b) {
        let (x, y): (Interval, Interval) = ((*x).into(), (*y).into());
        assert!(!x.intersection(y).is_empty(), "{what}: {x:?} vs {y:?}");
        let (wx, wy) = (x.wid(), y.wid());
        assert!(
            wx <= 1.1 * wy + 1e-300 && wy <= 1.1 * wx + 1e-300,
            "{what}: widths {wx:e} vs {wy:e}"
        );
    }
}

#[test]
fn the_particle_as_a_file_is_the_built_in_particle() {
    let file = toml(PARTICLE);
    let a = Model::new(&file).unwrap();
    let b = Model::new(&Particle).unwrap();
    assert_eq!((a.n(), a.k()), (b.n(), b.k()));
    assert_eq!(a.name(), "particle");
    let mut rng = SplitMix64(0x0005_CE7E_F11E);
    for _ in 0..200 {
        let x: Vec<f64> = (0..a.state_dim()).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qv: Vec<f64> = (0..2 * a.n()).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let q = &qv[..a.n()];
        for (ta, tb, input, what) in [
            (&a.dynamics().field, &b.dynamics().field, &x[..], "field"),
            (a.velocity(), b.velocity(), &x[..], "velocity"),
            (a.constraints(), b.constraints(), q, "constraints"),
            (a.energy(), b.energy(), &qv[..], "energy"),
            (a.momentum_d(), b.momentum_d(), &qv[..], "momentum"),
            (a.nh_force(), b.nh_force(), &qv[..], "nh force"),
        ] {
            assert_close(&ta.eval(input), &tb.eval(input), what);
            // point intervals and small boxes
            let pts: Vec<Interval> = input.iter().map(|v| point(*v)).collect();
            assert_overlap(&ta.eval(&pts), &tb.eval(&pts), what);
            let boxes: Vec<Interval> = input.iter().map(|v| iv(*v, *v + 1e-6)).collect();
            assert_overlap(&ta.eval(&boxes), &tb.eval(&boxes), what);
        }
    }
    // and the certified flows overlap with comparable widths
    let opts = FlowOptions::default();
    let fa = dalembert::flow(&a, &[0.0, 0.0, 0.0], &[0.8, 0.8], 2.0, &opts).unwrap();
    let fb = dalembert::flow(&b, &[0.0, 0.0, 0.0], &[0.8, 0.8], 2.0, &opts).unwrap();
    assert_overlap(&fa.q, &fb.q, "flow q");
    assert_overlap(&fa.u, &fb.u, "flow u");
}

const KNIFE: &str = r#"
coordinates = ["x", "y", "phi"]
potential = "-x/2"
constraints = [["sin(phi)", "-cos(phi)", 0]]
free = ["x", "phi"]
"#;

#[test]
fn the_knife_with_free_x_phi_has_the_basis_1_tan_phi_0_and_0_0_1() {
    let file = toml(KNIFE);
    assert_eq!(file.free(), vec![0, 2]);
    let model = Model::new(&file).unwrap();
    let mut rng = SplitMix64(7);
    for _ in 0..200 {
        let q = [
            rng.uniform(-5.0, 5.0),
            rng.uniform(-5.0, 5.0),
            rng.uniform(-1.4, 1.4),
        ];
        let e = file.basis(&q);
        assert_close(&e[0], &[1.0, q[2].tan(), 0.0], "e1");
        assert_eq!(e[1], vec![0.0, 0.0, 1.0]);
        // in intervals: the enclosure of tan(phi) from inari meets the derived entry
        let qi: Vec<Interval> = q.iter().map(|v| point(*v)).collect();
        let ei = model.scene().basis(&qi);
        let tan = qi[2].tan();
        assert!(!ei[0][1].intersection(tan).is_empty());
        assert!(ei[0][0] == point(1.0) && ei[0][2] == point(0.0));
        assert!(ei[1]
            .iter()
            .zip([0.0, 0.0, 1.0])
            .all(|(a, b)| *a == point(b)));
    }
    let d = file.description();
    assert_eq!(d.basis.len(), 2);
    assert!(
        d.basis[0].contains("(1, sin(phi)/cos(phi), 0)"),
        "{}",
        d.basis[0]
    );
    assert!(d.basis[1].contains("(0, 0, 1)"), "{}", d.basis[1]);
    assert_eq!(d.velocities, vec!["u1", "u2"]);
    // where the pivot block cos(phi) may vanish, the check refuses to certify (exit 3)
    let half_pi = Interval::FRAC_PI_2;
    let e = model
        .check_at(&[point(0.0), point(0.0), half_pi])
        .unwrap_err();
    assert_eq!(dalembert::protocol::exit_code(&e), 3, "{e}");
    assert!(model
        .check_at(&[point(0.0), point(0.0), point(0.5)])
        .is_ok());
}

#[test]
fn json_and_toml_forms_are_the_same_scene() {
    let t = toml(
        r#"
name = "sleigh-like"
coordinates = ["x", "y", "theta"]
quasi_velocities = ["s", "w"]
parameters = { m = 2, a = 0.25, I = 1.5 }
mass = [["m", 0, "-m*a*sin(theta)"], [0, "m", "m*a*cos(theta)"],
        ["-m*a*sin(theta)", "m * a*cos(theta)", "I + m*a^2"]]
potential = "0.5 * x"
one_form = [0, 0, "a"]
constraints = [["-sin(theta)", "cos(theta)", "0"]]
free = ["x", "theta"]
"#,
    );
    let j = SceneFile::from_json(&json!({
        "name": "sleigh-like",
        "coordinates": ["x", "y", "theta"],
        "quasi_velocities": ["s", "w"],
        "parameters": {"I": 1.5, "a": "0.25".parse::<f64>().unwrap(), "m": 2.0},
        "mass": [["m", "0", "-m*a*sin(theta)"], [0, "m", "m*a*cos(theta)"],
                 ["-m*a*sin(theta)", "m*a*cos(theta)", "I+m*a^2"]],
        "potential": "0.5*x",
        "one_form": [0, "0", "a"],
        "constraints": [["-sin(theta)", "cos(theta)", 0]],
        "free": ["x", "theta"]
    }))
    .unwrap();
    assert_eq!(t.key(), j.key());
    assert!(Model::new(&t).is_ok());
    let q = [0.3, -0.7, 1.1];
    assert_eq!(t.mass(&q), j.mass(&q));
    assert_eq!(t.basis(&q), j.basis(&q));
    assert_eq!(t.one_form(&q), j.one_form(&q));
    // a different parameter value, or a different definition, is a different key
    let t2 = t.clone().with_params(&[("m".into(), 3.0)]).unwrap();
    assert_ne!(t2.key(), t.key());
    assert_eq!(t2.mass(&q)[0][0], 3.0);
    let j2 = SceneFile::from_json(&json!({
        "name": "sleigh-like",
        "coordinates": ["x", "y", "theta"],
        "quasi_velocities": ["s", "w"],
        "parameters": {"I": 1.5, "a": 0.25, "m": 2.0},
        "constraints": [["-sin(theta)", "cos(theta)", 0]],
        "free": ["x", "theta"]
    }))
    .unwrap();
    assert_ne!(j2.key(), j.key());
    // the JSON default name
    let mut v = json!({"coordinates": ["x", "y"], "constraints": [[1, 1]], "free": ["x"]});
    assert_eq!(SceneFile::from_json(&v).unwrap().name(), "inline");
    v["name"] = json!("mine");
    assert_eq!(SceneFile::from_json(&v).unwrap().name(), "mine");
}

/// The value of `expr` as the potential of a one-coordinate-pair scene at q = (x, y).
fn value<S: dalembert::scalar::Scalar>(expr: &str, q: &[S]) -> S {
    let text = format!(
        "coordinates = [\"x\", \"y\"]\nconstraints = [[1, 1]]\nfree = [\"x\"]\n\
         potential = {}\n[parameters]\nc = 0.1\n",
        json!(expr)
    );
    toml(&text).potential(q)
}

#[test]
fn expressions_agree_with_hand_computed_values() {
    let q = [4.0, -0.5];
    let qi = [point(4.0), point(-0.5)];
    let exact = |e: &str, v: f64| {
        assert_eq!(value(e, &q), v, "{e}");
        let i: Interval = value(e, &qi);
        assert!(i.contains(v), "{e}: {i:?} misses {v}");
    };
    exact("2^-3", 0.125);
    exact("2^10", 1024.0);
    exact("x^0", 1.0);
    exact("y^3", -0.125);
    exact("y^-2", 4.0);
    exact("-x^2", -16.0);
    exact("x^0.5", 2.0);
    exact("x^-0.5", 0.5);
    exact("x - y - 1", 3.5);
    exact("x / y / 2", -4.0);
    exact("(x + y) * 2", 7.0);
    exact("1e-3 * 1000", 1.0);
    exact("c", 0.1);
    // (1/3)*3: the real 1/3 times 3, not the f64 1/3 times 3
    let i: Interval = value("(1/3)*3", &qi);
    assert!(i.contains(1.0) && i.inf() < i.sup(), "{i:?}");
    let third: Interval = value("1/3", &qi);
    assert!(
        third.inf() < third.sup(),
        "1/3 must not be folded to an f64"
    );
    // pi is the real pi
    let pi: Interval = value("pi", &qi);
    assert!(
        pi.contains(std::f64::consts::PI) && pi.inf() < pi.sup(),
        "{pi:?}"
    );
    assert!(value::<Interval>("sin(pi)", &qi).contains(0.0));
    // a decimal literal is the nearest f64: 0.1 is exactly the f64 0.1
    assert_eq!(value::<Interval>("0.1", &qi), point(0.1));
    assert_eq!(
        value::<Interval>("0.1000000000000000055511151231257827", &qi),
        point(0.1)
    );
    // a real exponent: exp(e log b)
    let r: Interval = value("x^1.5", &qi);
    assert!(r.contains(8.0) && r.wid() < 1e-13, "{r:?}");
    assert!((value("x^y", &q) - 0.5).abs() < 1e-15);
    // the functions
    for (e, v) in [
        ("sin(y)", (-0.5f64).sin()),
        ("cos(y)", (-0.5f64).cos()),
        ("tan(y)", (-0.5f64).tan()),
        ("exp(y)", (-0.5f64).exp()),
        ("log(x)", 4f64.ln()),
        ("ln(x)", 4f64.ln()),
        ("sqrt(x)", 2.0),
        ("atan(y)", (-0.5f64).atan()),
        ("sinh(y)", (-0.5f64).sinh()),
        ("cosh(y)", (-0.5f64).cosh()),
        ("tanh(y)", (-0.5f64).tanh()),
    ] {
        assert!((value(e, &q) - v).abs() < 1e-15, "{e}");
        let i: Interval = value(e, &qi);
        assert!(
            (i.inf() - v).abs() < 1e-15 && (i.sup() - v).abs() < 1e-15,
            "{e}: {i:?}"
        );
    }
    // a plain number is the same as the string
    let a = toml("coordinates = [\"x\", \"y\"]\nconstraints = [[1, -2.5]]\nfree = [\"x\"]\n");
    let b =
        toml("coordinates = [\"x\", \"y\"]\nconstraints = [[\"1\", \"-2.5\"]]\nfree = [\"x\"]\n");
    assert_eq!(a.key(), b.key());
    assert_eq!(a.constraints(&q), vec![vec![1.0, -2.5]]);
}

/// The input error of `text`, required to be one line containing every fragment; the JSON
/// form of the same scene (when TOML can carry it over) gives the same message.
fn refused(text: &str, fragments: &[&str]) -> String {
    let e = SceneFile::from_toml(text, "test").expect_err(text);
    let Error::Input(dalembert::InputError { message: m, .. }) = &e else {
        panic!("not an input error: {e}")
    };
    assert!(!m.contains('\n'), "two lines: {m}");
    for f in fragments {
        assert!(m.contains(f), "`{m}` lacks `{f}`");
    }
    if let Ok(t) = toml::from_str::<toml::Table>(text) {
        let has_non_finite = text.contains("inf") || text.contains("nan");
        if let (Ok(v), false) = (serde_json::to_value(&t), has_non_finite) {
            let je = SceneFile::from_json(&v).expect_err(text);
            assert_eq!(je.message(), m, "JSON and TOML differ");
        }
    }
    m.clone()
}

const OK_HEAD: &str = "coordinates = [\"x\", \"y\", \"z\"]\nconstraints = [[\"-y\", 0, 1]]\n";

#[test]
fn every_refusal_says_what_and_where() {
    // TOML syntax: line and column
    refused(
        "name = \"a\"\ncoordinates = [\"x\"]\n@ = 1\n",
        &["TOML", "line 3, column 1"],
    );
    refused("coordinates = [\"x\", \"y\"\n", &["TOML", "line "]);
    refused("name = \"a\"\nname = \"b\"\n", &["TOML", "line 2"]);
    // expression syntax: key, row, column, character
    let m = refused(
        &format!(
            "{OK_HEAD}free = [\"x\", \"y\"]\nparameters = {{ m = 1 }}\n\
             mass = [[1, 0, 0], [\"m*(x))\", 1, 0], [0, 0, 1]]\n"
        ),
        &["mass[2][1]", "unexpected `)`", "character 6", "`m*(x))`"],
    );
    assert!(m.starts_with("mass[2][1]: "), "{m}");
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = \"x +\"\n"),
        &["potential", "end of the expression", "character 4"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\none_form = [0, \"2 $ x\", 0]\n"),
        &["one_form[2]", "unexpected character `$`", "character 3"],
    );
    refused(
        &format!("{OK_HEAD}basis = [[1, 0, \"y\"], [0, \"(1\", 0]]\n"),
        &["basis[2][2]", "not closed"],
    );
    refused(
        "coordinates = [\"x\", \"y\"]\nconstraints = [[\"sin x\", 1]]\nfree = [\"y\"]\n",
        &["constraints[1][1]", "parentheses"],
    );
    // unknown names, listing the known ones
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = \"g*z\"\n"),
        &[
            "potential",
            "unknown name `g`",
            "character 1",
            "coordinates x, y, z",
            "pi",
        ],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = \"asin(z)\"\n"),
        &["unknown function `asin`", "sin, cos"],
    );
    // non-analytic functions
    for f in [
        "abs(x)",
        "min(x, y)",
        "max(x, y)",
        "floor(x)",
        "ceil(x)",
        "sign(x)",
        "round(x)",
        "mod(x, 2)",
    ] {
        refused(
            &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = \"1 + {f}\"\n"),
            &["potential", "not analytic", "character 5"],
        );
    }
    // wrong sizes
    refused(
        "coordinates = [\"x\", \"y\", \"z\"]\nconstraints = [[\"-y\", 1]]\nfree = [\"x\", \"y\"]\n",
        &["constraints[1]", "2 entries, expected 3"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nmass = [[1, 0, 0], [0, 1, 0]]\n"),
        &["mass", "2 rows, expected 3"],
    );
    refused(
        &format!("{OK_HEAD}basis = [[1, 0, \"y\"]]\n"),
        &["basis", "1 rows, expected 2"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\none_form = [1, 2]\n"),
        &["one_form", "2 entries, expected 3"],
    );
    refused(
        "coordinates = [\"x\", \"y\"]\nconstraints = [[1, 0], [0, 1]]\nfree = []\n",
        &["constraints", "2 rows for 2 coordinates"],
    );
    refused(
        "coordinates = [\"x\", \"y\"]\nconstraints = [1, 0]\nfree = [\"x\"]\n",
        &["constraints[1]", "expected a row"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nquasi_velocities = [\"a\"]\n"),
        &["quasi_velocities", "1 names, expected n - k = 2"],
    );
    refused(
        "coordinates = []\nconstraints = []\n",
        &["coordinates", "0 names"],
    );
    // duplicate and bad names
    refused(
        "coordinates = [\"x\", \"x\"]\nconstraints = [[1, 1]]\nfree = [\"x\"]\n",
        &["coordinates[2]", "duplicate name `x`"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nparameters = {{ y = 1 }}\n"),
        &["parameters.y", "already a coordinate"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nquasi_velocities = [\"a\", \"a\"]\n"),
        &["quasi_velocities[2]", "duplicate"],
    );
    refused(
        "coordinates = [\"x\", \"sin\"]\nconstraints = [[1, 1]]\nfree = [\"x\"]\n",
        &["coordinates[2]", "reserved"],
    );
    refused(
        "coordinates = [\"x\", \"pi\"]\nconstraints = [[1, 1]]\nfree = [\"x\"]\n",
        &["coordinates[2]", "reserved"],
    );
    refused(
        "coordinates = [\"x\", \"2y\"]\nconstraints = [[1, 1]]\nfree = [\"x\"]\n",
        &["coordinates[2]", "not a name"],
    );
    refused(
        "name = \"\"\ncoordinates = [\"x\", \"y\"]\nconstraints = [[1, 1]]\nfree = [\"x\"]\n",
        &["name", "empty"],
    );
    // free
    refused(
        &format!("{OK_HEAD}free = [\"x\"]\n"),
        &["free", "1 names, expected n - k = 2"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"w\"]\n"),
        &["free[2]", "unknown coordinate `w`", "known: x, y, z"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"x\"]\n"),
        &["free[2]", "repeated"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nbasis = [[1, 0, \"y\"], [0, 1, 0]]\n"),
        &["both `basis` and `free`"],
    );
    refused(OK_HEAD, &["missing key `free`", "`basis`"]);
    refused("constraints = [[1]]\n", &["missing key `coordinates`"]);
    refused(
        "coordinates = [\"x\", \"y\"]\n",
        &["missing key `constraints`"],
    );
    // unknown keys, with the near miss named and the known keys listed
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nmasss = [[1]]\n"),
        &[
            "unknown key `masss`",
            "did you mean `mass`",
            "known: name, coordinates",
        ],
    );
    let m = refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nlagrangian = \"1\"\n"),
        &["unknown key `lagrangian`", "known: name"],
    );
    assert!(!m.contains("did you mean"), "{m}");
    // non-finite numbers
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nparameters = {{ m = inf }}\n"),
        &["parameters.m", "not finite"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = nan\n"),
        &["potential", "not finite"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = \"1e999 * x\"\n"),
        &["potential", "not finite", "character 1"],
    );
    // integers beyond 2^53
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = 9007199254740993\n"),
        &["potential", "2^53"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nparameters = {{ k = -9007199254740993 }}\n"),
        &["parameters.k", "2^53"],
    );
    assert!(SceneFile::from_toml(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = 9007199254740992\n"),
        "t"
    )
    .is_ok());
    // exponents beyond the cap, wrong types
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = \"x^2000\"\n"),
        &["potential", "1024"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\npotential = true\n"),
        &["potential", "expected an expression", "boolean"],
    );
    refused(
        &format!("{OK_HEAD}free = [\"x\", \"y\"]\nparameters = {{ m = \"2\" }}\n"),
        &["parameters.m", "expected a number", "string"],
    );
}

#[test]
fn parameters_are_overridden_by_name_only() {
    let f = toml(&format!(
        "{OK_HEAD}free = [\"x\", \"y\"]\nparameters = {{ k = 2, c = 0.5 }}\npotential = \"k*x\"\n"
    ));
    let g = f.clone().with_params(&[("k".into(), 3.0)]).unwrap();
    assert_eq!(g.potential(&[2.0, 0.0, 0.0]), 6.0);
    assert_eq!(f.potential(&[2.0, 0.0, 0.0]), 4.0);
    let e = f.clone().with_params(&[("m".into(), 1.0)]).unwrap_err();
    assert!(
        e.message().contains("no parameter `m`") && e.message().contains("c, k"),
        "{e}"
    );
    assert!(f.clone().with_params(&[("k".into(), f64::NAN)]).is_err());
    assert!(f
        .clone()
        .with_params(&[("k".into(), f64::INFINITY)])
        .is_err());
    let bare = toml(&format!("{OK_HEAD}free = [\"x\", \"y\"]\n"));
    let e = bare.with_params(&[("m".into(), 1.0)]).unwrap_err();
    assert!(e.message().contains("no parameters"), "{e}");
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dalembert-scene-files-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn files_are_named_by_their_stem_and_their_errors_by_their_path() {
    let p = scratch("my_system.toml");
    std::fs::write(&p, format!("{OK_HEAD}free = [\"x\", \"y\"]\n")).unwrap();
    assert_eq!(SceneFile::read(&p).unwrap().name(), "my_system");
    std::fs::write(&p, format!("{OK_HEAD}free = [\"x\", \"q\"]\n")).unwrap();
    let e = SceneFile::read(&p).unwrap_err();
    assert!(
        e.message()
            .starts_with(&format!("{}: free[2]", p.display())),
        "{e}"
    );
    let bad = scratch("latin1.toml");
    std::fs::write(&bad, b"name = \"caf\xe9\"\n").unwrap();
    let e = SceneFile::read(&bad).unwrap_err();
    assert!(
        e.message().contains("not UTF-8") && dalembert::protocol::exit_code(&e) == 2,
        "{e}"
    );
    let missing = scratch("missing.toml");
    let e = SceneFile::read(&missing).unwrap_err();
    assert!(
        e.message().starts_with(&missing.display().to_string())
            && dalembert::protocol::exit_code(&e) == 2
    );
    let e = SceneFile::read(&scratch("")).unwrap_err();
    assert_eq!(dalembert::protocol::exit_code(&e), 2);
}

fn example_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v
}

/// Every example compiles; along its certified flow from a generic state the energy
/// E(q, v) (conserved by ideal constraints, with or without a one-form) keeps its initial
/// value: the enclosure of E at the final box contains the exact initial energy's
/// enclosure's points.
#[test]
fn every_example_compiles_and_its_flow_conserves_energy() {
    let files = example_files();
    assert!(files.len() >= 3);
    let mut two_constraints = false;
    let mut varying_mass = false;
    for p in &files {
        let f = SceneFile::read(p).unwrap_or_else(|e| panic!("{e}"));
        let model = Model::new(&f).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(dalembert::scene::scene_names()
            .iter()
            .all(|s| *s != f.name()));
        two_constraints |= model.k() >= 2;
        let q0: Vec<f64> = (0..model.n()).map(|i| 0.1 + 0.2 * i as f64).collect();
        let q1: Vec<f64> = q0.iter().map(|x| x + 0.4).collect();
        varying_mass |= f.mass(&q0) != f.mass(&q1);
        let qi: Vec<Interval> = q0.iter().map(|x| point(*x)).collect();
        model
            .check_at(&qi)
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let u0: Vec<f64> = (0..model.n() - model.k())
            .map(|a| 0.5 - 0.3 * a as f64)
            .collect();
        let fl = dalembert::flow(&model, &q0, &u0, 0.5, &FlowOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let x0: Vec<Interval> = q0.iter().chain(&u0).map(|x| point(*x)).collect();
        let v0 = model.velocity().eval(&x0);
        let e0 = model.energy().eval(&[qi.clone(), v0].concat())[0];
        let ia =
            |v: &[dalembert::Interval]| v.iter().map(|x| Interval::from(*x)).collect::<Vec<_>>();
        let e1 = model.energy().eval(&[ia(&fl.q), ia(&fl.v)].concat())[0];
        assert!(
            !e0.intersection(e1).is_empty() && e1.wid() < 1e-6 * (1.0 + e0.mag()),
            "{}: energy {e0:?} -> {e1:?}",
            p.display()
        );
        // the motion is not trivial
        assert!((fl.q[0].mid() - q0[0]).abs() > 1e-3 || (fl.q[1].mid() - q0[1]).abs() > 1e-3);
    }
    assert!(two_constraints && varying_mass);
}

const ALPHABET: &[u8] = b"()[]{}\"=,^-*/.0123456789eE\nxyzpi ";

/// A system that is not built in, against an independent reference: the differential-drive
/// robot's axle centre is on its centre of mass, so the wheel rates u are constant and the
/// robot runs on a circle: with v = R (ul + ur)/2 and w = R (ur - ul)/(2 b),
/// theta = theta0 + w t, x = x0 + v/w (sin theta - sin theta0),
/// y = y0 - v/w (cos theta - cos theta0), phi = phi0 + u t. The closed form, evaluated in
/// interval arithmetic from the exact inputs, must meet the certified flow's enclosure, and
/// the enclosure must be narrow.
#[test]
fn the_differential_drive_runs_on_its_closed_form_circle() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/differential_drive.toml");
    let f = SceneFile::read(&p).unwrap();
    let par = |name: &str| {
        f.parameters()
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| point(*v))
            .unwrap()
    };
    let (r, b) = (par("R"), par("b"));
    let model = Model::new(&f).unwrap();
    let mut rng = SplitMix64(0xD21F);
    for _ in 0..4 {
        let q0: Vec<f64> = (0..5).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let u: Vec<f64> = (0..2).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let t = rng.uniform(0.5, 5.0);
        let fl = dalembert::flow(&model, &q0, &u, t, &FlowOptions::default()).unwrap();
        let (ul, ur, ti) = (point(u[0]), point(u[1]), point(t));
        let v = r * (ul + ur) / point(2.0);
        let w = r * (ur - ul) / (point(2.0) * b);
        let th0 = point(q0[2]);
        let th = th0 + w * ti;
        let want = [
            point(q0[0]) + v / w * (th.sin() - th0.sin()),
            point(q0[1]) - v / w * (th.cos() - th0.cos()),
            th,
            point(q0[3]) + ul * ti,
            point(q0[4]) + ur * ti,
        ];
        for (i, (got, want)) in fl.q.iter().zip(&want).enumerate() {
            assert!(
                !got.intersection(*want).is_empty() && got.wid() < 1e-9,
                "q[{i}]: flow {got:?}, closed form {want:?}"
            );
        }
        for (a, (got, u0)) in fl.u.iter().zip(&u).enumerate() {
            assert!(got.contains(*u0) && got.wid() < 1e-9, "u[{a}] {got:?}");
        }
    }
}

#[test]
fn the_fuzz_check_holds_on_random_and_mutated_inputs() {
    let mut rng = SplitMix64(0xF022);
    let seeds: Vec<Vec<u8>> = example_files()
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .chain([PARTICLE.as_bytes().to_vec(), KNIFE.as_bytes().to_vec()])
        .collect();
    for round in 0..600 {
        let mut data = seeds[round % seeds.len()].clone();
        for _ in 0..1 + rng.next() % 4 {
            if data.is_empty() {
                break;
            }
            let i = (rng.next() as usize) % data.len();
            match rng.next() % 3 {
                0 => data[i] = rng.next() as u8,
                1 => {
                    data.remove(i);
                }
                _ => data.insert(i, ALPHABET[(rng.next() as usize) % ALPHABET.len()]),
            }
        }
        // mode byte 0: text as TOML
        dalembert::fuzzing::scene_file(&[[0u8].as_slice(), &data].concat());
        let mut random: Vec<u8> = (0..rng.next() % 200).map(|_| rng.next() as u8).collect();
        dalembert::fuzzing::scene_file(&random);
        // mode byte 2: a structured expression
        random.insert(0, 2);
        dalembert::fuzzing::scene_file(&random);
    }
}
