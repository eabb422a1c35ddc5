//! The paper's figures (section 5 examples), reproduced from this crate's own runs, and a
//! work-precision diagram ([spec/09-report.md](crate::spec::report), (9.1)-(9.4)).

use super::orders::{self, Orders, SCHEMES};
use super::{max_width, points, Figure, Panel, Progress, Series, Style, Table};
use crate::exact;
use crate::interval::unwrap;
use crate::oracle::{distance, energy};
use crate::precision::dd::DdInterval;
use crate::precision::wide::{self, WideInterval};
use crate::scalar::point;
use crate::scene::SceneFile;
use crate::schemes::{NewtonOptions, Scheme, SchemeKind, Trajectory};
use crate::testing::Ladder;
use crate::{
    flow, flow_at_in, work_done, AnyScene, Basis, Error, FlowOptions, Interval, Ival, Model,
};
use std::time::Instant;

/// Sizes of the runs. [`Settings::paper`] is the paper's; [`Settings::quick`] a small
/// setting that runs in a few seconds (for tests).
#[derive(Clone, Debug)]
pub struct Settings {
    /// Steps of the particle runs (paper: 1200).
    pub particle_steps: usize,
    /// Steps of the knife runs (paper: 600).
    pub knife_steps: usize,
    /// The M_h^{e,nh} figure ([spec (9.3)](crate::spec::report)): the abscissae `x1`.
    pub space_x: Vec<f64>,
    /// The M_h^{e,nh} figure: the values of `y1`, one slice each.
    pub space_y: Vec<f64>,
    /// Work-precision ([spec (9.4)](crate::spec::report)): the final time `T`.
    pub wp_time: f64,
    /// Work-precision: the schemes' step sizes.
    pub wp_scheme_h: Vec<f64>,
    /// Work-precision: the Taylor orders of the certified flow.
    pub wp_orders: Vec<usize>,
    /// Work-precision: the certified flow's fixed steps ([spec eq. (5.13)](crate::spec::enclosure)).
    pub wp_flow_h: Vec<f64>,
    /// Work-precision: each time is the shortest of runs repeated for at least this many
    /// seconds (and at least three times when `> 0`).
    pub wp_min_seconds: f64,
    /// Work-precision, second panel: the horizons `T` at which the two bases of (5.10) are
    /// compared on the knife (automatic steps).
    pub wp_set_times: Vec<f64>,
    /// Work-precision in bits ([spec (9.4')](crate::spec::report)): the precisions of the
    /// certified flows (53: f64 intervals; 54..=106: double-double; 107..=1024: that many bits).
    pub wp_bits: Vec<u32>,
    /// Work-precision in bits: the final time of the knife from `q = 0`, `u = (0.8, 0.8)`.
    pub wp_bits_knife_time: f64,
    /// Work-precision in bits: the final time of the trailer scene file from `q = 0`,
    /// `u = (1, 0.3)`.
    pub wp_bits_trailer_time: f64,
    /// Orders ([spec (9.6)](crate::spec::report)): the step sizes of the local ladder.
    pub orders_local_h: Vec<f64>,
    /// Orders: the step sizes of the global ladder over `[0, 1]`.
    pub orders_global_h: Vec<f64>,
    /// Orders: how many of [`super::orders::starts`] are used (`usize::MAX`: all of them,
    /// the README table's).
    pub orders_starts: usize,
}

impl Settings {
    /// The paper's settings ([spec (9.1)-(9.6)](crate::spec::report)).
    pub fn paper() -> Self {
        Settings {
            particle_steps: 1200,
            knife_steps: 600,
            space_x: (0..=20).map(|i| 0.05 * i as f64).collect(),
            space_y: vec![-2.0, -1.0, -0.5, 0.5, 1.0, 2.0],
            wp_time: 8.0,
            wp_scheme_h: (1..=9).map(|i| 0.5f64.powi(i)).collect(),
            wp_orders: vec![6, 10, 15, 20, 30],
            wp_flow_h: (2..=7).map(|i| 0.5f64.powi(i)).collect(),
            wp_min_seconds: 0.05,
            wp_set_times: vec![8.0, 25.0, 50.0, 100.0, 200.0, 400.0, 600.0],
            wp_bits: vec![53, 106, 160, 256],
            wp_bits_knife_time: 50.0,
            wp_bits_trailer_time: 2.0,
            orders_local_h: orders::LOCAL_H.to_vec(),
            orders_global_h: orders::GLOBAL_H.to_vec(),
            orders_starts: usize::MAX,
        }
    }
    /// A small setting that runs in a few seconds (`figures --quick`, tests).
    pub fn quick() -> Self {
        Settings {
            particle_steps: 30,
            knife_steps: 20,
            space_x: vec![0.0, 0.5, 1.0],
            space_y: vec![-1.0, 1.0],
            wp_time: 1.0,
            wp_scheme_h: vec![0.5, 0.25],
            wp_orders: vec![10, 20],
            wp_flow_h: vec![0.5, 0.25],
            wp_min_seconds: 0.0,
            wp_set_times: vec![1.0, 4.0],
            wp_bits: vec![53, 106, 160, 256],
            wp_bits_knife_time: 10.0,
            wp_bits_trailer_time: 0.25,
            orders_local_h: orders::LOCAL_H[..3].to_vec(),
            orders_global_h: vec![0.25, 0.125],
            orders_starts: usize::MAX,
        }
    }
}

