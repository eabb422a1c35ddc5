//! `dalembert order`: the certified local and global order of DLA or MLA on a scene
//! (spec chapter 11, `crate::testing::{local_order, global_order}`).

use super::{scene_spec, SceneArgs};
use crate::protocol::{self, Session};
use crate::schemes::{Scheme, SchemeKind};
use crate::testing::{global_order, local_order, Ladder};
use crate::{Error, FlowOptions, Interval};
use serde::Serialize;
use serde_json::json;

pub fn run(
    scene: &SceneArgs,
    scheme: &str,
    q: &str,
    u: &str,
    h: Option<&str>,
    rungs: Option<&str>,
    as_json: bool,
) -> Result<String, Error> {
    let spec = scene_spec(scene)?;
    let kind: SchemeKind = scheme.parse()?;
    let q = protocol::parse_vec("--q", q)?;
    let u = protocol::parse_vec("--u", u)?;
    let h0 = h.map_or(Ok(0.125), |h| protocol::parse_num("--h", h))?;
    if !(h0 > 0.0 && h0 <= 1.0) {
        return Err(Error::input(format!("--h: expected 0 < h <= 1, got {h0}")));
    }
    let rungs = match rungs.map_or(Ok(5), |r| r.trim().parse::<usize>()) {
        Ok(r) if (2..=12).contains(&r) => r,
        _ => return Err(Error::input("--rungs: expected an integer in 2..=12")),
    };
    let model = Session::default().model(&spec)?;
    let mut s = Scheme::new(&model, kind);
    let opts = FlowOptions::default();
    // powers of two below h0: exact halvings, and T = 1 a whole number of steps when h0 is
    // a power of two
    let local_h: Vec<f64> = (0..rungs).map(|i| h0 / f64::powi(2.0, i as i32)).collect();
    let global_h: Vec<f64> = (1..4).map(|i| h0 / f64::powi(2.0, i)).collect();
    let t_end = global_h[0] * (1.0 / global_h[0]).round().max(1.0);
    let local = local_order(&model, &mut s, &q, &u, &local_h, &opts)?;
    let global = global_order(&model, &mut s, &q, &u, t_end, &global_h, &opts)?;
    fn ladder(l: &Ladder) -> LadderView<'_> {
        LadderView {
            h: &l.h,
            error: &l.error,
            order: l.orders.iter().map(|o| order_json(*o)).collect(),
        }
    }
    let v = json!({
        "scene": model.name(),
        "scheme": scheme,
        "local": ladder(&local),
        "global": json!({"t": t_end, "ladder": ladder(&global)}),
    });
    if as_json {
        return Ok(v.to_string());
    }
    let mut out = format!(
        "{} on `{}` from q = {:?}, u = {:?} (certified intervals; spec chapter 11)\n",
        scheme.to_uppercase(),
        model.name(),
        q,
        u
    );
    for (title, l) in [
        ("local error of one step", &local),
        ("global error", &global),
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
    if global.h.is_empty() {
        return Ok(out);
    }
    out.push_str(&format!("(global error over [0, {t_end}])"));
    Ok(out)
}

/// A ladder as the JSON answer has it: `order` where [`Ladder`] has `orders`, and `null`
/// where none is proved.
#[derive(Serialize)]
struct LadderView<'a> {
    h: &'a [f64],
    error: &'a [Interval],
    order: Vec<Option<Interval>>,
}

/// An order enclosure: `None` (JSON null) where none is proved (the whole line).
fn order_json(o: Interval) -> Option<Interval> {
    (!o.is_entire()).then_some(o)
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
