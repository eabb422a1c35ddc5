//! The set representation (spec eqs. (5.1), (5.15)): Lohner's parallelepiped with a box,
//! its marked subset, and the derivative carried as `C + B [R]`.

use super::linalg::{self, IMat};
use crate::scalar::point;
use crate::tape::finite;
use inari::Interval;
use nalgebra::DMatrix;

/// A set `{ m + B r : r in [r] } ∩ boxed` (Lohner's parallelepiped and a box, both
/// enclosures of the same states; spec eq. (5.1)): `m` and `B` are exact f64 data, `[r]` an
/// interval vector that contains 0.
#[derive(Clone)]
pub struct LohnerSet {
    /// The centre `m` (exact f64 data).
    pub m: Vec<f64>,
    /// The basis `B`, `d x d` (exact f64 data).
    pub b: DMatrix<f64>,
    /// `[r]`, containing 0.
    pub r: Vec<Interval>,
    /// A box that also contains every state of the set (the box of spec eq. (5.12)).
    pub boxed: Vec<Interval>,
    /// A marked subset `{ m + B r : r in sub.r } ∩ sub.boxed` carried along with the same
    /// centre, basis and Jacobians (spec eq. (5.14)): e.g. the image of the initial centre,
    /// which the Krawczyk test needs beside the image of the whole box.
    pub sub: Option<SubSet>,
}

crate::readable::readable_debug!(LohnerSet {
    m: dbg,
    b: dbg,
    r: iv,
    boxed: iv,
    sub: dbg
});

/// The marked subset of a [`LohnerSet`]: its own `[r]` (inside the set's) and box.
#[derive(Clone)]
pub struct SubSet {
    /// The subset's `[r_S]` (spec eq. (5.14)).
    pub r: Vec<Interval>,
    /// The subset's box `[x_S]`.
    pub boxed: Vec<Interval>,
}

crate::readable::readable_debug!(SubSet { r: iv, boxed: iv });

/// `x - m` in intervals.
pub(super) fn relative(x: &[Interval], m: &[f64]) -> Vec<Interval> {
    x.iter().zip(m).map(|(v, c)| *v - point(*c)).collect()
}

impl LohnerSet {
    /// The single point `x` (exact f64 values).
    pub fn point(x: &[f64]) -> Self {
        LohnerSet {
            m: x.to_vec(),
            b: DMatrix::identity(x.len(), x.len()),
            r: vec![point(0.0); x.len()],
            boxed: x.iter().map(|v| point(*v)).collect(),
            sub: None,
        }
    }
    /// A box, as centre plus radius.
    pub fn from_box(x: &[Interval]) -> Self {
        let m: Vec<f64> = x.iter().map(|v| v.mid()).collect();
        Self::centred(&m, x)
    }
    /// The box `x` with centre `m` (a point of `x`).
    fn centred(m: &[f64], x: &[Interval]) -> Self {
        LohnerSet {
            m: m.to_vec(),
            b: DMatrix::identity(x.len(), x.len()),
            r: relative(x, m),
            boxed: x.to_vec(),
            sub: None,
        }
    }
    /// The box `x` with centre `m` (a point of `x`) and the marked subset `sub` (a box
    /// inside `x`, e.g. a single point).
    pub fn with_subset(m: &[f64], x: &[Interval], sub: &[Interval]) -> Self {
        LohnerSet {
            sub: Some(SubSet {
                r: relative(sub, m),
                boxed: sub.to_vec(),
            }),
            ..Self::centred(m, x)
        }
    }
    /// An interval box containing the set (spec eq. (5.2)): the parallelepiped's hull
    /// intersected with the box (both contain the set, so the intersection is not empty).
    pub fn hull(&self) -> Vec<Interval> {
        self.hull_of(&self.r, &self.boxed)
    }
    /// A box containing the marked subset, if there is one.
    pub fn sub_hull(&self) -> Option<Vec<Interval>> {
        self.sub.as_ref().map(|s| self.hull_of(&s.r, &s.boxed))
    }
    pub(super) fn hull_of(&self, r: &[Interval], boxed: &[Interval]) -> Vec<Interval> {
        let br = linalg::mul_vec(&linalg::imat(&self.b), r);
        self.m
            .iter()
            .zip(br)
            .zip(boxed)
            .map(|((c, x), bx)| {
                let p = point(*c) + x;
                let both = p.intersection(*bx);
                if both.is_empty() {
                    p
                } else {
                    both
                }
            })
            .collect()
    }

    /// An enclosure of `{ G(x) : x in the set }` by the centred form
    /// `G(m) + (DG([X]) B) [r]`, intersected with `G([X])` (spec eq. (5.12)); `g_jac` is the
    /// tape of `(G, DG)` (`G` then `DG` row-major). `None` if an evaluation is not proved.
    pub fn image(&self, g_jac: &crate::tape::Tape) -> Option<Vec<Interval>> {
        let d = self.m.len();
        let k = g_jac.n_outputs() / (d + 1);
        let at_m = g_jac.eval_checked(&self.m.iter().map(|x| point(*x)).collect::<Vec<_>>())?;
        let over = g_jac.eval_checked(&self.hull())?;
        let dg: IMat = (0..k)
            .map(|i| over[k + i * d..k + (i + 1) * d].to_vec())
            .collect();
        let lin = linalg::mul_vec(&linalg::mul(&dg, &linalg::imat(&self.b)), &self.r);
        let out: Vec<Interval> = (0..k)
            .map(|i| {
                let c = at_m[i] + lin[i];
                let both = c.intersection(over[i]);
                if both.is_empty() {
                    c
                } else {
                    both
                }
            })
            .collect();
        out.iter().all(|x| finite(*x)).then_some(out)
    }
}

/// The derivative `D x(t) / D x(0)` carried as `C + B [R]` (spec eq. (5.15)): `C` a float
/// matrix, `B` the state set's basis, `[R]` interval columns.
pub(super) struct JacobianSet {
    pub(super) c: DMatrix<f64>,
    pub(super) r: IMat,
}

impl JacobianSet {
    pub(super) fn identity(d: usize) -> Self {
        JacobianSet {
            c: DMatrix::identity(d, d),
            r: vec![vec![point(0.0); d]; d],
        }
    }
    /// (5.15) One step: `[J]` the step's derivative factor, `ba = [B'^{-1}][J B]` and
    /// `b_inv = [B'^{-1}]` from the state's update (5.10).
    pub(super) fn step(&self, jac: &IMat, ba: &IMat, b_inv: &IMat) -> Self {
        let jc = linalg::mul(jac, &linalg::imat(&self.c));
        let c = linalg::mid(&jc);
        let off: IMat = jc
            .iter()
            .enumerate()
            .map(|(i, row)| {
                row.iter()
                    .enumerate()
                    .map(|(j, x)| *x - point(c[(i, j)]))
                    .collect()
            })
            .collect();
        let r = linalg::add(&linalg::mul(ba, &self.r), &linalg::mul(b_inv, &off));
        JacobianSet { c, r }
    }
    /// `C + [B][R]` in intervals.
    pub(super) fn hull(&self, b: &DMatrix<f64>) -> IMat {
        linalg::add(
            &linalg::imat(&self.c),
            &linalg::mul(&linalg::imat(b), &self.r),
        )
    }
}
