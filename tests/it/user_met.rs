//! What a new user met (posing an inclined knife and a trailer from scene files, flowing
//! backward, asking for a scheme's order from batch, writing a scene file):
//! - a refusal along the motion names its cause (the derived basis's pivot block not proved
//!   regular, with the time reached), typed `Reason::Undefined` in the library and
//!   `"reason": "undefined"` in batch; the step budget is named only when it is the cause;
//! - flows to negative times (spec (5.17)): reversibility `q(-t; q0, u0) = q(t; q0, -u0)`
//!   on the paper's scenes (whose field is even in `u`), closed forms of the particle and
//!   the knife, dense output across 0 and the derivative backward;
//! - `order` as a batch query answers what `dalembert order --json` prints;
//! - the two scene-file mistakes get messages that say what to do.

use crate::common::{batch_answers, model, run_args, show};
use dalembert::flow::{flow_at, flow_c1};
use dalembert::scalar::{point, Scalar};
use dalembert::scene::SceneFile;
use dalembert::{flow, Error, FlowOptions, Model, Reason};
use inari::Interval;
use std::path::{Path, PathBuf};
use std::process::Output;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes")
        .join(name)
}

fn file_model(name: &str) -> Model {
    Model::new(&SceneFile::read(&example(name)).expect("scene file")).expect("model")
}

