//! Flows computed with double-double intervals (106 bits) against the closed forms of the
//! knife and the particle evaluated by mpmath at 100 digits (tests/data/flow_reference.py, an
//! independent derivation: closed forms, not a Taylor method): every reference lies inside the
//! answer, and the answer is narrow (a bound that f64 intervals could not meet), so that both a
//! wrong and a loose enclosure fail. Also the command line's `--precision` as a user meets it.

use crate::common::model;
use dalembert::exact::{discrete_lagrangian_in, retract_in, step_in};
use dalembert::precision::dd::{Dd, DdInterval};
use dalembert::{flow_at_in, FlowOptions};

const TABLE: &str = include_str!("../data/flow_reference.txt");
const EXACT: &str = include_str!("../data/exact_reference.txt");

fn nums(s: &str) -> Vec<f64> {
    s.split(',').map(|x| x.parse().unwrap()).collect()
}

/// An exact double from Python's hex form `[-]0x1.<13 hex digits>p<exp>` (or `0x0.0p+0`),
/// in the normal range.
fn hex_f64(s: &str) -> f64 {
    let (neg, s) = s.strip_prefix('-').map_or((false, s), |r| (true, r));
    let s = s.strip_prefix("0x").unwrap();
    let (mant, exp) = s.split_once('p').unwrap();
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let mut m = u64::from_str_radix(int, 16).unwrap() as f64;
    for (k, c) in frac.chars().enumerate() {
        let d = c.to_digit(16).unwrap() as f64;
        m += d * 2f64.powi(-4 * (k as i32 + 1));
    }
    let x = m * 2f64.powi(exp.parse::<i32>().unwrap());
    assert!(x == 0.0 || x.is_normal(), "{s}");
    if neg {
        -x
    } else {
        x
    }
}

/// The reference enclosure from its four doubles `lo_hi lo_lo up_hi up_lo` (exact sums).
fn reference(f: &[&str]) -> DdInterval {
    let d = |a: &str, b: &str| Dd::new(hex_f64(a), hex_f64(b));
    DdInterval::new(d(f[0], f[1]), d(f[2], f[3])).unwrap()
}

