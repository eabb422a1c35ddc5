//! `flow --jacobian` (and the batch key `jacobian`): the derivative of the flow,
//! D(q, u)(T) / D(q, u)(0), as (n+m) x (n+m) intervals. Reference: the particle's y and yd
//! (y = y0 + u2 t, yd = u2, paper Example 2.1) give exact rows of the derivative.

use std::process::Command;

/// The particle's flow from `q`, `u` to `t`, with `extra`.
fn particle_flow(q: &str, u: &str, t: &str, extra: &[&str]) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_dalembert"))
        .args(["flow", "--scene", "particle", "--q", q, "--u", u, "--t", t])
        .args(["--json"])
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The particle's flow from q = (0.1, 0.2, 0.3), u = (0.8, -0.4) to t = 7, with `extra`.
fn flow_jacobian(extra: &[&str]) -> serde_json::Value {
    particle_flow("0.1,0.2,0.3", "0.8,-0.4", "7", extra)
}

/// The particle's derivative at time `t` is 5 x 5 and contains its exact rows: that of
/// y = y0 + u2 t, d/d(x, y, z, u1, u2) = (0, 1, 0, 0, t), and that of the constant u2,
/// (0, 0, 0, 0, 1) (paper Example 2.1).
fn has_exact_rows(j: &[serde_json::Value], t: f64) {
    assert_eq!(j.len(), 5);
    assert!(j.iter().all(|r| r.as_array().unwrap().len() == 5));
    let (want_y, want_u2) = ([0.0, 1.0, 0.0, 0.0, t], [0.0, 0.0, 0.0, 0.0, 1.0]);
    for c in 0..5 {
        assert!(
            contains(&j[1][c], want_y[c]),
            "y row, column {c}: {}",
            j[1][c]
        );
        assert!(
            contains(&j[4][c], want_u2[c]),
            "u2 row, column {c}: {}",
            j[4][c]
        );
    }
}

fn contains(iv: &serde_json::Value, x: f64) -> bool {
    iv[0].as_f64().unwrap() <= x && x <= iv[1].as_f64().unwrap()
}

#[test]
fn the_particle_jacobian_has_its_exact_rows() {
    let v = flow_jacobian(&["--jacobian"]);
    let j = v["jacobian"].as_array().unwrap();
    has_exact_rows(j, 7.0);
    // and it is tight enough to serve a Newton solve
    for row in j {
        for e in row.as_array().unwrap() {
            assert!(
                e[1].as_f64().unwrap() - e[0].as_f64().unwrap() < 1e-9,
                "{e}"
            );
        }
    }
    // the field (x' = u1, y' = u2, z' = y u1, u1' = -y u1 u2 / (1 + y^2), u2' = 0) does not
    // read x or z: the columns of x and z are (1, 0, 0, 0, 0) and (0, 0, 1, 0, 0), and are
    // points (spec (5.6'))
    for (r, row) in j.iter().enumerate() {
        for c in [0, 2] {
            let e = if r == c { 1.0 } else { 0.0 };
            assert_eq!(
                row[c][0].as_f64(),
                Some(e),
                "row {r}, column {c}: {}",
                row[c]
            );
            assert_eq!(
                row[c][1].as_f64(),
                Some(e),
                "row {r}, column {c}: {}",
                row[c]
            );
        }
    }
    // without the flag, no jacobian key; the state is the same
    let w = flow_jacobian(&[]);
    assert!(w.get("jacobian").is_none());
    for i in 0..3 {
        let (a, b) = (&v["q"][i], &w["q"][i]);
        assert!(a[0].as_f64() <= b[1].as_f64() && b[0].as_f64() <= a[1].as_f64());
    }
}

/// Over a long flow the derivative stays narrow: each step's variational remainder is held
/// below 1 ulp of the step Jacobian (spec (5.6)); with 16 ulps the particle's derivative at
/// T = 600 was 1.35e-8 wide (CAPD's C1Rect2Set: 8.8e-10). It still has its exact rows.
#[test]
fn the_long_particle_derivative_stays_narrow() {
    let v = particle_flow("0,0,0", "0.8,0.8", "600", &["--jacobian"]);
    let j = v["jacobian"].as_array().unwrap();
    has_exact_rows(j, 600.0);
    let widest = j
        .iter()
        .flat_map(|r| r.as_array().unwrap())
        .map(|e| e[1].as_f64().unwrap() - e[0].as_f64().unwrap())
        .fold(0.0, f64::max);
    assert!(widest < 4e-9, "widest entry {widest:e}");
}