fn json_stdout(o: &Output) -> serde_json::Value {
    assert!(
        o.status.success(),
        "exit {:?}: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

fn meets(a: impl Into<Interval>, b: impl Into<Interval>) -> bool {
    !a.into().intersection(b.into()).is_empty()
}

fn json_interval(v: &serde_json::Value) -> Interval {
    let a = v.as_array().expect("an interval");
    dalembert::scalar::iv(a[0].as_f64().unwrap(), a[1].as_f64().unwrap())
}

// ---------------------------------------------------------------------------------------
// 1. Refusals that name their cause

/// phi = 1.3 t reaches pi/2 at t* = (pi/2) / 1.3 (phid is constant on the knife: the
/// constraint does not involve phi's velocity and V does not depend on phi).
fn knife_singular_time() -> Interval {
    Interval::FRAC_PI_2 / point(1.3)
}

fn expect_refusal(r: Result<impl std::fmt::Debug, Error>) -> dalembert::Refusal {
    match r {
        Err(Error::Uncertified(r)) => r,
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn the_inclined_knife_with_free_x_phi_is_refused_at_its_pivot_naming_the_time() {
    let m = file_model("inclined_knife_free.toml");
    let r = expect_refusal(flow(
        &m,
        &[0.0, 0.0, 0.0],
        &[0.5, 1.3],
        2.0,
        &FlowOptions::default(),
    ));
    assert_eq!(r.reason, Reason::Undefined, "{}", r.message);
    assert!(
        r.message.contains("pivot block") && r.message.contains("columns of y"),
        "{}",
        r.message
    );
    // proved up to a time before the singular one, and not far from it
    let reached = r.reached.expect("a time reached");
    let ts = knife_singular_time();
    assert!(reached < ts.inf() && reached > 1.1, "reached {reached}");
    assert!(r.message.contains("at t = 1.2"), "{}", r.message);
    // before the singular time the same scene answers, and agrees with the built-in knife
    // (the same motion in other quasi-velocities: q and qd are the same)
    let e = flow(&m, &[0.0; 3], &[0.5, 1.3], 1.0, &FlowOptions::default()).unwrap();
    let k = flow(
        &model("knife", &[]),
        &[0.0; 3],
        &[0.5, 1.3],
        1.0,
        &FlowOptions::default(),
    )
    .unwrap();
    for i in 0..3 {
        assert!(
            meets(e.q[i], k.q[i]),
            "q[{i}]: {} vs {}",
            show(e.q[i]),
            show(k.q[i])
        );
        assert!(
            meets(e.v[i], k.v[i]),
            "v[{i}]: {} vs {}",
            show(e.v[i]),
            show(k.v[i])
        );
    }
}

#[test]
fn the_command_line_and_batch_name_the_pivot_and_the_time() {
    let path = example("inclined_knife_free.toml");
    let p = path.to_str().unwrap();
    let o = run_args(&[
        "flow",
        "--scene-file",
        p,
        "--q",
        "0,0,0",
        "--u",
        "0.5,1.3",
        "--t",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(3));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("pivot block") && err.contains("at t = 1.2") && !err.contains("steps would"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    // batch takes a user's scene inline: the file's keys as a JSON object
    let text = std::fs::read_to_string(&path).unwrap();
    let table: toml::Table = toml::from_str(&text).unwrap();
    let line = serde_json::json!({
        "id": 1, "cmd": "flow", "scene": table, "q": [0, 0, 0], "u": [0.5, 1.3], "t": 2
    });
    let a = &batch_answers(&format!("{line}\n"))[0];
    let e = &a["error"];
    assert_eq!(e["code"], 3, "{a}");
    assert_eq!(e["reason"], "undefined", "{a}");
    assert!(
        e["message"].as_str().unwrap().contains("pivot block"),
        "{a}"
    );
    let reached = e["reached"].as_f64().unwrap();
    assert!(
        reached > 1.1 && reached < knife_singular_time().inf(),
        "{a}"
    );
}

#[test]
fn starting_on_the_singular_set_names_the_pivot_block() {
    let m = file_model("inclined_knife_free.toml");
    let phi = std::f64::consts::FRAC_PI_2;
    for t in [1.0, -1.0] {
        let r = expect_refusal(flow(
            &m,
            &[0.0, 0.0, phi],
            &[0.5, 1.3],
            t,
            &FlowOptions::default(),
        ));
        assert_eq!(r.reason, Reason::Undefined, "{}", r.message);
        assert!(r.message.contains("pivot block"), "{}", r.message);
        assert!(
            !r.message.contains("vector field not defined"),
            "{}",
            r.message
        );
        assert_eq!(r.reached, Some(0.0));
    }
}

#[test]
fn the_trailer_is_refused_at_its_pivot_not_for_the_budget() {
    let m = file_model("trailer.toml");
    let r = expect_refusal(flow(
        &m,
        &[0.0; 4],
        &[1.0, 0.4],
        5.0,
        &FlowOptions::default(),
    ));
    assert_eq!(r.reason, Reason::Undefined, "{}", r.message);
    assert!(r.message.contains("pivot block"), "{}", r.message);
    let reached = r.reached.unwrap();
    assert!(reached > 0.0 && reached < 5.0, "{reached}");
    // the state where it stopped has theta near pi/2 (cos(theta) = 0 makes the block
    // singular): a flow to a little before answers with theta below pi/2
    let e = flow(
        &m,
        &[0.0; 4],
        &[1.0, 0.4],
        reached * 0.99,
        &FlowOptions::default(),
    )
    .unwrap();
    assert!(
        e.q[2].sup() < std::f64::consts::FRAC_PI_2,
        "{}",
        show(e.q[2])
    );
    assert!(e.q[2].inf() > 1.2, "{}", show(e.q[2]));
}

#[test]
fn a_long_flow_on_a_regular_scene_is_still_refused_for_its_budget() {
    let m = model("knife", &[]);
    let opts = FlowOptions::default().with_max_taylor_steps(5);
    let r = expect_refusal(flow(&m, &[0.0; 3], &[0.8, 0.8], 600.0, &opts));
    assert_eq!(r.reason, Reason::Budget);
    assert!(r.message.starts_with("more than 5 steps"), "{}", r.message);
    // and backward, with the time asked for
    let r = expect_refusal(flow(&m, &[0.0; 3], &[0.8, 0.8], -600.0, &opts));
    assert_eq!(r.reason, Reason::Budget);
    assert!(r.message.contains("t = -600"), "{}", r.message);
    assert!(r.reached.is_some_and(|t| t < 0.0 && t > -600.0));
}

// ---------------------------------------------------------------------------------------
// 2. Backward flows

/// xorshift, fixed seed.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

#[test]
fn backward_flows_are_forward_flows_with_the_velocities_reversed() {
    // G(q, u) is even in u on these scenes (quadratic velocity terms, forces from V), so
    // (q(-t), u(-t)) from (q0, u0) is (q(t), -u(t)) from (q0, -u0).
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for (name, params) in [
        ("particle", vec![]),
        ("knife", vec![]),
        ("knife-eps", vec![("eps", 0.1)]),
    ] {
        let m = model(name, &params);
        for _ in 0..6 {
            let q = [
                rng.uniform(-2.0, 2.0),
                rng.uniform(-2.0, 2.0),
                rng.uniform(-1.5, 1.5),
            ];
            let u = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
            let t = rng.uniform(0.1, 3.0);
            let back = flow(&m, &q, &u, -t, &FlowOptions::default()).unwrap();
            let fwd = flow(&m, &q, &[-u[0], -u[1]], t, &FlowOptions::default()).unwrap();
            for i in 0..3 {
                assert!(meets(back.q[i], fwd.q[i]), "{name} q[{i}] {q:?} {u:?} {t}");
                assert!(back.q[i].wid() < 1e-9, "{name}: {}", show(back.q[i]));
            }
            for i in 0..2 {
                assert!(
                    meets(back.u[i], -Interval::from(fwd.u[i])),
                    "{name} u[{i}] {q:?} {u:?} {t}"
                );
            }
        }
    }
}

#[test]
fn backward_flows_contain_the_closed_forms() {
    // particle with yd = 0 (nhsolution0): x = x0 + xd t, y = y0, z = z0 + y0 xd t
    let m = model("particle", &[]);
    let (q, u, t) = ([0.5, 2.0, -1.0], [0.25, 0.0], -3.0);
    let e = flow(&m, &q, &u, t, &FlowOptions::default()).unwrap();
    assert!(e.q[0].contains(-0.25) && e.q[1].contains(2.0) && e.q[2].contains(-2.5));
    // knife, w != 0 (the textbook form, valid for every t): phi = phi0 + w t,
    // s = s0 + (sin phi - sin phi0) / (2 w),
    // x = x0 + S (sin phi - sin phi0) / w + (sin^2 phi - sin^2 phi0) / (4 w^2),
    // y = y0 + S (cos phi0 - cos phi) / w + t / (4 w)
    //       - (sin 2 phi - sin 2 phi0) / (8 w^2),   S = s0 - sin phi0 / (2 w)
    let m = model("knife", &[]);
    for (q, u, t) in [
        ([0.0, 0.0, 0.0], [0.8, 0.8], -1.0),
        ([0.5, -1.0, 0.3], [-0.4, 1.7], -2.5),
        ([1.0, 2.0, -0.7], [1.2, -0.6], -4.0),
    ] {
        let e = flow(&m, &q, &u, t, &FlowOptions::default()).unwrap();
        let (x0, y0, p0) = (point(q[0]), point(q[1]), point(q[2]));
        let (s0, w, tt) = (point(u[0]), point(u[1]), point(t));
        let two = point(2.0);
        let phi = p0 + w * tt;
        let (sp0, cp0, sp, cp) = (p0.sin(), p0.cos(), phi.sin(), phi.cos());
        let big_s = s0 - sp0 / (two * w);
        let s = s0 + (sp - sp0) / (two * w);
        let x = x0 + big_s * (sp - sp0) / w + (sp.sqr() - sp0.sqr()) / (point(4.0) * w.sqr());
        let y = y0 + big_s * (cp0 - cp) / w + tt / (point(4.0) * w)
            - ((two * phi).sin() - (two * p0).sin()) / (point(8.0) * w.sqr());
        for (i, r) in [x, y, phi].into_iter().enumerate() {
            assert!(meets(e.q[i], r), "q[{i}] {} vs {}", show(e.q[i]), show(r));
        }
        assert!(meets(e.u[0], s) && meets(e.u[1], w));
    }
}

#[test]
fn dense_output_across_zero_matches_single_flows() {
    let m = model("knife", &[]);
    let (q, u) = ([0.25, -0.5, 0.4], [0.8, -0.6]);
    let times = [-2.0, -0.75, 0.0, 0.5, 1.5];
    let all = flow_at(&m, &q, &u, &times, &FlowOptions::default()).unwrap();
    assert_eq!(all.len(), times.len());
    for (t, e) in times.iter().zip(&all) {
        let one = flow(&m, &q, &u, *t, &FlowOptions::default()).unwrap();
        for i in 0..3 {
            assert!(meets(e.q[i], one.q[i]), "t = {t}, q[{i}]");
        }
    }
    // at t = 0 the start itself
    assert!((0..3).all(|i| all[2].q[i].contains(q[i])));
    // still strictly increasing
    assert!(matches!(
        flow_at(&m, &q, &u, &[-1.0, -2.0], &FlowOptions::default()),
        Err(Error::Input(_))
    ));
}

#[test]
fn the_derivative_backward_is_the_reversed_derivative_and_the_knife_closed_form() {
    // with R = diag(1, 1, 1, -1, -1): x(-t; x0) = R x(t; R x0), so
    // D x(-t) / D x0 = R [D x(t) / D x0 at R x0] R
    let m = model("knife", &[]);
    let (q, u, t) = ([0.3, -0.2, 0.5], [0.7, 0.9], 1.75);
    let (_, jb) = flow_c1(&m, &q, &u, -t, &FlowOptions::default()).unwrap();
    let (_, jf) = flow_c1(&m, &q, &[-u[0], -u[1]], t, &FlowOptions::default()).unwrap();
    let sign = |i: usize| if i < 3 { 1.0 } else { -1.0 };
    for i in 0..5 {
        for j in 0..5 {
            let r = Interval::from(jf[i][j]) * point(sign(i) * sign(j));
            assert!(
                meets(jb[i][j], r),
                "J[{i}][{j}] {} vs {}",
                show(jb[i][j]),
                show(r)
            );
            assert!(jb[i][j].wid() < 1e-9, "J[{i}][{j}] {}", show(jb[i][j]));
        }
    }
    // phi = phi0 + w t: D phi / D phi0 = 1, D phi / D w0 = t (here -1.75)
    assert!(
        jb[2][2].contains(1.0) && jb[2][4].contains(-t),
        "{}",
        show(jb[2][4])
    );
}

#[test]
fn the_issue_query_backward_overlaps_the_reversed_forward_one_on_the_command_line() {
    let back = json_stdout(&run_args(&[
        "flow", "--scene", "knife", "--q", "0,0,0", "--u", "0.8,0.8", "--t", "-1", "--json",
    ]));
    let fwd = json_stdout(&run_args(&[
        "flow",
        "--scene",
        "knife",
        "--q",
        "0,0,0",
        "--u",
        "-0.8,-0.8",
        "--t",
        "1",
        "--json",
    ]));
    for i in 0..3 {
        let (b, f) = (json_interval(&back["q"][i]), json_interval(&fwd["q"][i]));
        assert!(meets(b, f), "q[{i}]: {} vs {}", show(b), show(f));
    }
    // and the derivative
    let jb = json_stdout(&run_args(&[
        "flow",
        "--scene",
        "knife",
        "--q",
        "0,0,0",
        "--u",
        "0.8,0.8",
        "--t",
        "-1",
        "--json",
        "--jacobian",
    ]));
    assert!(json_interval(&jb["jacobian"][2][4]).contains(-1.0), "{jb}");
    // --times below 0
    let d = json_stdout(&run_args(&[
        "flow",
        "--scene",
        "knife",
        "--q",
        "0,0,0",
        "--u",
        "0.8,0.8",
        "--times",
        "-1,-0.5,1",
        "--json",
    ]));
    let text = d.to_string();
    let at = d["at"].as_array().expect("stops");
    assert_eq!(at.len(), 3, "{text}");
    assert_eq!(at[1]["t"], -0.5, "{text}");
    let first = &at[0];
    for i in 0..3 {
        let b = json_interval(&first["q"][i]);
        assert!(meets(b, json_interval(&back["q"][i])), "{text}");
    }
    // a time that is not finite keeps its message
    let o = run_args(&[
        "flow", "--scene", "knife", "--q", "0,0,0", "--u", "0.8,0.8", "--t", "inf",
    ]);
    assert_eq!(o.status.code(), Some(2));
}

// ---------------------------------------------------------------------------------------
// 3. `order` in batch

#[test]
fn a_batch_order_query_answers_what_the_command_prints() {
    let args = [
        "order",
        "--scene",
        "particle",
        "--scheme",
        "mla",
        "--q",
        "0.1,0.2,0",
        "--u",
        "0.5,0.25",
        "--h",
        "0.25",
        "--rungs",
        "3",
        "--json",
    ];
    let cmd = json_stdout(&run_args(&args));
    let line = r#"{"id": "o", "cmd": "order", "scene": "particle", "scheme": "mla", "q": [0.1, 0.2, 0], "u": [0.5, 0.25], "h": 0.25, "rungs": 3}"#;
    let a = &batch_answers(&format!("{line}\n"))[0];
    assert_eq!(a["id"], "o");
    assert_eq!(a["ok"], cmd, "batch {a}\ncommand {cmd}");
    // the ladder is what was asked for: 3 rungs from 0.25, the global one from 0.125
    assert_eq!(cmd["local"]["h"].as_array().unwrap().len(), 3);
    assert_eq!(cmd["global"]["ladder"]["h"][0], 0.125);
    // defaults: h = 0.125 and 5 rungs, as the command's
    let line = r#"{"id": 2, "cmd": "order", "scene": "particle", "scheme": "dla", "q": [0, 0, 0], "u": [0.5, 0.25]}"#;
    let a = &batch_answers(&format!("{line}\n"))[0];
    assert_eq!(a["ok"]["local"]["h"][0], 0.125, "{a}");
    assert_eq!(a["ok"]["local"]["h"].as_array().unwrap().len(), 5, "{a}");
    // bad keys are input errors naming the key
    for (bad, key) in [
        (r#""scheme": "dla", "h": 2"#, "`h`"),
        (r#""scheme": "dla", "rungs": 20"#, "`rungs`"),
        (r#""scheme": "rk4""#, "rk4"),
    ] {
        let line = format!(
            r#"{{"id": 3, "cmd": "order", "scene": "particle", "q": [0, 0, 0], "u": [0.5, 0.25], {bad}}}"#
        );
        let a = &batch_answers(&format!("{line}\n"))[0];
        assert_eq!(a["error"]["code"], 2, "{a}");
        assert!(a["error"]["message"].as_str().unwrap().contains(key), "{a}");
    }
}

// ---------------------------------------------------------------------------------------
// 4. Scene-file messages

fn toml_error(text: &str) -> String {
    match SceneFile::from_toml(text, "t") {
        Err(Error::Input(m)) => m.message,
        other => panic!("expected an input error, got {other:?}"),
    }
}

#[test]
fn a_required_key_after_the_parameters_header_is_named_as_such() {
    let m = toml_error(
        r#"
quasi_velocities = ["xd", "thetad"]
[parameters]
m = 2.0
coordinates = ["x", "y", "theta"]
constraints = [["-sin(theta)", "cos(theta)", 0]]
free = ["x", "theta"]
"#,
    );
    assert!(
        m.contains("`coordinates` appears after [parameters]") && m.contains("move it above"),
        "{m}"
    );
    // a non-number under `potential` after the header too
    let m = toml_error(
        r#"
coordinates = ["x", "y", "theta"]
constraints = [["-sin(theta)", "cos(theta)", 0]]
free = ["x", "theta"]
[parameters]
m = 2.0
potential = "m*x"
"#,
    );
    assert!(m.contains("`potential` appears after [parameters]"), "{m}");
    // a parameter that happens to be called `mass` stays a parameter
    let ok = SceneFile::from_toml(
        r#"
coordinates = ["x", "y", "theta"]
constraints = [["-sin(theta)", "cos(theta)", 0]]
free = ["x", "theta"]
potential = "mass*x"
[parameters]
mass = 2.0
"#,
        "t",
    );
    assert!(ok.is_ok(), "{ok:?}");
}

#[test]
fn quasi_velocities_named_in_another_order_than_free_are_refused_with_the_order() {
    let m = toml_error(
        r#"
coordinates = ["x", "y", "phi"]
quasi_velocities = ["xd", "phid"]
constraints = [["sin(phi)", "-cos(phi)", 0]]
free = ["phi", "x"]
"#,
    );
    assert!(
        m.contains("quasi_velocities[1] = `xd`")
            && m.contains("velocity of `phi`")
            && m.contains(r#"write quasi_velocities = ["phid", "xd"]"#),
        "{m}"
    );
    // in the order of `free` it is accepted, and other spellings are read too
    for names in [
        r#"["phid", "xd"]"#,
        r#"["phi_dot", "x_dot"]"#,
        r#"["w", "v"]"#,
    ] {
        let text = format!(
            r#"
coordinates = ["x", "y", "phi"]
quasi_velocities = {names}
constraints = [["sin(phi)", "-cos(phi)", 0]]
free = ["phi", "x"]
"#
        );
        assert!(SceneFile::from_toml(&text, "t").is_ok(), "{names}");
    }
    let m = toml_error(
        r#"
coordinates = ["x", "y", "phi"]
quasi_velocities = ["dx", "dphi"]
constraints = [["sin(phi)", "-cos(phi)", 0]]
free = ["phi", "x"]
"#,
    );
    assert!(m.contains(r#"["dphi", "dx"]"#), "{m}");
}
