//! The set representation ([spec eqs. (5.1)](crate::spec::enclosure), (5.10'), (5.15)): Lohner's parallelepiped in
//! two parts (a doubleton) with a box, its marked subset, and the derivative carried as
//! `C + B [R]`.

use super::ival::Ival;
use super::linalg::{self, IMat};
use inari::Interval;
use nalgebra::DMatrix;

/// A set `{ m + C r0 + B r : r0 in [r0], r in [r] } ∩ boxed` (a doubleton: Lohner's
/// parallelepiped in two parts, and a box, all enclosures of the same states; [spec eq.
/// (5.1)](crate::spec::enclosure)): `m`, `C` and `B` are exact f64 data, `[r0]` and `[r]` interval vectors that
/// contain 0. `C r0` is the propagated part (the initial set, and the errors folded into it
/// by a reorganisation, [spec (5.10')](crate::spec::enclosure)); `B r` gathers the errors of the steps since.
#[derive(Clone, PartialEq)]
pub struct LohnerSet<I: Ival = Interval> {
    /// The centre `m` (exact data: f64 at 53 bits).
    pub m: Vec<I::Pt>,
    /// The basis `C` of the propagated part, `d x d` (exact f64 data).
    pub c: DMatrix<f64>,
    /// `[r0]`, containing 0.
    pub r0: Vec<I>,
    /// The basis `B` of the error part, `d x d` (exact f64 data).
    pub b: DMatrix<f64>,
    /// `[r]`, containing 0.
    pub r: Vec<I>,
    /// A box that also contains every state of the set (the box of [spec eq. (5.12)](crate::spec::enclosure)).
    pub boxed: Vec<I>,
    /// A marked subset `{ m + C r0 + B r : r0 in sub.r0, r in sub.r } ∩ sub.boxed` carried
    /// along with the same centre, bases and Jacobians ([spec eq. (5.14)](crate::spec::enclosure)): e.g. the image of
    /// the initial centre, which the Krawczyk test needs beside the image of the whole box.
    pub sub: Option<SubSet<I>>,
}

impl<I: Ival> std::fmt::Debug for LohnerSet<I> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use super::show::Show;
        f.debug_struct("LohnerSet")
            .field("m", &self.m)
            .field("c", &self.c)
            .field("r0", &Show(&self.r0))
            .field("b", &self.b)
            .field("r", &Show(&self.r))
            .field("boxed", &Show(&self.boxed))
            .field("sub", &self.sub)
            .finish()
    }
}

/// The marked subset of a [`LohnerSet`]: its own `[r0]`, `[r]` (inside the set's) and box.
#[derive(Clone, PartialEq)]
pub struct SubSet<I = Interval> {
    /// The subset's `[r0_S]` ([spec eq. (5.14)](crate::spec::enclosure)).
    pub r0: Vec<I>,
    /// The subset's `[r_S]` ([spec eq. (5.14)](crate::spec::enclosure)).
    pub r: Vec<I>,
    /// The subset's box `[x_S]`.
    pub boxed: Vec<I>,
}

impl<I: Ival> std::fmt::Debug for SubSet<I> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use super::show::Show;
        f.debug_struct("SubSet")
            .field("r0", &Show(&self.r0))
            .field("r", &Show(&self.r))
            .field("boxed", &Show(&self.boxed))
            .finish()
    }
}

/// `x - m` in intervals.
pub(super) fn relative<I: Ival>(x: &[I], m: &[I::Pt]) -> Vec<I> {
    x.iter().zip(m).map(|(v, c)| *v - I::pt(*c)).collect()
}