/// The paper's time step.
const H: f64 = 0.5;

fn model(name: &str, params: &[(String, f64)]) -> Result<Model, Error> {
    Model::new(&AnyScene::new(name, &crate::protocol::borrowed(params))?)
}

fn run_scheme(
    model: &Model,
    kind: SchemeKind,
    q0: &[f64],
    q1: &[f64],
    h: f64,
    n: usize,
) -> Result<Trajectory, Error> {
    Ok(Scheme::new(model, kind).integrate(q0, q1, h, n, &NewtonOptions::default())?)
}

/// An upper bound of `|e - E|` over the interval `E`.
fn above(e: f64, exact: Interval) -> f64 {
    (point(e) - inari::Interval::from(exact)).abs().sup()
}

/// Energy panels of DLA and MLA from the same `(q0, q1)` against the exact energy (9.1).
fn energy_figure(
    name: &str,
    title: &str,
    dla: &Trajectory,
    mla: &Trajectory,
    exact_energy: Interval,
) -> Figure {
    let n = dla.energy.len();
    let k = |i: usize| i as f64;
    let along = |e: &[f64]| e.iter().enumerate().map(|(i, x)| (k(i), *x)).collect();
    let error = |e: &[f64]| {
        e.iter()
            .enumerate()
            .map(|(i, x)| (k(i), above(*x, exact_energy)))
            .collect()
    };
    let mid = exact_energy.mid();
    let mut table = Table::new(
        "",
        &[
            "k",
            "energy_dla",
            "energy_mla",
            "exact_energy_lo",
            "exact_energy_hi",
        ],
    );
    for i in 0..n {
        table.rows.push(vec![
            k(i),
            dla.energy[i],
            mla.energy[i],
            exact_energy.inf(),
            exact_energy.sup(),
        ]);
    }
    Figure {
        name: name.to_string(),
        caption: format!(
            "{title}: H|D*(q_k, p_k) along DLA and MLA (h = {H}, N = {}), and the certified \
             energy E_L of the exact trajectory through (q_0, q_1) (an interval of width \
             {:.1e}); right: an upper bound of |H|D*(q_k, p_k) - E_L|.",
            n - 1,
            exact_energy.wid()
        ),
        panels: vec![
            Panel {
                title: format!("{title}: energy H|D*"),
                x_label: "step k".into(),
                y_label: "H|D*".into(),
                x_log: false,
                y_log: false,
                series: vec![
                    Series::new("DLA", Style::Line, along(&dla.energy)),
                    Series::new("MLA", Style::Line, along(&mla.energy)),
                    Series::new(
                        "exact (certified)",
                        Style::Dashed,
                        vec![(0.0, mid), (k(n - 1), mid)],
                    ),
                ],
            },
            Panel {
                title: format!("{title}: energy error"),
                x_label: "step k".into(),
                y_label: "|H|D* - E_exact|".into(),
                x_log: false,
                y_log: true,
                series: vec![
                    Series::new("DLA", Style::Line, error(&dla.energy)),
                    Series::new("MLA", Style::Line, error(&mla.energy)),
                ],
            },
        ],
        tables: vec![table],
    }
}

