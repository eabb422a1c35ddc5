//! The answers and their renderings.

use crate::scene::Description;
use crate::schemes::Trajectory;
use crate::{Error, FlowStats};
use inari::Interval;
use serde_json::{json, Value};

/// Every scene the crate knows, as the scene files describe them (the `scenes` command):
/// `{"scenes": [{"name", "summary", "coordinates", "velocities", "n", "k", "parameters":
/// [{"name", "default", "description"}], "lagrangian", "mu", "basis", "invariants"}]}`.
/// The strings are formulas for people and for implementations that pose the same problems.
pub fn scenes() -> Value {
    let list: Vec<Value> = crate::scene::SCENES
        .iter()
        .map(|s| description(&s.description()))
        .collect();
    json!({ "scenes": list })
}

/// One entry of [`scenes`]: a scene's description (for a user's scene, the compiled one:
/// its expressions and its derived basis as formulas).
pub fn description(s: &Description) -> Value {
    json!({
        "name": s.name,
        "summary": s.summary,
        "coordinates": s.coordinates,
        "velocities": s.velocities,
        "n": s.n,
        "k": s.k,
        "parameters": s.params.iter().map(|(name, default, description)| json!({
            "name": name,
            "default": default,
            "description": description,
        })).collect::<Vec<_>>(),
        "lagrangian": s.lagrangian,
        "mu": s.constraints,
        "basis": s.basis,
        "invariants": s.invariants,
    })
}

/// `[lo, hi]`; serde_json prints f64 in shortest round-trip form.
pub fn interval(x: Interval) -> Value {
    json!([x.inf(), x.sup()])
}

pub fn intervals(x: &[Interval]) -> Value {
    Value::Array(x.iter().map(|v| interval(*v)).collect())
}

pub fn stats(s: &FlowStats) -> Value {
    json!({"order": s.order, "steps": s.steps, "rejected": s.rejected, "h_min": s.h_min, "h_max": s.h_max})
}

/// The batch error object (contract, E10): `code` and `message`; for a refusal also its
/// `reason` (`budget`, `no_proof`, `unbounded`, `undefined`) and, when a flow was under
/// way, `reached` (the time up to which it was proved); `reason` `internal` for a fault of
/// the crate.
pub fn error_object(e: &Error) -> Value {
    let mut o = json!({"code": e.code(), "message": e.message()});
    match e {
        Error::Uncertified(r) => {
            o["reason"] = json!(r.reason.name());
            if let Some(t) = r.reached {
                o["reached"] = json!(t);
            }
        }
        Error::Internal(_) => o["reason"] = json!("internal"),
        Error::Input(_) => {}
    }
    o
}

/// The `check` answer: `{"distance", "max_distance", "defect", "energy_error", "passed"}`.
/// With pair figures also `"max_defect"` (contract E13).
pub fn verdict(v: &crate::oracle::Verdict, passed: bool) -> Value {
    let mut a = json!({
        "distance": intervals(&v.distance),
        "max_distance": interval(v.max_distance),
        "defect": v.defect.iter().map(|d| intervals(d)).collect::<Vec<_>>(),
        "energy_error": intervals(&v.energy_error),
        "passed": passed,
    });
    if let Some(m) = v.max_defect {
        a["max_defect"] = interval(m);
    }
    a
}

/// The `integrate` answer, with the Legendre transforms, energy and Newton figures.
pub fn trajectory(t: &Trajectory) -> Value {
    json!({
        "q": t.q,
        "p": t.p,
        "energy": t.energy,
        "newton_iterations": t.iterations,
        "max_residual": t.max_residual,
    })
}
