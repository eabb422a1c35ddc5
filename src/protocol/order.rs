//! The `order` query (the `order` command's and batch's, contract E15): the certified local
//! and global order of DLA or MLA on a scene ([spec chapter 11](crate::spec::testing),
//! `crate::testing::{local_order, global_order}`), its answer and the answer's renderings.

use super::{interval, intervals};
use crate::schemes::{Scheme, SchemeKind};
use crate::testing::{global_order, local_order, local_order_in, Ladder};
use crate::{Error, FlowOptions, Interval, Model};
use serde_json::{json, Value};

/// The largest step of the local ladder when none is given.
pub const DEFAULT_H: f64 = 0.125;

/// The rungs of the local ladder when none are given.
pub const DEFAULT_RUNGS: usize = 5;

/// The rungs a local ladder may have.
pub const RUNGS: std::ops::RangeInclusive<usize> = 2..=12;

/// `Err` unless `0 < h <= 1` (`label` names the flag or key in the message).
pub fn check_h(label: &str, h: f64) -> Result<f64, Error> {
    if h > 0.0 && h <= 1.0 {
        Ok(h)
    } else {
        Err(Error::input(format!(
            "{label}: expected 0 < h <= 1, got {h}"
        )))
    }
}

/// The certified errors and orders of a scheme from one start (`dalembert order`).
#[derive(Clone, Debug, PartialEq)]
pub struct OrderAnswer {
    /// The scene's name.
    pub scene: String,
    /// DLA or MLA.
    pub scheme: SchemeKind,
    /// The start `q` and `u`, as given.
    pub q: Vec<f64>,
    /// The initial quasi-velocities.
    pub u: Vec<f64>,
    /// One step's errors on the local ladder `h, h/2, ..` and the orders between rungs.
    pub local: Ladder,
    /// The end time of the global ladder.
    pub t_end: f64,
    /// The errors at `t_end` on the ladder `h/2, h/4, h/8` and the orders between rungs.
    pub global: Ladder,
}

/// The local ladder `h0, h0/2, ..` (`rungs` rungs) and the global ladder `h0/2, h0/4, h0/8`
/// to the whole number of its first step nearest 1, of `scheme` on `model` from `(q, u)`.
/// With `precision` (`Some`, above 53 bits: contract E18) the local ladder's exact steps are
/// computed with double-double intervals ([`local_order_in`]); the global ladder stays at 53
/// bits (the trajectory check of chapter 8 is not yet written over the interval type).
#[allow(clippy::too_many_arguments)]
pub(crate) fn answer(
    model: &Model,
    scheme: &mut Scheme,
    q: &[f64],
    u: &[f64],
    h0: f64,
    rungs: usize,
    opts: &FlowOptions,
    precision: Option<u32>,
) -> Result<OrderAnswer, Error> {
    // powers of two below h0: exact halvings, and T = 1 a whole number of steps when h0 is
    // a power of two
    let local_h: Vec<f64> = (0..rungs).map(|i| h0 / f64::powi(2.0, i as i32)).collect();
    let global_h: Vec<f64> = (1..4).map(|i| h0 / f64::powi(2.0, i)).collect();
    let t_end = global_h[0] * (1.0 / global_h[0]).round().max(1.0);
    let local = match precision {
        None => local_order(model, scheme, q, u, &local_h, opts)?,
        Some(_) => local_order_in::<crate::precision::dd::DdInterval, _>(
            model, scheme, q, u, &local_h, opts,
        )?,
    };
    let global = global_order(model, scheme, q, u, t_end, &global_h, opts)?;
    Ok(OrderAnswer {
        scene: model.name().to_string(),
        scheme: scheme.kind,
        q: q.to_vec(),
        u: u.to_vec(),
        local,
        t_end,
        global,
    })
}

impl OrderAnswer {
    /// The object `order --json` prints, and the `ok` of a batch `order` answer.
    pub fn to_json(&self) -> Value {
        let ladder = |l: &Ladder| {
            json!({
                "h": l.h,
                "error": intervals(&l.error),
                "order": l.orders.iter().map(|o| order_json(*o)).collect::<Vec<_>>(),
            })
        };
        json!({
            "scene": self.scene,
            "scheme": self.scheme.name(),
            "local": ladder(&self.local),
            "global": json!({"t": self.t_end, "ladder": ladder(&self.global)}),
        })
    }

    /// What `order` prints without `--json`.
    pub fn to_text(&self) -> String {
        let mut out = format!(
            "{} on `{}` from q = {:?}, u = {:?} (certified intervals; spec chapter 11)\n",
            self.scheme.name().to_uppercase(),
            self.scene,
            self.q,
            self.u
        );
        for (title, l) in [
            ("local error of one step", &self.local),
            ("global error", &self.global),
        ] {
            out.push_str(&format!(
                "{title}:\n{:>12} {:>28} {:>22}\n",
                "h", "error in", "order in"
            ));
            for (i, h) in l.h.iter().enumerate() {
                let e = l.error[i];
                let o = l.orders.get(i.wrapping_sub(1)).filter(|_| i > 0);
                out.push_str(&format!(
                    "{h:>12} {:>28} {:>22}\n",
                    format!("[{:.3e}, {:.3e}]", e.inf(), e.sup()),
                    o.map_or(String::new(), |o| show_order(*o))
                ));
            }
        }
        if self.global.h.is_empty() {
            return out;
        }
        out.push_str(&format!("(global error over [0, {}])", self.t_end));
        out
    }
}

/// An order enclosure as JSON: `[lo, hi]`, or null where none is proved.
fn order_json(o: Interval) -> Value {
    if o.is_entire() {
        Value::Null
    } else {
        interval(o)
    }
}

/// Rounded outward to 3 decimals (the printed interval contains the certified one).
fn show_order(o: Interval) -> String {
    if o.is_entire() {
        return "(none proved)".into();
    }
    let lo = (o.inf() * 1000.0 - 1e-6).floor() / 1000.0;
    let hi = (o.sup() * 1000.0 + 1e-6).ceil() / 1000.0;
    format!("[{lo:.3}, {hi:.3}]")
}