/// The particle (paper Example 5.1): energy of DLA and MLA, and their certified distance to
/// the exact discrete flow (9.1), (9.2). q0 = 0, q1 = (0.4, 0.4, z1) with z1 from M_h^d.
pub fn particle(steps: usize, progress: &Progress) -> Result<Vec<Figure>, Error> {
    let m = model("particle", &[])?;
    let q0 = [0.0; 3];
    progress.count("particle: DLA and MLA", 0, 3);
    let dla = run_scheme(&m, SchemeKind::Dla, &q0, &[0.4, 0.4, 0.0], H, steps)?;
    let mla = run_scheme(&m, SchemeKind::Mla, &q0, &[0.4, 0.4, 0.0], H, steps)?;
    progress.count("particle: certified exact discrete flow", 1, 3);
    // Both schemes start from the same pair (q_0, q_1 on M_h^d).
    let ex = exact::trajectory(
        &m,
        &points(&q0),
        &points(&mla.q[1]),
        H,
        steps,
        &FlowOptions::default(),
    )?;
    progress.count("particle: figures", 2, 3);
    let e = energy(&m, &unwrap(&ex.q[0]), &unwrap(&ex.v[0]))?.into();
    let mut figs = vec![energy_figure("particle_energy", "Particle", &dla, &mla, e)];
    // Certified distances |q_k - q(kh)|_inf (spec Theorem 8.1).
    let dist = |tr: &Trajectory| -> Vec<Interval> {
        tr.q.iter()
            .zip(&ex.q)
            .map(|(a, b)| distance(a, b))
            .collect()
    };
    let (dd, dm) = (dist(&dla), dist(&mla));
    let mut table = Table::new(
        "",
        &[
            "k",
            "distance_dla_lo",
            "distance_dla_hi",
            "distance_mla_lo",
            "distance_mla_hi",
            "exact_width",
        ],
    );
    for k in 0..=steps {
        table.rows.push(vec![
            k as f64,
            dd[k].inf(),
            dd[k].sup(),
            dm[k].inf(),
            dm[k].sup(),
            max_width(&ex.q[k]),
        ]);
    }
    let upper = |d: &[Interval]| {
        d.iter()
            .enumerate()
            .skip(1)
            .map(|(k, x)| (k as f64, x.sup()))
            .collect()
    };
    let width = ex.q.iter().map(max_width).fold(0.0, f64::max);
    figs.push(Figure {
        name: "particle_error".into(),
        caption: format!(
            "Particle: certified upper bound of |q_k - q(kh)|_inf, the distance of DLA's and \
             MLA's q_k to the exact discrete flow from the same (q_0, q_1) (spec Theorem 8.1; \
             h = {H}, N = {steps}; the exact flow's enclosures are at most {width:.1e} wide)."
        ),
        panels: vec![Panel {
            title: "Particle: distance to the exact discrete flow".into(),
            x_label: "step k".into(),
            y_label: "|q_k - q(kh)|_inf".into(),
            x_log: false,
            y_log: true,
            series: vec![
                Series::new("DLA", Style::Line, upper(&dd)),
                Series::new("MLA", Style::Line, upper(&dm)),
            ],
        }],
        tables: vec![table],
    });
    progress.count("particle", 3, 3);
    Ok(figs)
}

/// The knife edge (eps = None) or the perturbed knife edge (paper Examples 5.2, 5.3):
/// energies of DLA and MLA (9.1). q0 = 0, x1 = phi1 = 0.4, y1 from M_h^d (the paper's
/// q1 = (0.4, 0.4, y1) in its coordinates (x, phi, y); tests/schemes.rs).
pub fn knife(eps: Option<f64>, steps: usize, progress: &Progress) -> Result<Figure, Error> {
    let (scene, params, title, name) = match eps {
        None => ("knife", vec![], "Knife edge".to_string(), "knife_energy"),
        Some(e) => (
            "knife-eps",
            vec![("eps".to_string(), e)],
            format!("Perturbed knife edge (eps = {e})"),
            "knife_eps_energy",
        ),
    };
    progress.count(&format!("{scene}: DLA and MLA"), 0, 1);
    let m = model(scene, &params)?;
    let e = eps.unwrap_or(0.0);
    let q0 = [0.0; 3];
    let q1 = [0.4, 0.4 * 0.2f64.sin() / (0.2f64.cos() - e), 0.4];
    let dla = run_scheme(&m, SchemeKind::Dla, &q0, &q1, H, steps)?;
    let mla = run_scheme(&m, SchemeKind::Mla, &q0, &q1, H, steps)?;
    let r = exact::retract(
        &m,
        &points(&q0),
        &points(&mla.q[1]),
        H,
        &FlowOptions::default(),
    )?;
    let exact_energy = energy(&m, &unwrap(&points(&q0)), &unwrap(&r.v0))?.into();
    progress.count(scene, 1, 1);
    Ok(energy_figure(name, &title, &dla, &mla, exact_energy))
}

