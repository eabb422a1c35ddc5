//! Dense output (`flow_at`, `flow --times`), non-uniform steps (`check_trajectory_at`,
//! `check` without `--h`) and the defect tolerance (`--defect-tol`), issue 17 item 2
//! (spec (5.16), (8.4), (8.5); contract E11-E13).
//!
//! References: the knife's closed form (the textbook form of tests/closed_forms.rs,
//! derived by hand from the equations of motion s' = cos(phi)/2, phi' = w, x' = s cos(phi),
//! y' = s sin(phi)), evaluated in interval arithmetic; never the code under test.

use dalembert::flow::flow_at;
use dalembert::oracle::{check_trajectory, CheckOptions};
use dalembert::protocol::Session;
use dalembert::scalar::{point as pt, Scalar};
use dalembert::FlowOptions;
use dalembert::{flow, AnyScene, Error, Model};
use inari::Interval;
use serde_json::Value;
use std::process::Command;

fn knife() -> Model {
    Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap()
}

/// The knife's configuration at time t from (q, u), w = u[1] != 0 (textbook closed form):
/// phi = phi0 + w t, s = s0 + (sin phi - sin phi0)/(2w),
/// x = x0 + S (sin phi - sin phi0)/w + (sin^2 phi - sin^2 phi0)/(4 w^2), S = s0 - sin phi0/(2w),
/// y = y0 + S (cos phi0 - cos phi)/w + t/(4w) - (sin 2phi - sin 2phi0)/(8 w^2).
fn knife_closed(q: [f64; 3], u: [f64; 2], t: f64) -> [Interval; 3] {
    let (x0, y0, p0) = (pt(q[0]), pt(q[1]), pt(q[2]));
    let (s0, w, tt) = (pt(u[0]), pt(u[1]), pt(t));
    let phi = p0 + w * tt;
    let (sp0, cp0, sp, cp) = (p0.sin(), p0.cos(), phi.sin(), phi.cos());
    let two = pt(2.0);
    let big_s = s0 - sp0 / (two * w);
    let x = x0 + big_s * (sp - sp0) / w + (sp.sqr() - sp0.sqr()) / (pt(4.0) * w.sqr());
    let y = y0 + big_s * (cp0 - cp) / w + tt / (pt(4.0) * w)
        - ((two * phi).sin() - (two * p0).sin()) / (pt(8.0) * w.sqr());
    [x, y, phi]
}

const Q0: [f64; 3] = [0.1, -0.2, 0.3];
const U0: [f64; 2] = [0.7, 1.3];

fn float_point(t: f64) -> Vec<f64> {
    let c = knife_closed(Q0, U0, t);
    assert!(c.iter().all(|x| x.wid() < 1e-14), "reference too wide");
    c.iter().map(|x| x.mid()).collect()
}

fn width(b: &[dalembert::Interval]) -> f64 {
    b.iter().fold(0.0f64, |m, x| m.max(x.wid()))
}

// ---------------------------------------------------------------------------------------
// 1. Dense output.

#[test]
fn dense_flow_contains_the_closed_form_and_is_as_narrow_as_single_flows() {
    let model = knife();
    let times = [0.25, 0.5, 1.0, 1.5, 2.0, 3.0];
    let o = FlowOptions::default();
    let at = flow_at(&model, &Q0, &U0, &times, &o).unwrap();
    assert_eq!(at.len(), times.len());
    let mut steps = 0;
    for (t, e) in times.iter().zip(&at) {
        let r = knife_closed(Q0, U0, *t);
        for (i, (a, b)) in e.q.iter().zip(&r).enumerate() {
            // both contain the true q_i(t): they must meet
            assert!(
                !a.intersection(*b).is_empty(),
                "t = {t}: q_{i} {a:?} misses the closed form {b:?}"
            );
        }
        let single = flow(&model, &Q0, &U0, *t, &o).unwrap();
        let (wd, ws) = (width(&e.q), width(&single.q));
        println!("t = {t}: dense width {wd:.3e}, single flow {ws:.3e}");
        assert!(
            wd <= 1.25 * ws + 1e-15,
            "t = {t}: dense {wd:e} vs single {ws:e}"
        );
        assert!(e.stats.steps >= steps, "cumulative steps");
        steps = e.stats.steps;
    }
    // the one-time case is `flow` itself, bit for bit
    let one = flow_at(&model, &Q0, &U0, &[1.5], &o).unwrap();
    let single = flow(&model, &Q0, &U0, 1.5, &o).unwrap();
    assert_eq!(format!("{:?}", one[0].q), format!("{:?}", single.q));
    assert_eq!(one[0].stats, single.stats);
}