/// The particle's derivative in closed form, by hand from its flow (paper Example 2.1):
/// with `s(y) = sqrt(1 + y^2)`, `y = y0 + u2 t`, `K = u1 s(y0)`, `A = asinh y - asinh y0`,
/// `S = s(y) - s(y0)`: `x = x0 + K A / u2`, `z = z0 + K S / u2`, `u1(t) = K / s(y)`, so
/// (columns x0, y0, z0, u1, u2; `K' = dK/dy0 = u1 y0 / s(y0)`)
/// - x row: `(1, (K' A + K (1/s - 1/s0)) / u2, 0, s0 A / u2, K (u2 t / s - A) / u2^2)`,
/// - z row: `(0, (K' S + K (y/s - y0/s0)) / u2, 1, s0 S / u2, K (u2 t y / s - S) / u2^2)`,
/// - u1 row: `(0, K' / s - K y / s^3, 0, s0 / s, -K y t / s^3)`,
///
/// and the y and u2 rows of [`has_exact_rows`]. In outward-rounded intervals (inari and the
/// crate's interval `asinh`, none of the flow's code), for `u2 != 0`.
fn particle_jacobian_closed_form(q: [f64; 3], u: [f64; 2], t: f64) -> Vec<Vec<inari::Interval>> {
    use dalembert::elementary::asinh;
    use inari::{const_interval, Interval};
    let p = |x: f64| Interval::try_from((x, x)).unwrap();
    let (one, zero) = (const_interval!(1.0, 1.0), const_interval!(0.0, 0.0));
    let (y0, u1, u2, tt) = (p(q[1]), p(u[0]), p(u[1]), p(t));
    let y = y0 + u2 * tt;
    let (s0, s) = ((one + y0.sqr()).sqrt(), (one + y.sqr()).sqrt());
    let k = u1 * s0;
    let dk = u1 * y0 / s0;
    let a = asinh(y) - asinh(y0);
    let big_s = s - s0;
    let s3 = s * s.sqr();
    vec![
        vec![
            one,
            (dk * a + k * (one / s - one / s0)) / u2,
            zero,
            s0 * a / u2,
            k * (u2 * tt / s - a) / u2.sqr(),
        ],
        vec![zero, one, zero, zero, tt],
        vec![
            zero,
            (dk * big_s + k * (y / s - y0 / s0)) / u2,
            one,
            s0 * big_s / u2,
            k * (u2 * tt * y / s - big_s) / u2.sqr(),
        ],
        vec![zero, dk / s - k * y / s3, zero, s0 / s, -(k * y * tt / s3)],
        vec![zero, zero, zero, zero, one],
    ]
}

/// Every entry of the particle's derivative at T = 10, 50 and 600 from (0, 0, 0),
/// (0.8, 0.8) and at T = 7 from (0.1, 0.2, 0.3), (0.8, -0.4) meets the closed form (both
/// contain the exact value), and at T = 10, 50, 600 the widest entry is at most CAPD's
/// C1Rect2Set's (1.36e-12, 2.47e-11, 8.81e-10, issue 48; spec (5.6)).
#[test]
fn the_particle_jacobian_meets_its_closed_form() {
    let cases: [([f64; 3], [f64; 2], f64, f64); 4] = [
        ([0.0, 0.0, 0.0], [0.8, 0.8], 10.0, 1.36e-12),
        ([0.0, 0.0, 0.0], [0.8, 0.8], 50.0, 2.47e-11),
        ([0.0, 0.0, 0.0], [0.8, 0.8], 600.0, 8.81e-10),
        ([0.1, 0.2, 0.3], [0.8, -0.4], 7.0, 1e-9),
    ];
    for (q, u, t, most) in cases {
        let show = |v: &[f64]| {
            v.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(",")
        };
        let v = particle_flow(&show(&q), &show(&u), &t.to_string(), &["--jacobian"]);
        let j = v["jacobian"].as_array().unwrap();
        let exact = particle_jacobian_closed_form(q, u, t);
        let mut widest = 0.0f64;
        for (r, row) in j.iter().enumerate() {
            for (c, e) in row.as_array().unwrap().iter().enumerate() {
                let (lo, hi) = (e[0].as_f64().unwrap(), e[1].as_f64().unwrap());
                let x = exact[r][c];
                assert!(
                    lo <= x.sup() && x.inf() <= hi,
                    "T = {t}, entry ({r}, {c}): [{lo}, {hi}] misses the closed form {x:?}"
                );
                widest = widest.max(hi - lo);
            }
        }
        assert!(
            widest <= most,
            "T = {t}: widest entry {widest:e} > {most:e}"
        );
    }
}