#[test]
fn double_double_flows_contain_the_closed_forms_and_are_narrow() {
    let mut checked = 0;
    for line in TABLE.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let (scene, q, u, t) = (f[0], nums(f[1]), nums(f[2]), f[3].parse::<f64>().unwrap());
        let m = model(scene, &[]);
        let e = flow_at_in::<DdInterval>(&m, &q, &u, &[t], &FlowOptions::default())
            .unwrap_or_else(|e| panic!("{line}: {e}"))
            .pop()
            .unwrap();
        let got: Vec<DdInterval> = e.q.iter().chain(&e.u).chain(&e.v).copied().collect();
        assert_eq!(got.len() * 4, f.len() - 4, "{line}");
        for (k, x) in got.iter().enumerate() {
            let r = reference(&f[4 + 4 * k..8 + 4 * k]);
            assert!(
                r.subset(*x),
                "{scene} t = {t}: component {k}: the exact value {r} is not inside {x}"
            );
            // long flows magnify the rounding: 1e-28 relative per unit of time at most
            let bound = 1e-28 * t.abs().max(1.0) * x.mag_up().max(1.0);
            assert!(
                x.wid_up() <= bound,
                "{scene} t = {t}: component {k} is {:e} wide (bound {bound:e})",
                x.wid_up()
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 11 * 8);
}

/// The retraction (u0, s), the exact step's q2 and the exact discrete Lagrangian of the
/// particle at 106 bits against its closed form (tests/data/exact_reference.py): containment of
/// the exact values and widths far below f64's.
#[test]
fn double_double_retractions_steps_and_lagrangians_contain_the_closed_forms() {
    let m = model("particle", &[]);
    let opts = FlowOptions::default();
    let mut checked = 0;
    for line in EXACT.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let (q0, q1, h) = (nums(f[0]), nums(f[1]), f[2].parse::<f64>().unwrap());
        let r = retract_in::<DdInterval>(&m, &q0, &q1, h, &opts).unwrap();
        let s = step_in::<DdInterval>(&m, &q0, &q1, h, &opts).unwrap();
        let (_, l) = discrete_lagrangian_in::<DdInterval>(&m, &q0, &q1, h, &opts).unwrap();
        let got: Vec<DdInterval> =
            r.u0.iter()
                .chain(&r.s)
                .chain(&s.q2)
                .copied()
                .chain([l])
                .collect();
        for (k, x) in got.iter().enumerate() {
            let want = reference(&f[3 + 4 * k..7 + 4 * k]);
            assert!(
                want.subset(*x),
                "{line}: quantity {k}: {want} is not inside {x}"
            );
            let bound = 1e-29 * x.mag_up().max(1.0) / h.min(1.0);
            assert!(
                x.wid_up() <= bound,
                "{line}: quantity {k} is {:e} wide",
                x.wid_up()
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 4 * 7);
}

/// The double-double answer and the f64 one both contain the exact state, so they meet; the
/// double-double one is narrower.
#[test]
fn double_double_and_f64_flows_agree_and_the_wider_bits_are_narrower() {
    let m = model("knife", &[]);
    let (q, u) = ([0.1, -0.2, 0.3], [0.9, -0.6]);
    let opts = FlowOptions::default();
    let dd = flow_at_in::<DdInterval>(&m, &q, &u, &[-3.0, 2.0, 40.0], &opts).unwrap();
    let f = dalembert::flow::flow_at(&m, &q, &u, &[-3.0, 2.0, 40.0], &opts).unwrap();
    for (a, b) in dd.iter().zip(&f) {
        for (x, y) in a.q.iter().chain(&a.u).zip(b.q.iter().chain(&b.u)) {
            let y = DdInterval::from_f64_pair(y.inf(), y.sup()).unwrap();
            assert!(!x.disjoint(y), "{x} and {y} are disjoint");
            assert!(
                x.wid_up() < y.wid_up() || y.wid_up() == 0.0,
                "{x} is not narrower than {y}"
            );
        }
    }
}

/// The ends of a `[lo, hi]` pair of decimal strings as a double-double interval.
fn decimal_pair(v: &serde_json::Value) -> DdInterval {
    let lo = DdInterval::from_decimal(v[0].as_str().expect("a string end")).unwrap();
    let hi = DdInterval::from_decimal(v[1].as_str().expect("a string end")).unwrap();
    lo.hull(hi)
}

/// `flow --precision 106 --json` as a user runs it: string ends, the precision used, the
/// closed form of the knife at T = 50 inside, about 1e-28 wide; the f64 answer (no flag) is
/// unchanged in form.
#[test]
fn the_command_line_answers_at_106_bits_with_decimal_ends() {
    let args = [
        "flow", "--scene", "knife", "--q", "0,0,0", "--u", "0.8,0.8", "--t", "50",
    ];
    let out = crate::common::run_args(&[&args[..], &["--precision", "106", "--json"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["precision"], 106);
    let line = TABLE
        .lines()
        .find(|l| l.starts_with("knife 0.0,0.0,0.0 0.8,0.8 50.0 "))
        .unwrap();
    let f: Vec<&str> = line.split_whitespace().collect();
    let got: Vec<&serde_json::Value> = ["q", "u", "v"]
        .iter()
        .flat_map(|k| v[k].as_array().unwrap())
        .collect();
    for (k, x) in got.iter().enumerate() {
        let x = decimal_pair(x);
        assert!(
            reference(&f[4 + 4 * k..8 + 4 * k]).subset(x),
            "component {k}: {x}"
        );
        assert!(
            x.wid_up() < 1e-27 * x.mag_up().max(1.0),
            "component {k}: {x}"
        );
    }
    let plain = crate::common::run_args(&[&args[..], &["--json"]].concat());
    let p: serde_json::Value = serde_json::from_slice(&plain.stdout).unwrap();
    assert!(p.get("precision").is_none() && p["q"][0][0].is_f64());
}

/// Retract, step and lagrangian at 106 bits through `batch`, with an f64 query beside them;
/// `precision` out of range, and on a query that does not read it (`integrate`; `check` reads
/// it since contract E28), is an input error.
#[test]
fn batch_reads_precision_where_it_applies_and_refuses_it_elsewhere() {
    let pair = r#""scene":"particle","q0":[0,0,0],"q1":[0.4,0.4,0],"h":0.5"#;
    let input = [
        format!(r#"{{"id":1,"cmd":"retract",{pair},"precision":106}}"#),
        format!(r#"{{"id":2,"cmd":"step",{pair},"precision":90}}"#),
        format!(r#"{{"id":3,"cmd":"lagrangian",{pair},"precision":106}}"#),
        format!(r#"{{"id":4,"cmd":"step",{pair},"precision":53}}"#),
        format!(r#"{{"id":5,"cmd":"step",{pair},"precision":52}}"#),
        format!(r#"{{"id":6,"cmd":"integrate",{pair},"scheme":"dla","steps":2,"precision":106}}"#),
        r#"{"id":7,"cmd":"check","scene":"particle","h":0.5,"q":[[0,0,0],[0.4,0.4,0]],"precision":106}"#
            .to_string(),
    ]
    .join("\n");
    let a = crate::common::batch_answers(&input);
    let line = EXACT.lines().next().unwrap();
    let f: Vec<&str> = line.split_whitespace().collect();
    // u0, s of the closed form (tests/data/exact_reference.py), the step's q2 and l
    let u0: Vec<DdInterval> = (0..2).map(|k| decimal_pair(&a[0]["ok"]["u0"][k])).collect();
    assert!(reference(&f[3..7]).subset(u0[0]) && reference(&f[7..11]).subset(u0[1]));
    assert!(reference(&f[11..15]).subset(decimal_pair(&a[0]["ok"]["defect"][0])));
    assert_eq!(a[1]["ok"]["precision"], 106);
    for k in 0..3 {
        let q2 = decimal_pair(&a[1]["ok"]["q2"][k]);
        assert!(
            reference(&f[15 + 4 * k..19 + 4 * k]).subset(q2),
            "q2[{k}] = {q2}"
        );
    }
    assert!(reference(&f[27..31]).subset(decimal_pair(&a[2]["ok"]["l"])));
    assert!(a[3]["ok"]["q2"][0][0].is_f64() && a[3]["ok"].get("precision").is_none());
    for k in [4, 5] {
        assert_eq!(a[k]["error"]["code"], 2, "{}", a[k]);
        assert!(a[k]["error"]["message"]
            .as_str()
            .unwrap()
            .contains("precision"));
    }
    assert_eq!(a[6]["ok"]["precision"], 106, "{}", a[6]);
}

/// A float implementation of the exact discrete step checked to its last bits: the particle's
/// exact step evaluated in f64 from its closed form (tests/data/exact_reference.py's formulas,
/// with `asinh` of the standard library), against the certified exact step at 106 bits. The
/// enclosure is far below one ulp wide, so each float component's distance from the exact value
/// is known in ulps to a hundredth of an ulp: within a few ulps where the formula is well
/// conditioned, tens where `k` divides by a small difference (y near -20: measured 46), and
/// thousands for a variant that computes `asinh y` with the textbook `ln(y + sqrt(y^2 + 1))`,
/// which loses bits for negative `y` (measured 6015). At 53 bits the same enclosures are an ulp
/// wide or more and could tell none of this.
#[test]
fn a_float_exact_step_is_measured_in_ulps_at_106_bits() {
    fn float_q2(q0: &[f64], q1: &[f64], h: f64, asinh: fn(f64) -> f64) -> [f64; 3] {
        let (x0, y0, z0) = (q0[0], q0[1], q0[2]);
        let (x1, y1, z1) = (q1[0], q1[1], q1[2]);
        let yd0 = (y1 - y0) / h;
        let (r0, r1) = ((1.0 + y0 * y0).sqrt(), (1.0 + y1 * y1).sqrt());
        let (a, b) = (asinh(y1) - asinh(y0), r1 - r0);
        let k = (x1 - x0 + y1 * (z1 - z0)) / (a + y1 * b);
        let y2 = y0 + 2.0 * h * yd0;
        let r2 = (1.0 + y2 * y2).sqrt();
        [x0 + k * (asinh(y2) - asinh(y0)), y2, z0 + k * (r2 - r0)]
    }
    // certified bounds on |x - exact| in ulps of x
    fn ulps(x: f64, e: DdInterval) -> (f64, f64) {
        let d = DdInterval::from_f64(x) - e;
        let ulp = f64::EPSILON * 2f64.powi(x.abs().log2().floor() as i32);
        (d.mig_down() / ulp, d.mag_up() / ulp)
    }
    let m = model("particle", &[]);
    let opts = FlowOptions::default();
    let pairs: [([f64; 3], [f64; 3], f64); 3] = [
        ([0.1, -0.3, 0.2], [0.35, -0.1, 0.18], 0.25),
        ([0.0, -20.0, 0.0], [0.03, -20.5, -0.6], 0.4),
        ([1.0, -40.0, -1.0], [1.01, -40.5, -1.4], 0.5),
    ];
    let (mut careful, mut textbook) = (Vec::new(), Vec::new());
    for (q0, q1, h) in pairs {
        let s = step_in::<DdInterval>(&m, &q0, &q1, h, &opts).unwrap();
        let good = float_q2(&q0, &q1, h, f64::asinh);
        let poor = float_q2(&q0, &q1, h, |y| (y + (y * y + 1.0).sqrt()).ln());
        for i in [0, 2] {
            let e = s.q2[i];
            for (x, out) in [(good[i], &mut careful), (poor[i], &mut textbook)] {
                let (lo, hi) = ulps(x, e);
                assert!(
                    hi - lo < 0.01,
                    "the distance is known to [{lo}, {hi}] ulps only"
                );
                out.push(hi);
            }
        }
    }
    let most = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(*x));
    // the well-conditioned pair: a few ulps; the others: within 64
    assert!(careful[..2].iter().all(|u| *u <= 8.0), "{careful:?}");
    assert!(most(&careful) <= 64.0, "{careful:?}");
    // the textbook asinh: thousands of ulps on the x of the pairs with y near -20
    assert!(textbook[2] >= 1000.0, "{textbook:?}");
    assert!(
        most(&textbook) > 50.0 * most(&careful),
        "{textbook:?} {careful:?}"
    );
}

/// The retraction at 106 bits of a sleigh pair whose f64 centre is far from the zero in the
/// shooting map's scale: its `u0` and defect lie at the double-double level (relative width at
/// most 1e-30; with the f64 centre and one Krawczyk test they were 7.6e-29 and 9.3e-29 wide,
/// spec (12.0.9)), and each contains the retraction at 256 bits (a high-precision solve by the
/// other route of spec (12.0.7): a centre refined at 256 bits, one Krawczyk test), both read
/// exactly from their outward decimals.
#[test]
fn a_double_double_retraction_is_at_its_rounding_level_and_holds_the_256_bit_one() {
    use dalembert::precision::mp::MpInterval;
    use dalembert::precision::wide::{self, WideInterval};
    use dalembert::OutwardDecimal;
    let m = model("sleigh", &[]);
    let opts = FlowOptions::default();
    let (q0, q1, h) = ([0.0, 0.0, 0.0], [0.05, 0.1, 0.02], 0.1);
    let exact = |x: &dyn OutwardDecimal| {
        let d = x.decimal();
        let lo = MpInterval::from_decimal(&d.0, 1024).unwrap();
        lo.hull(&MpInterval::from_decimal(&d.1, 1024).unwrap())
    };
    let dd = retract_in::<DdInterval>(&m, &q0, &q1, h, &opts).unwrap();
    let wide: Vec<MpInterval> = wide::with_bits(256, || {
        let r = retract_in::<WideInterval>(&m, &q0, &q1, h, &opts).unwrap();
        r.u0.iter().chain(&r.s).map(|x| exact(x)).collect()
    });
    for (k, (x, w)) in dd.u0.iter().chain(&dd.s).zip(&wide).enumerate() {
        assert!(
            w.subset(&exact(x)),
            "component {k}: the 256-bit {w} is not inside {x}"
        );
        assert!(
            x.wid_up() <= 1e-30 * x.mag_up(),
            "component {k}: {x} is {:e} wide",
            x.wid_up()
        );
    }
}
