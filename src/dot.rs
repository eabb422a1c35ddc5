//! Interval kernels: dot products, Horner's scheme, rows of matrix products and quotients,
//! where the Taylor method spends its arithmetic ([spec (1.4)](crate::spec::scalars)). The crate's one module with
//! `unsafe` ([spec/design.md](crate::spec::design)).
//!
//! Each kernel has one claim and two paths that give the same doubles: the portable chains of
//! inari's fused multiply-adds, each rounded outward, and, where the target has AVX-512,
//! a path computing those chains' tightest ends with the fused multiply-add (or division)
//! rounded upward by the instruction: eight entries, or eight terms, at a time in vectors; a
//! dot product of at most three terms, and a quotient, in scalars (there the vector set-up
//! costs more than it saves, while for longer rows the vectors pay). Any input not finite
//! sends the call down the portable path.

use inari::Interval;

/// `acc + sum_j x_j y_j` when `!neg`, `acc - sum_j x_j y_j` when `neg`; `y_j` is
/// `y[y.len() - 1 - j]` when `rev`. `x` and `y` have the same length. Summed as [`chain`]
/// sums: one chain up to [`LANES`] terms, [`LANES`] chains added pairwise above.
///
/// # Containment
/// Spec (1.4): the result contains the real value for every choice of reals in the
/// intervals `acc`, `x_j`, `y_j`.
pub(crate) fn dot(acc: Interval, neg: bool, x: &[Interval], y: &[Interval], rev: bool) -> Interval {
    debug_assert_eq!(x.len(), y.len());
    #[cfg(all(
        target_arch = "x86_64",
        target_feature = "avx512f",
        target_feature = "avx512dq"
    ))]
    if let Some(s) = wide::sum(acc, neg, x, y, rev) {
        return s;
    }
    chain(acc, neg, x, y, rev)
}

/// `a / b` for an interval `b` without 0: inari's quotient (the tightest interval), with
/// AVX-512 computed from the signs of the ends without inari's case dispatch ([spec (1.4)](crate::spec::scalars)).
/// Any other `b` (containing 0, empty, unbounded) or an unbounded `a` is inari's `a / b`.
pub(crate) fn quotient(a: Interval, b: Interval) -> Interval {
    #[cfg(all(
        target_arch = "x86_64",
        target_feature = "avx512f",
        target_feature = "avx512dq"
    ))]
    if let Some(q) = wide::quotient(a, b) {
        return q;
    }
    a / b
}

/// Horner's scheme for many polynomials at once: entry `i` encloses
/// `sum_k rows[k][i] t^k` for every `t` in `h` and every choice of reals in the
/// coefficients (`rows[k]` all of one length). Each step `s <- s h + c` is inari's fused
/// multiply-add, or with AVX-512 the same tightest interval computed eight entries at a
/// time ([spec (1.4)](crate::spec::scalars)): the answers are the same.
pub(crate) fn horner(rows: &[&[Interval]], h: Interval) -> Vec<Interval> {
    let mut out = Vec::new();
    lanewise(rows, Scheme::Horner(h), &mut out);
    out
}

/// One row of a matrix product, appended to `out`: entry `j` encloses
/// `sum_l a_l rows[l][j]` (`rows[l]` all of one length), each term added by inari's fused
/// multiply-add in the order of `l`, or with AVX-512 the same tightest intervals computed
/// eight entries at a time ([spec (1.4)](crate::spec::scalars)).
pub(crate) fn row_times(a: &[Interval], rows: &[&[Interval]], out: &mut Vec<Interval>) {
    lanewise(rows, Scheme::Row(a), out)
}

/// What [`lanewise`] computes for each entry: Horner's scheme at `h`, or a row times a
/// matrix.
#[derive(Clone, Copy)]
enum Scheme<'a> {
    Horner(Interval),
    Row(&'a [Interval]),
}

/// The scheme for every entry of the rows: with AVX-512 eight entries at a time, otherwise
/// (or when an input is not finite) inari's chain of fused multiply-adds, entry by entry.
/// The entries are appended to `out`.
fn lanewise(rows: &[&[Interval]], scheme: Scheme, out: &mut Vec<Interval>) {
    #[cfg(all(
        target_arch = "x86_64",
        target_feature = "avx512f",
        target_feature = "avx512dq"
    ))]
    if wide::lanewise(rows, scheme, out) {
        return;
    }
    let len = rows.first().map_or(0, |r| r.len());
    out.extend((0..len).map(|i| {
        match scheme {
            Scheme::Horner(h) => rows.iter().rev().fold(ZERO, |s, r| s.mul_add(h, r[i])),
            Scheme::Row(a) => a
                .iter()
                .zip(rows)
                .fold(ZERO, |s, (x, r)| x.mul_add(r[i], s)),
        }
    }))
}

const ZERO: Interval = inari::const_interval!(0.0, 0.0);

/// The chains of a dot product: eight, one per lane of an AVX-512 vector of doubles.
pub(crate) const LANES: usize = 8;

