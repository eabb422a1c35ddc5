//! The command line: parsing, JSON, exit codes (contract.md). No mathematics here.

pub mod demo;
pub mod json;

use clap::{Parser, Subcommand};
use dalembert::integrator::{NewtonOptions, Scheme, SchemeKind};
use dalembert::scalar::point;
use dalembert::{exact, AnyScene, Error, FlowOptions, Model};
use inari::Interval;
use serde_json::{json, Value};

#[derive(Parser, Debug)]
#[command(
    name = "dalembert",
    version,
    about = "Certified enclosures of exact discrete nonholonomic mechanics",
    long_about = "Certified enclosures of exact discrete nonholonomic mechanics.\n\
                  With no command: a demonstration on the paper's nonholonomic particle."
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Option<Cmd>,
}

#[derive(clap::Args, Debug, Clone)]
pub struct SceneArgs {
    /// Scene: particle, knife, knife-eps
    #[arg(long, allow_hyphen_values = true)]
    pub scene: String,
    /// Scene parameter name=value (may repeat)
    #[arg(long = "param", allow_hyphen_values = true)]
    pub params: Vec<String>,
}

#[derive(clap::Args, Debug, Clone)]
pub struct PairArgs {
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
    /// Print one JSON object
    #[arg(long)]
    pub json: bool,
}

#[derive(Subcommand, Debug)]
pub enum Cmd {
    /// Exact retractions R^{e-}, R^{e+} and the defect of (Q0, Q1) w.r.t. M_h^{e,nh}
    Retract(PairArgs),
    /// One step of the exact discrete flow with the exact discrete Legendre transforms
    Step(PairArgs),
    /// The exact discrete Lagrangian: the action along the retraction's trajectory
    Lagrangian(PairArgs),
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
    /// Enclose the exact nonholonomic state at time T
    Flow {
        #[command(flatten)]
        scene: SceneArgs,
        /// Initial configuration, comma-separated
        #[arg(long, allow_hyphen_values = true)]
        q: String,
        /// Initial quasi-velocities in the scene's basis of D
        #[arg(long, allow_hyphen_values = true)]
        u: String,
        /// Time T >= 0
        #[arg(long, allow_hyphen_values = true)]
        t: String,
        /// Taylor order (default: automatic)
        #[arg(long, allow_hyphen_values = true)]
        order: Option<String>,
        /// Print one JSON object
        #[arg(long)]
        json: bool,
    },
}

/// Run the command line; returns the exit status.
pub fn run(args: Vec<String>) -> i32 {
    let cli = match Cli::try_parse_from(&args) {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                print!("{e}");
                return 0;
            }
            let text = e.to_string();
            let first = text
                .lines()
                .next()
                .unwrap_or("invalid arguments")
                .trim_start_matches("error: ");
            eprintln!("error: {first}");
            return 2;
        }
    };
    let result = match cli.cmd {
        None => demo::run(),
        Some(cmd) => execute(cmd),
    };
    match result {
        Ok(out) => {
            match out {
                Some(Value::String(text)) => println!("{text}"),
                Some(v) => println!("{v}"),
                None => {}
            }
            0
        }
        Err(e) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            e.code()
        }
    }
}

fn one_line(s: &str) -> String {
    s.replace('\n', " ")
}

fn render(out: Value, as_json: bool) -> Option<Value> {
    if as_json {
        Some(out)
    } else {
        Some(Value::String(json::human(&out)))
    }
}

fn pair_inputs(a: &PairArgs) -> Result<(Model, Vec<f64>, Vec<f64>, f64), Error> {
    let model = model_of(&a.scene)?;
    let q0 = json::parse_vec("q0", &a.q0)?;
    let q1 = json::parse_vec("q1", &a.q1)?;
    let h = json::parse_num("h", &a.h)?;
    Ok((model, q0, q1, h))
}

fn points(v: &[f64]) -> Vec<Interval> {
    v.iter().map(|x| point(*x)).collect()
}

fn execute(cmd: Cmd) -> Result<Option<Value>, Error> {
    match cmd {
        Cmd::Retract(a) => {
            let (model, q0, q1, h) = pair_inputs(&a)?;
            let r = exact::retract(
                &model,
                &points(&q0),
                &points(&q1),
                h,
                &FlowOptions::default(),
            )?;
            Ok(render(json::retraction(&r), a.json))
        }
        Cmd::Integrate {
            pair,
            scheme,
            steps,
        } => {
            let (model, q0, q1, h) = pair_inputs(&pair)?;
            let kind: SchemeKind = scheme.parse()?;
            let steps = json::parse_steps(&steps)?;
            let tr = Scheme::new(&model, kind).integrate(
                &q0,
                &q1,
                h,
                steps,
                &NewtonOptions::default(),
            )?;
            if pair.json {
                Ok(Some(json::trajectory(&tr)))
            } else {
                Ok(Some(Value::String(json::trajectory_csv(&tr))))
            }
        }
        Cmd::Lagrangian(a) => {
            let (model, q0, q1, h) = pair_inputs(&a)?;
            let (r, l) = exact::discrete_lagrangian(
                &model,
                &points(&q0),
                &points(&q1),
                h,
                &FlowOptions::default(),
            )?;
            let out =
                serde_json::json!({"l": json::intervals(&[l])[0], "defect": json::intervals(&r.s)});
            Ok(render(out, a.json))
        }
        Cmd::Step(a) => {
            let (model, q0, q1, h) = pair_inputs(&a)?;
            let s = exact::step(
                &model,
                &points(&q0),
                &points(&q1),
                h,
                &FlowOptions::default(),
            )?;
            Ok(render(json::step(&s), a.json))
        }
        Cmd::Flow {
            scene,
            q,
            u,
            t,
            order,
            json: as_json,
        } => {
            let model = model_of(&scene)?;
            let q = json::parse_vec("q", &q)?;
            let u = json::parse_vec("u", &u)?;
            let t = json::parse_num("t", &t)?;
            let mut opts = FlowOptions::default();
            if let Some(o) = order {
                opts.order = json::parse_order(&o)?;
            }
            let e = dalembert::flow(&model, &q, &u, t, &opts)?;
            let out = json!({
                "q": json::intervals(&e.q),
                "v": json::intervals(&e.v),
                "u": json::intervals(&e.u),
                "stats": json::stats(&e.stats),
            });
            Ok(render(out, as_json))
        }
    }
}

pub fn model_of(s: &SceneArgs) -> Result<Model, Error> {
    let params = s
        .params
        .iter()
        .map(|p| json::parse_param(p))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Model::new(AnyScene::new(&s.scene, &params)?))
}
