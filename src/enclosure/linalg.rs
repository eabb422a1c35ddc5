//! Small dense linear algebra over intervals, and the one rigorous inverse the method needs
//! (spec/05-enclosure.md, eq. (5.9)). Float matrices (nalgebra) are only ever *chosen*
//! objects (a basis, an approximate inverse): every set they act on is computed in intervals.

use crate::scalar::point;
use crate::tape::finite;
use inari::Interval;
use nalgebra::DMatrix;

/// Interval matrix, rows.
pub type IMat = Vec<Vec<Interval>>;

/// A float matrix as an interval matrix of points (exact).
pub fn imat(m: &DMatrix<f64>) -> IMat {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| point(m[(i, j)])).collect())
        .collect()
}

/// The `n x n` identity.
pub fn identity(n: usize) -> IMat {
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| point(if i == j { 1.0 } else { 0.0 }))
                .collect()
        })
        .collect()
}

/// `a b` in interval arithmetic (sums by fused multiply-add, outward rounded; a row at a
/// time, spec (1.4)).
pub fn mul(a: &IMat, b: &IMat) -> IMat {
    times(a.iter().map(|r| &r[..]), &b.iter().map(|r| &r[..]).collect::<Vec<_>>())
}

/// The rows `left` times the matrix with rows `rows`, each product row by the kernel.
fn times<'a>(left: impl Iterator<Item = &'a [Interval]>, rows: &[&[Interval]]) -> IMat {
    left.map(|ai| crate::dot::row_times(&ai[..rows.len()], rows))
        .collect()
}

/// A float matrix with its entries as point intervals (exact), in one buffer:
/// `Points::of(m).rows()` are the rows of `imat(m)`.
struct Points {
    flat: Vec<Interval>,
    rows: usize,
    cols: usize,
}

impl Points {
    fn of(m: &DMatrix<f64>) -> Self {
        let mut flat = Vec::with_capacity(m.nrows() * m.ncols());
        for i in 0..m.nrows() {
            flat.extend(m.row(i).iter().map(|x| point(*x)));
        }
        Points {
            flat,
            rows: m.nrows(),
            cols: m.ncols(),
        }
    }
    fn rows(&self) -> impl Iterator<Item = &[Interval]> {
        (0..self.rows).map(move |i| &self.flat[i * self.cols..(i + 1) * self.cols])
    }
}

/// `a b` for a float matrix `b`: the same doubles as `mul(a, &imat(b))` (its entries are
/// exact as points), without forming the matrix of points row by row.
pub fn mul_points(a: &IMat, b: &DMatrix<f64>) -> IMat {
    let b = Points::of(b);
    times(a.iter().map(|r| &r[..]), &b.rows().collect::<Vec<_>>())
}

/// `a b` for a float matrix `a`: the same doubles as `mul(&imat(a), b)`.
pub fn points_mul(a: &DMatrix<f64>, b: &IMat) -> IMat {
    times(
        Points::of(a).rows(),
        &b.iter().map(|r| &r[..]).collect::<Vec<_>>(),
    )
}

/// `a x` for a float matrix `a`: the same doubles as `mul_vec(&imat(a), x)`.
pub fn points_mul_vec(a: &DMatrix<f64>, x: &[Interval]) -> Vec<Interval> {
    Points::of(a).rows().map(|r| row_dot(r, x)).collect()
}

/// `a + b`, entrywise.
pub fn add(a: &IMat, b: &IMat) -> IMat {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.iter().zip(y).map(|(u, v)| *u + *v).collect())
        .collect()
}

/// `a x` in interval arithmetic (sums by fused multiply-add, outward rounded; a dot product
/// per row, spec (1.4)).
pub fn mul_vec(a: &IMat, x: &[Interval]) -> Vec<Interval> {
    a.iter().map(|r| row_dot(r, x)).collect()
}

/// `sum_j r_j x_j` over the common length, by the dot kernel (spec (1.4)).
fn row_dot(r: &[Interval], x: &[Interval]) -> Interval {
    let n = r.len().min(x.len());
    crate::dot::dot(point(0.0), false, &r[..n], &x[..n], false)
}

/// The midpoints of the entries, as a float matrix (a choice, spec 0.2).
pub fn mid(a: &IMat) -> DMatrix<f64> {
    let (n, m) = (a.len(), a.first().map_or(0, |r| r.len()));
    DMatrix::from_fn(n, m, |i, j| a[i][j].mid())
}

/// `(mid(A), A - mid(A))`: a float matrix and the interval matrix of what `A` exceeds it
/// by, outward rounded (CAPD's `split`): `A ⊆ mid(A) + (A - mid(A))`.
pub fn split(a: &IMat) -> (DMatrix<f64>, IMat) {
    let c = mid(a);
    let off = a
        .iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .enumerate()
                .map(|(j, x)| *x - point(c[(i, j)]))
                .collect()
        })
        .collect();
    (c, off)
}

/// Upper bound of the infinity norm of an interval matrix.
pub fn norm_inf_sup(a: &IMat) -> f64 {
    a.iter()
        .map(|r| r.iter().fold(point(0.0), |s, x| s + point(x.mag())).sup())
        .fold(0.0, f64::max)
}

/// Whether every entry is non-empty with finite ends.
pub fn all_finite(a: &IMat) -> bool {
    a.iter().all(|r| r.iter().all(|x| finite(*x)))
}

/// An interval matrix containing `B^{-1}` for the float matrix `b`, given any float
/// approximate inverse `x` (spec eq. (5.9)): with `E = I - X B` and `d >= ||E||_inf < 1`,
/// `B^{-1} = (I - E)^{-1} X in (I + E + [-eps, eps]) X`, `eps = d^2 / (1 - d)`.
/// `None` when `d >= 1/2` (the approximate inverse is too poor to prove anything useful).
pub fn enclose_inverse(b: &DMatrix<f64>, x: &DMatrix<f64>) -> Option<IMat> {
    let n = b.nrows();
    let xb = mul_points(&imat(x), b);
    let e: IMat = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| point(if i == j { 1.0 } else { 0.0 }) - xb[i][j])
                .collect()
        })
        .collect();
    if !all_finite(&e) {
        return None;
    }
    let d = norm_inf_sup(&e);
    if d.is_nan() || d >= 0.5 {
        return None;
    }
    let di = point(d);
    let eps = (di * di / (point(1.0) - di)).sup();
    let tail = Interval::try_from((-eps, eps)).ok()?;
    let mut s = e;
    for (i, row) in s.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = *x + tail + point(if i == j { 1.0 } else { 0.0 });
        }
    }
    let r = mul_points(&s, x);
    all_finite(&r).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_enclosure_contains_the_exact_inverse_of_a_rotation() {
        let (c, s) = (0.6f64, 0.8f64);
        let b = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]);
        let inv = enclose_inverse(&b, &b.transpose()).unwrap();
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
        assert!(enclose_inverse(&singular, &DMatrix::identity(2, 2)).is_none());
    }
}