/// The portable path: one inari fused multiply-add per term, each outward rounded. Up to
/// [`LANES`] terms in one chain from `acc`; more into [`LANES`] chains (term `j` into chain
/// `j mod LANES`; chain 0 starts from `acc`, the others from 0), then the chains added
/// pairwise, `((c0 + c1) + (c2 + c3)) + ((c4 + c5) + (c6 + c7))`, each sum outward rounded.
/// Independent chains let the vector path run eight terms at once (one chain through every
/// term made the fuzz target `precision_step` wait on each term's rounding in turn), and the
/// pairwise sum waits on three roundings instead of seven; a short product keeps one chain,
/// whose fewer roundings matter where the terms are points (a centre's series at 53 bits).
pub(crate) fn chain(
    acc: Interval,
    neg: bool,
    x: &[Interval],
    y: &[Interval],
    rev: bool,
) -> Interval {
    let n = x.len().min(y.len());
    let term = |j: usize| {
        let yj = if rev { y[n - 1 - j] } else { y[j] };
        let xj = if neg { -x[j] } else { x[j] };
        (xj, yj)
    };
    if n <= LANES {
        return (0..n).fold(acc, |s, j| {
            let (xj, yj) = term(j);
            xj.mul_add(yj, s)
        });
    }
    let mut lanes = [ZERO; LANES];
    lanes[0] = acc;
    for j in 0..n {
        let (xj, yj) = term(j);
        lanes[j % LANES] = xj.mul_add(yj, lanes[j % LANES]);
    }
    pairwise(&lanes, 0, LANES)
}

/// The pairwise sum of `lanes[k .. k + w]` (`w` a power of 2), as [`chain`] adds its chains.
fn pairwise(lanes: &[Interval; LANES], k: usize, w: usize) -> Interval {
    if w == 1 {
        lanes[k]
    } else {
        let h = w / 2;
        pairwise(lanes, k, h) + pairwise(lanes, k + h, h)
    }
}

#[cfg(all(
    target_arch = "x86_64",
    target_feature = "avx512f",
    target_feature = "avx512dq"
))]
mod wide {
    use super::Scheme;
    use inari::Interval;
    use std::arch::x86_64::*;
    use std::sync::OnceLock;

    const UP: i32 = _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC;

    // inari stores an interval [a, b] as the two doubles (-a, b), `#[repr(C)]` (inari 2.0,
    // `src/interval.rs`). Reading its bytes as two f64 is defined whatever they hold (16 bytes,
    // any bit pattern is a double); what they mean is checked once, by `layout_known`.
    const _: () = assert!(std::mem::size_of::<Interval>() == 16);
    const _: () = assert!(std::mem::align_of::<Interval>() >= 8);

    fn raw(x: &[Interval]) -> &[f64] {
        // SAFETY: `Interval` is 16 bytes, aligned to at least 8 (asserted above), with no
        // padding (it holds one 128-bit vector); `2 x.len()` doubles cover exactly the
        // borrowed memory, and every bit pattern is a valid f64.
        unsafe { std::slice::from_raw_parts(x.as_ptr().cast::<f64>(), 2 * x.len()) }
    }

    /// True when the bytes of an interval are (-inf, sup), as inari 2.0 stores them.
    pub(super) fn layout_known() -> bool {
        static KNOWN: OnceLock<bool> = OnceLock::new();
        *KNOWN.get_or_init(|| {
            [(-1.5, 2.25), (3.0, 5.0), (-7.0, -0.125), (0.0, 0.0)]
                .into_iter()
                .all(|(a, b)| match Interval::try_from((a, b)) {
                    Ok(x) => raw(&[x]) == [-a, b],
                    Err(_) => false,
                })
        })
    }

    /// `acc ± sum_j x_j y_j` (`y` backwards when `rev`), or `None` when an input is not
    /// finite or the sum overflows.
    pub(super) fn sum(
        acc: Interval,
        neg: bool,
        x: &[Interval],
        y: &[Interval],
        rev: bool,
    ) -> Option<Interval> {
        if x.len() != y.len() || !layout_known() {
            return None;
        }
        // SAFETY: this module is compiled only when the target has avx512f and avx512dq.
        let (hi, nlo) = if x.len() <= SHORT {
            unsafe { terms(raw(&[acc]), neg, raw(x), raw(y), rev) }?
        } else if x.len() <= super::LANES {
            unsafe { one_chain(raw(&[acc]), neg, raw(x), raw(y), rev) }?
        } else {
            unsafe { lanes(raw(&[acc]), neg, raw(x), raw(y), rev) }?
        };
        Interval::try_from((-nlo, hi)).ok()
    }

    const SHORT: usize = 3;

