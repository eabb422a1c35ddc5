//! Small dense linear algebra over intervals, and the one rigorous inverse the method needs
//! ([spec/05-enclosure.md](crate::spec::enclosure), eq. (5.9)). Float matrices (nalgebra) are only ever *chosen*
//! objects (a basis, an approximate inverse): every set they act on is computed in intervals.

use super::ival::Ival;
use inari::Interval;
use nalgebra::DMatrix;

/// Interval matrix: `nrows x ncols` entries, row after row in one buffer. `m[i]` is row
/// `i`, `m[i][j]` an entry.
#[derive(Clone, Debug, PartialEq)]
pub struct IMat<I = Interval> {
    rows: usize,
    cols: usize,
    flat: Vec<I>,
}

impl<I: Ival> IMat<I> {
    /// The matrix of entries `f(i, j)`.
    pub fn from_fn(rows: usize, cols: usize, mut f: impl FnMut(usize, usize) -> I) -> Self {
        let mut flat = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            flat.extend((0..cols).map(|j| f(i, j)));
        }
        IMat { rows, cols, flat }
    }
    /// The `rows x cols` matrix whose rows are the consecutive `cols` entries of `flat`.
    pub fn from_flat(rows: usize, cols: usize, flat: Vec<I>) -> Self {
        assert_eq!(rows * cols, flat.len(), "the entries of a {rows} x {cols} matrix");
        IMat { rows, cols, flat }
    }
    /// The matrix with these rows (all of the first one's length).
    pub fn from_rows(rows: &[Vec<I>]) -> Self {
        let cols = rows.first().map_or(0, |r| r.len());
        IMat::from_fn(rows.len(), cols, |i, j| rows[i][j])
    }
    pub fn nrows(&self) -> usize {
        self.rows
    }
    /// The rows, in order.
    pub fn rows(&self) -> impl ExactSizeIterator<Item = &[I]> {
        (0..self.rows).map(move |i| &self[i])
    }
    /// Every entry, row after row.
    pub fn entries(&self) -> &[I] {
        &self.flat
    }
    /// Every entry, row after row, to change in place.
    pub fn entries_mut(&mut self) -> &mut [I] {
        &mut self.flat
    }
    /// The rows as vectors (the form of the public answers).
    pub fn to_rows(&self) -> Vec<Vec<I>> {
        self.rows().map(|r| r.to_vec()).collect()
    }
}

impl<I> std::ops::Index<usize> for IMat<I> {
    type Output = [I];
    fn index(&self, i: usize) -> &[I] {
        &self.flat[i * self.cols..(i + 1) * self.cols]
    }
}

impl<I> std::ops::IndexMut<usize> for IMat<I> {
    fn index_mut(&mut self, i: usize) -> &mut [I] {
        &mut self.flat[i * self.cols..(i + 1) * self.cols]
    }
}

/// A float matrix as an interval matrix of points (exact).
pub fn imat<I: Ival>(m: &DMatrix<f64>) -> IMat<I> {
    IMat::from_fn(m.nrows(), m.ncols(), |i, j| I::cst(m[(i, j)]))
}

/// Entry `(i, j)` of the identity.
fn unit<I: Ival>(i: usize, j: usize) -> I {
    I::cst(if i == j { 1.0 } else { 0.0 })
}

/// The `n x n` identity.
pub fn identity<I: Ival>(n: usize) -> IMat<I> {
    IMat::from_fn(n, n, unit)
}

/// `I - a` for a square `a`, entrywise.
pub fn identity_minus<I: Ival>(a: &IMat<I>) -> IMat<I> {
    IMat::from_fn(a.rows, a.cols, |i, j| unit::<I>(i, j) - a[i][j])
}

/// `a b` in interval arithmetic (sums by fused multiply-add, outward rounded; a row at a
/// time by the kernel, [spec (1.4)](crate::spec::scalars)). A float factor enters as `imat` (its points are exact).
pub fn mul<I: Ival>(a: &IMat<I>, b: &IMat<I>) -> IMat<I> {
    let rows: Vec<&[I]> = b.rows().collect();
    let mut flat = Vec::with_capacity(a.rows * b.cols);
    for ai in a.rows() {
        if rows.is_empty() {
            // an empty sum: a row of zeros
            flat.extend(std::iter::repeat_n(I::zero(), b.cols));
        } else {
            I::row_times(&ai[..rows.len()], &rows, &mut flat);
        }
    }
    IMat::from_flat(a.rows, b.cols, flat)
}

/// `a + b`, entrywise.
pub fn add<I: Ival>(a: &IMat<I>, b: &IMat<I>) -> IMat<I> {
    IMat::from_flat(
        a.rows,
        a.cols,
        a.flat.iter().zip(&b.flat).map(|(u, v)| *u + *v).collect(),
    )
}

/// `a x` in interval arithmetic (sums by fused multiply-add, outward rounded; a dot product
/// per row, [spec (1.4)](crate::spec::scalars)).
pub fn mul_vec<I: Ival>(a: &IMat<I>, x: &[I]) -> Vec<I> {
    a.rows().map(|r| row_dot(r, x)).collect()
}

/// `sum_j r_j x_j` over the common length, by the dot kernel ([spec (1.4)](crate::spec::scalars)).
fn row_dot<I: Ival>(r: &[I], x: &[I]) -> I {
    let n = r.len().min(x.len());
    I::dot(I::zero(), false, &r[..n], &x[..n], false)
}

