//! The command line: parsing flags into `crate::protocol::Query`, printing answers, exit
//! codes (contract.md). No mathematics here.

/// `println!` to stdout that ends quietly when stdout is closed (a reader such as `head` that
/// stopped reading): a closed pipe is not an error of the query, and never a panic.
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

/// `print!` to stdout, as `outln!`.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($t)*);
    }};
}

mod batch;
mod check;
pub(crate) mod demo;
mod figures;
mod integrate;
mod order;
mod progress;
mod render;
mod scenes;
mod spool;
mod stability;

use crate::protocol::{self, Pair, Query, SceneSpec, Session};
use crate::Error;
use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "dalembert",
    version,
    about = "Certified enclosures of exact discrete nonholonomic mechanics",
    long_about = "Certified enclosures of exact discrete nonholonomic mechanics.\n\
                  With no command: a demonstration on the paper's nonholonomic particle."
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub cmd: Option<Cmd>,
}

#[derive(clap::Args, Debug, Clone)]
pub(crate) struct SceneArgs {
    #[arg(long, allow_hyphen_values = true, help = scene_help(),
          required_unless_present = "scene_file", conflicts_with = "scene_file")]
    pub scene: Option<String>,
    /// Your own system: a scene file (TOML; README "Your own system")
    #[arg(long = "scene-file", value_name = "PATH")]
    pub scene_file: Option<String>,
    /// Scene parameter name=value (may repeat)
    #[arg(long = "param", allow_hyphen_values = true)]
    pub params: Vec<String>,
}

/// The `--scene` help: every registered scene.
fn scene_help() -> String {
    format!(
        "Scene: {} (`dalembert scenes` describes them)",
        crate::scene::scene_names().join(", ")
    )
}

#[derive(clap::Args, Debug, Clone)]
pub(crate) struct PairArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// First configuration Q0, comma-separated
    #[arg(long, allow_hyphen_values = true)]
    pub q0: String,
    /// Second configuration Q1
    #[arg(long, allow_hyphen_values = true)]
    pub q1: String,
    /// Time step H > 0
    #[arg(long, allow_hyphen_values = true)]
    pub h: String,
    #[arg(long, allow_hyphen_values = true, help = DEADLINE_HELP)]
    pub deadline: Option<String>,
    #[arg(long, allow_hyphen_values = true, help = WORK_HELP)]
    pub work: Option<String>,
    #[arg(long = "max-steps", allow_hyphen_values = true, help = MAX_STEPS_HELP)]
    pub max_steps: Option<String>,
    #[arg(long, allow_hyphen_values = true, help = PRECISION_HELP)]
    pub precision: Option<String>,
    #[arg(long = "exact-decimals", help = EXACT_DECIMALS_HELP)]
    pub exact_decimals: bool,
    /// Print one JSON object
    #[arg(long)]
    pub json: bool,
}

const MAX_STEPS_HELP: &str = "Step limit of the validated flows (an integer >= 1, default \
     20000): a flow that would need more accepted Taylor steps is refused with exit 3 (cause \
     `steps`); a retraction's work is a multiple of it";

const PRECISION_HELP: &str = "Significand bits to compute with: 53 (default, f64 intervals), \
     54..106 (double-double intervals, 106 bits) or 107..1024 (exactly that many); above 53 each \
     end prints as a decimal string rounded outward (retract, step, lagrangian and flow). \
     Decimal inputs are read as their nearest f64 at every precision, unless --exact-decimals";

const EXACT_DECIMALS_HELP: &str = "With --precision above 53: read the configuration and \
     velocity vectors (--q and --u; --q0 and --q1) as the exact decimals written, enclosed at \
     that precision, instead of their nearest f64 (times and steps stay their nearest f64)";

/// `query` at the precision of `--precision` (none: 53 bits; contract E18), with its vectors
/// read as the exact decimal texts `exact` (`--exact-decimals`, contract E22).
pub(super) fn precise(
    query: Query,
    precision: Option<&str>,
    exact: Option<[&str; 2]>,
) -> Result<Query, Error> {
    match precision.map(protocol::parse_precision).transpose()? {
        Some(bits) if bits > 53 => Ok(Query::Precise {
            precision: bits,
            query: Box::new(query),
            decimals: exact.map(|v| {
                v.iter()
                    .map(|s| s.split(',').map(|x| x.trim().to_string()).collect())
                    .collect()
            }),
        }),
        _ if exact.is_some() => Err(Error::input_key(
            "exact-decimals",
            "--exact-decimals needs --precision above 53 (at 53 bits the inputs are f64 values)",
        )),
        _ => Ok(query),
    }
}