    /// A dot product of at most [`SHORT`] terms (there the vector set-up costs more than it
    /// saves) in one chain, in scalars: the end
    /// product that bounds each term above (below) chosen from the signs of the ends, as in
    /// the case table of interval multiplication (for `[a, b] [c, d]` the upper bound is
    /// `b d` when `a >= 0` and `c >= 0`, `a d` when `a >= 0 >= d`, ..., and `max(a c, b d)`
    /// when both straddle 0, then both are formed); the chains `U <- RU(e_up + U)` and
    /// `D <- RU(-e_down + D)` side by side: inari's chain, the same doubles.
    #[target_feature(enable = "avx512f")]
    fn terms(acc: &[f64], neg: bool, x: &[f64], y: &[f64], rev: bool) -> Option<(f64, f64)> {
        let n = x.len() / 2;
        let (mut up, mut down) = (acc[1], acc[0]);
        for j in 0..n {
            let k = if rev { n - 1 - j } else { j };
            let (a, b) = if neg {
                (-x[2 * j + 1], x[2 * j])
            } else {
                (-x[2 * j], x[2 * j + 1])
            };
            let (c, d) = (-y[2 * k], y[2 * k + 1]);
            if !(a.is_finite() && b.is_finite() && c.is_finite() && d.is_finite()) {
                return None;
            }
            let (xp, yp) = (a >= 0.0, c >= 0.0);
            let (xn, yn) = (b <= 0.0 && !xp, d <= 0.0 && !yp);
            let (xm, ym) = (!xp && !xn, !yp && !yn);
            let ux = if (!xn && !yn) || (xn && yp) { b } else { a };
            let uy = if xp || (xm && !yn) { d } else { c };
            let dx = if (xp && !yp) || (xn && yn) || (xm && yn) {
                b
            } else {
                a
            };
            let dy = if xn || (xm && !yn) { d } else { c };
            let (u, w) = (up, down);
            up = fma_up(ux, uy, u);
            down = fma_up(-dx, dy, w);
            if xm && ym {
                up = up.max(fma_up(a, c, u));
                down = down.max(fma_up(-b, c, w));
            }
        }
        (up.is_finite() && down.is_finite()).then_some((up, down))
    }

    /// Index vectors that read up to eight (-inf, sup) pairs backwards: for a block of `m`
    /// pairs, lane `i < m` takes pair `m - 1 - i` (its -inf end in `REV[m].0`, its sup end in
    /// `REV[m].1`); lanes `i >= m` take lane 15, which the masked load left 0 when `m < 8`.
    const fn rev_index(m: usize, odd: usize) -> [i64; 8] {
        let mut r = [15i64; 8];
        let mut i = 0;
        while i < m {
            r[i] = (2 * (m - 1 - i) + odd) as i64;
            i += 1;
        }
        r
    }
    /// Index vectors that read eight (-inf, sup) pairs in order: the -inf ends, the sup ends.
    const FORWARD: ([i64; 8], [i64; 8]) =
        ([0, 2, 4, 6, 8, 10, 12, 14], [1, 3, 5, 7, 9, 11, 13, 15]);
    const REV: [([i64; 8], [i64; 8]); 9] = {
        let mut t = [([0i64; 8], [0i64; 8]); 9];
        let mut m = 0;
        while m <= 8 {
            t[m] = (rev_index(m, 0), rev_index(m, 1));
            m += 1;
        }
        t
    };

    /// Eight doubles from `s[from..]`, 0 in the lanes past its end.
    #[target_feature(enable = "avx512f")]
    fn load(s: &[f64], from: usize) -> __m512d {
        let m = s.len().saturating_sub(from).min(8);
        let mask = ((1u16 << m) - 1) as u8;
        // SAFETY: the lanes read are `s[from..from + m]`, in bounds; the masked-off lanes are
        // not accessed (the instruction suppresses them; LLVM's masked load does not touch
        // them).
        unsafe { _mm512_maskz_loadu_pd(mask, s.as_ptr().wrapping_add(from)) }
    }

    #[target_feature(enable = "avx512f")]
    fn vector(v: [i64; 8]) -> __m512i {
        _mm512_set_epi64(v[7], v[6], v[5], v[4], v[3], v[2], v[1], v[0])
    }

    /// `RU(a b + c)`: the fused multiply-add rounded upward.
    #[target_feature(enable = "avx512f")]
    fn fma_up(a: f64, b: f64, c: f64) -> f64 {
        _mm_cvtsd_f64(_mm_fmadd_round_sd::<UP>(
            _mm_set_sd(a),
            _mm_set_sd(b),
            _mm_set_sd(c),
        ))
    }

    /// The eight lanes of `v`.
    #[target_feature(enable = "avx512f")]
    fn store(v: __m512d) -> [f64; 8] {
        let mut out = [0.0f64; 8];
        // SAFETY: `out` holds the 8 doubles stored.
        unsafe { _mm512_storeu_pd(out.as_mut_ptr(), v) };
        out
    }