/// The exact discrete space M_h^{e,nh} of the particle beside M_h^d, from q0 = 0 (9.3).
pub fn discrete_space(xs: &[f64], ys: &[f64], progress: &Progress) -> Result<Figure, Error> {
    let m = model("particle", &[])?;
    let q0 = points(&[0.0; 3]);
    let opts = FlowOptions::default();
    let mut table = Table::new(
        "",
        &["y1", "x1", "z1_exact", "width", "z1_discrete", "difference"],
    );
    let (mut exact_s, mut discrete_s, mut diff_s) = (vec![], vec![], vec![]);
    let total = xs.len() * ys.len();
    for (j, &y) in ys.iter().enumerate() {
        let (mut ex, mut di, mut df) = (vec![], vec![], vec![]);
        for (i, &x) in xs.iter().enumerate() {
            progress.count("M_h^{e,nh}: retractions", j * xs.len() + i, total);
            // Start on M_h^d; the retraction moves the point along N = (-y, 0, 1) onto
            // M_h^{e,nh}: y is kept, x and z move (spec eq. (6.2)).
            let r = exact::retract(&m, &q0, &points(&[x, y, x * y / 2.0]), H, &opts)?;
            let (x1, z1) = (r.q1[0].mid(), r.q1[2].mid());
            let w = r.q1[0].wid().max(r.q1[2].wid());
            let zd = x1 * y / 2.0;
            table.rows.push(vec![y, x1, z1, w, zd, z1 - zd]);
            ex.push((x1, z1));
            di.push((x1, zd));
            df.push((x1, z1 - zd));
        }
        exact_s.push(Series::new(format!("y1 = {y}"), Style::LineMarkers, ex).color(j));
        // One legend entry per slice: the dashed twin has none.
        discrete_s.push(Series::new("", Style::Dashed, di).color(j));
        diff_s.push(Series::new(format!("y1 = {y}"), Style::LineMarkers, df).color(j));
    }
    progress.count("M_h^{e,nh}: retractions", total, total);
    let width = table.rows.iter().map(|r| r[3]).fold(0.0, f64::max);
    exact_s.extend(discrete_s);
    Ok(Figure {
        name: "discrete_space".into(),
        caption: format!(
            "Particle, q0 = 0, h = {H}: z1 as a function of x1 on slices y1 = const (both \
             spaces are symmetric under (x1, z1) -> (-x1, -z1)). Solid: the \
             exact discrete space M_h^(e,nh) (midpoints of the certified points q(h) = Q1 + \
             N(Q1) s of the retraction, enclosures at most {width:.1e} wide); dashed: M_h^d, \
             z1 = x1 y1 / 2. Right: z1(M_h^(e,nh)) - z1(M_h^d) at the same (x1, y1)."
        ),
        panels: vec![
            Panel {
                title: "M_h^(e,nh) (solid) and M_h^d (dashed)".into(),
                x_label: "x1".into(),
                y_label: "z1".into(),
                x_log: false,
                y_log: false,
                series: exact_s,
            },
            Panel {
                title: "z1 exact - z1 discrete".into(),
                x_label: "x1".into(),
                y_label: "difference in z1".into(),
                x_log: false,
                y_log: false,
                series: diff_s,
            },
        ],
        tables: vec![table],
    })
}

/// The shortest time of a call of `f` (seconds) over repetitions that go on until
/// `min_seconds` have passed, at least three when `min_seconds > 0` (the minimum is the
/// least disturbed by other work on the machine), and the last result.
fn timed<T>(min_seconds: f64, mut f: impl FnMut() -> T) -> (T, f64) {
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut reps = 0;
    loop {
        let t0 = Instant::now();
        let out = f();
        best = best.min(t0.elapsed().as_secs_f64());
        reps += 1;
        if start.elapsed().as_secs_f64() >= min_seconds && (reps >= 3 || min_seconds <= 0.0) {
            return (out, best);
        }
    }
}