const CHECK_PRECISION_HELP: &str = "Significand bits of the exact discrete flow the \
     candidate is compared with: 53 (default), 54..106 (double-double) or 107..1024; the \
     distances, defects and energy errors print as f64 intervals rounded outward at every \
     precision";

/// The decimal texts of a pair's `--q0` and `--q1` when `--exact-decimals` is given.
fn exact(a: &PairArgs) -> Option<[&str; 2]> {
    a.exact_decimals.then_some([a.q0.as_str(), a.q1.as_str()])
}

const DEADLINE_HELP: &str = "Time budget in seconds (> 0): past it, refused with exit 3 \
     `not certified within the budget`. Default: none (the work budget, --work, applies)";

const WORK_HELP: &str = "Work budget in Taylor terms (an integer >= 1; the same on every \
     machine): past it, refused with exit 3 `not certified within the budget`. Default, when \
     neither --work nor --deadline is given: 1000000000 for retract, step, lagrangian and \
     each pair of check; none for flow and integrate";

#[derive(Subcommand, Debug)]
pub(crate) enum Cmd {
    /// Enclose the exact nonholonomic state at time T (or at each of --times)
    Flow {
        #[command(flatten)]
        scene: SceneArgs,
        /// Initial configuration, comma-separated
        #[arg(long, allow_hyphen_values = true)]
        q: String,
        /// Initial quasi-velocities in the scene's basis of D
        #[arg(long, allow_hyphen_values = true)]
        u: String,
        /// Time T (negative: the state at T < 0, flowing backward)
        #[arg(
            long,
            allow_hyphen_values = true,
            required_unless_present = "times",
            conflicts_with = "times"
        )]
        t: Option<String>,
        /// Dense output: increasing times T1,T2,.. (instead of --t), one integration each way
        /// from 0
        #[arg(long, allow_hyphen_values = true)]
        times: Option<String>,
        /// Taylor order (default: automatic)
        #[arg(long, allow_hyphen_values = true)]
        order: Option<String>,
        /// Also enclose the derivative D(q, u)(T) / D(q, u)(0) (JSON key `jacobian`)
        #[arg(long)]
        jacobian: bool,
        #[arg(long, allow_hyphen_values = true, help = PRECISION_HELP)]
        precision: Option<String>,
        #[arg(long = "exact-decimals", help = EXACT_DECIMALS_HELP)]
        exact_decimals: bool,
        #[arg(long, allow_hyphen_values = true, help = DEADLINE_HELP)]
        deadline: Option<String>,
        #[arg(long, allow_hyphen_values = true, help = WORK_HELP)]
        work: Option<String>,
        #[arg(long = "max-steps", allow_hyphen_values = true, help = MAX_STEPS_HELP)]
        max_steps: Option<String>,
        /// Print one JSON object
        #[arg(long)]
        json: bool,
    },
    /// Exact retractions R^{e-}, R^{e+} and the defect of (Q0, Q1) w.r.t. M_h^{e,nh}
    Retract(PairArgs),
    /// One step of the exact discrete flow with the exact discrete Legendre transforms
    Step(PairArgs),
    /// Float trajectory of the DLA or MLA scheme (CSV unless --json)
    Integrate {
        #[command(flatten)]
        pair: PairArgs,
        /// mla or dla
        #[arg(long, allow_hyphen_values = true)]
        scheme: String,
        /// Number of steps N (q_0 .. q_N)
        #[arg(long, allow_hyphen_values = true)]
        steps: String,
    },
    /// The exact discrete Lagrangian: the action along the retraction's trajectory
    Lagrangian(PairArgs),
    /// Certified verdict on a candidate trajectory (CSV or JSON file from any integrator);
    /// exit 1 when the certified distance to the exact discrete flow exceeds --tol
    Check {
        #[command(flatten)]
        scene: SceneArgs,
        /// Time step H > 0 of the candidate; without it, the CSV column `t` (or the JSON
        /// key "t") gives the times of non-uniform steps
        #[arg(long, allow_hyphen_values = true)]
        h: Option<String>,
        /// File with q_0 .. q_N: JSON {"q": [[..], ..]} (as `integrate --json` prints it) or
        /// [[..], ..], or CSV: with a header, columns by name (the scene's coordinates or
        /// q0.., and k, t, p0.., energy); without one, exactly the coordinates in order
        #[arg(long, allow_hyphen_values = true)]
        trajectory: String,
        #[arg(long, allow_hyphen_values = true, help = DEADLINE_HELP)]
        deadline: Option<String>,
        #[arg(long, allow_hyphen_values = true, help = WORK_HELP)]
        work: Option<String>,
        /// Tolerance on max_k |q_k - q^e_k|_inf
        #[arg(long, allow_hyphen_values = true)]
        tol: Option<String>,
        /// Tolerance on the pairs' defects max_k |s_k|_inf (both must pass with --tol)
        #[arg(long = "defect-tol", allow_hyphen_values = true)]
        defect_tol: Option<String>,
        /// Skip the per-pair defects and energies (faster)
        #[arg(long)]
        no_pairs: bool,
        #[arg(long = "max-steps", allow_hyphen_values = true, help = MAX_STEPS_HELP)]
        max_steps: Option<String>,
        #[arg(long, allow_hyphen_values = true, help = CHECK_PRECISION_HELP)]
        precision: Option<String>,
        /// Print one JSON object
        #[arg(long)]
        json: bool,
    },
    /// Every scene: coordinates, parameters with defaults, Lagrangian, constraints, basis of D
    Scenes {
        /// Describe this scene file as compiled (its derived basis included) instead
        #[arg(long = "scene-file", value_name = "PATH")]
        scene_file: Option<String>,
        /// Parameter name=value of the scene file (may repeat)
        #[arg(long = "param", allow_hyphen_values = true)]
        params: Vec<String>,
        /// Print one JSON object
        #[arg(long)]
        json: bool,
    },
    /// Write the paper's figures and a work-precision diagram (SVG and CSV) into --out
    Figures {
        /// Output directory (created when missing)
        #[arg(long)]
        out: String,
        /// A small setting that runs in seconds, instead of the paper's
        #[arg(long)]
        quick: bool,
        /// Print one JSON object (the files written)
        #[arg(long)]
        json: bool,
    },
    /// Stability at the extremes of h, coordinates, phi and eps: certified step and Newton
    /// solves of DLA and MLA (Markdown table unless --json)
    Stability {
        /// Print one JSON object
        #[arg(long)]
        json: bool,
    },
    /// Certified local and global order of DLA or MLA on a scene: errors against the exact
    /// discrete flow on a ladder of step sizes, the observed orders as intervals
    Order {
        #[command(flatten)]
        scene: SceneArgs,
        /// mla or dla
        #[arg(long, allow_hyphen_values = true)]
        scheme: String,
        /// Initial configuration, comma-separated
        #[arg(long, allow_hyphen_values = true)]
        q: String,
        /// Initial quasi-velocities
        #[arg(long, allow_hyphen_values = true)]
        u: String,
        /// Largest step of the local ladder (default 0.125); the global ladder starts at h/2
        #[arg(long, allow_hyphen_values = true)]
        h: Option<String>,
        /// Rungs of the local ladder, each half the last (default 5, at most 12)
        #[arg(long, allow_hyphen_values = true)]
        rungs: Option<String>,
        /// Significand bits of the local ladder's exact steps: 53 (default) up to 106 (the
        /// global ladder stays at 53)
        #[arg(long, allow_hyphen_values = true)]
        precision: Option<String>,
        /// Print one JSON object
        #[arg(long)]
        json: bool,
    },
    /// JSON lines in, JSON lines out (one answer per query, in order)
    Batch {
        /// Worker threads
        #[arg(long, allow_hyphen_values = true, default_value = "1")]
        jobs: String,
        /// Time budget in seconds of every query without a `deadline` or `work` key
        /// (default: none; the work budget applies)
        #[arg(long, allow_hyphen_values = true)]
        deadline: Option<String>,
        /// Work budget in Taylor terms of every query without a `deadline` or `work` key
        /// (default, when neither --work nor --deadline is given: 1000000000 for retract,
        /// step, lagrangian and each row of check; none for flow and integrate)
        #[arg(long, allow_hyphen_values = true)]
        work: Option<String>,
        /// Step limit of the validated flows of every query without a `max_steps` key
        /// (default 20000)
        #[arg(long = "max-steps", allow_hyphen_values = true)]
        max_steps: Option<String>,
        /// Accepted for uniformity: batch output is always JSON
        #[arg(long)]
        json: bool,
    },
}