    /// `sup` and `-inf` of `acc ± sum x_j y_j`, from the (-inf, sup) pairs: the chains of
    /// [`super::chain`] (term `j` in lane `j mod 8`, lane 0 from `acc`), eight terms at a time
    /// in one vector fused multiply-add of each end product, then the lanes added pairwise;
    /// so the same doubles.
    ///
    /// A step `x y + z` of a lane forms the four end products of `x y` ([`fma`]) and keeps
    /// the largest sum: since RU is monotone and the range of a product is the hull of its
    /// end products, that is the tightest end, as inari's `mul_add`. Lanes past the last
    /// term read 0 and keep their sums (`RU(0 0 + z) = z`).
    #[target_feature(enable = "avx512f,avx512dq")]
    fn lanes(acc: &[f64], neg: bool, x: &[f64], y: &[f64], rev: bool) -> Option<(f64, f64)> {
        let n = x.len() / 2;
        let first = _mm512_mask_blend_pd(1, _mm512_setzero_pd(), _mm512_set1_pd(acc[1]));
        let first_down = _mm512_mask_blend_pd(1, _mm512_setzero_pd(), _mm512_set1_pd(acc[0]));
        let mut sums = Lanes {
            up: first,
            down: first_down,
        };
        let mut bad = 0u8;
        let mut j = 0;
        while j < n {
            let (xs, ys, b) = terms_at(x, y, j, neg, rev);
            bad |= b;
            sums = fma(xs, ys, sums);
            j += 8;
        }
        // the lanes added pairwise, as `super::chain` adds its chains: lane i to lane i + 1,
        // then i + 2, then i + 4 (lanes without terms hold 0, and adding 0 is exact)
        let mut up = sums.up;
        let mut down = sums.down;
        for (odd, even) in PAIRS {
            let (o, e) = (vector(odd), vector(even));
            up = _mm512_add_round_pd::<UP>(
                _mm512_permutexvar_pd(e, up),
                _mm512_permutexvar_pd(o, up),
            );
            down = _mm512_add_round_pd::<UP>(
                _mm512_permutexvar_pd(e, down),
                _mm512_permutexvar_pd(o, down),
            );
        }
        let (u, d) = (store(up)[0], store(down)[0]);
        (bad == 0 && u.is_finite() && d.is_finite()).then_some((u, d))
    }

    /// `sup` and `-inf` of `acc ± sum x_j y_j` for at most [`super::LANES`] terms, from the
    /// (-inf, sup) pairs: inari's one chain of fused multiply-adds, term by term in the same
    /// order, so the same doubles.
    ///
    /// The end product that bounds a term's range above (below) is chosen from the signs of
    /// the ends, eight terms at a time, as in the case table of interval multiplication:
    /// for `[a, b] [c, d]` the upper bound is `b d` when `a >= 0` and `c >= 0`, `a d` when
    /// `a >= 0 >= d`, ..., and `max(a c, b d)` when both straddle 0 (then both are formed).
    /// The two chains `U <- RU(e_up + U)` and `D <- RU(-e_down + D)` then run side by side.
    #[target_feature(enable = "avx512f,avx512dq")]
    fn one_chain(acc: &[f64], neg: bool, x: &[f64], y: &[f64], rev: bool) -> Option<(f64, f64)> {
        let n = x.len() / 2;
        if n > 8 {
            // one block only: a longer product goes elsewhere (the portable path)
            return None;
        }
        let zero = _mm512_setzero_pd();
        let (mut up, mut down) = (acc[1], acc[0]);
        let (xs, ys, bad) = terms_at(x, y, 0, neg, rev);
        // x = [xl, xh] (already negated when `neg`), y = [yl, yh]
        let (nxl, xh) = (xs.down, xs.up);
        let (nyl, yh) = (ys.down, ys.up);
        let xl = _mm512_sub_pd(zero, nxl);
        let yl = _mm512_sub_pd(zero, nyl);
        // signs: x >= 0, x <= 0 (and not >= 0), straddling; the same for y
        let xp = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(xl, zero);
        let xn = _mm512_cmp_pd_mask::<_CMP_LE_OQ>(xh, zero) & !xp;
        let xm = !xp & !xn;
        let yp = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(yl, zero);
        let yn = _mm512_cmp_pd_mask::<_CMP_LE_OQ>(yh, zero) & !yp;
        let ym = !yp & !yn;
        // the upper bound's factors (b d, a d, b c or a c; for both straddling b d, and
        // a c beside it), and the lower bound's (a c, b c, a d or b d; a d and b c)
        let up_x = _mm512_mask_blend_pd((!xn & !yn) | (xn & yp), xl, xh);
        let up_y = _mm512_mask_blend_pd(xp | (xm & !yn), yl, yh);
        let down_x = _mm512_mask_blend_pd((xp & !yp) | (xn & yn) | (xm & yn), xl, xh);
        let down_y = _mm512_mask_blend_pd(xn | (xm & !yn), yl, yh);
        let both = xm & ym;
        let (ux, uy) = (store(up_x), store(up_y));
        let (dx, dy) = (store(_mm512_sub_pd(zero, down_x)), store(down_y));
        // the second candidates, needed only where both factors straddle 0
        let (al, ah, bl) = if both == 0 {
            ([0.0; 8], [0.0; 8], [0.0; 8])
        } else {
            (store(xl), store(xh), store(yl))
        };
        for i in 0..n {
            let (u, d) = (up, down);
            up = fma_up(ux[i], uy[i], u);
            down = fma_up(dx[i], dy[i], d);
            if both & (1 << i) != 0 {
                up = up.max(fma_up(al[i], bl[i], u));
                down = down.max(fma_up(-ah[i], bl[i], d));
            }
        }
        (bad == 0 && up.is_finite() && down.is_finite()).then_some((up, down))
    }