/// The midpoints of the entries, as a float matrix (a choice, [spec 0.2](crate::spec::overview#02-the-global-promise)).
pub fn mid<I: Ival>(a: &IMat<I>) -> DMatrix<f64> {
    DMatrix::from_fn(a.rows, a.cols, |i, j| a[i][j].mid())
}

/// `(mid(A), A - mid(A))`: a float matrix and the interval matrix of what `A` exceeds it
/// by, outward rounded (CAPD's `split`): `A ⊆ mid(A) + (A - mid(A))`.
pub fn split<I: Ival>(a: &IMat<I>) -> (DMatrix<f64>, IMat<I>) {
    let c = mid(a);
    let off = IMat::from_fn(a.rows, a.cols, |i, j| a[i][j] - I::cst(c[(i, j)]));
    (c, off)
}

/// Upper bound of the infinity norm of an interval matrix.
pub fn norm_inf_sup<I: Ival>(a: &IMat<I>) -> f64 {
    a.rows()
        .map(|r| r.iter().fold(I::zero(), |s, x| s + I::cst(x.mag())).sup())
        .fold(0.0, f64::max)
}

/// Whether every entry is non-empty with finite ends.
pub fn all_finite<I: Ival>(a: &IMat<I>) -> bool {
    a.flat.iter().all(|x| x.is_finite())
}

/// The most powers of `E` that [`enclose_inverse`] keeps.
const MAX_POWERS: usize = 64;

/// An interval matrix containing `B^{-1}` for the float matrix `b`, given any float
/// approximate inverse `x` ([spec eq. (5.9)](crate::spec::enclosure)): with `E = I - X B` and `d >= ||E||_inf < 1`,
/// `B^{-1} = (I - E)^{-1} X in (I + E + [-eps, eps]) X`, `eps = d^2 / (1 - d)`; above 106 bits
/// `(I + E + ... + E^k + [-eps, eps]) X`, `eps = d^(k+1) / (1 - d)`, with `k` the least that
/// brings `d^(k+1)` to the rounding level ([spec (12.0.7)](crate::spec::precision)).
/// `None` when `d >= 1/2` (the approximate inverse is too poor to prove anything useful).
pub fn enclose_inverse<I: Ival>(b: &DMatrix<f64>, x: &DMatrix<f64>) -> Option<IMat<I>> {
    let n = b.nrows();
    let xi: IMat<I> = imat(x);
    let e = identity_minus(&mul(&xi, &imat(b)));
    if !all_finite(&e) {
        return None;
    }
    let d = norm_inf_sup(&e);
    if d.is_nan() || d >= 0.5 {
        return None;
    }
    // (5.9') the number of powers of E kept: one (I + E) up to 106 bits; above, as many as
    // bring d^(k+1) below the rounding level (a choice: every k gives an enclosure)
    let mut k = 1;
    if I::eps() < f64::EPSILON * f64::EPSILON {
        while k < MAX_POWERS && d.powi(k as i32 + 1) > I::eps() {
            k += 1;
        }
    }
    let di = I::cst(d);
    let mut dk = di * di;
    for _ in 1..k {
        dk = dk * di;
    }
    let eps = (dk / (I::one() - di)).sup();
    if eps.is_nan() {
        return None;
    }
    let tail = I::iv(-eps, eps);
    // S = E + E^2 + ... + E^k by Horner's rule, S <- E + E S
    let mut s = e.clone();
    for _ in 1..k {
        s = add(&e, &mul(&e, &s));
    }
    for i in 0..n {
        for (j, x) in s[i].iter_mut().enumerate() {
            *x = *x + tail + unit::<I>(i, j);
        }
    }
    let r = mul(&s, &xi);
    all_finite(&r).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::point;

    /// Products keep their shape, an empty inner dimension included (then every entry is
    /// the empty sum 0).
    #[test]
    fn products_have_the_shape_of_their_factors() {
        let a: IMat = IMat::from_fn(2, 3, |i, j| point((i + j) as f64));
        let b = DMatrix::from_fn(3, 4, |i, j| (i * j) as f64);
        let ab = mul(&a, &imat(&b));
        assert_eq!((ab.nrows(), ab[1].len()), (2, 4));
        // row 1 of a is (1, 2, 3); column 3 of b is (0, 3, 6): 0 + 6 + 18
        assert_eq!((ab[1][3].inf(), ab[1][3].sup()), (24.0, 24.0));
        let empty: IMat = mul(&IMat::from_flat(2, 0, Vec::new()), &IMat::from_flat(0, 3, Vec::new()));
        assert_eq!((empty.nrows(), empty[1].len()), (2, 3));
        assert!(empty.entries().iter().all(|x| x.inf() == 0.0 && x.sup() == 0.0));
        assert_eq!(a.to_rows()[1], vec![point(1.0), point(2.0), point(3.0)]);
    }

    #[test]
    fn inverse_enclosure_contains_the_exact_inverse_of_a_rotation() {
        let (c, s) = (0.6f64, 0.8f64);
        let b = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]);
        let inv: IMat = enclose_inverse(&b, &b.transpose()).unwrap();
        // exact inverse of [[0.6,-0.8],[0.8,0.6]] (in binary, not exactly orthogonal):
        // check B * inv contains I
        let prod = mul(&imat(&b), &inv);
        for i in 0..2 {
            for j in 0..2 {
                assert!(prod[i][j].contains(if i == j { 1.0 } else { 0.0 }));
                assert!(prod[i][j].wid() < 1e-14);
            }
        }
        let singular = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        assert!(enclose_inverse::<Interval>(&singular, &DMatrix::identity(2, 2)).is_none());
    }
}