/// Run the command line on the process's arguments as OS strings: an argument that is not
/// UTF-8 is refused with the option it belongs to (exit 2); returns the exit status.
pub fn run_os(args: Vec<std::ffi::OsString>) -> i32 {
    match utf8_args(args) {
        Ok(args) => run(args),
        Err(e) => {
            eprintln!("error: {e}");
            crate::protocol::exit_code(&e)
        }
    }
}

/// The arguments as UTF-8, or the input error naming the first argument that is not: the
/// option itself (`--name=value`), or the option before a value.
pub(crate) fn utf8_args(args: Vec<std::ffi::OsString>) -> Result<Vec<String>, Error> {
    let mut out: Vec<String> = Vec::with_capacity(args.len());
    for (i, a) in args.into_iter().enumerate() {
        match a.into_string() {
            Ok(s) => out.push(s),
            Err(bad) => {
                let lossy = bad.to_string_lossy();
                let what = if lossy.starts_with("--") {
                    let name = lossy.split('=').next().unwrap_or("");
                    format!("`{name}`")
                } else {
                    match out.last() {
                        Some(prev) if i > 1 && prev.starts_with("--") && !prev.contains('=') => {
                            format!("the value of `{prev}`")
                        }
                        _ => format!("argument {i}"),
                    }
                };
                return Err(Error::input(format!(
                    "{what}: not valid UTF-8 (`{lossy}`); arguments must be UTF-8 text"
                )));
            }
        }
    }
    Ok(out)
}

