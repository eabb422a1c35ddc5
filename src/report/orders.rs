//! The certified local and global orders of DLA and MLA on every scene: the starts and
//! ladders of the README table "Certified orders of DLA and MLA" (`examples/orders.rs`) and
//! of the figure `orders` (`dalembert figures`; [spec (9.6)](crate::spec::report)). One list, so that the table and
//! the figure show the same runs.

use super::Progress;
use crate::schemes::{Scheme, SchemeKind};
use crate::testing::{global_order, local_order, Ladder};
use crate::{AnyScene, Error, FlowOptions, Model};

/// The local ladder of the table: h = 1/8 .. 1/128.
pub const LOCAL_H: [f64; 5] = [0.125, 0.0625, 0.03125, 0.015625, 0.0078125];
/// The global ladder of the table: h = 1/16 .. 1/64, over [0, T_END].
pub const GLOBAL_H: [f64; 3] = [0.0625, 0.03125, 0.015625];
/// The end `T` of the global ladder's interval `[0, T]`.
pub const T_END: f64 = 1.0;
/// The schemes, in the order of the table's columns.
pub const SCHEMES: [SchemeKind; 2] = [SchemeKind::Dla, SchemeKind::Mla];

/// A scene and a start `(q0, u0)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Start {
    /// The built-in scene's name (default parameters).
    pub scene: &'static str,
    /// The initial configuration.
    pub q0: Vec<f64>,
    /// The initial quasi-velocities.
    pub u0: Vec<f64>,
}

/// The table's starts: every built-in scene (default parameters) from q0 = (0, 0.5, 0, ..,
/// 0.3) (`q0[1]` = 0.5, last component 0.3, the others 0) and u0_a = 0.8 - 0.3 a; then the
/// particle at y = 0, q0 = (0, 0, 0.3), a special start where the leading term of the
/// local error vanishes (local order 4).
pub fn starts() -> Vec<Start> {
    let mut v: Vec<Start> = crate::scene::SCENES
        .iter()
        .map(|info| {
            let mut q0 = vec![0.0; info.n];
            q0[1] = 0.5;
            q0[info.n - 1] = 0.3;
            let u0 = (0..info.n - info.k).map(|a| 0.8 - 0.3 * a as f64).collect();
            Start {
                scene: info.name,
                q0,
                u0,
            }
        })
        .collect();
    v.push(Start {
        scene: "particle",
        q0: vec![0.0, 0.0, 0.3],
        u0: vec![0.8, 0.5],
    });
    v
}

/// The ladders of one start: `local[j]` and `global[j]` for the scheme `SCHEMES[j]`, or why
/// the oracle (or the scheme) refused.
#[derive(Clone, Debug)]
pub struct Orders {
    /// The start the ladders were run from.
    pub start: Start,
    /// The local ladders ([spec (11.1)](crate::spec::testing)) of DLA and MLA, or why each was refused.
    pub local: [Result<Ladder, Error>; 2],
    /// The global ladders ([spec (11.3)](crate::spec::testing)) of DLA and MLA, or why each was refused.
    pub global: [Result<Ladder, Error>; 2],
}

/// `testing::local_order` on `local_h` and `testing::global_order` over `[0, t_end]` on
/// `global_h`, for DLA and MLA from every start of `starts` (default flow options).
pub fn ladders(
    starts: &[Start],
    local_h: &[f64],
    global_h: &[f64],
    t_end: f64,
    progress: &Progress,
) -> Result<Vec<Orders>, Error> {
    let opts = FlowOptions::default();
    let mut out = Vec::with_capacity(starts.len());
    for (i, st) in starts.iter().enumerate() {
        progress.count(&format!("orders: {}", st.scene), i, starts.len());
        let m = Model::new(&AnyScene::new(st.scene, &[])?)?;
        let run = |kind: SchemeKind, global: bool| {
            let mut s = Scheme::new(&m, kind);
            if global {
                global_order(&m, &mut s, &st.q0, &st.u0, t_end, global_h, &opts)
            } else {
                local_order(&m, &mut s, &st.q0, &st.u0, local_h, &opts)
            }
        };
        out.push(Orders {
            start: st.clone(),
            local: SCHEMES.map(|k| run(k, false)),
            global: SCHEMES.map(|k| run(k, true)),
        });
    }
    progress.count("orders", starts.len(), starts.len());
    Ok(out)
}