#[test]
fn dense_flow_refuses_bad_times() {
    let model = knife();
    let o = FlowOptions::default();
    for times in [
        &[][..],
        &[0.5, 0.25][..],
        &[0.5, 0.5][..],
        &[0.5, f64::NAN][..],
        &[f64::NEG_INFINITY, 1.0][..],
        &[-0.5, -1.0][..],
        &[0.5, f64::INFINITY][..],
    ] {
        assert!(
            matches!(flow_at(&model, &Q0, &U0, times, &o), Err(Error::Input(_))),
            "{times:?} accepted"
        );
    }
}

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn flow_times_on_the_command_line_and_in_batch() {
    let base = [
        "flow",
        "--scene",
        "knife",
        "--q",
        "0.1,-0.2,0.3",
        "--u",
        "0.7,1.3",
    ];
    let (code, out, err) = run(&[&base[..], &["--times", "0.5,1,2", "--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let at = v["at"].as_array().unwrap();
    assert_eq!(at.len(), 3);
    assert_eq!(at[2]["t"], 2.0);
    assert!(v["stats"]["steps"].as_u64().unwrap() > 0);
    let r = knife_closed(Q0, U0, 2.0);
    for i in 0..3 {
        let lo = at[2]["q"][i][0].as_f64().unwrap();
        let hi = at[2]["q"][i][1].as_f64().unwrap();
        assert!(lo <= r[i].sup() && r[i].inf() <= hi);
    }
    // the readable form names the stops
    let (code, out, _) = run(&[&base[..], &["--times", "0.5,1"]].concat());
    assert_eq!(code, 0);
    assert!(out.contains("at"), "{out}");
    // exactly one of --t and --times; sorted times
    assert_eq!(
        run(&[&base[..], &["--t", "1", "--times", "0.5,1"]].concat()).0,
        2
    );
    assert_eq!(run(&base).0, 2);
    assert_eq!(run(&[&base[..], &["--times", "1,0.5"]].concat()).0, 2);
    // batch: `times` instead of `t`, the same answer as the command line
    let mut s = Session::default();
    let line = r#"{"id": 1, "cmd": "flow", "scene": "knife", "q": [0.1,-0.2,0.3], "u": [0.7,1.3], "times": [0.5, 1, 2]}"#;
    let a: Value = serde_json::from_str(&s.batch_line(line).unwrap()).unwrap();
    assert_eq!(a["ok"]["at"], v["at"]);
    let both = r#"{"cmd": "flow", "scene": "knife", "q": [0.1,-0.2,0.3], "u": [0.7,1.3], "t": 1, "times": [0.5, 1]}"#;
    let a: Value = serde_json::from_str(&s.batch_line(both).unwrap()).unwrap();
    assert_eq!(a["error"]["code"], 2);
}

// ---------------------------------------------------------------------------------------
// 2. Non-uniform steps.

fn pairs_opts() -> CheckOptions {
    CheckOptions::default()
}

#[test]
fn uniform_steps_checked_as_times_give_the_same_verdict() {
    let model = knife();
    // dyadic h: the times k h and their differences are exact, so the spans are h itself
    let h = 0.125;
    let q: Vec<Vec<f64>> = (0..12).map(|k| float_point(k as f64 * h)).collect();
    let times: Vec<f64> = (0..12).map(|k| k as f64 * h).collect();
    let u = check_trajectory(&model, h, &q, &pairs_opts()).unwrap();
    let t = check_trajectory(&model, &times, &q, &pairs_opts()).unwrap();
    assert_eq!(format!("{:?}", u.distance), format!("{:?}", t.distance));
    assert_eq!(format!("{:?}", u.defect), format!("{:?}", t.defect));
    assert_eq!(format!("{:?}", u.max_defect), format!("{:?}", t.max_defect));
    // h = 0.1: the float times k h are not equally spaced; the verdicts still agree
    let h = 0.1;
    let q: Vec<Vec<f64>> = (0..12).map(|k| float_point(k as f64 * h)).collect();
    let times: Vec<f64> = (0..12).map(|k| k as f64 * h).collect();
    let u = check_trajectory(&model, h, &q, &pairs_opts()).unwrap();
    let t = check_trajectory(&model, &times, &q, &pairs_opts()).unwrap();
    for (a, b) in u.distance.iter().zip(&t.distance) {
        assert!((a.sup() - b.sup()).abs() < 1e-13, "{a:?} vs {b:?}");
    }
    assert!(u.max_distance.sup() < 1e-12 && t.max_distance.sup() < 1e-12);
}

/// Times with steps h, 2h, h, 2h, ..
fn uneven_times(h: f64, n: usize) -> Vec<f64> {
    let mut t = vec![0.0];
    for k in 1..n {
        let step = if k % 2 == 1 { h } else { 2.0 * h };
        t.push(t[k - 1] + step);
    }
    t
}

#[test]
fn non_uniform_steps_distances_contain_the_true_ones_and_see_a_perturbation() {
    let model = knife();
    let times = uneven_times(0.125, 13);
    let q: Vec<Vec<f64>> = times.iter().map(|t| float_point(*t)).collect();
    let v = check_trajectory(&model, &times, &q, &pairs_opts()).unwrap();
    // The exact discrete flow through (q_0, q_1) is the motion through q_0 whose position at
    // t_1 is q_1 + N(q_1) s: it differs from the closed form's motion by the rounding of
    // q_1 (< 1e-16), amplified over 2 time units by the retraction's conditioning; 1e-13
    // bounds that generously. So the true distance |q_k - q^e_k| lies within 1e-13 of the
    // closed form's |q_k - q(t_k)| (an enclosure by interval arithmetic).
    for (k, t) in times.iter().enumerate() {
        let r = knife_closed(Q0, U0, *t);
        let reference = q[k]
            .iter()
            .zip(&r)
            .map(|(a, b)| (pt(*a) - *b).abs())
            .fold(pt(0.0), |m, d| m.max(d));
        let d = v.distance[k];
        assert!(
            d.inf() <= reference.sup() + 1e-13 && reference.inf() <= d.sup() + 1e-13,
            "k = {k}: certified {d:?}, closed form {reference:?}"
        );
    }
    assert!(v.max_distance.sup() < 1e-12, "{:?}", v.max_distance);
    // a perturbation of 1e-7 in row 7 shows there, and only there
    let mut p = q.clone();
    p[7][0] += 1e-7;
    let w = check_trajectory(&model, &times, &p, &pairs_opts()).unwrap();
    assert!(w.distance[7].inf() > 0.99e-7 && w.distance[7].sup() < 1.01e-7);
    assert!(w.distance[6].sup() < 1e-12 && w.distance[8].sup() < 1e-12);
    // times out of order, or fewer than rows
    let mut bad = times.clone();
    bad.swap(3, 4);
    assert!(matches!(
        check_trajectory(&model, &bad, &q, &pairs_opts()),
        Err(Error::Input(_))
    ));
    assert!(matches!(
        check_trajectory(&model, &times[1..], &q, &pairs_opts()),
        Err(Error::Input(_))
    ));
}

fn temp(name: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("dalembert-dense-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

fn csv(times: &[f64], q: &[Vec<f64>]) -> String {
    let mut s = String::from("t,q0,q1,q2\n");
    for (t, r) in times.iter().zip(q) {
        s += &format!("{t:e},{:e},{:e},{:e}\n", r[0], r[1], r[2]);
    }
    s
}

#[test]
fn check_without_h_reads_the_times_from_csv_json_and_batch() {
    let times = uneven_times(0.125, 9);
    let q: Vec<Vec<f64>> = times.iter().map(|t| float_point(*t)).collect();
    let file = temp("uneven.csv", &csv(&times, &q));
    let (code, out, err) = run(&["check", "--scene", "knife", "--trajectory", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let cli: Value = serde_json::from_str(&out).unwrap();
    assert!(cli["max_distance"][1].as_f64().unwrap() < 1e-12);
    // with --h the t column must be k h: these times are not
    let (code, _, err) = run(&[
        "check",
        "--scene",
        "knife",
        "--h",
        "0.125",
        "--trajectory",
        &file,
    ]);
    assert_eq!(code, 2, "{err}");
    // a JSON file with "t"
    let j = serde_json::json!({"t": times, "q": q}).to_string();
    let jf = temp("uneven.json", &j);
    let (code, out, err) = run(&["check", "--scene", "knife", "--trajectory", &jf, "--json"]);
    assert_eq!(code, 0, "{err}");
    let from_json: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(from_json, cli);
    // no times and no --h
    let plain = temp("plain.json", &serde_json::json!({"q": q}).to_string());
    assert_eq!(
        run(&["check", "--scene", "knife", "--trajectory", &plain]).0,
        2
    );
    // batch: "t" instead of "h", the same answer
    let line = serde_json::json!({"cmd": "check", "scene": "knife", "t": times, "q": q});
    let a: Value =
        serde_json::from_str(&Session::default().batch_line(&line.to_string()).unwrap()).unwrap();
    assert_eq!(a["ok"], cli);
    let both =
        serde_json::json!({"cmd": "check", "scene": "knife", "h": 0.125, "t": times, "q": q});
    let a: Value =
        serde_json::from_str(&Session::default().batch_line(&both.to_string()).unwrap()).unwrap();
    assert_eq!(a["error"]["code"], 2);
}

// ---------------------------------------------------------------------------------------
// 3. The defect tolerance.

#[test]
fn a_small_perturbation_shows_in_the_defect_before_the_distance() {
    let h = 0.125;
    let times: Vec<f64> = (0..17).map(|k| k as f64 * h).collect();
    let q: Vec<Vec<f64>> = times.iter().map(|t| float_point(*t)).collect();
    let mut p = q.clone();
    p[8][0] += 1e-6;
    let clean = temp("clean.csv", &csv(&times, &q));
    let bent = temp("bent.csv", &csv(&times, &p));
    let check = |file: &str, extra: &[&str]| {
        let base = [
            "check",
            "--scene",
            "knife",
            "--h",
            "0.125",
            "--trajectory",
            file,
            "--json",
        ];
        let (code, out, err) = run(&[&base[..], extra].concat());
        let v: Value = serde_json::from_str(&out).unwrap_or(Value::Null);
        (code, v, err)
    };
    // the distance sees 1e-6 and passes a tolerance of 1e-5 ...
    let (code, v, err) = check(&bent, &["--tol", "1e-5"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(v["passed"], true);
    let md = v["max_defect"].as_array().unwrap();
    assert!(md[0].as_f64().unwrap() > 1e-9, "{md:?}");
    // ... while the defect is proved beyond 1e-9: exit 1, both tolerances together too
    let (code, v, _) = check(&bent, &["--defect-tol", "1e-9"]);
    assert_eq!(code, 1);
    assert_eq!(v["passed"], false);
    assert_eq!(
        check(&bent, &["--tol", "1e-5", "--defect-tol", "1e-9"]).0,
        1
    );
    // the unperturbed trajectory: its defects are tiny and pass 1e-9
    let (code, v, err) = check(&clean, &["--tol", "1e-12", "--defect-tol", "1e-9"]);
    assert_eq!(code, 0, "{err}");
    let md = v["max_defect"].as_array().unwrap();
    let (lo, hi) = (md[0].as_f64().unwrap(), md[1].as_f64().unwrap());
    println!("unperturbed max defect in [{lo:e}, {hi:e}]");
    assert!(lo >= 0.0 && hi < 1e-13, "[{lo:e}, {hi:e}]");
    // undecided: a tolerance inside the enclosure of the perturbed defect is exit 3
    let (code, v, _) = check(&bent, &[]);
    let md = v["max_defect"].as_array().unwrap();
    let mid = 0.5 * (md[0].as_f64().unwrap() + md[1].as_f64().unwrap());
    if md[0].as_f64().unwrap() < mid && mid < md[1].as_f64().unwrap() {
        assert_eq!(check(&bent, &["--defect-tol", &format!("{mid:e}")]).0, 3);
    }
    assert_eq!(code, 0);
    // a defect tolerance needs the pairs
    assert_eq!(check(&clean, &["--no-pairs", "--defect-tol", "1e-9"]).0, 2);
    // text form
    let (code, out, _) = run(&[
        "check",
        "--scene",
        "knife",
        "--h",
        "0.125",
        "--trajectory",
        &bent,
        "--defect-tol",
        "1e-9",
    ]);
    assert_eq!(code, 1);
    assert!(out.contains("max defect") && out.contains("FAIL"), "{out}");
    // batch: "defect_tol"
    let line = serde_json::json!({"cmd": "check", "scene": "knife", "h": h, "q": p, "tol": 1e-5, "defect_tol": 1e-9});
    let a: Value =
        serde_json::from_str(&Session::default().batch_line(&line.to_string()).unwrap()).unwrap();
    assert_eq!(a["ok"]["passed"], false);
    let line = serde_json::json!({"cmd": "check", "scene": "knife", "h": h, "q": p, "pairs": false, "defect_tol": 1e-9});
    let a: Value =
        serde_json::from_str(&Session::default().batch_line(&line.to_string()).unwrap()).unwrap();
    assert_eq!(a["error"]["code"], 2);
}

#[test]
fn stepper_verdict_passes_with_a_defect_tolerance() {
    use dalembert::oracle::Tolerances;
    let model = knife();
    let h = 0.125;
    let q: Vec<Vec<f64>> = (0..9).map(|k| float_point(k as f64 * h)).collect();
    let v = check_trajectory(&model, h, &q, &pairs_opts()).unwrap();
    let t = Tolerances::default().with_tol(1e-12).with_defect_tol(1e-9);
    assert!(t.passes(v.max_distance, v.max_defect).unwrap());
    let mut p = q.clone();
    p[4][0] += 1e-6;
    let v = check_trajectory(&model, h, &p, &pairs_opts()).unwrap();
    assert!(!t.passes(v.max_distance, v.max_defect).unwrap());
    let loose = Tolerances::default().with_tol(1e-5);
    assert!(loose.passes(v.max_distance, v.max_defect).unwrap());
}

#[test]
fn dense_flow_step_limit_is_the_whole_integrations() {
    let model = knife();
    let o = FlowOptions::default().with_max_taylor_steps(3);
    // no leg needs more than one step (the legs of length 1 at order 28, spec (5.8) (e)),
    // the four together need 4
    match flow_at(&model, &Q0, &U0, &[0.5, 1.0, 2.0, 3.0], &o) {
        Err(Error::Uncertified(r)) => {
            assert!(r.message.contains("more than 3 steps"), "{}", r.message);
            assert!(r.message.contains("t = 3"), "{}", r.message);
            assert!(r.reached.is_some_and(|t| (0.0..3.0).contains(&t)));
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
}