    /// Terms `j .. j + 8` of a dot product (fewer at the end) in lanes: `x`'s, negated when
    /// `neg`; `y`'s, read backwards when `rev` (the pairs `n - j - m .. n - j`); 0 in the lanes
    /// past the end; and the lanes that are infinite or NaN.
    #[target_feature(enable = "avx512f,avx512dq")]
    fn terms_at(x: &[f64], y: &[f64], j: usize, neg: bool, rev: bool) -> (Lanes, Lanes, u8) {
        let n = x.len() / 2;
        let m = (n - j).min(8);
        let (xs, bx) = gather(x, j, None);
        let (ys, by) = if rev {
            gather(y, n - j - m, Some(m))
        } else {
            gather(y, j, None)
        };
        // -x = [-xh, -xl]: its sup is -xl, minus its inf is xh
        let xs = if neg {
            Lanes {
                up: xs.down,
                down: xs.up,
            }
        } else {
            xs
        };
        (xs, ys, bx | by)
    }

    /// The index vectors of the pairwise sum of eight lanes, three rounds: lane `i` of a
    /// round is the sum of lanes `even[i]` and `odd[i]` of the one before (the first four
    /// lanes carry the sums, the rest repeat them and are not read).
    const PAIRS: [([i64; 8], [i64; 8]); 3] = [
        ([1, 3, 5, 7, 1, 3, 5, 7], [0, 2, 4, 6, 0, 2, 4, 6]),
        ([1, 3, 1, 3, 1, 3, 1, 3], [0, 2, 0, 2, 0, 2, 0, 2]),
        ([1, 1, 1, 1, 1, 1, 1, 1], [0, 0, 0, 0, 0, 0, 0, 0]),
    ];

    /// Eight intervals in lanes: their sup ends, and minus their inf ends.
    #[derive(Clone, Copy)]
    struct Lanes {
        up: __m512d,
        down: __m512d,
    }

    /// `x y + z` lane by lane, each the tightest interval (the hull of the four end
    /// products, plus `z`, rounded outward), as inari's `mul_add`.
    #[target_feature(enable = "avx512f")]
    fn fma(x: Lanes, y: Lanes, z: Lanes) -> Lanes {
        let zero = _mm512_setzero_pd();
        let (xl, xh, nxh) = (_mm512_sub_pd(zero, x.down), x.up, _mm512_sub_pd(zero, x.up));
        let (yl, yh) = (_mm512_sub_pd(zero, y.down), y.up);
        let u1 = _mm512_fmadd_round_pd::<UP>(xl, yl, z.up);
        let u2 = _mm512_fmadd_round_pd::<UP>(xl, yh, z.up);
        let u3 = _mm512_fmadd_round_pd::<UP>(xh, yl, z.up);
        let u4 = _mm512_fmadd_round_pd::<UP>(xh, yh, z.up);
        let d1 = _mm512_fmadd_round_pd::<UP>(x.down, yl, z.down);
        let d2 = _mm512_fmadd_round_pd::<UP>(x.down, yh, z.down);
        let d3 = _mm512_fmadd_round_pd::<UP>(nxh, yl, z.down);
        let d4 = _mm512_fmadd_round_pd::<UP>(nxh, yh, z.down);
        Lanes {
            up: _mm512_max_pd(_mm512_max_pd(u1, u2), _mm512_max_pd(u3, u4)),
            down: _mm512_max_pd(_mm512_max_pd(d1, d2), _mm512_max_pd(d3, d4)),
        }
    }

    /// One interval in every lane.
    #[target_feature(enable = "avx512f")]
    fn splat(x: Interval) -> Lanes {
        let r = raw(std::slice::from_ref(&x));
        Lanes {
            up: _mm512_set1_pd(r[1]),
            down: _mm512_set1_pd(r[0]),
        }
    }

    /// Up to eight intervals from the (-inf, sup) pairs `s`: the pairs `from ..` (0 past the
    /// end), or with `backwards = Some(m)` the pairs `from + m - 1` down to `from` (0 in the
    /// lanes from `m` on); with the lanes that are infinite or NaN.
    #[target_feature(enable = "avx512f,avx512dq")]
    fn gather(s: &[f64], from: usize, backwards: Option<usize>) -> (Lanes, u8) {
        let (s, (even, odd)) = match backwards {
            None => (s, FORWARD),
            Some(m) => (&s[..2 * (from + m)], REV[m]),
        };
        let (a, b) = (load(s, 2 * from), load(s, 2 * from + 8));
        let bad = _mm512_fpclass_pd_mask::<0x99>(a) | _mm512_fpclass_pd_mask::<0x99>(b);
        let lanes = Lanes {
            up: _mm512_permutex2var_pd(a, vector(odd), b),
            down: _mm512_permutex2var_pd(a, vector(even), b),
        };
        (lanes, bad)
    }

