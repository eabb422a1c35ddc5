//! `dalembert order`: the certified local and global order of DLA or MLA on a scene
//! ([spec chapter 11](crate::spec::testing)): the flags read into a [`Query::Order`], answered by the protocol
//! (the batch query `order` takes the same path).

use super::{scene_spec, SceneArgs};
use crate::protocol::{self, order, Query, Session};
use crate::Error;

#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: &SceneArgs,
    scheme: &str,
    q: &str,
    u: &str,
    h: Option<&str>,
    rungs: Option<&str>,
    precision: Option<&str>,
    as_json: bool,
) -> Result<String, Error> {
    let spec = scene_spec(scene)?;
    let kind = scheme.parse()?;
    let q = protocol::parse_vec("--q", q)?;
    let u = protocol::parse_vec("--u", u)?;
    let h0 = h.map_or(Ok(order::DEFAULT_H), |h| protocol::parse_num("--h", h))?;
    let h0 = order::check_h("--h", h0)?;
    let rungs = match rungs.map_or(Ok(order::DEFAULT_RUNGS), |r| r.trim().parse::<usize>()) {
        Ok(r) if order::RUNGS.contains(&r) => r,
        _ => return Err(Error::input("--rungs: expected an integer in 2..=12")),
    };
    let query = Query::Order {
        scene: spec,
        scheme: kind,
        q,
        u,
        h: h0,
        rungs,
    };
    let query = super::precise(query, precision, None)?;
    Ok(Session::default().answer(&query)?.render(as_json))
}