/// Work-precision diagram on the knife edge (9.4): DLA and MLA error at time T against the
/// certified flow, and the certified flow's width, against the cost per unit time.
pub fn work_precision(s: &Settings, progress: &Progress) -> Result<Figure, Error> {
    let m = model("knife", &[])?;
    let (q0, u0, t) = ([0.1, -0.2, 0.3], [0.7, 0.9], s.wp_time);
    let reference = flow(&m, &q0, &u0, t, &FlowOptions::default())?;
    let total = s.wp_scheme_h.len()
        + s.wp_orders.len() * (s.wp_flow_h.len() + 1)
        + 3 * s.wp_set_times.len();
    let mut done = 0;
    let mut schemes = Table::new(
        "schemes",
        &["h", "cost_dla", "error_dla", "cost_mla", "error_mla"],
    );
    let (mut dla_s, mut mla_s) = (vec![], vec![]);
    for &h in &s.wp_scheme_h {
        progress.count("work-precision: DLA and MLA", done, total);
        done += 1;
        let q1: Vec<f64> = flow(&m, &q0, &u0, h, &FlowOptions::default())?
            .q
            .iter()
            .map(|x| x.mid())
            .collect();
        let n = (t / h).round() as usize;
        let mut row = vec![h];
        for (kind, series) in [(SchemeKind::Dla, &mut dla_s), (SchemeKind::Mla, &mut mla_s)] {
            let scheme = Scheme::new(&m, kind);
            let (tr, secs) = timed(s.wp_min_seconds, || {
                scheme.integrate(&q0, &q1, h, n, &NewtonOptions::default())
            });
            let tr = tr?;
            let err = distance(&tr.q[n], &reference.q).sup();
            let cost = secs / t;
            row.extend([cost, err]);
            series.push((cost, err));
        }
        schemes.rows.push(row);
    }
    let mut certified = Table::new("certified", &["order", "h", "cost", "width", "steps"]);
    let mut panel_series = vec![
        Series::new("DLA (error)", Style::LineMarkers, dla_s),
        Series::new("MLA (error)", Style::LineMarkers, mla_s),
    ];
    let mut automatic = vec![];
    let mut failed = 0;
    for &p in &s.wp_orders {
        let mut pts = vec![];
        // Fixed steps (spec eq. (5.13)), then the automatic rule (5.8) (h = 0 in the table).
        for &h in s.wp_flow_h.iter().chain(&[0.0]) {
            progress.count("work-precision: certified flow", done, total);
            done += 1;
            let opts = FlowOptions {
                order: Some(p),
                fixed_h: (h > 0.0).then_some(h),
                ..FlowOptions::default()
            };
            let (e, secs) = timed(s.wp_min_seconds, || flow(&m, &q0, &u0, t, &opts));
            let Ok(e) = e else {
                failed += 1;
                continue;
            };
            let (cost, width) = (secs / t, max_width(&e.q));
            certified
                .rows
                .push(vec![p as f64, h, cost, width, e.stats.steps as f64]);
            if h == 0.0 {
                automatic.push((cost, width));
            } else {
                pts.push((cost, width));
            }
        }
        panel_series.push(Series::new(
            format!("certified, order {p} (width)"),
            Style::LineMarkers,
            pts,
        ));
    }
    panel_series.push(Series::new(
        "certified, automatic steps (width)",
        Style::Markers,
        automatic,
    ));
    // The doubleton of (5.1), (5.10') against the single parallelepiped (no
    // reorganisation, spec (5.10')) and Lohner's orthogonal basis (spec (5.10)), over
    // growing horizons (automatic steps, default order).
    let mut sets = Table::new("sets", &["t", "set", "cost", "width", "steps"]);
    let mut set_series = vec![];
    for (code, basis, reorganise, label) in [
        (
            0.0,
            Basis::Parallelepiped,
            true,
            "doubleton, parallelepiped basis (default, (5.10'))",
        ),
        (
            2.0,
            Basis::Parallelepiped,
            false,
            "single parallelepiped (the set before)",
        ),
        (
            1.0,
            Basis::Orthogonal,
            false,
            "single set, orthogonal basis (Lohner's QR, the first set)",
        ),
    ] {
        let mut pts = vec![];
        for &tt in &s.wp_set_times {
            progress.count("work-precision: certified sets", done, total);
            done += 1;
            let opts = FlowOptions {
                basis,
                reorganise,
                ..FlowOptions::default()
            };
            let (e, secs) = timed(s.wp_min_seconds, || flow(&m, &q0, &u0, tt, &opts));
            let e = e?;
            let width = max_width(&e.q);
            sets.rows
                .push(vec![tt, code, secs / tt, width, e.stats.steps as f64]);
            pts.push((tt, width));
        }
        set_series.push(Series::new(label, Style::LineMarkers, pts));
    }
    progress.count("work-precision", total, total);
    let fmt_list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    Ok(Figure {
        name: "work_precision".into(),
        caption: format!(
            "Knife edge, q0 = (0.1, -0.2, 0.3), u0 = (0.7, 0.9), T = {t}. Schemes: upper bound \
             of |q_N - q(T)|_inf against the certified flow, q1 = q(h), h = {}. Certified \
             flow: width of the enclosure of q(T), Taylor orders {:?}, fixed steps {} (each \
             order one line) and the automatic step rule (markers){}. Cost: wall time per \
             unit of simulated time on this machine. Second panel: width of the certified \
             q(T) with automatic steps against T = {}: the doubleton of (5.10') (the \
             default), the single parallelepiped before it, and Lohner's orthogonal basis.",
            fmt_list(&s.wp_scheme_h),
            s.wp_orders,
            fmt_list(&s.wp_flow_h),
            if failed > 0 {
                format!("; {failed} runs could not be certified and are not shown")
            } else {
                String::new()
            },
            fmt_list(&s.wp_set_times),
        ),
        panels: vec![
            Panel {
                title: "Work-precision, knife edge".into(),
                x_label: "seconds per unit time".into(),
                y_label: "error (schemes) / width (certified)".into(),
                x_log: true,
                y_log: true,
                series: panel_series,
            },
            Panel {
                title: "Certified sets, knife edge".into(),
                x_label: "T".into(),
                y_label: "width of q(T)".into(),
                x_log: true,
                y_log: true,
                series: set_series,
            },
        ],
        tables: vec![schemes, certified, sets],
    })
}