    /// The scheme for every entry, blocks of eight at a time, appended to `out`; `false`
    /// (and `out` as it was) when an input is not finite or a result overflows.
    pub(super) fn lanewise(rows: &[&[Interval]], scheme: Scheme, out: &mut Vec<Interval>) -> bool {
        let start = out.len();
        let done = append(rows, scheme, out).is_some();
        if !done {
            out.truncate(start);
        }
        done
    }

    fn append(rows: &[&[Interval]], scheme: Scheme, out: &mut Vec<Interval>) -> Option<()> {
        let width = rows.first().map_or(0, |r| r.len());
        if !layout_known() || rows.iter().any(|r| r.len() != width) {
            return None;
        }
        if let Scheme::Row(a) = scheme {
            if a.len() != rows.len() || !a.iter().all(|x| crate::tape::finite(*x)) {
                return None;
            }
        }
        out.reserve(width);
        let mut from = 0;
        while from < width {
            // SAFETY: this module is compiled only when the target has avx512f and avx512dq.
            let block = unsafe { block(rows, &scheme, from) }?;
            let m = (width - from).min(8);
            for i in 0..m {
                out.push(Interval::try_from((-block[2 * i], block[2 * i + 1])).ok()?);
            }
            from += m;
        }
        Some(())
    }

    /// Entries `from .. from + 8` of the scheme, as (-inf, sup) pairs.
    #[target_feature(enable = "avx512f,avx512dq")]
    fn block(rows: &[&[Interval]], scheme: &Scheme, from: usize) -> Option<[f64; 16]> {
        let zero = _mm512_setzero_pd();
        let mut acc = Lanes {
            up: zero,
            down: zero,
        };
        let mut bad = 0u8;
        match scheme {
            Scheme::Horner(h) => {
                if !crate::tape::finite(*h) {
                    return None;
                }
                let h = splat(*h);
                for r in rows.iter().rev() {
                    let (c, b) = gather(raw(r), from, None);
                    bad |= b;
                    acc = fma(acc, h, c);
                }
            }
            Scheme::Row(a) => {
                for (x, r) in a.iter().zip(rows) {
                    let (c, b) = gather(raw(r), from, None);
                    bad |= b;
                    acc = fma(splat(*x), c, acc);
                }
            }
        }
        let even = _mm512_set_epi64(11, 3, 10, 2, 9, 1, 8, 0);
        let odd = _mm512_set_epi64(15, 7, 14, 6, 13, 5, 12, 4);
        let (lo, hi) = (
            _mm512_permutex2var_pd(acc.down, even, acc.up),
            _mm512_permutex2var_pd(acc.down, odd, acc.up),
        );
        let mut out = [0.0f64; 16];
        // SAFETY: `out` holds the 16 doubles stored.
        unsafe {
            _mm512_storeu_pd(out.as_mut_ptr(), lo);
            _mm512_storeu_pd(out.as_mut_ptr().add(8), hi);
        }
        let finite = _mm512_fpclass_pd_mask::<0x99>(lo) | _mm512_fpclass_pd_mask::<0x99>(hi);
        (bad == 0 && finite == 0).then_some(out)
    }

    /// `a / b` when both are finite and `0` is not in `b`: over such a box `a / b` is
    /// monotone in each argument, so its range is the hull of the corner quotients, and
    /// the sign of `b` and of the relevant end of `a` say which corner bounds it. Each end is
    /// one division rounded outward by the instruction (`RD(n / d) = -RU(-n / d)`).
    pub(super) fn quotient(a: Interval, b: Interval) -> Option<Interval> {
        if !layout_known() {
            return None;
        }
        let (ra, rb) = (raw(std::slice::from_ref(&a)), raw(std::slice::from_ref(&b)));
        let (al, ah, bl, bh) = (-ra[0], ra[1], -rb[0], rb[1]);
        if !(al.is_finite() && ah.is_finite() && bl.is_finite() && bh.is_finite())
            || (bl <= 0.0 && bh >= 0.0)
        {
            return None;
        }
        // b > 0: the upper end ah / (bl if ah >= 0, else bh), the lower al / (bh if al >= 0,
        // else bl); b < 0: the upper al / (bl if al >= 0, else bh), the lower
        // ah / (bh if ah >= 0, else bl)
        let ((un, ud), (dn, dd)) = if bl > 0.0 {
            (
                (ah, if ah >= 0.0 { bl } else { bh }),
                (al, if al >= 0.0 { bh } else { bl }),
            )
        } else {
            (
                (al, if al >= 0.0 { bl } else { bh }),
                (ah, if ah >= 0.0 { bh } else { bl }),
            )
        };
        // SAFETY: this module is compiled only when the target has avx512f.
        let (hi, nlo) = unsafe { (div_up(un, ud), div_up(-dn, dd)) };
        if !(hi.is_finite() && nlo.is_finite()) {
            return None;
        }
        Interval::try_from((-nlo, hi)).ok()
    }