/// Run the command line; returns the exit status.
pub(crate) fn run(args: Vec<String>) -> i32 {
    let cli = match Cli::try_parse_from(&args) {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                out!("{e}");
                return 0;
            }
            // clap's message spans several lines: keep the part before the usage, on one line
            let text = e.to_string();
            let msg: Vec<&str> = text
                .lines()
                .map(str::trim)
                .take_while(|l| !l.starts_with("Usage:"))
                .filter(|l| !l.is_empty() && !l.starts_with("tip:"))
                .collect();
            let msg = msg.join(" ");
            eprintln!("error: {}", msg.trim_start_matches("error: "));
            return 2;
        }
    };
    let result = match cli.cmd {
        None => demo::run().map(|()| None),
        Some(Cmd::Scenes {
            scene_file,
            params,
            json,
        }) => scenes::run(scene_file.as_deref(), &params, json).map(Some),
        Some(Cmd::Batch {
            jobs,
            deadline,
            work,
            max_steps,
            ..
        }) => batch::run(
            &jobs,
            deadline.as_deref(),
            work.as_deref(),
            max_steps.as_deref(),
        )
        .map(|()| None),
        Some(Cmd::Check {
            scene,
            h,
            trajectory,
            deadline,
            work,
            tol,
            defect_tol,
            no_pairs,
            max_steps,
            precision,
            json,
        }) => match check::run(
            &scene,
            h.as_deref(),
            &trajectory,
            (deadline.as_deref(), work.as_deref(), max_steps.as_deref()),
            (tol.as_deref(), defect_tol.as_deref()),
            no_pairs,
            precision.as_deref(),
            json,
        ) {
            Ok(passed) => return if passed { 0 } else { 1 },
            Err(e) => Err(e),
        },
        Some(Cmd::Figures { out, quick, json }) => figures::run(&out, quick, json).map(Some),
        Some(Cmd::Stability { json }) => stability::run(json).map(Some),
        Some(Cmd::Order {
            scene,
            scheme,
            q,
            u,
            h,
            rungs,
            precision,
            json,
        }) => order::run(
            &scene,
            &scheme,
            &q,
            &u,
            h.as_deref(),
            rungs.as_deref(),
            precision.as_deref(),
            json,
        )
        .map(Some),
        Some(cmd) => execute(cmd),
    };
    match result {
        Ok(Some(text)) => {
            outln!("{text}");
            0
        }
        Ok(None) => 0,
        Err(e) => {
            eprintln!("error: {}", e.to_string().replace('\n', " "));
            crate::protocol::exit_code(&e)
        }
    }
}

pub(crate) fn scene_spec(s: &SceneArgs) -> Result<SceneSpec, Error> {
    let params: Vec<(String, f64)> = s
        .params
        .iter()
        .map(|p| protocol::parse_param(p))
        .collect::<Result<_, _>>()?;
    match (&s.scene, &s.scene_file) {
        (_, Some(path)) => Ok(SceneSpec::defined(read_scene_file(path)?, params)),
        (Some(name), None) => Ok(SceneSpec::named(name, params)),
        (None, None) => Err(Error::input("give --scene NAME or --scene-file PATH")),
    }
}

/// The scene file at `path`: JSON when its extension is `.json`, else TOML (contract E26).
pub(crate) fn read_scene_file(path: &str) -> Result<crate::scene::SceneFile, Error> {
    let path = std::path::Path::new(path);
    if crate::scene::SceneFile::is_json_path(path) {
        crate::scene::SceneFile::read_json(path, protocol::parse_json)
    } else {
        crate::scene::SceneFile::read(path)
    }
}