/// The trailer of `examples/scenes/trailer.toml` (a cart towing a trailer, two knife-edge
/// constraints, a derived basis), the same definition without the file's comments: the
/// figures are computed without reading files (`tests/it/figures.rs` checks that both pose
/// the same scene).
pub const TRAILER_SCENE: &str = r#"name = "trailer"
coordinates = ["x", "y", "theta", "psi"]
quasi_velocities = ["xd", "thetad"]
mass = [
  ["m + mt", 0,        0,   "mt*l*sin(psi)"],
  [0,        "m + mt", 0,   "-mt*l*cos(psi)"],
  [0,        0,        "I", 0],
  ["mt*l*sin(psi)", "-mt*l*cos(psi)", 0, "mt*l^2 + It"],
]
constraints = [
  ["-sin(theta)", "cos(theta)", 0, 0],
  ["-sin(psi)", "cos(psi)", 0, "-l"],
]
free = ["x", "theta"]

[parameters]
m = 1.0
I = 0.1
mt = 0.5
It = 0.05
l = 1.5
"#;

/// One certified flow of the bits figure: its widths, cost and steps.
struct BitsRun {
    /// `max wid` over the enclosures of `q(T)` and `u(T)`.
    width: f64,
    /// `max wid / max(1, |x|)` over the same.
    relative: f64,
    /// Wall time (seconds).
    seconds: f64,
    /// [`crate::work_done`] terms of one run.
    work: u64,
    steps: usize,
    order: usize,
}

/// The certified flow in the interval type `I`: the wall time as in [`timed`], except that a
/// first run longer than a second is not repeated; the Taylor terms of the first run.
fn bits_run<I: Ival>(
    m: &Model,
    q: &[f64],
    u: &[f64],
    t: f64,
    min_seconds: f64,
) -> Result<BitsRun, Error> {
    let run = || flow_at_in::<I>(m, q, u, &[t], &FlowOptions::default());
    let (w0, t0) = (work_done(), Instant::now());
    let first = run()?;
    let (mut seconds, work) = (t0.elapsed().as_secs_f64(), work_done() - w0);
    if min_seconds > 0.0 && seconds < 1.0 {
        seconds = seconds.min(timed(min_seconds, run).1);
    }
    let e = first.into_iter().next().ok_or_else(|| {
        Error::internal_at(crate::Invariant::Missing, "flow_at_in answered no time")
    })?;
    let (mut width, mut relative) = (0.0f64, 0.0f64);
    for x in e.q.iter().chain(&e.u) {
        width = width.max(x.wid());
        relative = relative.max(x.wid() / x.mag().max(1.0));
    }
    Ok(BitsRun {
        width,
        relative,
        seconds,
        work,
        steps: e.stats.steps,
        order: e.stats.order,
    })
}

/// [`bits_run`] at `bits` significand bits: f64 intervals at 53, double-double up to 106,
/// [`WideInterval`] at exactly `bits` up to [`wide::MAX_BITS`] (as `--precision`).
fn run_at_bits(
    bits: u32,
    m: &Model,
    q: &[f64],
    u: &[f64],
    t: f64,
    min_seconds: f64,
) -> Result<BitsRun, Error> {
    match bits {
        53 => bits_run::<inari::Interval>(m, q, u, t, min_seconds),
        54..=106 => bits_run::<DdInterval>(m, q, u, t, min_seconds),
        wide::MIN_BITS..=wide::MAX_BITS => {
            wide::with_bits(bits, || bits_run::<WideInterval>(m, q, u, t, min_seconds))
        }
        _ => Err(Error::input(format!(
            "work-precision: {bits} bits is not one of 53, 54..=106, {}..={}",
            wide::MIN_BITS,
            wide::MAX_BITS
        ))),
    }
}