    /// `RU(n / d)`: the division rounded upward.
    #[target_feature(enable = "avx512f")]
    fn div_up(n: f64, d: f64) -> f64 {
        _mm_cvtsd_f64(_mm_div_round_sd::<UP>(_mm_set_sd(n), _mm_set_sd(d)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed-seed xorshift generator.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn int(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % (hi - lo + 1) as u64) as i64
        }
    }

    /// `k 2^e` with `|k| < 2^30`, `e` in `[e0, e1]`, `e0 >= -SCALE`: exact in f64 and, times
    /// `2^SCALE`, an integer. With `e1 <= 12` for the factors, the scaled products are below
    /// 2^108 and every sum the tests form stays in i128.
    fn dyadic(r: &mut Rng, e0: i64, e1: i64) -> f64 {
        let k = match r.int(0, 9) {
            0 => 0,
            1 => r.int(-3, 3),
            _ => r.int(-(1 << 30) + 1, (1 << 30) - 1),
        };
        k as f64 * 2f64.powi(r.int(e0, e1) as i32)
    }
    const SCALE: i32 = 12;

    fn exact(v: f64) -> i128 {
        let s = v * 2f64.powi(SCALE);
        assert_eq!(s, s.trunc(), "{v} is not a multiple of 2^-{SCALE}");
        s as i128
    }

    fn interval(r: &mut Rng, e0: i64, e1: i64) -> (Interval, i128, i128) {
        let (a, b) = (dyadic(r, e0, e1), dyadic(r, e0, e1));
        let (a, b) = if r.int(0, 3) == 0 {
            (a, a)
        } else {
            (a.min(b), a.max(b))
        };
        (Interval::try_from((a, b)).unwrap(), exact(a), exact(b))
    }

    /// Spec (1.4) against exact integer arithmetic: the result contains the real range
    /// `acc ± sum_j x_j y_j` (each term's range is the hull of its end products, the terms
    /// are independent), and each end is within `(n + 2)` roundings of it.
    #[test]
    fn dot_products_contain_the_exact_range_and_are_tight() {
        let mut r = Rng(0x9e37_79b9_7f4a_7c15);
        for case in 0..20_000 {
            let n = (case % 21) as usize;
            let (neg, rev) = (r.int(0, 1) == 1, r.int(0, 1) == 1);
            let (acc, lo, hi) = interval(&mut r, -12, 30);
            let (mut lo, mut hi) = (lo << SCALE, hi << SCALE);
            let mut size = acc.mag();
            let (mut x, mut y) = (vec![], vec![]);
            let mut ends = vec![];
            for _ in 0..n {
                let (a, al, ah) = interval(&mut r, -12, 12);
                let (b, bl, bh) = interval(&mut r, -12, 12);
                x.push(a);
                y.push(b);
                ends.push((al, ah, bl, bh));
            }
            for j in 0..n {
                let (al, ah, _, _) = ends[j];
                let (_, _, bl, bh) = ends[if rev { n - 1 - j } else { j }];
                let sign = if neg { -1 } else { 1 };
                let p = [al * bl, al * bh, ah * bl, ah * bh].map(|v| sign * v);
                // products scaled by 2^(2 SCALE), as the sums `lo`, `hi`: exact
                lo += p.iter().min().unwrap();
                hi += p.iter().max().unwrap();
                let yj = y[if rev { n - 1 - j } else { j }];
                size += x[j].mag() * yj.mag();
            }
            let got = dot(acc, neg, &x, &y, rev);
            let scale = 2f64.powi(2 * SCALE);
            let (gl, gh) = ((got.inf() * scale).floor(), (got.sup() * scale).ceil());
            assert!(
                (gl as i128) <= lo && hi <= (gh as i128),
                "case {case}: {got:?} misses the exact range (n {n}, neg {neg}, rev {rev})"
            );
            let slack = (n as f64 + 2.0) * f64::EPSILON * size * scale + 2.0;
            assert!(
                (lo as f64 - gl) <= slack && (gh - hi as f64) <= slack,
                "case {case}: {got:?} is loose (n {n})"
            );
        }
    }

    /// Spec (1.4): with finite inputs the vector paths give inari's chain bit for bit
    /// (dot products and convolutions, short and long, Horner's scheme, rows times
    /// matrices, quotients by intervals with or without 0), on random
    /// intervals of every sign pattern, thin and wide, with zero ends.
    #[test]
    fn the_vector_paths_give_the_chains_doubles() {
        let mut r = Rng(0x2545_f491_4f6c_dd1d);
        let any = |r: &mut Rng| {
            let e = |r: &mut Rng| match r.int(0, 7) {
                0 => 0.0,
                _ => (r.int(-(1 << 52), 1 << 52) as f64) * 2f64.powi(r.int(-80, 20) as i32),
            };
            let (a, b) = (e(r), e(r));
            let (a, b) = if r.int(0, 2) == 0 {
                (a, a)
            } else {
                (a.min(b), a.max(b))
            };
            Interval::try_from((a, b)).unwrap()
        };
        let same = |a: Interval, b: Interval| a.inf() == b.inf() && a.sup() == b.sup();
        for case in 0..5_000 {
            let n = case % 19;
            let x: Vec<Interval> = (0..n).map(|_| any(&mut r)).collect();
            let y: Vec<Interval> = (0..n).map(|_| any(&mut r)).collect();
            let acc = any(&mut r);
            let (neg, rev) = (r.int(0, 1) == 1, r.int(0, 1) == 1);
            let (a, b) = (dot(acc, neg, &x, &y, rev), chain(acc, neg, &x, &y, rev));
            assert!(
                same(a, b),
                "case {case}: dot {a:?} against the chain's {b:?}"
            );
            let h = any(&mut r);
            let rows: Vec<&[Interval]> = vec![&x, &y, &x];
            let v = horner(&rows, h);
            for i in 0..n {
                let c = rows.iter().rev().fold(ZERO, |s, row| s.mul_add(h, row[i]));
                assert!(
                    same(v[i], c),
                    "case {case}: Horner {:?} against {c:?}",
                    v[i]
                );
            }
            let q = quotient(acc, h);
            let inari_q = acc / h;
            let same_q = same(q, inari_q) || (q.is_empty() && inari_q.is_empty());
            assert!(
                same_q,
                "case {case}: {acc:?} / {h:?} = {q:?} against {inari_q:?}"
            );
            let coef = [h, acc, x.first().copied().unwrap_or(h)];
            // appended after what the buffer holds, which stays (also when the fast path
            // gives up part way, on an input that is not finite)
            let mut w = vec![h];
            row_times(&coef, &rows, &mut w);
            assert_eq!(w.len(), n + 1, "case {case}");
            assert!(same(w[0], h), "case {case}");
            for j in 0..n {
                let c = coef
                    .iter()
                    .zip(&rows)
                    .fold(ZERO, |s, (a, row)| a.mul_add(row[j], s));
                let got = w[j + 1];
                assert!(same(got, c), "case {case}: row {got:?} against {c:?}");
            }
        }
    }

    /// Inputs that are not all finite take the portable path, whose answer is inari's.
    #[test]
    fn unbounded_and_empty_inputs_give_the_chain_answer() {
        let i = |a: f64, b: f64| Interval::try_from((a, b)).unwrap();
        let x = [i(1.0, 2.0), i(-3.0, f64::INFINITY), i(0.5, 0.5)];
        let y = [i(-1.0, 1.0), i(2.0, 3.0), i(0.0, 4.0)];
        for (neg, rev) in [(false, false), (true, true)] {
            let (a, b) = (
                dot(i(0.0, 1.0), neg, &x, &y, rev),
                chain(i(0.0, 1.0), neg, &x, &y, rev),
            );
            assert_eq!((a.inf(), a.sup()), (b.inf(), b.sup()));
        }
        let e = [Interval::EMPTY, i(1.0, 1.0)];
        assert!(dot(i(0.0, 1.0), false, &e, &e, false).is_empty());
        // a sum that overflows: the portable path's infinite end, not a wrong finite one
        let big = [i(f64::MAX, f64::MAX); 3];
        let s = dot(i(0.0, 0.0), false, &big, &[i(1.0, 1.0); 3], false);
        assert_eq!(s.sup(), f64::INFINITY);
        assert!(s.inf() >= f64::MAX);
        // a row whose second block of eight holds an unbounded entry: the vector path has
        // written the first block when it gives up; the buffer gets the chain's entries
        // once, after what it held
        let wide: Vec<Interval> = (0..12)
            .map(|j| {
                if j == 10 {
                    i(-1.0, f64::INFINITY)
                } else {
                    i(j as f64, j as f64 + 0.5)
                }
            })
            .collect();
        let rows: Vec<&[Interval]> = vec![&wide, &wide];
        let coef = [i(1.0, 2.0), i(-1.0, 0.5)];
        let mut out = vec![i(7.0, 7.0)];
        row_times(&coef, &rows, &mut out);
        assert_eq!(out.len(), 13);
        assert_eq!((out[0].inf(), out[0].sup()), (7.0, 7.0));
        for j in 0..12 {
            let c = coef
                .iter()
                .zip(&rows)
                .fold(ZERO, |s, (a, row)| a.mul_add(row[j], s));
            assert_eq!(
                (out[j + 1].inf(), out[j + 1].sup()),
                (c.inf(), c.sup()),
                "entry {j}"
            );
        }
    }

    /// The vector path reads inari's bytes as (-inf, sup): on a CPU where it is compiled,
    /// that layout must be the one found (else every product would take the portable path).
    #[cfg(all(
        target_arch = "x86_64",
        target_feature = "avx512f",
        target_feature = "avx512dq"
    ))]
    #[test]
    fn the_vector_path_knows_inaris_layout() {
        assert!(wide::layout_known());
    }
}