impl<I: Ival> LohnerSet<I> {
    /// The single point `x` (exact f64 values).
    pub fn point(x: &[f64]) -> Self {
        Self::point_at(&x.iter().map(|v| I::pt_of(*v)).collect::<Vec<_>>())
    }
    /// The single point `x` (exact points of this precision).
    pub fn point_at(x: &[I::Pt]) -> Self {
        let d = x.len();
        LohnerSet {
            m: x.to_vec(),
            c: DMatrix::identity(d, d),
            r0: vec![I::zero(); d],
            b: DMatrix::identity(d, d),
            r: vec![I::zero(); d],
            boxed: x.iter().map(|v| I::pt(*v)).collect(),
            sub: None,
        }
    }
    /// A box, as centre plus radius.
    pub fn from_box(x: &[I]) -> Self {
        let m: Vec<I::Pt> = x.iter().map(|v| v.mid_pt()).collect();
        Self::centred(&m, x)
    }
    /// The box `x` with centre `m` (a point of `x`): `x - m` in the propagated part.
    fn centred(m: &[I::Pt], x: &[I]) -> Self {
        let d = x.len();
        LohnerSet {
            m: m.to_vec(),
            c: DMatrix::identity(d, d),
            r0: relative(x, m),
            b: DMatrix::identity(d, d),
            r: vec![I::zero(); d],
            boxed: x.to_vec(),
            sub: None,
        }
    }
    /// The box `x` with centre `m` (a point of `x`) and the marked subset `sub` (a box
    /// inside `x`, e.g. a single point).
    pub fn with_subset(m: &[I::Pt], x: &[I], sub: &[I]) -> Self {
        LohnerSet {
            sub: Some(SubSet {
                r0: relative(sub, m),
                r: vec![I::zero(); m.len()],
                boxed: sub.to_vec(),
            }),
            ..Self::centred(m, x)
        }
    }
    /// An interval box containing the set ([spec eq. (5.2)](crate::spec::enclosure)): the parallelepiped's hull
    /// intersected with the box (both contain the set, so the intersection is not empty).
    pub fn hull(&self) -> Vec<I> {
        self.hull_of(&self.r0, &self.r, &self.boxed)
    }
    /// A box containing the marked subset, if there is one.
    pub fn sub_hull(&self) -> Option<Vec<I>> {
        self.sub
            .as_ref()
            .map(|s| self.hull_of(&s.r0, &s.r, &s.boxed))
    }
    /// `(m + [C] r0 + [B] r) ∩ boxed`.
    pub(super) fn hull_of(
        &self,
        r0: &[I],
        r: &[I],
        boxed: &[I],
    ) -> Vec<I> {
        let cr0 = linalg::mul_vec(&linalg::imat::<I>(&self.c), r0);
        let br = linalg::mul_vec(&linalg::imat::<I>(&self.b), r);
        self.m
            .iter()
            .zip(cr0.iter().zip(br))
            .zip(boxed)
            .map(|((c, (x0, x)), bx)| {
                let p = I::pt(*c) + (*x0 + x);
                let both = p.intersection(*bx);
                if both.is_empty() {
                    p
                } else {
                    both
                }
            })
            .collect()
    }

    /// (5.10') Reorganisation: `C r0 + B r = B (B^-1 C r0 + r)`, so the same set (and
    /// marked subset) is `C := B`, `[r0] := ([B^-1] C) [r0] + [r]`, `B := I`, `[r] := 0`,
    /// with `b_inv ∋ B^-1` (5.9). Returns the old `B`, which the derivative carried in
    /// this basis (5.15) needs.
    pub(super) fn reorganise(&mut self, b_inv: &IMat<I>) -> DMatrix<f64> {
        let d = self.m.len();
        let bc = linalg::mul(b_inv, &linalg::imat(&self.c));
        let fold = |r0: &[I], r: &[I]| -> Vec<I> {
            linalg::mul_vec(&bc, r0)
                .iter()
                .zip(r)
                .map(|(a, b)| *a + *b)
                .collect()
        };
        self.r0 = fold(&self.r0, &self.r);
        self.r = vec![I::zero(); d];
        if let Some(sb) = &mut self.sub {
            sb.r0 = fold(&sb.r0, &sb.r);
            sb.r = vec![I::zero(); d];
        }
        let b = std::mem::replace(&mut self.b, DMatrix::identity(d, d));
        self.c = b.clone();
        b
    }