/// `--deadline`, `--work` and `--max-steps`, read when given.
fn budget(
    deadline: &Option<String>,
    work: &Option<String>,
    max_steps: &Option<String>,
) -> Result<protocol::Budget, Error> {
    Ok(protocol::Budget {
        deadline: deadline
            .as_deref()
            .map(|s| protocol::parse_seconds("--deadline", s))
            .transpose()?,
        work: work
            .as_deref()
            .map(|s| protocol::parse_work("--work", s))
            .transpose()?,
        max_steps: max_steps
            .as_deref()
            .map(|s| protocol::parse_max_steps("--max-steps", s))
            .transpose()?,
    })
}

fn pair_budget(a: &PairArgs) -> Result<protocol::Budget, Error> {
    budget(&a.deadline, &a.work, &a.max_steps)
}

fn pair(a: &PairArgs) -> Result<Pair, Error> {
    Ok(Pair {
        scene: scene_spec(&a.scene)?,
        q0: protocol::parse_vec("--q0", &a.q0)?,
        q1: protocol::parse_vec("--q1", &a.q1)?,
        h: protocol::parse_num("--h", &a.h)?,
    })
}

/// Translate flags into a query, answer it, render it (`integrate` writes its own rows and
/// returns an empty text).
fn execute(cmd: Cmd) -> Result<Option<String>, Error> {
    let (query, own, as_json) = match cmd {
        Cmd::Flow {
            scene,
            q,
            u,
            t,
            times,
            order,
            jacobian,
            precision,
            exact_decimals,
            deadline,
            work,
            max_steps,
            json,
        } => {
            let t = match (t, times) {
                (Some(t), None) => protocol::At::One(protocol::parse_num("--t", &t)?),
                (None, Some(ts)) => protocol::At::Many(protocol::parse_vec("--times", &ts)?),
                _ => return Err(Error::input("give exactly one of --t and --times")),
            };
            let query = Query::Flow {
                scene: scene_spec(&scene)?,
                q: protocol::parse_vec("--q", &q)?,
                u: protocol::parse_vec("--u", &u)?,
                t,
                order: order.map_or(Ok(0), |o| protocol::parse_order(&o))?,
                jacobian,
            };
            let exact = exact_decimals.then_some([q.as_str(), u.as_str()]);
            let query = precise(query, precision.as_deref(), exact)?;
            (query, budget(&deadline, &work, &max_steps)?, json)
        }
        Cmd::Retract(a) => (
            precise(Query::Retract(pair(&a)?), a.precision.as_deref(), exact(&a))?,
            pair_budget(&a)?,
            a.json,
        ),
        Cmd::Step(a) => (
            precise(Query::Step(pair(&a)?), a.precision.as_deref(), exact(&a))?,
            pair_budget(&a)?,
            a.json,
        ),
        Cmd::Lagrangian(a) => (
            precise(
                Query::Lagrangian(pair(&a)?),
                a.precision.as_deref(),
                exact(&a),
            )?,
            pair_budget(&a)?,
            a.json,
        ),
        Cmd::Integrate {
            pair: a,
            scheme,
            steps,
        } => {
            if a.exact_decimals {
                return Err(Error::input_key(
                    "exact-decimals",
                    "--exact-decimals is read by flow, retract, step and lagrangian, not \
                     integrate (its trajectory is the scheme's, in f64)",
                ));
            }
            if a.precision.is_some() {
                return Err(Error::input_key(
                    "precision",
                    "--precision is read by flow, retract, step and lagrangian, not integrate \
                     (its trajectory is the scheme's, in f64)",
                ));
            }
            let p = pair(&a)?;
            let scheme = scheme.parse()?;
            let steps = protocol::parse_steps(&steps)?;
            integrate::run(&p, scheme, steps, pair_budget(&a)?, a.json)?;
            return Ok(None);
        }
        Cmd::Batch { .. }
        | Cmd::Check { .. }
        | Cmd::Scenes { .. }
        | Cmd::Figures { .. }
        | Cmd::Stability { .. }
        | Cmd::Order { .. } => return Err(Error::input("not a single query")),
    };
    let mut session = Session::default();
    // a long flow draws a bar on a terminal (erased when the bar is dropped)
    let bar = progress::SharedBar::new();
    if matches!(query, Query::Flow { .. }) {
        session.flow.progress = bar.progress();
    }
    let answer = session.answer_with(&query, own)?;
    drop(session);
    bar.clear();
    Ok(Some(answer.render(as_json)))
}