/// Work-precision with the precision as the knob (9.4'): the certified flow's width against
/// its wall time at each of `s.wp_bits`, on the knife and on the trailer posed by its scene
/// file.
pub fn work_precision_bits(s: &Settings, progress: &Progress) -> Result<Figure, Error> {
    let knife = model("knife", &[])?;
    let trailer = Model::new(&SceneFile::from_toml(TRAILER_SCENE, "trailer")?)?;
    let problems = [
        (
            "knife",
            &knife,
            vec![0.0; 3],
            vec![0.8, 0.8],
            s.wp_bits_knife_time,
        ),
        (
            "trailer.toml",
            &trailer,
            vec![0.0; 4],
            vec![1.0, 0.3],
            s.wp_bits_trailer_time,
        ),
    ];
    let total = problems.len() * s.wp_bits.len();
    let mut done = 0;
    let mut table = Table::new(
        "",
        &[
            "problem",
            "bits",
            "t",
            "seconds",
            "work",
            "width",
            "relative_width",
            "steps",
            "order",
        ],
    );
    let mut series = vec![];
    for (i, (name, m, q, u, t)) in problems.into_iter().enumerate() {
        let (mut pts, mut labels) = (vec![], vec![]);
        for &bits in &s.wp_bits {
            progress.count("work-precision: bits", done, total);
            done += 1;
            let r = run_at_bits(bits, m, &q, &u, t, s.wp_min_seconds)?;
            table.rows.push(vec![
                i as f64,
                bits as f64,
                t,
                r.seconds,
                r.work as f64,
                r.width,
                r.relative,
                r.steps as f64,
                r.order as f64,
            ]);
            pts.push((r.seconds, r.width));
            labels.push(format!("{bits}"));
        }
        series
            .push(Series::new(format!("{name}, T = {t}"), Style::LineMarkers, pts).labels(labels));
    }
    progress.count("work-precision: bits", total, total);
    let bits = s
        .wp_bits
        .iter()
        .map(|b| b.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    Ok(Figure {
        name: "work_precision_bits".into(),
        caption: format!(
            "The precision as the knob: certified flows at {bits} bits (53: f64 intervals, \
             106: double-double, above: that many bits), automatic steps and orders, each \
             point labelled by its bits. Knife from q = 0, u = (0.8, 0.8) to T = {}; the \
             trailer posed by its scene file (examples/scenes/trailer.toml) from q = 0, \
             u = (1, 0.3) to T = {}. Width: the largest width over the enclosures of q(T) \
             and u(T). Time: wall time of one flow on this machine (the shortest of \
             repeated runs as in work_precision, a run of more than a second once); the \
             CSV adds the deterministic work (Taylor terms, dalembert::work_done), the \
             steps and the order.",
            s.wp_bits_knife_time, s.wp_bits_trailer_time
        ),
        panels: vec![Panel {
            title: "Work-precision by bits".into(),
            x_label: "seconds per flow".into(),
            y_label: "width of q(T), u(T)".into(),
            x_log: true,
            y_log: true,
            series,
        }],
        tables: vec![table],
    })
}

/// All figures.
pub fn all(s: &Settings, progress: &Progress) -> Result<Vec<Figure>, Error> {
    let mut figs = particle(s.particle_steps, progress)?;
    figs.push(discrete_space(&s.space_x, &s.space_y, progress)?);
    figs.push(knife(None, s.knife_steps, progress)?);
    figs.push(knife(Some(0.1), s.knife_steps, progress)?);
    figs.push(work_precision(s, progress)?);
    figs.push(work_precision_bits(s, progress)?);
    figs.push(orders(s, progress)?);
    Ok(figs)
}

/// Palette indices of the starts: every colour but grey (7) and cyan (9), which draw the
/// reference slopes.
const START_COLORS: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 8];
const REFERENCE_COLORS: [usize; 2] = [7, 9];

/// The legend's name of start `i`: the scene, and its q0 when an earlier start has the same
/// scene.
fn start_label(starts: &[orders::Start], i: usize) -> String {
    let s = &starts[i];
    if starts[..i].iter().any(|t| t.scene == s.scene) {
        format!("{}, q0 = {:?}", s.scene, s.q0)
    } else {
        s.scene.to_string()
    }
}

/// One panel of the orders figure: the certified errors of one scheme against h for every
/// start (upper ends as points, the intervals as bars), and dashed reference slopes c h^p for
/// each integer p that some start's last certified order is nearest to (c: half the least
/// e / h^p at the last rung over those starts, so the line runs just below them).
fn order_panel(
    title: String,
    y_label: &str,
    rows: &[(usize, String, &Ladder)],
    min_order: i32,
) -> Panel {
    let mut series = vec![];
    let mut slopes: Vec<(i32, f64, f64, f64)> = vec![]; // (p, c, h_lo, h_hi)
    for (i, label, l) in rows {
        let pts: Vec<(f64, f64)> =
            l.h.iter()
                .zip(&l.error)
                .map(|(h, e)| (*h, e.sup()))
                .collect();
        let lower = l.error.iter().map(|e| e.inf()).collect();
        series.push(
            Series::new(label.clone(), Style::LineMarkers, pts)
                .lower(lower)
                .color(START_COLORS[i % START_COLORS.len()]),
        );
        let last = l.orders[l.orders.len() - 1];
        if last.is_entire() {
            continue;
        }
        let p = (last.mid().round() as i32).max(min_order);
        let (h, e) = (l.h[l.h.len() - 1], l.error[l.error.len() - 1].sup());
        let c = 0.5 * e / h.powi(p);
        let (h_lo, h_hi) = (h, l.h[0]);
        match slopes.iter_mut().find(|s| s.0 == p) {
            Some(s) => *s = (p, s.1.min(c), s.2.min(h_lo), s.3.max(h_hi)),
            None => slopes.push((p, c, h_lo, h_hi)),
        }
    }
    slopes.sort_by_key(|s| s.0);
    for (j, (p, c, a, b)) in slopes.into_iter().enumerate() {
        series.push(
            Series::new(
                format!("h^{p} (reference)"),
                Style::Dashed,
                vec![(a, c * a.powi(p)), (b, c * b.powi(p))],
            )
            .color(REFERENCE_COLORS[j % REFERENCE_COLORS.len()]),
        );
    }
    Panel {
        title,
        x_label: "step h".into(),
        y_label: y_label.into(),
        x_log: true,
        y_log: true,
        series,
    }
}