    /// (12.0.9) The states from a part of the initial set, around another initial centre.
    /// For a set flown without reorganisation (5.10'), the state from the initial point
    /// `c + a`, `a in [r0]`, lies in `m + C a + B [r]`. For an initial point `c' + a'` with
    /// `c' - c in shift` and `a' in r0` (`r0` containing 0, and `shift + r0` inside the
    /// set's `[r0]`), it lies in `w + C a' + B [r]`, `w = m + C shift`, so in
    /// `m' + C a' + B ([r] + [B^-1] (w - m'))` with `m' = mid(w)`. `None` when `B^-1`
    /// is not enclosed (5.9). The marked subset is dropped; the box still holds every state.
    pub(crate) fn moved(&self, shift: &[I], r0: Vec<I>) -> Option<Self> {
        let c = linalg::imat::<I>(&self.c);
        let cs = linalg::mul_vec(&c, shift);
        let w: Vec<I> = self.m.iter().zip(&cs).map(|(m, x)| I::pt(*m) + *x).collect();
        let m: Vec<I::Pt> = w.iter().map(|x| x.mid_pt()).collect();
        let e = relative(&w, &m);
        let b_inv = linalg::enclose_inverse::<I>(&self.b, &self.b.clone().try_inverse()?)?;
        let r: Vec<I> = self
            .r
            .iter()
            .zip(linalg::mul_vec(&b_inv, &e))
            .map(|(a, b)| *a + b)
            .collect();
        if !w.iter().chain(&r).all(|x| x.is_finite()) {
            return None;
        }
        Some(LohnerSet {
            m,
            c: self.c.clone(),
            r0,
            b: self.b.clone(),
            r,
            boxed: self.boxed.clone(),
            sub: None,
        })
    }

    /// An enclosure of `{ G(x) : x in the set }` by the centred form
    /// `G(m) + (DG([X]) C) [r0] + (DG([X]) B) [r]`, intersected with `G([X])` ([spec eq. (5.12)](crate::spec::enclosure)); `g_jac` is the
    /// tape of `(G, DG)` (`G` then `DG` row-major). `None` if an evaluation is not proved.
    pub fn image(&self, g_jac: &crate::tape::Tape) -> Option<Vec<I>> {
        let d = self.m.len();
        let k = g_jac.n_outputs() / (d + 1);
        let at_m = g_jac.eval_checked(&self.m.iter().map(|x| I::pt(*x)).collect::<Vec<_>>())?;
        let over = g_jac.eval_checked(&self.hull())?;
        let dg = IMat::from_flat(k, d, over[k..k + k * d].to_vec());
        let lin0 = linalg::mul_vec(&linalg::mul(&dg, &linalg::imat(&self.c)), &self.r0);
        let lin1 = linalg::mul_vec(&linalg::mul(&dg, &linalg::imat(&self.b)), &self.r);
        let lin: Vec<I> = lin0.iter().zip(&lin1).map(|(a, b)| *a + *b).collect();
        let out: Vec<I> = (0..k)
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
        out.iter().all(|x| x.is_finite()).then_some(out)
    }
}

/// The derivative `D x(t) / D x(0)` carried as `C + B [R]` ([spec eq. (5.15)](crate::spec::enclosure)): `C` a float
/// matrix, `B` the state set's basis, `[R]` interval columns.
pub(super) struct JacobianSet<I> {
    pub(super) c: DMatrix<f64>,
    pub(super) r: IMat<I>,
}

