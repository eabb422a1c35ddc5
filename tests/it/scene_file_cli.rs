//! Scene files and inline JSON scenes through the command line and `batch`, as a user runs
//! them (README, "Your own system"): every command takes `--scene-file`, a built-in scene
//! written as a file is the same program as the built-in (identical tapes, identical
//! answers), batch answers inline scenes as it answers files, and every refusal is one
//! `error:` line with the right exit status.

use crate::common::{batch_answers, run_args};
use dalembert::scene::{AnyScene, SceneFile};
use dalembert::Model;
use std::path::PathBuf;
use std::process::Output;

const PARTICLE: &str = r#"
name = "particle"
coordinates = ["x", "y", "z"]
quasi_velocities = ["xd", "yd"]
constraints = [["-y", 0, 1]]
basis = [[1, 0, "y"], [0, 1, 0]]
"#;

const KNIFE_EPS: &str = r#"
# the built-in knife-eps (spec eq. (3.4)) as a file
coordinates = ["x", "y", "phi"]
potential = "-(x*0.5)"
constraints = [["sin(phi)", "-(cos(phi) - eps)", 0]]
basis = [["cos(phi) - eps", "sin(phi)", 0], [0, 0, 1]]

[parameters]
eps = 0.1
"#;

fn file(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("scene_file_cli");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn ok_stdout(o: &Output) -> String {
    assert!(
        o.status.success(),
        "exit {:?}: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout.clone()).unwrap()
}

/// One `error:` line on stderr, nothing on stdout, the given exit status.
fn refused(o: &Output, code: i32, fragment: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert!(o.stdout.is_empty());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: ") && err.contains(fragment),
        "{err}"
    );
}

/// Compiling a built-in scene and the same scene written as a file gives the same tapes
/// (the same operations, recorded perhaps in another order): the same programs, so every
/// test of the built-in holds for the file (spec eq. (3.16)).
#[test]
fn a_built_in_written_as_a_file_compiles_to_identical_tapes() {
    for (text, name, params) in [
        (PARTICLE, "particle", vec![]),
        (KNIFE_EPS, "knife-eps", vec![("eps".to_string(), 0.1)]),
        (KNIFE_EPS, "knife-eps", vec![("eps".to_string(), -0.3)]),
    ] {
        let f = SceneFile::from_toml(text, name)
            .unwrap()
            .with_params(&params)
            .unwrap();
        let a = Model::new(&f).unwrap();
        let borrowed: Vec<(&str, f64)> = params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let b = Model::new(&AnyScene::new(name, &borrowed).unwrap()).unwrap();
        assert!(
            a.dynamics().field.same_program(&b.dynamics().field),
            "{name}: field"
        );
        assert!(
            a.dynamics().field_var.same_program(&b.dynamics().field_var),
            "{name}"
        );
        assert!(a
            .dynamics()
            .field_var_tail()
            .same_program(b.dynamics().field_var_tail()));
        assert!(
            a.with_action().field.same_program(&b.with_action().field),
            "{name}: action"
        );
        assert!(a.velocity_jac().same_program(b.velocity_jac()), "{name}");
        assert!(a.momentum_d().same_program(b.momentum_d()), "{name}");
        assert!(a.energy().same_program(b.energy()), "{name}");
        assert!(a.nh_force().same_program(b.nh_force()), "{name}");
    }
}

/// Every command that takes --scene takes --scene-file; the file's answers are the
/// built-in's, byte for byte (the same tapes give the same enclosures).
#[test]
fn every_command_takes_a_scene_file_and_answers_as_the_built_in() {
    let p = file("particle.toml", PARTICLE);
    let p = p.to_str().unwrap();
    let cases: [&[&str]; 4] = [
        &[
            "flow", "--q", "0,0,0", "--u", "0.8,0.8", "--t", "2", "--json",
        ],
        &[
            "retract",
            "--q0",
            "0,0,0",
            "--q1",
            "0.4,0.4,0.08",
            "--h",
            "0.5",
            "--json",
        ],
        &[
            "step",
            "--q0",
            "0,0,0",
            "--q1",
            "0.4,0.4,0.08",
            "--h",
            "0.5",
            "--json",
        ],
        &[
            "lagrangian",
            "--q0",
            "0,0,0",
            "--q1",
            "0.4,0.4,0.08",
            "--h",
            "0.5",
            "--json",
        ],
    ];
    for args in cases {
        let (cmd, rest) = args.split_first().unwrap();
        let mut a = vec![*cmd, "--scene-file", p];
        a.extend(rest);
        let mut b = vec![*cmd, "--scene", "particle"];
        b.extend(rest);
        assert_eq!(ok_stdout(&run_args(&a)), ok_stdout(&run_args(&b)), "{cmd}");
    }
    let traj = ok_stdout(&run_args(&[
        "integrate",
        "--scene-file",
        p,
        "--scheme",
        "mla",
        "--q0",
        "0,0,0",
        "--q1",
        "0.4,0.4,0.08",
        "--h",
        "0.5",
        "--steps",
        "10",
    ]));
    let t = file("traj.csv", &traj);
    let check = run_args(&[
        "check",
        "--scene-file",
        p,
        "--h",
        "0.5",
        "--trajectory",
        t.to_str().unwrap(),
        "--tol",
        "0.1",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&ok_stdout(&check)).unwrap();
    assert!(v.is_object());
    // `scenes --scene-file` describes the compiled scene, the basis as given
    let d: serde_json::Value = serde_json::from_str(&ok_stdout(&run_args(&[
        "scenes",
        "--scene-file",
        p,
        "--json",
    ])))
    .unwrap();
    let s = &d["scenes"][0];
    assert_eq!(s["name"], "particle");
    assert_eq!((s["n"].as_u64(), s["k"].as_u64()), (Some(3), Some(1)));
    assert_eq!(s["coordinates"], serde_json::json!(["x", "y", "z"]));
}

/// `--param` overrides the file's parameters, as it does a built-in's.
#[test]
fn parameters_of_a_file_are_overridden_on_the_command_line() {
    let k = file("knife_eps.toml", KNIFE_EPS);
    let k = k.to_str().unwrap();
    let args = [
        "--q0",
        "0,0,0",
        "--q1",
        "0.4,0.1,0.4",
        "--h",
        "0.5",
        "--json",
    ];
    for eps in ["0.1", "0.5", "-0.3"] {
        let pe = format!("eps={eps}");
        let mut a = vec!["step", "--scene-file", k, "--param", &pe];
        a.extend(args);
        let mut b = vec!["step", "--scene", "knife-eps", "--param", &pe];
        b.extend(args);
        assert_eq!(
            ok_stdout(&run_args(&a)),
            ok_stdout(&run_args(&b)),
            "eps = {eps}"
        );
    }
    let mut a = vec!["step", "--scene-file", k, "--param", "epsilon=0.1"];
    a.extend(args);
    refused(&run_args(&a), 2, "no parameter `epsilon`");
}

/// A scene given inline in a batch query is answered as the same scene from a file.
#[test]
fn batch_answers_inline_scenes_as_files() {
    let inline = r#"{"coordinates":["x","y","z"],"quasi_velocities":["xd","yd"],"constraints":[["-y",0,1]],"basis":[[1,0,"y"],[0,1,0]]}"#;
    let q = r#""q0":[0,0,0],"q1":[0.4,0.4,0.08],"h":0.5"#;
    let input = format!(
        "{{\"id\":1,\"cmd\":\"step\",\"scene\":{inline},{q}}}\n\
         {{\"id\":2,\"cmd\":\"step\",\"scene\":\"particle\",{q}}}\n\
         {{\"id\":3,\"cmd\":\"step\",\"scene\":{{\"coordinates\":[\"x\"]}},{q}}}\n\
         {{\"id\":4,\"cmd\":\"step\",\"scene\":7,{q}}}\n"
    );
    let a = batch_answers(&input);
    assert_eq!(a.len(), 4);
    assert_eq!(a[0]["ok"], a[1]["ok"]);
    assert!(a[0]["ok"]["q2"].is_array());
    assert_eq!(a[2]["error"]["code"], 2, "{}", a[2]);
    assert!(a[2]["error"]["message"]
        .as_str()
        .unwrap()
        .contains("constraints"));
    assert_eq!(a[3]["error"]["code"], 2);
}

#[test]
fn bad_scene_files_are_one_line_input_errors() {
    refused(
        &run_args(&[
            "flow",
            "--scene-file",
            "/nonexistent/x.toml",
            "--q",
            "0",
            "--u",
            "0",
            "--t",
            "1",
        ]),
        2,
        "/nonexistent/x.toml",
    );
    let bad = file("bad.toml", "coordinates = [\"x\", \"y\"\nconstraints = 3\n");
    refused(
        &run_args(&["scenes", "--scene-file", bad.to_str().unwrap()]),
        2,
        "line",
    );
    let p = file("particle2.toml", PARTICLE);
    refused(
        &run_args(&[
            "flow",
            "--scene",
            "particle",
            "--scene-file",
            p.to_str().unwrap(),
            "--q",
            "0,0,0",
            "--u",
            "0,0",
            "--t",
            "1",
        ]),
        2,
        "--scene",
    );
    // a mass matrix not positive definite where the query starts: exit 2, with the reason
    let indefinite = file(
        "indefinite.toml",
        "coordinates = [\"x\", \"y\"]\nmass = [[\"x\", 0], [0, 1]]\nconstraints = [[0, 1]]\nfree = [\"x\"]\n",
    );
    refused(
        &run_args(&[
            "flow",
            "--scene-file",
            indefinite.to_str().unwrap(),
            "--q",
            "-1,0",
            "--u",
            "1",
            "--t",
            "1",
        ]),
        2,
        "positive definite",
    );
}

/// The derived basis of the README's unicycle is singular at cos(theta) = 0: a flow that
/// reaches it is refused (exit 3), never answered.
#[test]
fn the_readme_unicycle_answers_and_refuses_where_its_basis_is_singular() {
    let u = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes/unicycle.toml");
    let flow_to = |t: &str| {
        run_args(&[
            "flow",
            "--scene-file",
            u,
            "--q",
            "0.2,-0.1,0.3",
            "--u",
            "0.6,0.9",
            "--t",
            t,
            "--json",
        ])
    };
    let o = flow_to("1");
    let v: serde_json::Value = serde_json::from_str(&ok_stdout(&o)).unwrap();
    // theta(1) = 0.3 + 0.9 exactly in the real numbers
    let th = &v["q"][2];
    assert!(th[0].as_f64().unwrap() <= 1.2 && 1.2 <= th[1].as_f64().unwrap() + 1e-15);
    let o = flow_to("2");
    refused(&o, 3, "");
}

/// `check` as a batch query (a whole trajectory in one line) answers what `check --json`
/// prints, for a built-in and for an inline scene.
#[test]
fn batch_check_answers_what_the_check_command_prints() {
    let p = file("particle_check.toml", PARTICLE);
    let traj = ok_stdout(&run_args(&[
        "integrate",
        "--scene",
        "particle",
        "--scheme",
        "dla",
        "--q0",
        "0,0,0",
        "--q1",
        "0.4,0.4,0.08",
        "--h",
        "0.5",
        "--steps",
        "8",
        "--json",
    ]));
    let t: serde_json::Value = serde_json::from_str(&traj).unwrap();
    let q = t["q"].to_string();
    let tf = file("traj_check.json", &format!("{{\"q\": {q}}}"));
    let cli: serde_json::Value = serde_json::from_str(&ok_stdout(&run_args(&[
        "check",
        "--scene-file",
        p.to_str().unwrap(),
        "--h",
        "0.5",
        "--trajectory",
        tf.to_str().unwrap(),
        "--tol",
        "0.1",
        "--json",
    ])))
    .unwrap();
    let inline =
        r#"{"coordinates":["x","y","z"],"constraints":[["-y",0,1]],"basis":[[1,0,"y"],[0,1,0]]}"#;
    let input = format!(
        "{{\"id\":1,\"cmd\":\"check\",\"scene\":\"particle\",\"h\":0.5,\"q\":{q},\"tol\":0.1}}\n\
         {{\"id\":2,\"cmd\":\"check\",\"scene\":{inline},\"h\":0.5,\"q\":{q},\"tol\":0.1}}\n\
         {{\"id\":3,\"cmd\":\"check\",\"scene\":\"particle\",\"h\":0.5,\"q\":{q},\"pairs\":false}}\n\
         {{\"id\":4,\"cmd\":\"check\",\"scene\":\"particle\",\"h\":0.5,\"q\":[[0,0,0],[0.1,0.1]]}}\n\
         {{\"id\":5,\"cmd\":\"check\",\"scene\":\"particle\",\"h\":0.5,\"q\":{q},\"tolerance\":1}}\n\
         {{\"id\":6,\"cmd\":\"check\",\"scene\":\"particle\",\"h\":0.5,\"q\":{q},\"tol\":1e-12}}\n"
    );
    let a = batch_answers(&input);
    assert_eq!(a.len(), 6);
    assert_eq!(a[0]["ok"], cli);
    assert_eq!(a[1]["ok"], cli);
    assert_eq!(a[0]["ok"]["passed"], true);
    assert_eq!(a[2]["ok"]["defect"], serde_json::json!([]));
    assert_eq!(a[2]["ok"]["distance"], cli["distance"]);
    assert_eq!(a[3]["error"]["code"], 2, "{}", a[3]);
    assert_eq!(a[4]["error"]["code"], 2, "{}", a[4]);
    assert!(a[4]["error"]["message"]
        .as_str()
        .unwrap()
        .contains("unknown key `tolerance`"));
    // DLA is not within 1e-12 of the exact discrete flow: proved beyond the tolerance
    assert_eq!(a[5]["ok"]["passed"], false, "{}", a[5]);
}

/// `integrate` checks the scene at both start configurations (spec (3.17)) on the command
/// line as in batch: a mass matrix `diag(x, 1)` is not positive definite at x = -1, so both
/// refuse that start with the same input error (exit 2) and accept x = 1.
#[test]
fn integrate_checks_the_scene_at_its_start_on_the_command_line_as_in_batch() {
    let f = file(
        "mass_x.toml",
        "coordinates = [\"x\", \"y\"]\nquasi_velocities = [\"xd\"]\n\
         mass = [[\"x\", 0], [0, 1]]\nconstraints = [[0, 1]]\nfree = [\"x\"]\n",
    );
    let f = f.to_str().unwrap();
    let cli = |q0: &str, q1: &str| {
        run_args(&[
            "integrate",
            "--scene-file",
            f,
            "--scheme",
            "dla",
            "--q0",
            q0,
            "--q1",
            q1,
            "--h",
            "0.1",
            "--steps",
            "2",
        ])
    };
    refused(&cli("-1,0", "-1.1,0"), 2, "not proved positive definite");
    refused(&cli("1,0", "-1,0"), 2, "not proved positive definite");
    ok_stdout(&cli("1,0", "1.1,0"));
    let scene = serde_json::json!({
        "coordinates": ["x", "y"], "quasi_velocities": ["xd"],
        "mass": [["x", 0], [0, 1]], "constraints": [[0, 1]], "free": ["x"]
    });
    let line = serde_json::json!({
        "id": 1, "cmd": "integrate", "scene": scene, "scheme": "dla",
        "q0": [-1.0, 0.0], "q1": [-1.1, 0.0], "h": 0.1, "steps": 2
    });
    let a = batch_answers(&format!("{line}\n"));
    assert_eq!(a[0]["error"]["code"], 2, "{}", a[0]);
    assert!(a[0]["error"]["message"]
        .as_str()
        .unwrap()
        .contains("not proved positive definite"));
}
