//! The steps' errors in product form ([spec (5.10''')](crate::spec::enclosure)): a second enclosure of a
//! flow's final set, read back over the steps, in which no step's error is wrapped by a
//! basis.

use super::ival::Ival;
use super::linalg::{self, IMat};
use super::set::LohnerSet;
use nalgebra::DMatrix;

/// What a flow leaves for the flow that continues it from its final set (a dense flow's
/// next leg, [spec (5.16)](crate::spec::enclosure)): the step rule's memory (5.8) (the last accepted step that was not
/// a final one, and its remainder's width relative to the tolerance), and the steps for the
/// product form (5.10''') with the centre they end at.
pub(crate) struct Memo<I: Ival> {
    pub(super) step: Option<(f64, f64)>,
    pub(super) links: Vec<Link<I>>,
    pub(super) end: Vec<I::Pt>,
    /// The box of the set at `end` before (5.10''') narrowed it: the set the next leg
    /// starts from, so that the steps of a dense flow are those of a single flow's.
    pub(super) boxed: Option<Vec<I>>,
}

impl<I: Ival> Default for Memo<I> {
    fn default() -> Self {
        Memo {
            step: None,
            links: Vec::new(),
            end: Vec::new(),
            boxed: None,
        }
    }
}

/// One accepted step as the product form reads it: the set before the step (its `C`,
/// `[r0]`, `B`, `[r]`), the step's derivative factor `[J]` (over that set's hull) and the
/// enclosure `[e]` of `x(h; m) - m'` (the new centre's error, not joined with 0).
pub(super) struct Link<I> {
    pub(super) c: DMatrix<f64>,
    pub(super) r0: Vec<I>,
    pub(super) b: DMatrix<f64>,
    pub(super) r: Vec<I>,
    pub(super) jac: DMatrix<f64>,
    pub(super) err: Vec<I>,
}

/// (5.10''') Narrows the box of `set` (the set after the last link) by the enclosures
/// `m_N + ([P_k] C_k) [r0_k] + ([P_k] B_k) [r_k] + [S_k]` with `[P_k] = M_N ... M_{k+1}`
/// (the links' float matrices) and `[S_k] = sum_{j > k} [P_j] [f_j]`, read from the last
/// link back over at most `most` links, at the links whose set has `[r] = 0` and at the
/// first of those. Stops once `[S_k]`
/// alone is wider than the box in every component (no earlier enclosure can be
/// narrower: `[S]` only grows going back) or stops being finite.
pub(super) fn narrow<I: Ival>(set: &mut LohnerSet<I>, chain: &[Link<I>], most: usize) {
    let d = set.m.len();
    if chain.len() < 2 || set.sub.is_some() {
        return;
    }
    let mut best = set.hull();
    let mut p: IMat<I> = linalg::identity(d);
    let mut s = vec![I::zero(); d];
    let add = |a: &[I], b: &[I]| -> Vec<I> { a.iter().zip(b).map(|(x, y)| *x + *y).collect() };
    // at most `most` links back (4 per step of the flow that ends here: a dense flow's many
    // short legs would otherwise read the whole chain at every stop)
    let chain = &chain[chain.len().saturating_sub(most)..];
    for link in chain.iter().rev() {
        s = add(&s, &linalg::mul_vec(&p, &link.err));
        p = linalg::mul(&p, &linalg::imat(&link.jac));
        if !linalg::all_finite(&p) || !s.iter().all(|x| x.is_finite()) {
            break;
        }
        // the enclosures from the sets whose error part is empty (the first, and those
        // just reorganised: `[r] = 0`), and from the first link
        let fresh = link.r.iter().all(|x| x.is_exact_zero());
        let first = std::ptr::eq(link, &chain[0]);
        if !(fresh || first) {
            continue;
        }
        let pc = linalg::mul(&p, &linalg::imat(&link.c));
        let mut e = add(&linalg::mul_vec(&pc, &link.r0), &s);
        if !fresh {
            let pb = linalg::mul(&p, &linalg::imat(&link.b));
            e = add(&e, &linalg::mul_vec(&pb, &link.r));
        }
        for i in 0..d {
            let both = best[i].intersection(I::pt(set.m[i]) + e[i]);
            if !both.is_empty() {
                best[i] = both;
            }
        }
        if s.iter().zip(&best).all(|(x, b)| x.wid() > b.wid()) {
            break;
        }
    }
    // the centre stays in the box (the next flow's mean-value segments start there, (5.6b))
    set.boxed = best
        .iter()
        .zip(&set.m)
        .map(|(x, c)| x.convex_hull(I::pt(*c)))
        .collect();
}