impl<I: Ival> JacobianSet<I> {
    /// (5.15) One step: `[J]` the step's derivative factor, `ba = [B'^{-1}][J B]` and
    /// `b_inv = [B'^{-1}]` from the state's update (5.10).
    pub(super) fn step(&self, jac: &IMat<I>, ba: &IMat<I>, b_inv: &IMat<I>) -> Self {
        let (c, off) = linalg::split(&linalg::mul(jac, &linalg::imat(&self.c)));
        let r = linalg::add(&linalg::mul(ba, &self.r), &linalg::mul(b_inv, &off));
        JacobianSet { c, r }
    }
    /// (5.15) The first step, from the identity (`C = I`, `[R] = 0`): `[J] I` is `[J]` and
    /// `ba 0` is 0, so only `[B'^{-1}]` times the split's interval part is computed.
    pub(super) fn first(jac: &IMat<I>, b_inv: &IMat<I>) -> Self {
        let (c, off) = linalg::split(jac);
        JacobianSet {
            c,
            r: linalg::mul(b_inv, &off),
        }
    }
    /// The same derivative after the state's reorganisation ([spec (5.10')](crate::spec::enclosure)) replaced the
    /// basis `B` by `I`: `C + B [R] ⊂ C + I ([B] [R])`.
    pub(super) fn rebase(&self, b: &DMatrix<f64>) -> Self {
        JacobianSet {
            c: self.c.clone(),
            r: linalg::mul(&linalg::imat(b), &self.r),
        }
    }
    /// `C + [B][R]` in intervals.
    pub(super) fn hull(&self, b: &DMatrix<f64>) -> IMat<I> {
        linalg::add(
            &linalg::imat(&self.c),
            &linalg::mul(&linalg::imat(b), &self.r),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::{iv, point};

    /// (5.10'): after the reorganisation the set still holds every point
    /// `m + C a + B b` (a, b corners of `[r0]`, `[r]`), its marked subset every point of the
    /// subset, and the new bases are `C = old B`, `B = I`.
    #[test]
    fn reorganisation_keeps_every_point_of_the_set_and_its_subset() {
        let m = vec![1.0, -2.0, 0.5];
        let c = DMatrix::from_row_slice(3, 3, &[2.0, 1.0, 0.0, 0.5, 3.0, -1.0, 0.0, 1.0, 1.0]);
        let b = DMatrix::from_row_slice(3, 3, &[1.0, 0.2, 0.0, 0.1, 1.0, 0.3, 0.0, 0.4, 1.0]);
        let sym = |r: &[f64]| r.iter().map(|x| iv(-x, *x)).collect::<Vec<_>>();
        let (r0, r) = (sym(&[1e-3, 2e-3, 5e-4]), sym(&[1e-4, 3e-5, 2e-4]));
        let (sub_r0, sub_r) = (sym(&[1e-5, 0.0, 1e-5]), sym(&[0.0, 1e-6, 1e-6]));
        let b_inv = b
            .clone()
            .try_inverse()
            .and_then(|x| linalg::enclose_inverse(&b, &x))
            .unwrap();
        let mut set = LohnerSet {
            m: m.clone(),
            c: c.clone(),
            r0: r0.clone(),
            b: b.clone(),
            r: r.clone(),
            boxed: vec![iv(-10.0, 10.0); 3],
            sub: Some(SubSet {
                r0: sub_r0.clone(),
                r: sub_r.clone(),
                boxed: vec![iv(-10.0, 10.0); 3],
            }),
        };
        let before = set.hull();
        let old_b = set.reorganise(&b_inv);
        assert_eq!(old_b, b);
        assert_eq!(set.c, b);
        assert_eq!(set.b, DMatrix::identity(3, 3));
        assert!(set.r.iter().all(|x| x.inf() == 0.0 && x.sup() == 0.0));
        let (after, sub_after) = (set.hull(), set.sub_hull().unwrap());
        // every corner combination, enclosed in intervals from the exact data
        let corners = |r: &[Interval], k: usize| -> Vec<Interval> {
            (0..3)
                .map(|i| point(if k >> i & 1 == 1 { r[i].sup() } else { r[i].inf() }))
                .collect()
        };
        for (r0, r, hull) in [(&r0, &r, &after), (&sub_r0, &sub_r, &sub_after)] {
            for ka in 0..8 {
                for kb in 0..8 {
                    let ca = linalg::mul_vec(&linalg::imat(&c), &corners(r0, ka));
                    let bb = linalg::mul_vec(&linalg::imat(&b), &corners(r, kb));
                    for i in 0..3 {
                        let x = point(m[i]) + ca[i] + bb[i];
                        assert!(
                            !x.intersection(hull[i]).is_empty(),
                            "corner ({ka}, {kb}), component {i}: [{}, {}] outside [{}, {}]",
                            x.inf(),
                            x.sup(),
                            hull[i].inf(),
                            hull[i].sup()
                        );
                    }
                }
            }
        }
        // not vacuous: the fold wraps C r0 into B's frame, a few times wider at most here
        for (a, b) in after.iter().zip(&before) {
            assert!(a.wid() < 4.0 * b.wid(), "{} against {}", a.wid(), b.wid());
        }
    }

    /// (12.0.9): the set moved to another initial centre holds the state of every initial
    /// point it keeps, `m + C (shift + a') + B b` for the corners `a'` of the new `[r0]` and
    /// `b` of `[r]` (enclosed in double-double intervals from the exact data, a few ulps of
    /// 2^-106 wide, so that each lies inside the moved set's f64 hull only if that hull holds
    /// the exact state), and is narrower than the whole set. The shift `0.1` makes
    /// `m + C shift` round in f64, so that the rounding is carried by `[r]`.
    #[test]
    fn a_moved_set_holds_the_states_of_the_initial_points_it_keeps() {
        use crate::precision::dd::DdInterval;
        let m = vec![1.0, -2.0, 0.5];
        let c = DMatrix::from_row_slice(3, 3, &[3.0, 0.7, 0.0, 0.5, 3.0, -1.1, 0.0, 1.3, 1.0]);
        let b = DMatrix::from_row_slice(3, 3, &[1.0, 0.2, 0.0, 0.1, 1.0, 0.3, 0.0, 0.4, 1.0]);
        let sym = |r: &[f64]| r.iter().map(|x| iv(-x, *x)).collect::<Vec<_>>();
        let set = LohnerSet {
            m: m.clone(),
            c: c.clone(),
            r0: sym(&[0.5, 0.25, 0.125]),
            b: b.clone(),
            r: sym(&[1e-6, 2e-6, 1e-6]),
            boxed: vec![iv(-10.0, 10.0); 3],
            sub: None,
        };
        let shift = [0.1, -0.1, 0.0];
        let r0 = sym(&[0.2, 0.1, 0.05]);
        let moved = set
            .moved(&shift.map(point), r0.clone())
            .expect("B is well conditioned");
        assert!(moved.r.iter().all(|x| x.contains(0.0)));
        assert_eq!(moved.r0, r0);
        let (hull, whole) = (moved.hull(), set.hull());
        let dd = |x: f64| DdInterval::from_f64(x);
        let corner = |r: &[Interval], k: usize, i: usize| {
            if k >> i & 1 == 1 {
                r[i].sup()
            } else {
                r[i].inf()
            }
        };
        for ka in 0..8 {
            for kb in 0..8 {
                for i in 0..3 {
                    let mut x = dd(m[i]);
                    for j in 0..3 {
                        x = x + dd(c[(i, j)]) * (dd(shift[j]) + dd(corner(&r0, ka, j)));
                        x = x + dd(b[(i, j)]) * dd(corner(&set.r, kb, j));
                    }
                    let h = DdInterval::from_f64_pair(hull[i].inf(), hull[i].sup()).unwrap();
                    assert!(x.subset(h), "corners {ka}, {kb}: component {i}: {x} is not in {h}");
                }
            }
        }
        for (a, w) in hull.iter().zip(&whole) {
            assert!(a.wid() < 0.6 * w.wid(), "{} against {}", a.wid(), w.wid());
        }
    }
}