/// Certified local and global errors of DLA and MLA against h from the starts of the README
/// table "Certified orders of DLA and MLA" (9.6; `report::orders`): the figure of the table.
pub fn orders(s: &Settings, progress: &Progress) -> Result<Figure, Error> {
    let starts: Vec<orders::Start> = orders::starts().into_iter().take(s.orders_starts).collect();
    let t_end = orders::T_END;
    let rows: Vec<Orders> = orders::ladders(
        &starts,
        &s.orders_local_h,
        &s.orders_global_h,
        t_end,
        progress,
    )?;
    let columns = ["start", "h", "dla_lo", "dla_hi", "mla_lo", "mla_hi"];
    let mut local = Table::new("local", &columns);
    let mut global = Table::new("global", &columns);
    let mut refused = vec![];
    let mut widest: f64 = 0.0;
    // (start, label, ladder) per panel: DLA local, MLA local, DLA global, MLA global.
    let mut shown: [Vec<(usize, String, &Ladder)>; 4] = Default::default();
    for (i, r) in rows.iter().enumerate() {
        let label = start_label(&starts, i);
        for (g, (ladders, table)) in [(&r.local, &mut local), (&r.global, &mut global)]
            .into_iter()
            .enumerate()
        {
            let [Ok(dla), Ok(mla)] = ladders else {
                refused.push(format!(
                    "{label} ({})",
                    if g == 0 { "local" } else { "global" }
                ));
                continue;
            };
            for k in 0..dla.h.len() {
                let (a, b) = (dla.error[k], mla.error[k]);
                table
                    .rows
                    .push(vec![i as f64, dla.h[k], a.inf(), a.sup(), b.inf(), b.sup()]);
                widest = widest.max(a.wid() / a.sup()).max(b.wid() / b.sup());
            }
            shown[2 * g].push((i, label.clone(), dla));
            shown[2 * g + 1].push((i, label.clone(), mla));
        }
    }
    let names = ["DLA", "MLA"];
    let panels = shown
        .iter()
        .enumerate()
        .map(|(j, rows)| {
            let (name, g) = (names[j % 2], j / 2);
            debug_assert_eq!(SCHEMES.len(), names.len());
            if g == 0 {
                order_panel(
                    format!("{name}: local error of one step"),
                    "|q_2 - q^e_2|_inf",
                    rows,
                    1,
                )
            } else {
                order_panel(
                    format!("{name}: global error over [0, {t_end}]"),
                    "max_k |q_k - q^e_k|_inf",
                    rows,
                    1,
                )
            }
        })
        .collect();
    let list = starts
        .iter()
        .enumerate()
        .map(|(i, st)| format!("{i} {} from q0 = {:?}, u0 = {:?}", st.scene, st.q0, st.u0))
        .collect::<Vec<_>>()
        .join("; ");
    let fmt_list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    Ok(Figure {
        name: "orders".into(),
        caption: format!(
            "Certified errors of DLA and MLA against the step h (log-log), from the starts of \
             the README table \"Certified orders of DLA and MLA\" (CSV column start: {list}). \
             Local (left two panels): |q_2 - q^e_2|_inf of one step from (q_0, q_1 = q(h)) \
             against the exact discrete flow from that pair (spec (11.1)), h = {}. Global \
             (right two): max_k |q_k - q^e_k|_inf over [0, {t_end}] (spec (11.3)), h = {}. \
             Points: upper ends of the certified error intervals; bars: the intervals (at \
             most {widest:.0e} of the error wide, so they hide under the points). Dashed: c \
             h^p for each whole p nearest to some start's last certified order, c putting \
             the line just below those starts at the smallest h.{}",
            fmt_list(&s.orders_local_h),
            fmt_list(&s.orders_global_h),
            if refused.is_empty() {
                String::new()
            } else {
                format!(
                    " Refused by the oracle or a scheme, not shown: {}.",
                    refused.join(", ")
                )
            }
        ),
        panels,
        tables: vec![local, global],
    })
}
